/* -*- c++ -*- ----------------------------------------------------------
   Two spheres, no smooth forces, one collision: the exact outcome computed
   independently of the fix (free flight to the analytic contact time, the
   root of |dq + t dv| = sigma; the elastic impulse along the line of centres
   at contact; free flight to the end of the run), and a check of a
   hardsphere fix's run against it. Include after hs_test_main.h.
------------------------------------------------------------------------- */

#ifndef HS_TWO_BODY_H
#define HS_TWO_BODY_H

#include "hs_test_main.h"

#include "atom.h"
#include "library.h"

#include <array>
#include <cmath>
#include <functional>
#include <string>

namespace hs_two_body {

using Vec = std::array<double, 3>;

struct Body {
  Vec x, v;
  double m, r;
};

inline double dot(const Vec &a, const Vec &b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// exact outcome of a run of length T for two free spheres that collide once;
// period[k] > 0: periodic in k with that length (minimum image)
inline void exact_two_body(Body &a, Body &b, double T, const Vec &period, double &tc)
{
  Vec dq, dv;
  for (int k = 0; k < 3; k++) {
    dq[k] = a.x[k] - b.x[k];
    if (period[k] > 0.0) dq[k] -= period[k] * std::round(dq[k] / period[k]);
    dv[k] = a.v[k] - b.v[k];
  }
  const double sigma = a.r + b.r;
  const double A = dot(dv, dv), B = dot(dq, dv), C = dot(dq, dq) - sigma * sigma;
  const double disc = B * B - A * C;
  ASSERT_GT(C, 0.0);
  ASSERT_LT(B, 0.0);
  ASSERT_GT(disc, 0.0);
  // smaller root, in the cancellation-free form
  tc = C / (-B + std::sqrt(disc));
  ASSERT_GT(tc, 0.0);
  ASSERT_LT(tc, T);
  Vec n;
  for (int k = 0; k < 3; k++) n[k] = (dq[k] + tc * dv[k]) / sigma;
  const double un = dot(dv, n);
  const double mu = a.m * b.m / (a.m + b.m);
  for (int k = 0; k < 3; k++) {
    const double J = -2.0 * mu * un * n[k];
    a.x[k] += tc * a.v[k];
    b.x[k] += tc * b.v[k];
    a.v[k] += J / a.m;
    b.v[k] -= J / b.m;
    a.x[k] += (T - tc) * a.v[k];
    b.x[k] += (T - tc) * b.v[k];
    if (period[k] > 0.0) {
      // wrap into [0, L) like LAMMPS (box starts at 0 in these tests)
      a.x[k] -= period[k] * std::floor(a.x[k] / period[k]);
      b.x[k] -= period[k] * std::floor(b.x[k] / period[k]);
    }
  }
}

inline std::string f17(double v)
{
  char buf[64];
  snprintf(buf, sizeof(buf), "%.17g", v);
  return buf;
}

inline std::string vec(const Vec &a)
{
  return f17(a[0]) + " " + f17(a[1]) + " " + f17(a[2]);
}

// Build two spheres, run nsteps of dt with fix hardsphere/<method> and
// compare with the exact outcome (positions to xtol, velocities to 1e-12,
// kinetic energy to 1e-13 relative, one pair collision in one step);
// extra_checks(h) then tests the method's own counters.
// sphere_style: atom_style sphere with per-atom radius/rmass (no diameter
// keyword); otherwise atom_style atomic with per-type mass and diameter
// 2*a.r (a.r == b.r required).
inline void check_two_body(const std::string &method, Body a, Body b, double dt, int nsteps,
                    bool sphere_style, bool periodic, double L = 20.0, double xtol = 1e-12,
                    const std::function<void(HSLammps &)> &extra_checks = {})
{
  HSLammps h;
  std::string lo = periodic ? "0" : f17(-0.5 * L), hi = periodic ? f17(L) : f17(0.5 * L);
  std::string s = "units lj\n";
  s += sphere_style ? "atom_style sphere\n" : "atom_style atomic\n";
  s += periodic ? "boundary p p p\n" : "boundary f f f\n";
  s += "atom_modify map array\n";
  s += "region box block " + lo + " " + hi + " " + lo + " " + hi + " " + lo + " " + hi +
      " units box\n";
  s += "create_box 2 box\n";
  s += "create_atoms 1 single " + vec(a.x) + " units box\n";
  s += "create_atoms 2 single " + vec(b.x) + " units box\n";
  if (sphere_style) {
    s += "set atom 1 diameter " + f17(2 * a.r) + "\n";
    s += "set atom 2 diameter " + f17(2 * b.r) + "\n";
    s += "set atom 1 mass " + f17(a.m) + "\n";
    s += "set atom 2 mass " + f17(b.m) + "\n";
  } else {
    s += "mass 1 " + f17(a.m) + "\nmass 2 " + f17(b.m) + "\n";
  }
  s += "group g1 id 1\ngroup g2 id 2\n";
  s += "velocity g1 set " + vec(a.v) + " units box\n";
  s += "velocity g2 set " + vec(b.v) + " units box\n";
  s += "comm_modify cutoff 3.0\n";
  s += "timestep " + f17(dt) + "\n";
  if (sphere_style)
    s += "fix hs all hardsphere/" + method + "\n";
  else
    s += "fix hs all hardsphere/" + method + " diameter " + f17(2 * a.r) + "\n";
  s += "thermo_style custom step ke\nthermo_modify norm no\n";
  s += "run " + std::to_string(nsteps) + "\n";
  if (getenv("HS_TEST_VERBOSE")) fprintf(stderr, "%s", s.c_str());
  h.lines(s);

  const double T = dt * nsteps;
  double tc = 0.0;
  const Vec period = periodic ? Vec{L, L, L} : Vec{0, 0, 0};
  const double ke0 = 0.5 * a.m * dot(a.v, a.v) + 0.5 * b.m * dot(b.v, b.v);
  exact_two_body(a, b, T, period, tc);
  if (::testing::Test::HasFatalFailure()) return;

  std::vector<double> x(6), v(6);
  lammps_gather_atoms(h.lmp, (char *) "x", 1, 3, x.data());
  lammps_gather_atoms(h.lmp, (char *) "v", 1, 3, v.data());
  // positions are wrapped only at reneighboring: compare modulo the period
  auto pdiff = [&](double u, double w, int k) {
    double d = u - w;
    if (period[k] > 0.0) d -= period[k] * std::round(d / period[k]);
    return d;
  };
  for (int k = 0; k < 3; k++) {
    EXPECT_NEAR(pdiff(x[k], a.x[k], k), 0.0, xtol) << "x1[" << k << "] tc=" << tc;
    EXPECT_NEAR(pdiff(x[3 + k], b.x[k], k), 0.0, xtol) << "x2[" << k << "]";
    EXPECT_NEAR(v[k], a.v[k], 1e-12) << "v1[" << k << "]";
    EXPECT_NEAR(v[3 + k], b.v[k], 1e-12) << "v2[" << k << "]";
  }
  EXPECT_EQ(h.fix_vector("hs", 0), 1.0);    // all collisions
  EXPECT_EQ(h.fix_vector("hs", 1), 1.0);    // sphere-sphere
  EXPECT_EQ(h.fix_vector("hs", 2), 0.0);    // wall
  EXPECT_EQ(h.fix_vector("hs", 3), 1.0);    // steps with a collision
  EXPECT_NEAR(h.thermo("ke"), ke0, 1e-13 * ke0);
  if (extra_checks) extra_checks(h);
}

}    // namespace hs_two_body

#endif
