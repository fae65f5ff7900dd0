// The rule for fixes beside the integrator (doc/fix_hardsphere.rst, "Fixes
// beside the integrator"), apart from the thermostat statistics
// (test_thermostats.cpp):
// - fix langevin tally yes: etotal + ecouple is conserved up to the errors
//   of the integrator and of the tally's quadrature, which vanish as dt -> 0:
//   small against the energy the thermostat exchanged, and smaller at dt/2;
// - deterministic force fixes (spring/self, wall/lj93, efield on charged
//   spheres) are evaluated again at every sub-step of the global engine, and
//   held by the local one (cva, vci: riding in the members' flows): each
//   method keeps its energy order (psa 1, the others 2) with their energies
//   in etotal; which fixes the local engine can hold (only add to f);
// - fixes that change the box, and langevin's gjf, are refused by name; a
//   fix with forces of an unknown kind is named in a warning; the held
//   thermostats are named in the log; compute hamiltonian/modified warns
//   about atoms of its group that no integrator moves; an overlap at set-up
//   names its likely causes.

#include "hs_chain.h"
#include "hs_errors.h"
#include "hs_fix_rule.h"

#include <algorithm>
#include <cmath>
#include <regex>

using hs_chain::f17;
using hs_errors::expect_error;

namespace {

// the 108-sphere fluid of test_thermostats.cpp; smooth: lj/smooth/linear
// (no force jump at the cutoff) instead of the shifted lj/cut
std::string fluid(const std::string &method, double dt, int seed, const std::string &extra,
                  bool smooth = false)
{
  const std::string pair = smooth ? "pair_style lj/smooth/linear 2.5\npair_coeff 1 1 1.0 1.0 2.5\n"
                                  : "pair_style lj/cut 2.5\npair_coeff 1 1 1.0 1.0 2.5\n"
                                    "pair_modify shift yes\n";
  return R"LMP(
units lj
atom_style atomic
atom_modify map array
lattice fcc 0.8
region box block 0 3 0 3 0 3
create_box 1 box
create_atoms 1 box
mass 1 1.0
)LMP" + pair + R"LMP(
neighbor 0.3 bin
neigh_modify every 1 delay 0 check yes
comm_modify cutoff 3.0
velocity all create 1.5 )LMP" +
      std::to_string(seed) + R"LMP( dist gaussian
timestep )LMP" + f17(dt) + R"LMP(
fix int all hardsphere/)LMP" + method + R"LMP( diameter 1.05
)LMP" + extra;
}

// the value printed on a line "KEY value"
double printed(const std::string &out, const std::string &key)
{
  std::smatch m;
  if (std::regex_search(out, m, std::regex("\n" + key + " ([-0-9.eE+naninf]+)")))
    return std::stod(m[1]);
  ADD_FAILURE() << "no " << key << " line in:\n" << out;
  return NAN;
}

// max |econserve(t) - econserve(0)| and max |ecouple| over T = 5 with
// fix langevin tally yes (kT 1.5, damp 0.5), extensive energies; without
// the thermostat econserve = etotal (the method's own energy error);
// method "nve": fix nve (LAMMPS alone, no hard spheres)
void tally_run(const std::string &method, double dt, int seed, bool thermostat, double &dEc,
               double &ecmax)
{
  const int n = (int) std::lround(5.0 / dt);
  std::string in = fluid(method, dt, seed, (thermostat ? "fix th all langevin 1.5 1.5 0.5 " +
                                                  std::to_string(seed + 1) + " tally yes\n"
                                                       : std::string()) +
                             R"LMP(
thermo_modify norm no
variable ec equal econserve
variable eco equal abs(ecouple)
fix ecv all vector 1 v_ec v_eco
run )LMP" + std::to_string(n) + R"LMP(
variable ecmin equal min(f_ecv[1])
variable ecmaxv equal max(f_ecv[1])
variable ec0 equal f_ecv[1][1]
print "DEC $(0.5*(v_ecmaxv-v_ecmin)+abs(0.5*(v_ecmaxv+v_ecmin)-v_ec0))"
print "ECOUPLE $(max(f_ecv[2]))"
)LMP", true);
  if (method == "nve") {
    const std::string from = "fix int all hardsphere/nve diameter 1.05";
    in.replace(in.find(from), from.size(), "fix int all nve");
  }
  RunResult r = expect_runs(in);
  dEc = printed(r.output, "DEC");
  ecmax = printed(r.output, "ECOUPLE");
}

class Rule : public ::testing::TestWithParam<const char *> {};

std::string case_name(const ::testing::TestParamInfo<const char *> &info)
{
  return info.param;
}

}    // namespace

// etotal + ecouple is conserved up to the method's own energy error (the
// same run without the thermostat) and the error of langevin's tally
// quadrature (fix nve + langevin on the same fluid, LAMMPS alone): within
// 3x their sum, and converging with dt (two seeds, geometric mean of the
// ratio). Before the rule, sub-step kicks of fresh random forces that the
// tally never saw broke this by orders of magnitude.
TEST_P(Rule, LangevinTallyConserved)
{
  const std::string method = GetParam();
  double lratio = 0.0;
  for (int seed : {3101, 4409}) {
    double d[2], e[2];
    for (int k = 0; k < 2; k++) {
      const double dt = k ? 0.0025 : 0.005;
      double dnve, dtally, dummy;
      tally_run(method, dt, seed, true, d[k], e[k]);
      tally_run(method, dt, seed, false, dnve, dummy);
      tally_run("nve", dt, seed, true, dtally, dummy);
      printf("[ %s tally seed %d dt %g ] max|econserve - econserve0| %.4g; method without "
             "thermostat %.4g, fix nve + langevin %.4g; max|ecouple| %.4g\n",
             method.c_str(), seed, dt, d[k], dnve, dtally, e[k]);
      EXPECT_LT(d[k], 3.0 * (dnve + dtally));
      EXPECT_LT(d[k], 0.2 * e[k]);
    }
    lratio += 0.5 * std::log(d[0] / d[1]);
  }
  const double ratio = std::exp(lratio);
  printf("[ %s tally ] error ratio dt 0.005 / 0.0025: %.2f (order %.2f)\n", method.c_str(),
         ratio, std::log2(ratio));
  // it converges: at least order 1/2
  EXPECT_GT(ratio, std::sqrt(2.0));
}

INSTANTIATE_TEST_SUITE_P(Methods, Rule, ::testing::Values("psa", "cva", "pcva", "vci"),
                         case_name);

/* ---------------------------------------------------------------------- */

namespace {

// 32 charged spheres (diameter 1.1, nearest lattice neighbours 1.21 apart)
// tethered by spring/self between soft walls (wall/lj93) in a field
// (efield), with a weak LJ attraction: frequent collisions, and every
// deterministic fix's energy in etotal. Smooth forces only (the LJ force
// goes to zero at its cutoff, the walls' cutoff is beyond the box), so
// that no force jump adds an O(dt) error. max |E(t) - E(0)| over T = 2.
double fixes_run(const std::string &method, double dt)
{
  const int n = (int) std::lround(2.0 / dt);
  // cva, vci and mcva take the local engine (the fixes' forces held,
  // riding in the members' flows; mcva's projection counts their work as
  // pcva's does): the output entry that counts steps fallen back to
  // substep global (cva f_int[10], vci f_int[16], mcva f_int[18]), "" where
  // it is not checked
  const std::string fellback = method == "cva"    ? "10"
                               : method == "vci"  ? "16"
                               : method == "mcva" ? "18"
                                                  : "";
  const std::string in = R"LMP(
units lj
atom_style charge
atom_modify map array
boundary p p f
lattice fcc 0.8
region box block 0 2 0 2 -0.6 2.1
create_box 1 box
region inside block 0 2 0 2 0 1.9
create_atoms 1 region inside
mass 1 1.0
set atom 1*16 charge 1.0
set atom 17*32 charge -1.0
pair_style lj/smooth/linear 2.5
pair_coeff 1 1 0.5 1.0 2.5
neighbor 0.3 bin
neigh_modify every 1 delay 0 check yes
comm_modify cutoff 3.0
velocity all create 1.0 6823 dist gaussian mom yes
timestep )LMP" + f17(dt) + R"LMP(
fix int all hardsphere/)LMP" + method + R"LMP( diameter 1.1
fix sp all spring/self 20.0
fix wl all wall/lj93 zlo EDGE 1.0 1.0 6.0 zhi EDGE 1.0 1.0 6.0
fix ef all efield 0.0 0.0 0.5
fix_modify sp energy yes
fix_modify wl energy yes
fix_modify ef energy yes
thermo_modify norm no
variable E equal etotal
fix Ev all vector 1 v_E
run )LMP" + std::to_string(n) + R"LMP(
variable Emin equal min(f_Ev)
variable Emax equal max(f_Ev)
variable E0 equal f_Ev[1]
print "DE $(0.5*(v_Emax-v_Emin)+abs(0.5*(v_Emax+v_Emin)-v_E0))"
print "NCOLL $(f_int[1])"
)LMP" + (fellback.empty() ? "" : "print \"FELLBACK $(f_int[" + fellback + "])\"\n");
  RunResult r = expect_runs(in);
  const double ncoll = printed(r.output, "NCOLL");
  EXPECT_GT(ncoll, 20.0) << "the case is meant to collide";
  if (!fellback.empty())
    EXPECT_EQ(printed(r.output, "FELLBACK"), 0.0) << method << " fell back to substep global";
  return printed(r.output, "DE");
}

class DeterministicFixes : public ::testing::TestWithParam<const char *> {};

}    // namespace

TEST_P(DeterministicFixes, EnergyOrder)
{
  const std::string method = GetParam();
  std::vector<double> dts = {0.004, 0.002, 0.001}, errs;
  for (double dt : dts) errs.push_back(fixes_run(method, dt));
  const double order = hs_chain::loglog_slope(dts, errs);
  printf("[ %s spring/self + wall/lj93 + efield ] max|E-E0|: %.3g %.3g %.3g, order %.2f\n",
         method.c_str(), errs[0], errs[1], errs[2], order);
  EXPECT_GT(order, method == "psa" ? 0.8 : 1.8);
}

// the local engine holds a conservative fix only if its post_force() adds a
// force of the positions to f (independent of what f holds); fixes that set,
// average, project or read f, thermostats and unknown fixes are not held
TEST(FixRuleTable, AddsForceOnly)
{
  for (const char *s : {"addforce", "efield", "indent", "spring", "spring/self", "wall/lj93",
                        "wall/harmonic", "wall/region", "restrain", "wall/lj93/omp"})
    EXPECT_TRUE(HardSphere::adds_force_only(s)) << s;
  for (const char *s : {"setforce", "aveforce", "freeze", "lineforce", "planeforce", "enforce2d",
                        "store/force", "langevin", "viscous", "shake", "my/own/fix"})
    EXPECT_FALSE(HardSphere::adds_force_only(s)) << s;
}

// the fixes whose post_force() touches f of their own group's atoms only:
// beside a group that shares none of them the local engine ignores them
// (setforce on a frozen wall of atoms); not additive fixes (held anyway),
// thermostats, or fixes that may reach other groups' atoms
TEST(FixRuleTable, OwnGroupOnly)
{
  for (const char *s : {"setforce", "aveforce", "freeze", "lineforce", "planeforce",
                        "store/force", "setforce/kk", "freeze/omp"})
    EXPECT_TRUE(HardSphere::own_group_only(s)) << s;
  for (const char *s : {"addforce", "spring", "cmap", "restrain", "langevin", "enforce2d",
                        "shake", "my/own/fix"})
    EXPECT_FALSE(HardSphere::own_group_only(s)) << s;
}

// pair styles whose forces read the velocities or are random (their
// accelerated variants too); conservative ones are not
TEST(FixRuleTable, VelocityPairStyles)
{
  const auto names = HardSphere::velocity_pair_names();
  auto listed = [&names](const char *s) {
    return std::find(names.begin(), names.end(), s) != names.end();
  };
  for (const char *s : {"dpd", "dpd/tstat", "dpd/tstat/omp", "lubricate", "brownian",
                        "gran/hooke", "gran/hooke/history", "gran/hooke/omp", "granular/kk",
                        "dsmc", "sph/lj"})
    EXPECT_TRUE(listed(s)) << s;
  for (const char *s : {"lj/cut", "lj/cut/omp", "colloid", "yukawa/colloid", "soft",
                        "lj/cut/coul/long", "table", "hybrid/overlay", "dpdx"})
    EXPECT_FALSE(listed(s)) << s;
}

// a granular or lubrication pair style (velocity-dependent forces), alone or
// as a hybrid sub-style: an error for the methods that evaluate the forces
// again at contacts; psa evaluates them once per step, as beside fix nve.
// (The LAMMPS 4Feb2025 build of the tests has neither GRANULAR nor COLLOID)
TEST(RuleErrors, VelocityPairStyleRefused)
{
  std::string style;
  {
    HSLammps probe;
    for (const char *s : {"gran/hooke", "lubricate"})
      if (style.empty() && lammps_has_style(probe.lmp, "pair", s)) style = s;
  }
  if (style.empty()) GTEST_SKIP() << "no granular or lubrication pair style in this LAMMPS";
  const std::string args = style == "gran/hooke" ? " 2000.0 NULL 50.0 NULL 0.5 0"
                                                 : " 1.0 1 1 1.001 2.5";
  auto input = [&](const std::string &pair, const std::string &method) {
    return R"LMP(
units lj
atom_style sphere
comm_modify vel yes cutoff 2.0
lattice fcc 0.5
region box block 0 4 0 4 0 4
create_box 1 box
create_atoms 1 box
set type 1 diameter 1.0
set type 1 mass 1.0
)LMP" + pair + R"LMP(
neighbor 0.3 bin
velocity all create 1.0 4928 dist gaussian
timestep 0.002
fix hs all hardsphere/)LMP" +
        method + "\nrun 10\n";
  };
  const std::string alone = "pair_style " + style + args + "\npair_coeff * *";
  const std::string hybrid = "pair_style hybrid/overlay soft 1.0 " + style + args +
      "\npair_coeff * * soft 1.0\npair_coeff * * " + style;
  for (const std::string method : {"cva", "pcva", "vci", "mcva"})
    expect_error(input(alone, method),
                 {"hardsphere/" + method + " cannot run with pair style " + style,
                  "depend on the velocities", "fix langevin"});
  expect_error(input(hybrid, "cva substep global"),
               {"hardsphere/cva cannot run with pair style " + style});
  expect_runs(input(hybrid, "psa"));
}

namespace {
// hard spheres (type 1, group spheres: a simple cubic grid of 4 x 8 x 8 in
// x < 6.4) beside 64 rigid dimers (type 2, bond length 1.0, held by fix
// shake, integrated by fix nve) in x > 6.4; lj/cut 2.5 between all, the
// box 12.8 x 12.8 x 12.8; T = 1 (the velocities along the bonds, which
// shake removes in the first step, before E0). fix_line: the spheres'
// integrator
std::string shake_beside(const std::string &fix_line, double dt, int nsteps,
                         const std::string &shake_group = "dimers")
{
  std::string in = R"LMP(
units lj
atom_style bond
atom_modify map array
boundary p p p
region box block 0 12.8 0 12.8 0 12.8
create_box 2 box bond/types 1 extra/bond/per/atom 1 extra/special/per/atom 1
mass * 1.0
)LMP";
  int n = 0;
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 8; j++)
      for (int k = 0; k < 8; k++) {
        in += "create_atoms 1 single " + hs_chain::f17(0.8 + 1.6 * i) + " " +
            hs_chain::f17(0.8 + 1.6 * j) + " " + hs_chain::f17(0.8 + 1.6 * k) + " units box\n";
        n++;
      }
  for (int i = 0; i < 2; i++)
    for (int j = 0; j < 4; j++)
      for (int k = 0; k < 8; k++) {
        const double x = 7.0 + 3.2 * i, y = 0.8 + 3.2 * j, z = 0.8 + 1.6 * k;
        in += "create_atoms 2 single " + hs_chain::f17(x) + " " + hs_chain::f17(y) + " " +
            hs_chain::f17(z) + " units box\n";
        in += "create_atoms 2 single " + hs_chain::f17(x + 1.0) + " " + hs_chain::f17(y) + " " +
            hs_chain::f17(z) + " units box\n";
        in += "create_bonds single/bond 1 " + std::to_string(n + 1) + " " +
            std::to_string(n + 2) + "\n";
        n += 2;
      }
  in += R"LMP(
pair_style lj/cut 2.5
pair_coeff * * 1.0 1.0
pair_modify shift yes
bond_style harmonic
bond_coeff 1 100.0 1.0
special_bonds lj/coul 0.0 1.0 1.0
neighbor 0.3 bin
neigh_modify every 1 delay 0 check yes
group spheres type 1
group dimers type 2
velocity all create 1.0 48823 mom yes rot no dist gaussian
)LMP";
  in += fix_line + "\n";
  in += "fix nv dimers nve\nfix sh " + shake_group + " shake 1e-10 100 0 b 1\n";
  in += "timestep " + hs_chain::f17(dt) + "\n" + R"LMP(
compute bl dimers bond/local dist
compute bmax dimers reduce max c_bl
compute bmin dimers reduce min c_bl
thermo_style custom step etotal c_bmax c_bmin
thermo_modify norm yes
run 10
variable E0 equal $(etotal:%.17g)
variable dE equal abs(etotal-v_E0)
fix mx all ave/histo 1 1 1 0.0 1.0 1 v_dE ave running
run )LMP" + std::to_string(nsteps) +
      R"LMP(
print "DE $(f_mx[4]:%.10g)"
print "BOND $(c_bmin:%.12g) $(c_bmax:%.12g)"
)LMP";
  return in;
}
}    // namespace

// fix shake on molecules that share no atom with the spheres (a rigid
// solvent beside hard spheres): substep local evaluates no fix inside a
// collisional step, so the constraints hold to shake's tolerance and the
// energy error is second order in dt, as for each part alone. The global
// engine (substep global, any method) evaluates every fix at each contact: an
// error naming substep local; shake on the spheres themselves stays refused.
// (The LAMMPS 4Feb2025 build of the tests has no RIGID package)
TEST(RuleErrors, ShakeOnAnotherGroup)
{
  {
    HSLammps probe;
    if (!lammps_has_style(probe.lmp, "fix", "shake"))
      GTEST_SKIP() << "no fix shake (RIGID package) in this LAMMPS";
  }
  std::vector<double> dts = {0.004, 0.002, 0.001}, errs;
  for (double dt : dts) {
    RunResult r =
        expect_runs(shake_beside("fix hs spheres hardsphere/cva diameter 1.0", dt,
                                 (int) std::lround(2.0 / dt)) +
                        "print \"COLL $(f_hs[1])\"\nprint \"FB $(f_hs[10])\"\n",
                    {"substep local (collisions"}, {"falls back"});
    errs.push_back(printed(r.output, "DE"));
    std::smatch m;
    ASSERT_TRUE(std::regex_search(r.output, m,
                                  std::regex("\nBOND ([-0-9.eE+]+) ([-0-9.eE+]+)")));
    EXPECT_NEAR(std::stod(m[1]), 1.0, 1e-8) << dt;
    EXPECT_NEAR(std::stod(m[2]), 1.0, 1e-8) << dt;
    EXPECT_GT(printed(r.output, "COLL"), 20.0) << dt;
    EXPECT_EQ(printed(r.output, "FB"), 0.0) << dt;
  }
  const double order = hs_chain::loglog_slope(dts, errs);
  std::printf("[ cva beside shake ] max|E-E0| per atom: %.3g %.3g %.3g, order %.2f\n", errs[0],
              errs[1], errs[2], order);
  EXPECT_GT(order, 1.7);
  expect_runs(shake_beside("fix hs spheres hardsphere/psa diameter 1.0", 0.002, 50));
  expect_error(shake_beside("fix hs spheres hardsphere/cva diameter 1.0 substep global", 0.002,
                            50),
               {"hardsphere/cva cannot run beside fix sh shake with substep global",
                "substep local"});
  expect_error(shake_beside("fix hs spheres hardsphere/cva diameter 1.0 overflow global", 0.002,
                            50),
               {"hardsphere/cva cannot run beside fix sh shake with overflow global"});
  // mcva's local form (its default) runs beside it; its global form does not
  expect_runs(shake_beside("fix hs spheres hardsphere/mcva diameter 1.0", 0.002, 50),
              {"substep local (collisions"}, {"falls back"});
  expect_error(shake_beside("fix hs spheres hardsphere/mcva diameter 1.0 substep global", 0.002,
                            50),
               {"hardsphere/mcva cannot run beside fix sh shake with substep global"});
  expect_error(shake_beside("fix hs spheres hardsphere/cva diameter 1.0", 0.002, 50, "all"),
               {"cannot run beside fix sh shake on atoms of its group", "velocity-Verlet"});
}

INSTANTIATE_TEST_SUITE_P(Methods, DeterministicFixes,
                         ::testing::Values("psa", "cva", "pcva", "mcva", "vci"), case_name);

/* ---------------------------------------------------------------------- */

TEST(RuleErrors, PressBerendsenRefused)
{
  expect_error(fluid("cva", 0.005, 1, "fix pr all press/berendsen iso 4.0 4.0 5.0\nrun 10\n"),
               {"hardsphere/cva cannot run beside fix pr press/berendsen", "changes the box",
                "overlap"});
}

TEST(RuleErrors, DeformRefused)
{
  expect_error(fluid("pcva", 0.005, 1, "fix df all deform 1 x scale 1.01\nrun 10\n"),
               {"hardsphere/pcva cannot run beside fix df deform", "changes the box"});
}

TEST(RuleErrors, LangevinGJFRefused)
{
  expect_error(
      fluid("vci", 0.005, 1, "fix th all langevin 1.5 1.5 0.5 1 gjf vhalf\nrun 10\n"),
      {"hardsphere/vci cannot run beside fix th langevin with the gjf keyword", "gjf no"});
}

TEST(RuleWarnings, UnknownFixNamedHeldFixLogged)
{
  RunResult r = expect_runs(fluid("cva", 0.005, 1,
                                  "fix ex all external pf/array 1\n"
                                  "fix th all langevin 1.5 1.5 0.5 7\nrun 20\n"),
                            {"WARNING: Fix hardsphere/cva: the forces of fix ex external are of a "
                             "kind it does not know",
                             "forces of fix th langevin held through collisional steps"});
  // known fixes are not warned about
  EXPECT_EQ(r.output.find("fix th langevin are of a kind"), std::string::npos) << r.output;
}

TEST(RuleWarnings, ComputeGroupNotIntegrated)
{
  const std::string base = R"LMP(
units lj
atom_style atomic
atom_modify map array
boundary f f f
region box block -5 5 -5 5 -5 5 units box
create_box 1 box
create_atoms 1 single -1 0 0 units box
create_atoms 1 single 1 0 0 units box
mass 1 1.0
pair_style lj/cut 2.5
pair_coeff 1 1 1.0 1.0 2.5
comm_modify cutoff 3.0
group mob id 1
fix hs mob hardsphere/cva diameter 1.0
)LMP";
  expect_runs(base + "compute h all hamiltonian/modified\n"
                     "thermo_style custom step c_h[1] c_h[2]\nrun 5\n",
              {"WARNING: Compute hamiltonian/modified h: 1 atoms of group all are "
               "moved by no time integrator"});
  expect_runs(base + "compute h mob hamiltonian/modified\n"
                     "thermo_style custom step c_h[1] c_h[2]\nrun 5\n",
              {}, {"moved by no time integrator"});
}

TEST(RuleErrors, OverlapAtSetupNamesLikelyCause)
{
  expect_error(hs_errors::two_atoms("0", "2", "fix hs all hardsphere/cva diameter 1.0",
                                    "run 0\ndisplace_atoms all move 0 0 0 units box\n"
                                    "set atom 2 x 0.5\n"),
               {"atoms 1 and 2 overlap", "at set-up", "change_box, displace_atoms, set"});
}
