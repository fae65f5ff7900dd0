/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: the 2-stage Gauss-Legendre method (order 4) with its
   stage equations solved by fixed-point iteration, on a generic vector
   field y' = f(y).

   Pure math, no LAMMPS types, header-only, unit-tested on its own
   (unittest/math/test_gauss.cpp). Used by fix hardsphere/mcva for the
   "symplectic fourth-order Gauss method" Psi^[*] of Bond & Leimkuhler
   (2007), section 3.1, applied to the flow of H_[2,VV].

   Butcher tableau (Hairer, Lubich & Wanner, Geometric Numerical
   Integration, II.1.3):  c = 1/2 -+ sqrt3/6,
     a = [[1/4, 1/4 - sqrt3/6], [1/4 + sqrt3/6, 1/4]],  b = [1/2, 1/2].
   Stage derivatives K_i = f(y0 + h sum_j a_ij K_j); y1 = y0 + h sum_i b_i K_i.
   The method is symplectic and conserves quadratic invariants exactly
   (up to the stage tolerance and round-off).

   Distributed use: the state may be split over MPI ranks. The field
   evaluation is then collective, and the convergence test sums its
   squared norms through a user reduction (an MPI_Allreduce), so every rank
   takes the same number of iterations.
------------------------------------------------------------------------- */

#ifndef LMP_HS_GAUSS_H
#define LMP_HS_GAUSS_H

#include <algorithm>
#include <cmath>
#include <vector>

namespace HardSphere {

struct GaussLegendre2 {
  static constexpr double s3 = 1.7320508075688772935274463415058723;    // sqrt(3)
  static constexpr double a11 = 0.25;
  static constexpr double a12 = 0.25 - s3 / 6.0;
  static constexpr double a21 = 0.25 + s3 / 6.0;
  static constexpr double a22 = 0.25;
  static constexpr double b1 = 0.5;
  static constexpr double b2 = 0.5;
  static constexpr double c1 = 0.5 - s3 / 6.0;
  static constexpr double c2 = 0.5 + s3 / 6.0;
};

struct GaussOptions {
  // converged when the relative change of the stage derivatives (largest
  // over the blocks, see below) drops to tol ...
  double tol = 1.0e-14;
  // ... or stops decreasing while already below stag_tol (the round-off
  // floor of the field evaluation was reached). It fails on NaN or inf, and
  // as soon as the change grows while above 1 (diverging)
  double stag_tol = 1.0e-10;
  int maxit = 100;
};

struct GaussStatus {
  bool converged = false;
  int iterations = 0;        // field evaluations of both stages = 2 * iterations
  double residual = 0.0;     // last relative change of the stage derivatives
};

/* ----------------------------------------------------------------------
   Solve the stage equations for step h from y0 (local length n).
   field(const double *y, double *k): k = f(y) (collective if distributed).
   reduce(double *buf, int m): sums buf[0..m) over all ranks (no-op serially).
   The state is nblocks contiguous equal blocks (e.g. positions, velocities);
   the relative change is measured per block (so blocks of different units
   count alike) and the largest one decides.
   K1, K2 (length n) hold the initial guess on entry and the stage
   derivatives on return; work needs 3 n doubles.
------------------------------------------------------------------------- */

template <class Field, class Reduce>
GaussStatus gauss2_stages(Field &&field, Reduce &&reduce, const double *y0, int n, int nblocks,
                          double h, double *K1, double *K2, const GaussOptions &opt, double *work)
{
  using G = GaussLegendre2;
  GaussStatus st;
  double *Y = work;              // one stage state at a time
  double *K1n = work + n;        // the new stage derivatives
  double *K2n = work + 2 * n;
  const int nb = std::max(nblocks, 1);
  const int bl = std::max(n / nb, 1);
  std::vector<double> sums(2 * nb);
  double prev = HUGE_VAL;

  for (int it = 1; it <= opt.maxit; ++it) {
    // Jacobi sweep: both stage states from the old derivatives
    for (int k = 0; k < n; ++k) Y[k] = y0[k] + h * (G::a11 * K1[k] + G::a12 * K2[k]);
    field(Y, K1n);
    for (int k = 0; k < n; ++k) Y[k] = y0[k] + h * (G::a21 * K1[k] + G::a22 * K2[k]);
    field(Y, K2n);
    std::fill(sums.begin(), sums.end(), 0.0);
    for (int k = 0; k < n; ++k) {
      const int b = std::min(k / bl, nb - 1);
      const double d1 = K1n[k] - K1[k], d2 = K2n[k] - K2[k];
      sums[2 * b] += d1 * d1 + d2 * d2;
      sums[2 * b + 1] += K1n[k] * K1n[k] + K2n[k] * K2n[k];
      K1[k] = K1n[k];
      K2[k] = K2n[k];
    }
    reduce(sums.data(), (int) sums.size());
    double d = 0.0;
    for (int b = 0; b < nb; ++b) {
      const double num = sums[2 * b], den = sums[2 * b + 1];
      const double r = (num == 0.0) ? 0.0 : std::sqrt(num / den);
      if (!(r <= HUGE_VAL)) d = r;    // NaN (0/0, inf/inf): keep it, std::max would drop it
      else if (!(d != d)) d = std::max(d, r);
    }
    st.iterations = it;
    st.residual = d;
    if (!(d <= HUGE_VAL) || !std::isfinite(d)) return st;    // NaN or inf: not converged
    if (d <= opt.tol || (d >= prev && d <= opt.stag_tol)) {
      st.converged = true;
      return st;
    }
    // growing while the stage derivatives change by more than their size:
    // diverging; stop before the stage states run away
    if (it >= 2 && d > 1.0 && d > prev) return st;
    prev = d;
  }
  return st;
}

// y1 = y0 + h (b1 K1 + b2 K2)
inline void gauss2_update(const double *y0, int n, double h, const double *K1, const double *K2,
                          double *y1)
{
  using G = GaussLegendre2;
  for (int k = 0; k < n; ++k) y1[k] = y0[k] + h * (G::b1 * K1[k] + G::b2 * K2[k]);
}

// Initial guess for the stages of step h from a solution (K1p, K2p) of step
// hp from the same y0 and f0 = f(y0): K_i(t) is smooth in the stage time
// c_i h, so extrapolate linearly between f0 (t = 0) and K_i(hp).
inline void gauss2_guess(const double *f0, const double *K1p, const double *K2p, double hp,
                         double h, int n, double *K1, double *K2)
{
  const double s = (hp != 0.0) ? h / hp : 0.0;
  for (int k = 0; k < n; ++k) {
    K1[k] = f0[k] + s * (K1p[k] - f0[k]);
    K2[k] = f0[k] + s * (K2p[k] - f0[k]);
  }
}

}    // namespace HardSphere

#endif
