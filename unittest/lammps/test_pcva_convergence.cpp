// fix hardsphere/pcva on the 5-sphere impact pendulum chain (Bond &
// Leimkuhler 2007, section 4): the energy error is second order in dt
// (fig. 4.2), and the modified Hamiltonian H_[2,VV] is kept far better than
// by hardsphere/cva (fig. 4.3). H_[2,VV] is evaluated independently from a
// dump (hs_modified_energy.h).

#include "hs_chain.h"

#include "hs_modified_energy.h"

#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>

using namespace hs_test;

namespace {

const std::string CHAIN = hs_chain::chain_path();

struct ChainRun {
  double dEmax = -1.0, ncoll = -1.0, nskip = -1.0;
};

// the chain with pcva (seed 1) and its count of unprojected sub-steps f_ID[7]
ChainRun run_chain(const std::string &method, double dt, double T)
{
  const hs_chain::ChainRun c = hs_chain::run_chain(method, dt, T, 1, {"$(f_hs[7])"});
  return {c.dEmax, c.ncoll, c.extra.at(0)};
}

// max |H~(t) - H~(0)| over a run of the chain, every step (independent H~)
double chain_modified_drift(const std::string &method, double dt, int nsteps)
{
  char dts[32];
  snprintf(dts, sizeof(dts), "%.17g", dt);
  HSLammps h({"-var", "method", method, "-var", "dt", dts, "-var", "T", "0", "-var", "seed", "1"});
  h.file(CHAIN);
  const std::string dump = scratch_name("conv_dump_" + method + ".txt");
  h.cmd("dump hsd all custom 1 " + dump + " id x y z vx vy vz");
  h.cmd("dump_modify hsd format float %.17g sort id");
  h.cmd("run " + std::to_string(nsteps));
  h.cmd("undump hsd");
  std::vector<HarmonicBond> bonds;
  std::map<int, double> masses;
  for (int i = 1; i <= 5; i++) {
    bonds.push_back({i, i + 1, 0.5, 1.0});
    masses[i + 1] = 1.0;
  }
  const std::vector<Frame> fr = read_dump(dump);
  std::remove(dump.c_str());
  EXPECT_EQ((int) fr.size(), nsteps + 1);
  if (fr.empty()) return -1.0;
  const double H0 = modified_energy(fr[0], bonds, masses, dt, 1.0, 1.0).Ht;
  double drift = 0.0;
  for (const Frame &f : fr)
    drift = std::max(drift, std::fabs(modified_energy(f, bonds, masses, dt, 1.0, 1.0).Ht - H0));
  return drift;
}

// the same with compute hamiltonian/modified (vector element 2: H_[2,VV])
double chain_modified_drift_compute(const std::string &method, double dt, int nsteps)
{
  char dts[32];
  snprintf(dts, sizeof(dts), "%.17g", dt);
  HSLammps h({"-var", "method", method, "-var", "dt", dts, "-var", "T", "0", "-var", "seed", "1"});
  h.file(CHAIN);
  const std::string out = scratch_name("conv_hm_" + method + ".txt");
  h.cmd("compute hm chain hamiltonian/modified");
  h.cmd("fix hmo all ave/time 1 1 1 c_hm[2] file " + out + " format \" %.17g\"");
  h.cmd("run " + std::to_string(nsteps));
  h.cmd("unfix hmo");
  const auto ser = read_series(out);
  std::remove(out.c_str());
  EXPECT_EQ((int) ser.size(), nsteps + 1);
  if (ser.empty()) return -1.0;
  const double H0 = ser.begin()->second.at(0);
  double drift = 0.0;
  for (const auto &kv : ser) drift = std::max(drift, std::fabs(kv.second.at(0) - H0));
  return drift;
}

}    // namespace

TEST(PCVAConvergence, PendulumChainEnergyErrorSecondOrder)
{
  const double T = 20.0;
  const std::vector<double> dts = {0.04, 0.02, 0.01, 0.005};
  std::vector<double> lx, ly;
  for (double dt : dts) {
    ChainRun r = run_chain("pcva", dt, T);
    EXPECT_GT(r.ncoll, 0.0) << "dt " << dt;
    EXPECT_EQ(r.nskip, 0.0) << "dt " << dt;
    ASSERT_GT(r.dEmax, 0.0) << "dt " << dt;
    lx.push_back(std::log(dt));
    ly.push_back(std::log(r.dEmax));
    printf("[ pcva conv ] dt %-6g collisions %g  max|H-H0| %.4e\n", dt, r.ncoll, r.dEmax);
  }
  const double slope = hs_chain::fitted_slope(lx, ly);
  printf("[ pcva conv ] fitted order %.3f\n", slope);
  EXPECT_GE(slope, 1.6);
  EXPECT_LE(slope, 2.6);
}

TEST(PCVAConvergence, ModifiedHamiltonianFarBetterThanCVA)
{
  // fig. 4.3 of the paper at dt = 0.02, here over T = 100 (5000 steps)
  const double dt = 0.02;
  const double p = chain_modified_drift("pcva", dt, 5000);
  const double c = chain_modified_drift("cva", dt, 5000);
  printf("[ pcva conv ] dt %g T 100: max|H~-H~0| pcva %.3e, cva %.3e (ratio %.0f)\n", dt, p, c,
         c / p);
  ASSERT_GT(p, 0.0);
  EXPECT_GT(c, 10.0 * p);
}

TEST(PCVAConvergence, ComputeHamiltonianModifiedAgrees)
{
  // compute hamiltonian/modified measures the same drift as the independent
  // evaluation above (over T = 50)
  const double dt = 0.02;
  const double p = chain_modified_drift("pcva", dt, 2500);
  const double pc = chain_modified_drift_compute("pcva", dt, 2500);
  const double c = chain_modified_drift("cva", dt, 2500);
  const double cc = chain_modified_drift_compute("cva", dt, 2500);
  printf("[ pcva conv ] dt %g T 50, compute hamiltonian/modified: max|H~-H~0| pcva %.3e "
         "(independent %.3e), cva %.3e (independent %.3e)\n",
         dt, pc, p, cc, c);
  EXPECT_NEAR(pc, p, 1e-12);
  EXPECT_NEAR(cc, c, 1e-12);
  EXPECT_GT(cc, 10.0 * pc);
}
