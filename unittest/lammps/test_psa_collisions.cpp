// fix hardsphere/psa: two-sphere collisions with no smooth forces, where the
// primitive splitting algorithm (section 2.1) is exact event-driven free
// flight: the outcome is the closed form, to round-off.
//
// Expected outcomes are computed here independently of the fix: free flight
// to the analytic contact time (root of |dq + t dv| = sigma), the elastic
// impulse along the line of centres at contact, free flight to the end of
// the run.

#include "hs_test_main.h"

#include "atom.h"
#include "library.h"

#include <array>
#include <cmath>
#include <sstream>

namespace {

using Vec = std::array<double, 3>;

struct Body {
  Vec x, v;
  double m, r;
};

double dot(const Vec &a, const Vec &b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// exact outcome of a run of length T for two free spheres that collide once;
// period[k] > 0: periodic in k with that length (minimum image)
void exact_two_body(Body &a, Body &b, double T, const Vec &period, double &tc)
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

std::string fmt(double v)
{
  char buf[64];
  snprintf(buf, sizeof(buf), "%.17g", v);
  return buf;
}

std::string vec(const Vec &a)
{
  return fmt(a[0]) + " " + fmt(a[1]) + " " + fmt(a[2]);
}

// Build two spheres, run nsteps of dt and compare with the exact outcome.
// sphere_style: atom_style sphere with per-atom radius/rmass (no diameter
// keyword); otherwise atom_style atomic with per-type mass and diameter
// 2*a.r (a.r == b.r required).
void check_two_body(Body a, Body b, double dt, int nsteps, bool sphere_style, bool periodic,
                    double L = 20.0)
{
  HSLammps h;
  std::string lo = periodic ? "0" : fmt(-0.5 * L), hi = periodic ? fmt(L) : fmt(0.5 * L);
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
    s += "set atom 1 diameter " + fmt(2 * a.r) + "\n";
    s += "set atom 2 diameter " + fmt(2 * b.r) + "\n";
    s += "set atom 1 mass " + fmt(a.m) + "\n";
    s += "set atom 2 mass " + fmt(b.m) + "\n";
  } else {
    s += "mass 1 " + fmt(a.m) + "\nmass 2 " + fmt(b.m) + "\n";
  }
  s += "group g1 id 1\ngroup g2 id 2\n";
  s += "velocity g1 set " + vec(a.v) + " units box\n";
  s += "velocity g2 set " + vec(b.v) + " units box\n";
  s += "comm_modify cutoff 3.0\n";
  s += "timestep " + fmt(dt) + "\n";
  if (sphere_style)
    s += "fix hs all hardsphere/psa\n";
  else
    s += "fix hs all hardsphere/psa diameter " + fmt(2 * a.r) + "\n";
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
    EXPECT_NEAR(pdiff(x[k], a.x[k], k), 0.0, 1e-12) << "x1[" << k << "] tc=" << tc;
    EXPECT_NEAR(pdiff(x[3 + k], b.x[k], k), 0.0, 1e-12) << "x2[" << k << "]";
    EXPECT_NEAR(v[k], a.v[k], 1e-12) << "v1[" << k << "]";
    EXPECT_NEAR(v[3 + k], b.v[k], 1e-12) << "v2[" << k << "]";
  }
  EXPECT_EQ(h.fix_vector("hs", 0), 1.0);    // all collisions
  EXPECT_EQ(h.fix_vector("hs", 1), 1.0);    // sphere-sphere
  EXPECT_EQ(h.fix_vector("hs", 2), 0.0);    // wall
  EXPECT_EQ(h.fix_vector("hs", 3), 1.0);    // steps with a collision
  EXPECT_NEAR(h.thermo("ke"), ke0, 1e-13 * ke0);
}

}    // namespace

TEST(PSACollision, HeadOnUnequalMasses)
{
  // 1-D: v1' = ((m1-m2) v1 + 2 m2 v2)/(m1+m2), v2' = ((m2-m1) v2 + 2 m1 v1)/(m1+m2)
  const double m1 = 1.0, m2 = 3.0, v1 = 1.0, v2 = -0.5;
  const double v1p = ((m1 - m2) * v1 + 2 * m2 * v2) / (m1 + m2);    // -1.25
  const double v2p = ((m2 - m1) * v2 + 2 * m1 * v1) / (m1 + m2);    //  0.25
  // contact at |x2-x1| = 1 after (2-1)/1.5 = 2/3 time units; run to t = 1.0
  const double tc = 1.0 / 1.5, T = 1.0;
  Body a{{-1.0, 0.0, 0.0}, {v1, 0.0, 0.0}, m1, 0.5};
  Body b{{1.0, 0.0, 0.0}, {v2, 0.0, 0.0}, m2, 0.5};
  // the closed form for this case, independently of the generic helper
  const double x1 = -1.0 + v1 * tc + v1p * (T - tc), x2 = 1.0 + v2 * tc + v2p * (T - tc);
  HSLammps h;
  h.lines(R"(
units lj
atom_style atomic
boundary f f f
atom_modify map array
region box block -10 10 -10 10 -10 10 units box
create_box 2 box
create_atoms 1 single -1 0 0 units box
create_atoms 2 single 1 0 0 units box
mass 1 1.0
mass 2 3.0
group g1 id 1
group g2 id 2
velocity g1 set 1.0 0 0 units box
velocity g2 set -0.5 0 0 units box
comm_modify cutoff 3.0
run 0
timestep 0.01
fix hs all hardsphere/psa diameter 1.0
run 100
)");
  std::vector<double> x(6), v(6);
  lammps_gather_atoms(h.lmp, (char *) "x", 1, 3, x.data());
  lammps_gather_atoms(h.lmp, (char *) "v", 1, 3, v.data());
  EXPECT_NEAR(v[0], v1p, 1e-12);
  EXPECT_NEAR(v[3], v2p, 1e-12);
  EXPECT_NEAR(x[0], x1, 1e-12);
  EXPECT_NEAR(x[3], x2, 1e-12);
  for (int k : {1, 2, 4, 5}) {
    EXPECT_EQ(x[k], 0.0);
    EXPECT_EQ(v[k], 0.0);
  }
  EXPECT_EQ(h.fix_vector("hs", 1), 1.0);
  // and the generic helper agrees with the closed form
  check_two_body(a, b, 0.01, 100, false, false);
}

TEST(PSACollision, Oblique3D)
{
  Body a{{-1.0, 0.2, -0.1}, {0.9, 0.05, 0.1}, 1.0, 0.5};
  Body b{{0.8, -0.2, 0.25}, {-0.6, 0.15, -0.05}, 2.5, 0.5};
  check_two_body(a, b, 0.01, 200, false, false);
}

TEST(PSACollision, ObliqueGrazingTimestepNotMultiple)
{
  // a contact time that is no multiple of dt and a large impact parameter
  Body a{{-1.5, 0.0, 0.0}, {1.0, 0.0, 0.0}, 1.0, 0.5};
  Body b{{0.5, 0.93, 0.0}, {0.0, 0.0, 0.0}, 1.0, 0.5};
  check_two_body(a, b, 0.0137, 200, false, false);
}

TEST(PSACollision, PerAtomRadiusAndMass)
{
  // atom_style sphere: radii 0.4 and 0.7 (contact distance 1.1), rmass 2 and 0.5
  Body a{{-1.2, 0.1, 0.0}, {1.0, 0.0, 0.05}, 2.0, 0.4};
  Body b{{0.6, -0.3, 0.1}, {-0.4, 0.1, 0.0}, 0.5, 0.7};
  check_two_body(a, b, 0.01, 150, true, false);
}

TEST(PSACollision, AcrossPeriodicBoundary)
{
  // box [0,10)^3 periodic; the spheres approach each other through the x faces
  Body a{{0.6, 5.0, 5.0}, {-1.0, 0.0, 0.0}, 1.0, 0.5};
  Body b{{9.4, 5.3, 5.0}, {0.5, 0.0, 0.0}, 2.0, 0.5};
  check_two_body(a, b, 0.01, 100, false, true, 10.0);
}

TEST(PSACollision, AcrossPeriodicBoundaryPerAtomRadius)
{
  Body a{{5.0, 0.3, 5.0}, {0.0, -1.0, 0.2}, 1.5, 0.6};
  Body b{{5.2, 9.3, 5.1}, {0.1, 0.7, 0.0}, 0.7, 0.3};
  check_two_body(a, b, 0.01, 100, true, true, 10.0);
}

namespace {

// a small line-up of spheres of diameter 1, unit mass, along x; no forces
struct LineRun {
  std::vector<double> x, v;
  double all = -1, pair = -1, wall = -1, steps = -1, fevals = -1;
};

LineRun run_line(const std::vector<double> &x0, const std::vector<double> &v0, double dt,
                 int nsteps, const std::string &extra_fix, double skin)
{
  HSLammps h;
  std::string s = "units lj\natom_style atomic\nboundary f f f\natom_modify map array\n"
                  "region box block -10 10 -10 10 -10 10 units box\ncreate_box 1 box\n";
  for (double xx : x0) s += "create_atoms 1 single " + fmt(xx) + " 0 0 units box\n";
  s += "mass 1 1.0\n";
  for (size_t k = 0; k < v0.size(); k++)
    s += "set atom " + std::to_string(k + 1) + " vx " + fmt(v0[k]) + "\n";
  s += "neighbor " + fmt(skin) + " bin\ncomm_modify cutoff " + fmt(1.0 + 2 * skin + 0.1) + "\n";
  s += "timestep " + fmt(dt) + "\nfix hs all hardsphere/psa diameter 1.0" + extra_fix + "\n";
  s += "run " + std::to_string(nsteps) + "\n";
  h.lines(s);
  LineRun r;
  const int n = (int) x0.size();
  std::vector<double> x(3 * n), v(3 * n);
  lammps_gather_atoms(h.lmp, (char *) "x", 1, 3, x.data());
  lammps_gather_atoms(h.lmp, (char *) "v", 1, 3, v.data());
  for (int k = 0; k < n; k++) {
    r.x.push_back(x[3 * k]);
    r.v.push_back(v[3 * k]);
    EXPECT_EQ(x[3 * k + 1], 0.0);
    EXPECT_EQ(v[3 * k + 2], 0.0);
  }
  r.all = h.fix_vector("hs", 0);
  r.pair = h.fix_vector("hs", 1);
  r.wall = h.fix_vector("hs", 2);
  r.steps = h.fix_vector("hs", 3);
  r.fevals = h.fix_vector("hs", 4);
  return r;
}

}    // namespace

TEST(PSACollision, WallBounceClosedForm)
{
  // centre at 0 moving at -1 toward the plane x = -2 (radius 0.5): contact at
  // t = 1.5 at x = -1.5, then back at +1 to x(T) = -1.5 + (T - 1.5); dt is
  // chosen so the contact falls inside a step
  const double dt = 0.2273;
  const int n = 11;
  const double T = dt * n;
  LineRun r = run_line({0.0}, {-1.0}, dt, n, " wall xlo -2.0", 0.3);
  EXPECT_NEAR(r.x[0], -1.5 + (T - 1.5), 1e-13);
  EXPECT_EQ(r.v[0], 1.0);
  EXPECT_EQ(r.wall, 1.0);
  EXPECT_EQ(r.pair, 0.0);
  EXPECT_EQ(r.steps, 1.0);
  EXPECT_EQ(r.fevals, 0.0);    // PSA never re-evaluates forces
}

TEST(PSACollision, ChainOfSimultaneousCollisionsInOneStep)
{
  // A (v = 1) hits B at t = 1; B touches C, which touches D: momentum passes
  // down the line within the same instant (three collisions in one step) and
  // D leaves at v = 1 while A, B, C rest (equal masses). One step of 1.5.
  LineRun r = run_line({-2.0, 0.0, 1.0, 2.0}, {1.0, 0.0, 0.0, 0.0}, 1.5, 1, "", 1.6);
  EXPECT_NEAR(r.x[0], -1.0, 1e-14);
  EXPECT_NEAR(r.x[1], 0.0, 1e-14);
  EXPECT_NEAR(r.x[2], 1.0, 1e-14);
  EXPECT_NEAR(r.x[3], 2.5, 1e-14);
  EXPECT_NEAR(r.v[0], 0.0, 1e-15);
  EXPECT_NEAR(r.v[1], 0.0, 1e-15);
  EXPECT_NEAR(r.v[2], 0.0, 1e-15);
  EXPECT_NEAR(r.v[3], 1.0, 1e-15);
  EXPECT_EQ(r.pair, 3.0);
  EXPECT_EQ(r.steps, 1.0);
}

TEST(PSACollision, RepeatedCollisionsBetweenWallsInOneStep)
{
  // two spheres touching the walls x = -1.5 and 1.5 (centres at -1 and 1),
  // moving inward at unit speed: they meet (centres at -/+0.5) at t = 0.5,
  // 1.5, 2.5, 3.5 and bounce off the walls at t = 1, 2, 3, 4. One single step
  // of 4.25 (skin 5) must do all 4 pair and 8 wall collisions.
  LineRun r = run_line({-1.0, 1.0}, {1.0, -1.0}, 4.25, 1, " wall xlo -1.5 wall xhi 1.5", 5.0);
  EXPECT_NEAR(r.x[0], -1.0 + 0.25, 1e-13);
  EXPECT_NEAR(r.x[1], 1.0 - 0.25, 1e-13);
  EXPECT_EQ(r.v[0], 1.0);
  EXPECT_EQ(r.v[1], -1.0);
  EXPECT_EQ(r.pair, 4.0);
  EXPECT_EQ(r.wall, 8.0);
  EXPECT_EQ(r.steps, 1.0);
}
