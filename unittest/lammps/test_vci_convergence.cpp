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

#include "hs_test_main.h"

#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>

namespace {

std::string slurp(const std::string &path)
{
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

struct ChainRun {
  double dEmax = -1.0, ncoll = -1.0;
  double solved = -1, fallback = -1, zero = -1, evals = -1, maxevals = -1, maxdiff = -1;
};

ChainRun run_chain(double dt, double T, int seed)
{
  ChainRun r;
  char dts[32];
  snprintf(dts, sizeof(dts), "%.17g", dt);
  const std::string out = "vci_conv_dE_" + std::to_string(dt) + ".txt";
  std::string input = slurp(std::string(HS_SOURCE_DIR) + "/examples/pendulum-chain/in.pendulum-chain");
  input += "print \"VCI $(f_hs[6]) $(f_hs[7]) $(f_hs[8]) $(f_hs[9]) $(f_hs[10]) $(f_hs[11]:%.6e)\"\n";
  RunResult res = run_lmp(input, {"-var", "method", "vci", "-var", "dt", dts, "-var", "T",
                                  std::to_string(T), "-var", "seed", std::to_string(seed), "-var", "out", out});
  EXPECT_EQ(res.exit_code, 0) << res.output;
  std::smatch m;
  std::regex re(R"((?:^|\n)pendulum chain: [^\n]*: ([0-9.eE+-]+) collisions)");
  if (std::regex_search(res.output, m, re)) r.ncoll = std::stod(m[1]);
  else ADD_FAILURE() << "no summary line in output:\n" << res.output;
  std::regex rv(R"((?:^|\n)VCI ([0-9.eE+-]+) ([0-9.eE+-]+) ([0-9.eE+-]+) ([0-9.eE+-]+) ([0-9.eE+-]+) ([0-9.eE+-]+))");
  if (std::regex_search(res.output, m, rv)) {
    r.solved = std::stod(m[1]);
    r.fallback = std::stod(m[2]);
    r.zero = std::stod(m[3]);
    r.evals = std::stod(m[4]);
    r.maxevals = std::stod(m[5]);
    r.maxdiff = std::stod(m[6]);
  } else
    ADD_FAILURE() << "no VCI line in output:\n" << res.output;
  std::ifstream in(out);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    double step, dE;
    if (ls >> step >> dE) r.dEmax = std::max(r.dEmax, dE);
  }
  std::remove(out.c_str());
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
    ChainRun r = run_chain(dt, T, seed);
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
  const double n = (double) lx.size();
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (size_t k = 0; k < lx.size(); k++) {
    sx += lx[k];
    sy += ly[k];
    sxx += lx[k] * lx[k];
    sxy += lx[k] * ly[k];
  }
  const double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
  printf("[ vci conv ] fitted order %.3f\n", slope);
  EXPECT_GE(slope, 1.6);
  EXPECT_LE(slope, 2.6);
}
