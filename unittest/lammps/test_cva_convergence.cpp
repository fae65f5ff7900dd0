// fix hardsphere/cva is second order (Bond & Leimkuhler 2007, section 2.2 /
// section 4): on the 5-sphere impact pendulum chain the maximal energy error
// over a fixed horizon scales like dt^2.

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
  double dEmax = -1.0;
  long nsamples = 0;
  double ncoll = -1.0, nwall = -1.0, npair = -1.0;
};

ChainRun run_chain(double dt, double T, int seed)
{
  ChainRun r;
  const std::string input = slurp(std::string(HS_SOURCE_DIR) + "/examples/pendulum-chain/in.pendulum-chain");
  EXPECT_FALSE(input.empty());
  char dts[32];
  snprintf(dts, sizeof(dts), "%.17g", dt);
  const std::string out = "cva_conv_dE_" + std::to_string(seed) + "_" + std::to_string(dt) + ".txt";
  RunResult res = run_lmp(input, {"-var", "method", "cva", "-var", "dt", dts, "-var", "T",
                                  std::to_string(T), "-var", "seed", std::to_string(seed),
                                  "-var", "out", out});
  EXPECT_EQ(res.exit_code, 0) << res.output;
  std::smatch m;
  // the summary line printed by the input (not its echo, which starts with "print")
  std::regex re(R"((?:^|\n)pendulum chain: [^\n]*: ([0-9.eE+-]+) collisions \(([0-9.eE+-]+) sphere-sphere, ([0-9.eE+-]+) wall\))");
  if (std::regex_search(res.output, m, re)) {
    r.ncoll = std::stod(m[1]);
    r.npair = std::stod(m[2]);
    r.nwall = std::stod(m[3]);
  } else
    ADD_FAILURE() << "no summary line in output:\n" << res.output;
  std::ifstream in(out);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    double step, dE;
    if (ls >> step >> dE) {
      r.dEmax = std::max(r.dEmax, dE);
      r.nsamples++;
    }
  }
  std::remove(out.c_str());
  return r;
}

}    // namespace

TEST(CVAConvergence, PendulumChainEnergyErrorSecondOrder)
{
  const double T = 20.0;
  const std::vector<double> dts = {0.04, 0.02, 0.01, 0.005};
  std::vector<double> lx, ly;
  for (double dt : dts) {
    ChainRun r = run_chain(dt, T, 1);
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
  const double n = (double) lx.size();
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (size_t k = 0; k < lx.size(); k++) {
    sx += lx[k];
    sy += ly[k];
    sxx += lx[k] * lx[k];
    sxy += lx[k] * ly[k];
  }
  const double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
  printf("[ cva conv ] fitted order %.3f\n", slope);
  EXPECT_GE(slope, 1.6);
  EXPECT_LE(slope, 2.6);
}
