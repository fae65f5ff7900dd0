// Unit tests for src/HARDSPHERE/hs_cluster_flow.h: one cluster's flow with
// contacts for mcva's local form (Gauss-Legendre flow of the cluster's
// modified Hamiltonian H~, contacts on the collocation parabola refined on
// the flow, alpha-hat impulses, partners' momentum by Gauss quadrature).
//
// Expected values, none from the kernel's own output:
// - a sphere bouncing on a wall under a constant force (no terms: the flow
//   is the exact parabola and alpha-hat the elastic impulse): contact
//   times, bounce count and end state from the closed-form solution;
// - two spheres on a spring that collide again and again: H~ is kept
//   through the contacts to fourth order in dt (each run's H~ with its own
//   dt; fitted slope >= 3.6), as many contacts at every dt, momentum kept
//   to round-off (Gauss keeps linear invariants, the impulse is equal and
//   opposite);
// - members tied to static partners: the members' and partners' momenta
//   together are kept to round-off (the partners' quadrature);
// - a static sphere in the way ends the flow with its index.

#include "hs_cluster_flow.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

using namespace HardSphere;

namespace {

// kind 1: spring 20/2 (r - 1.2)^2; kind 2: a soft repulsion 0.5 / r^4
void phi(int kind, double r, int, double *d)
{
  if (kind == 1) {
    d[0] = 10.0 * (r - 1.2) * (r - 1.2);
    d[1] = 20.0 * (r - 1.2);
    d[2] = 20.0;
    d[3] = d[4] = 0.0;
  } else {
    const double i = 1.0 / r, i4 = i * i * i * i;
    d[0] = 0.5 * i4;
    d[1] = -2.0 * i4 * i;
    d[2] = 10.0 * i4 * i * i;
    d[3] = -60.0 * i4 * i * i * i;
    d[4] = 420.0 * i4 * i4;
  }
}
using PhiFn = void (*)(int, double, int, double *);
using Gauss = ClusterGauss<PhiFn>;
using Flow = ClusterFlow<PhiFn>;

ClusterTerm term(int a, int b, int kind, std::vector<double> xb = {0, 0, 0}, int partner = -1)
{
  ClusterTerm t;
  t.a = a;
  t.b = b;
  t.kind = kind;
  t.partner = partner;
  for (int d = 0; d < 3; d++) t.xb[d] = xb[d];
  return t;
}

TEST(ClusterFlow, WallBounceUnderConstantForceIsExact)
{
  const double m = 2.0, g = 1.5, R = 0.5;
  const double im[1] = {1.0 / m}, fc[3] = {0.0, 0.0, -m * g};
  const Gauss G(1, im, fc, 0.01 * 0.01 / 12.0, {}, &phi);
  FlowWall W;
  W.dim = 2;
  W.coord = 0.0;
  W.sign = 1.0;
  Flow F(G, {R}, {}, {W}, 0, 1e-9);
  const double z0 = 2.0, vz0 = 0.3, vx = 0.7, T = 3.0;
  std::vector<double> y = {0.0, 0.0, z0, vx, 0.0, vz0}, pm;
  ASSERT_EQ(F.run(T, y, pm), Flow::DONE);
  // closed form: first impact at t1, then bounces every 2 v_imp / g
  const double vimp = std::sqrt(vz0 * vz0 + 2.0 * g * (z0 - R));
  const double t1 = (vz0 + vimp) / g, period = 2.0 * vimp / g;
  int nb = 0;
  double tlast = 0.0;
  for (double tb = t1; tb <= T; tb += period) {
    nb++;
    tlast = tb;
  }
  EXPECT_EQ(F.stats.wall, nb);
  const double s = T - tlast;
  EXPECT_NEAR(y[2], R + vimp * s - 0.5 * g * s * s, 1e-11);
  EXPECT_NEAR(y[5], vimp - g * s, 1e-11);
  EXPECT_NEAR(y[0], vx * T, 1e-12);
  // the sub-steps end at the contacts
  const auto &sg = F.segments()[0];
  ASSERT_EQ((int) sg.size(), nb + 1);
  for (int k = 0; k < nb; k++) EXPECT_NEAR(sg[k].t1, t1 + k * period, 1e-12) << "bounce " << k;
}

// a sphere at rest on the wall, pressed against it by a constant force:
// no impulse can move it on (no normal velocity) and the flow cannot pass
// the wall, a resting contact, which the flow names instead of taking
// sub-steps of zero length without end
TEST(ClusterFlow, RestingContactIsNamed)
{
  const double im[1] = {1.0}, fc[3] = {0.0, 0.0, -1.5};
  const Gauss G(1, im, fc, 0.01 * 0.01 / 12.0, {}, &phi);
  FlowWall W;
  W.dim = 2;
  W.coord = 0.0;
  W.sign = 1.0;
  Flow F(G, {0.5}, {}, {W}, 0, 1e-9);
  std::vector<double> y = {0.3, 0.0, 0.5, 0.2, 0.0, 0.0}, pm;
  ASSERT_EQ(F.run(0.01, y, pm), Flow::RESTING);
  EXPECT_EQ(F.hit_member, 0);
  EXPECT_EQ(F.hit_static, -1);    // wall 0
  // a bounce under the same force is no resting contact
  std::vector<double> y2 = {0.3, 0.0, 0.5, 0.2, 0.0, -0.1};
  Flow F2(G, {0.5}, {}, {W}, 0, 1e-9);
  EXPECT_EQ(F2.run(0.01, y2, pm), Flow::DONE);
  EXPECT_EQ(F2.stats.wall, 1);
}

// two unit-radius-sum spheres (masses 1 and 3) on a spring of rest length
// 1.2 with a soft repulsion, oscillating hard enough to collide at r = 1
struct Pair {
  std::vector<double> im = {1.0, 1.0 / 3.0};
  std::vector<ClusterTerm> terms = {term(0, 1, 1), term(0, 1, 2)};
  std::vector<double> y0 = {0.0, 0.0, 0.0, 1.6, 0.2, 0.0,     // q
                            1.0, 0.3, -0.2, -0.6, 0.1, 0.4};   // v
};

TEST(ClusterFlow, SpringPairKeepsModifiedEnergyToFourthOrderThroughContacts)
{
  Pair P;
  // static atoms in the terms too: their terms' directions differ from the
  // contact normal, so the elastic impulse would change H~ (with the pair's
  // terms alone, along the normal, it keeps it)
  P.terms.push_back(term(0, -1, 1, {-1.0, 0.3, 0.1}));
  P.terms.push_back(term(1, -1, 2, {2.6, -0.4, 0.2}));
  const double T = 10.0;
  std::vector<double> dts = {0.04, 0.02, 0.01}, errs;
  std::vector<double> ncoll;
  for (double dt : dts) {
    const Gauss G(2, P.im.data(), nullptr, dt * dt / 12.0, P.terms, &phi);
    Flow F(G, {0.5, 0.5}, {}, {}, 0, 1e-9);
    std::vector<double> y = P.y0, pm;
    const double H0 = G.energy(y.data());
    double emax = 0.0;
    const int nsteps = (int) std::lround(T / dt);
    for (int s = 0; s < nsteps; s++) {
      ASSERT_EQ(F.run(dt, y, pm), Flow::DONE) << "dt " << dt << " step " << s;
      emax = std::max(emax, std::fabs(G.energy(y.data()) - H0));
    }
    // a step without a contact is one Gauss solve; the solves beyond one a
    // step are the contacts' (their time searches' trials, and a solve of
    // the whole sub-step where the predictor's parabola has no contact)
    const double per_contact = (G.tally.solves - nsteps) / F.stats.pair;
    std::printf("dt %.3f: %g contacts, max |H~ - H~0| %.3e; Newton %.2f per solve (max %g), "
                "%.2f solves per sub-step, %.2f trial steps and %.2f solves more per contact\n",
                dt, F.stats.pair, emax, G.tally.iterations / G.tally.solves, G.tally.maxit,
                G.tally.solves / F.stats.substeps, F.stats.refine / F.stats.pair, per_contact);
    // the contact time by Halley steps on the flow's g', g'', from the time
    // on the predictor's parabola: 2.56 trials at dt 0.01, 2.78 at 0.02, and
    // no solve of the whole sub-step (from the solved step's parabola: 2.0
    // and 2.67 trials and that solve, 3.0 and 3.67 solves more per contact;
    // the secant from the second trial took 3.0, 3.1 trials at dt 0.02,
    // Newton on the end state's g', gaining ~300x a trial, four)
    if (dt < 0.03) EXPECT_LE(per_contact, dt < 0.015 ? 2.75 : 3.0) << "dt " << dt;
    errs.push_back(emax);
    ncoll.push_back(F.stats.pair);
    EXPECT_LE(G.tally.maxit, 8.0);
  }
  const double order = std::log(errs.front() / errs.back()) / std::log(dts.front() / dts.back());
  std::printf("order of H~'s error: %.2f\n", order);
  EXPECT_GE(order, 3.6);
  EXPECT_GE(ncoll.back(), 5.0);
  for (double c : ncoll) EXPECT_NEAR(c, ncoll.back(), 1.0);
}

// a contact on the predictor's parabola (ClusterGauss::predict()) that the
// flow does not reach: a sphere falling onto a wall, braked by a repulsive
// centre beyond it (0.5 / r^4), so that it turns 4e-6 short of the wall on
// the solved step's parabola, where the predictor's parabola, 1.3e-5 lower,
// overlaps the wall. The contact-time search then finds a positive gap at
// the step's end and the whole step is solved: no impulse, the end state of
// one Gauss step (where a graze on the solved step's parabola is taken as
// a contact at that parabola's time)
TEST(ClusterFlow, ContactOnlyOnThePredictorsParabolaIsNone)
{
  const double h = 0.05, R = 0.5, im[1] = {1.0};
  const std::vector<ClusterTerm> terms = {term(0, -1, 2, {0.0, 0.0, -0.2})};
  ClusterNewtonOptions opt;
  opt.keep = true;
  FlowWall W;
  W.dim = 2;
  W.coord = 0.0;
  W.sign = 1.0;
  auto start = [&](double vz) { return std::vector<double>{0.0, 0.0, R + 0.05, 0.1, 0.0, vz}; };
  // the least gap of a parabola in z over [0, h] (sampled)
  auto least = [&](const std::vector<double> &y, const ClusterStepDetail &d) {
    double g = 1e300;
    for (int k = 0; k <= 20000; k++) {
      const double t = h * k / 20000.0;
      g = std::min(g, y[2] + d.vq[2] * t + 0.5 * d.aq[2] * t * t - R);
    }
    return g;
  };
  auto solved_least = [&](double vz) {
    const Gauss G(1, im, nullptr, h * h / 12.0, terms, &phi);
    const std::vector<double> y = start(vz);
    std::vector<double> y1(6);
    ClusterStepDetail d;
    G.step(y.data(), h, y1.data(), opt, &d);
    return least(y, d);
  };
  // the speed at which the solved step's parabola turns 4e-6 short of the
  // wall (it reaches the wall at -1.51, turns 2.3e-3 short at -1.16)
  double lo = -1.51, hi = -1.16;
  ASSERT_LT(solved_least(lo), 0.0);
  ASSERT_GT(solved_least(hi), 4e-6);
  for (int k = 0; k < 60; k++) {
    const double mid = 0.5 * (lo + hi);
    (solved_least(mid) > 4e-6 ? hi : lo) = mid;
  }
  const std::vector<double> y0 = start(hi);
  {
    const Gauss G(1, im, nullptr, h * h / 12.0, terms, &phi);
    ClusterStepDetail d;
    G.predict(y0.data(), h, opt, d);
    ASSERT_LT(least(y0, d), -5e-6) << "the predictor's parabola should reach the wall";
  }
  // the flow's own gap, the ends of Gauss steps of every length up to h
  double gmin = 1e300;
  for (int k = 1; k <= 200; k++) {
    const Gauss G(1, im, nullptr, h * h / 12.0, terms, &phi);
    std::vector<double> y1(6);
    G.step(y0.data(), h * k / 200.0, y1.data(), opt);
    gmin = std::min(gmin, y1[2] - R);
  }
  ASSERT_GT(gmin, 2e-6);
  const Gauss G(1, im, nullptr, h * h / 12.0, terms, &phi);
  Flow F(G, {R}, {}, {W}, 0, 1e-9);
  std::vector<double> y = y0, pm;
  ASSERT_EQ(F.run(h, y, pm), Flow::DONE);
  EXPECT_EQ(F.stats.wall, 0.0);
  EXPECT_TRUE(F.kicks().empty());
  const Gauss G1(1, im, nullptr, h * h / 12.0, terms, &phi);
  std::vector<double> y1(6);
  G1.step(y0.data(), h, y1.data(), opt);
  for (int d = 0; d < 6; d++) EXPECT_NEAR(y[d], y1[d], 1e-12 * (1.0 + std::fabs(y1[d]))) << d;
}

TEST(ClusterFlow, PartnersTakeTheMomentumTheMembersLose)
{
  Pair P;
  // member 0 tied to a static partner (index 0), member 1 repelled by
  // another (index 1)
  P.terms.push_back(term(0, -1, 1, {-1.0, 0.3, 0.1}, 0));
  P.terms.push_back(term(1, -1, 2, {2.6, -0.4, 0.2}, 1));
  const double dt = 0.02;
  const Gauss G(2, P.im.data(), nullptr, dt * dt / 12.0, P.terms, &phi);
  Flow F(G, {0.5, 0.5}, {}, {}, 2, 1e-9);
  std::vector<double> y = P.y0, pm;
  double p0[3];
  for (int d = 0; d < 3; d++) p0[d] = y[6 + d] / P.im[0] + y[9 + d] / P.im[1];
  for (int s = 0; s < 200; s++) ASSERT_EQ(F.run(dt, y, pm), Flow::DONE);
  EXPECT_GT(F.stats.pair, 0.0);
  double pmax = 0.0;
  for (double v : pm) pmax = std::max(pmax, std::fabs(v));
  EXPECT_GT(pmax, 0.1);
  for (int d = 0; d < 3; d++)
    EXPECT_NEAR(y[6 + d] / P.im[0] + y[9 + d] / P.im[1] + pm[d] + pm[3 + d], p0[d], 1e-11)
        << "dimension " << d;
}

TEST(ClusterFlow, StaticSphereInTheWayEndsTheFlow)
{
  Pair P;
  const Gauss G(2, P.im.data(), nullptr, 1e-4, P.terms, &phi);
  FlowStatic far, behind;
  far.x[1] = -3.0;
  behind.x[0] = -1.5;    // member 0 (at the origin) runs into it at vx = -4
  behind.x[1] = -0.1;
  Flow F(G, {0.5, 0.5}, {far, behind}, {}, 0, 1e-9);
  std::vector<double> y = P.y0, pm;
  y[6] = -4.0;
  EXPECT_EQ(F.run(0.5, y, pm), Flow::STATIC_HIT);
  EXPECT_EQ(F.hit_member, 0);
  EXPECT_EQ(F.hit_static, 1);
}

}    // namespace

// a flow object reused for another cluster (reset()) keeps its scratch
// (segments' rows, a step's stages): its run must give what a new object
// gives, bit for bit, with nothing of the last cluster's flow left in
TEST(ClusterFlow, ReusedObjectGivesTheNewObjectsFlowBitForBit)
{
  Pair P;
  P.terms.push_back(term(0, -1, 1, {-1.0, 0.3, 0.1}, 0));
  P.terms.push_back(term(1, -1, 2, {2.6, -0.4, 0.2}, 1));
  const double dt = 0.02;
  // the reused pair: first another flow (faster spheres, more contacts)
  Gauss G1(2, P.im.data(), nullptr, dt * dt / 12.0, P.terms, &phi);
  Flow F1(G1, {0.5, 0.5}, {}, {}, 2, 1e-9);
  std::vector<double> ya = P.y0, pma;
  for (int k = 6; k < 12; k++) ya[k] *= 1.7;
  for (int s = 0; s < 60; s++) ASSERT_EQ(F1.run(dt, ya, pma), Flow::DONE);
  ASSERT_GT(F1.stats.pair, 0.0);
  G1.reset(2, P.im.data(), nullptr, dt * dt / 12.0, &phi);
  F1.reset(2, 1e-9);
  // and a new one
  const Gauss G2(2, P.im.data(), nullptr, dt * dt / 12.0, P.terms, &phi);
  Flow F2(G2, {0.5, 0.5}, {}, {}, 2, 1e-9);
  std::vector<double> y1 = P.y0, y2 = P.y0, pm1, pm2;
  double kicks = 0.0;
  for (int s = 0; s < 100; s++) {
    ASSERT_EQ(F1.run(dt, y1, pm1), Flow::DONE);
    ASSERT_EQ(F2.run(dt, y2, pm2), Flow::DONE);
    ASSERT_EQ(y1, y2) << "step " << s;
    ASSERT_EQ(pm1, pm2) << "step " << s;
    ASSERT_EQ(F1.kicks().size(), F2.kicks().size()) << "step " << s;
    kicks += (double) F2.kicks().size();
    for (size_t k = 0; k < F2.kicks().size(); k++) {
      const FlowKick &k1 = F1.kicks()[k], &k2 = F2.kicks()[k];
      ASSERT_EQ(k1.i, k2.i);
      ASSERT_EQ(k1.j, k2.j);
      for (int d = 0; d < 3; d++) {
        ASSERT_EQ(k1.J[d], k2.J[d]);
        ASSERT_EQ(k1.dq[d], k2.dq[d]);
      }
    }
    const auto &S1 = F1.segments(), &S2 = F2.segments();
    ASSERT_EQ(S1.size(), S2.size());
    for (size_t a = 0; a < S2.size(); a++) {
      ASSERT_EQ(S1[a].size(), S2[a].size()) << "step " << s << " member " << a;
      for (size_t k = 0; k < S2[a].size(); k++) {
        EXPECT_EQ(S1[a][k].t0, S2[a][k].t0);
        EXPECT_EQ(S1[a][k].t1, S2[a][k].t1);
        for (int d = 0; d < 3; d++) {
          EXPECT_EQ(S1[a][k].q[d], S2[a][k].q[d]);
          EXPECT_EQ(S1[a][k].v[d], S2[a][k].v[d]);
          EXPECT_EQ(S1[a][k].a[d], S2[a][k].a[d]);
        }
      }
    }
  }
  EXPECT_GT(kicks, 0.0);    // (contacts within the compared steps)
}
