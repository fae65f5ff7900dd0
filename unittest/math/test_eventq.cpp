// Unit tests for src/HARDSPHERE/hs_eventq.h: free-flight contact times and
// the event calendar (indexed min-heap) of fix hardsphere/psa
// (Bond & Leimkuhler 2007, section 2.1).
//
// Expected values come from closed forms, the independent root isolation of
// hs_contact.h's first_contact() on the same (degree 2) gap polynomial, the
// geometry |dq + t dv| evaluated directly, and a brute-force linear scan for
// the heap.

#include "hs_eventq.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

using namespace HardSphere;

namespace {

constexpr double TOL = 1e-9;

double gap_at(const double *dq, const double *dv, double sigma, double t)
{
  double r2 = 0.0;
  for (int k = 0; k < 3; k++) {
    const double r = dq[k] + t * dv[k];
    r2 += r * r;
  }
  return std::sqrt(r2) - sigma;
}

}    // namespace

TEST(FreeFlightContact, HeadOnClosedForm)
{
  // centres 3 apart closing at speed 2, contact at distance 1: t = 1
  const double dq[3] = {3.0, 0.0, 0.0}, dv[3] = {-2.0, 0.0, 0.0};
  Contact c = free_flight_pair_contact(dq, dv, 1.0, 10.0, TOL);
  EXPECT_EQ(c.status, CONTACT);
  EXPECT_DOUBLE_EQ(c.t, 1.0);
  // beyond tmax: none
  c = free_flight_pair_contact(dq, dv, 1.0, 0.999, TOL);
  EXPECT_EQ(c.status, NO_CONTACT);
}

TEST(FreeFlightContact, ObliqueClosedForm)
{
  // impact parameter b = 0.6 < sigma = 1: contact when the along-line
  // separation is sqrt(1 - 0.36) = 0.8, i.e. after (5 - 0.8)/1.5 = 2.8
  const double dq[3] = {5.0, 0.6, 0.0}, dv[3] = {-1.5, 0.0, 0.0};
  Contact c = free_flight_pair_contact(dq, dv, 1.0, 10.0, TOL);
  ASSERT_EQ(c.status, CONTACT);
  EXPECT_NEAR(c.t, 2.8, 1e-15);
  // impact parameter above sigma: a miss
  const double dq2[3] = {5.0, 1.0000001, 0.0};
  EXPECT_EQ(free_flight_pair_contact(dq2, dv, 1.0, 10.0, TOL).status, NO_CONTACT);
}

TEST(FreeFlightContact, TouchingOverlapSeparatingParallel)
{
  const double dv_in[3] = {-1.0, 0.0, 0.0}, dv_out[3] = {1.0, 0.0, 0.0}, dv0[3] = {0, 0, 0};
  const double touch[3] = {1.0, 0.0, 0.0}, over[3] = {0.9, 0.0, 0.0}, far[3] = {2.0, 0, 0};
  EXPECT_EQ(free_flight_pair_contact(touch, dv_in, 1.0, 1.0, TOL).status, CONTACT_NOW);
  EXPECT_EQ(free_flight_pair_contact(touch, dv_out, 1.0, 1.0, TOL).status, NO_CONTACT);
  EXPECT_EQ(free_flight_pair_contact(over, dv_out, 1.0, 1.0, TOL).status, OVERLAP);
  EXPECT_EQ(free_flight_pair_contact(far, dv0, 1.0, 1.0, TOL).status, NO_CONTACT);
  // sliding past tangentially while touching: no contact
  const double slide[3] = {0.0, 1.0, 0.0};
  EXPECT_EQ(free_flight_pair_contact(touch, slide, 1.0, 1.0, TOL).status, NO_CONTACT);
  // touching within round-off, slightly inside, approaching: contact now
  const double in_tol[3] = {1.0 - 1e-12, 0.0, 0.0};
  EXPECT_EQ(free_flight_pair_contact(in_tol, dv_in, 1.0, 1.0, TOL).status, CONTACT_NOW);
}

TEST(FreeFlightContact, MatchesRootIsolationAndGeometry)
{
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  int ncontact = 0, nnone = 0;
  for (int trial = 0; trial < 20000; trial++) {
    double dq[3], dv[3];
    for (int k = 0; k < 3; k++) {
      dq[k] = 2.0 * U(rng);
      dv[k] = 3.0 * U(rng);
    }
    const double sigma = 0.5 + 0.5 * (U(rng) + 1.0);
    const double tmax = 0.5 + (U(rng) + 1.0);
    double r2 = dq[0] * dq[0] + dq[1] * dq[1] + dq[2] * dq[2];
    if (r2 < sigma * sigma * 1.0001) continue;    // only clearly separated starts here
    const double tol = TOL * sigma * sigma;
    Contact c = free_flight_pair_contact(dq, dv, sigma, tmax, tol);
    // the same gap polynomial through hs_contact.h's generic root isolation
    const double da[3] = {0, 0, 0};
    double poly[5];
    pair_gap_poly(dq, dv, da, sigma, poly);
    Contact ref = first_contact(poly, 2, tmax, tol);
    ASSERT_EQ(c.status, ref.status) << "trial " << trial;
    if (c.status == CONTACT) {
      ncontact++;
      EXPECT_NEAR(c.t, ref.t, 1e-12 * (1.0 + ref.t)) << "trial " << trial;
      // geometry: at contact the distance is sigma, before it larger
      EXPECT_NEAR(gap_at(dq, dv, sigma, c.t), 0.0, 1e-12) << "trial " << trial;
      for (int s = 0; s < 50; s++) EXPECT_GT(gap_at(dq, dv, sigma, c.t * s / 50.0), -1e-12);
    } else {
      nnone++;
      for (int s = 0; s <= 200; s++) EXPECT_GT(gap_at(dq, dv, sigma, tmax * s / 200.0), -1e-12);
    }
  }
  // the sample exercised both outcomes
  EXPECT_GT(ncontact, 1000);
  EXPECT_GT(nnone, 1000);
}

TEST(FreeFlightContact, NearTangentIsAccurate)
{
  // impact parameter p = 1 - 1e-8 (grazing): dt/dp = p / sqrt(1 - p^2) ~ 7e3,
  // so round-off in p alone moves t by ~1e-12 (1e-13 relative); b^2 - a c0
  // would lose ~2 more digits (here 6e-12)
  const double p = 1.0 - 1e-8;
  const double dq[3] = {10.0, p, 0.0}, dv[3] = {-1.0, 0.0, 0.0};
  Contact c = free_flight_pair_contact(dq, dv, 1.0, 100.0, TOL);
  ASSERT_EQ(c.status, CONTACT);
  const double exact = 10.0 - std::sqrt((1.0 - p) * (1.0 + p));
  EXPECT_NEAR(c.t, exact, 2e-13 * exact);
}

TEST(FreeFlightWallContact, Cases)
{
  Contact c = free_flight_wall_contact(2.0, -0.5, 10.0, TOL);
  EXPECT_EQ(c.status, CONTACT);
  EXPECT_DOUBLE_EQ(c.t, 4.0);
  EXPECT_EQ(free_flight_wall_contact(2.0, -0.5, 3.9, TOL).status, NO_CONTACT);
  EXPECT_EQ(free_flight_wall_contact(2.0, 0.5, 10.0, TOL).status, NO_CONTACT);
  EXPECT_EQ(free_flight_wall_contact(2.0, 0.0, 10.0, TOL).status, NO_CONTACT);
  EXPECT_EQ(free_flight_wall_contact(0.0, -1.0, 10.0, TOL).status, CONTACT_NOW);
  EXPECT_EQ(free_flight_wall_contact(1e-12, 1.0, 10.0, TOL).status, NO_CONTACT);
  EXPECT_EQ(free_flight_wall_contact(-1e-3, 1.0, 10.0, TOL).status, OVERLAP);
  // against first_contact on the same linear gap
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  for (int trial = 0; trial < 5000; trial++) {
    const double d = 0.01 + std::fabs(U(rng)), vn = U(rng), tmax = 1.0 + U(rng);
    double poly[3];
    wall_gap_poly(d, vn, 0.0, poly);
    Contact ref = first_contact(poly, 2, tmax, TOL);
    Contact got = free_flight_wall_contact(d, vn, tmax, TOL);
    ASSERT_EQ(got.status, ref.status);
    if (got.status == CONTACT) EXPECT_NEAR(got.t, ref.t, 1e-13 * (1 + ref.t));
  }
}

TEST(EventHeap, RandomOperationsMatchLinearScan)
{
  const int n = 300;
  EventHeap h;
  h.reset(n);
  std::vector<double> ref(n, -1.0);    // -1: absent
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::uniform_int_distribution<int> K(0, n - 1);
  for (int op = 0; op < 200000; op++) {
    const double r = U(rng);
    const int k = K(rng);
    if (r < 0.6) {
      // coarse keys make ties frequent
      const double t = std::floor(U(rng) * 50.0) / 50.0;
      h.set(k, t);
      ref[k] = t;
    } else if (r < 0.8) {
      h.remove(k);
      ref[k] = -1.0;
    } else if (!h.empty()) {
      // pop the top
      const int top = h.top();
      h.remove(top);
      ref[top] = -1.0;
    }
    // invariant: the top has the minimal key, sizes and membership agree
    int count = 0;
    double tmin = std::numeric_limits<double>::infinity();
    for (int s = 0; s < n; s++)
      if (ref[s] >= 0.0) {
        count++;
        tmin = std::min(tmin, ref[s]);
        ASSERT_TRUE(h.contains(s));
        ASSERT_EQ(h.key(s), ref[s]);
      } else
        ASSERT_FALSE(h.contains(s));
    ASSERT_EQ(h.size(), count);
    if (count) {
      ASSERT_EQ(h.top_key(), tmin) << "op " << op;
      ASSERT_EQ(ref[h.top()], tmin);
    }
  }
}

TEST(EventHeap, PopsInSortedOrder)
{
  const int n = 1000;
  EventHeap h;
  h.reset(n);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::vector<double> keys(n);
  for (int k = 0; k < n; k++) {
    keys[k] = U(rng);
    h.set(k, 2.0);        // insert high, then decrease
    h.set(k, keys[k]);
  }
  std::sort(keys.begin(), keys.end());
  for (int k = 0; k < n; k++) {
    ASSERT_FALSE(h.empty());
    EXPECT_EQ(h.top_key(), keys[k]);
    h.remove(h.top());
  }
  EXPECT_TRUE(h.empty());
  // reset empties it again
  h.set(5, 1.0);
  h.reset(10);
  EXPECT_TRUE(h.empty());
  EXPECT_FALSE(h.contains(5));
}
