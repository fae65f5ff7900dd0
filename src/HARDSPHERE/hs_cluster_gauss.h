/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: the 2-stage Gauss-Legendre flow of the modified
   Hamiltonian of one collision cluster (issue 21: the local form of fix
   hardsphere/mcva, doc/fix_hardsphere_mcva.rst "Local form"), with its
   stage equations solved by full Newton on the exact Jacobian.

   A cluster: n moving spheres ("members", slots 0..n-1) with inverse
   masses im (a = im F; the units' ftm2v mvv2e = 1, as in every LAMMPS
   unit style, so the kinetic energy is 1/2 v^2 / im), a constant force
   fc per member (the local engine's cross terms and held smooth forces)
   and the radial terms phi(|q_a - q_b|) of its restricted potential,
   either between two members or between a member and a static atom (a
   partner, which does not move in Phi_H1). Its modified Hamiltonian
   (Bond & Leimkuhler 2007, section 3, H_[2,VV] with the step dt of the
   splitting, c = dt^2/12):

     H~ = 1/2 v^T M v + V + c v^T V'' v - c/2 grad V^T M^-1 grad V,
     V  = sum_t phi_t - fc . q,

   and its flow in (q, v), F = -grad V, a = M^-1 F:

     dq/dt = v + 2c M^-1 V'' v
     dv/dt = M^-1 (F - c V'''[v, v] - c V'' a)

   (the field of HSMethodMCVA::field(), restricted to the cluster).

   Why Newton on the exact Jacobian here and simplified Newton
   (hs_newton.h, G = M^-1 V'' only) in the global form: a cluster has 2-8
   members, so its 12n stage equations are small and dense and a
   partial-pivot LU (Eigen) is cheap; with the leading Jacobian it is one
   complex 3n x 3n LU (LeadingStageLU). With the exact Jacobian at every
   iterate (ClusterNewtonOptions::full) the iteration converges
   quadratically; the engine keeps the Jacobian of the flow's start
   instead, by default its leading part from V'' (leading_jacobian(); the
   exact one, ClusterNewtonOptions::leading = false, took a fifth of a
   collisional step for no fewer iterations), which at the fluid's
   sub-steps stops in about 2.5 iterations from a cold start (the
   contraction's estimate, step()); a step from the same start as the last
   solved one (a contact time's trials) starts from that solution (step()'s
   predictor), 2.1 iterations per solve on average.

   The Jacobian is exact: each term's contribution to the field is a
   function of its two spheres' q, v and a (18 numbers), differentiated by
   forward-mode automatic differentiation (Eigen's AutoDiffScalar with a
   fixed 18-vector: no heap); the a-dependence goes through da/dq =
   -M^-1 V'' by the chain rule. The radial derivatives come from the
   caller's phi(kind, r, order, d): d[k] = phi^(k)(r), k = 0..order (4 for
   the Jacobian of V'''[v, v], 3 for the field, 2 for H~); each term's once
   per evaluation.

   The modified impulse (alpha-hat, hs_modified.h) keeps H~ across a
   contact; contact times are found on the Gauss flow (contact_root()).

   Pure math, no LAMMPS types, header-only, unit-tested alone
   (unittest/math/test_cluster_gauss.cpp).
------------------------------------------------------------------------- */

#ifndef LMP_HS_CLUSTER_GAUSS_H
#define LMP_HS_CLUSTER_GAUSS_H

#include "hs_gauss.h"
#include "hs_lj_terms.h"
#include "hs_modified.h"

#include <Eigen/Dense>
#include <unsupported/Eigen/AutoDiff>

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <type_traits>
#include <utility>
#include <vector>

namespace HardSphere {

// one radial term of a cluster: between members a and b, or (b < 0)
// between member a and a static atom at xb; kind: the caller's key for phi
// (partner: the caller's index of that static atom, >= 0 if it takes the
// term's momentum, partner_forces()). Between two members the term's
// separation is q_a - q_b + off (off: a periodic image's shift, constant)
struct ClusterTerm {
  int a = 0, b = -1;
  double xb[3] = {0.0, 0.0, 0.0};
  double off[3] = {0.0, 0.0, 0.0};
  int kind = 0;
  int partner = -1;
};

struct ClusterNewtonOptions {
  // converged when the largest change of a stage derivative, relative to
  // the largest stage derivative of its block (q' or v'), drops to tol, or
  // stops decreasing below stag_tol (round-off of the field reached)
  // (1e-12: with the start's Jacobian each iteration contracts by 1e-3 or
  // more at the fluid's sub-steps, so the stages stop within ~1e-15)
  double tol = 1.0e-12;
  double stag_tol = 1.0e-10;
  int maxit = 20;
  // true: the exact Jacobian at every iterate (quadratic convergence);
  // false: the exact Jacobian at the step's start, kept for its iterations
  // and for every step from the same start (a contact time's trial
  // lengths): each iteration then contracts by about h^2 |V'''| |v| / m,
  // 1e-5 or less at the steps where Verlet is accurate, for one Jacobian
  // per start instead of two per iteration
  bool full = false;
  // with !full: keep the Jacobian of the first start this kernel saw for
  // every later start (the sub-steps of one cluster flow, h <= dt/2 apart:
  // J moves by O(h) in q, and by O(dt^2) in v, as its v-dependent parts
  // carry c = dt^2/12), its field evaluated at each; the iteration then
  // contracts by about h^2 |V'''| |dq| / m more, for one Jacobian per flow
  bool keep = false;
  // with !full: the start's Jacobian is its leading part, from V'' alone
  // (leading_jacobian()): the parts it drops carry V''' and V'''' and are
  // O(c |V'''| |v|) against V'', so the iteration contracts about as fast
  // (on the 4000-sphere fluid 2.73 iterations per solve against the exact
  // Jacobian's 2.77) without the automatic differentiation, which took a
  // fifth of a collisional step; false: the exact Jacobian (field())
  bool leading = true;
  // record each iteration's change (ClusterNewtonStatus::history); false
  // (the cluster flows): none, as that vector's growth allocated 2-3 times
  // per solve
  bool history = true;
};

struct ClusterNewtonStatus {
  bool converged = false;
  int iterations = 0;    // Newton iterations (each: two fields and two Jacobians, one LU)
  int fields = 0;        // field evaluations (stages and predictor)
  int jacobians = 0;     // Jacobian evaluations
  double residual = 0.0;
  // the relative change of each iteration (for the rate of convergence)
  std::vector<double> history;
};

// what a step leaves besides its end state: the stage states Y1, Y2 (for
// the partners' momentum by the method's own quadrature) and the
// collocation polynomial of the positions, q(t) = q0 + t vq + t^2/2 aq on
// [0, h]: a Gauss method is the collocation method of its stages (Hairer,
// Lubich & Wanner, II.1.3), of degree 2 here, so q(t) is a parabola that
// ends at the step's end (the path on which contacts are predicted, as a
// Verlet sub-step's)
// every step()'s counts, summed (a flow's contact-time trials included)
struct ClusterTally {
  double solves = 0.0, iterations = 0.0, maxit = 0.0, fields = 0.0, jacobians = 0.0;
};

struct ClusterStepDetail {
  std::vector<double> Y1, Y2, vq, aq;
  // the partners' forces (ClusterTerm::partner) at the stages of the last
  // Newton iteration: the partners' momentum over the step is h (pf1 +
  // pf2) / 2, the same quadrature as the members' to the stages' tolerance
  std::vector<double> pf1, pf2;
};

// The Gauss stage matrix I - h A (x) J0 of a Jacobian in the leading form
// J0 = [[0, P], [Q, 0]] (ClusterGauss::leading_jacobian(): P = I + 2c G,
// Q = -G + c G G, m x m each), solved through one complex m x m LU instead
// of a real 4m x 4m one (Hairer & Wanner, Solving ODEs II, IV.8): Gauss'
// A = T diag(l, conj l) T^-1 with l = a11 + i b, b^2 = -a12 a21 (a11 =
// a22), eigenvectors (a12, +-i b), so that (I - h A (x) J0) D = R splits
// into (I - h l J0) x = s and its conjugate, s = R1 / (2 a12) - i R2 / (2 b),
// and D1 = 2 a12 Re x, D2 = -2 b Im x; with J0's blocks, x_v solves
// (I - mu^2 Q P) x_v = s_v + mu Q s_q (mu = h l) and x_q = s_q + mu P x_v.
// The same linear algebra as a real LU of the whole matrix, to round-off
// (unittest/math/test_cluster_gauss.cpp), for a sixth of its factorisation's
// instructions on the 4000 fluid (mostly 2 members)
// (M: m at compile time, or Eigen::Dynamic; StageLU below picks)
template <int M = Eigen::Dynamic> class LeadingStageLU {
 public:
  using Mat = Eigen::MatrixXd;
  using Vec = Eigen::VectorXd;
  using Cx = std::complex<double>;
  using CMat = Eigen::Matrix<Cx, M, M>;
  using CVec = Eigen::Matrix<Cx, M, 1>;
  // J0 (2m x 2m): only its blocks P (top right) and Q (bottom left) are read
  void set_blocks(const Mat &J0)
  {
    m_ = (int) J0.rows() / 2;
    const auto P = J0.block(0, m_, m_, m_);
    const auto Q = J0.block(m_, 0, m_, m_);
    QP_.noalias() = Q * P;
    P_ = P;
    Q_ = Q;
  }
  void factor(double h)
  {
    mu_ = h * Cx(GaussLegendre2::a11, b());
    M_ = (-(mu_ * mu_)) * QP_.template cast<Cx>();
    M_.diagonal().array() += 1.0;
    // PartialPivLU::compute()'s own factorisation (Eigen 3.3, 3.4), without
    // the l1 norm it also takes for rcond(), never asked here: 36 complex
    // abs() (hypot) a 6 x 6 matrix, ~1 % of mcva's instructions
    lu_ = M_;
    tr_.resize(m_);
    typename Eigen::Transpositions<M, M, int>::StorageIndex nswaps;
    Eigen::internal::partial_lu_inplace(lu_, tr_, nswaps);
  }
  // D = (I - h A (x) J0)^-1 R, R and D of 2N = 4m (the two stages' blocks)
  void solve(const Vec &R, Vec &D)
  {
    using GL = GaussLegendre2;
    const int N = 2 * m_, m = m_;
    const double r1 = 0.5 / GL::a12, r2 = -0.5 / b();
    sq_.resize(m);
    sv_.resize(m);
    for (int k = 0; k < m; k++) {
      sq_[k] = Cx(r1 * R[k], r2 * R[N + k]);
      sv_[k] = Cx(r1 * R[m + k], r2 * R[N + m + k]);
    }
    t_.noalias() = Q_ * sq_;
    t_ = sv_ + mu_ * t_;
    // (PartialPivLU::solve()'s steps: P t, then L and U in place)
    xv_ = tr_ * t_;
    lu_.template triangularView<Eigen::UnitLower>().solveInPlace(xv_);
    lu_.template triangularView<Eigen::Upper>().solveInPlace(xv_);
    xq_.noalias() = P_ * xv_;
    xq_ = sq_ + mu_ * xq_;
    const double d1 = 2.0 * GL::a12, d2 = -2.0 * b();
    D.resize(2 * N);
    for (int k = 0; k < m; k++) {
      D[k] = d1 * xq_[k].real();
      D[N + k] = d2 * xq_[k].imag();
      D[m + k] = d1 * xv_[k].real();
      D[N + m + k] = d2 * xv_[k].imag();
    }
  }

 private:
  static double b() { return std::sqrt(-GaussLegendre2::a12 * GaussLegendre2::a21); }
  int m_ = 0;
  // P and Q stay real: their products with the complex stage vectors are
  // real x complex (Eigen's mixed product), half the multiplications
  Eigen::Matrix<double, M, M> QP_, P_, Q_;
  CMat M_, lu_;
  Eigen::Transpositions<M, M, int> tr_;
  CVec sq_, sv_, t_, xq_, xv_;
  Cx mu_;
};

// LeadingStageLU with m fixed at compile time for a cluster of one or two
// members (nearly all of them on a fluid: Eigen's dynamic-size LU and
// solves spent more in calls and loops than in arithmetic at m = 6), else
// of dynamic size
class StageLU {
 public:
  using Mat = Eigen::MatrixXd;
  using Vec = Eigen::VectorXd;
  void set_blocks(const Mat &J0)
  {
    m_ = (int) J0.rows() / 2;
    with([&](auto &l) { l.set_blocks(J0); });
  }
  void factor(double h)
  {
    with([&](auto &l) { l.factor(h); });
  }
  void solve(const Vec &R, Vec &D)
  {
    with([&](auto &l) { l.solve(R, D); });
  }

 private:
  int m_ = 0;
  // f on the form of this m
  template <class F> void with(F f)
  {
    if (m_ == 3) f(l3_);
    else if (m_ == 6)
      f(l6_);
    else
      f(lx_);
  }
  LeadingStageLU<3> l3_;
  LeadingStageLU<6> l6_;
  LeadingStageLU<> lx_;
};

// a Phi that names a term's lj/cut coefficients: lj_coef(kind, fl) returns
// lj1..lj4 and the offset (hs_ljcut.h's LJCutTable row) and sets the
// special factor fl, or returns nullptr for a term of another form; its
// operator() then gives lj_cut_phi04()'s values for such a term (forces()
// takes a member's static lj/cut terms four at a time, hs_lj_terms.h, and
// the others one by one after them)
template <class P, class = void> struct PhiNamesLJ : std::false_type {};
template <class P>
struct PhiNamesLJ<P, std::void_t<decltype(std::declval<const P &>().lj_coef(
                         0, std::declval<double &>()))>> : std::true_type {};

template <class Phi> class ClusterGauss {
 public:
  using Mat = Eigen::MatrixXd;
  using Vec = Eigen::VectorXd;

  // n members, their inverse masses im[n], constant forces fc[3n] (null:
  // none), H~'s coefficient c = dt^2/12, the terms, the radial functions
  ClusterGauss(int n, const double *im, const double *fc, double c, std::vector<ClusterTerm> terms,
               Phi phi)
  {
    terms_ = std::move(terms);
    reset(n, im, fc, c, phi);
  }
  ClusterGauss() = default;
  // another cluster (terms: into terms(), before), with this object's
  // storage: a flow's kernel built anew held ~5 % of a collisional step in
  // malloc and free
  void reset(int n, const double *im, const double *fc, double c, Phi phi)
  {
    n_ = n;
    c_ = c;
    im_.assign(im, im + n);
    fc_.assign(3 * n, 0.0);
    if (fc) std::copy(fc, fc + 3 * n, fc_.begin());
    phi_ = phi;
    np_ = 0;
    for (const ClusterTerm &t : terms_) np_ = std::max(np_, t.partner + 1);
    // the terms between members first, then each member's static terms
    // together (soff_[a] .. soff_[a + 1]): with a static atom w = v_a and
    // a_rel = a_a are the member's own, so field() sums the static terms'
    // parts of V_t'' w, V_t'' a_rel and grad(w^T V_t'' w) as coefficients of
    // e, w and a_rel (static_field()), and forces() their V_t'' into one
    // 3 x 3 block (on the fluid nearly every term is static)
    // (a counting sort, each group in the caller's order)
    soff_.assign(n + 1, 0);
    for (const ClusterTerm &t : terms_)
      if (t.b < 0) soff_[t.a + 1]++;
    soff_[0] = (int) terms_.size();
    for (int a = 0; a < n; a++) soff_[0] -= soff_[a + 1];
    for (int a = 0; a < n; a++) soff_[a + 1] += soff_[a];
    std::vector<int> &next = snext_;
    next.assign(soff_.begin(), soff_.end() - 1);
    int mm = 0;
    tsort_.resize(terms_.size());
    for (const ClusterTerm &t : terms_) tsort_[t.b >= 0 ? mm++ : next[t.a]++] = t;
    terms_.swap(tsort_);
    // the static atoms' coordinates by column (static_terms()), and the
    // columns' scratch
    const int ns = (int) terms_.size() - soff_[0];
    sbx_.resize(ns);
    sby_.resize(ns);
    sbz_.resize(ns);
    for (int k = 0; k < ns; k++) {
      const ClusterTerm &t = terms_[soff_[0] + k];
      sbx_[k] = t.xb[0];
      sby_[k] = t.xb[1];
      sbz_[k] = t.xb[2];
    }
    gr_.resize(5 * (size_t) ns);
    gp_.resize(5 * (size_t) ns);
    gq_.resize(3 * (size_t) ns);    // (the partners' forces by component)
    gq1_.resize(3 * (size_t) ns);
    gq2_.resize(3 * (size_t) ns);
    // the terms' lj/cut coefficients where the Phi names them (PhiNamesLJ);
    // a term of another form (a bond, or every term of a Phi that names
    // none) takes zero coefficients in the batch and its own phi_() after
    // it (sother_, by member)
    sother_.clear();
    sooff_.assign(n + 1, 0);
    slj_.resize(ns);
    sfl_.resize(ns);
    static const double zero[5] = {0.0, 0.0, 0.0, 0.0, 0.0};
    for (int a = 0; a < n; a++) {
      for (int ti = soff_[a]; ti < soff_[a + 1]; ti++) {
        const int k = ti - soff_[0];
        slj_[k] = nullptr;
        if constexpr (PhiNamesLJ<Phi>::value) slj_[k] = phi_.lj_coef(terms_[ti].kind, sfl_[k]);
        if (!slj_[k]) {
          slj_[k] = zero;
          sfl_[k] = 0.0;
          sother_.push_back(ti - soff_[a]);
        }
      }
      sooff_[a + 1] = (int) sother_.size();
    }
    tally = ClusterTally();
    start_ok_ = last_ok_ = lu_ok_ = j0_leading_ = false;
    sh_ = lu_h_ = 0.0;
    stheta_ = -1.0;
  }
  std::vector<ClusterTerm> &terms() { return terms_; }

  int dim() const { return 6 * n_; }
  mutable ClusterTally tally;
  int members() const { return n_; }
  double coefficient() const { return c_; }
  double inverse_mass(int k) const { return im_[k]; }

  // H~ at y = (q[3n], v[3n])
  double energy(const double *y) const
  {
    const double *q = y, *v = y + 3 * n_;
    double V = 0.0;
    std::vector<double> F(3 * n_, 0.0);
    Mat K = Mat::Zero(3 * n_, 3 * n_);
    forces(q, V, F.data(), &K, 2, false);
    double T = 0.0, vKv = 0.0, g2 = 0.0;
    Eigen::Map<const Vec> vv(v, 3 * n_);
    vKv = vv.dot(K * vv);
    for (int k = 0; k < n_; k++)
      for (int d = 0; d < 3; d++) {
        T += 0.5 * v[3 * k + d] * v[3 * k + d] / im_[k];
        g2 += im_[k] * F[3 * k + d] * F[3 * k + d];
      }
    return T + V + c_ * vKv - 0.5 * c_ * g2;
  }

  // the field (dq/dt, dv/dt) at y into k[6n]; J (if not null): its Jacobian
  // pf (if not null, 3 x the partners' count): each static term's force
  // on its partner added (partner_forces()'s, in the same pass)
  // Kout (if not null, J null): V'' at y into it (leading_jacobian())
  // v3 (if not null, J null; 3n): M^-1 V'''[v, v] added (the terms'
  // grad(w^T V_t'' w), which the modified field computes anyway; step()'s
  // predictor)
  // prows (if not null, J and pf null; 3 x the static terms): the static
  // terms' partner forces by column, for add_partner_rows() (step()'s
  // stages: only the last iteration's are scattered)
  void field(const double *y, double *k, Mat *J = nullptr, double *pf = nullptr,
             Mat *Kout = nullptr, double *v3 = nullptr, double *prows = nullptr) const
  {
    const int m = 3 * n_;
    const double *q = y, *v = y + m;
    double V = 0.0;
    std::vector<double> &F = sF_, &a = sa_;
    F.assign(m, 0.0);
    a.resize(m);
    Mat &K = Kout ? *Kout : sK_;
    if (J || Kout) K.setZero(m, m);
    // (the static terms' values in pc_ only for the Jacobian's loop below:
    // without J, static_field() reads them by column)
    forces(q, V, F.data(), (J || Kout) ? &K : nullptr, J ? 4 : 3, J != nullptr);
    for (int i = 0; i < n_; i++)
      for (int d = 0; d < 3; d++) a[3 * i + d] = im_[i] * F[3 * i + d];
    for (int i = 0; i < n_; i++)
      for (int d = 0; d < 3; d++) {
        k[3 * i + d] = v[3 * i + d];
        k[m + 3 * i + d] = a[3 * i + d];
      }
    Mat &Da = sDa_;    // da/dq = -M^-1 V''
    if (J) {
      J->setZero(2 * m, 2 * m);
      J->block(0, m, m, m).setIdentity();
      Da = -K;
      for (int r = 0; r < m; r++) Da.row(r) *= im_[r / 3];
      J->block(m, 0, m, m) = Da;
    }
    // (without J: the static terms by member, static_field())
    const size_t nt = J ? terms_.size() : (size_t) soff_[0];
    if (!J)
      for (int i = 0; i < n_; i++)
        static_field(i, v + 3 * i, a.data() + 3 * i, k, pf, v3, prows);
    for (size_t ti = 0; ti < nt; ti++) {
      const ClusterTerm &t = terms_[ti];
      const TermAt &at = pc_[ti];
      const double *pt = at.p.data();
      const bool two = t.b >= 0;
      // inputs: q_a, q_b, v_a, v_b, a_a, a_b (a static atom: q = xb, v = a = 0)
      double z[18];
      for (int d = 0; d < 3; d++) {
        z[d] = q[3 * t.a + d];
        z[3 + d] = two ? q[3 * t.b + d] - t.off[d] : t.xb[d];
        z[6 + d] = v[3 * t.a + d];
        z[9 + d] = two ? v[3 * t.b + d] : 0.0;
        z[12 + d] = a[3 * t.a + d];
        z[15 + d] = two ? a[3 * t.b + d] : 0.0;
      }
      // outputs: 2c V_t'' w on a (b: minus) and -c (grad(w^T V_t'' w) + V_t'' a_rel) on a
      // (b: minus), w = v_a - v_b, a_rel = a_a - a_b
      if (!J) {
        double o[6], g[3];
        term_field_at(at, z, o, v3 ? g : nullptr);
        add_term(t, o, k);
        if (v3)
          for (int d = 0; d < 3; d++) {
            v3[3 * t.a + d] += im_[t.a] * g[d];
            if (two) v3[3 * t.b + d] -= im_[t.b] * g[d];
          }
        if (pf && !two && t.partner >= 0) add_partner(t, at, o, pf);
        continue;
      }
      AD za[18], o[6];
      for (int s = 0; s < 18; s++) za[s] = AD(z[s], 18, s);
      term_field<AD>(pt, za, o);
      double ov[6];
      for (int r = 0; r < 6; r++) ov[r] = o[r].value();
      add_term(t, ov, k);
      if (pf && !two && t.partner >= 0) add_partner(t, at, ov, pf);
      // chain rule into J: a row block (outputs of member a, and -those of b)
      // by the inputs' columns; a's columns through Da
      for (int side = 0; side < (two ? 2 : 1); side++) {
        const int who = side == 0 ? t.a : t.b;
        const double sgn = side == 0 ? 1.0 : -1.0;
        for (int r = 0; r < 6; r++) {
          const int row = (r < 3 ? 0 : m) + 3 * who + (r % 3);
          const double scale = sgn * im_[who];
          const auto &g = o[r].derivatives();
          for (int blk = 0; blk < 6; blk++) {
            // blk: 0 q_a, 1 q_b, 2 v_a, 3 v_b, 4 a_a, 5 a_b
            const int atom = (blk % 2 == 0) ? t.a : t.b;
            if (atom < 0) continue;
            for (int d = 0; d < 3; d++) {
              const double gd = scale * g[3 * blk + d];
              if (gd == 0.0) continue;
              const int col = 3 * atom + d;
              if (blk < 2) (*J)(row, col) += gd;
              else if (blk < 4) (*J)(row, m + col) += gd;
              else (*J).row(row).head(m) += gd * Da.row(col);
            }
          }
        }
      }
    }
  }

  // the field at y into k and the leading part of its Jacobian into J: with
  // G = M^-1 V'', d(dq/dt)/dv = I + 2c G (exact) and d(dv/dt)/dq = -G + c
  // G G (the chain rule's part through a = M^-1 F); dropped: the parts with
  // V''' and V'''' (d(dq/dt)/dq = 2c M^-1 V'''[v], d(dv/dt)/dv = -2c M^-1
  // V'''[v], and -c M^-1 (V''''[v, v] + V'''[a]) in d(dv/dt)/dq)
  void leading_jacobian(const double *y, double *k, Mat &J, double *v3 = nullptr) const
  {
    const int m = 3 * n_;
    field(y, k, nullptr, nullptr, &sK_, v3);
    Mat &G = sDa_;
    G = sK_;
    for (int r = 0; r < m; r++) G.row(r) *= im_[r / 3];
    J.setZero(2 * m, 2 * m);
    J.block(0, m, m, m).setIdentity();
    J.block(0, m, m, m) += (2.0 * c_) * G;
    J.block(m, 0, m, m).noalias() = c_ * G * G;
    J.block(m, 0, m, m) -= G;
  }

  // dR/dK = I - h [[a11 Ja, a12 Ja], [a21 Jb, a22 Jb]], factorised into ss_.lu
  void factor(const Mat &Ja, const Mat &Jb, double h) const
  {
    using GL = GaussLegendre2;
    const int N = dim();
    Mat &A = ss_.A;
    A.resize(2 * N, 2 * N);
    A.setIdentity();
    A.block(0, 0, N, N) -= h * GL::a11 * Ja;
    A.block(0, N, N, N) -= h * GL::a12 * Ja;
    A.block(N, 0, N, N) -= h * GL::a21 * Jb;
    A.block(N, N, N, N) -= h * GL::a22 * Jb;
    ss_.lu.compute(A);
  }

  // step()'s start: the start's field and Jacobian (kept while the start
  // is the same), the stage matrix's LU for h and the stages' predictor
  // (into ss_.K1, ss_.K2)
  void start_and_predict(const double *y0, double h, const ClusterNewtonOptions &opt,
                         ClusterNewtonStatus &st) const
  {
    using GL = GaussLegendre2;
    const int N = dim(), m = 3 * n_;
    // (scratch kept between calls: a step's vectors, matrix and LU were a
    // dozen heap allocations, 3 % of a collisional step on the fluid)
    Vec &K1 = ss_.K1, &K2 = ss_.K2;
    K1.resize(N);
    K2.resize(N);
    Eigen::Map<const Vec> y(y0, N);
    bool interp = false;    // (the predictor from the last step's stages)
    if (!opt.full) {
      // the start's field and Jacobian, kept while the start is the same
      if (!(start_ok_ && std::equal(y0, y0 + N, sy0_.data()))) {
        sy0_ = y;
        sf0_.resize(N);
        // (opt.keep: the Jacobian of this object's first start serves the
        // later ones, its field is evaluated anew)
        const bool fresh = !(opt.keep && start_ok_);
        // (and M^-1 V'''[v, v] for the predictor, where no exact
        // Jacobian is asked for)
        sv3_.setZero(m);
        if (fresh && opt.leading) leading_jacobian(y0, sf0_.data(), sJ0_, sv3_.data());
        else if (fresh)
          field(y0, sf0_.data(), &sJ0_);
        else    // (the kept J0's form decides whether the predictor takes V''')
          field(y0, sf0_.data(), nullptr, nullptr, nullptr, j0_leading_ ? sv3_.data() : nullptr);
        if (fresh) {
          j0_leading_ = opt.leading;
          if (opt.leading) slu_.set_blocks(sJ0_);
        }
        st.fields++;
        if (fresh) {
          st.jacobians++;
          lu_ok_ = false;
        }
        start_ok_ = true;
        last_ok_ = false;
        stheta_ = -1.0;
      }
      // the predictor: after a step of length h' from the same start (a
      // contact time's trials), the quadratic through f0 at 0 and its
      // stages K_i' at c_i h' (f along that step's path, to O(h'^3)) at the
      // new stage times: the first trial, a fraction of h' long, starts
      // within its interpolation error, not O(|h - h'| h) off as with
      // K_i' + c_i (h - h') J0 f0 (res 1e-3 on the fluid's first trials;
      // 108709 Newton iterations against 118845), and a later trial, 1e-5
      // h' or less away, within round-off of the solution. A step more than
      // half again as long (or after one of length 0) takes the start's
      // predictor, as a cold start: far out, the quadratic's extrapolation
      // is worse. Cold, with J0 in its leading form: the stages of a model
      // solved with the stage matrix's LU (below); with the exact J0, f(y(c_i
      // h)) to O(h^2), f0 + c_i h J0 f0 + (c_i h)^2 / 2 J0 J0 f0
      interp = last_ok_ && sh_ > 0.0 && h <= 1.5 * sh_;
      if (interp) {
        const double t1 = GL::c1 * sh_, t2 = GL::c2 * sh_;
        auto lagrange = [&](double t, Vec &K) {
          const double l0 = (t - t1) * (t - t2) / (t1 * t2);
          const double l1 = t * (t - t2) / (t1 * (t1 - t2));
          const double l2 = t * (t - t1) / (t2 * (t2 - t1));
          K = l0 * sf0_ + l1 * sK1_ + l2 * sK2_;
        };
        lagrange(GL::c1 * h, K1);
        lagrange(GL::c2 * h, K2);
      } else if (!j0_leading_) {
        // (J0 exact: no linear model below)
        Vec &Jf = ss_.Jf, &JJf = ss_.JJf;
        Jf.noalias() = sJ0_ * sf0_;
        JJf.noalias() = sJ0_ * Jf;
        K1 = sf0_ + (GL::c1 * h) * Jf + (0.5 * GL::c1 * GL::c1 * h * h) * JJf;
        K2 = sf0_ + (GL::c2 * h) * Jf + (0.5 * GL::c2 * GL::c2 * h * h) * JJf;
      }
    } else {
      field(y0, K1.data());
      st.fields++;
      K2 = K1;
    }
    // the last factorisation with J0 serves a length within 1e-6 of its
    // own (a contact time's later trials, 1e-5 h apart or less): the matrix
    // is then off by 1e-6 h |J0|, below the iteration's own contraction
    // from the stages' Jacobians' change, and the LU is not repeated
    // (J0's leading form: the same matrix solved through one complex m x m
    // LU, LeadingStageLU)
    const bool structured = !opt.full && j0_leading_;
    if (!opt.full && !(lu_ok_ && std::fabs(h - lu_h_) <= 1e-6 * std::fabs(lu_h_))) {
      if (structured) slu_.factor(h);
      else
        factor(sJ0_, sJ0_, h);
      lu_ok_ = true;
      lu_h_ = h;
    }
    // the cold predictor with J0's leading form: the exact stages of the
    // model y' = f0 + J0 (y - y0) + t b + t^2 / 2 d, K_i = f0 + h J0 sum_j
    // a_ij K_j + c_i h b + (c_i h)^2 / 2 d, solved with the LU above: the
    // model's f follows the flow's to O(t^2) but for the parts J0 drops,
    // b = (2c M^-1 V'''[v, v], 0) (d(dq/dt)/dq's dropped part times v) and
    // d = (0, -M^-1 V'''[v, v]) (the second derivative of a = M^-1 F along
    // the flow, less G a, which J0 carries), each to O(c); the stiff part
    // near a contact, h J0 of order 1, enters through the LU to all orders,
    // where the Taylor predictor f0 + c_i h J0 f0 + (c_i h)^2 / 2 J0 J0 f0
    // had it to second (108709 Newton iterations against 99667 on the 4000
    // fluid, 200 steps)
    if (structured && !interp) {
      Vec &R0 = ss_.R0, &P0 = ss_.P0;
      R0.resize(2 * N);
      R0.head(N) = sf0_;
      R0.tail(N) = sf0_;
      const double e1 = GL::c1 * h, e2 = GL::c2 * h;
      R0.segment(0, m) += (2.0 * c_ * e1) * sv3_;
      R0.segment(m, m) -= (0.5 * e1 * e1) * sv3_;
      R0.segment(N, m) += (2.0 * c_ * e2) * sv3_;
      R0.segment(N + m, m) -= (0.5 * e2 * e2) * sv3_;
      slu_.solve(R0, P0);
      K1 = P0.head(N);
      K2 = P0.tail(N);
    }
  }

  // the parabola u(t) = q0 + vq t + aq t^2 / 2 through stages K1, K2 of a
  // step of length h (u'(c_i h) = the q part of K_i)
  void parabola(const Vec &K1, const Vec &K2, double h, ClusterStepDetail &detail) const
  {
    using GL = GaussLegendre2;
    const int m = 3 * n_;
    detail.vq.resize(m);
    detail.aq.resize(m);
    for (int r = 0; r < m; r++) {
      const double aq = (K2[r] - K1[r]) / ((GL::c2 - GL::c1) * h);
      detail.aq[r] = aq;
      detail.vq[r] = K1[r] - aq * GL::c1 * h;
    }
  }

  // the parabola (detail's vq and aq) of a step of length h from y0 that
  // step()'s predictor gives, with no Newton iteration: where the start is
  // new, the cold predictor, the exact stages of a model whose field follows
  // the flow's to O(t^2) (start_and_predict()), so that a contact on it is
  // within O(h^3) of the flow's, as one on a solved step's parabola. A
  // step() of the same length from the same start then takes the start's
  // field, Jacobian and LU computed here (and solves for the same
  // predictor again: one LU solve)
  void predict(const double *y0, double h, const ClusterNewtonOptions &opt,
               ClusterStepDetail &detail) const
  {
    ClusterNewtonStatus st;
    start_and_predict(y0, h, opt, st);
    tally.fields += st.fields;
    tally.jacobians += st.jacobians;
    parabola(ss_.K1, ss_.K2, h, detail);
  }

  // one Gauss-Legendre step of length h from y0 into y1 (6n), stages by
  // Newton (ClusterNewtonOptions::full) from the predictor K1 = K2 = f(y0)
  // (full), else from start_and_predict()'s
  ClusterNewtonStatus step(const double *y0, double h, double *y1,
                           const ClusterNewtonOptions &opt = ClusterNewtonOptions(),
                           ClusterStepDetail *detail = nullptr) const
  {
    using GL = GaussLegendre2;
    const int N = dim(), m = 3 * n_;
    ClusterNewtonStatus st;
    start_and_predict(y0, h, opt, st);
    Vec &K1 = ss_.K1, &K2 = ss_.K2;
    Eigen::Map<const Vec> y(y0, N);
    const bool structured = !opt.full && j0_leading_;
    // started from the last solution (the predictor above)
    const bool warm = !opt.full && last_ok_;

    Vec &Y1 = ss_.Y1, &Y2 = ss_.Y2, &f1 = ss_.f1, &f2 = ss_.f2, &R = ss_.R, &D = ss_.D;
    Y1.resize(N);
    Y2.resize(N);
    f1.resize(N);
    f2.resize(N);
    R.resize(2 * N);
    D.resize(2 * N);
    Mat &J1 = ss_.J1, &J2 = ss_.J2;
    double prev = std::numeric_limits<double>::infinity();
    bool rows_pending = false;    // (gq1_, gq2_ hold an iteration's partner rows)
    for (int it = 0; it < opt.maxit; it++) {
      Y1 = y + h * (GL::a11 * K1 + GL::a12 * K2);
      Y2 = y + h * (GL::a21 * K1 + GL::a22 * K2);
      // R = K - f(Y)
      // (detail: the partners' forces at the stages, from the same passes,
      // which only the last iteration's are read of: not in a cold start's
      // first iteration, which stops the solve only if already below tol,
      // and then one more iteration takes them; 8.5 % of a collisional
      // step's instructions on the 4000 fluid were the partners' forces).
      // Without J, each stage's pass leaves its static terms' partner rows
      // (gq1_, gq2_) and only the last iteration's are added up, after the
      // loop, in the same order (the scatters of the iterations before the
      // last were 0.6 % of mcva's instructions at 32000 atoms)
      double *p1 = nullptr, *p2 = nullptr;
      const bool pf_skipped = detail && np_ > 0 && !opt.full && !warm && it == 0;
      const bool want_pf = detail && np_ > 0 && !pf_skipped;
      if (want_pf && opt.full) {
        detail->pf1.assign(3 * np_, 0.0);
        detail->pf2.assign(3 * np_, 0.0);
        p1 = detail->pf1.data();
        p2 = detail->pf2.data();
      }
      if (want_pf && !opt.full) rows_pending = true;
      if (opt.full) {
        field(Y1.data(), f1.data(), &J1, p1);
        field(Y2.data(), f2.data(), &J2, p2);
        st.jacobians += 2;
        factor(J1, J2, h);
        lu_ok_ = false;
      } else {
        field(Y1.data(), f1.data(), nullptr, nullptr, nullptr, nullptr,
              want_pf ? gq1_.data() : nullptr);
        field(Y2.data(), f2.data(), nullptr, nullptr, nullptr, nullptr,
              want_pf ? gq2_.data() : nullptr);
      }
      st.fields += 2;
      R.head(N) = K1 - f1;
      R.tail(N) = K2 - f2;
      if (structured) slu_.solve(R, D);
      else
        D.noalias() = ss_.lu.solve(R);
      K1 -= D.head(N);
      K2 -= D.tail(N);
      st.iterations++;
      // relative change per block (q', v'), as hs_gauss.h
      double res = 0.0;
      for (int blk = 0; blk < 2; blk++) {
        const int off = blk * m;
        const double sc = std::max({K1.segment(off, m).cwiseAbs().maxCoeff(),
                                    K2.segment(off, m).cwiseAbs().maxCoeff(), 1e-300});
        res = std::max({res, D.segment(off, m).cwiseAbs().maxCoeff() / sc,
                        D.segment(N + off, m).cwiseAbs().maxCoeff() / sc});
      }
      st.residual = res;
      if (opt.history) st.history.push_back(res);
      if (!(res == res) || std::isinf(res)) break;
      if (res <= opt.tol || (res <= opt.stag_tol && res >= prev)) {
        if (pf_skipped) {    // (above)
          prev = res;
          continue;
        }
        st.converged = true;
        break;
      }
      // with the start's Jacobian the iteration contracts linearly: with
      // theta = res / prev, the error left is about theta / (1 - theta) res
      // (Hairer & Wanner, Solving ODEs II, IV.8), below tol without one
      // more iteration to see it
      if (!opt.full && prev < 1.0) {
        const double theta = res / prev;
        stheta_ = theta;
        if (theta < 0.5 && theta / (1.0 - theta) * res <= opt.tol) {
          st.converged = true;
          break;
        }
      }
      // a warm start's first iteration: the contraction of the last solve
      // from the same start (the same Jacobian, a length within 1e-5 or so)
      // stands in for this one's (Hairer & Wanner's estimate from the
      // previous step), so that a trial that starts within round-off stops
      // after one iteration
      if (warm && it == 0 && stheta_ > 0.0 && stheta_ < 0.5 &&
          stheta_ / (1.0 - stheta_) * res <= opt.tol) {
        st.converged = true;
        break;
      }
      prev = res;
    }
    if (rows_pending) {    // (the last iteration's stage passes' partner forces)
      detail->pf1.assign(3 * np_, 0.0);
      detail->pf2.assign(3 * np_, 0.0);
      add_partner_rows(gq1_.data(), detail->pf1.data());
      add_partner_rows(gq2_.data(), detail->pf2.data());
    }
    Eigen::Map<Vec>(y1, N) = y + h * (GL::b1 * K1 + GL::b2 * K2);
    if (!opt.full && st.converged) {
      last_ok_ = true;
      sh_ = h;
      sK1_ = K1;
      sK2_ = K2;
    }
    tally.solves += 1.0;
    tally.iterations += st.iterations;
    tally.maxit = std::max(tally.maxit, (double) st.iterations);
    tally.fields += st.fields;
    tally.jacobians += st.jacobians;
    if (detail) {
      Y1 = y + h * (GL::a11 * K1 + GL::a12 * K2);
      Y2 = y + h * (GL::a21 * K1 + GL::a22 * K2);
      detail->Y1.assign(Y1.data(), Y1.data() + N);
      detail->Y2.assign(Y2.data(), Y2.data() + N);
      parabola(K1, K2, h, *detail);
    }
    return st;
  }

  // the force each term puts on its partner (ClusterTerm::partner) at y,
  // added into out[3 * partner]: minus the term's part of the members'
  // dp/dt (its force and its modified terms), so that members and partners
  // together conserve momentum (a term between two members gives +-)
  void partner_forces(const double *y, double *out) const
  {
    const int m = 3 * n_;
    const double *q = y, *v = y + m;
    double V = 0.0;
    std::vector<double> F(m, 0.0), a(m);
    forces(q, V, F.data(), nullptr, 3, true);
    for (int r = 0; r < m; r++) a[r] = im_[r / 3] * F[r];
    for (size_t ti = 0; ti < terms_.size(); ti++) {
      const ClusterTerm &t = terms_[ti];
      if (t.b >= 0 || t.partner < 0) continue;
      const TermAt &at = pc_[ti];
      double z[18], o[6];
      for (int d = 0; d < 3; d++) {
        z[d] = q[3 * t.a + d];
        z[3 + d] = t.xb[d];
        z[6 + d] = v[3 * t.a + d];
        z[9 + d] = 0.0;
        z[12 + d] = a[3 * t.a + d];
        z[15 + d] = 0.0;
      }
      term_field_at(at, z, o);
      add_partner(t, at, o, out);
    }
  }

  // the strength alpha of the impulse p -> p + alpha u (u[3n]) at y that
  // keeps H~ (alpha-hat, Bond & Leimkuhler 2007, eq. (3.3); hs_modified.h);
  // false if H~ is not convex in p along u
  bool alpha_hat(const double *y, const double *u, double &alpha) const
  {
    const int m = 3 * n_;
    double V = 0.0;
    std::vector<double> F(m, 0.0);
    Mat K = Mat::Zero(m, m);
    forces(y, V, F.data(), &K, 2, false);
    Eigen::Map<const Vec> uu(u, m), vv(y + m, m);
    Vec w(m);
    for (int r = 0; r < m; r++) w[r] = im_[r / 3] * u[r];
    const Vec Kw = K * w;
    return modified_alpha(uu.dot(vv), uu.dot(w), Kw.dot(vv), Kw.dot(w), 2.0 * c_, alpha);
  }

  // the first time t in (0, tmax] at which members i and j (j < 0: a static
  // atom at xj) come within sigma on the Gauss flow from y0, from the guess
  // (e.g. the Verlet prediction); each evaluation is one step() from y0.
  // off (members, null: none): their separation is q_i - q_j + off
  RootResult contact_time(const double *y0, int i, int j, const double *xj, double sigma,
                          double guess, double tmax, double ttol, int maxeval = 40,
                          const double *off = nullptr) const
  {
    std::vector<double> yt(dim());
    auto gap = [&](double t, double &g, double &dg) {
      step(y0, t, yt.data());
      double dq[3], dv[3];
      for (int d = 0; d < 3; d++) {
        dq[d] = yt[3 * i + d] - (j >= 0 ? yt[3 * j + d] - (off ? off[d] : 0.0) : xj[d]);
        dv[d] = yt[3 * n_ + 3 * i + d] - (j >= 0 ? yt[3 * n_ + 3 * j + d] : 0.0);
      }
      const double r = std::sqrt(dq[0] * dq[0] + dq[1] * dq[1] + dq[2] * dq[2]);
      g = r - sigma;
      dg = (dq[0] * dv[0] + dq[1] * dv[1] + dq[2] * dv[2]) / r;
    };
    return contact_root(gap, guess, tmax, ttol, maxeval);
  }

 private:
  using Der = Eigen::Matrix<double, 18, 1>;
  using AD = Eigen::AutoDiffScalar<Der>;

  int n_ = 0;
  int np_ = 0;    // partners (the largest ClusterTerm::partner + 1)
  double c_ = 0.0;
  std::vector<double> im_, fc_;
  // step(): the last start's field and Jacobian (ClusterNewtonOptions::full)
  mutable bool start_ok_ = false;
  mutable Vec sy0_, sf0_, sv3_;
  // the last converged step from that start: its length and stages
  mutable bool last_ok_ = false;
  mutable double sh_ = 0.0;
  mutable double stheta_ = -1.0;    // the last contraction seen (step())
  mutable Vec sK1_, sK2_;
  mutable Mat sJ0_;
  // step()'s scratch
  struct StepScratch {
    Vec K1, K2, Jf, JJf, Y1, Y2, f1, f2, R, D, R0, P0;
    Mat J1, J2, A;
    Eigen::PartialPivLU<Mat> lu;
  };
  mutable StepScratch ss_;
  // ss_.lu holds I - h A (x) J0 for h = lu_h_ and the kept start's J0
  // (its leading form: slu_)
  mutable bool lu_ok_ = false;
  mutable double lu_h_ = 0.0;
  mutable bool j0_leading_ = false;    // sJ0_ is leading_jacobian()'s
  mutable StageLU slu_;               // (its stage matrix)
  // field()'s scratch
  mutable std::vector<double> sF_, sa_;
  mutable Mat sK_, sDa_;
  std::vector<ClusterTerm> terms_;
  // terms_[soff_[a] .. soff_[a + 1]): member a's static terms (reset());
  // terms_[0 .. soff_[0]): the terms between members
  std::vector<int> soff_;
  std::vector<int> snext_;           // (reset()'s scratch)
  std::vector<ClusterTerm> tsort_;
  Phi phi_;

  // V, F = -grad V (fc included) and V'' (K) at positions q; each term's
  // phi^(k), k <= order, and the geometry kept in pc_ for term_field_at()
  // at the same q (the static terms' only with keep_static: the copy was
  // ~3 % of mcva's instructions, and only field()'s Jacobian and
  // partner_forces() read it)
  void forces(const double *q, double &V, double *F, Mat *K, int order,
              bool keep_static) const
  {
    pc_.resize(terms_.size());
    V = 0.0;
    for (int i = 0; i < 3 * n_; i++) {
      F[i] = fc_[i];
      V -= fc_[i] * q[i];
    }
    // one term: phi^(k), 1/r (term_field()'s arithmetic: one division a
    // term) and e kept; its force on a added into Fa; the coefficients of
    // V_t'' = phi'' e e^T + phi'/r (I - e e^T) returned (A = phi'' - phi'/r,
    // B = phi'/r)
    auto term = [&](int ti, const double *x, double *Fa, double &A,
                    double &B) -> const double * {
      const ClusterTerm &t = terms_[ti];
      const double r = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
      TermAt &at = pc_[ti];
      double *p = at.p.data();
      phi_(t.kind, r, order, p);
      V += p[0];
      at.ir = 1.0 / r;
      double *e = at.e;
      for (int d = 0; d < 3; d++) {
        e[d] = x[d] * at.ir;
        Fa[d] -= p[1] * e[d];
      }
      B = p[1] * at.ir;
      A = p[2] - B;
      return e;
    };
    // between members
    for (int ti = 0; ti < soff_[0]; ti++) {
      const ClusterTerm &t = terms_[ti];
      double x[3], A, B;
      for (int d = 0; d < 3; d++) x[d] = q[3 * t.a + d] - q[3 * t.b + d] + t.off[d];
      const double *e = term(ti, x, F + 3 * t.a, A, B);
      for (int d = 0; d < 3; d++) F[3 * t.b + d] += pc_[ti].p[1] * e[d];
      if (!K) continue;
      Eigen::Matrix3d H;
      for (int r1 = 0; r1 < 3; r1++)
        for (int c1 = 0; c1 < 3; c1++) H(r1, c1) = A * e[r1] * e[c1] + (r1 == c1 ? B : 0.0);
      K->block<3, 3>(3 * t.a, 3 * t.a) += H;
      K->block<3, 3>(3 * t.b, 3 * t.b) += H;
      K->block<3, 3>(3 * t.a, 3 * t.b) -= H;
      K->block<3, 3>(3 * t.b, 3 * t.a) -= H;
    }
    // each member's static terms: their V_t'' summed into one block
    // (static_terms())
    for (int a = 0; a < n_; a++) static_terms(a, q + 3 * a, V, F, K, order, keep_static);
  }

  // forces()' part of member a's static terms (at qa), in passes whose
  // iterations do not wait on each other: their geometry and the lj/cut
  // terms' phi^(k) four at a time (hs_lj_terms.h: a square root and two
  // divisions a term, which one term at a time held the loop to the
  // divider's latency; -8 % of mcva's instructions and -6 % of its time on
  // the 4000 fluid), the other terms' phi^(k) by phi_() after them, then
  // the sums; each term's values kept in pc_ for term_field_at(),
  // partner_forces() and the Jacobian
  void static_terms(int a, const double *qa, double &V, double *F, Mat *K, int order,
                    bool keep) const
  {
    const int t0 = soff_[a], na = soff_[a + 1] - t0, s = t0 - soff_[0];
    const int ns = (int) sbx_.size();
    double *r = gr_.data() + s, *ir = r + ns, *ex = ir + ns, *ey = ex + ns, *ez = ey + ns;
    double *p = gp_.data() + 5 * (size_t) s;
    static_geometry(qa, na, sbx_.data() + s, sby_.data() + s, sbz_.data() + s, r, ir, ex, ey, ez);
    if (sooff_[a + 1] - sooff_[a] < na) lj_phi(r, na, slj_.data() + s, sfl_.data() + s, order, p);
    for (int o = sooff_[a]; o < sooff_[a + 1]; o++) {
      const int k = sother_[o];
      double d[5] = {0.0, 0.0, 0.0, 0.0, 0.0};
      phi_(terms_[t0 + k].kind, r[k], order, d);
      for (int j = 0; j < 5; j++) p[j * na + k] = d[j];
    }
    if (keep)
      for (int k = 0; k < na; k++) {
        TermAt &at = pc_[t0 + k];
        for (int j = 0; j < 5; j++) at.p[j] = p[j * na + k];
        at.ir = ir[k];
        at.e[0] = ex[k];
        at.e[1] = ey[k];
        at.e[2] = ez[k];
      }
    if (!K) {
      // (V and the force, each in term order, four terms at a time)
      double acc[4] = {V, 0.0, 0.0, 0.0};
      static_force_sums(na, p, p + na, ex, ey, ez, acc);
      V = acc[0];
      for (int d = 0; d < 3; d++) F[3 * a + d] += acc[1 + d];
      return;
    }
    double Hs[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0}, Bs = 0.0;    // (xx yy zz xy xz yz)
    double Fa[3] = {0.0, 0.0, 0.0};
    for (int k = 0; k < na; k++) {
      const double e[3] = {ex[k], ey[k], ez[k]};
      const double p1 = p[na + k];
      V += p[k];
      for (int d = 0; d < 3; d++) Fa[d] -= p1 * e[d];
      const double B = p1 * ir[k], A = p[2 * na + k] - B;
      Hs[0] += A * e[0] * e[0];
      Hs[1] += A * e[1] * e[1];
      Hs[2] += A * e[2] * e[2];
      Hs[3] += A * e[0] * e[1];
      Hs[4] += A * e[0] * e[2];
      Hs[5] += A * e[1] * e[2];
      Bs += B;
    }
    for (int d = 0; d < 3; d++) F[3 * a + d] += Fa[d];
    if (na == 0) return;
    auto blk = K->block<3, 3>(3 * a, 3 * a);
    blk(0, 0) += Hs[0] + Bs;
    blk(1, 1) += Hs[1] + Bs;
    blk(2, 2) += Hs[2] + Bs;
    blk(0, 1) += Hs[3];
    blk(1, 0) += Hs[3];
    blk(0, 2) += Hs[4];
    blk(2, 0) += Hs[4];
    blk(1, 2) += Hs[5];
    blk(2, 1) += Hs[5];
  }

  // phi^(k)(r) for k = 1..3 as S from the term's p (forces() at the same
  // q); an AD r carries phi^(k+1) dr
  static void radial(const double *p, double, double out[3])
  {
    for (int k = 0; k < 3; k++) out[k] = p[k + 1];
  }
  static void radial(const double *p, const AD &r, AD out[3])
  {
    for (int k = 0; k < 3; k++) out[k] = AD(p[k + 1], p[k + 2] * r.derivatives());
  }
  // a term at the positions of the last forces(): phi^(k), 1/r, e = x / r
  struct TermAt {
    std::array<double, 5> p;
    double ir, e[3];
  };
  mutable std::vector<TermAt> pc_;
  // the static terms by column (reset()): their atoms' coordinates, lj/cut
  // coefficients and special factors (Phi names them: PhiNamesLJ; zeros for
  // the others); static_terms()' scratch (r, 1/r, e by column; phi^(k) in
  // rows of each member's count; static_field()'s partner forces)
  std::vector<double> sbx_, sby_, sbz_, sfl_;
  std::vector<const double *> slj_;
  std::vector<int> sother_, sooff_;    // a member's static terms not lj/cut (index in its terms)
  mutable std::vector<double> gr_, gp_, gq_;
  mutable std::vector<double> gq1_, gq2_;    // step()'s stages' partner rows (field()'s prows)

  // one term's part of the field, before the inverse mass (member a's; b's is
  // its negative): o[0..2] = 2c V_t'' w, o[3..5] = -c (grad_x (w^T V_t'' w)
  // + V_t'' a_rel), x = q_a - q_b, w = v_a - v_b, a_rel = a_a - a_b. With
  // s = e.w, V_t'' z = A (e.z) e + B z, A = phi'' - phi'/r, B = phi'/r:
  // w^T V_t'' w = A s^2 + B |w|^2, grad_x = A' s^2 e + 2 A s (w - s e)/r
  // + B' |w|^2 e, A' = phi''' - phi''/r + phi'/r^2, B' = phi''/r - phi'/r^2
  template <class S> void term_field(const double *pt, const S *z, S *o) const
  {
    using std::sqrt;
    S x[3], w[3], ar[3];
    for (int d = 0; d < 3; d++) {
      x[d] = z[d] - z[3 + d];
      w[d] = z[6 + d] - z[9 + d];
      ar[d] = z[12 + d] - z[15 + d];
    }
    const S r = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    S p[3];
    radial(pt, r, p);
    // (one division: 1/r, the rest products)
    const S ir = 1.0 / r;
    S e[3];
    for (int d = 0; d < 3; d++) e[d] = x[d] * ir;
    term_core<S>(p, ir, e, w, ar, o);
  }
  // the same in double at the positions of the last forces(), whose
  // geometry (1/r, e) and phi^(k) it takes: the same bits as term_field()
  void term_field_at(const TermAt &at, const double *z, double *o, double *g = nullptr) const
  {
    double w[3], ar[3];
    for (int d = 0; d < 3; d++) {
      w[d] = z[6 + d] - z[9 + d];
      ar[d] = z[12 + d] - z[15 + d];
    }
    term_core<double>(&at.p[1], at.ir, at.e, w, ar, o, g);
  }
  // p: phi', phi'', phi'''; g (if not null): grad(w^T V_t'' w) = V_t'''[w, w]
  template <class S>
  void term_core(const S *p, const S &ir, const S *e, const S *w, const S *ar, S *o,
                 S *g = nullptr) const
  {
    const S B = p[0] * ir, A = p[1] - B;
    const S Bp = (p[1] - B) * ir, Ap = p[2] - Bp;
    const S s = e[0] * w[0] + e[1] * w[1] + e[2] * w[2];
    const S ww = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
    const S sa = e[0] * ar[0] + e[1] * ar[1] + e[2] * ar[2];
    const S c2 = 2.0 * c_, cAs2 = 2.0 * A * s * ir;
    const S ce = Ap * s * s + Bp * ww - cAs2 * s;    // grad's e part: (A' s^2 + B' w^2 - 2 A s^2 / r)
    for (int d = 0; d < 3; d++) {
      const S Hw = A * s * e[d] + B * w[d];
      const S Ha = A * sa * e[d] + B * ar[d];
      const S grad = ce * e[d] + cAs2 * w[d];
      o[d] = c2 * Hw;
      o[3 + d] = -c_ * (grad + Ha);
      if (g) g[d] = grad;
    }
  }

  // member i's static terms' part of the field (term_core() with w = v_i,
  // a_rel = a_i, summed: sum_t V_t'' w = (sum A s e) + (sum B) w, and so
  // for V_t'' a_rel and grad(w^T V_t'' w)), of v3 and of their partners'
  // forces (add_partner()'s), at the positions of the last forces()
  void static_field(int i, const double *w, const double *ar, double *k, double *pf,
                    double *v3, double *prows = nullptr) const
  {
    if (soff_[i] == soff_[i + 1]) return;
    const double ww = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
    // the sums, each in term order, four terms at a time from the columns
    // of the last forces() (static_terms(), hs_lj_terms.h), with the
    // partners' forces by column if asked, then scattered (eleven sums
    // from stored rows, one term at a time, were 6 % of mcva's instructions
    // at 32000 atoms)
    const int t0 = soff_[i], na = soff_[i + 1] - t0, s = t0 - soff_[0];
    const int ns = (int) sbx_.size();
    const double *ir = gr_.data() + ns + s, *ex = ir + ns, *ey = ex + ns, *ez = ey + ns;
    const double *p = gp_.data() + 5 * (size_t) s;
    double *o = prows ? prows + 3 * (size_t) s : gq_.data();
    double S[STATIC_FIELD_SUMS] = {};
    static_field_terms(na, p + na, p + 2 * na, p + 3 * na, ir, ex, ey, ez, w, ar, ww, c_, S,
                       (pf || prows) ? o : nullptr);
    if (pf) scatter_partner_rows(i, o, pf);
    const double Bs = S[SF_B], Cs = S[SF_CAS2];
    const double *Ue = S + SF_AS_E, *Ge = S + SF_CE_E, *He = S + SF_ASA_E;
    const int m = 3 * n_;
    const double im = im_[i];
    for (int d = 0; d < 3; d++) {
      const double grad = Ge[d] + Cs * w[d];
      k[3 * i + d] += im * (2.0 * c_ * (Ue[d] + Bs * w[d]));
      k[m + 3 * i + d] += im * (-c_ * (grad + He[d] + Bs * ar[d]));
      if (v3) v3[3 * i + d] += im * grad;
    }
  }

  // member i's static terms' partner forces (rows o: 3 of its term count,
  // static_field_terms()') added to pf, term by term
  void scatter_partner_rows(int i, const double *o, double *pf) const
  {
    const int t0 = soff_[i], na = soff_[i + 1] - t0;
    for (int t = 0; t < na; t++) {
      const int pt = terms_[t0 + t].partner;
      // phi' e + c (grad + V_t'' a_rel)
      if (pt >= 0)
        for (int d = 0; d < 3; d++) pf[3 * pt + d] += o[d * na + t];
    }
  }
  // all members' rows (field()'s prows) added to pf, in field()'s order:
  // the same sums as field() with pf
  void add_partner_rows(const double *prows, double *pf) const
  {
    for (int i = 0; i < n_; i++)
      scatter_partner_rows(i, prows + 3 * (size_t) (soff_[i] - soff_[0]), pf);
  }

  // a static term's force on its partner: minus its part of the member's
  // dp/dt (phi' e less the modified part o[3..5]); at: the term at the
  // positions of the last forces()
  static void add_partner(const ClusterTerm &t, const TermAt &at, const double *o, double *pf)
  {
    for (int d = 0; d < 3; d++) pf[3 * t.partner + d] += at.p[1] * at.e[d] - o[3 + d];
  }

  void add_term(const ClusterTerm &t, const double *o, double *k) const
  {
    const int m = 3 * n_;
    for (int d = 0; d < 3; d++) {
      k[3 * t.a + d] += im_[t.a] * o[d];
      k[m + 3 * t.a + d] += im_[t.a] * o[3 + d];
      if (t.b >= 0) {
        k[3 * t.b + d] -= im_[t.b] * o[d];
        k[m + 3 * t.b + d] -= im_[t.b] * o[3 + d];
      }
    }
  }
};

}    // namespace HardSphere

#endif
