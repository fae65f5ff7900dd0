// fix hardsphere/mcva where the answer is known:
// - a run in which no contact is predicted is the Verlet method (section
//   3.1: "When there is no collision, the method is simply the standard
//   Verlet method"): bit for bit fix nve;
// - with no smooth forces H~ = H, the Gauss flow is exact free flight and
//   alpha-hat is the elastic alpha: two-sphere collisions must match the
//   analytic outcome (free flight to the root of |dq + t dv| = sigma,
//   elastic impulse, free flight) to round-off, also across periodic
//   boundaries and with per-atom radius and mass.

#include "hs_test_main.h"

#include "atom.h"
#include "library.h"

#include <array>
#include <cmath>

namespace {

struct State {
  std::vector<double> x, v;
  std::vector<int> img;
  double ncoll = -1.0, nsub = -1.0, pe = 0.0, ke = 0.0;
};

State run_case(const std::string &setup, const std::string &fixline, const std::string &tail)
{
  HSLammps h;
  h.lines(setup);
  h.cmd(fixline);
  h.lines(tail);
  State s;
  const int n = (int) h.lmp->atom->natoms;
  s.x.resize(3 * n);
  s.v.resize(3 * n);
  s.img.resize(n);
  lammps_gather_atoms(h.lmp, (char *) "x", 1, 3, s.x.data());
  lammps_gather_atoms(h.lmp, (char *) "v", 1, 3, s.v.data());
  lammps_gather_atoms(h.lmp, (char *) "image", 0, 1, s.img.data());
  if (fixline.find("hardsphere") != std::string::npos) {
    s.ncoll = h.fix_vector("int", 0);
    s.nsub = h.fix_vector("int", 6);
  }
  s.pe = h.thermo("pe");
  s.ke = h.thermo("ke");
  return s;
}

void expect_identical(const State &a, const State &b)
{
  ASSERT_EQ(a.x.size(), b.x.size());
  int nx = 0, nv = 0, ni = 0;
  for (size_t k = 0; k < a.x.size(); k++) {
    if (a.x[k] != b.x[k] && nx++ < 5)
      ADD_FAILURE() << "x differs at " << k << ": " << a.x[k] << " vs " << b.x[k];
    if (a.v[k] != b.v[k] && nv++ < 5)
      ADD_FAILURE() << "v differs at " << k << ": " << a.v[k] << " vs " << b.v[k];
  }
  for (size_t k = 0; k < a.img.size(); k++)
    if (a.img[k] != b.img[k] && ni++ < 5) ADD_FAILURE() << "image differs at " << k;
  EXPECT_EQ(nx, 0);
  EXPECT_EQ(nv, 0);
  EXPECT_EQ(ni, 0);
  EXPECT_EQ(a.pe, b.pe);
  EXPECT_EQ(a.ke, b.ke);
}

}    // namespace

TEST(MCVANoCollision, LJFluidBitwiseFixNVE)
{
  const std::string setup = R"(
units lj
atom_style atomic
atom_modify map array
lattice fcc 0.8
region box block 0 4 0 4 0 4
create_box 1 box
create_atoms 1 box
mass 1 1.0
velocity all create 1.0 4928459 mom yes rot yes dist gaussian
pair_style lj/cut 2.5
pair_coeff 1 1 1.0 1.0 2.5
neighbor 0.3 bin
neigh_modify every 1 delay 0 check yes
timestep 0.005
thermo_style custom step pe ke
thermo_modify norm no
)";
  // hard cores of diameter 0.5 never touch in an LJ liquid at T ~ 1
  const std::string tail = "run 200\n";
  State nve = run_case(setup, "fix int all nve", tail);
  State hs = run_case(setup, "fix int all hardsphere/mcva diameter 0.5", tail);
  EXPECT_EQ(hs.ncoll, 0.0);
  EXPECT_EQ(hs.nsub, 0.0);
  expect_identical(nve, hs);
  EXPECT_GT(nve.ke, 0.0);
}

TEST(MCVANoCollision, BondedChainBitwiseFixNVE)
{
  const std::string setup = R"(
units lj
dimension 2
atom_style bond
atom_modify map array
boundary f f p
region box block -8 8 -8 8 -0.5 0.5
create_box 2 box bond/types 1 extra/bond/per/atom 2 extra/special/per/atom 6
create_atoms 1 single 0 0 0
create_atoms 2 single 1 0 0
create_atoms 2 single 2 0 0
create_atoms 2 single 3 0 0
create_atoms 2 single 4 0 0
create_atoms 2 single 5 0 0
mass * 1.0
bond_style harmonic
bond_coeff 1 0.5 1.0
create_bonds single/bond 1 1 2
create_bonds single/bond 1 2 3
create_bonds single/bond 1 3 4
create_bonds single/bond 1 4 5
create_bonds single/bond 1 5 6
group chain type 2
group s2 id 3
group s4 id 5
velocity s2 set 0.6 0.8 0
velocity s4 set -0.28 0.96 0
comm_modify cutoff 2.0
fix 2d all enforce2d
timestep 0.02
thermo_style custom step pe ke
thermo_modify norm no
)";
  const std::string tail = "run 500\n";
  State nve = run_case(setup, "fix int chain nve", tail);
  State hs = run_case(setup, "fix int chain hardsphere/mcva diameter 0.05", tail);
  EXPECT_EQ(hs.ncoll, 0.0);
  expect_identical(nve, hs);
  EXPECT_EQ(hs.x[0], 0.0);
  EXPECT_EQ(hs.x[1], 0.0);
}

// ---------------------------------------------------------------------- free flight

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

// exact outcome after T for two free spheres that collide once (box [0, L)^3
// if periodic: minimum image, wrapped like LAMMPS)
void exact_two_body(Body &a, Body &b, double T, double L, bool periodic)
{
  Vec dq, dv;
  for (int k = 0; k < 3; k++) {
    dq[k] = a.x[k] - b.x[k];
    if (periodic) dq[k] -= L * std::round(dq[k] / L);
    dv[k] = a.v[k] - b.v[k];
  }
  const double sigma = a.r + b.r;
  const double A = dot(dv, dv), B = dot(dq, dv), C = dot(dq, dq) - sigma * sigma;
  const double disc = B * B - A * C;
  ASSERT_GT(disc, 0.0);
  const double tc = C / (-B + std::sqrt(disc));
  ASSERT_GT(tc, 0.0);
  ASSERT_LT(tc, T);
  Vec n;
  for (int k = 0; k < 3; k++) n[k] = (dq[k] + tc * dv[k]) / sigma;
  const double un = dot(dv, n), mu = a.m * b.m / (a.m + b.m);
  for (int k = 0; k < 3; k++) {
    const double J = -2.0 * mu * un * n[k];
    a.x[k] += tc * a.v[k] + (T - tc) * (a.v[k] + J / a.m);
    b.x[k] += tc * b.v[k] + (T - tc) * (b.v[k] - J / b.m);
    a.v[k] += J / a.m;
    b.v[k] -= J / b.m;
  }
}

std::string f17(double v)
{
  char buf[64];
  snprintf(buf, sizeof(buf), "%.17g", v);
  return buf;
}

std::string vec(const Vec &a)
{
  return f17(a[0]) + " " + f17(a[1]) + " " + f17(a[2]);
}

void check_two_body(Body a, Body b, double dt, int nsteps, bool sphere_style, bool periodic)
{
  const double L = 20.0;
  HSLammps h;
  const std::string lo = periodic ? "0" : f17(-0.5 * L), hi = periodic ? f17(L) : f17(0.5 * L);
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
    s += "set atom 1 diameter " + f17(2 * a.r) + "\nset atom 2 diameter " + f17(2 * b.r) + "\n";
    s += "set atom 1 mass " + f17(a.m) + "\nset atom 2 mass " + f17(b.m) + "\n";
  } else
    s += "mass 1 " + f17(a.m) + "\nmass 2 " + f17(b.m) + "\n";
  s += "group g1 id 1\ngroup g2 id 2\n";
  s += "velocity g1 set " + vec(a.v) + " units box\nvelocity g2 set " + vec(b.v) + " units box\n";
  s += "comm_modify cutoff 3.0\ntimestep " + f17(dt) + "\n";
  s += sphere_style ? "fix hs all hardsphere/mcva\n"
                    : "fix hs all hardsphere/mcva diameter " + f17(2 * a.r) + "\n";
  s += "thermo_style custom step ke\nthermo_modify norm no\nrun " + std::to_string(nsteps) + "\n";
  h.lines(s);

  const double ke0 = 0.5 * a.m * dot(a.v, a.v) + 0.5 * b.m * dot(b.v, b.v);
  exact_two_body(a, b, dt * nsteps, L, periodic);
  if (::testing::Test::HasFatalFailure()) return;
  std::vector<double> x(6), v(6);
  lammps_gather_atoms(h.lmp, (char *) "x", 1, 3, x.data());
  lammps_gather_atoms(h.lmp, (char *) "v", 1, 3, v.data());
  auto pdiff = [&](double u, double w) {
    double d = u - w;
    if (periodic) d -= L * std::round(d / L);
    return d;
  };
  for (int k = 0; k < 3; k++) {
    EXPECT_NEAR(pdiff(x[k], a.x[k]), 0.0, 1e-11) << "x1[" << k << "]";
    EXPECT_NEAR(pdiff(x[3 + k], b.x[k]), 0.0, 1e-11) << "x2[" << k << "]";
    EXPECT_NEAR(v[k], a.v[k], 1e-12) << "v1[" << k << "]";
    EXPECT_NEAR(v[3 + k], b.v[k], 1e-12) << "v2[" << k << "]";
  }
  EXPECT_EQ(h.fix_vector("hs", 0), 1.0);
  EXPECT_EQ(h.fix_vector("hs", 1), 1.0);
  EXPECT_EQ(h.fix_vector("hs", 3), 1.0);
  EXPECT_GE(h.fix_vector("hs", 6), 2.0);     // Gauss sub-steps: to and from the contact
  EXPECT_GE(h.fix_vector("hs", 5), 1.0);     // stage iterations
  EXPECT_GE(h.fix_vector("hs", 8), 1.0);     // Gauss solves
  EXPECT_EQ(h.fix_vector("hs", 9), 0.0);     // nothing missed
  EXPECT_NEAR(h.thermo("ke"), ke0, 1e-13 * ke0);
}

}    // namespace

TEST(MCVAFreeFlight, HeadOnUnequalMasses)
{
  check_two_body({{-1.0, 0.0, 0.0}, {1.0, 0.0, 0.0}, 1.0, 0.5},
                 {{1.0, 0.0, 0.0}, {-0.5, 0.0, 0.0}, 3.0, 0.5}, 0.01, 150, false, false);
}

TEST(MCVAFreeFlight, Oblique3DStepNotMultiple)
{
  check_two_body({{-1.0, 0.1, -0.2}, {0.9, 0.05, 0.1}, 1.0, 0.5},
                 {{1.1, -0.2, 0.1}, {-0.7, 0.1, -0.05}, 1.0, 0.5}, 0.0137, 111, false, false);
}

TEST(MCVAFreeFlight, PerAtomRadiusMassAcrossPeriodicBoundary)
{
  check_two_body({{19.2, 5.0, 5.1}, {0.8, 0.1, 0.0}, 2.0, 0.4},
                 {{1.0, 5.2, 5.0}, {-0.6, 0.0, 0.05}, 0.7, 0.6}, 0.01, 120, true, true);
}

TEST(MCVARestart, CountersContinue)
{
  // the 10 counters go into the restart file and come back with the fix
  const std::string chain =
      std::string(HS_SOURCE_DIR) + "/examples/pendulum-chain/in.pendulum-chain";
  std::vector<double> before(10);
  {
    HSLammps h({"-var", "method", "mcva", "-var", "T", "20", "-var", "every", "100000"});
    h.file(chain);
    for (int k = 0; k < 10; k++) before[k] = h.fix_vector("hs", k);
    h.cmd("write_restart mcva_restart.bin");
  }
  ASSERT_GT(before[0], 0.0);
  ASSERT_GT(before[5], 0.0);
  HSLammps h;
  h.cmd("read_restart mcva_restart.bin");
  h.cmd("fix hs chain hardsphere/mcva diameter 0.9 wall xlo 0.0");
  h.cmd("fix 2d all enforce2d");
  h.cmd("run 0");
  for (int k = 0; k < 10; k++) EXPECT_EQ(h.fix_vector("hs", k), before[k]) << "entry " << k + 1;
  std::remove("mcva_restart.bin");
}
