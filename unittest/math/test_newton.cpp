// Unit tests for the simplified Newton solver of the Gauss-Legendre stage
// equations in src/HARDSPHERE/hs_newton.h (fix hardsphere/mcva, Bond &
// Leimkuhler 2007, section 3.1).
//
// The test field: four atoms of different masses in 3D with Morse pair
// potentials, y = (q, v), f = (v, M^-1 F(q)): smooth, nonlinear, with a
// Hessian that changes along the step. Expected values:
// - the block-sparse Hessian against central differences of the analytic
//   forces (an independent computation of V''x);
// - the Newton stages against the fixed-point stages of hs_gauss.h (the
//   same equations solved by another method);
// - a linear field f = J0 y is solved exactly by one Newton step (the
//   second iteration only confirms it);
// - convergence orders in h of the per-iteration contraction, from the
//   linearized error recursions (see hs_newton.h): fixed point h^1, Newton
//   with G = 0 h^2, Newton with G = M^-1 V''(y0) h^3 (the change of V''
//   along the step, O(h), times h^2).
// - Eigen's dense LU of the full 2n x 2n Newton matrix (I - h A (x) J0)
//   gives the same correction as the eliminated system with the Neumann
//   series.

#include "hs_newton.h"

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using namespace HardSphere;

namespace {

auto no_reduce = [](double *, int) {};

struct Morse {
  int N = 4;
  double D = 1.0, a = 1.5, r0 = 1.1;
  double mass[4] = {1.0, 2.0, 1.5, 3.0};
  // phi'(r), phi''(r)
  void dphi(double r, double &d1, double &d2) const
  {
    const double u = std::exp(-a * (r - r0));
    d1 = 2.0 * D * a * (u - u * u);
    d2 = 2.0 * D * a * a * u * (2.0 * u - 1.0);
  }
  // fn(i, j, del = q_i - q_j, r, phi'(r), phi''(r)) for every pair i < j
  template <class Fn> void each_pair(const double *q, Fn fn) const
  {
    for (int i = 0; i < N; ++i)
      for (int j = i + 1; j < N; ++j) {
        double del[3], rsq = 0.0;
        for (int d = 0; d < 3; ++d) {
          del[d] = q[3 * i + d] - q[3 * j + d];
          rsq += del[d] * del[d];
        }
        const double r = std::sqrt(rsq);
        double d1, d2;
        dphi(r, d1, d2);
        fn(i, j, del, r, d1, d2);
      }
  }
  // F = -grad V at q (3N)
  void forces(const double *q, double *F) const
  {
    for (int k = 0; k < 3 * N; ++k) F[k] = 0.0;
    each_pair(q, [&](int i, int j, const double *del, double r, double d1, double) {
      for (int d = 0; d < 3; ++d) {
        F[3 * i + d] -= d1 * del[d] / r;
        F[3 * j + d] += d1 * del[d] / r;
      }
    });
  }
  // G = M^-1 V''(q) as block-sparse
  void hessian(const double *q, RadialHessian &G) const
  {
    G.clear(N);
    for (int i = 0; i < N; ++i) G.set_row_scale(i, 1.0 / mass[i]);
    each_pair(q, [&](int i, int j, const double *del, double, double d1, double d2) {
      G.add_radial(i, j, del, d1, d2);
    });
  }
  // f(y) = (v, M^-1 F(q))
  void field(const double *y, double *k) const
  {
    const int m = 3 * N;
    std::vector<double> F(m);
    forces(y, F.data());
    for (int c = 0; c < m; ++c) {
      k[c] = y[m + c];
      k[m + c] = F[c] / mass[c / 3];
    }
  }
  std::vector<double> start() const
  {
    // a distorted tetrahedron near r0, moving
    return {0.0,  0.0,  0.0,  1.2, 0.1, -0.1, 0.5, 1.0, 0.05, 0.6, 0.4, 1.0,
            0.3,  -0.2, 0.1,  -0.4, 0.2, 0.3, 0.1, -0.3, 0.2, -0.2, 0.1, -0.25};
  }
};

// residual of the stage equations, max-norm relative to |K|
double stage_residual(const Morse &p, const std::vector<double> &y0, double h,
                      const std::vector<double> &K1, const std::vector<double> &K2)
{
  using G = GaussLegendre2;
  const int n = (int) y0.size();
  std::vector<double> Y(n), F(n);
  double res = 0.0, scale = 0.0;
  for (int s = 0; s < 2; ++s) {
    const double c1 = s ? G::a21 : G::a11, c2 = s ? G::a22 : G::a12;
    for (int k = 0; k < n; ++k) Y[k] = y0[k] + h * (c1 * K1[k] + c2 * K2[k]);
    p.field(Y.data(), F.data());
    const std::vector<double> &K = s ? K2 : K1;
    for (int k = 0; k < n; ++k) {
      res = std::max(res, std::fabs(F[k] - K[k]));
      scale = std::max(scale, std::fabs(K[k]));
    }
  }
  return res / scale;
}

// relative change after 'its' iterations from the cold start K = f(y0):
// the fixed point (mode 0), Newton with G = 0 (1), Newton with G (2)
double after(const Morse &p, double h, int its, int mode)
{
  const std::vector<double> y0 = p.start();
  const int n = (int) y0.size();
  std::vector<double> K1(n), K2(n);
  p.field(y0.data(), K1.data());
  K2 = K1;
  auto f = [&](const double *y, double *k) { p.field(y, k); };
  if (mode == 0) {
    GaussOptions o;
    o.maxit = its;
    o.tol = 0.0;
    o.stag_tol = 0.0;
    std::vector<double> work(3 * n);
    return gauss2_stages(f, no_reduce, y0.data(), n, 2, h, K1.data(), K2.data(), o, work.data())
        .residual;
  }
  RadialHessian G;
  p.hessian(y0.data(), G);
  auto applyG = [&](const double *x, double *out) { G.apply(x, out); };
  NewtonOptions o;
  o.gauss.maxit = its;
  o.gauss.tol = 0.0;
  o.gauss.stag_tol = 0.0;
  GaussNewton2 solver;
  return solver.solve(f, no_reduce, applyG, mode == 2, y0.data(), n, h, K1.data(), K2.data(), o)
      .residual;
}

}    // namespace

// V''x from the block-sparse assembly against central differences of F
TEST(RadialHessian, RadialHessianMatchesForceDifferences)
{
  Morse p;
  const std::vector<double> y = p.start();
  const int m = 3 * p.N;
  RadialHessian H;
  // unit masses: G = V''
  H.clear(p.N);
  for (int i = 0; i < p.N; ++i)
    for (int j = i + 1; j < p.N; ++j) {
      double del[3], rsq = 0.0;
      for (int d = 0; d < 3; ++d) {
        del[d] = y[3 * i + d] - y[3 * j + d];
        rsq += del[d] * del[d];
      }
      double d1, d2;
      p.dphi(std::sqrt(rsq), d1, d2);
      H.add_radial(i, j, del, d1, d2);
    }
  EXPECT_EQ(H.nterms(), 6u);
  std::vector<double> x(m), hx(m), qp(m), qm(m), Fp(m), Fm(m);
  for (int k = 0; k < m; ++k) x[k] = std::sin(1.0 + 2.3 * k);
  H.apply(x.data(), hx.data());
  const double eps = 1e-5;
  for (int k = 0; k < m; ++k) {
    qp[k] = y[k] + eps * x[k];
    qm[k] = y[k] - eps * x[k];
  }
  p.forces(qp.data(), Fp.data());
  p.forces(qm.data(), Fm.data());
  double scale = 0.0;
  for (int k = 0; k < m; ++k) scale = std::max(scale, std::fabs(hx[k]));
  for (int k = 0; k < m; ++k)
    EXPECT_NEAR(hx[k], -(Fp[k] - Fm[k]) / (2.0 * eps), 1e-8 * scale) << "component " << k;
  // an atom that does not move (index -1): only the other's diagonal block
  RadialHessian one;
  one.clear(1);
  const double del[3] = {0.3, -0.4, 1.2};
  one.add_radial(0, -1, del, 0.7, 2.0);
  const double e[3] = {0.3 / 1.3, -0.4 / 1.3, 1.2 / 1.3};
  double out[3];
  one.apply(e, out);    // k e = phi'' e
  for (int d = 0; d < 3; ++d) EXPECT_NEAR(out[d], 2.0 * e[d], 1e-15);
  const double t[3] = {0.4, 0.3, 0.0};    // perpendicular to e: k t = phi'/r t
  one.apply(t, out);
  for (int d = 0; d < 3; ++d) EXPECT_NEAR(out[d], 0.7 / 1.3 * t[d], 1e-15);
}

// the same stages as the fixed-point iteration, in fewer iterations
TEST(GaussNewton2, AgreesWithFixedPoint)
{
  Morse p;
  const std::vector<double> y0 = p.start();
  const int n = (int) y0.size();
  auto f = [&](const double *y, double *k) { p.field(y, k); };
  for (double h : {0.05, 0.2}) {
    std::vector<double> A1(n), A2(n), work(3 * n);
    p.field(y0.data(), A1.data());
    A2 = A1;
    GaussOptions go;
    const GaussStatus fp =
        gauss2_stages(f, no_reduce, y0.data(), n, 2, h, A1.data(), A2.data(), go, work.data());
    ASSERT_TRUE(fp.converged);

    RadialHessian G;
    p.hessian(y0.data(), G);
    auto applyG = [&](const double *x, double *out) { G.apply(x, out); };
    for (int useG = 0; useG < 2; ++useG) {
      std::vector<double> B1(n), B2(n);
      p.field(y0.data(), B1.data());
      B2 = B1;
      GaussNewton2 solver;
      const NewtonStatus nt = solver.solve(f, no_reduce, applyG, useG != 0, y0.data(), n, h,
                                           B1.data(), B2.data(), NewtonOptions());
      ASSERT_TRUE(nt.converged) << "h " << h << " useG " << useG;
      EXPECT_FALSE(nt.lin_dropped);
      // the solver stops at an estimated remaining error of tol = 1e-14 (2-norm
      // per block, relative); the max-norm residual is within a few of that
      EXPECT_LT(stage_residual(p, y0, h, B1, B2), 5e-14);
      double scale = 0.0;
      for (int k = 0; k < n; ++k) scale = std::max(scale, std::fabs(A1[k]));
      for (int k = 0; k < n; ++k) {
        EXPECT_NEAR(B1[k], A1[k], 1e-13 * scale);
        EXPECT_NEAR(B2[k], A2[k], 1e-13 * scale);
      }
      printf("[ h %.2f ] fixed point %d iterations, Newton (G %s) %d, %d products with G\n", h,
             fp.iterations, useG ? "M^-1 V''" : "0", nt.iterations, nt.lin_iters);
      EXPECT_LT(nt.iterations, fp.iterations);
    }
  }
}

// linear field f = J0 y with the G given to the solver: one Newton step is
// exact, the second iteration's correction is round-off
TEST(GaussNewton2, LinearFieldInOneStep)
{
  Morse p;
  const std::vector<double> y0 = p.start();
  const int n = (int) y0.size(), m = n / 2;
  RadialHessian G;
  p.hessian(y0.data(), G);
  auto applyG = [&](const double *x, double *out) { G.apply(x, out); };
  auto f = [&](const double *y, double *k) {
    G.apply(y, k + m);    // dv/dt = -G q
    for (int c = 0; c < m; ++c) {
      k[m + c] = -k[m + c];
      k[c] = y[m + c];
    }
  };
  std::vector<double> K1(n, 0.0), K2(n, 0.0);
  NewtonOptions o;
  o.gauss.maxit = 2;
  o.gauss.tol = 0.0;
  o.gauss.stag_tol = 0.0;
  o.lin_tol = 1e-15;    // the linear solve to round-off: the step is exact
  GaussNewton2 solver;
  const NewtonStatus st =
      solver.solve(f, no_reduce, applyG, true, y0.data(), n, 0.3, K1.data(), K2.data(), o);
  EXPECT_EQ(st.iterations, 2);
  EXPECT_LT(st.residual, 1e-13);    // round-off of |K| ~ 1 (the first correction is K itself)
}

// the per-iteration contraction factor scales as h (fixed point), h^2
// (Newton, G = 0) and h^3 (Newton, G = M^-1 V''(y0))
TEST(GaussNewton2, ContractionOrders)
{
  Morse p;
  const int mode_order[3] = {1, 2, 3};
  for (int mode = 0; mode < 3; ++mode) {
    // contraction of the third iteration over the second, at h and h/2
    const double h = 0.1;
    auto rate = [&](double hh) { return after(p, hh, 3, mode) / after(p, hh, 2, mode); };
    const double r1 = rate(h), r2 = rate(h / 2.0);
    const double order = std::log2(r1 / r2);
    printf("[ mode %d ] contraction %.3e (h %.3f), %.3e (h %.3f): order %.2f\n", mode, r1, h, r2,
           h / 2.0, order);
    EXPECT_NEAR(order, mode_order[mode], 0.3) << "mode " << mode;
    EXPECT_LT(r1, 1.0);
  }
}

// the eliminated system with the Neumann series against Eigen's dense LU of
// the full Newton matrix (I - h A (x) J0) for one correction
TEST(GaussNewton2, CorrectionMatchesDenseNewtonSolve)
{
  using GL = GaussLegendre2;
  Morse p;
  const std::vector<double> y0 = p.start();
  const int n = (int) y0.size(), m = n / 2;
  const double h = 0.2;
  RadialHessian G;
  p.hessian(y0.data(), G);
  // dense J0 = [[0, I], [-G, 0]]
  Eigen::MatrixXd J0 = Eigen::MatrixXd::Zero(n, n);
  for (int c = 0; c < m; ++c) {
    std::vector<double> e(m, 0.0), col(m);
    e[c] = 1.0;
    G.apply(e.data(), col.data());
    J0(c, m + c) = 1.0;
    for (int r = 0; r < m; ++r) J0(m + r, c) = -col[r];
  }
  const double a[2][2] = {{GL::a11, GL::a12}, {GL::a21, GL::a22}};
  Eigen::MatrixXd Mat = Eigen::MatrixXd::Identity(2 * n, 2 * n);
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) Mat.block(i * n, j * n, n, n) -= h * a[i][j] * J0;
  // one solver iteration from K = 0: Delta solves Mat Delta = D = f(y0) - 0
  std::vector<double> K1(n, 0.0), K2(n, 0.0), f0(n);
  p.field(y0.data(), f0.data());
  auto f = [&](const double *y, double *k) { p.field(y, k); };
  auto applyG = [&](const double *x, double *out) { G.apply(x, out); };
  NewtonOptions o;
  o.gauss.maxit = 1;
  o.lin_tol = 1e-15;    // to round-off, for the comparison
  GaussNewton2 solver;
  solver.solve(f, no_reduce, applyG, true, y0.data(), n, h, K1.data(), K2.data(), o);
  Eigen::VectorXd D(2 * n);
  for (int k = 0; k < n; ++k) D(k) = D(n + k) = f0[k];    // both stages at y0 + 0
  const Eigen::VectorXd Delta = Mat.partialPivLu().solve(D);
  const double scale = Delta.cwiseAbs().maxCoeff();
  for (int k = 0; k < n; ++k) {
    EXPECT_NEAR(K1[k], Delta(k), 1e-13 * scale);
    EXPECT_NEAR(K2[k], Delta(n + k), 1e-13 * scale);
  }
}
