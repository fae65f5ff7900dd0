// Unit tests for the 2-stage Gauss-Legendre kernel in src/HARDSPHERE/hs_gauss.h
// (the Psi^[*] of Bond & Leimkuhler 2007, section 3.1).
//
// Expected values come from exact solutions (harmonic oscillator), exact
// invariants (quadratic invariants are conserved by Gauss methods: energy of
// linear oscillators, |m|^2 and the energy of the free rigid body), the
// classical order 4 (fitted slope on the nonlinear pendulum against a
// reference from classical RK4 with a tiny step, an independent method) and
// the convergence behaviour of fixed-point iteration.

#include "hs_gauss.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <vector>

using namespace HardSphere;

namespace {

using Field = std::function<void(const double *, double *)>;
auto no_reduce = [](double *, int) {};

// n steps of size h; returns the number of stage iterations in total
int integrate(const Field &f, std::vector<double> &y, double h, int nsteps, int nblocks = 1,
              const GaussOptions &opt = GaussOptions())
{
  const int n = (int) y.size();
  std::vector<double> K1(n), K2(n), work(3 * n), y1(n);
  int total = 0;
  for (int s = 0; s < nsteps; ++s) {
    f(y.data(), K1.data());
    K2 = K1;
    GaussStatus st = gauss2_stages(f, no_reduce, y.data(), n, nblocks, h, K1.data(), K2.data(),
                                   opt, work.data());
    EXPECT_TRUE(st.converged) << "step " << s << " residual " << st.residual;
    total += st.iterations;
    gauss2_update(y.data(), n, h, K1.data(), K2.data(), y1.data());
    y = y1;
  }
  return total;
}

double slope(const std::vector<double> &x, const std::vector<double> &y)
{
  const double n = (double) x.size();
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (size_t k = 0; k < x.size(); ++k) {
    sx += std::log(x[k]);
    sy += std::log(y[k]);
    sxx += std::log(x[k]) * std::log(x[k]);
    sxy += std::log(x[k]) * std::log(y[k]);
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

}    // namespace

TEST(Gauss, TableauSatisfiesOrderConditions)
{
  using G = GaussLegendre2;
  // row sums = c; b.c = 1/2; b.c^2 = 1/3; sum b a c = 1/6 (order conditions up to 3 plus
  // the collocation/simplifying ones that give order 4)
  EXPECT_NEAR(G::a11 + G::a12, G::c1, 1e-16);
  EXPECT_NEAR(G::a21 + G::a22, G::c2, 1e-16);
  EXPECT_NEAR(G::b1 + G::b2, 1.0, 1e-16);
  EXPECT_NEAR(G::b1 * G::c1 + G::b2 * G::c2, 0.5, 1e-16);
  EXPECT_NEAR(G::b1 * G::c1 * G::c1 + G::b2 * G::c2 * G::c2, 1.0 / 3.0, 1e-16);
  EXPECT_NEAR(G::b1 * G::c1 * G::c1 * G::c1 + G::b2 * G::c2 * G::c2 * G::c2, 0.25, 1e-16);
  EXPECT_NEAR(G::b1 * (G::a11 * G::c1 + G::a12 * G::c2) + G::b2 * (G::a21 * G::c1 + G::a22 * G::c2),
              1.0 / 6.0, 1e-16);
  // symplecticity condition b_i a_ij + b_j a_ji - b_i b_j = 0
  EXPECT_NEAR(2 * G::b1 * G::a11 - G::b1 * G::b1, 0.0, 1e-16);
  EXPECT_NEAR(G::b1 * G::a12 + G::b2 * G::a21 - G::b1 * G::b2, 0.0, 1e-16);
}

TEST(Gauss, HarmonicOscillatorEnergyToRoundoffAndPhaseOrder4)
{
  // q' = p, p' = -w^2 q; E = p^2 + w^2 q^2 is a quadratic invariant
  const double w = 1.7;
  Field f = [&](const double *y, double *k) {
    k[0] = y[1];
    k[1] = -w * w * y[0];
  };
  const double T = 10.0;
  std::vector<double> hs = {0.2, 0.1, 0.05, 0.025}, errs;
  for (double h : hs) {
    std::vector<double> y = {1.0, 0.3};
    const double E0 = y[1] * y[1] + w * w * y[0] * y[0];
    const int n = (int) std::lround(T / h);
    double Emax = 0.0;
    for (int s = 0; s < n; ++s) {
      integrate(f, y, h, 1);
      Emax = std::max(Emax, std::fabs(y[1] * y[1] + w * w * y[0] * y[0] - E0) / E0);
    }
    EXPECT_LT(Emax, 2e-14) << "h " << h;
    const double qex = 1.0 * std::cos(w * T) + 0.3 / w * std::sin(w * T);
    errs.push_back(std::fabs(y[0] - qex));
  }
  const double p = slope(hs, errs);
  EXPECT_NEAR(p, 4.0, 0.2) << "errors " << errs[0] << " .. " << errs.back();
}

TEST(Gauss, CoupledLinearSystemConservesItsQuadraticForm)
{
  // y' = (J S) y with J skew, S symmetric positive: H = y^T S y / 2 is a quadratic invariant
  const int n = 4;
  const double S[4][4] = {{3, 1, 0, 0.5}, {1, 2, 0.3, 0}, {0, 0.3, 4, 1}, {0.5, 0, 1, 2.5}};
  Field f = [&](const double *y, double *k) {
    double g[4];
    for (int i = 0; i < n; ++i) {
      g[i] = 0;
      for (int j = 0; j < n; ++j) g[i] += S[i][j] * y[j];
    }
    // J = [[0, I], [-I, 0]]
    k[0] = g[2];
    k[1] = g[3];
    k[2] = -g[0];
    k[3] = -g[1];
  };
  auto H = [&](const std::vector<double> &y) {
    double h = 0;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) h += 0.5 * y[i] * S[i][j] * y[j];
    return h;
  };
  std::vector<double> y = {0.3, -1.0, 0.7, 0.2};
  const double H0 = H(y);
  integrate(f, y, 0.15, 400, 2);
  EXPECT_LT(std::fabs(H(y) - H0) / H0, 1e-13);
}

TEST(Gauss, RigidBodyKeepsBothQuadraticInvariants)
{
  // Euler's equations m' = m x (I^-1 m): |m|^2 and m.I^-1 m are quadratic
  // invariants of a nonlinear flow; Gauss methods keep both to round-off
  const double I1 = 2.0, I2 = 1.0, I3 = 2.0 / 3.0;
  Field f = [&](const double *m, double *k) {
    const double w[3] = {m[0] / I1, m[1] / I2, m[2] / I3};
    k[0] = m[1] * w[2] - m[2] * w[1];
    k[1] = m[2] * w[0] - m[0] * w[2];
    k[2] = m[0] * w[1] - m[1] * w[0];
  };
  std::vector<double> m = {std::cos(1.1), 0.0, std::sin(1.1)};
  const double C0 = m[0] * m[0] + m[1] * m[1] + m[2] * m[2];
  const double E0 = m[0] * m[0] / I1 + m[1] * m[1] / I2 + m[2] * m[2] / I3;
  integrate(f, m, 0.1, 500);
  const double C = m[0] * m[0] + m[1] * m[1] + m[2] * m[2];
  const double E = m[0] * m[0] / I1 + m[1] * m[1] / I2 + m[2] * m[2] / I3;
  EXPECT_LT(std::fabs(C - C0) / C0, 1e-13);
  EXPECT_LT(std::fabs(E - E0) / E0, 1e-13);
}

TEST(Gauss, NonlinearPendulumIsFourthOrder)
{
  Field f = [](const double *y, double *k) {
    k[0] = y[1];
    k[1] = -std::sin(y[0]);
  };
  const double T = 4.0;
  // reference: classical RK4 with h = 1e-4 (global error ~1e-16)
  std::vector<double> ref = {2.0, 0.5};
  {
    const double h = 1e-4;
    const int n = (int) std::lround(T / h);
    for (int s = 0; s < n; ++s) {
      double k1[2], k2[2], k3[2], k4[2], t[2];
      f(ref.data(), k1);
      for (int i = 0; i < 2; ++i) t[i] = ref[i] + 0.5 * h * k1[i];
      f(t, k2);
      for (int i = 0; i < 2; ++i) t[i] = ref[i] + 0.5 * h * k2[i];
      f(t, k3);
      for (int i = 0; i < 2; ++i) t[i] = ref[i] + h * k3[i];
      f(t, k4);
      for (int i = 0; i < 2; ++i) ref[i] += h / 6.0 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
    }
  }
  std::vector<double> hs = {0.4, 0.2, 0.1, 0.05}, errs;
  for (double h : hs) {
    std::vector<double> y = {2.0, 0.5};
    integrate(f, y, h, (int) std::lround(T / h));
    errs.push_back(std::hypot(y[0] - ref[0], y[1] - ref[1]));
  }
  const double p = slope(hs, errs);
  EXPECT_NEAR(p, 4.0, 0.25) << "errors " << errs[0] << " " << errs[1] << " " << errs[2] << " "
                            << errs[3];
  EXPECT_LT(errs.back(), 1e-6);
}

TEST(Gauss, IterationCountFollowsContraction)
{
  // fixed-point iteration contracts by about |h lambda| per sweep on y' = lambda y:
  // smaller steps need fewer sweeps to reach 1e-14
  Field f = [](const double *y, double *k) { k[0] = -2.0 * y[0]; };
  std::vector<double> y = {1.0};
  const int it_big = integrate(f, y, 0.2, 1);
  y = {1.0};
  const int it_small = integrate(f, y, 0.002, 1);
  EXPECT_GT(it_big, it_small);
  EXPECT_LE(it_small, 6);
  // and the converged step matches the Gauss stability function
  // R(z) = (1 + z/2 + z^2/12) / (1 - z/2 + z^2/12) to round-off
  y = {1.0};
  integrate(f, y, 0.2, 1);
  const double z = -0.4;
  EXPECT_NEAR(y[0], (1 + z / 2 + z * z / 12) / (1 - z / 2 + z * z / 12), 1e-15);
}

TEST(Gauss, ReportsFailureWhenIterationDiverges)
{
  // |h lambda| = 5 > 1: the fixed point iteration diverges
  Field f = [](const double *y, double *k) { k[0] = -50.0 * y[0]; };
  std::vector<double> y = {1.0}, K1 = {-50.0}, K2 = {-50.0}, work(3);
  GaussStatus st = gauss2_stages(f, no_reduce, y.data(), 1, 1, 0.1, K1.data(), K2.data(),
                                 GaussOptions(), work.data());
  EXPECT_FALSE(st.converged);
  EXPECT_LT(st.iterations, 10);    // stopped as soon as it grew above 1
  EXPECT_GT(st.residual, 1.0);
  // too few iterations allowed: also reported
  GaussOptions few;
  few.maxit = 2;
  Field g = [](const double *y, double *k) { k[0] = -2.0 * y[0]; };
  K1 = {-2.0};
  K2 = {-2.0};
  st = gauss2_stages(g, no_reduce, y.data(), 1, 1, 0.2, K1.data(), K2.data(), few, work.data());
  EXPECT_FALSE(st.converged);
  EXPECT_EQ(st.iterations, 2);
}

TEST(Gauss, StagnationAtNoiseFloorCountsAsConverged)
{
  // a field with deterministic noise of relative size 1e-12 in its output:
  // the change cannot drop below ~1e-12, the iteration stops when it stagnates
  Field f = [](const double *y, double *k) {
    const double noise = 1e-12 * std::sin(1e7 * y[0]);
    k[0] = -y[0] * (1.0 + noise);
  };
  std::vector<double> y = {1.0}, K1 = {-1.0}, K2 = {-1.0}, work(3);
  GaussStatus st = gauss2_stages(f, no_reduce, y.data(), 1, 1, 0.3, K1.data(), K2.data(),
                                 GaussOptions(), work.data());
  EXPECT_TRUE(st.converged);
  EXPECT_LT(st.iterations, 40);
  EXPECT_LE(st.residual, GaussOptions().stag_tol);
}

TEST(Gauss, BlocksOfDifferentScaleEachConverge)
{
  // positions of size 1e6 and velocities of size 1e-6 in one state: the
  // small block's relative change decides, not the absolute one
  Field f = [](const double *y, double *k) {
    k[0] = 1e12 * y[1];     // q' = v (scaled)
    k[1] = -1e-12 * y[0];   // v' = -q (scaled)
  };
  std::vector<double> y = {1e6, 1e-6};
  // invariant: y0^2 * 1e-12 + y1^2 * 1e12
  auto E = [](const std::vector<double> &y) { return 1e-12 * y[0] * y[0] + 1e12 * y[1] * y[1]; };
  const double E0 = E(y);
  integrate(f, y, 0.1, 50, 2);
  EXPECT_LT(std::fabs(E(y) - E0) / E0, 1e-13);
}

TEST(Gauss, WarmStartGuessIsExactForLinearStageTimes)
{
  // K_i(h) = f(y(c_i h)) for y' = const + t: the linear extrapolation from
  // (0, f0) and (hp, K(hp)) is exact when K is linear in the stage time
  const double f0[1] = {1.0}, K1p[1] = {1.0 + 0.5}, K2p[1] = {1.0 + 1.5};
  double K1[1], K2[1];
  gauss2_guess(f0, K1p, K2p, 1.0, 2.0, 1, K1, K2);
  EXPECT_DOUBLE_EQ(K1[0], 2.0);
  EXPECT_DOUBLE_EQ(K2[0], 4.0);
}

TEST(Gauss, NaNAndInfAreFailures)
{
  // a field that turns NaN (or inf) away from y0 must not count as converged
  // (a NaN must not vanish in the max over blocks)
  for (double bad : {std::nan(""), HUGE_VAL}) {
    Field f = [bad](const double *y, double *k) {
      k[0] = (std::fabs(y[0] - 1.0) > 1e-3) ? bad : -y[0];
      k[1] = -y[1];
    };
    std::vector<double> y = {1.0, 1.0}, K1 = {-1.0, -1.0}, K2 = {-1.0, -1.0}, work(6);
    GaussStatus st = gauss2_stages(f, no_reduce, y.data(), 2, 2, 0.1, K1.data(), K2.data(),
                                   GaussOptions(), work.data());
    EXPECT_FALSE(st.converged) << bad;
    EXPECT_LT(st.iterations, 5) << bad;
  }
}
