// Every hardsphere fix without collisions is velocity Verlet, done with fix
// nve's arithmetic: a run in which no contact happens must reproduce fix nve
// bit for bit (positions, velocities, image flags, pe, ke).
//  - psa (section 2.1): half kick + free flight over dt + half kick;
//  - cva (section 2.2): the collision Verlet step with no collision is the
//    Verlet step;
//  - pcva (section 3.2): only steps with collisions are projected, so the
//    projection counter stays 0 as well;
//  - mcva (section 3.1: "When there is no collision, the method is simply the
//    standard Verlet method"): no Gauss sub-step either.
// One suite, instantiated per method (test names start with the method).

#include "hs_state.h"

#include <algorithm>

using hs_state::State;

namespace {

struct NoCollisionCase {
  const char *method;
  int lj_cells;       // LJ fluid box: lj_cells^3 fcc cells
  int lj_steps;       // length of the LJ fluid run
  int zero_counter;   // 0-based entry of the fix vector that must stay 0 too (-1: none)
};

class NoCollision : public ::testing::TestWithParam<NoCollisionCase> {
 protected:
  std::string fix(const std::string &group, const std::string &diameter) const
  {
    return "fix int " + group + " hardsphere/" + GetParam().method + " diameter " + diameter;
  }
  int ncounters() const { return std::max(GetParam().zero_counter + 1, 1); }
  void expect_zero_counter(const State &s) const
  {
    const int k = GetParam().zero_counter;
    if (k >= 0) EXPECT_EQ(s.counters.at(k), 0.0) << "fix vector entry " << k + 1;
  }
};

std::string case_name(const ::testing::TestParamInfo<NoCollisionCase> &info)
{
  return info.param.method;
}

}    // namespace

TEST_P(NoCollision, LJFluidBitwiseFixNVE)
{
  const std::string setup = hs_state::lj_fluid(GetParam().lj_cells);
  const std::string tail = "run " + std::to_string(GetParam().lj_steps) + "\n";
  State nve = hs_state::run_case(setup, "fix int all nve", tail);
  State hs = hs_state::run_case(setup, fix("all", "0.5"), tail, ncounters());
  EXPECT_EQ(hs.ncoll, 0.0);
  expect_zero_counter(hs);
  hs_state::expect_identical(nve, hs);
  // the systems did move (compare with the lattice is not needed: ke changed)
  EXPECT_GT(nve.ke, 0.0);
}

TEST_P(NoCollision, BondedChainBitwiseFixNVE)
{
  const std::string setup = hs_state::bonded_chain();
  const std::string tail = "run 500\n";
  State nve = hs_state::run_case(setup, "fix int chain nve", tail);
  State hs = hs_state::run_case(setup, fix("chain", "0.05"), tail, ncounters());
  EXPECT_EQ(hs.ncoll, 0.0);
  expect_zero_counter(hs);
  hs_state::expect_identical(nve, hs);
  // the anchor stayed put in both
  EXPECT_EQ(hs.x[0], 0.0);
  EXPECT_EQ(hs.x[1], 0.0);
}

// Spheres the screen flags on most steps (diameter 0.8 in the LJ fluid: free
// gaps of a few hundredths) that never touch (LJ is ~50 epsilon at r = 0.8):
// the local engine's steps with flagged spheres. After a first guess that
// found nothing it tests the flagged spheres' pairs and walls alone
// (quick_clear(), counted in the engine's entry 8); the run must still be
// fix nve's bit for bit, and that path must have been taken
class NoCollisionFlagged : public ::testing::TestWithParam<std::pair<const char *, int>> {};

TEST_P(NoCollisionFlagged, LJFluidBitwiseFixNVE)
{
  const std::string setup = hs_state::lj_fluid(5);
  const std::string tail = "run 300\n";
  const int quick = GetParam().second;    // 0-based entry of the quick-cleared steps
  State nve = hs_state::run_case(setup, "fix int all nve", tail);
  State hs = hs_state::run_case(
      setup, std::string("fix int all hardsphere/") + GetParam().first + " diameter 0.8", tail,
      quick + 1);
  EXPECT_EQ(hs.ncoll, 0.0);
  EXPECT_GT(hs.counters.at(quick), 50.0) << "steps the flagged spheres' pairs cleared";
  hs_state::expect_identical(nve, hs);
}

INSTANTIATE_TEST_SUITE_P(Local, NoCollisionFlagged,
                         ::testing::Values(std::make_pair("cva", 12), std::make_pair("pcva", 15)),
                         [](const ::testing::TestParamInfo<std::pair<const char *, int>> &info) {
                           return std::string(info.param.first);
                         });

// entry [6] of pcva is the number of projections, entry [7] of mcva the
// number of Gauss sub-steps
INSTANTIATE_TEST_SUITE_P(PSA, NoCollision, ::testing::Values(NoCollisionCase{"psa", 5, 300, -1}),
                         case_name);
INSTANTIATE_TEST_SUITE_P(CVA, NoCollision, ::testing::Values(NoCollisionCase{"cva", 5, 300, -1}),
                         case_name);
INSTANTIATE_TEST_SUITE_P(PCVA, NoCollision, ::testing::Values(NoCollisionCase{"pcva", 4, 200, 5}),
                         case_name);
INSTANTIATE_TEST_SUITE_P(MCVA, NoCollision, ::testing::Values(NoCollisionCase{"mcva", 4, 200, 6}),
                         case_name);
INSTANTIATE_TEST_SUITE_P(VCI, NoCollision, ::testing::Values(NoCollisionCase{"vci", 4, 200, -1}),
                         case_name);
