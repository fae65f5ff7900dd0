// Unit tests for src/HARDSPHERE/hs_modified.h: the modified collision
// strength alpha-hat of Bond & Leimkuhler (2007), section 3.1, and the
// safeguarded root finder for the collision time on the Gauss flow.
//
// Expected values: conservation of the quadratic form H~(p) = 1/2 p^T A p,
// A = M^-1 + dt^2/6 M^-1 K M^-1 (the p-dependent part of H_[2,VV] with
// K = V''), checked in closed form for random masses and random symmetric
// K; the elastic limit; known roots of adversarial scalar functions.

#include "hs_contact.h"
#include "hs_modified.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>
#include <vector>

using namespace HardSphere;

namespace {

struct Problem {
  int n;
  std::vector<double> minv;    // diagonal M^-1
  std::vector<double> K;       // symmetric V'', n x n
  std::vector<double> u, p;
};

Problem random_problem(std::mt19937_64 &eng, int n, double kscale)
{
  std::uniform_real_distribution<double> U(-1.0, 1.0), L(-1.0, 1.0);
  Problem P;
  P.n = n;
  P.minv.resize(n);
  P.K.assign(n * n, 0.0);
  P.u.resize(n);
  P.p.resize(n);
  for (int i = 0; i < n; ++i) P.minv[i] = 1.0 / std::pow(10.0, L(eng));    // masses 0.1..10
  for (int i = 0; i < n; ++i)
    for (int j = 0; j <= i; ++j) P.K[i * n + j] = P.K[j * n + i] = kscale * U(eng);
  for (int i = 0; i < n; ++i) {
    P.u[i] = U(eng);
    P.p[i] = U(eng);
  }
  return P;
}

// H~(p) = 1/2 p^T (M^-1 + c M^-1 K M^-1) p, written out as in H_[2,VV]:
// 1/2 p M^-1 p + c/2 v^T K v with v = M^-1 p (c = dt^2/6, so c/2 = dt^2/12)
double Htilde(const Problem &P, const std::vector<double> &p, double c)
{
  const int n = P.n;
  double kin = 0.0, vKv = 0.0;
  for (int i = 0; i < n; ++i) kin += 0.5 * p[i] * p[i] * P.minv[i];
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) vKv += (p[i] * P.minv[i]) * P.K[i * n + j] * (p[j] * P.minv[j]);
  return kin + 0.5 * c * vKv;
}

double alpha_hat(const Problem &P, double c, bool &ok)
{
  const int n = P.n;
  std::vector<double> w(n), v(n);
  for (int i = 0; i < n; ++i) {
    w[i] = P.minv[i] * P.u[i];
    v[i] = P.minv[i] * P.p[i];
  }
  double uv = 0, uw = 0, wKv = 0, wKw = 0;
  for (int i = 0; i < n; ++i) {
    uv += P.u[i] * v[i];
    uw += P.u[i] * w[i];
    for (int j = 0; j < n; ++j) {
      wKv += w[i] * P.K[i * n + j] * v[j];
      wKw += w[i] * P.K[i * n + j] * w[j];
    }
  }
  double a = 0.0;
  ok = modified_alpha(uv, uw, wKv, wKw, c, a);
  return a;
}

}    // namespace

TEST(ModifiedImpulse, ConservesModifiedKineticFormToRoundoff)
{
  std::mt19937_64 eng(20070101);
  int tested = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 2 + trial % 9;
    Problem P = random_problem(eng, n, 5.0);
    const double dt = 0.05 + 0.003 * (trial % 50);
    const double c = dt * dt / 6.0;
    bool ok;
    const double a = alpha_hat(P, c, ok);
    if (!ok) continue;
    ++tested;
    std::vector<double> p1(P.p);
    for (int i = 0; i < n; ++i) p1[i] += a * P.u[i];
    const double H0 = Htilde(P, P.p, c), H1 = Htilde(P, p1, c);
    // scale of the terms that cancel
    double scale = 0.0;
    for (int i = 0; i < n; ++i) scale += (P.p[i] * P.p[i] + a * a * P.u[i] * P.u[i]) * P.minv[i];
    EXPECT_LT(std::fabs(H1 - H0), 1e-13 * scale) << "trial " << trial;
    // the nontrivial root: the modified normal velocity u^T A p flips sign
    EXPECT_NE(a, 0.0);
  }
  EXPECT_GT(tested, 150);
}

TEST(ModifiedImpulse, PaperPrintedCoefficientDoesNotConserveHtilde)
{
  // the paper prints alpha-hat = -2 u^T (M^-1 + dt^2 V''/12) p / u^T (M^-1 + dt^2 V''/12) u.
  // With unit masses and H_[2,VV] = H + dt^2/24 H2 the matrix of the p-quadratic form is
  // M^-1 + dt^2/6 V'': the printed 1/12 changes H~ by O(dt^2), far above round-off.
  std::mt19937_64 eng(7);
  Problem P = random_problem(eng, 6, 3.0);
  for (double &m : P.minv) m = 1.0;
  const double dt = 0.2, c = dt * dt / 6.0;
  bool ok;
  const double a_right = alpha_hat(P, c, ok);
  ASSERT_TRUE(ok);
  const double a_paper = alpha_hat(P, dt * dt / 12.0, ok);
  ASSERT_TRUE(ok);
  std::vector<double> pr(P.p), pp(P.p);
  for (int i = 0; i < P.n; ++i) {
    pr[i] += a_right * P.u[i];
    pp[i] += a_paper * P.u[i];
  }
  const double H0 = Htilde(P, P.p, c);
  EXPECT_LT(std::fabs(Htilde(P, pr, c) - H0), 1e-14 * std::fabs(H0) + 1e-15);
  EXPECT_GT(std::fabs(Htilde(P, pp, c) - H0), 1e-5 * std::fabs(H0));
}

TEST(ModifiedImpulse, ElasticLimitIsTheCVAImpulse)
{
  // K = 0 (or dt = 0): alpha-hat u reduces to the elastic impulse of section 2
  const double dq[3] = {0.6, -0.7, 0.38}, vi[3] = {0.3, 0.2, -1.0}, vj[3] = {-0.5, 0.4, 0.1};
  const double mi = 1.3, mj = 0.4;
  double J[3], dv[3];
  for (int k = 0; k < 3; ++k) dv[k] = vi[k] - vj[k];
  pair_impulse(dq, dv, mi, mj, J);
  // u = (dq, -dq), w = M^-1 u
  double uv = 0, uw = 0;
  for (int k = 0; k < 3; ++k) {
    uv += dq[k] * vi[k] - dq[k] * vj[k];
    uw += dq[k] * dq[k] / mi + dq[k] * dq[k] / mj;
  }
  double a;
  ASSERT_TRUE(modified_alpha(uv, uw, 123.0, -45.0, 0.0, a));
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(a * dq[k], J[k], 1e-15);
}

TEST(ModifiedImpulse, NonConvexDirectionIsRejected)
{
  double a = 7.0;
  // u^T A u = uw + c wKw <= 0
  EXPECT_FALSE(modified_alpha(1.0, 1.0, 0.0, -10.0, 0.1, a));
  EXPECT_FALSE(modified_alpha(1.0, 1.0, 0.0, -10.0, 0.2, a));
  EXPECT_EQ(a, 7.0);
  EXPECT_TRUE(modified_alpha(1.0, 1.0, 0.0, -10.0, 0.05, a));
  EXPECT_DOUBLE_EQ(a, -2.0 / 0.5);
}

// ---------------------------------------------------------------------- root finder

namespace {

using Fn = std::function<double(double)>;

// phi from g with a derivative estimate scaled by 'dscale' (approximate derivatives)
RootResult solve(const Fn &g, const Fn &dg, double guess, double tmax, double dscale = 1.0,
                 int maxeval = 200, double ttol = 1e-14)
{
  auto phi = [&](double t, double &gv, double &dgv) {
    gv = g(t);
    dgv = dscale * dg(t);
  };
  return contact_root(phi, guess, tmax, ttol, maxeval);
}

// the result is a contact: on the allowed side (g >= 0), with g <= 0 within ttol after it
void expect_contact(const RootResult &r, const Fn &g, double troot, double ttol = 1e-14)
{
  ASSERT_EQ(r.status, ROOT_FOUND);
  EXPECT_GE(g(r.t), 0.0);
  EXPECT_LE(r.t, troot + 1e-15);
  EXPECT_NEAR(r.t, troot, 4 * ttol + 1e-15 * troot);
}

}    // namespace

TEST(ContactRoot, LinearAndSmoothWithExactDerivative)
{
  Fn g = [](double t) { return 0.3 - t; };
  Fn dg = [](double) { return -1.0; };
  RootResult r = solve(g, dg, 0.29, 1.0);
  expect_contact(r, g, 0.3);
  EXPECT_LE(r.nevals, 4);
  // squared-distance gap of two spheres in free flight: |q + t v|^2 - s^2
  Fn g2 = [](double t) {
    const double x = 2.0 - 3.0 * t, y = 0.5 + 0.2 * t;
    return x * x + y * y - 1.0;
  };
  Fn d2 = [](double t) {
    const double x = 2.0 - 3.0 * t, y = 0.5 + 0.2 * t;
    return -6.0 * x + 0.4 * y;
  };
  // roots of 9.04 t^2 - 11.8 t + 3.25 = 0
  const double A = 9.04, B = -11.8, C = 3.25;
  const double t1 = (-B - std::sqrt(B * B - 4 * A * C)) / (2 * A);
  for (double guess : {t1 * 0.999, t1 * 1.001, t1}) {
    r = solve(g2, d2, guess, 1.0);
    expect_contact(r, g2, t1);
    EXPECT_LE(r.nevals, 8) << "guess " << guess;
  }
}

TEST(ContactRoot, ApproximateOrWrongDerivatives)
{
  Fn g = [](double t) { return std::cos(3.0 * t) - 0.2; };
  Fn dg = [](double t) { return -3.0 * std::sin(3.0 * t); };
  const double root = std::acos(0.2) / 3.0;
  for (double dscale : {0.999, 1.001, 0.5, 3.0, 0.01, 100.0}) {
    for (double guess : {0.95 * root, 1.05 * root, 0.2 * root}) {
      RootResult r = solve(g, dg, guess, 1.0, dscale);
      expect_contact(r, g, root);
      EXPECT_LE(r.nevals, 20) << "dscale " << dscale << " guess " << guess;
    }
  }
  // a derivative estimate with the wrong sign: the bracket keeps it safe
  // when the guess lies past the root
  RootResult r = solve(g, dg, 1.2 * root, 1.0, -1.0);
  expect_contact(r, g, root);
}

TEST(ContactRoot, FlatTripleRoot)
{
  // g = (t0 - t)^3: Newton converges only linearly, bisection must take over
  const double t0 = 0.4;
  Fn g = [&](double t) { return std::pow(t0 - t, 3); };
  Fn dg = [&](double t) { return -3.0 * std::pow(t0 - t, 2); };
  RootResult r = solve(g, dg, 0.5, 1.0);
  ASSERT_EQ(r.status, ROOT_FOUND);
  EXPECT_GE(g(r.t), 0.0);
  EXPECT_NEAR(r.t, t0, 1e-13);
  EXPECT_LE(r.nevals, 120);
}

TEST(ContactRoot, NoContact)
{
  // stays positive: gap closing but the root lies past tmax
  Fn g = [](double t) { return 2.0 - t; };
  Fn dg = [](double) { return -1.0; };
  RootResult r = solve(g, dg, 0.9, 1.0);
  EXPECT_EQ(r.status, ROOT_NONE);
  EXPECT_LE(r.nevals, 3);
  // grazing: minimum 0.01 > 0 at t = 0.5, guessed contact at its bottom
  Fn h = [](double t) { return (t - 0.5) * (t - 0.5) + 0.01; };
  Fn dh = [](double t) { return 2.0 * (t - 0.5); };
  r = solve(h, dh, 0.5, 1.0);
  EXPECT_EQ(r.status, ROOT_NONE);
  r = solve(h, dh, 0.45, 1.0);
  EXPECT_EQ(r.status, ROOT_NONE);
  // opening at the guess and positive at tmax
  r = solve(h, dh, 0.7, 1.0);
  EXPECT_EQ(r.status, ROOT_NONE);
}

TEST(ContactRoot, RootAtOrNearTheEnds)
{
  Fn g = [](double t) { return 1.0 - t; };
  Fn dg = [](double) { return -1.0; };
  RootResult r = solve(g, dg, 0.999, 1.0);
  ASSERT_EQ(r.status, ROOT_FOUND);
  EXPECT_NEAR(r.t, 1.0, 1e-14);
  EXPECT_GE(g(r.t), 0.0);
  // the root just before tmax, guessed past it (clamped to tmax)
  Fn g2 = [](double t) { return 0.9999999 - t; };
  r = solve(g2, dg, 1.5, 1.0);
  expect_contact(r, g2, 0.9999999);
  // a root very near 0
  Fn g3 = [](double t) { return 1e-12 - t; };
  r = solve(g3, dg, 0.3, 1.0);
  expect_contact(r, g3, 1e-12);
}

TEST(ContactRoot, SeparatingFromContactThenReturning)
{
  // g(0) = 0 while opening (a pair that just collided), back to 0 at t = 0.3
  Fn g = [](double t) { return t * (0.3 - t); };
  Fn dg = [](double t) { return 0.3 - 2.0 * t; };
  for (double guess : {0.25, 0.299, 0.31, 0.6}) {
    RootResult r = solve(g, dg, guess, 1.0);
    expect_contact(r, g, 0.3);
  }
}

TEST(ContactRoot, StiffExponentialAndKinks)
{
  // very steep near the root, flat far from it
  Fn g = [](double t) { return 1.0 - std::exp(40.0 * (t - 0.5)); };
  Fn dg = [](double t) { return -40.0 * std::exp(40.0 * (t - 0.5)); };
  for (double guess : {0.1, 0.49, 0.51, 0.9}) {
    RootResult r = solve(g, dg, guess, 1.0);
    expect_contact(r, g, 0.5);
    EXPECT_LE(r.nevals, 80);
  }
  // piecewise linear with a kink before the root
  Fn k = [](double t) { return t < 0.2 ? 1.0 - t : 0.8 - 10.0 * (t - 0.2); };
  Fn dk = [](double t) { return t < 0.2 ? -1.0 : -10.0; };
  for (double guess : {0.05, 0.15, 0.27, 0.5}) {
    RootResult r = solve(k, dk, guess, 1.0);
    expect_contact(r, k, 0.28);
  }
}

TEST(ContactRoot, NaNIsAFailure)
{
  Fn g = [](double t) { return t > 0.1 ? std::nan("") : 1.0; };
  Fn dg = [](double) { return -1.0; };
  RootResult r = solve(g, dg, 0.5, 1.0);
  EXPECT_EQ(r.status, ROOT_FAILED);
}

TEST(ContactRoot, EvaluationBudgetExhausted)
{
  Fn g = [](double t) { return std::pow(0.4 - t, 3); };
  Fn dg = [](double) { return 0.0; };
  RootResult r = solve(g, dg, 0.9, 1.0, 1.0, 5);
  EXPECT_EQ(r.status, ROOT_FAILED);
  EXPECT_EQ(r.nevals, 5);
}
