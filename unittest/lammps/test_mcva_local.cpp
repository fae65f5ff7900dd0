// fix hardsphere/mcva's local form, its default (issue 21,
// doc/fix_hardsphere_mcva.rst, "Local form"): each cluster's flow is the Gauss-Legendre flow of the
// cluster's modified Hamiltonian with alpha-hat impulses
// (hs_cluster_flow.h), and after the step the colliding spheres' velocities
// are projected so that the whole system's H~ = H_[2,VV] keeps its value
// (pcva's ledger, hs_local_modified.h). Expected values from theory, not
// from the method's output:
// - H~ (compute hamiltonian/modified, an independent evaluation) is kept to
//   fourth order: fitted order >= 3.6 on the 500-sphere fluid (mean of two
//   starts, 0.5 time units) and on the pendulum chain (T 50), at least 10x
//   below cva local's error at every dt;
// - the stage equations take a handful of Newton iterations per Gauss
//   solve (the exact Jacobian at each sub-step's start);
// - momentum is conserved (the partners take the terms' momentum, the
//   projection is relative to each cluster's centre of mass);
// - styles the local Gauss flow cannot take (angles) and fix_modify stages
//   fixed are named: an error with substep local; without it mcva falls
//   back to the global form with a warning;
// - local and global forms sample the same fluid: the collision rate and
//   the pressure over 3000 steps of a 108-sphere fluid agree within 4
//   combined standard errors (block averages; the global form costs a
//   force evaluation of the whole system per Gauss stage, so not on 4000
//   spheres: doc "Local form").

#include "hs_chain.h"
#include "hs_errors.h"
#include "hs_fluid.h"
#include "hs_test_main.h"

#include <cmath>
#include <cstdio>
#include <regex>
#include <string>
#include <vector>

namespace {

// max |H~(t) - H~(0)| per atom over time T on the 500-sphere fluid
double fluid_error(const std::string &method, double dt, int seed, double *newton = nullptr)
{
  HSLammps L;
  L.lines(hs_fluid::fluid("fix hs all hardsphere/" + method + " diameter 1.0 substep local", dt,
                          seed));
  L.lines(R"LMP(
compute hm all hamiltonian/modified
variable H2 equal c_hm[2]/atoms
thermo_style custom step etotal v_H2
run 0
variable E0 equal $(v_H2:%.17g)
variable dE equal abs(v_H2-v_E0)
fix mx all ave/histo 1 1 1 0.0 1.0 1 v_dE ave running
)LMP");
  L.cmd("run " + std::to_string((int) std::lround(0.5 / dt)));
  if (method == "mcva") {
    // entries 1-4 (0-based 5-8): Newton iterations, Gauss sub-steps, most
    // iterations of one solve, Gauss solves; 13: the engine's clusters
    const double it = L.fix_vector("hs", 5), sub = L.fix_vector("hs", 6),
                 mx = L.fix_vector("hs", 7), solves = L.fix_vector("hs", 8);
    EXPECT_GT(L.fix_vector("hs", 0), 100.0) << "collisions";
    EXPECT_GT(sub, 0.0) << "no local Gauss flow ran";
    EXPECT_GT(L.fix_vector("hs", 13), 0.0) << "the engine's clusters";
    if (newton) *newton = it / solves;
    EXPECT_LE(mx, 10.0) << "most Newton iterations of one solve";
  }
  return L.fix_vector("mx", 3);
}

// the chain's max |H~(t) - H~(0)| (examples/pendulum-chain, hmod 1)
double chain_error(const std::string &method, double dt)
{
  const std::string input = hs_chain::slurp(hs_chain::chain_path());
  const RunResult r = run_lmp(input, {"-var", "method", method, "-var", "dt", hs_chain::f17(dt),
                                      "-var", "T", "50", "-var", "hmod", "1", "-var", "substep",
                                      "local"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  std::smatch m;
  const std::regex re(R"(max\|H2-H2\(0\)\| ([0-9.eE+-]+))");
  if (!std::regex_search(r.output, m, re)) {
    ADD_FAILURE() << "no maxima line:\n" << r.output;
    return -1.0;
  }
  EXPECT_NE(r.output.find("substep local (collisions sub-stepped per cluster)"),
            std::string::npos)
      << method << " did not run locally";
  return std::stod(m[1]);
}

}    // namespace

TEST(MCVALocal, FluidModifiedHamiltonianFourthOrder)
{
  const std::vector<double> dts = {0.01, 0.005, 0.0025};
  std::vector<double> em;
  for (double dt : dts) {
    double e = 0.0, c = 0.0, newton = 0.0;
    for (int seed : {111, 222}) {
      double nw = 0.0;
      e += 0.5 * fluid_error("mcva", dt, seed, &nw);
      newton += 0.5 * nw;
      c += 0.5 * fluid_error("cva", dt, seed);
    }
    std::printf("dt %g mean max|dH~|/N: mcva local %.3e, cva local %.3e (%.0fx); Newton "
                "iterations per Gauss solve %.2f\n",
                dt, e, c, c / e, newton);
    EXPECT_GT(c, 10.0 * e) << "dt " << dt;
    EXPECT_LE(newton, 5.0) << "dt " << dt;
    em.push_back(e);
  }
  const double order = hs_chain::loglog_slope(dts, em);
  std::printf("mcva local on the fluid: fitted order %.2f\n", order);
  EXPECT_GE(order, 3.6);
}

TEST(MCVALocal, PendulumChainFourthOrder)
{
  const std::vector<double> dts = {0.04, 0.02, 0.01};
  std::vector<double> em;
  for (double dt : dts) {
    const double e = chain_error("mcva", dt), c = chain_error("cva", dt);
    std::printf("chain dt %g max|dH~|: mcva local %.3e, cva local %.3e (%.0fx)\n", dt, e, c,
                c / e);
    EXPECT_GT(c, 10.0 * e) << "dt " << dt;
    em.push_back(e);
  }
  const double order = hs_chain::loglog_slope(dts, em);
  std::printf("mcva local on the chain: fitted order %.2f\n", order);
  EXPECT_GE(order, 3.6);
}

TEST(MCVALocal, MomentumIsConserved)
{
  HSLammps L;
  L.lines(hs_fluid::fluid("fix hs all hardsphere/mcva diameter 1.0 substep local", 0.005));
  double P, scale;
  hs_fluid::momentum_after(L, 200, P, scale);
  EXPECT_GT(L.fix_vector("hs", 0), 100.0);
  EXPECT_LT(P, 1e-11 * scale) << "P " << P << " scale " << scale;
}

TEST(MCVALocal, StylesItCannotTakeAreNamed)
{
  const std::string base = R"LMP(units lj
atom_style full
atom_modify map array
boundary p p p
region box block -5 5 -5 5 -5 5
create_box 1 box bond/types 1 angle/types 1 extra/bond/per/atom 2 extra/angle/per/atom 1 extra/special/per/atom 4
create_atoms 1 single 0 0 0
create_atoms 1 single 1.1 0 0
create_atoms 1 single 2.2 0.3 0
mass 1 1.0
pair_style lj/cut 2.5
pair_coeff 1 1 1.0 1.0
bond_style harmonic
bond_coeff 1 10.0 1.1
angle_style harmonic
angle_coeff 1 1.0 150.0
create_bonds single/bond 1 1 2
create_bonds single/bond 1 2 3
create_bonds single/angle 1 1 2 3
velocity all create 1.0 4321
timestep 0.005
)LMP";
  hs_errors::expect_error(base + "fix hs all hardsphere/mcva diameter 1.0 substep local\nrun 5\n",
                          {"Fix hardsphere/mcva substep local cannot run with angle styles (the "
                           "local Gauss flow takes radial terms only)"});
  // without substep local: the global form, with one warning naming why
  expect_runs(base + "fix hs all hardsphere/mcva diameter 1.0\nrun 5\n",
              {"substep local is not available with angle styles (the local Gauss flow takes "
               "radial terms only); this run falls back to substep global"});
  // with substep global: no warning
  const auto r =
      expect_runs(base + "fix hs all hardsphere/mcva diameter 1.0 substep global\nrun 5\n", {});
  EXPECT_EQ(r.output.find("substep local"), std::string::npos) << r.output;
}

TEST(MCVALocal, FixedPointStagesFallBackToGlobal)
{
  const std::string base = hs_fluid::fluid("", 0.005, 87287, 3);
  hs_errors::expect_error(base + "fix hs all hardsphere/mcva diameter 1.0 substep local\n"
                                 "fix_modify hs stages fixed\nrun 5\n",
                          {"Fix hardsphere/mcva substep local cannot run with fix_modify stages "
                           "fixed"});
  HSLammps L;
  L.lines(base + "fix hs all hardsphere/mcva diameter 1.0\nfix_modify hs stages fixed\n");
  L.cmd("run 100");
  // entries (0-based) 0 collisions, 13 clusters, 17 steps that fell back
  EXPECT_GT(L.fix_vector("hs", 0), 0.0);
  EXPECT_EQ(L.fix_vector("hs", 13), 0.0) << "the local engine ran with stages fixed";
  EXPECT_EQ(L.fix_vector("hs", 17), L.fix_vector("hs", 3)) << "every collisional step falls back";
}

// 60 blocks of 50 steps of a 108-sphere fluid in either form
hs_fluid::Blocks sample(const std::string &substep)
{
  HSLammps L;
  L.lines(hs_fluid::fluid("fix hs all hardsphere/mcva diameter 1.0" + substep, 0.005, 4242, 3));
  const hs_fluid::Blocks b = hs_fluid::sample_blocks(L, 60);
  EXPECT_EQ(L.fix_vector("hs", 13) > 0.0, substep.empty()) << "clusters: the form that ran";
  return b;
}

TEST(MCVALocal, LocalAndGlobalSampleTheSameFluid)
{
  hs_fluid::expect_same_fluid(sample(""), sample(" substep global"), "local", "global");
}
