// Unit tests for the hard-sphere contact-time kernel src/HARDSPHERE/hs_contact.h
// (Bond & Leimkuhler, SIAM J. Sci. Comput. 30(1) (2007), section 2.2).
//
// Stand-alone build:
//   g++ -std=c++17 -O2 -I src/HARDSPHERE unittest/math/test_contact.cpp
//       -lgtest -lgtest_main -pthread -o /tmp/tc && /tmp/tc
//
// Every expected value below comes from a closed-form solution, an exact
// (representable) construction, or an independent brute-force computation that
// evaluates the gap from the geometry |dq + t dv + t^2/2 da|^2 - sigma^2 directly
// (never from the polynomial coefficients produced by the code under test).

#include "hs_contact.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

using namespace HardSphere;

namespace {

constexpr double EPS = std::numeric_limits<double>::epsilon();

// ---------------------------------------------------------------------------
// geometry helpers (independent of the code under test)

double dot(const double *a, const double *b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

double norm(const double *a)
{
  return std::sqrt(dot(a, a));
}

// separation vector r(t) = dq + t dv + t^2/2 da
void sep(const double *dq, const double *dv, const double *da, double t, double *r)
{
  for (int k = 0; k < 3; ++k) r[k] = dq[k] + t * dv[k] + 0.5 * t * t * da[k];
}

struct PairCase {
  double dq[3], dv[3], da[3];
  double sigma, tmax;
};

// g(t) evaluated from the geometry
double gap(const PairCase &p, double t)
{
  double r[3];
  sep(p.dq, p.dv, p.da, t, r);
  return dot(r, r) - p.sigma * p.sigma;
}

// g'(t) = 2 r(t).r'(t)
double dgap(const PairCase &p, double t)
{
  double r[3], rp[3];
  sep(p.dq, p.dv, p.da, t, r);
  for (int k = 0; k < 3; ++k) rp[k] = p.dv[k] + t * p.da[k];
  return 2.0 * dot(r, rp);
}

Contact pair_contact(const double *dq, const double *dv, const double *da, double sigma,
                     double tmax, double tol)
{
  double c[5];
  pair_gap_poly(dq, dv, da, sigma, c);
  return first_contact(c, 4, tmax, tol);
}

Contact wall_contact(double dist, double vn, double an, double tmax, double tol)
{
  double c[3];
  wall_gap_poly(dist, vn, an, c);
  return first_contact(c, 2, tmax, tol);
}

// round-off tolerance for a root t of a polynomial whose terms sum in absolute
// value to `scale` near t and whose slope there is `slope`: coefficient rounding
// (eps/2) + Horner evaluation (~2n eps) + the bracket's stopping width (4 eps |t|)
double rt(double scale, double slope, double t)
{
  return 16.0 * EPS * scale / std::fabs(slope) + 8.0 * EPS * std::fabs(t);
}

// smallest root > 0 of c0 + c1 t + c2 t^2 with c0 > 0 (the downward crossing),
// by the cancellation-free quadratic formula, in long double; returns -1 if none
long double first_positive_root_quadratic(long double c0, long double c1, long double c2)
{
  if (c2 == 0.0L) {
    if (c1 < 0.0L) return -c0 / c1;
    return -1.0L;
  }
  const long double disc = c1 * c1 - 4.0L * c2 * c0;
  if (disc < 0.0L) return -1.0L;
  const long double s = std::sqrt(disc);
  const long double q = -0.5L * (c1 + (c1 >= 0.0L ? s : -s));
  long double r1 = (q != 0.0L) ? q / c2 : -1.0L;
  long double r2 = (q != 0.0L) ? c0 / q : -1.0L;
  long double best = -1.0L;
  for (long double r : {r1, r2})
    if (r > 0.0L && (best < 0.0L || r < best)) best = r;
  return best;
}

// ---------------------------------------------------------------------------
// brute force: dense sampling of g on [0, tmax] + bisection refinement.
//
// With M2 >= max |g''| on [0,tmax], between two samples a, b = a + h the gap
// satisfies g >= min(g(a), g(b)) - M2 h^2 / 8, so a grid whose samples all
// exceed that margin (plus a round-off floor) proves g > 0 everywhere, and a
// first sample with g <= 0 whose predecessor has g' < -M2 h proves a single,
// transversal downward crossing in that cell. Anything else is AMBIGUOUS
// (a dip or a tangency below the sampling resolution) and is not compared.

enum class BF { NONE, CONTACT, AMBIGUOUS };

struct BruteResult {
  BF kind;
  double t;        // refined crossing time (CONTACT)
  double slope;    // |g'| at the crossing (CONTACT)
};

template <class G, class DG> struct Brute {
  G g;
  DG dg;
  double M2, roundoff;
  int maxdepth;

  // first crossing in the cell [a, b] given g(a) > 0
  BruteResult cell(double a, double b, double ga, double gb, int depth) const
  {
    const double h = b - a;
    if (gb > 0.0 && std::min(ga, gb) - M2 * h * h / 8.0 > roundoff) return {BF::NONE, 0, 0};
    if (gb <= 0.0 && dg(a) < -M2 * h - roundoff / h) {
      // g' < 0 on the whole cell: exactly one crossing, refine by bisection
      double lo = a, hi = b;
      for (int it = 0; it < 200 && hi - lo > 2.0 * EPS * hi; ++it) {
        const double mid = 0.5 * (lo + hi);
        if (g(mid) > 0.0) lo = mid;
        else hi = mid;
      }
      const double tc = 0.5 * (lo + hi);
      return {BF::CONTACT, tc, std::fabs(dg(tc))};
    }
    if (depth == 0) return {BF::AMBIGUOUS, 0, 0};
    const double m = 0.5 * (a + b), gm = g(m);
    if (gm <= 0.0) {
      // the first crossing is in [a, m]
      return cell(a, m, ga, gm, depth - 1);
    }
    const BruteResult left = cell(a, m, ga, gm, depth - 1);
    if (left.kind != BF::NONE) return left;
    return cell(m, b, gm, gb, depth - 1);
  }
};

template <class G, class DG>
BruteResult brute_first_crossing(G g, DG dg, double tmax, double M2, double roundoff, int N)
{
  const Brute<G, DG> B{g, dg, M2, roundoff, 40};
  double gprev = g(0.0), tprev = 0.0;
  if (!(gprev > roundoff)) return {BF::AMBIGUOUS, 0.0, 0.0};
  for (int i = 1; i <= N; ++i) {
    const double t = (i == N) ? tmax : tmax * (double(i) / N);
    const double gi = g(t);
    const BruteResult r = B.cell(tprev, t, gprev, gi, B.maxdepth);
    if (r.kind != BF::NONE) {
      // a crossing within round-off of tmax cannot be called either way
      if (r.kind == BF::CONTACT && i == N && !(g(tmax) < -roundoff)) return {BF::AMBIGUOUS, 0, 0};
      return r;
    }
    gprev = gi;
    tprev = t;
  }
  return {BF::NONE, 0.0, 0.0};
}

// random helpers
struct Rng {
  std::mt19937_64 eng;
  explicit Rng(uint64_t seed) : eng(seed) {}
  double uni(double a, double b) { return std::uniform_real_distribution<double>(a, b)(eng); }
  double logu(double lo_exp, double hi_exp) { return std::pow(10.0, uni(lo_exp, hi_exp)); }
  void unit(double *u)
  {
    std::normal_distribution<double> n(0.0, 1.0);
    double s;
    do {
      for (int k = 0; k < 3; ++k) u[k] = n(eng);
      s = norm(u);
    } while (s < 1e-3);
    for (int k = 0; k < 3; ++k) u[k] /= s;
  }
};

}    // namespace

// ===========================================================================
// 0. small building blocks

TEST(PolyBasics, EvalDegreeDerivative)
{
  const double c[5] = {4.0, -12.0, 13.0, -6.0, 1.0};    // (t-1)^2 (t-2)^2
  EXPECT_EQ(poly_eval(c, 4, 1.0), 0.0);
  EXPECT_EQ(poly_eval(c, 4, 2.0), 0.0);
  EXPECT_EQ(poly_eval(c, 4, 3.0), 4.0);
  EXPECT_EQ(poly_eval(c, 4, 0.0), 4.0);
  const double z[5] = {1.0, 2.0, 0.0, 0.0, 0.0};
  EXPECT_EQ(poly_degree(z, 4), 1);
  const double zz[5] = {0.0, 0.0, 0.0, 0.0, 0.0};
  EXPECT_EQ(poly_degree(zz, 4), 0);
  EXPECT_EQ(poly_degree(c, 4), 4);
  double d[4];
  poly_derivative(c, 4, d);
  EXPECT_EQ(d[0], -12.0);
  EXPECT_EQ(d[1], 26.0);
  EXPECT_EQ(d[2], -18.0);
  EXPECT_EQ(d[3], 4.0);
}

TEST(PairGapPoly, MatchesGeometryAtSamplePoints)
{
  // the expansion must reproduce |dq + t dv + t^2/2 da|^2 - sigma^2 (exact data)
  const double dq[3] = {1.5, -2.0, 0.25}, dv[3] = {-0.5, 1.0, 2.0}, da[3] = {3.0, -1.0, 0.5};
  double c[5];
  pair_gap_poly(dq, dv, da, 0.75, c);
  PairCase p{{1.5, -2.0, 0.25}, {-0.5, 1.0, 2.0}, {3.0, -1.0, 0.5}, 0.75, 1.0};
  for (double t : {0.0, 0.25, 0.5, 1.0, 2.0, -1.0}) {
    double r[3];
    sep(p.dq, p.dv, p.da, t, r);
    EXPECT_NEAR(poly_eval(c, 4, t), gap(p, t), 1e-14 * (dot(r, r) + 10.0)) << t;
  }
  EXPECT_EQ(c[4], 0.25 * dot(da, da));
  EXPECT_EQ(c[1], 2.0 * dot(dq, dv));
}

// ===========================================================================
// 1. first_contact against brute force on random pair and wall cases

namespace {

PairCase random_pair(Rng &rng)
{
  PairCase p;
  p.sigma = rng.logu(-3.0, 3.0);
  const double T = rng.logu(-2.0, 2.0);    // time scale
  p.tmax = T * rng.logu(-1.0, 1.0);
  const double L = p.sigma;

  double u[3], w[3], z[3];
  rng.unit(u);
  const double dist = p.sigma + L * rng.logu(-5.0, 0.7);
  for (int k = 0; k < 3; ++k) p.dq[k] = dist * u[k];

  const double vmag = (L / T) * rng.logu(-2.0, 1.0);
  const double mode = rng.uni(0.0, 1.0);
  rng.unit(w);
  if (mode < 0.5) {
    // mostly approaching: -u plus a random transverse part
    const double b = rng.uni(0.0, 1.5);
    for (int k = 0; k < 3; ++k) p.dv[k] = vmag * (-u[k] + b * w[k]);
  } else if (mode < 0.95) {
    for (int k = 0; k < 3; ++k) p.dv[k] = vmag * w[k];
  } else {
    for (int k = 0; k < 3; ++k) p.dv[k] = 0.0;    // vanishing odd coefficients
  }

  rng.unit(z);
  const double amode = rng.uni(0.0, 1.0);
  const double amag = (L / (T * T)) * rng.logu(-3.0, 1.5);
  if (amode < 0.1) {
    for (int k = 0; k < 3; ++k) p.da[k] = 0.0;    // free flight, degree 2
  } else if (amode < 0.4) {
    for (int k = 0; k < 3; ++k) p.da[k] = -amag * u[k] + 0.3 * amag * z[k];    // pulled together
  } else {
    for (int k = 0; k < 3; ++k) p.da[k] = amag * z[k];
  }
  return p;
}

// bound on |g''| over [0, tmax]: g'' = 2 (|r'|^2 + r.da)
double pair_M2(const PairCase &p)
{
  const double T = p.tmax;
  const double vmax = norm(p.dv) + T * norm(p.da);
  const double rmax = norm(p.dq) + T * norm(p.dv) + 0.5 * T * T * norm(p.da);
  return 2.0 * (vmax * vmax + rmax * norm(p.da));
}

double pair_roundoff(const PairCase &p)
{
  const double T = p.tmax;
  const double rmax = norm(p.dq) + T * norm(p.dv) + 0.5 * T * T * norm(p.da);
  return 64.0 * EPS * (rmax * rmax + p.sigma * p.sigma);
}

}    // namespace

TEST(FirstContactRandom, PairsAgainstBruteForce)
{
  Rng rng(20070101);
  const int NCASE = 20000;
  const int NSAMP = 20000;
  int n_contact = 0, n_none = 0, n_amb = 0, n_fail = 0;
  double worst = 0.0;    // worst |t - t_bf| / tolerance
  for (int icase = 0; icase < NCASE; ++icase) {
    const PairCase p = random_pair(rng);
    const double M2 = pair_M2(p);
    const double rnd = pair_roundoff(p);
    const double tol = 1e-12 * p.sigma * p.sigma;
    ASSERT_GT(gap(p, 0.0), 100.0 * tol);    // generator guarantees a clear initial gap

    const BruteResult bf = brute_first_crossing([&](double t) { return gap(p, t); },
                                                [&](double t) { return dgap(p, t); }, p.tmax,
                                                M2, rnd, NSAMP);
    if (bf.kind == BF::AMBIGUOUS) {
      ++n_amb;
      continue;
    }
    double c[5];
    pair_gap_poly(p.dq, p.dv, p.da, p.sigma, c);
    const Contact got = first_contact(c, 4, p.tmax, tol);
    if (bf.kind == BF::NONE) {
      ++n_none;
      if (got.status != NO_CONTACT) {
        if (++n_fail <= 10)
          ADD_FAILURE() << "case " << icase << ": brute force sees no contact, got status "
                        << got.status << " t=" << got.t;
      }
      continue;
    }
    ++n_contact;
    // time accuracy: a few ulps of the time, plus the round-off level of the
    // coefficients divided by the slope of g at the crossing
    const double ttol = 8.0 * EPS * p.tmax + 16.0 * EPS * (rnd / (64.0 * EPS)) / bf.slope;
    if (got.status != CONTACT || !(std::fabs(got.t - bf.t) <= ttol)) {
      if (++n_fail <= 10)
        ADD_FAILURE() << std::scientific << "case " << icase << ": brute force contact at "
                      << bf.t << ", got status " << got.status << " t=" << got.t
                      << " (tol " << ttol << ")";
      continue;
    }
    worst = std::max(worst, std::fabs(got.t - bf.t) / ttol);
    // documented: the returned time lies on the open side of the root
    EXPECT_GE(poly_eval(c, 4, got.t), 0.0) << "case " << icase;
  }
  EXPECT_EQ(n_fail, 0);
  std::printf("[ info     ] pairs: %d contact, %d no contact, %d ambiguous (excluded), worst "
              "err/tol %.3g\n",
              n_contact, n_none, n_amb, worst);
  // the comparison is not vacuous
  EXPECT_GT(n_contact, NCASE / 10);
  EXPECT_GT(n_none, NCASE / 10);
  EXPECT_LT(n_amb, NCASE / 50);
}

// first_contact() clears most pairs by a bound on the gap polynomial
// (clear_by_bound()) before searching the roots of g': it must give the
// search's answer, bit for bit (the local engine's trajectories on 1 and
// n ranks rest on it), and the bound must hold for the geometry itself
TEST(FirstContactBound, SameAnswerAsTheSearchAndSound)
{
  Rng rng(20261127);
  const int NCASE = 200000;
  int n_bound = 0, n_down = 0, n_touch = 0, n_touch_clear = 0, n_contact = 0, n_diff = 0,
      n_unsound = 0;
  for (int icase = 0; icase < NCASE; ++icase) {
    PairCase p = random_pair(rng);
    // a third of the cases graze: a straight line that passes the contact
    // distance by a relative 1e-14 .. 1e-2 (a tiny positive minimum)
    if (icase % 3 == 0) {
      double u[3], w[3];
      rng.unit(u);
      rng.unit(w);
      const double uw = dot(u, w);
      for (int k = 0; k < 3; ++k) w[k] -= uw * u[k];
      const double wn = norm(w);
      if (wn < 1e-3) continue;
      const double b = p.sigma * (1.0 + rng.logu(-14.0, -2.0));
      const double speed = norm(p.dv) > 0.0 ? norm(p.dv) : p.sigma / p.tmax;
      const double tc = p.tmax * rng.uni(0.0, 1.2);    // closest approach
      for (int k = 0; k < 3; ++k) {
        p.dv[k] = -speed * u[k];
        p.dq[k] = b * w[k] / wn + speed * tc * u[k];
        p.da[k] = (icase % 2) ? 0.0 : 1e-9 * speed / p.tmax * w[k] / wn;
      }
    }
    // another third touch at t = 0 (|g(0)| <= tol), most of them separating
    // (a pair just after its impulse), pulled back by da in some
    if (icase % 3 == 1) {
      double u[3];
      rng.unit(u);
      const double r = p.sigma * (1.0 + rng.uni(-1.0, 1.0) * 1e-13);
      const double vn = rng.uni(-0.2, 1.0) * norm(p.dv);
      for (int k = 0; k < 3; ++k) {
        p.dq[k] = r * u[k];
        p.dv[k] += (vn - dot(p.dv, u)) * u[k];
      }
    }
    double c[5];
    pair_gap_poly(p.dq, p.dv, p.da, p.sigma, c);
    const double tol = 1e-12 * p.sigma * p.sigma;
    const Contact a = first_contact(c, 4, p.tmax, tol);
    const Contact b = first_contact_searched(c, 4, p.tmax, tol);
    if (a.status != b.status || a.t != b.t) {
      if (++n_diff <= 10)
        ADD_FAILURE() << std::scientific << "case " << icase << ": status " << a.status
                      << " t " << a.t << " against the search's " << b.status << " t " << b.t;
    }
    // whether, not when: the same status
    if (first_contact(c, 4, p.tmax, tol, false).status != b.status) {
      if (++n_diff <= 10) ADD_FAILURE() << "case " << icase << ": untimed status differs";
    }
    if (std::fabs(c[0]) <= tol) {
      ++n_touch;
      if (c[1] > 0.0 && clear_by_bound(c + 1, 3, p.tmax)) {
        ++n_touch_clear;
        // the geometry: separating throughout
        for (int k = 1; k <= 200; ++k) {
          const double t = p.tmax * k / 200.0;
          if (!(dgap(p, t) > 0.0 || gap(p, t) > 0.0)) {
            if (++n_unsound <= 10)
              ADD_FAILURE() << std::scientific << "case " << icase << ": cleared touching, "
                            << "but the gap is " << gap(p, t) << " at t " << t;
            break;
          }
        }
      }
    }
    if (b.status == CONTACT || b.status == CONTACT_NOW) ++n_contact;
    if (c[0] > tol && clear_by_bound(c, 4, p.tmax)) {
      ++n_bound;
      // the geometry, not the coefficients: the gap stays positive
      for (int k = 0; k <= 200; ++k) {
        const double t = p.tmax * k / 200.0;
        if (!(gap(p, t) > 0.0)) {
          if (++n_unsound <= 10)
            ADD_FAILURE() << std::scientific << "case " << icase << ": cleared, but the gap is "
                          << gap(p, t) << " at t " << t;
          break;
        }
      }
    } else if (c[0] > tol) {
      double d[4];
      poly_derivative(c, 4, d);
      if (!decreasing_by_bound(d, 3, p.tmax)) continue;
      ++n_down;
      // the geometry: approaching throughout
      for (int k = 0; k <= 200; ++k) {
        const double t = p.tmax * k / 200.0;
        if (!(dgap(p, t) < 0.0)) {
          if (++n_unsound <= 10)
            ADD_FAILURE() << std::scientific << "case " << icase << ": taken as approaching, "
                          << "but g' is " << dgap(p, t) << " at t " << t;
          break;
        }
      }
    }
  }
  EXPECT_EQ(n_diff, 0);
  EXPECT_EQ(n_unsound, 0);
  std::printf("[ info     ] %d cases: %d cleared by the bound, %d approaching throughout, %d "
              "touching (%d cleared), %d contacts\n",
              NCASE, n_bound, n_down, n_touch, n_touch_clear, n_contact);
  // no side is vacuous
  EXPECT_GT(n_bound, NCASE / 10);
  EXPECT_GT(n_down, NCASE / 20);
  EXPECT_GT(n_touch_clear, NCASE / 10);
  EXPECT_GT(n_contact, NCASE / 10);
}

TEST(FirstContactRandom, WallsAgainstBruteForceAndClosedForm)
{
  Rng rng(424242);
  const int NCASE = 20000;
  const int NSAMP = 20000;
  int n_contact = 0, n_none = 0, n_amb = 0, n_fail = 0;
  for (int icase = 0; icase < NCASE; ++icase) {
    const double L = rng.logu(-3.0, 3.0);
    const double T = rng.logu(-2.0, 2.0);
    const double tmax = T * rng.logu(-1.0, 1.0);
    const double dist = L * rng.logu(-5.0, 0.5);
    const double vn = (rng.uni(0, 1) < 0.6 ? -1.0 : 1.0) * (L / T) * rng.logu(-2.0, 1.0) *
        (rng.uni(0, 1) < 0.05 ? 0.0 : 1.0);
    const double an = (rng.uni(0, 1) < 0.5 ? -1.0 : 1.0) * (L / (T * T)) * rng.logu(-3.0, 1.5) *
        (rng.uni(0, 1) < 0.1 ? 0.0 : 1.0);
    const double tol = 1e-12 * L;

    auto g = [&](double t) { return dist + t * vn + 0.5 * an * t * t; };
    auto dg = [&](double t) { return vn + an * t; };
    const double rnd = 64.0 * EPS * (dist + tmax * std::fabs(vn) + tmax * tmax * std::fabs(an));
    const BruteResult bf = brute_first_crossing(g, dg, tmax, std::fabs(an), rnd, NSAMP);

    const Contact got = wall_contact(dist, vn, an, tmax, tol);
    const long double tcf = first_positive_root_quadratic(dist, vn, 0.5L * an);

    if (bf.kind == BF::AMBIGUOUS) {
      ++n_amb;
      continue;
    }
    if (bf.kind == BF::NONE) {
      ++n_none;
      if (got.status != NO_CONTACT && ++n_fail <= 10)
        ADD_FAILURE() << "wall case " << icase << ": expected no contact, got " << got.status
                      << " t=" << got.t;
      continue;
    }
    ++n_contact;
    const double ttol = 8.0 * EPS * tmax + 16.0 * EPS * (rnd / (64.0 * EPS)) / bf.slope;
    // the closed form and the brute force must agree with each other first
    ASSERT_NEAR((double) tcf, bf.t, ttol) << "test self-check, wall case " << icase;
    if ((got.status != CONTACT || !(std::fabs(got.t - (double) tcf) <= ttol)) && ++n_fail <= 10)
      ADD_FAILURE() << std::scientific << "wall case " << icase << " dist=" << dist
                    << " vn=" << vn << " an=" << an << " tmax=" << tmax
                    << ": expected contact at " << (double) tcf << ", got status "
                    << got.status << " t=" << got.t;
  }
  EXPECT_EQ(n_fail, 0);
  std::printf("[ info     ] walls: %d contact, %d no contact, %d ambiguous (excluded)\n",
              n_contact, n_none, n_amb);
  EXPECT_GT(n_contact, NCASE / 10);
  EXPECT_GT(n_none, NCASE / 10);
  EXPECT_LT(n_amb, NCASE / 50);
}

// A pair that starts in contact (|g(0)| at round-off level) and separates, in
// random directions, with an acceleration that may bring it back. The contract:
// the gap is measured from the current contact, i.e. the reference function is
// gt(t) = |r(t)|^2 - |dq|^2 = 2 dq.s + |s|^2, s = t dv + t^2/2 da.
TEST(FirstContactRandom, TouchingAndSeparatingAgainstBruteForce)
{
  Rng rng(777);
  const int NCASE = 2000;
  const int NSAMP = 20000;
  int n_contact = 0, n_none = 0, n_amb = 0, n_fail = 0;
  for (int icase = 0; icase < NCASE; ++icase) {
    PairCase p;
    p.sigma = rng.logu(-3.0, 3.0);
    const double T = rng.logu(-2.0, 2.0);
    p.tmax = T * rng.logu(-1.0, 1.0);
    double u[3], w[3], z[3];
    rng.unit(u);
    for (int k = 0; k < 3; ++k) p.dq[k] = p.sigma * u[k];    // |g(0)| ~ round-off
    rng.unit(w);
    const double vmag = (p.sigma / T) * rng.logu(-2.0, 1.0);
    for (int k = 0; k < 3; ++k) p.dv[k] = vmag * w[k];
    if (dot(p.dq, p.dv) <= 0.0)
      for (int k = 0; k < 3; ++k) p.dv[k] = -p.dv[k];    // separating
    rng.unit(z);
    const double amag = (p.sigma / (T * T)) * rng.logu(-2.0, 2.0);
    for (int k = 0; k < 3; ++k) p.da[k] = amag * (-u[k] + 0.5 * z[k]);

    double c[5];
    pair_gap_poly(p.dq, p.dv, p.da, p.sigma, c);
    const double tol = 1e-10 * p.sigma * p.sigma;
    ASSERT_LE(std::fabs(c[0]), tol);
    ASSERT_GT(c[1], 0.0);

    // brute force on gt, starting just after t = 0 where gt grows like c1 t
    auto gt = [&](double t) {
      double s[3];
      for (int k = 0; k < 3; ++k) s[k] = t * p.dv[k] + 0.5 * t * t * p.da[k];
      return 2.0 * dot(p.dq, s) + dot(s, s);
    };
    auto dgt = [&](double t) { return dgap(p, t); };
    const double M2 = pair_M2(p), rnd = pair_roundoff(p);
    // skip the initial cell: gt(0) = 0, gt' (0) = c1 > 0 ; start the scan at t0
    // where gt is provably positive on (0, t0]
    const double t0 = std::min(p.tmax, c[1] / M2);    // gt'(t) >= c1 - M2 t >= 0 on [0,t0]
    if (!(t0 > 0.0)) {
      ++n_amb;
      continue;
    }
    const Contact got = first_contact(c, 4, p.tmax, tol);
    ASSERT_NE(got.status, CONTACT_NOW) << "case " << icase;
    ASSERT_NE(got.status, OVERLAP) << "case " << icase;
    if (got.status == CONTACT) {
      // never a contact at (or at round-off distance from) t = 0
      EXPECT_GE(got.t, 0.5 * t0) << "case " << icase;
    }
    if (t0 >= p.tmax) {
      ++n_none;
      EXPECT_EQ(got.status, NO_CONTACT) << "case " << icase;
      continue;
    }
    const BruteResult bf0 = brute_first_crossing(
        [&](double t) { return gt(t0 + t); }, [&](double t) { return dgt(t0 + t); },
        p.tmax - t0, M2, rnd, NSAMP);
    if (bf0.kind == BF::AMBIGUOUS) {
      ++n_amb;
      continue;
    }
    if (bf0.kind == BF::NONE) {
      ++n_none;
      if (got.status != NO_CONTACT && ++n_fail <= 10)
        ADD_FAILURE() << "touching case " << icase << ": expected no contact, got "
                      << got.status << " t=" << got.t;
      continue;
    }
    ++n_contact;
    const double tbf = t0 + bf0.t;
    const double ttol = 8.0 * EPS * p.tmax + 16.0 * EPS * (rnd / (64.0 * EPS)) / bf0.slope;
    if ((got.status != CONTACT || !(std::fabs(got.t - tbf) <= ttol)) && ++n_fail <= 10)
      ADD_FAILURE() << std::scientific << "touching case " << icase
                    << ": expected re-contact at " << tbf << ", got " << got.status
                    << " t=" << got.t << " (tol " << ttol << ")";
  }
  EXPECT_EQ(n_fail, 0);
  std::printf("[ info     ] touching: %d re-contact, %d no contact, %d ambiguous (excluded)\n",
              n_contact, n_none, n_amb);
  EXPECT_GT(n_contact, NCASE / 10);
  EXPECT_GT(n_none, NCASE / 20);
  EXPECT_LT(n_amb, NCASE / 20);
}

// ===========================================================================
// 2. analytic cases

TEST(FirstContactAnalytic, HeadOnFreeFlight)
{
  // exactly representable: |dq| = 5, |dv| = 1/2, sigma = 1 -> t = (5-1)/0.5 = 8
  {
    const double dq[3] = {3.0, 4.0, 0.0}, dv[3] = {-0.3, -0.4, 0.0}, da[3] = {0, 0, 0};
    const Contact c = pair_contact(dq, dv, da, 1.0, 10.0, 1e-12);
    EXPECT_EQ(c.status, CONTACT);
    EXPECT_NEAR(c.t, 8.0, rt(80, 1, 8));    // g = 24 - 5t + t^2/4
  }
  // random directions and scales: t = (|dq| - sigma) / |dv|
  Rng rng(5);
  for (int i = 0; i < 200; ++i) {
    double u[3];
    rng.unit(u);
    const double sigma = rng.logu(-3, 3);
    const double d = sigma * (1.0 + rng.logu(-3, 1));
    const double s = rng.logu(-2, 2);
    double dq[3], dv[3], da[3] = {0, 0, 0};
    for (int k = 0; k < 3; ++k) {
      dq[k] = d * u[k];
      dv[k] = -s * u[k];
    }
    // exact reference from the rounded inputs
    const long double dn = std::sqrt((long double) dq[0] * dq[0] + (long double) dq[1] * dq[1] +
                                     (long double) dq[2] * dq[2]);
    const long double vn = std::sqrt((long double) dv[0] * dv[0] + (long double) dv[1] * dv[1] +
                                     (long double) dv[2] * dv[2]);
    const double texp = (double) ((dn - sigma) / vn);
    const Contact c = pair_contact(dq, dv, da, sigma, 2.0 * texp, 1e-12 * sigma * sigma);
    ASSERT_EQ(c.status, CONTACT) << i;
    // condition: g' = -2 sigma |dv| at the root, round-off ~ eps |dq|^2
    const double ttol = 1e-13 * texp + 64 * EPS * d * d / (2 * sigma * s);
    EXPECT_NEAR(c.t, texp, ttol) << i;
    // receding: never
    for (int k = 0; k < 3; ++k) dv[k] = -dv[k];
    EXPECT_EQ(pair_contact(dq, dv, da, sigma, 1e3 * texp, 1e-12 * sigma * sigma).status,
              NO_CONTACT);
  }
}

TEST(FirstContactAnalytic, ConstantAccelerationApproach)
{
  // 1-D: x(t) = 2 - t^2 (x0 = 2, v = 0, a = -2), sigma = 1  ->  t = 1
  {
    const double dq[3] = {2, 0, 0}, dv[3] = {0, 0, 0}, da[3] = {-2, 0, 0};
    const Contact c = pair_contact(dq, dv, da, 1.0, 5.0, 1e-12);
    EXPECT_EQ(c.status, CONTACT);
    EXPECT_NEAR(c.t, 1.0, rt(8, 4, 1));    // g = 3 - 4t^2 + t^4
  }
  // decelerating approach that stops short: x = 3 - t + t^2/4 has min 2 > 1
  {
    const double dq[3] = {3, 0, 0}, dv[3] = {-1, 0, 0}, da[3] = {0.5, 0, 0};
    EXPECT_EQ(pair_contact(dq, dv, da, 1.0, 100.0, 1e-12).status, NO_CONTACT);
  }
  // 3-D with impact parameter b: |r|^2 = x(t)^2 + b^2, contact at x(t) = sqrt(sigma^2-b^2),
  // x(t) = x0 + v t + a t^2/2 with x0 > 0 moving in (v < 0, a < 0)
  Rng rng(99);
  for (int i = 0; i < 300; ++i) {
    const double sigma = rng.logu(-1, 1);
    const double b = sigma * rng.uni(0.0, 0.99);
    const double x0 = sigma * (1.0 + rng.logu(-2, 1));
    const double v = -rng.logu(-2, 1) * (rng.uni(0, 1) < 0.2 ? 0.0 : 1.0);
    const double a = -rng.logu(-2, 1);
    double e1[3], e2[3], tmp[3];
    rng.unit(e1);
    double n2;
    do {    // e2 orthogonal to e1
      rng.unit(tmp);
      const double pr = dot(tmp, e1);
      for (int k = 0; k < 3; ++k) e2[k] = tmp[k] - pr * e1[k];
      n2 = norm(e2);
    } while (n2 < 0.1);
    for (int k = 0; k < 3; ++k) e2[k] /= n2;
    double dq[3], dv[3], da[3];
    for (int k = 0; k < 3; ++k) {
      dq[k] = x0 * e1[k] + b * e2[k];
      dv[k] = v * e1[k];
      da[k] = a * e1[k];
    }
    const long double xc = std::sqrt((long double) sigma * sigma - (long double) b * b);
    // x0 - xc + v t + a/2 t^2 = 0, first positive root
    const long double texp = first_positive_root_quadratic(x0 - xc, v, 0.5L * a);
    ASSERT_GT(texp, 0.0L);
    const Contact c = pair_contact(dq, dv, da, sigma, 2.0 * (double) texp, 1e-12);
    ASSERT_EQ(c.status, CONTACT) << i;
    // slope of g at the root: 2 x x' = 2 xc |v + a t|; round-off ~ eps |r|^2;
    // the orthonormal frame itself is only accurate to ~eps
    const double slope = 2.0 * (double) xc * std::fabs(v + a * (double) texp);
    const double scale = x0 * x0 + b * b + sigma * sigma;
    EXPECT_NEAR(c.t, (double) texp, 1e-13 * (double) texp + 256 * EPS * scale / slope) << i;
  }
}

TEST(FirstContactAnalytic, WallQuadratic)
{
  // g = 1 - 3t + 2t^2 = (1-t)(1-2t): contact at 1/2
  {
    const Contact c = wall_contact(1.0, -3.0, 4.0, 2.0, 1e-12);
    EXPECT_EQ(c.status, CONTACT);
    EXPECT_NEAR(c.t, 0.5, rt(3, 1, 0.5));
  }
  // linear: dist 1, vn -4 -> 1/4
  {
    const Contact c = wall_contact(1.0, -4.0, 0.0, 1.0, 1e-12);
    EXPECT_EQ(c.status, CONTACT);
    EXPECT_NEAR(c.t, 0.25, rt(2, 4, 0.25));
  }
  // moving away but pulled back: 1 + t - t^2 -> (1 + sqrt 5)/2
  {
    const Contact c = wall_contact(1.0, 1.0, -2.0, 3.0, 1e-12);
    EXPECT_EQ(c.status, CONTACT);
    EXPECT_NEAR(c.t, 0.5 * (1.0 + std::sqrt(5.0)), rt(5.3, 2.2, 1.7));
  }
  // decelerated before the wall: 1 - t + t^2/2 > 0 always
  EXPECT_EQ(wall_contact(1.0, -1.0, 1.0, 100.0, 1e-12).status, NO_CONTACT);
  // at rest, pulled in: 2 - t^2/2 ... contact at 2
  {
    const Contact c = wall_contact(2.0, 0.0, -1.0, 3.0, 1e-12);
    EXPECT_EQ(c.status, CONTACT);
    EXPECT_NEAR(c.t, 2.0, rt(4, 2, 2));
  }
  // random quadratics vs the closed form
  Rng rng(31337);
  for (int i = 0; i < 1000; ++i) {
    const double dist = rng.logu(-3, 1);
    const double vn = rng.uni(-3, 3);
    const double an = rng.uni(-5, 5);
    const long double texp = first_positive_root_quadratic(dist, vn, 0.5L * an);
    const double tmax = 4.0;
    const Contact c = wall_contact(dist, vn, an, tmax, 1e-13);
    if (texp < 0 || texp > tmax) {
      // no root in range; but a near-tangency could be a round-off call: skip those
      const double disc = (double) (vn * (long double) vn - 2.0L * an * dist);
      if (std::fabs(disc) < 1e-9) continue;
      EXPECT_EQ(c.status, NO_CONTACT) << i;
      continue;
    }
    const double slope = std::fabs(vn + an * (double) texp);
    if (slope < 1e-6) continue;    // (near-)double root: ill-conditioned
    ASSERT_EQ(c.status, CONTACT) << i;
    EXPECT_NEAR(c.t, (double) texp, 16 * EPS * (1 + (double) texp) + 64 * EPS * 20 / slope) << i;
  }
}

// ===========================================================================
// 3. adversarial cases

TEST(FirstContactAdversarial, GrazingStraightLine)
{
  // dq = (b, -3, 0), dv = (0, 1, 0): min distance b at t = 3
  const double dv[3] = {0, 1, 0}, da[3] = {0, 0, 0};
  {
    // exactly tangent, g = (t-3)^2 exactly: a double root at 3 is a contact
    const double dq[3] = {1.0, -3.0, 0.0};
    const Contact c = pair_contact(dq, dv, da, 1.0, 10.0, 1e-13);
    EXPECT_EQ(c.status, CONTACT);
    EXPECT_EQ(c.t, 3.0);
  }
  {
    // misses by 1e-12 relative: min g = 2e-12 > 0
    const double dq[3] = {1.0 + 1e-12, -3.0, 0.0};
    EXPECT_EQ(pair_contact(dq, dv, da, 1.0, 10.0, 1e-13).status, NO_CONTACT);
  }
  {
    // dips by 1e-12 relative: roots 3 -+ sqrt(1 - b^2)
    const double b = 1.0 - 1e-12;
    const double dq[3] = {b, -3.0, 0.0};
    const long double texp = 3.0L - std::sqrt(1.0L - (long double) b * b);
    const Contact c = pair_contact(dq, dv, da, 1.0, 10.0, 1e-13);
    EXPECT_EQ(c.status, CONTACT);
    // slope 2 sqrt(2e-12) ~ 2.8e-6, round-off ~ 10 eps
    EXPECT_NEAR(c.t, (double) texp, 1e-8);
  }
  // scaled (sigma = 1e-3 and 1e3): same verdicts
  for (double L : {1e-3, 1e3}) {
    const double dvL[3] = {0, L, 0};
    const double dq_in[3] = {L * (1.0 - 1e-12), -3.0 * L, 0.0};
    const double dq_out[3] = {L * (1.0 + 1e-12), -3.0 * L, 0.0};
    EXPECT_EQ(pair_contact(dq_out, dvL, da, L, 10.0, 1e-13 * L * L).status, NO_CONTACT) << L;
    const Contact c = pair_contact(dq_in, dvL, da, L, 10.0, 1e-13 * L * L);
    EXPECT_EQ(c.status, CONTACT) << L;
    EXPECT_NEAR(c.t, 3.0 - std::sqrt(2e-12), 1e-8) << L;
  }
}

TEST(FirstContactAdversarial, GrazingQuartic)
{
  // dq = (b, -2, 0), dv = (0, 3, 0), da = (0, -2, 0): y(t) = -(t-1)(t-2),
  // |r|^2 - sigma^2 = b^2 - sigma^2 + y^2 ; with b = sigma = 1 exactly
  // g = (t^2 - 3t + 2)^2 = 4 - 12t + 13t^2 - 6t^3 + t^4 (double roots at 1, 2)
  const double dv[3] = {0, 3, 0}, da[3] = {0, -2, 0};
  {
    const double dq[3] = {1.0, -2.0, 0.0};
    double c[5];
    pair_gap_poly(dq, dv, da, 1.0, c);
    ASSERT_EQ(c[0], 4.0);
    ASSERT_EQ(c[1], -12.0);
    ASSERT_EQ(c[2], 13.0);
    ASSERT_EQ(c[3], -6.0);
    ASSERT_EQ(c[4], 1.0);
    const Contact r = first_contact(c, 4, 3.0, 1e-13);
    EXPECT_EQ(r.status, CONTACT);
    EXPECT_NEAR(r.t, 1.0, 1e-7);    // touching double root (min g == 0)
  }
  {
    const double dq[3] = {1.0 + 1e-12, -2.0, 0.0};    // min g = +2e-12
    EXPECT_EQ(pair_contact(dq, dv, da, 1.0, 3.0, 1e-13).status, NO_CONTACT);
  }
  {
    const double b = 1.0 - 1e-12;    // min g = -2e-12: dips near t = 1
    const double dq[3] = {b, -2.0, 0.0};
    const long double dlt = std::sqrt(1.0L - (long double) b * b);
    // y(t) = -dlt on the way up: t^2 - 3t + 2 - dlt = 0
    const long double texp = (3.0L - std::sqrt(1.0L + 4.0L * dlt)) / 2.0L;
    const Contact r = pair_contact(dq, dv, da, 1.0, 3.0, 1e-13);
    EXPECT_EQ(r.status, CONTACT);
    EXPECT_NEAR(r.t, (double) texp, 1e-8);
  }
}

TEST(FirstContactAdversarial, DoubleRootWall)
{
  // g = (t-1)^2: touches the wall at t = 1 exactly
  const Contact c = wall_contact(1.0, -2.0, 2.0, 5.0, 1e-13);
  EXPECT_EQ(c.status, CONTACT);
  EXPECT_EQ(c.t, 1.0);
  // g = (t-1)^2 + 1e-12: no contact ; g = (t-1)^2 - 1e-12: contact at 1 - 1e-6
  EXPECT_EQ(wall_contact(1.0 + 1e-12, -2.0, 2.0, 5.0, 1e-13).status, NO_CONTACT);
  const Contact d = wall_contact(1.0 - 1e-12, -2.0, 2.0, 5.0, 1e-13);
  EXPECT_EQ(d.status, CONTACT);
  // g = (t-1)^2 - delta, delta = 1 - dist (exact by Sterbenz): root 1 - sqrt(delta)
  const double delta = 1.0 - (1.0 - 1e-12);
  // slope 2 sqrt(delta) ~ 2e-6, round-off ~ 4 eps
  EXPECT_NEAR(d.t, 1.0 - std::sqrt(delta), 1e-9);
}

TEST(FirstContactAdversarial, TouchingAndSeparatingThenPulledBack)
{
  // 1-D: x(t) = x0 + v t + a t^2/2, v > 0, a < 0. From a contact, the gap is
  // measured from the current state, so the re-contact is x(t) = x0: t = -2v/a.
  const double v = 0.75, a = -0.5;    // t = 3 exactly
  for (double x0 : {1.0, 1.0 - 5e-15, 1.0 + 5e-15, 1.0 - 4.9e-11}) {
    const double dq[3] = {x0, 0, 0}, dv[3] = {v, 0, 0}, da[3] = {a, 0, 0};
    double c[5];
    pair_gap_poly(dq, dv, da, 1.0, c);
    ASSERT_LE(std::fabs(c[0]), 1e-10) << x0;
    const Contact r = first_contact(c, 4, 10.0, 1e-10);
    EXPECT_EQ(r.status, CONTACT) << "x0=" << x0 << " g(0)=" << c[0];
    // g~(t) = (x - x0)(x + x0): terms ~ 10, slope 2 x0 |x'(3)| = 1.5
    EXPECT_NEAR(r.t, 3.0, rt(10, 1.5, 3)) << "x0=" << x0 << " g(0)=" << c[0];
    // a tmax far below the re-contact: nothing, in particular no contact at ~0
    EXPECT_EQ(first_contact(c, 4, 1e-15, 1e-10).status, NO_CONTACT) << x0;
    // not pulled back within tmax: no contact, and certainly not at 0
    const Contact s = first_contact(c, 4, 2.5, 1e-10);
    EXPECT_EQ(s.status, NO_CONTACT) << "x0=" << x0 << " g(0)=" << c[0];
  }
  // slightly negative g(0) = -1e-14 given directly as coefficients:
  // g = -1e-14 + t - t^2/4 ... separating, comes back at t = 4
  {
    const double c[3] = {-1e-14, 1.0, -0.25};
    const Contact r = first_contact(c, 2, 10.0, 1e-12);
    EXPECT_EQ(r.status, CONTACT);
    EXPECT_NEAR(r.t, 4.0, rt(8, 1, 4));
    EXPECT_EQ(first_contact(c, 2, 3.9, 1e-12).status, NO_CONTACT);
    // g(0) < 0 but within tol: a short step must not be a contact
    EXPECT_EQ(first_contact(c, 2, 1e-15, 1e-12).status, NO_CONTACT);
  }
  // g(0) = +tol/2, separating: gap measured from here, re-contact at exactly 4
  // (taking g(0) at face value would give 4 + 2e-13)
  {
    const double c[3] = {0.5e-12, 1.0, -0.25};
    const Contact r = first_contact(c, 2, 10.0, 1e-12);
    EXPECT_EQ(r.status, CONTACT);
    EXPECT_NEAR(r.t, 4.0, rt(8, 1, 4));
  }
  // touching, tangential velocity, weak central pull: |r|^2 = 1 + t^4/4 (c1=c2=c3=0)
  {
    const double dq[3] = {1, 0, 0}, dv[3] = {0, 1, 0}, da[3] = {-1, 0, 0};
    double c[5];
    pair_gap_poly(dq, dv, da, 1.0, c);
    ASSERT_EQ(c[0], 0.0);
    ASSERT_EQ(c[1], 0.0);
    ASSERT_EQ(c[2], 0.0);
    ASSERT_EQ(c[3], 0.0);
    ASSERT_EQ(c[4], 0.25);
    EXPECT_EQ(first_contact(c, 4, 10.0, 1e-12).status, NO_CONTACT);
  }
  // wall: touching (dist = -1e-14), moving away, gravity brings it back at 2 vn/|an|
  {
    const Contact r = wall_contact(-1e-14, 2.0, -1.0, 10.0, 1e-12);
    EXPECT_EQ(r.status, CONTACT);
    EXPECT_NEAR(r.t, 4.0, 1e-12);
  }
}

TEST(FirstContactAdversarial, TouchingTangentialThenPulledBack)
{
  // touching with a purely tangential relative velocity (c1 = 0) and c2 > 0:
  // separating to second order. r = (1 - a t^2/2, t - b t^2/2, 0), a = 1/2, b = 1:
  // g = (1-a) t^2 - b t^3 + (a^2+b^2)/4 t^4 = t^2 (0.3125 t^2 - t + 0.5)
  // re-contact at the smaller root of the quadratic factor: (1 - sqrt(0.375)) / 0.625
  const double dq[3] = {1, 0, 0}, dv[3] = {0, 1, 0}, da[3] = {-0.5, -1, 0};
  double c[5];
  pair_gap_poly(dq, dv, da, 1.0, c);
  ASSERT_EQ(c[0], 0.0);
  ASSERT_EQ(c[1], 0.0);
  ASSERT_EQ(c[2], 0.5);
  ASSERT_EQ(c[3], -1.0);
  ASSERT_EQ(c[4], 0.3125);
  const double texp = (1.0 - std::sqrt(0.375)) / 0.625;
  const Contact r = first_contact(c, 4, 2.0, 1e-12);
  EXPECT_EQ(r.status, CONTACT);
  // g'(texp) = texp^2 (0.625 texp - 1) ~ -0.24, terms ~ 0.3
  EXPECT_NEAR(r.t, texp, rt(0.5, 0.24, texp));
  EXPECT_EQ(first_contact(c, 4, 0.99 * texp, 1e-12).status, NO_CONTACT);
}

TEST(FirstContactAdversarial, RootFarBelowTmax)
{
  // approaching a wall from a tiny positive gap (tol = 0, so not "touching"):
  // the contact time dist/|vn| is many decades below tmax = 1 and must still be
  // resolved to relative round-off, strictly inside (0, tmax]
  for (double d : {1e-10, 1e-20, 1e-40, 1e-60}) {
    const Contact r = wall_contact(d, -1.0, 0.0, 1.0, 0.0);
    EXPECT_EQ(r.status, CONTACT) << d;
    EXPECT_GT(r.t, 0.0) << d;
    EXPECT_NEAR(r.t, d, rt(2 * d, 1, d)) << d;
    // quadratic with a near-zero root: d - t + t^2, roots 2d / (1 + sqrt(1 - 4d)) and ~1
    const double tq = (double) first_positive_root_quadratic(d, -1.0L, 1.0L);
    const Contact q = wall_contact(d, -1.0, 2.0, 0.5, 0.0);
    EXPECT_EQ(q.status, CONTACT) << d;
    EXPECT_NEAR(q.t, tq, rt(2 * d, 1, d)) << d;
  }
}

TEST(FirstContactAdversarial, RootFarBelowTmaxExtreme)
{
  // Same as RootFarBelowTmax one step further. The documented contract is that
  // CONTACT means a crossing at t in (0, tmax] and that the returned t is on the
  // g > 0 side of the root "to within round-off". For g = 1e-80 - t on (0, 1]
  // the root 1e-80 is a perfectly representable double.
  const double d = 1e-80;
  const Contact r = wall_contact(d, -1.0, 0.0, 1.0, 0.0);
  EXPECT_EQ(r.status, CONTACT);
  EXPECT_GT(r.t, 0.0) << "CONTACT reported at t = 0, outside (0, tmax]";
  EXPECT_NEAR(r.t, d, rt(2 * d, 1, d));
}

TEST(FirstContactAdversarial, TouchingAndApproachingIsContactNow)
{
  {
    const double dq[3] = {1, 0, 0}, dv[3] = {-1, 0.5, 0}, da[3] = {3, 0, 0};
    const Contact r = pair_contact(dq, dv, da, 1.0, 1.0, 1e-12);
    EXPECT_EQ(r.status, CONTACT_NOW);
    EXPECT_EQ(r.t, 0.0);
  }
  // g(0) slightly negative / positive within tol, approaching
  for (double x0 : {1.0 - 5e-15, 1.0 + 5e-15}) {
    const double dq[3] = {x0, 0, 0}, dv[3] = {-1, 0, 0}, da[3] = {0, 0, 0};
    EXPECT_EQ(pair_contact(dq, dv, da, 1.0, 1.0, 1e-12).status, CONTACT_NOW) << x0;
  }
  // tangential velocity (c1 = 0), central pull strong enough (c2 < 0)
  {
    const double dq[3] = {1, 0, 0}, dv[3] = {0, 1, 0}, da[3] = {-1.5, 0, 0};
    double c[5];
    pair_gap_poly(dq, dv, da, 1.0, c);
    ASSERT_EQ(c[1], 0.0);
    ASSERT_LT(c[2], 0.0);
    EXPECT_EQ(first_contact(c, 4, 1.0, 1e-12).status, CONTACT_NOW);
  }
  // at rest, pulled together (c1 = c3 = 0, c2 < 0)
  {
    const double dq[3] = {1, 0, 0}, dv[3] = {0, 0, 0}, da[3] = {-1, 0, 0};
    EXPECT_EQ(pair_contact(dq, dv, da, 1.0, 1.0, 1e-12).status, CONTACT_NOW);
  }
  // wall, touching and approaching
  EXPECT_EQ(wall_contact(1e-14, -1.0, 0.0, 1.0, 1e-12).status, CONTACT_NOW);
  EXPECT_EQ(wall_contact(0.0, 0.0, -1.0, 1.0, 1e-12).status, CONTACT_NOW);
}

TEST(FirstContactAdversarial, Overlap)
{
  const double dq[3] = {0.999, 0, 0}, da[3] = {0, 0, 0};
  for (double vx : {-1.0, 0.0, 1.0}) {
    const double dv[3] = {vx, 0, 0};
    const Contact r = pair_contact(dq, dv, da, 1.0, 1.0, 1e-12);
    EXPECT_EQ(r.status, OVERLAP) << vx;
    EXPECT_EQ(r.t, 0.0);
  }
  // just beyond the tolerance
  const double c[3] = {-2e-12, 1.0, 0.0};
  EXPECT_EQ(first_contact(c, 2, 1.0, 1e-12).status, OVERLAP);
  const double c2[3] = {-0.5e-12, 1.0, 0.0};
  EXPECT_EQ(first_contact(c2, 2, 1.0, 1e-12).status, NO_CONTACT);
  EXPECT_EQ(wall_contact(-1e-6, 1.0, 0.0, 1.0, 1e-12).status, OVERLAP);
}

TEST(FirstContactAdversarial, ContactExactlyAtTmax)
{
  // g = (3 - t)^2 - 1 = 8 - 6t + t^2, roots 2 and 4
  const double dq[3] = {3, 0, 0}, dv[3] = {-1, 0, 0}, da[3] = {0, 0, 0};
  {
    const Contact r = pair_contact(dq, dv, da, 1.0, 2.0, 1e-12);
    EXPECT_EQ(r.status, CONTACT);
    EXPECT_EQ(r.t, 2.0);
  }
  EXPECT_EQ(pair_contact(dq, dv, da, 1.0, 2.0 * (1 - 1e-9), 1e-12).status, NO_CONTACT);
  {
    const Contact r = wall_contact(1.0, -1.0, 0.0, 1.0, 1e-12);
    EXPECT_EQ(r.status, CONTACT);
    EXPECT_EQ(r.t, 1.0);
  }
  {
    // quadratic wall hitting at tmax: 2 - t^2/2 at t = 2
    const Contact r = wall_contact(2.0, 0.0, -1.0, 2.0, 1e-12);
    EXPECT_EQ(r.status, CONTACT);
    EXPECT_EQ(r.t, 2.0);
  }
  EXPECT_EQ(wall_contact(1.0, -1.0, 0.0, 1.0 - std::ldexp(1.0, -20), 1e-12).status, NO_CONTACT);
}

TEST(FirstContactAdversarial, TinyTmax)
{
  const double dq[3] = {3, 0, 0}, dv[3] = {-1, 0, 0}, da[3] = {-1, 0, 0};
  for (double tmax : {1e-12, 1e-300, 0.0, -1.0}) {
    const Contact r = pair_contact(dq, dv, da, 1.0, tmax, 1e-12);
    EXPECT_EQ(r.status, NO_CONTACT) << tmax;
  }
  EXPECT_EQ(wall_contact(1e-3, -1.0, 0.0, 0.999e-3, 1e-15).status, NO_CONTACT);
  // a receding pair was in contact in the past (g(-1) < 0): a non-positive or
  // NaN tmax must not look backwards in time
  {
    const double dqr[3] = {1.5, 0, 0}, dvr[3] = {1, 0, 0}, z[3] = {0, 0, 0};
    for (double tmax : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN()})
      EXPECT_EQ(pair_contact(dqr, dvr, z, 1.0, tmax, 1e-12).status, NO_CONTACT) << tmax;
    EXPECT_EQ(wall_contact(1.0, 1.0, 0.0, -2.0, 1e-12).status, NO_CONTACT);
  }
  // tiny but sufficient
  {
    const Contact r = wall_contact(1e-9, -1.0, 0.0, 2e-9, 1e-15);
    EXPECT_EQ(r.status, CONTACT);
    EXPECT_NEAR(r.t, 1e-9, rt(2e-9, 1, 1e-9));
  }
}

TEST(FirstContactAdversarial, SimultaneousContacts)
{
  // sphere i moves along +x and is accelerated; spheres j, k are mirror images
  // of each other in the x axis: both pairs must report the very same time
  const double vi[3] = {1.25, 0.0, 0.0}, ai[3] = {0.5, 0.0, 0.0};
  const double qj[3] = {4.0, 0.7, 0.3}, qk[3] = {4.0, -0.7, -0.3};
  double dqj[3], dqk[3];
  for (int k = 0; k < 3; ++k) {
    dqj[k] = -qj[k];
    dqk[k] = -qk[k];
  }
  const Contact cj = pair_contact(dqj, vi, ai, 1.0, 5.0, 1e-12);
  const Contact ck = pair_contact(dqk, vi, ai, 1.0, 5.0, 1e-12);
  ASSERT_EQ(cj.status, CONTACT);
  ASSERT_EQ(ck.status, CONTACT);
  EXPECT_EQ(cj.t, ck.t);
  // analytic: (x - 4)^2 = 1 - 0.58, x = 1.25 t + 0.25 t^2
  const double xc = 4.0 - std::sqrt(1.0 - 0.49 - 0.09);
  const double texp = (-1.25 + std::sqrt(1.25 * 1.25 + xc)) / 0.5;
  EXPECT_NEAR(cj.t, texp, 1e-13);

  // two different head-on pairs with the same contact time t = 2:
  // (|dq| - sigma)/|dv| = (3 - 1)/1 = (4 - 1)/1.5 = (7 - 3)/2
  const double z[3] = {0, 0, 0};
  const double dq1[3] = {3, 0, 0}, dv1[3] = {-1, 0, 0};
  const double dq2[3] = {0, 4, 0}, dv2[3] = {0, -1.5, 0};
  const double dq3[3] = {0, 0, -7}, dv3[3] = {0, 0, 2};
  const Contact r1 = pair_contact(dq1, dv1, z, 1.0, 3.0, 1e-12);
  const Contact r2 = pair_contact(dq2, dv2, z, 1.0, 3.0, 1e-12);
  const Contact r3 = pair_contact(dq3, dv3, z, 3.0, 3.0, 1e-12);
  EXPECT_EQ(r1.status, CONTACT);
  EXPECT_EQ(r2.status, CONTACT);
  EXPECT_EQ(r3.status, CONTACT);
  EXPECT_NEAR(r1.t, 2.0, rt(24, 2, 2));      // 8 - 6t + t^2
  EXPECT_NEAR(r2.t, 2.0, rt(48, 3, 2));      // 15 - 12t + 2.25t^2
  EXPECT_NEAR(r3.t, 2.0, rt(112, 12, 2));    // 40 - 28t + 4t^2
  // the mirror pair with the axes permuted (y,z,x): the coefficient sums are
  // formed in a different order, so identical only up to an ulp or two
  {
    const double vp[3] = {0.0, 0.0, 1.25}, ap[3] = {0.0, 0.0, 0.5};
    const double dqp[3] = {-0.7, -0.3, -4.0};
    const Contact cp = pair_contact(dqp, vp, ap, 1.0, 5.0, 1e-12);
    ASSERT_EQ(cp.status, CONTACT);
    EXPECT_NEAR(cp.t, cj.t, 2 * rt(40, 2.8, 2));
  }
}

TEST(FirstContactAdversarial, VanishingLeadingCoefficients)
{
  const double z[3] = {0, 0, 0};
  // da = 0 -> degree 2 (c3 = c4 = 0): t = (2 - 1)/1 = 1
  {
    const double dq[3] = {2, 0, 0}, dv[3] = {-1, 0, 0};
    double c[5];
    pair_gap_poly(dq, dv, z, 1.0, c);
    ASSERT_EQ(c[3], 0.0);
    ASSERT_EQ(c[4], 0.0);
    const Contact r = first_contact(c, 4, 2.0, 1e-12);
    EXPECT_EQ(r.status, CONTACT);
    EXPECT_NEAR(r.t, 1.0, rt(8, 2, 1));    // 3 - 4t + t^2
  }
  // dv = 0, da = 0 -> constant: never
  {
    const double dq[3] = {2, 0, 0};
    EXPECT_EQ(pair_contact(dq, z, z, 1.0, 1e9, 1e-12).status, NO_CONTACT);
  }
  // dv = 0, da != 0 (c1 = c3 = 0): x = 2 - t^2/2 ... contact x = 1 at t = sqrt 2
  {
    const double dq[3] = {2, 0, 0}, da[3] = {-1, 0, 0};
    const Contact r = pair_contact(dq, z, da, 1.0, 3.0, 1e-12);
    EXPECT_EQ(r.status, CONTACT);
    EXPECT_NEAR(r.t, std::sqrt(2.0), rt(8, 2.8, 1.5));    // 3 - 2t^2 + t^4/4
  }
  // da orthogonal to dv (c3 = 0, c4 != 0):
  // |r|^2 = (3 - 2.4 t)^2 + 0.64 t^4 = 1 at t = 1 (0.36 + 0.64), g'(1) = -0.32
  {
    const double dq[3] = {0, 0, 3}, dv[3] = {0, 0, -2.4}, da[3] = {1.6, 0, 0};
    double c[5];
    pair_gap_poly(dq, dv, da, 1.0, c);
    ASSERT_EQ(c[3], 0.0);
    ASSERT_GT(c[4], 0.0);
    const Contact r = first_contact(c, 4, 3.0, 1e-12);
    EXPECT_EQ(r.status, CONTACT);
    EXPECT_NEAR(r.t, 1.0, 1e-13);
  }
  // degree 1 wall, degree 0 wall
  {
    const Contact r = wall_contact(3.0, -1.5, 0.0, 5.0, 1e-12);
    EXPECT_EQ(r.status, CONTACT);
    EXPECT_NEAR(r.t, 2.0, rt(6, 1.5, 2));
    EXPECT_EQ(wall_contact(3.0, 0.0, 0.0, 5.0, 1e-12).status, NO_CONTACT);
    EXPECT_EQ(wall_contact(3.0, 1.0, 0.0, 5.0, 1e-12).status, NO_CONTACT);
  }
  // caller passing degree 4 with explicit zero leading coefficients, and n < 4
  {
    const double c[5] = {1.0, -1.0, 0.0, 0.0, 0.0};
    const Contact r = first_contact(c, 4, 2.0, 1e-12);
    EXPECT_EQ(r.status, CONTACT);
    EXPECT_NEAR(r.t, 1.0, rt(2, 1, 1));
  }
  // all-zero polynomial (touching, no relative motion): not a contact
  {
    const double c[5] = {0, 0, 0, 0, 0};
    EXPECT_EQ(first_contact(c, 4, 1.0, 1e-12).status, NO_CONTACT);
  }
}

TEST(FirstContactAdversarial, LengthAndTimeScaleInvariance)
{
  // reference case with a generic contact time
  const double dq0[3] = {2.1, -0.7, 0.4}, dv0[3] = {-0.9, 0.35, -0.1}, da0[3] = {-0.3, 0.2, 0.15};
  const double sigma0 = 1.0, tmax0 = 3.0, tol0 = 1e-12;
  const Contact ref = pair_contact(dq0, dv0, da0, sigma0, tmax0, tol0);
  ASSERT_EQ(ref.status, CONTACT);
  // independent check of the reference itself by the brute force
  {
    PairCase p{{2.1, -0.7, 0.4}, {-0.9, 0.35, -0.1}, {-0.3, 0.2, 0.15}, sigma0, tmax0};
    const BruteResult bf = brute_first_crossing([&](double t) { return gap(p, t); },
                                                [&](double t) { return dgap(p, t); }, tmax0,
                                                pair_M2(p), pair_roundoff(p), 20000);
    ASSERT_EQ(bf.kind, BF::CONTACT);
    EXPECT_NEAR(ref.t, bf.t, 1e-12);
  }
  // power-of-two scaling is exact in floating point: bit-identical times
  for (int e : {-40, -10, 10, 40}) {
    const double L = std::ldexp(1.0, e);
    double dq[3], dv[3], da[3];
    for (int k = 0; k < 3; ++k) {
      dq[k] = L * dq0[k];
      dv[k] = L * dv0[k];
      da[k] = L * da0[k];
    }
    const Contact r = pair_contact(dq, dv, da, L * sigma0, tmax0, tol0 * L * L);
    EXPECT_EQ(r.status, CONTACT) << e;
    EXPECT_EQ(r.t, ref.t) << "length scale 2^" << e;
  }
  // decimal scales sigma = 1e-3, 1e3: same time to round-off
  for (double L : {1e-3, 1e3}) {
    double dq[3], dv[3], da[3];
    for (int k = 0; k < 3; ++k) {
      dq[k] = L * dq0[k];
      dv[k] = L * dv0[k];
      da[k] = L * da0[k];
    }
    const Contact r = pair_contact(dq, dv, da, L * sigma0, tmax0, tol0 * L * L);
    EXPECT_EQ(r.status, CONTACT) << L;
    EXPECT_NEAR(r.t, ref.t, 1e-12 * ref.t) << "length scale " << L;
  }
  // time scale: v -> v/T, a -> a/T^2, tmax -> T tmax gives t -> T t
  for (double T : {1e-3, 0.37, 1e3}) {
    double dv[3], da[3];
    for (int k = 0; k < 3; ++k) {
      dv[k] = dv0[k] / T;
      da[k] = da0[k] / (T * T);
    }
    const Contact r = pair_contact(dq0, dv, da, sigma0, tmax0 * T, tol0);
    EXPECT_EQ(r.status, CONTACT) << T;
    EXPECT_NEAR(r.t, T * ref.t, 1e-12 * T * ref.t) << "time scale " << T;
  }
}

// ===========================================================================
// 4. poly_roots_in against known roots

namespace {

// coefficients of lead * prod (t - r_i), computed in long double
void poly_from_roots(const std::vector<double> &r, double lead, double *c)
{
  long double p[5] = {(long double) lead, 0, 0, 0, 0};
  int deg = 0;
  for (double ri : r) {
    // p <- p * (t - ri)
    for (int k = deg + 1; k >= 1; --k) p[k] = p[k - 1] - ri * p[k];
    p[0] = -ri * p[0];
    ++deg;
  }
  for (int k = 0; k < 5; ++k) c[k] = (k <= deg) ? (double) p[k] : 0.0;
}

}    // namespace

TEST(PolyRootsIn, RandomProductsOfLinearFactors)
{
  Rng rng(1234);
  int n_checked_roots = 0, n_skipped = 0, n_clustered = 0;
  for (int icase = 0; icase < 20000; ++icase) {
    const int deg = 1 + icase % 4;
    std::vector<double> r;
    const bool clustered = (icase / 4) % 3 == 0 && deg >= 2;
    const double a = rng.uni(-3.5, 0.0), b = rng.uni(0.5, 3.5);
    for (int i = 0; i < deg; ++i) r.push_back(rng.uni(-3.0, 3.0));
    if (clustered) {
      r[0] = rng.uni(a + 0.01, b - 0.01);    // the cluster lies inside (a, b)
      r[1] = r[0] + (rng.uni(0, 1) < 0.5 ? 1e-6 : -1e-6) * rng.uni(1.0, 2.0);
      if (deg == 4 && rng.uni(0, 1) < 0.5) r[3] = r[2] + 1e-6;    // two clusters
    }
    // reject accidental near-coincidences other than the designed cluster
    bool ok = true;
    for (int i = 0; i < deg; ++i)
      for (int j = i + 1; j < deg; ++j)
        if (std::fabs(r[i] - r[j]) < 0.5e-6) ok = false;
    if (!ok) {
      ++n_skipped;
      continue;
    }
    const double lead = (rng.uni(0, 1) < 0.5 ? -1 : 1) * rng.logu(-3, 3);
    double c[5];
    poly_from_roots(r, lead, c);

    // expected roots: those in (a, b), with their condition-based tolerance
    std::vector<double> exp_roots, exp_tol;
    bool ambiguous = false;
    for (int i = 0; i < deg; ++i) {
      double dp = lead;    // p'(r_i) = lead * prod_{j != i} (r_i - r_j)
      for (int j = 0; j < deg; ++j)
        if (j != i) dp *= (r[i] - r[j]);
      double scale = 0.0;
      for (int k = 0; k <= deg; ++k) scale += std::fabs(c[k]) * std::pow(std::fabs(r[i]), k);
      // rounding of the coefficients (eps/2) + Horner (~2n eps) + bracket (4 eps |r|)
      const double tol = 16.0 * EPS * scale / std::fabs(dp) + 8.0 * EPS * std::fabs(r[i]);
      if (tol > 1e-7 && r[i] > a - 0.01 && r[i] < b + 0.01) ambiguous = true;    // vs 1e-6 cluster
      if (std::fabs(r[i] - a) <= 2 * tol || std::fabs(r[i] - b) <= 2 * tol) ambiguous = true;
      if (r[i] > a && r[i] < b) {
        exp_roots.push_back(r[i]);
        exp_tol.push_back(tol);
      }
    }
    // two neighbouring roots are resolvable only if |p| between them is well above
    // its round-off level; otherwise the number of roots is a round-off call
    {
      std::vector<double> rs = r;
      std::sort(rs.begin(), rs.end());
      for (int i = 0; i + 1 < deg; ++i) {
        const double m = 0.5 * (rs[i] + rs[i + 1]);
        double pm = lead, sc = 0.0;
        for (int j = 0; j < deg; ++j) pm *= (m - rs[j]);
        for (int k = 0; k <= deg; ++k) sc += std::fabs(c[k]) * std::pow(std::fabs(m), k);
        if (std::fabs(pm) < 100 * EPS * sc && m > a - 1e-3 && m < b + 1e-3) ambiguous = true;
      }
    }
    if (ambiguous) {
      ++n_skipped;
      continue;
    }
    std::vector<size_t> idx(exp_roots.size());
    for (size_t i = 0; i < idx.size(); ++i) idx[i] = i;
    std::sort(idx.begin(), idx.end(), [&](size_t x, size_t y) { return exp_roots[x] < exp_roots[y]; });

    double out[4] = {NAN, NAN, NAN, NAN};
    const int nr = poly_roots_in(c, 4, a, b, out);
    ASSERT_EQ(nr, (int) exp_roots.size())
        << "case " << icase << " deg " << deg << (clustered ? " clustered" : "");
    for (int i = 0; i < nr; ++i) {
      const size_t j = idx[i];
      EXPECT_NEAR(out[i], exp_roots[j], exp_tol[j]) << "case " << icase << " root " << i;
      EXPECT_GT(out[i], a);
      EXPECT_LT(out[i], b);
      if (i > 0) {
        EXPECT_LT(out[i - 1], out[i]) << "ascending, case " << icase;
      }
      ++n_checked_roots;
    }
    if (clustered) ++n_clustered;
  }
  std::printf("[ info     ] roots checked %d, clustered cases %d, skipped cases %d\n",
              n_checked_roots, n_clustered, n_skipped);
  EXPECT_GT(n_checked_roots, 20000);
  EXPECT_GT(n_clustered, 4000);
  EXPECT_LT(n_skipped, 2000);
}

TEST(PolyRootsIn, SpecialCases)
{
  double out[4];
  // exact roots 0.5, 1, 2 and 3 (degree 4), interval (0, 2.5)
  {
    double c[5];
    poly_from_roots({0.5, 1.0, 2.0, 3.0}, 1.0, c);
    ASSERT_EQ(poly_roots_in(c, 4, 0.0, 2.5, out), 3);
    EXPECT_NEAR(out[0], 0.5, rt(13.2, 1.875, 0.5));
    EXPECT_NEAR(out[1], 1.0, rt(36, 1, 1));
    EXPECT_NEAR(out[2], 2.0, rt(150, 1.5, 2));
  }
  // no real roots: (t^2 + 1)(t^2 + 2)
  {
    const double c[5] = {2.0, 0.0, 3.0, 0.0, 1.0};
    EXPECT_EQ(poly_roots_in(c, 4, -10.0, 10.0, out), 0);
  }
  // (t^2 + 1)(t - 0.25)(t + 4): one root in (-1, 1)
  {
    double c[5];
    poly_from_roots({0.25, -4.0}, 1.0, c);
    // multiply by t^2 + 1
    double d[5] = {c[0], c[1], c[2] + c[0], c[1], c[2]};
    ASSERT_EQ(poly_roots_in(d, 4, -1.0, 1.0, out), 1);
    EXPECT_NEAR(out[0], 0.25, rt(2.3, 4.5, 0.25));
  }
  // double root at a critical point, exactly representable: (t - 1)^2
  {
    const double c[3] = {1.0, -2.0, 1.0};
    ASSERT_EQ(poly_roots_in(c, 2, 0.0, 3.0, out), 1);
    EXPECT_EQ(out[0], 1.0);
    // (t - 1)^2 (t - 3) = t^3 - 5t^2 + 7t - 3: double root 1, simple root 3
    const double d[4] = {-3.0, 7.0, -5.0, 1.0};
    const int n = poly_roots_in(d, 3, 0.0, 4.0, out);
    ASSERT_GE(n, 1);
    EXPECT_NEAR(out[n - 1], 3.0, rt(48, 4, 3));
  }
  // open interval: roots at the endpoints are excluded
  {
    double c[5];
    poly_from_roots({1.0, 2.0}, 1.0, c);
    EXPECT_EQ(poly_roots_in(c, 2, 1.0, 2.0, out), 0);
    EXPECT_EQ(poly_roots_in(c, 2, 1.0, 2.0 + 1e-9, out), 1);
  }
  // empty or reversed interval
  {
    const double c[2] = {-1.0, 1.0};
    EXPECT_EQ(poly_roots_in(c, 1, 2.0, 2.0, out), 0);
    EXPECT_EQ(poly_roots_in(c, 1, 3.0, 0.0, out), 0);
  }
  // vanishing leading coefficients: 2 - t passed as degree 4
  {
    const double c[5] = {2.0, -1.0, 0.0, 0.0, 0.0};
    ASSERT_EQ(poly_roots_in(c, 4, 0.0, 5.0, out), 1);
    EXPECT_EQ(out[0], 2.0);
  }
  // clustered pair around 1 (1e-6 apart) plus two far roots, tiny leading coefficient
  {
    double c[5];
    poly_from_roots({1.0, 1.0 + 1e-6, -2.0, 2.5}, 1e-3, c);
    ASSERT_EQ(poly_roots_in(c, 4, 0.0, 2.0, out), 2);
    EXPECT_NEAR(out[0], 1.0, 1e-8);
    EXPECT_NEAR(out[1], 1.0 + 1e-6, 1e-8);
    EXPECT_LT(out[0], out[1]);
  }
}
