// The keywords and set-up checks every hardsphere fix shares (they are the
// base class's): invalid input ends in an ERROR naming the problem and the
// method's own style name. One suite, instantiated per method (test names
// start with the method); a method's own failures are in test_<method>_errors.cpp.

#include "hs_errors.h"

using hs_errors::expect_error;
using hs_errors::two_atoms;

namespace {

class SharedErrors : public ::testing::TestWithParam<const char *> {
 protected:
  std::string style() const { return std::string("hardsphere/") + GetParam(); }
  // "fix hs all hardsphere/<method><args>"
  std::string fix(const std::string &args) const { return "fix hs all " + style() + args; }
};

std::string case_name(const ::testing::TestParamInfo<const char *> &info)
{
  return info.param;
}

}    // namespace

TEST_P(SharedErrors, OverlapAtSetup)
{
  expect_error(two_atoms("0", "0.5", fix(" diameter 1.0")),
               {style(), "atoms 1 and 2 overlap", "set-up"});
}

TEST_P(SharedErrors, SphereThroughWallAtSetup)
{
  // centre 0.2 from the wall plane, radius 0.5
  expect_error(two_atoms("-1.8", "1", fix(" diameter 1.0 wall xlo -2.0")),
               {"atom 1 is", "through wall xlo"});
}

TEST_P(SharedErrors, MissingDiameterAtomic)
{
  expect_error(two_atoms("-1", "1", fix("")), {"Fix " + style() + " needs the diameter keyword"});
}

TEST_P(SharedErrors, UnknownKeyword)
{
  expect_error(two_atoms("-1", "1", fix(" diameter 1.0 bogus 3")),
               {"Unknown fix " + style() + " keyword: bogus"});
}

TEST_P(SharedErrors, NegativeDiameter)
{
  expect_error(two_atoms("-1", "1", fix(" diameter -1")),
               {"Fix " + style() + " diameter must be > 0", "-1"});
}

TEST_P(SharedErrors, ZeroDiameter)
{
  expect_error(two_atoms("-1", "1", fix(" diameter 0")),
               {"Fix " + style() + " diameter must be > 0"});
}

TEST_P(SharedErrors, BadWallFace)
{
  expect_error(two_atoms("-1", "1", fix(" diameter 1.0 wall xmid 0")),
               {"Fix " + style() + " wall face must be", "xmid"});
  expect_error(two_atoms("-1", "1", fix(" diameter 1.0 wall qlo 1")),
               {"Fix " + style() + " wall face must be"});
}

TEST_P(SharedErrors, WallGivenTwice)
{
  expect_error(two_atoms("-1", "1", fix(" diameter 1.0 wall ylo -4 wall ylo -3")),
               {"Fix " + style() + " wall ylo given twice"});
  expect_error(two_atoms("-1", "1", fix(" diameter 1.0 wall xlo -4.0 wall xlo 3")),
               {"Fix " + style() + " wall xlo given twice"});
}

TEST_P(SharedErrors, DiameterGivenTwice)
{
  // (the last one silently won before)
  expect_error(two_atoms("-1", "1", fix(" diameter 1.0 diameter 0.5")),
               {"Fix " + style() + " diameter given twice (1 and 0.5)"});
}

// a wall below the box's fixed lower face (box -5 to 5): the spheres left
// the box ("Lost atoms") before they reached it
TEST_P(SharedErrors, WallOutsideAFixedBox)
{
  expect_error(two_atoms("-1", "1", fix(" diameter 1.0 wall xlo -6.0")),
               {"Fix " + style() + " wall xlo at -6 lies outside the box (-5 to 5 on a fixed "
                "boundary)"});
  expect_error(two_atoms("-1", "1", fix(" diameter 1.0 wall yhi 5.5")),
               {"Fix " + style() + " wall yhi at 5.5 lies outside the box"});
  // inside, at the face, and outside a shrink-wrapped face: runs
  for (const std::string &w : {" wall xlo -4.5", " wall xlo -5.0"}) {
    RunResult r = run_lmp(two_atoms("-1", "1", fix(" diameter 1.0" + w)));
    EXPECT_EQ(r.exit_code, 0) << w << "\n" << r.output;
  }
  expect_runs(two_atoms("-1", "1", fix(" diameter 1.0 wall xlo -6.0"), "", "m f f"));
}

// EDGE on a shrink-wrapped face: the box edge is the outermost centre, so
// the wall went through that sphere ("atom 1 is 0.5 through wall", blaming
// the configuration)
TEST_P(SharedErrors, WallAtTheEdgeOfAShrinkWrappedFace)
{
  expect_error(two_atoms("-1", "1", fix(" diameter 1.0 wall xlo EDGE"), "", "s f f"),
               {"Fix " + style() + " wall xlo EDGE on a shrink-wrapped face (boundary s)"});
  expect_runs(two_atoms("-1", "1", fix(" diameter 1.0 wall xlo EDGE"), "", "f f f"));
}

TEST_P(SharedErrors, SecondIntegratorOnSameAtoms)
{
  // defined before the hardsphere fix ...
  expect_error(two_atoms("-1", "1", fix(" diameter 1.0"), "fix mynve all nve\n"),
               {"mynve", "hs", "nve", style(), "both time-integrate"});
  // ... and after it
  expect_error(two_atoms("-1", "1", fix(" diameter 1.0\nfix 2 all nve")),
               {"both time-integrate the atoms common to group all and group all"});
  // a subgroup: the message names both groups
  expect_error(two_atoms("-1", "1", fix(" diameter 1.0\ngroup half id 1\nfix 2 half nve")),
               {"both time-integrate the atoms common to group all and group half"});
  // a Nose-Hoover thermostat or barostat: the message says what gives the
  // ensemble beside this fix
  expect_error(two_atoms("-1", "1", fix(" diameter 1.0\nfix t all nvt temp 1 1 0.5")),
               {"fix t nvt both time-integrate", "fix langevin"});
  expect_error(two_atoms("-1", "1", fix(" diameter 1.0\nfix t all npt temp 1 1 0.5 iso 1 1 5"),
                         "", "p p p"),
               {"fix t npt both time-integrate", "fix hardsphere/press"});
}

// run_style respa calls fixes' *_respa stages only: without the error the
// atoms stood still (measured: 4000-atom fluid, pe unchanged over 10 steps)
TEST_P(SharedErrors, RunStyleRespa)
{
  expect_error(two_atoms("-1", "1", fix(" diameter 1.0"), "run_style respa 2 2\n"),
               {"Fix " + style() + " does not support run_style respa", "run_style verlet"});
}

// atoms deleted between runs and a run that skips its set-up: the fix's
// references of the last list build are by local index (atom 2 now sits
// where atom 1's were); without the check a step would read them as its own
TEST_P(SharedErrors, AtomsDeletedBeforeRunPreNo)
{
  expect_error(two_atoms("-1", "1", fix(" diameter 1.0"), "",
                         "f f f") + "group first id 1\ndelete_atoms group first\nrun 10 pre no\n",
               {"Fix " + style() + ": 1 owned and 0 ghost atoms on rank 0 at step 11, 2 and 0 "
                "when the neighbor lists", "run ... pre no", "pre yes"});
  // the same deletion with the set-up runs
  expect_runs(two_atoms("-1", "1", fix(" diameter 1.0")) +
              "group first id 1\ndelete_atoms group first\nrun 10\n");
}

// a change between runs that keeps every rank's atom counts (a position, a
// mass, a radius, the box), then a run that skips its set-up: LAMMPS builds
// no lists and the ghosts keep their old copies; the fix would go on from
// the old state (measured before the check: "set density" left momentum
// off by 5e-3 on 2 ranks and each rank count on another trajectory). A run
// with only velocities changed goes on as a run with its set-up does
TEST_P(SharedErrors, StateChangedBeforeRunPreNo)
{
  const std::vector<std::string> needles = {
      "Fix " + style() + ": the atoms' positions, radii or masses, or the box, changed since "
      "the last run ended", "run ... pre no", "pre yes"};
  const std::string base = two_atoms("-1", "1", fix(" diameter 1.0"), "", "f f f");
  expect_error(base + "displace_atoms all move 0.1 0 0 units box\nrun 10 pre no\n", needles);
  expect_error(base + "mass 1 2.0\nrun 10 pre no\n", needles);
  expect_error(base + "change_box all x final -6 5 units box\nrun 10 pre no\n", needles);
  // per-atom radius and mass (atom style sphere, no diameter keyword)
  std::string sph = two_atoms("-1", "1", fix(""), "set atom * diameter 1.0\n", "f f f", "sphere");
  sph.replace(sph.find("mass 1 1.0\n"), 11, "");    // (per-atom masses: set by the diameter)
  expect_error(sph + "set atom 2 diameter 0.8\nrun 10 pre no\n", needles);
  expect_error(sph + "set atom 2 density 3.0\nrun 10 pre no\n", needles);
  // velocities changed, positions kept: runs, as with its set-up
  for (const std::string &pre : {"no", "yes"}) {
    expect_runs(base + "velocity all set 0.5 0 0\nrun 10 pre " + pre +
                    "\nprint \"END $(x[1]:%.15g)\"\n",
                {"END -0.975"});
  }
}

// the fix defined between runs, then a run without set-up: the fix had no
// list build, references or forces of its own (a segmentation fault before)
TEST_P(SharedErrors, FixDefinedBeforeRunPreNo)
{
  expect_error(two_atoms("-1", "1", "fix nv all nve", "", "f f f") + "unfix nv\n" +
                   fix(" diameter 1.0") + "\nrun 10 pre no\n",
               {"Fix " + style() + " was defined after the last run, and this run skipped its "
                "set-up (run ... pre no)", "pre yes"});
}

// minimize, then a run without set-up: the minimizer rebuilt the lists and
// ghosts without this fix (ended in the atom-count error, naming other
// commands); with pre yes the run goes on
TEST_P(SharedErrors, MinimizeBeforeRunPreNo)
{
  const std::string base = two_atoms("-1", "1", fix(" diameter 1.0"), "", "f f f") +
      "minimize 1e-4 1e-6 10 100\n";
  expect_error(base + "run 10 pre no\n",
               {"Fix " + style() + ": a minimization ran since the last run, and this run "
                "skipped its set-up (run ... pre no)", "use pre yes after minimize"});
  expect_runs(base + "run 10\n");
}

// fix wall/reflect moves atoms after the fix's step without regard to the
// contacts: it ended in "a collision was missed" some steps later
// (measured: a 2048-atom fluid, step 44); now an error naming the wall keyword
TEST_P(SharedErrors, WallReflectOnTheSameAtoms)
{
  expect_error(two_atoms("-1", "1", fix(" diameter 1.0\nfix wr all wall/reflect xlo EDGE")),
               {"Fix " + style() + " cannot run beside fix wr wall/reflect", "wall keyword"});
}

// the impulses enter the global virial only: a per-atom virial compute is
// warned about (its stresses summed to the pressure without the collisions,
// silently)
TEST_P(SharedErrors, PerAtomStressWarns)
{
  expect_runs(two_atoms("-1", "1", fix(" diameter 1.0"), "compute sa all stress/atom NULL\n"),
              {"compute sa stress/atom leaves out the collisions' virial"});
  RunResult q = run_lmp(two_atoms("-1", "1", fix(" diameter 1.0")));
  EXPECT_EQ(q.output.find("leaves out the collisions' virial"), std::string::npos) << q.output;
}

// an atom lost through a non-periodic face under thermo_modify lost ignore
// leaves at a reneighboring, whose list build renews the references: the run
// goes on (it stopped with the error above: LAMMPS counts the lost atom in
// atom->natoms only at the next thermo output, after that build)
TEST_P(SharedErrors, LostAtomIgnored)
{
  const std::string input =
      "units lj\natom_style atomic\natom_modify map array\nboundary f f f\n"
      "region box block -5 5 -5 5 -5 5\ncreate_box 1 box\n"
      "create_atoms 1 single -1 0 0\ncreate_atoms 1 single 1 0 0\n"
      "create_atoms 1 single 0 3 0\nmass 1 1.0\nvelocity all set 0 0 0\n"
      "group fly id 1\nvelocity fly set -2 0 0\npair_style zero 2.0\npair_coeff * *\n"
      "neighbor 0.3 bin\n" + fix(" diameter 1.0") +
      "\nthermo_modify lost ignore\nthermo 50\ntimestep 0.01\nrun 300\n"
      "print \"ATOMS $(atoms) STEP $(step)\"\n";
  expect_runs(input, {"\nATOMS 2 STEP 300"});
}

// neighbor multi lists each type pair to its pair cutoff + skin, not to
// the contact list's own cutoff: pure hard spheres (no pair style) lost
// every pair and collided 15 % deep before an overlap error. An error; with
// pair cutoffs that reach the contact list (the list copied), multi runs
TEST_P(SharedErrors, NeighborMultiWithoutTheContactList)
{
  const std::string pure = "neighbor 0.3 multi\n";
  expect_error(two_atoms("-1", "1", fix(" diameter 1.0"), pure),
               {"Fix " + style() + " needs its contact list out to 1.6",
                "neighbor multi does not build (with no pair style it lists no pairs)",
                "use neighbor 0.3 bin"});
  expect_runs(two_atoms("-1", "1", fix(" diameter 1.0"),
                        "pair_style lj/cut 2.5\npair_coeff 1 1 1.0 1.0\n" + pure));
}

// a negative timestep: contacts are predicted within [0, dt], so none was
// found and the spheres ran into each other ("a collision was missed"
// some steps later); fix nve runs backwards, these do not
TEST_P(SharedErrors, NegativeTimestep)
{
  expect_error(two_atoms("-1", "1", fix(" diameter 1.0"), "timestep -0.005\n"),
               {"Fix " + style() + ": the timestep -0.005 is negative", "negate the velocities"});
  expect_runs(two_atoms("-1", "1", fix(" diameter 1.0"), "timestep 0.005\n"));
}

// pcva, mcva and vci keep an energy of the whole system; a conservative
// fix's force whose energy is not in the potential energy (fix_modify ...
// energy no, most fixes' default) changes it, and the method undid that:
// spheres falling under fix gravity lost kinetic energy to pcva's
// projection. Now an error naming the fix and fix_modify; with the energy
// on, or with psa or cva (which keep no energy), the run goes on
TEST_P(SharedErrors, ConservativeFixWithoutItsEnergy)
{
  const std::string method = GetParam();
  const std::string base = fix(" diameter 1.0") + "\nfix g all gravity 1.0 vector 0 0 -1";
  const bool keeps_energy = method == "pcva" || method == "mcva" || method == "vci";
  if (keeps_energy)
    expect_error(two_atoms("-1", "1", base),
                 {"Fix " + style(), "fix g gravity adds forces whose energy is not in the "
                  "potential energy", "fix_modify <fix-ID> energy yes"});
  else {
    expect_runs(two_atoms("-1", "1", base));
  }
  expect_runs(two_atoms("-1", "1", base + "\nfix_modify g energy yes"));
}

INSTANTIATE_TEST_SUITE_P(PSA, SharedErrors, ::testing::Values("psa"), case_name);
INSTANTIATE_TEST_SUITE_P(CVA, SharedErrors, ::testing::Values("cva"), case_name);
INSTANTIATE_TEST_SUITE_P(PCVA, SharedErrors, ::testing::Values("pcva"), case_name);
INSTANTIATE_TEST_SUITE_P(MCVA, SharedErrors, ::testing::Values("mcva"), case_name);
INSTANTIATE_TEST_SUITE_P(VCI, SharedErrors, ::testing::Values("vci"), case_name);
