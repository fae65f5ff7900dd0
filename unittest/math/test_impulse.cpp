// Unit tests for the elastic collision impulse HardSphere::pair_impulse in
// src/HARDSPHERE/hs_contact.h (Bond & Leimkuhler 2007, section 2: R(q,p) =
// (q, p + alpha u), alpha from H o R = H).
//
// Stand-alone build:
//   g++ -std=c++17 -O2 -I src/HARDSPHERE unittest/math/test_impulse.cpp
//       -lgtest -lgtest_main -pthread -o /tmp/ti && /tmp/ti
//
// Expected values: conservation laws, the 1-D elastic collision formulas and
// the paper's alpha = -2 u^T M^-1 p / u^T M^-1 u evaluated in 6-D.

#include "hs_contact.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

using namespace HardSphere;

namespace {

constexpr double EPS = std::numeric_limits<double>::epsilon();

double dot(const double *a, const double *b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

double norm(const double *a)
{
  return std::sqrt(dot(a, a));
}

struct Rng {
  std::mt19937_64 eng;
  explicit Rng(uint64_t seed) : eng(seed) {}
  double uni(double a, double b) { return std::uniform_real_distribution<double>(a, b)(eng); }
  double logu(double lo_exp, double hi_exp) { return std::pow(10.0, uni(lo_exp, hi_exp)); }
  void vec(double *u, double scale)
  {
    std::normal_distribution<double> n(0.0, 1.0);
    for (int k = 0; k < 3; ++k) u[k] = scale * n(eng);
  }
};

struct After {
  double vi[3], vj[3], J[3];
};

After collide(const double *dq, const double *vi, const double *vj, double mi, double mj)
{
  After a;
  double dv[3];
  for (int k = 0; k < 3; ++k) dv[k] = vi[k] - vj[k];
  pair_impulse(dq, dv, mi, mj, a.J);
  for (int k = 0; k < 3; ++k) {
    a.vi[k] = vi[k] + a.J[k] / mi;
    a.vj[k] = vj[k] - a.J[k] / mj;
  }
  return a;
}

}    // namespace

TEST(PairImpulse, RandomConservationAndReflection)
{
  Rng rng(2007);
  const int NCASE = 20000;
  double worst_p = 0, worst_e = 0, worst_n = 0, worst_t = 0, worst_par = 0;
  for (int icase = 0; icase < NCASE; ++icase) {
    const double mi = rng.logu(-3, 3), mj = rng.logu(-3, 3);
    double dq[3], vi[3], vj[3], dv[3];
    rng.vec(dq, rng.logu(-3, 3));
    rng.vec(vi, rng.logu(-2, 2));
    rng.vec(vj, rng.logu(-2, 2));
    for (int k = 0; k < 3; ++k) dv[k] = vi[k] - vj[k];
    if (dot(dq, dv) > 0.0)
      for (int k = 0; k < 3; ++k) dq[k] = -dq[k];    // approaching: dq.dv < 0
    ASSERT_LT(dot(dq, dv), 0.0);

    const After a = collide(dq, vi, vj, mi, mj);

    // total momentum, to round-off relative to the momenta involved
    double dP = 0, Pscale = 0;
    for (int k = 0; k < 3; ++k) {
      const double P0 = mi * vi[k] + mj * vj[k];
      const double P1 = mi * a.vi[k] + mj * a.vj[k];
      dP = std::max(dP, std::fabs(P1 - P0));
      Pscale = std::max(Pscale, std::fabs(mi * vi[k]) + std::fabs(mj * vj[k]) +
                                    std::fabs(mi * a.vi[k]) + std::fabs(mj * a.vj[k]));
    }
    EXPECT_LE(dP, 1e-13 * Pscale) << "momentum, case " << icase;
    worst_p = std::max(worst_p, dP / Pscale);

    // kinetic energy (a sum of positive terms: plain relative error)
    const double E0 = 0.5 * mi * dot(vi, vi) + 0.5 * mj * dot(vj, vj);
    const double E1 = 0.5 * mi * dot(a.vi, a.vi) + 0.5 * mj * dot(a.vj, a.vj);
    EXPECT_LE(std::fabs(E1 - E0), 1e-13 * E0) << "energy, case " << icase;
    worst_e = std::max(worst_e, std::fabs(E1 - E0) / E0);

    // normal relative velocity reversed, tangential unchanged
    double u[3], dv1[3];
    const double nq = norm(dq);
    for (int k = 0; k < 3; ++k) {
      u[k] = dq[k] / nq;
      dv1[k] = a.vi[k] - a.vj[k];
    }
    const double vscale = norm(vi) + norm(vj) + norm(a.vi) + norm(a.vj);
    const double un0 = dot(u, dv), un1 = dot(u, dv1);
    EXPECT_NEAR(un1, -un0, 1e-13 * vscale) << "normal component, case " << icase;
    worst_n = std::max(worst_n, std::fabs(un1 + un0) / vscale);
    for (int k = 0; k < 3; ++k) {
      const double t0 = dv[k] - un0 * u[k], t1 = dv1[k] - un1 * u[k];
      EXPECT_NEAR(t1, t0, 1e-13 * vscale) << "tangential component " << k << ", case " << icase;
      worst_t = std::max(worst_t, std::fabs(t1 - t0) / vscale);
    }

    // J parallel to dq and repulsive (pushes i along +dq, away from j)
    double cr[3] = {a.J[1] * dq[2] - a.J[2] * dq[1], a.J[2] * dq[0] - a.J[0] * dq[2],
                    a.J[0] * dq[1] - a.J[1] * dq[0]};
    EXPECT_LE(norm(cr), 1e-13 * norm(a.J) * nq) << "J parallel to dq, case " << icase;
    EXPECT_GT(dot(a.J, dq), 0.0) << "case " << icase;
    worst_par = std::max(worst_par, norm(cr) / (norm(a.J) * nq));
  }
  std::printf("[ info     ] worst relative errors: momentum %.2g energy %.2g normal %.2g "
              "tangential %.2g parallel %.2g\n",
              worst_p, worst_e, worst_n, worst_t, worst_par);
}

TEST(PairImpulse, MatchesPaperAlpha)
{
  // alpha = -2 u^T M^-1 p / u^T M^-1 u with the 6-D constraint normal
  // u = (dq, -dq) and p = (mi vi, mj vj); the momentum added to i is alpha dq.
  Rng rng(11);
  for (int icase = 0; icase < 2000; ++icase) {
    const double mi = rng.logu(-2, 2), mj = rng.logu(-2, 2);
    double dq[3], vi[3], vj[3], dv[3], J[3];
    rng.vec(dq, 1.0);
    rng.vec(vi, 1.0);
    rng.vec(vj, 1.0);
    for (int k = 0; k < 3; ++k) dv[k] = vi[k] - vj[k];
    long double num = 0, den = 0;
    for (int k = 0; k < 3; ++k) {
      num += (long double) dq[k] * ((long double) mi * vi[k]) / mi -
          (long double) dq[k] * ((long double) mj * vj[k]) / mj;
      den += (long double) dq[k] * dq[k] / mi + (long double) dq[k] * dq[k] / mj;
    }
    const long double alpha = -2.0L * num / den;
    pair_impulse(dq, dv, mi, mj, J);
    // round-off: relative in alpha, plus the cancellation in dq.dv (~eps |dq||dv|)
    const double mu = mi * mj / (mi + mj);
    const double jscale = std::fabs((double) alpha) * norm(dq) + 2.0 * mu * norm(dv);
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(J[k], (double) (alpha * dq[k]), 64 * EPS * jscale) << icase << " " << k;
  }
}

TEST(PairImpulse, OneDimensionalElasticFormulas)
{
  // head-on along x: vi' = ((mi - mj) vi + 2 mj vj)/(mi + mj), etc.
  {
    const double dq[3] = {-1, 0, 0}, vi[3] = {2, 0, 0}, vj[3] = {-1, 0, 0};
    const After a = collide(dq, vi, vj, 1.0, 3.0);
    EXPECT_DOUBLE_EQ(a.vi[0], -2.5);
    EXPECT_DOUBLE_EQ(a.vj[0], 0.5);
    EXPECT_EQ(a.vi[1], 0.0);
    EXPECT_EQ(a.vj[2], 0.0);
  }
  // equal masses exchange velocities
  {
    const double dq[3] = {0, 0, 2}, vi[3] = {0.25, -0.5, -1.0}, vj[3] = {0.25, -0.5, 0.75};
    const After a = collide(dq, vi, vj, 2.0, 2.0);
    for (int k = 0; k < 3; ++k) {
      EXPECT_DOUBLE_EQ(a.vi[k], vj[k]);
      EXPECT_DOUBLE_EQ(a.vj[k], vi[k]);
    }
  }
  // random masses and speeds against the 1-D formulas, random direction
  Rng rng(3);
  for (int icase = 0; icase < 1000; ++icase) {
    const double mi = rng.logu(-3, 3), mj = rng.logu(-3, 3);
    double e[3];
    rng.vec(e, 1.0);
    const double ne = norm(e);
    for (int k = 0; k < 3; ++k) e[k] /= ne;
    const double ui = rng.uni(-2, 2), uj = rng.uni(-2, 2);
    // dq along -e if ui > uj so that they approach
    double dq[3], vi[3], vj[3];
    const double sgn = (ui > uj) ? -1.0 : 1.0;
    const double dist = rng.logu(-1, 1);
    for (int k = 0; k < 3; ++k) {
      dq[k] = sgn * dist * e[k];
      vi[k] = ui * e[k];
      vj[k] = uj * e[k];
    }
    const double ui1 = ((mi - mj) * ui + 2 * mj * uj) / (mi + mj);
    const double uj1 = ((mj - mi) * uj + 2 * mi * ui) / (mi + mj);
    const After a = collide(dq, vi, vj, mi, mj);
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(a.vi[k], ui1 * e[k], 1e-13 * (std::fabs(ui) + std::fabs(uj))) << icase;
      EXPECT_NEAR(a.vj[k], uj1 * e[k], 1e-13 * (std::fabs(ui) + std::fabs(uj))) << icase;
    }
  }
}

TEST(PairImpulse, LimitsAndSymmetries)
{
  // a very heavy partner at rest is a wall: vi reflects in the plane normal to dq
  {
    const double dq[3] = {1, 2, -2}, vi[3] = {-1.5, 0.5, 2.0}, vj[3] = {0, 0, 0};
    const After a = collide(dq, vi, vj, 1.0, 1e20);
    const double un = dot(dq, vi) / 9.0;    // |dq|^2 = 9
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(a.vi[k], vi[k] - 2 * un * dq[k], 1e-14 * 4);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(a.vj[k], 0.0, 1e-19);
  }
  // equal masses, target at rest: outgoing velocities are perpendicular
  Rng rng(17);
  for (int icase = 0; icase < 500; ++icase) {
    double dq[3], vi[3], vj[3] = {0, 0, 0};
    rng.vec(dq, 1.0);
    rng.vec(vi, 1.0);
    if (dot(dq, vi) > 0)
      for (int k = 0; k < 3; ++k) dq[k] = -dq[k];
    const After a = collide(dq, vi, vj, 0.7, 0.7);
    EXPECT_NEAR(dot(a.vi, a.vj), 0.0, 1e-14 * dot(vi, vi)) << icase;
  }
  // only the direction of dq matters: power-of-two rescaling is bit-identical
  {
    const double dq0[3] = {0.3, -0.7, 1.1}, dv[3] = {-0.9, 0.2, -0.4};
    double J0[3];
    pair_impulse(dq0, dv, 1.3, 0.45, J0);
    for (int e : {-30, -5, 5, 30}) {
      double dq[3], J[3];
      for (int k = 0; k < 3; ++k) dq[k] = std::ldexp(dq0[k], e);
      pair_impulse(dq, dv, 1.3, 0.45, J);
      for (int k = 0; k < 3; ++k) EXPECT_EQ(J[k], J0[k]) << e;
    }
    // swapping the roles of i and j (dq -> -dq, dv -> -dv, mi <-> mj) gives -J
    const double mdq[3] = {-0.3, 0.7, -1.1}, mdv[3] = {0.9, -0.2, 0.4};
    double Jr[3];
    pair_impulse(mdq, mdv, 0.45, 1.3, Jr);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(Jr[k], -J0[k], 4 * EPS * norm(J0));
  }
  // grazing (dq.dv = 0): no impulse
  {
    const double dq[3] = {1, 0, 0}, dv[3] = {0, 1, -1};
    double J[3];
    pair_impulse(dq, dv, 1.0, 2.0, J);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(J[k], 0.0);
  }
}
