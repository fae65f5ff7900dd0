// fix hardsphere/psa without collisions is velocity Verlet (the plain cases
// for every method are in test_nve_bitwise.cpp). Here psa's own path: steps
// in which screening marks spheres as possibly touching run the event-driven
// path (half kick, predictions, drift), find nothing, and must still
// reproduce fix nve bit for bit.

#include "hs_state.h"

using hs_state::State;

TEST(PSANoCollision, LJFluidNearMissesBitwiseFixNVE)
{
  // hard cores of diameter 0.75 in the LJ fluid: neighbours come within a
  // few hundredths of contact, so screening sends many steps through the
  // event-driven path and none collides
  const std::string setup = hs_state::lj_fluid(5);
  const std::string tail = "run 300\n";
  State nve = hs_state::run_case(setup, "fix int all nve", tail);
  State hs = hs_state::run_case(setup, "fix int all hardsphere/psa diameter 0.75", tail);
  EXPECT_EQ(hs.ncoll, 0.0);
  hs_state::expect_identical(nve, hs);
}
