// fix hardsphere/vci: the keywords and errors are the base's (shared base;
// tested for every method in test_shared_errors.cpp). A contact where no impulse strength in
// [1/2, 2] times the elastic one matches the discrete energy (grazing
// contacts: E_d+ - E_d- at the elastic impulse is O(dt^2) while the
// impulse is small, section 2.3 / hs_vci.h) gets the elastic impulse, is
// counted in f_ID[7] and warned about once. Each case runs in its own lmp
// process (run_lmp): LAMMPS here is built without exceptions.

#include "hs_errors.h"

#include <regex>
#include <string>

using hs_errors::expect_error;

TEST(VCIErrors, ValidBaselineRuns)
{
  // free flight (no potential) between walls: E_d = H, every contact is
  // elastic (s = 1 solves it) and counted as solved
  RunResult r = expect_runs(R"IN(units lj
atom_style atomic
atom_modify map array
boundary f f f
region box block -5 5 -5 5 -5 5 units box
create_box 1 box
create_atoms 1 single -1 0 0 units box
create_atoms 1 single 1 0 0 units box
mass 1 1.0
comm_modify cutoff 3.0
group a id 1
velocity a set 1.0 0.3 0 units box
fix hs all hardsphere/vci diameter 1.0 wall xlo -4 wall xhi 4 wall ylo -4 wall yhi 4
timestep 0.05
run 400
print "COUNTS $(f_hs[1]) $(f_hs[6]) $(f_hs[7])"
)IN", {}, {"ERROR", "WARNING: Fix"});
  std::smatch m;
  const std::regex re(R"((?:^|\n)COUNTS ([0-9.eE+-]+) ([0-9.eE+-]+) ([0-9.eE+-]+))");
  ASSERT_TRUE(std::regex_search(r.output, m, re)) << r.output;
  EXPECT_GT(std::stod(m[1]), 2.0);
  EXPECT_EQ(std::stod(m[2]), std::stod(m[1]));
  EXPECT_EQ(std::stod(m[3]), 0.0);
}

TEST(VCIErrors, NoRootFallsBackToElasticCountedAndWarnedOnce)
{
  // hard spheres with LJ attraction at density 0.6: some contacts graze
  const std::string input = R"IN(units lj
atom_style atomic
lattice fcc 0.6
region box block 0 5 0 5 0 5
create_box 1 box
create_atoms 1 box
mass 1 1.0
velocity all create 1.5 87287 mom yes rot yes dist gaussian loop geom
pair_style lj/cut 2.5
pair_coeff 1 1 1.0 1.0 2.5
neighbor 0.3 bin
fix hs all hardsphere/vci diameter 1.0
timestep 0.005
run 100
print "COUNTS $(f_hs[1]) $(f_hs[6]) $(f_hs[7]) $(f_hs[8]) $(f_hs[11]:%.3e)"
)IN";
  RunResult r = expect_runs(input);
  const std::string warn = "WARNING: Fix hardsphere/vci: no impulse strength between 0.5 and 2 times";
  const size_t first = r.output.find(warn);
  ASSERT_NE(first, std::string::npos) << r.output;
  EXPECT_EQ(r.output.find(warn, first + 1), std::string::npos) << "warned more than once";
  EXPECT_NE(r.output.find("the elastic impulse is used", first), std::string::npos);
  std::smatch m;
  const std::regex re(R"((?:^|\n)COUNTS ([0-9.eE+-]+) ([0-9.eE+-]+) ([0-9.eE+-]+) ([0-9.eE+-]+) ([0-9.eE+-]+))");
  ASSERT_TRUE(std::regex_search(r.output, m, re)) << r.output;
  const double ncoll = std::stod(m[1]), solved = std::stod(m[2]), fallback = std::stod(m[3]),
               zero = std::stod(m[4]), maxdiff = std::stod(m[5]);
  printf("[ vci fluid ] %g collisions: %g solved, %g elastic fallbacks, %g with tau2 = 0; "
         "max|E_d+ - E_d-| %.3e\n", ncoll, solved, fallback, zero, maxdiff);
  EXPECT_GE(fallback, 1.0);
  EXPECT_EQ(solved + fallback + zero, ncoll);
  EXPECT_GT(solved, 0.9 * ncoll);
  // the solved ones are matched to round-off (energies ~ 1e3 here)
  EXPECT_LT(maxdiff, 1e-9);
}

TEST(VCIErrors, SimultaneousContactsGetElasticImpulseWithZeroSubstep)
{
  // three spheres on a line, the outer two moving in symmetrically: both
  // contacts at the same instant. The first has no sub-step after it
  // (tau2 = 0): elastic, counted in f_ID[8]; the second matches the E_d of
  // the sub-step before the first. Kinetic energy is conserved (no forces).
  RunResult r = expect_runs(R"IN(units lj
atom_style atomic
atom_modify map array
boundary f f f
region box block -6 6 -6 6 -6 6 units box
create_box 1 box
create_atoms 1 single -2.05 0 0 units box
create_atoms 1 single 0 0 0 units box
create_atoms 1 single 2.05 0 0 units box
mass 1 1.0
comm_modify cutoff 3.0
group a id 1
group c id 3
velocity a set 1.0 0 0 units box
velocity c set -1.0 0 0 units box
fix hs all hardsphere/vci diameter 1.0
timestep 0.1
thermo_style custom step ke
run 0
variable k0 equal $(ke:%.17g)
run 20
print "COUNTS $(f_hs[1]) $(f_hs[6]) $(f_hs[7]) $(f_hs[8]) $(abs(ke-v_k0):%.3e)"
)IN");
  std::smatch m;
  const std::regex re(R"((?:^|\n)COUNTS ([0-9.eE+-]+) ([0-9.eE+-]+) ([0-9.eE+-]+) ([0-9.eE+-]+) ([0-9.eE+-]+))");
  ASSERT_TRUE(std::regex_search(r.output, m, re)) << r.output;
  EXPECT_GE(std::stod(m[1]), 2.0);
  EXPECT_GE(std::stod(m[4]), 1.0);
  EXPECT_EQ(std::stod(m[2]) + std::stod(m[3]) + std::stod(m[4]), std::stod(m[1]));
  EXPECT_LT(std::stod(m[5]), 1e-14);
}
