// fix hardsphere/psa: invalid set-ups end in an ERROR naming the problem
// (psa's own check that a sphere's flight after a collision stays within
// the neighbor skin; the base class's checks, with psa's name, are in
// test_shared_errors.cpp).
// LAMMPS here is built without exceptions: each case runs in its own lmp
// process through run_lmp().

#include "hs_errors.h"

#include <string>

using hs_errors::expect_error;

namespace {

// two atoms of types 1 and 2 (masses m1, m2) at (x1,0,0) and (x2,0,0)
// with x-velocities v1, v2
std::string two_atoms(const std::string &x1, const std::string &x2, const std::string &fix,
                      const std::string &extra = "", const std::string &v1 = "0",
                      const std::string &v2 = "0", const std::string &m1 = "1.0",
                      const std::string &m2 = "1.0", const std::string &dt = "0.005")
{
  return "units lj\natom_style atomic\natom_modify map array\nboundary f f f\n"
         "region box block -5 5 -5 5 -5 5 units box\ncreate_box 2 box\n"
         "create_atoms 1 single " + x1 + " 0 0 units box\n"
         "create_atoms 2 single " + x2 + " 0 0 units box\n"
         "mass 1 " + m1 + "\nmass 2 " + m2 + "\nset atom 1 vx " + v1 + "\nset atom 2 vx " + v2 +
      "\ncomm_modify cutoff 3.0\ntimestep " + dt + "\n" + extra + fix + "\nrun 10\n";
}

}    // namespace

TEST(PSAErrors, ValidBaselineRuns)
{
  expect_runs(
      two_atoms("-1", "1", "fix hs all hardsphere/psa diameter 1.0 wall xlo -4", "", "1", "-1"), {},
      {"ERROR"});
}

TEST(PSAErrors, StepLongerThanSkinAllows)
{
  // 5 x dt at speed 1 > skin 0.3: screening refuses the step
  expect_error(two_atoms("-2", "2", "fix hs all hardsphere/psa diameter 1.0", "", "1", "0",
                         "1.0", "1.0", "0.5"),
               {"atom 1 may be", "more than the skin"});
}

TEST(PSAErrors, FlightAfterCollisionBeyondSkin)
{
  // a heavy sphere (mass 10, v = 1, dt 0.25: 0.25 < skin 0.3 per step) hits
  // a light one (mass 0.1) 0.05 into the step: the light one leaves at
  // 2 x 10/10.1 ~ 1.98 and would fly 0.2 x 1.98 ~ 0.4 > skin in the rest of
  // the step, out of the neighbor list's reach
  expect_error(two_atoms("-1.0", "0.05", "fix hs all hardsphere/psa diameter 1.0", "", "1", "0",
                         "10.0", "0.1", "0.25"),
               {"atom 2 may be", "after a collision", "more than the skin"});
}

TEST(PSAErrors, SameCollisionWithSmallerStepRuns)
{
  // the previous case with dt 0.1 is fine, and collides
  expect_runs(two_atoms("-1.0", "0.05", "fix hs all hardsphere/psa diameter 1.0", "", "1", "0",
                        "10.0", "0.1", "0.1") +
                  "print \"RESULT $(f_hs[2])\"\n",
              {"\nRESULT 1"});
}
