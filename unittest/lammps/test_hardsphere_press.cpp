// fix hardsphere/press: Monte Carlo volume moves sample the isothermal-
// isobaric ensemble. Pure hard spheres at P sigma^3/kT = 2, 5, 10 give the
// Carnahan-Starling packing fraction and volume fluctuation (the isothermal
// compressibility of Carnahan-Starling); no sphere ever overlaps another in
// a stress case with wide moves; a rejected move leaves the run bit for bit
// as if no move had been tried; 2 ranks sample the same distribution; a
// restart continues the chain; the smooth energy change enters exactly
// (ideal gas of harmonic dimers, whose density is beta P per molecule).
// Expected values come from the equation of state or exact statistical
// mechanics; statistical checks use block averages with error bars.

#include "hs_npt.h"

#include "atom.h"
#include "library.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>

using namespace hs_npt;

namespace {

struct EosCase {
  double pstar;
  int seed;
};

class PressCS : public ::testing::TestWithParam<EosCase> {};

std::string eos_name(const ::testing::TestParamInfo<EosCase> &info)
{
  return "P" + std::to_string((int) info.param.pstar);
}

constexpr int NATOMS = 108;    // fluid_input's 3 x 3 x 3 fcc cells

// packing fractions of NATOMS spheres of diameter 1 from sampled volumes
std::vector<double> packing(const std::vector<double> &vol)
{
  std::vector<double> eta;
  for (double v : vol) eta.push_back(NATOMS * PI / 6.0 / v);
  return eta;
}

void check_cs(const char *label, double pstar, const std::vector<double> &vol, int nblocks,
              double tol_eta)
{
  const double eta_cs = cs_eta(pstar);
  const Blocks be = block_stats(packing(vol), nblocks);
  const Blocks bv = block_stats(vol, nblocks);
  const double rel_var = bv.var / (bv.mean * bv.mean);
  const double rel_var_cs = 1.0 / (NATOMS * cs_dbetap_drho(eta_cs));
  const double rel_var_err = bv.var_err / (bv.mean * bv.mean);
  printf("[ %s ] P* %g: <eta> = %.5f +- %.5f, CS %.5f (%+.3f %%, %.1f sigma); "
         "<dV^2>/<V>^2 = %.3e +- %.1e, CS %.3e (%+.1f %%, %.1f sigma); %zu samples\n",
         label, pstar, be.mean, be.err, eta_cs, 100.0 * (be.mean / eta_cs - 1.0),
         (be.mean - eta_cs) / be.err, rel_var, rel_var_err, rel_var_cs,
         100.0 * (rel_var / rel_var_cs - 1.0), (rel_var - rel_var_cs) / rel_var_err, vol.size());
  ASSERT_GT(be.err, 0.0);
  EXPECT_LT(std::fabs(be.mean / eta_cs - 1.0), tol_eta);
  EXPECT_LT(std::fabs(be.mean - eta_cs), 3.0 * be.err);
  EXPECT_LT(std::fabs(rel_var - rel_var_cs), 3.0 * rel_var_err);
  // the error bars must be small enough for the checks to mean something
  EXPECT_LT(be.err / eta_cs, tol_eta / 2.0);
  EXPECT_LT(rel_var_err / rel_var_cs, 0.25);
}

}    // namespace

// mean packing fraction and volume variance against Carnahan-Starling.
// Volume moves of hard spheres are short (an accepted compression is limited
// by the closest pair, ~1/(N (Z-1)) in ln V), so the volume decorrelates
// over ~10^3 attempts: 108 spheres, a move every step, 250000 steps
TEST_P(PressCS, CarnahanStarling)
{
  const EosCase c = GetParam();
  const int nequil = 30000, nprod = 250000;
  HSLammps h;
  h.lines(fluid_input(c.pstar, "psa", c.seed, "adapt 1000 delta 0.002"));
  h.cmd("run " + std::to_string(nequil));
  const double delta = h.fix_vector("press", 6);
  h.cmd("variable vol equal vol");
  h.cmd("fix vol all vector 1 v_vol");
  h.cmd("run " + std::to_string(nprod));
  const double acc = h.fix_vector("press", 5);
  printf("[ press ] P* %g: delta %.5f, acceptance %.3f, %g attempts, %g rejected by overlap\n",
         c.pstar, delta, acc, h.fix_vector("press", 1), h.fix_vector("press", 3));
  EXPECT_EQ(h.fix_vector("press", 6), delta);    // fixed after adaptation
  EXPECT_GT(acc, 0.2);
  EXPECT_LT(acc, 0.7);
  check_cs("press CS", c.pstar, fix_series(h, "vol", nprod), 20, 0.005);
}

INSTANTIATE_TEST_SUITE_P(PSA, PressCS,
                         ::testing::Values(EosCase{2.0, 4711}, EosCase{5.0, 5821},
                                           EosCase{10.0, 6932}),
                         eos_name);

// beside every method of the family: a shorter run at P* = 5, the packing
// fraction within 4 error bars and 2 % of Carnahan-Starling
class PressMethods : public ::testing::TestWithParam<const char *> {};

TEST_P(PressMethods, ShortRunNearCarnahanStarling)
{
  const std::string method = GetParam();
  const double pstar = 5.0;
  const int nequil = 2000, nprod = 20000;
  HSLammps h;
  h.lines(fluid_input(pstar, method, 3141, "adapt 500 delta 0.002"));
  h.cmd("run " + std::to_string(nequil));
  h.cmd("variable vol equal vol");
  h.cmd("fix vol all vector 1 v_vol");
  h.cmd("run " + std::to_string(nprod));
  const std::vector<double> vol = fix_series(h, "vol", nprod);
  const double eta_cs = cs_eta(pstar);
  const Blocks be = block_stats(packing(vol), 10);
  printf("[ press %s ] P* %g: <eta> = %.5f +- %.5f, CS %.5f (%+.2f %%); acceptance %.3f\n",
         method.c_str(), pstar, be.mean, be.err, eta_cs, 100.0 * (be.mean / eta_cs - 1.0),
         h.fix_vector("press", 5));
  EXPECT_GT(h.fix_vector("press", 2), 0.0);
  EXPECT_LT(std::fabs(be.mean - eta_cs), 4.0 * be.err);
  EXPECT_LT(std::fabs(be.mean / eta_cs - 1.0), 0.02);
}

std::string method_name(const ::testing::TestParamInfo<const char *> &info)
{
  return info.param;
}

INSTANTIATE_TEST_SUITE_P(Family, PressMethods,
                         ::testing::Values("cva", "pcva", "mcva", "vci"), method_name);

// P* = 10 with wide moves attempted every step: the smallest distance of any
// two spheres, measured after every step's move (compute pair/local on its
// own list, built at the current positions), is never below the diameter
TEST(PressStress, NoOverlapEverWithWideMoves)
{
  const int nsteps = 1500;
  HSLammps h;
  h.lines(fluid_input(10.0, "psa", 2718, "adapt 0 delta 0.05", "1", 4));
  // compute reduce of local values needs "inputs local" in newer LAMMPS
  // (4Feb2025), which 29Sep2021 does not know
  const std::string inputs = lammps_version(h.lmp) >= 20230802 ? " inputs local" : "";
  h.lines(R"(
pair_style zero 1.5
pair_coeff * *
compute pl all pair/local dist
)");
  h.cmd("compute dmin all reduce min c_pl" + inputs);
  h.cmd("fix dmin all vector 1 c_dmin");
  h.cmd("run " + std::to_string(nsteps));
  const std::vector<double> d = fix_series(h, "dmin", nsteps);
  const double worst = *std::min_element(d.begin(), d.end());
  const double attempts = h.fix_vector("press", 1), accepted = h.fix_vector("press", 2),
               overlaps = h.fix_vector("press", 3);
  printf("[ press stress ] %d steps: smallest distance %.12f; %g attempts, %g accepted, "
         "%g rejected by overlap; eta %.4f\n",
         nsteps, worst, attempts, accepted, overlaps, 256.0 * PI / 6.0 / h.thermo("vol"));
  EXPECT_EQ(attempts, (double) nsteps);
  EXPECT_GT(accepted, 10.0);
  EXPECT_GT(overlaps, 0.3 * attempts);    // the test tries overlapping moves
  EXPECT_GE(worst, 1.0 - 1e-9);
  EXPECT_LT(worst, 1.05);    // pairs near contact were measured
}

// a rejected move restores box and positions bit for bit: with every move
// rejected (P* = 1e6 rejects expansions, overlaps most compressions) the run
// is the run without the barostat, to the bit. Both runs rebuild their lists
// on the same steps (every 5 steps, a skin no sphere crosses in 5 steps), as
// the wrapping of positions at a rebuild changes their last bits.
TEST(PressBitwise, RejectedMovesLeaveTheRunUnchanged)
{
  auto run = [](bool press, double &accepted, double &attempts) {
    HSLammps h;
    h.lines(R"(
units lj
atom_style atomic
atom_modify map array
lattice fcc 0.859436692696
region box block 0 4 0 4 0 4
create_box 1 box
create_atoms 1 box
mass 1 1.0
velocity all create 1.0 8812 mom yes rot no dist gaussian loop geom
neighbor 1.0 bin
neigh_modify every 5 delay 0 check no
comm_modify cutoff 4.0
timestep 0.01
fix hs all hardsphere/psa diameter 1.0
)");
    if (press) h.cmd("fix press all hardsphere/press iso 1e6 1e6 0.05 temp 1.0 seed 2345 every 5 adapt 0 delta 1.0");
    h.cmd("run 400");
    accepted = press ? h.fix_vector("press", 2) : 0.0;
    attempts = press ? h.fix_vector("press", 1) : 0.0;
    const int n = (int) h.thermo("atoms");
    std::vector<double> x(3 * n), v(3 * n);
    lammps_gather_atoms(h.lmp, (char *) "x", 1, 3, x.data());
    lammps_gather_atoms(h.lmp, (char *) "v", 1, 3, v.data());
    x.insert(x.end(), v.begin(), v.end());
    x.push_back(h.thermo("vol"));
    return x;
  };
  double acc_a, att_a, acc_b, att_b;
  const std::vector<double> a = run(true, acc_a, att_a);
  const std::vector<double> b = run(false, acc_b, att_b);
  ASSERT_EQ(att_a, 80.0);
  ASSERT_EQ(acc_a, 0.0) << "this seed accepted a move: the test needs all rejected";
  ASSERT_EQ(a.size(), b.size());
  size_t ndiff = 0;
  for (size_t k = 0; k < a.size(); k++)
    if (memcmp(&a[k], &b[k], sizeof(double)) != 0) ndiff++;
  EXPECT_EQ(ndiff, 0u) << "of " << a.size() << " values (x, v, volume)";
}

// 2 ranks: the same distribution (Carnahan-Starling at P* = 5 within 3 error
// bars and 2 %: a shorter run than the 1-rank test's, as 2 ranks of 108
// atoms are slow), run as a separate 2-rank lmp process
TEST(PressMPI, TwoRanksSampleCarnahanStarling)
{
  const double pstar = 5.0;
  const int nprod = 12000;
  const std::string file = scratch_name("press_vol.txt");
  std::string input = fluid_input(pstar, "psa", 9051, "adapt 1000 delta 0.002");
  input += "run 6000\nvariable v equal vol\n";
  input += "fix out all ave/time 1 1 1 v_v file " + file + " format \" %.17g\"\n";
  input += "run " + std::to_string(nprod) + "\n";
  RunResult r = run_lmp(input, {}, 2);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::vector<double> vol;
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line))
    if (!line.empty() && line[0] != '#') vol.push_back(std::stod(line.substr(line.find(' '))));
  std::remove(file.c_str());
  ASSERT_GE(vol.size(), (size_t) nprod);
  const Blocks be = block_stats(packing(vol), 10);
  const double eta_cs = cs_eta(pstar);
  printf("[ press 2 ranks ] P* %g: <eta> = %.5f +- %.5f, CS %.5f (%+.3f %%)\n", pstar, be.mean,
         be.err, eta_cs, 100.0 * (be.mean / eta_cs - 1.0));
  EXPECT_LT(std::fabs(be.mean - eta_cs), 3.0 * be.err);
  EXPECT_LT(std::fabs(be.mean / eta_cs - 1.0), 0.02);
}

// write_restart / read_restart: counters, the move width and the random
// sequence continue (the continued chain equals the uninterrupted one)
TEST(PressRestart, ChainContinues)
{
  const std::string file = scratch_name("press_restart.bin");
  const std::string input = fluid_input(5.0, "psa", 777, "adapt 40 delta 0.002", "5");
  std::vector<double> before(7), straight(7);
  {
    HSLammps h;
    h.lines(input);
    h.cmd("run 500");
    for (int k = 0; k < 7; k++) before[k] = h.fix_vector("press", k);
    h.cmd("write_restart " + file);
    h.cmd("run 500");
    for (int k = 0; k < 7; k++) straight[k] = h.fix_vector("press", k);
  }
  ASSERT_GT(before[2], 0.0);
  HSLammps h;
  h.cmd("read_restart " + file);
  h.lines(R"(
neighbor 0.3 bin
neigh_modify every 1 delay 0 check yes
comm_modify cutoff 2.0
timestep 0.003
fix hs all hardsphere/psa diameter 1.0
fix press all hardsphere/press iso 5 5 0.003 temp 1.0 seed 999 every 5 adapt 40 delta 0.002
run 0
)");
  for (int k = 0; k < 7; k++)
    if (k != 4) EXPECT_EQ(h.fix_vector("press", k), before[k]) << "entry " << k + 1;
  h.cmd("run 500");
  printf("[ press restart ] straight: V %.10g, %g/%g accepted; restarted: V %.10g, %g/%g\n",
         straight[0], straight[2], straight[1], h.fix_vector("press", 0),
         h.fix_vector("press", 2), h.fix_vector("press", 1));
  EXPECT_EQ(h.fix_vector("press", 1), straight[1]);
  EXPECT_EQ(h.fix_vector("press", 6), straight[6]);
  // the same random numbers (the seed on the command line is not used): the
  // same decisions, hence the same volume, as long as the trajectories agree
  EXPECT_EQ(h.fix_vector("press", 2), straight[2]);
  EXPECT_NEAR(h.fix_vector("press", 0), straight[0], 1e-9 * straight[0]);
  std::remove(file.c_str());
}

// the smooth energy change: an ideal gas of M harmonic dimers (bond length
// 0.5, tiny hard spheres that never meet), scaled atom by atom. The volume
// density of the ensemble is V^M exp(-beta P V) (each dimer's centre ranges
// over V, its bond does not depend on V), so <M/V> = beta P exactly; without
// the bond energy change in the acceptance it would be 2 beta P.
TEST(PressSmooth, HarmonicDimersIdealGasOfMolecules)
{
  const int every = 2, nprod = 80000;
  const double betap = 0.1;
  HSLammps h;
  h.lines(R"(
units lj
atom_style bond
atom_modify map array
region box block 0 10 0 10 0 10
create_box 1 box bond/types 1 extra/bond/per/atom 1 extra/special/per/atom 1
mass 1 1.0
bond_style harmonic
bond_coeff 1 50.0 0.5
special_bonds lj/coul 0 1 1
)");
  // 100 dimers on a 5 x 5 x 4 grid, bonds along x
  int id = 0;
  for (int a = 0; a < 5; a++)
    for (int b = 0; b < 5; b++)
      for (int c = 0; c < 4; c++) {
        const double x0 = 2.0 * a + 0.5, y0 = 2.0 * b + 0.5, z0 = 2.5 * c + 0.5;
        h.cmd("create_atoms 1 single " + std::to_string(x0) + " " + std::to_string(y0) + " " +
              std::to_string(z0) + " units box");
        h.cmd("create_atoms 1 single " + std::to_string(x0 + 0.5) + " " + std::to_string(y0) +
              " " + std::to_string(z0) + " units box");
        id += 2;
        h.cmd("create_bonds single/bond 1 " + std::to_string(id - 1) + " " + std::to_string(id));
      }
  h.lines(R"(
velocity all create 1.0 4412 mom yes rot no dist gaussian loop geom
neighbor 0.3 bin
comm_modify cutoff 2.0
timestep 0.005
fix hs all hardsphere/cva diameter 0.01
fix th all langevin 1.0 1.0 1.0 9912
fix press all hardsphere/press iso 0.1 0.1 0.01 temp 1.0 seed 5533 every 2 adapt 200 delta 0.1
run 4000
)");
  h.cmd("variable vol equal vol");
  h.cmd("fix vol all vector " + std::to_string(every) + " v_vol");
  h.cmd("run " + std::to_string(nprod));
  std::vector<double> dens;
  for (double v : fix_series(h, "vol", nprod / every)) dens.push_back(100.0 / v);
  const Blocks b = block_stats(dens, 20);
  printf("[ press dimers ] <M/V> = %.5f +- %.5f, beta P = %.5f (%+.2f %%, %.1f sigma); "
         "acceptance %.3f, delta %.4f\n",
         b.mean, b.err, betap, 100.0 * (b.mean / betap - 1.0), (b.mean - betap) / b.err,
         h.fix_vector("press", 5), h.fix_vector("press", 6));
  EXPECT_LT(std::fabs(b.mean - betap), 3.0 * b.err);
  EXPECT_LT(std::fabs(b.mean / betap - 1.0), 0.02);
  EXPECT_LT(b.err / betap, 0.008);
}

// aniso: each dimension (couple none) or a coupled set (couple xy) scaled by
// moves of its own, one set per move. The density in the log-lengths is
// V^(N+1) exp(-beta P V) as for iso, so the packing fraction is still
// Carnahan-Starling's (P* = 5, 4 error bars and 2 %); the box shape changes
// (couple none), and coupled lengths stay equal to the bit
class PressAniso : public ::testing::TestWithParam<const char *> {};

TEST_P(PressAniso, HardSpheresNearCarnahanStarling)
{
  const std::string couple = GetParam();
  const double pstar = 5.0;
  const int nequil = 3000, nprod = 30000;
  HSLammps h;
  std::string input = fluid_input(pstar, "psa", 1618, "adapt 600 delta 0.002 couple " + couple);
  const size_t at = input.find("hardsphere/press iso");
  input.replace(at, 20, "hardsphere/press aniso");
  h.lines(input);
  h.cmd("run " + std::to_string(nequil));
  h.cmd("variable vol equal vol");
  h.cmd("fix vol all vector 1 v_vol");
  h.cmd("run " + std::to_string(nprod));
  const std::vector<double> vol = fix_series(h, "vol", nprod);
  const double eta_cs = cs_eta(pstar);
  const Blocks be = block_stats(packing(vol), 10);
  const double lx = h.thermo("lx"), ly = h.thermo("ly"), lz = h.thermo("lz");
  printf("[ press aniso couple %s ] P* %g: <eta> = %.5f +- %.5f, CS %.5f (%+.2f %%, %.1f "
         "sigma); acceptance %.3f; box %.6f %.6f %.6f\n",
         couple.c_str(), pstar, be.mean, be.err, eta_cs, 100.0 * (be.mean / eta_cs - 1.0),
         (be.mean - eta_cs) / be.err, h.fix_vector("press", 5), lx, ly, lz);
  EXPECT_LT(std::fabs(be.mean - eta_cs), 4.0 * be.err);
  EXPECT_LT(std::fabs(be.mean / eta_cs - 1.0), 0.02);
  EXPECT_GT(std::fabs(lz / lx - 1.0), 1e-3);    // the shape changed
  if (couple == "xy") EXPECT_EQ(lx, ly);
  else EXPECT_GT(std::fabs(ly / lx - 1.0), 1e-3);
}

INSTANTIATE_TEST_SUITE_P(Psa, PressAniso, ::testing::Values("none", "xy"), method_name);
