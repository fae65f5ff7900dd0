// fix hardsphere/mcva where the answer is known: with no smooth forces
// H~ = H, the Gauss flow is exact free flight and alpha-hat is the elastic
// alpha: two-sphere collisions must match the analytic outcome (free flight
// to the root of |dq + t dv| = sigma, elastic impulse, free flight;
// hs_two_body.h) to round-off, also across periodic boundaries and with
// per-atom radius and mass. (The no-collision run that must be fix nve bit for
// bit is in test_nve_bitwise.cpp, the restart of the counters in
// test_restart_counters.cpp.)

#include "hs_two_body.h"

using namespace hs_two_body;

namespace {

// the Gauss flow is exact only to the stage solver's tolerance: positions to
// 1e-11; and the Gauss sub-steps go to and from the contact
void check_mcva(Body a, Body b, double dt, int nsteps, bool sphere_style, bool periodic)
{
  check_two_body("mcva", a, b, dt, nsteps, sphere_style, periodic, 20.0, 1e-11, [](HSLammps &h) {
    EXPECT_GE(h.fix_vector("hs", 6), 2.0);    // Gauss sub-steps: to and from the contact
    EXPECT_GE(h.fix_vector("hs", 5), 1.0);    // stage iterations
    EXPECT_GE(h.fix_vector("hs", 8), 1.0);    // Gauss solves
    EXPECT_EQ(h.fix_vector("hs", 9), 0.0);    // nothing missed
  });
}

}    // namespace

TEST(MCVAFreeFlight, HeadOnUnequalMasses)
{
  check_mcva({{-1.0, 0.0, 0.0}, {1.0, 0.0, 0.0}, 1.0, 0.5},
             {{1.0, 0.0, 0.0}, {-0.5, 0.0, 0.0}, 3.0, 0.5}, 0.01, 150, false, false);
}

TEST(MCVAFreeFlight, Oblique3DStepNotMultiple)
{
  check_mcva({{-1.0, 0.1, -0.2}, {0.9, 0.05, 0.1}, 1.0, 0.5},
             {{1.1, -0.2, 0.1}, {-0.7, 0.1, -0.05}, 1.0, 0.5}, 0.0137, 111, false, false);
}

TEST(MCVAFreeFlight, PerAtomRadiusMassAcrossPeriodicBoundary)
{
  check_mcva({{19.2, 5.0, 5.1}, {0.8, 0.1, 0.0}, 2.0, 0.4},
             {{1.0, 5.2, 5.0}, {-0.6, 0.0, 0.05}, 0.7, 0.6}, 0.01, 120, true, true);
}
