// fix hardsphere/cva is second order (Bond & Leimkuhler 2007, section 2.2 /
// section 4): on the 5-sphere impact pendulum chain the maximal energy error
// over a fixed horizon scales like dt^2.

#include "hs_chain.h"

using hs_chain::ChainRun;

TEST(CVAConvergence, PendulumChainEnergyErrorSecondOrder)
{
  const double T = 20.0;
  const std::vector<double> dts = {0.04, 0.02, 0.01, 0.005};
  std::vector<double> lx, ly;
  for (double dt : dts) {
    ChainRun r = hs_chain::run_chain("cva", dt, T, 1);
    // the run has collisions of both kinds, and a per-step series
    EXPECT_GT(r.ncoll, 0.0) << "dt " << dt;
    EXPECT_GT(r.npair, 0.0) << "dt " << dt;
    EXPECT_GT(r.nwall, 0.0) << "dt " << dt;
    EXPECT_EQ(r.ncoll, r.npair + r.nwall);
    EXPECT_GE(r.nsamples, std::lround(T / dt));
    ASSERT_GT(r.dEmax, 0.0) << "dt " << dt;
    EXPECT_LT(r.dEmax, 0.1) << "dt " << dt;
    lx.push_back(std::log(dt));
    ly.push_back(std::log(r.dEmax));
    printf("[ cva conv ] dt %-6g collisions %g (%g pair, %g wall)  max|H-H0| %.4e\n", dt, r.ncoll,
           r.npair, r.nwall, r.dEmax);
  }
  // least-squares slope of log max|dE| against log dt
  const double slope = hs_chain::fitted_slope(lx, ly);
  printf("[ cva conv ] fitted order %.3f\n", slope);
  EXPECT_GE(slope, 1.6);
  EXPECT_LE(slope, 2.6);
}
