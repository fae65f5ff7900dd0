/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: the stage equations of the 2-stage Gauss-Legendre
   method (hs_gauss.h) solved by simplified Newton iteration, for a
   second-order system y = (q, v) whose field has the Jacobian

     J0 = [[0, I], [-G, 0]],   G = M^-1 V''  (V'' possibly only in part)

   i.e. dq/dt = v + O(dt^2), dv/dt = M^-1 F(q) + O(dt^2) as for the flow of
   H_[2,VV] (Bond & Leimkuhler 2007, section 3.1). The O(dt^2) parts of the
   Jacobian are left out of J0: the iteration then contracts by about
   h dt^2 |V'''| |v| instead of to zero, far below the tolerance's needs.

   Pure math, no LAMMPS types, header-only, unit-tested on its own
   (unittest/math/test_newton.cpp). Used by fix hardsphere/mcva.

   Simplified Newton (Hairer & Wanner, Solving ODEs II, IV.8): with
   D_i = f(Y_i) - K_i, solve (I - h A (x) J0) Delta = D and K += Delta. With
   this J0 the q-part eliminates (Delta_q = D_q + h (A (x) I) Delta_v):

     (I + h^2 (A^2 (x) G)) Delta_v = D_v - h (A (x) G) D_q .

   The spectral radius of h^2 (A^2 (x) G) is h^2 omega^2 / 12 (|eig A|^2 =
   1/12), below 1/3 wherever Verlet is stable (h omega < 2), so the system
   is solved by the Neumann series, one product with G per term; G is
   kept as its radial terms (RadialHessian), built once per sub-step start. No factorization: that of a 3N system with ~50 neighbours per
   atom (an LJ fluid cut at 2.5) fills in to a dense one.

   Rates (linearized): fixed-point (Jacobi) iteration, hs_gauss.h: h omega
   / sqrt(12) per sweep. Newton with G = 0 (only dq/dt = v in J0): its
   square, h^2 omega^2 / 12, per iteration, at the same cost (two field
   evaluations). With G = M^-1 V''(y0): the change of V'' over the step,
   about h^2 |V'''| |dq| / m. Parts of V'' left out of G (e.g. those known
   only as force differences) converge at the G = 0 rate.

   Distributed use: as gauss2_stages(), the convergence sums go through a
   user reduction; G must then act on the local part only (G = 0: nothing).
------------------------------------------------------------------------- */

#ifndef LMP_HS_NEWTON_H
#define LMP_HS_NEWTON_H

#include "hs_gauss.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace HardSphere {

/* ----------------------------------------------------------------------
   G = M^-1 V'' for V a sum of radial terms phi(|x_i - x_j|), kept as the
   list of its terms' 3x3 blocks k = phi'' e e^T + phi'/r (I - e e^T),
   e = (x_i - x_j)/r: (V''x)_i = sum k (x_i - x_j), (V''x)_j = -sum k (x_i - x_j).
   A product costs one pass over the terms (half that of the assembled
   block matrix), and building it needs no sorting.
------------------------------------------------------------------------- */

class RadialHessian {
 public:
  void clear(int natoms)
  {
    n = natoms;
    terms.clear();
    scale.assign(natoms, 1.0);
  }
  // a term between atoms i and j (del = x_i - x_j), phi'(r), phi''(r); an
  // index < 0 is an atom that does not move. rowi / rowj false: that atom's
  // rows come from elsewhere (e.g. the other copy of a term listed twice)
  void add_radial(int i, int j, const double del[3], double dphi, double d2phi, bool rowi = true,
                  bool rowj = true)
  {
    const double rsq = del[0] * del[0] + del[1] * del[1] + del[2] * del[2];
    if (!(rsq > 0.0)) return;
    const double r = std::sqrt(rsq);
    if (i < 0) rowi = false;
    if (j < 0) rowj = false;
    if (!rowi && !rowj) return;
    const double a = (d2phi - dphi / r) / rsq, b = dphi / r;
    Term t;
    t.i = i;
    t.j = j;
    t.flags = (rowi ? 1 : 0) | (rowj ? 2 : 0);
    // symmetric: xx yy zz xy xz yz
    t.k[0] = a * del[0] * del[0] + b;
    t.k[1] = a * del[1] * del[1] + b;
    t.k[2] = a * del[2] * del[2] + b;
    t.k[3] = a * del[0] * del[1];
    t.k[4] = a * del[0] * del[2];
    t.k[5] = a * del[1] * del[2];
    terms.push_back(t);
  }
  // the rows of atom i are multiplied by s (1/m_i for G = M^-1 V'')
  void set_row_scale(int i, double s) { scale[i] = s; }
  // out = G x (length 3 n)
  void apply(const double *x, double *out) const
  {
    for (int c = 0; c < 3 * n; c++) out[c] = 0.0;
    for (const Term &t : terms) {
      double d[3];
      for (int c = 0; c < 3; c++)
        d[c] = (t.i >= 0 ? x[3 * t.i + c] : 0.0) - (t.j >= 0 ? x[3 * t.j + c] : 0.0);
      const double *k = t.k;
      const double o0 = k[0] * d[0] + k[3] * d[1] + k[4] * d[2];
      const double o1 = k[3] * d[0] + k[1] * d[1] + k[5] * d[2];
      const double o2 = k[4] * d[0] + k[5] * d[1] + k[2] * d[2];
      if (t.flags & 1) {
        out[3 * t.i] += o0;
        out[3 * t.i + 1] += o1;
        out[3 * t.i + 2] += o2;
      }
      if (t.flags & 2) {
        out[3 * t.j] -= o0;
        out[3 * t.j + 1] -= o1;
        out[3 * t.j + 2] -= o2;
      }
    }
    for (int i = 0; i < n; i++)
      for (int c = 0; c < 3; c++) out[3 * i + c] *= scale[i];
  }
  int atoms() const { return n; }
  size_t nterms() const { return terms.size(); }

 private:
  struct Term {
    int i, j, flags;
    double k[6];
  };
  int n = 0;
  std::vector<Term> terms;
  std::vector<double> scale;
};

struct NewtonOptions {
  GaussOptions gauss;           // tol, stag_tol, maxit as for the fixed point
  // Neumann series: relative size of the last term. An inexact Newton
  // correction: its error only needs to stay below the iteration's own
  // contraction (~h dt^2 |V'''| |v|, or the change of V'' over the step)
  double lin_tol = 1.0e-6;
  int lin_maxit = 60;
  // stop once the estimated remaining error is below tol (see solve())
  bool predict_stop = true;
};

struct NewtonStatus : GaussStatus {
  int lin_iters = 0;          // products with G (pairs: both stages)
  bool lin_dropped = false;   // the Neumann series did not contract: G dropped
};

/* ----------------------------------------------------------------------
   Solve the stage equations for step h from y0 (local length n = 2 m:
   q = y[0..m), v = y[m..n)) by simplified Newton. field and reduce as for
   gauss2_stages() (nblocks = 2: q and v measured separately). applyG(x,
   out): out = G x for a vector of length m; with useG false it is never
   called (J0 = [[0, I], [0, 0]]). K1, K2 hold the initial guess on entry
   and the stage derivatives on return. Convergence and failure are
   judged as in gauss2_stages(), on the Newton correction.
------------------------------------------------------------------------- */

class GaussNewton2 {
 public:
  template <class Field, class Reduce, class ApplyG>
  NewtonStatus solve(Field &&field, Reduce &&reduce, ApplyG &&applyG, bool useG, const double *y0,
                     int n, double h, double *K1, double *K2, const NewtonOptions &opt)
  {
    using G = GaussLegendre2;
    // A^2 (Gauss-Legendre 2)
    const double b11 = G::a11 * G::a11 + G::a12 * G::a21, b12 = G::a11 * G::a12 + G::a12 * G::a22,
                 b21 = G::a21 * G::a11 + G::a22 * G::a21, b22 = G::a21 * G::a12 + G::a22 * G::a22;
    const int m = n / 2;
    Y.resize(n);
    F1.resize(n);
    F2.resize(n);
    x1.resize(m);
    x2.resize(m);
    r1.resize(m);
    r2.resize(m);
    g1.resize(m);
    g2.resize(m);
    NewtonStatus st;
    double prev = HUGE_VAL;
    const GaussOptions &go = opt.gauss;

    for (int it = 1; it <= go.maxit; ++it) {
      for (int k = 0; k < n; ++k) Y[k] = y0[k] + h * (G::a11 * K1[k] + G::a12 * K2[k]);
      field(Y.data(), F1.data());
      for (int k = 0; k < n; ++k) Y[k] = y0[k] + h * (G::a21 * K1[k] + G::a22 * K2[k]);
      field(Y.data(), F2.data());
      // D_i = f(Y_i) - K_i, in F
      for (int k = 0; k < n; ++k) {
        F1[k] -= K1[k];
        F2[k] -= K2[k];
      }
      const double *Dq1 = F1.data(), *Dq2 = F2.data();
      double *Dv1 = F1.data() + m, *Dv2 = F2.data() + m;
      if (useG) {
        // rhs = D_v - h (A (x) G) D_q
        applyG(Dq1, g1.data());
        applyG(Dq2, g2.data());
        for (int k = 0; k < m; ++k) {
          r1[k] = Dv1[k] - h * (G::a11 * g1[k] + G::a12 * g2[k]);
          r2[k] = Dv2[k] - h * (G::a21 * g1[k] + G::a22 * g2[k]);
        }
        if (!neumann(reduce, applyG, h * h, b11, b12, b21, b22, m, opt, st)) {
          // not contracting (h omega beyond Verlet's stability, or G not
          // what the field's Jacobian is): J0 without G for this solve
          useG = false;
          st.lin_dropped = true;
          std::copy(Dv1, Dv1 + m, x1.begin());
          std::copy(Dv2, Dv2 + m, x2.begin());
        }
      } else {
        std::copy(Dv1, Dv1 + m, x1.begin());
        std::copy(Dv2, Dv2 + m, x2.begin());
      }
      // Delta_v = x, Delta_q = D_q + h (A (x) I) Delta_v; K += Delta
      double sums[4] = {0.0, 0.0, 0.0, 0.0};    // |Delta|^2, |K|^2 per block
      for (int k = 0; k < m; ++k) {
        const double dq1 = Dq1[k] + h * (G::a11 * x1[k] + G::a12 * x2[k]);
        const double dq2 = Dq2[k] + h * (G::a21 * x1[k] + G::a22 * x2[k]);
        K1[k] += dq1;
        K2[k] += dq2;
        K1[m + k] += x1[k];
        K2[m + k] += x2[k];
        sums[0] += dq1 * dq1 + dq2 * dq2;
        sums[1] += K1[k] * K1[k] + K2[k] * K2[k];
        sums[2] += x1[k] * x1[k] + x2[k] * x2[k];
        sums[3] += K1[m + k] * K1[m + k] + K2[m + k] * K2[m + k];
      }
      reduce(sums, 4);
      double d = 0.0;
      for (int b = 0; b < 2; ++b) {
        const double num = sums[2 * b], den = sums[2 * b + 1];
        const double r = (num == 0.0) ? 0.0 : std::sqrt(num / den);
        if (!(r <= HUGE_VAL)) d = r;
        else if (!(d != d)) d = std::max(d, r);
      }
      st.iterations = it;
      st.residual = d;
      if (!(d <= HUGE_VAL) || !std::isfinite(d)) return st;
      // the error left after this correction is about theta d / (1 - theta),
      // theta the contraction (this solve's last ratio, or the last one
      // measured before): stop when that is below the tolerance, which saves
      // the iteration that would only confirm it (Hairer & Wanner, ODEs II,
      // IV.8, eq. 8.10)
      // (a ratio of corrections near round-off says nothing: kept only while
      // both are far above it)
      const bool measured = it >= 2 && prev > 0.0 && d > THETA_FLOOR;
      const double theta = measured ? d / prev : theta_last;
      if (measured) theta_last = theta;
      const bool predicted = opt.predict_stop && theta >= 0.0 && theta < 0.5 &&
          theta / (1.0 - theta) * d <= go.tol;
      if (d <= go.tol || predicted || (d >= prev && d <= go.stag_tol)) {
        st.converged = true;
        return st;
      }
      if (it >= 2 && d > 1.0 && d > prev) return st;
      prev = d;
    }
    return st;
  }

 private:
  std::vector<double> Y, F1, F2, x1, x2, r1, r2, g1, g2;
  double theta_last = -1.0;    // the last measured contraction (< 0: none yet)
  static constexpr double THETA_FLOOR = 1.0e-12;

  // x = (I + s (B (x) G))^-1 r by the Neumann series x <- r - s (B (x) G) x,
  // B = A^2; false if it does not contract
  template <class Reduce, class ApplyG>
  bool neumann(Reduce &reduce, ApplyG &applyG, double s, double b11, double b12, double b21,
               double b22, int m, const NewtonOptions &opt, NewtonStatus &st)
  {
    std::copy(r1.begin(), r1.end(), x1.begin());
    std::copy(r2.begin(), r2.end(), x2.begin());
    double prev = HUGE_VAL;
    for (int it = 1; it <= opt.lin_maxit; ++it) {
      applyG(x1.data(), g1.data());
      applyG(x2.data(), g2.data());
      st.lin_iters++;
      double sums[2] = {0.0, 0.0};    // |change|^2, |x|^2
      for (int k = 0; k < m; ++k) {
        const double n1 = r1[k] - s * (b11 * g1[k] + b12 * g2[k]);
        const double n2 = r2[k] - s * (b21 * g1[k] + b22 * g2[k]);
        sums[0] += (n1 - x1[k]) * (n1 - x1[k]) + (n2 - x2[k]) * (n2 - x2[k]);
        sums[1] += n1 * n1 + n2 * n2;
        x1[k] = n1;
        x2[k] = n2;
      }
      reduce(sums, 2);
      const double d = (sums[0] == 0.0) ? 0.0 : std::sqrt(sums[0] / sums[1]);
      if (!std::isfinite(d)) return false;
      if (d <= opt.lin_tol) return true;
      // the terms shrink by the spectral radius: give up where it is not
      // below 1/2, unless round-off is reached already
      if (it >= 3 && d > 0.5 * prev) return d < 1.0e-13;
      prev = d;
    }
    return false;
  }
};

}    // namespace HardSphere

#endif
