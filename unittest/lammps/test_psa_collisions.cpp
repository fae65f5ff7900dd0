// fix hardsphere/psa: collisions in a line of spheres and between walls,
// several within one step, where the primitive splitting algorithm (section
// 2.1) is exact event-driven free flight: the outcome is the closed form, to
// round-off. (The two-sphere cases of psa and cva are in
// test_two_body_collisions.cpp.)

#include "hs_two_body.h"

using hs_two_body::f17;

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
  for (double xx : x0) s += "create_atoms 1 single " + f17(xx) + " 0 0 units box\n";
  s += "mass 1 1.0\n";
  for (size_t k = 0; k < v0.size(); k++)
    s += "set atom " + std::to_string(k + 1) + " vx " + f17(v0[k]) + "\n";
  s += "neighbor " + f17(skin) + " bin\ncomm_modify cutoff " + f17(1.0 + 2 * skin + 0.1) + "\n";
  s += "timestep " + f17(dt) + "\nfix hs all hardsphere/psa diameter 1.0" + extra_fix + "\n";
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
