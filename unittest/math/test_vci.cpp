// Unit tests for the VCI root solve HardSphere::vci_root
// (src/HARDSPHERE/hs_vci.h; Bond & Leimkuhler 2007, section 2.3).
//
// Expected values: closed-form roots of the quadratic model
// F(s) = a (s^2 - s) + c (nontrivial root 1/2 + sqrt(1/4 - c/a)), brute-force
// bisection of perturbed models, and the cases without a root (c > a/4,
// a root beyond smax, a jump of F across zero) which must be reported.

#include "hs_vci.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

using namespace HardSphere;

namespace {

constexpr double EPS = std::numeric_limits<double>::epsilon();

struct Quadratic {
  double a, c;
  int calls = 0;
  double operator()(double s, double &scale)
  {
    calls++;
    scale = a * (s * s + s) + std::fabs(c);
    return a * (s * s - s) + c;
  }
};

// brute force: bisection to the last bit
template <class F> double bisect(F f, double lo, double hi)
{
  double flo = f(lo);
  for (int it = 0; it < 2000 && hi - lo > 0; it++) {
    const double mid = 0.5 * (lo + hi);
    if (mid == lo || mid == hi) break;
    const double fm = f(mid);
    if ((fm > 0) == (flo > 0)) {
      lo = mid;
      flo = fm;
    } else
      hi = mid;
  }
  return 0.5 * (lo + hi);
}

VciRoot solve(Quadratic &q, double smin = 0.5, double smax = 2.0, int maxit = 60)
{
  double scale;
  const double f1 = q(1.0, scale);
  return vci_root(q, f1, scale, q.a, smin, smax, maxit);
}

// F = a (s^2 - s) + c + b (s - 1)^3 + d sin(5 s): smooth, not quadratic,
// its parameters drawn from rng (a, c, b, d in that order)
struct Perturbed {
  double a, c, b, d;
  template <class Rng, class U> Perturbed(Rng &rng, U &u)
  {
    a = 0.2 + std::fabs(u(rng));
    c = 0.05 * u(rng);
    b = 0.1 * u(rng);
    d = 0.002 * u(rng);
  }
  double f(double s) const
  {
    return a * (s * s - s) + c + b * std::pow(s - 1, 3) + d * std::sin(5 * s);
  }
  double df(double s) const
  {
    return a * (2 * s - 1) + 3 * b * std::pow(s - 1, 2) + 5 * d * std::cos(5 * s);
  }
  double scale(double s) const
  {
    return a * (s * s + s) + std::fabs(c) + std::fabs(b) + std::fabs(d);
  }
};

// the solve r of p from F(1) = f1 against brute force: has_root when F
// changes sign between 1 and the limit on F(1)'s side, and then r
// converged to the bisection's root in at most 15 evaluations; else r
// reports no root
void check_with_bisection(const Perturbed &p, double f1, const VciRoot &r, int trial,
                          bool &has_root)
{
  auto f = [&](double s) { return p.f(s); };
  const double lim = f1 > 0 ? 0.5 : 2.0;
  has_root = (f(lim) > 0) != (f1 > 0);
  if (!has_root) {
    EXPECT_EQ(r.status, VCI_NO_ROOT) << trial;
    return;
  }
  ASSERT_EQ(r.status, VCI_CONVERGED) << trial;
  const double ref = bisect(f, std::min(1.0, lim), std::max(1.0, lim));
  // the model is monotone near its root here: one root on that side
  EXPECT_NEAR(r.s, ref, 1e-12) << trial;
  EXPECT_LE(r.evals, 15) << trial;
}

}    // namespace

TEST(VciRoot, QuadraticModelClosedForm)
{
  for (double c : {1e-3, -1e-3, 0.1, -0.4, 1e-9, -1e-9, 0.2}) {
    Quadratic q{1.3, c};
    const VciRoot r = solve(q);
    ASSERT_EQ(r.status, VCI_CONVERGED) << "c " << c;
    const double exact = 0.5 + std::sqrt(0.25 - c / q.a);
    EXPECT_NEAR(r.s, exact, 1e-13) << "c " << c;
    EXPECT_LE(std::fabs(r.F), 64 * EPS * (q.a * (r.s * r.s + r.s) + std::fabs(c)));
    EXPECT_EQ(r.evals, q.calls);
    EXPECT_LE(r.evals, 12) << "c " << c;
  }
}

TEST(VciRoot, ElasticWhenAlreadyBalanced)
{
  Quadratic q{2.0, 0.0};
  const VciRoot r = solve(q);
  EXPECT_EQ(r.status, VCI_CONVERGED);
  EXPECT_EQ(r.s, 1.0);
  EXPECT_EQ(r.evals, 1);
  EXPECT_EQ(q.calls, 1);
}

TEST(VciRoot, NoRootIsReported)
{
  // c > a/4: F > 0 on all of [1/2, 2] (minimum at s = 1/2)
  Quadratic q{1.0, 0.3};
  VciRoot r = solve(q);
  EXPECT_EQ(r.status, VCI_NO_ROOT);
  EXPECT_EQ(r.s, 1.0);
  EXPECT_EQ(r.lo, 0.5);    // it did look at the limit
  // the root lies beyond smax: 1/2 + sqrt(1/4 + 3) = 2.30 > 2
  Quadratic q2{1.0, -3.0};
  r = solve(q2);
  EXPECT_EQ(r.status, VCI_NO_ROOT);
  EXPECT_EQ(r.hi, 2.0);
  // ... and is found with a larger smax
  Quadratic q3{1.0, -3.0};
  r = solve(q3, 0.5, 4.0);
  ASSERT_EQ(r.status, VCI_CONVERGED);
  EXPECT_NEAR(r.s, 0.5 + std::sqrt(3.25), 1e-13);
}

TEST(VciRoot, JumpAcrossZeroIsNotARoot)
{
  // F changes sign at s = 0.9 by a jump (the next sub-step's length
  // switching between two contacts), without passing through zero
  int calls = 0;
  auto F = [&](double s, double &scale) {
    calls++;
    scale = 1.0;
    return s < 0.9 ? -0.01 - 0.1 * (0.9 - s) : 0.02 + 0.1 * (s - 0.9);
  };
  double sc;
  const double f1 = F(1.0, sc);
  const VciRoot r = vci_root(F, f1, sc, 0.5, 0.5, 2.0, 200);
  EXPECT_EQ(r.status, VCI_JUMP);
  EXPECT_EQ(r.s, 1.0);
  EXPECT_LE(r.lo, 0.9);
  EXPECT_GE(r.hi, 0.9);
  EXPECT_LE(r.hi - r.lo, 4 * EPS);
  EXPECT_LT(calls, 200);
}

TEST(VciRoot, UndefinedValueIsNoRoot)
{
  // F undefined (NaN: no sub-step after the contact) below s = 0.8; the
  // root of the model, 0.5 + sqrt(0.25 - 0.2) = 0.72, lies there: no root
  // (not a root at the end of the defined range), whether the search meets
  // the NaN while bracketing or while refining
  for (double cut : {0.8, 0.73}) {
    auto F = [&](double s, double &scale) {
      scale = 1.0;
      return s < cut ? std::numeric_limits<double>::quiet_NaN() : (s * s - s) + 0.2;
    };
    double sc;
    const double f1 = F(1.0, sc);
    const VciRoot r = vci_root(F, f1, sc, 1.0, 0.5, 2.0, 100);
    EXPECT_EQ(r.status, VCI_NO_ROOT) << cut;
    EXPECT_EQ(r.s, 1.0) << cut;
    EXPECT_TRUE(std::isnan(r.F)) << cut;
  }
}

TEST(VciRoot, IterationLimitIsReported)
{
  // (not the quadratic model itself: its first step is its root)
  auto F = [](double s, double &scale) {
    scale = s * s + s + 1.0;
    return s * s - s + 1e-2 + 0.3 * std::pow(s - 1.0, 3);
  };
  double sc;
  const double f1 = F(1.0, sc);
  const VciRoot r = vci_root(F, f1, sc, 1.0, 0.5, 2.0, 2);
  EXPECT_EQ(r.status, VCI_NOT_CONVERGED);
  EXPECT_EQ(r.evals, 2);
  EXPECT_EQ(r.s, 1.0);
}

// the first step is the root of the model a (s^2 - s) + F(1), and later
// ones secants less the quadratic term a s^2: where F is that quadratic
// plus any line (a linear V along the trial step) the solve takes two
// evaluations, F(1) and the root (a plain secant from the line model took
// 4-6 here)
TEST(VciRoot, QuadraticPlusLineInTwoEvaluations)
{
  for (double m : {0.0, 0.05, -0.08})
    for (double c : {1e-3, -1e-3, 0.05, -0.2, 1e-9}) {
      const double a = 1.3;
      int calls = 0;
      auto F = [&](double s, double &scale) {
        calls++;
        scale = a * (s * s + s) + std::fabs(c) + std::fabs(m);
        return a * (s * s - s) + m * (s - 1.0) + c;
      };
      double sc;
      const double f1 = F(1.0, sc);
      const VciRoot r = vci_root(F, f1, sc, a, 0.5, 2.0, 60);
      ASSERT_EQ(r.status, VCI_CONVERGED) << "m " << m << " c " << c;
      // a s^2 + (m - a) s + (c - m) = 0, the root near 1
      const double B = m - a, C = c - m;
      const double exact = (-B + std::sqrt(B * B - 4.0 * a * C)) / (2.0 * a);
      EXPECT_NEAR(r.s, exact, 1e-13) << "m " << m << " c " << c;
      EXPECT_LE(r.evals, m == 0.0 ? 2 : 3) << "m " << m << " c " << c;
      EXPECT_EQ(r.evals, calls);
    }
}

// quad_secant() against the closed form: through two points of
// a x^2 + m x + b it returns that quadratic's root nearest the second
TEST(VciRoot, QuadSecantIsExactOnTheModel)
{
  const double a = 0.7, m = -0.9, b = 0.1;
  auto f = [&](double x) { return a * x * x + m * x + b; };
  const double r_lo = (-m - std::sqrt(m * m - 4 * a * b)) / (2 * a),
               r_hi = (-m + std::sqrt(m * m - 4 * a * b)) / (2 * a);
  EXPECT_NEAR(quad_secant(1.0, f(1.0), 1.2, f(1.2), a), r_hi, 1e-14);
  EXPECT_NEAR(quad_secant(0.1, f(0.1), 0.2, f(0.2), a), r_lo, 1e-14);
  // no real root, and no quadratic term: NaN (the caller's plain secant)
  EXPECT_TRUE(std::isnan(quad_secant(1.0, a + 1.0, 1.2, a * 1.44 + 1.0, a)));    // a x^2 + 1
  EXPECT_TRUE(std::isnan(quad_secant(1.0, 0.1, 1.2, 0.2, 0.0)));
}

TEST(VciRoot, PerturbedModelsAgainstBisection)
{
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int found = 0;
  for (int trial = 0; trial < 300; trial++) {
    const Perturbed p(rng, u);
    int calls = 0;
    auto F = [&](double s, double &scale) {
      calls++;
      scale = p.scale(s);
      return p.f(s);
    };
    double sc;
    const double f1 = F(1.0, sc);
    const VciRoot r = vci_root(F, f1, sc, p.a, 0.5, 2.0, 100);
    bool has_root;
    ASSERT_NO_FATAL_FAILURE(check_with_bisection(p, f1, r, trial, has_root));
    found += has_root;
    EXPECT_EQ(r.evals, calls);
  }
  EXPECT_GT(found, 200);
}

// quad_newton() against the closed form: from a point of a x^2 + m x + b
// and its slope it returns that quadratic's root nearest the point
TEST(VciRoot, QuadNewtonIsExactOnTheModel)
{
  const double a = 0.7, m = -0.9, b = 0.1;
  auto f = [&](double x) { return a * x * x + m * x + b; };
  auto df = [&](double x) { return 2 * a * x + m; };
  const double r_lo = (-m - std::sqrt(m * m - 4 * a * b)) / (2 * a),
               r_hi = (-m + std::sqrt(m * m - 4 * a * b)) / (2 * a);
  EXPECT_NEAR(quad_newton(1.2, f(1.2), df(1.2), a), r_hi, 1e-14);
  EXPECT_NEAR(quad_newton(0.9, f(0.9), df(0.9), a), r_hi, 1e-14);
  EXPECT_NEAR(quad_newton(0.1, f(0.1), df(0.1), a), r_lo, 1e-14);
  // a = 0: Newton's step on the line
  EXPECT_NEAR(quad_newton(2.0, 3.0, 1.5, 0.0), 0.0, 1e-15);
  // no real root, or no slope: NaN (the caller's secants)
  EXPECT_TRUE(std::isnan(quad_newton(0.0, 1.0, 0.1, a)));    // a x^2 + 0.1 x + 1
  EXPECT_TRUE(std::isnan(quad_newton(1.0, f(1.0), std::numeric_limits<double>::quiet_NaN(), a)));
}

// with F'(s) from eval (the local form's trials: the flow's slope), each
// step is quad_newton() from the last point: on the quadratic plus a line
// the first step is the root (F(1) and one more evaluation, where the
// secants above take up to three)
TEST(VciRoot, WithTheSlopeQuadraticPlusLineInTwoEvaluations)
{
  for (double m : {0.0, 0.05, -0.08, 0.4})
    for (double c : {1e-3, -1e-3, 0.05, -0.2, 1e-9}) {
      const double a = 1.3;
      int calls = 0;
      auto F = [&](double s, double &scale, double &dF) {
        calls++;
        scale = a * (s * s + s) + std::fabs(c) + std::fabs(m);
        dF = a * (2.0 * s - 1.0) + m;
        return a * (s * s - s) + m * (s - 1.0) + c;
      };
      double sc, d1;
      const double f1 = F(1.0, sc, d1);
      const VciRoot r = vci_root(F, f1, sc, a, 0.5, 2.0, 60, 64.0 * EPS, d1);
      ASSERT_EQ(r.status, VCI_CONVERGED) << "m " << m << " c " << c;
      const double B = m - a, C = c - m;
      const double exact = (-B + std::sqrt(B * B - 4.0 * a * C)) / (2.0 * a);
      EXPECT_NEAR(r.s, exact, 1e-13) << "m " << m << " c " << c;
      EXPECT_EQ(r.evals, 2) << "m " << m << " c " << c;
      EXPECT_EQ(r.evals, calls);
    }
}

// the perturbed models above with their slopes: the same roots (bisection
// to the last bit), the same cases without a root, and on the smooth
// ones no more evaluations than the secants take; a slope unknown at some
// points (NaN: a trial whose sub-step ends at a contact) falls back to
// the secants there
TEST(VciRoot, WithTheSlopePerturbedModelsAgainstBisection)
{
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int found = 0, fewer = 0;
  for (int trial = 0; trial < 300; trial++) {
    const Perturbed p(rng, u);
    const bool holes = trial % 3 == 2;    // no slope at every other call
    int calls = 0;
    auto F = [&](double s, double &scale, double &dF) {
      calls++;
      scale = p.scale(s);
      dF = (holes && calls % 2 == 0) ? std::numeric_limits<double>::quiet_NaN() : p.df(s);
      return p.f(s);
    };
    auto G = [&](double s, double &scale) {
      scale = p.scale(s);
      return p.f(s);
    };
    double sc, d1;
    const double f1 = F(1.0, sc, d1);
    const VciRoot r = vci_root(F, f1, sc, p.a, 0.5, 2.0, 100, 64.0 * EPS, d1);
    const VciRoot r0 = vci_root(G, f1, sc, p.a, 0.5, 2.0, 100);
    bool has_root;
    ASSERT_NO_FATAL_FAILURE(check_with_bisection(p, f1, r, trial, has_root));
    if (has_root) {
      if (!holes) EXPECT_LE(r.evals, r0.evals) << trial;
      fewer += r.evals < r0.evals;
      found++;
    }
    EXPECT_EQ(r.evals, calls);
  }
  EXPECT_GT(found, 200);
  EXPECT_GT(fewer, found / 2);
}
