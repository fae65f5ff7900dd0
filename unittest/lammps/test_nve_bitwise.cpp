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
