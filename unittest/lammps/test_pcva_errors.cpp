// fix hardsphere/pcva: the keywords and errors are the base's (tested for
// every method in test_shared_errors.cpp); a sub-step where no momentum scaling can
// restore H_[2,VV] (section 3.2: alpha^2 = (H~0 - U)/K~ has no positive
// root) is left unprojected with a one-time warning and counted in f_ID[7].
// LAMMPS here is built without exceptions: each case runs in its own lmp
// process (run_lmp).

#include "hs_errors.h"

#include <regex>
#include <string>

using hs_errors::expect_error;

namespace {

std::string two_atoms(const std::string &fix)
{
  return "units lj\natom_style atomic\natom_modify map array\nboundary f f f\n"
         "region box block -5 5 -5 5 -5 5 units box\ncreate_box 1 box\n"
         "create_atoms 1 single -1 0 0 units box\ncreate_atoms 1 single 1 0 0 units box\n"
         "mass 1 1.0\ncomm_modify cutoff 3.0\nvelocity all set 0.5 0 0 units box\n" +
      fix + "\nthermo_style custom step f_hs[1] f_hs[6] f_hs[7]\nrun 100\n";
}

}    // namespace

TEST(PCVAErrors, ValidBaselineRuns)
{
  expect_runs(two_atoms("fix hs all hardsphere/pcva diameter 1.0 wall xlo -4 wall xhi 4"), {},
              {"ERROR", "WARNING: Fix hardsphere/pcva"});
}

namespace {
// a sphere on a strongly compressed stiff bond, its partner outside the
// group, thrown against a wall (see NoRealScalingIsCountedAndWarnedOnce)
std::string no_root_input(const std::string &substep)
{
  return R"IN(units lj
dimension 2
atom_style bond
atom_modify map array
boundary f f p
region box block -12 12 -12 12 -0.5 0.5 units box
create_box 2 box bond/types 1 extra/bond/per/atom 1 extra/special/per/atom 2
create_atoms 1 single 0 0 0 units box
create_atoms 2 single 0.5 0 0 units box
mass * 1.0
bond_style harmonic
bond_coeff 1 50.0 1.0
create_bonds single/bond 1 1 2
group s type 2
velocity s set 0 3.0 0 units box
neighbor 4.0 bin
comm_modify cutoff 10.0
fix hs s hardsphere/pcva diameter 0.45 wall xhi 0.735 substep )IN" +
         substep + R"IN(
fix 2d all enforce2d
timestep 0.3
run 1
print "SKIPPED $(f_hs[7]) PROJECTED $(f_hs[6])"
)IN";
}
}    // namespace

TEST(PCVAErrors, NoRealScalingIsCountedAndWarnedOnce)
{
  // a sphere on a strongly compressed stiff bond (r = 0.5, r0 = 1, K = 50)
  // moving sideways, thrown against a wall by the bond: along its velocity
  // V'' = 2K (r - r0)/r = -100, so with dt = 0.3 the quadratic form
  // K~ = 1/2 |v|^2 + dt^2/12 v^T V'' v is negative after the bounce
  // (|v_y| = 3 > sqrt(5) |v_x|): no alpha > 0 exists
  const std::string input = no_root_input("global");
  RunResult r = expect_runs(
      input, {"WARNING: Fix hardsphere/pcva: no momentum scaling restores H_[2,VV]", "K~ <= 0"});
  // printed once however often it happens
  const size_t first = r.output.find("no momentum scaling");
  EXPECT_EQ(r.output.find("no momentum scaling", first + 1), std::string::npos) << r.output;
  std::smatch m;
  const std::regex re(R"((?:^|\n)SKIPPED ([0-9.eE+-]+) PROJECTED ([0-9.eE+-]+))");
  ASSERT_TRUE(std::regex_search(r.output, m, re)) << r.output;
  EXPECT_GE(std::stod(m[1]), 1.0);
}

// the same with substep local: the step's single projection finds no real
// scaling either (the sphere alone in its cluster, its partner outside the
// group); counted and warned once, naming the local projection
TEST(PCVAErrors, NoRealScalingLocalIsCountedAndWarned)
{
  const std::string input = no_root_input("local");
  RunResult r =
      expect_runs(input, {"WARNING: Fix hardsphere/pcva: no momentum scaling restores H_[2,VV] at "
                          "the end of a step with collisions (substep local"});
  std::smatch m;
  const std::regex re(R"((?:^|\n)SKIPPED ([0-9.eE+-]+) PROJECTED ([0-9.eE+-]+))");
  ASSERT_TRUE(std::regex_search(r.output, m, re)) << r.output;
  EXPECT_EQ(std::stod(m[1]), 1.0);
  EXPECT_EQ(std::stod(m[2]), 0.0);
}

// another fix moving atoms outside the group (a solvent under fix nve beside
// the hard spheres): the projection would scale the group's momenta to undo
// their changes of H_[2,VV] (substep global: +31 % energy in 300 steps on
// hard colloids in a solvent). An error naming the other fix, on either
// engine; with pcva on every moving atom it runs
TEST(PCVAErrors, AnotherIntegratorOutsideTheGroupIsAnError)
{
  for (const char *substep : {"global", "local"})
    expect_error(two_atoms(std::string("group one id 1\ngroup two id 2\n"
                                       "fix hs one hardsphere/pcva diameter 1.0 substep ") +
                           substep + "\nfix sv two nve"),
                 {"Fix hardsphere/pcva: fix sv nve time-integrates atoms outside group one",
                  "closed system", "use hardsphere/cva"});
  expect_runs(two_atoms("group one id 1\nfix hs one hardsphere/pcva diameter 1.0"), {}, {"ERROR"});
}
