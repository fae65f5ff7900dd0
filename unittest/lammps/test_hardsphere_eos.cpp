// A pure hard-sphere fluid with psa (its event-driven use case) and cva: the
// pressure from the collision (impulse) virial follows the Carnahan-Starling
// equation of state, the collision rate the Enskog frequency, and the
// temperature is conserved to round-off, since elastic collisions and free
// flight conserve it exactly. One suite, instantiated per method (test names
// start with the method).

#include "hs_test_main.h"

#include "hs_eos.h"

namespace {

class HardSphereFluid : public ::testing::TestWithParam<const char *> {};

std::string case_name(const ::testing::TestParamInfo<const char *> &info)
{
  return info.param;
}

}    // namespace

TEST_P(HardSphereFluid, CarnahanStarlingAndTemperatureConservation)
{
  hs_eos::carnahan_starling(GetParam(), "region box block 0 5 0 5 0 5", "eos ");
}

INSTANTIATE_TEST_SUITE_P(PSA, HardSphereFluid, ::testing::Values("psa"), case_name);
INSTANTIATE_TEST_SUITE_P(CVA, HardSphereFluid, ::testing::Values("cva"), case_name);
