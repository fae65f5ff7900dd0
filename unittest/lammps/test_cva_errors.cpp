// fix hardsphere/cva: invalid set-ups end in an ERROR naming the problem.
// LAMMPS here is built without exceptions (an error exits the process), so
// every case runs in a separate lmp process through run_lmp(). The checks
// every method shares (overlap, walls, keywords, second integrator) are in
// test_shared_errors.cpp, run for each method; here the rest of the base's.

#include "hs_errors.h"

#include <string>

using hs_errors::expect_error;
using hs_errors::two_atoms;


TEST(CVAErrors, ValidBaselineRuns)
{
  // the template itself is fine: the errors below come from the one change
  expect_runs(two_atoms("-1", "1", "fix hs all hardsphere/cva diameter 1.0 wall xlo -4"), {},
              {"ERROR"});
}

TEST(CVAErrors, SphereThroughEdgeWallAtSetup)
{
  expect_error(two_atoms("1", "4.9", "fix hs all hardsphere/cva diameter 1.0 wall xhi EDGE"),
               {"atom 2 is", "through wall xhi"});
}

TEST(CVAErrors, NonNumericDiameter)
{
  expect_error(two_atoms("-1", "1", "fix hs all hardsphere/cva diameter abc"), {"abc"});
}

TEST(CVAErrors, DiameterWithoutValue)
{
  expect_error(two_atoms("-1", "1", "fix hs all hardsphere/cva diameter"), {"diameter"});
}

TEST(CVAErrors, WallOnPeriodicDimension)
{
  expect_error(two_atoms("-1", "1", "fix hs all hardsphere/cva diameter 1.0 wall xlo -4", "",
                         "p f f"),
               {"wall xlo", "periodic"});
}

TEST(CVAErrors, ZWallIn2d)
{
  expect_error("units lj\ndimension 2\natom_style atomic\natom_modify map array\n"
               "boundary f f p\nregion box block -5 5 -5 5 -0.5 0.5 units box\n"
               "create_box 1 box\ncreate_atoms 1 single -1 0 0 units box\n"
               "create_atoms 1 single 1 0 0 units box\nmass 1 1.0\ncomm_modify cutoff 3.0\n"
               "fix hs all hardsphere/cva diameter 1.0 wall zlo 0\nrun 10\n",
               {"wall zlo", "2d"});
}

TEST(CVAErrors, SecondIntegratorOnSubset)
{
  // fix nve on atom 2 only still shares atoms with the hard-sphere group
  expect_error(two_atoms("-1", "1", "fix hs all hardsphere/cva diameter 1.0",
                         "group two id 2\nfix other two nve\n"),
               {"other", "hs", "both time-integrate"});
}

TEST(CVAErrors, TriclinicWallOnALeaningFace)
{
  // x non-periodic, xy tilted: the x faces lean, a wall plane x = const is
  // no face of the box (a wall on a face no tilt leans: test_triclinic.cpp)
  const std::string input = R"(
units lj
atom_style atomic
boundary f p p
region box prism -5 5 -5 5 -5 5 0.5 0 0 units box
create_box 1 box
create_atoms 1 single -1 0 0 units box
create_atoms 1 single 1 0 0 units box
mass 1 1.0
comm_modify cutoff 3.0
fix hs all hardsphere/cva diameter 1.0 wall xlo EDGE
run 10
)";
  expect_error(input, {"wall xlo", "triclinic box", "xy 0.5", "lean the x faces"});
}

TEST(CVAErrors, GhostCutoffTooSmall)
{
  // contact list cutoff 1 + 2 x 0.3 = 1.6 > ghost cutoff 1.0 + 0.3: an
  // error for substep global; substep local (the default) sets the cutoff
  // it needs itself and says so
  const std::string input = R"(
units lj
atom_style atomic
boundary p p p
region box block -5 5 -5 5 -5 5 units box
create_box 1 box
create_atoms 1 single -1 0 0 units box
create_atoms 1 single 1 0 0 units box
mass 1 1.0
pair_style lj/cut 1.0
pair_coeff 1 1 1.0 1.0 1.0
fix hs all hardsphere/cva diameter 1.0 SUBSTEP
run 10
)";
  std::string global = input, local = input;
  global.replace(global.find("SUBSTEP"), 7, "substep global");
  local.replace(local.find(" SUBSTEP"), 8, "");
  expect_error(global, {"ghost", "comm_modify cutoff 1.6"});
  expect_runs(local, {"substep local sets comm_modify cutoff 1.6"});
}

TEST(CVAErrors, GhostCutoffLargeEnoughRuns)
{
  // the same with a sufficient comm_modify cutoff is fine
  const std::string input = R"(
units lj
atom_style atomic
boundary p p p
region box block -5 5 -5 5 -5 5 units box
create_box 1 box
create_atoms 1 single -1 0 0 units box
create_atoms 1 single 1 0 0 units box
mass 1 1.0
pair_style lj/cut 1.0
pair_coeff 1 1 1.0 1.0 1.0
comm_modify cutoff 1.6
fix hs all hardsphere/cva diameter 1.0
run 10
)";
  expect_runs(input);
}

TEST(CVAErrors, NeighExcludeAtFirstRun)
{
  expect_error(two_atoms("-1", "1", "fix hs all hardsphere/cva diameter 1.0",
                         "neigh_modify exclude type 1 1\n"),
               {"neigh_modify exclude"});
}

// an exclusion among atoms outside the group (a frozen wall's atoms
// excluded from each other, a common idiom) takes no pair of the group off
// the lists: it runs, and the group's spheres collide (it was an error that
// said excluded pairs would pass through each other). One that takes a pair
// of the group off is still an error, by type or by group
TEST(CVAErrors, NeighExcludeOutsideTheGroupRuns)
{
  auto input = [](const std::string &exclude) {
    return R"IN(
units lj
atom_style atomic
atom_modify map array
region box block -5 5 -5 5 -5 5 units box
create_box 2 box
create_atoms 1 single -1 0 0 units box
create_atoms 1 single 1 0 0 units box
create_atoms 2 single 0 3 0 units box
create_atoms 2 single 0.5 3 0 units box
mass * 1.0
comm_modify cutoff 3.0
group one id 1
group two id 2
group spheres type 1
group wall type 2
)IN" + exclude + R"IN(
velocity one set 1 0 0 units box
velocity two set -1 0 0 units box
fix hs spheres hardsphere/cva diameter 1.0
run 100
print "RESULT collisions $(f_hs[1])"
)IN";
  };
  for (const std::string ex : {"neigh_modify exclude type 2 2", "neigh_modify exclude type 1 2",
                               "neigh_modify exclude group wall wall"})
    expect_runs(input(ex), {"RESULT collisions 1"});
  expect_error(input("neigh_modify exclude type 1 1"),
               {"Fix hardsphere/cva cannot be used with neigh_modify exclude type 1 1",
                "pairs of the atoms of group spheres"});
  expect_error(input("neigh_modify exclude group one two"),
               {"neigh_modify exclude group one two"});
}

// LAMMPS::init() runs modify->init() before neighbor->init(), where Neighbor
// sets 'exclude': the check must see the current run's setting, not the
// previous run's: (a) exclusions added after a run are caught (else the
// spheres pass through each other); (b) exclusions removed after a run are
// no error.
TEST(CVAErrors, NeighExcludeAddedAfterARun)
{
  const std::string input = R"IN(
units lj
atom_style atomic
atom_modify map array
region box block -5 5 -5 5 -5 5 units box
create_box 1 box
create_atoms 1 single -1 0 0 units box
create_atoms 1 single 1 0 0 units box
mass 1 1.0
comm_modify cutoff 3.0
fix hs all hardsphere/cva diameter 1.0
run 0
neigh_modify exclude type 1 1
group one id 1
group two id 2
velocity one set 1 0 0 units box
velocity two set -1 0 0 units box
variable d equal x[2]-x[1]
run 200
print "RESULT distance $(v_d:%.6f) collisions $(f_hs[1])"
)IN";
  RunResult r = run_lmp(input);
  // expected: the exclusion is rejected as at the first run
  EXPECT_NE(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("neigh_modify exclude"), std::string::npos)
      << "the excluded pair was integrated without an error:\n"
      << r.output.substr(r.output.rfind("RESULT") == std::string::npos ? 0 : r.output.rfind("RESULT"));
}

TEST(CVAErrors, NeighExcludeRemovedAfterARun)
{
  const std::string input = R"(
units lj
atom_style atomic
atom_modify map array
region box block -5 5 -5 5 -5 5 units box
create_box 1 box
create_atoms 1 single -1 0 0 units box
create_atoms 1 single 1 0 0 units box
mass 1 1.0
comm_modify cutoff 3.0
neigh_modify exclude type 1 1
fix int all nve
run 0
unfix int
neigh_modify exclude none
fix hs all hardsphere/cva diameter 1.0
run 10
)";
  RunResult r = run_lmp(input);
  // expected: no exclusions are left, so this is a valid run
  EXPECT_EQ(r.exit_code, 0) << r.output;
}
