// fix hardsphere/vci on the 5-sphere impact pendulum chain (Bond &
// Leimkuhler 2007, sections 2.3 and 4): the energy error is second order in
// dt, and every contact matches the discrete energy of the sub-steps before
// and after it to round-off (the fix's own measurement, f_ID[11]).
//
// VCI changes H at each contact by (tau1^2 D- - tau2^2 D+)/4 + O(dt^3)
// (D = v^T V'' v - |grad V|^2_{M^-1}/2, tau1 and tau2 the sub-steps before
// and after): second order, but with a factor that depends on where in its
// step each contact falls, so max|H - H0| of one run scatters by factors of
// 3 around the dt^2 line. The order is fitted to the geometric mean over
// three initial conditions (seeds) and five timesteps.

#include "hs_chain.h"

namespace {

struct VCIRun : hs_chain::ChainRun {
  double solved = -1, fallback = -1, zero = -1, evals = -1, maxevals = -1, maxdiff = -1;
};

// the chain with vci and its own counters f_ID[6..11]
VCIRun run_chain(double dt, double T, int seed)
{
  VCIRun r;
  static_cast<hs_chain::ChainRun &>(r) = hs_chain::run_chain(
      "vci", dt, T, seed,
      {"$(f_hs[6])", "$(f_hs[7])", "$(f_hs[8])", "$(f_hs[9])", "$(f_hs[10])", "$(f_hs[11]:%.6e)"});
  r.solved = r.extra[0];
  r.fallback = r.extra[1];
  r.zero = r.extra[2];
  r.evals = r.extra[3];
  r.maxevals = r.extra[4];
  r.maxdiff = r.extra[5];
  return r;
}

}    // namespace

TEST(VCIConvergence, PendulumChainSecondOrderAndDiscreteEnergyMatched)
{
  const double T = 20.0;
  const std::vector<double> dts = {0.04, 0.02, 0.01, 0.005, 0.0025};
  std::vector<double> lx, ly;
  for (double dt : dts) {
    double logsum = 0.0;
    for (int seed = 1; seed <= 3; seed++) {
    VCIRun r = run_chain(dt, T, seed);
    printf("[ vci conv ] dt %-6g seed %d collisions %g: solved %g, elastic fallback %g, tau2=0 %g; "
           "%g evaluations of E_d+ (max %g per contact); max|E_d+ - E_d-| %.2e; max|H-H0| %.4e\n",
           dt, seed, r.ncoll, r.solved, r.fallback, r.zero, r.evals, r.maxevals, r.maxdiff, r.dEmax);
    EXPECT_GT(r.ncoll, 0.0) << "dt " << dt;
    // every collision is either solved or accounted for
    EXPECT_EQ(r.solved + r.fallback + r.zero, r.ncoll) << "dt " << dt;
    EXPECT_GE(r.solved, 0.9 * r.ncoll) << "dt " << dt;
    EXPECT_LT(r.maxdiff, 1e-13) << "dt " << dt;    // energies ~ 1
    EXPECT_LE(r.maxevals, 20.0) << "dt " << dt;
    ASSERT_GT(r.dEmax, 0.0) << "dt " << dt;
    logsum += std::log(r.dEmax);
    }
    lx.push_back(std::log(dt));
    ly.push_back(logsum / 3.0);
    printf("[ vci conv ] dt %-6g geometric mean of max|H-H0| %.4e\n", dt, std::exp(ly.back()));
  }
  const double slope = hs_chain::fitted_slope(lx, ly);
  printf("[ vci conv ] fitted order %.3f\n", slope);
  EXPECT_GE(slope, 1.6);
  EXPECT_LE(slope, 2.6);
}
