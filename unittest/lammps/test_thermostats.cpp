// Fixes beside the integrator (doc/fix_hardsphere.rst, "Fixes beside the
// integrator"): thermostats give their target temperature and a Maxwellian
// velocity distribution at a high collision rate with every method; fix
// langevin's tally keeps etotal + ecouple constant to the method's accuracy;
// deterministic force fixes keep the method's energy order.
//
// The fluid: 108 hard spheres (diameter 1.05) in the LJ fluid of issue 8
// (fcc 0.8, kT 1.5, dt 0.005), with lj/smooth/linear 2.5 for lj/cut: mcva's
// stage iteration used to fail to converge where lj/cut's force jumps at the
// cutoff (measured once in 5000 steps; now its Gauss sub-steps freeze the
// cutoff set, test_mcva_cutoff.cpp), which is not what this tests.
// One collision per sphere every 8-16 steps. Expected temperatures from statistical mechanics:
// - langevin (zero no) thermalizes all 3N velocity components, compute temp
//   divides 2 KE by 3N - 3: <T> = T0 3N / (3N - 3);
// - langevin zero yes: the random forces sum to zero, the drag takes the
//   total momentum to zero: 3N - 3 components at T0, <T> = T0;
// - langevin + viscous: the drag adds up, the noise is langevin's only
//   (fluctuation-dissipation): <T> = T0 3N/(3N-3) g_L / (g_L + g_v/m),
//   g_L = 1/damp;
// - langevin + spring/self (each sphere tethered to its start; the spring
//   is a held smooth force of the local engine, defined before the
//   integrator and the thermostat after it, so that the thermostat's force
//   stays two half kicks and the spring's rides in the colliding spheres'
//   flows): as langevin, T0 3N/(3N-3), and no fall-back to substep global;
// - temp/berendsen and temp/rescale act on compute temp: <T> = T0.
// Error bars: 20 or 100 block means (each block much longer than the correlation
// time of the kinetic energy); a check is meaningful only with a standard
// error well below the 1 % tolerance, which is asserted too.
//
// mcva runs its local form by default and gets every case's 1 % check like
// the other methods; its global form (mcva_global: substep global) the
// shorter runs below.
//
// Kurtosis kappa = <v^4>/<v^2>^2 of the velocity components (x, y and z
// pooled, by isotropy). A Maxwellian has 3. Bounds that statistical mechanics
// gives for these thermostats, widened by four error bars:
// - LAMMPS' fix langevin draws uniform, not Gaussian, random numbers: one
//   velocity component with no interactions is then the AR(1) process
//   v' = rho v + e with rho = 1 - dt/damp and innovations of excess kurtosis
//   -6/5, whose stationary excess kurtosis is -6/5 (1-rho^2)^2 / (1-rho^4);
//   collisions and forces mix components and bring it closer to 0. So
//   3 - (6/5)(1-rho^2)^2/(1-rho^4) <= kappa <= 3.
// - temp/berendsen and temp/rescale hold the kinetic energy near its target:
//   between the canonical 3 and the isokinetic 3 (3N-3)/(3N-1) (one component
//   of a point on the sphere in 3N-3 dimensions).

#include "hs_test_main.h"

#include "hs_chain.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>
#include <tuple>

namespace {

const double T0 = 1.5;
double NATOMS = 108.0;

struct Blocks {
  std::vector<double> T, v2, v4;
};

Blocks read_blocks(const std::string &path)
{
  Blocks b;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    double step, t, a, c;
    if (ls >> step >> t >> a >> c) {
      b.T.push_back(t);
      b.v2.push_back(a);
      b.v4.push_back(c);
    }
  }
  in.close();
  std::remove(path.c_str());
  return b;
}

// the fluid with fix hardsphere/<method> and a thermostat; returns the block
// means of T, <v^2>, <v^4> over nrun steps after equil of equilibration
// the fix's style and keywords of a case's method: mcva_global is mcva's
// global form (substep global; doc/fix_hardsphere_mcva.rst), plain mcva its
// default, the local form
std::string fix_style(const std::string &method)
{
  return method == "mcva_global" ? std::string("mcva substep global") : method;
}

Blocks run_fluid(const std::string &method, const std::string &thermo, double damp, int nrun,
                 int seed, int equil = 1000, std::string *log = nullptr, int nblocks = 20)
{
  const int cells = 3;
  NATOMS = 4.0 * cells * cells * cells;
  std::string th, pre;
  const std::string T = hs_chain::f17(T0), d = hs_chain::f17(damp), s = std::to_string(seed);
  if (thermo == "langevin") th = "fix th all langevin " + T + " " + T + " " + d + " " + s;
  else if (thermo == "langevin_spring") {
    pre = "fix sp all spring/self 2.0\nfix_modify sp energy yes\n";
    th = "fix th all langevin " + T + " " + T + " " + d + " " + s;
  }
  else if (thermo == "langevin_zero")
    th = "fix th all langevin " + T + " " + T + " " + d + " " + s + " zero yes";
  else if (thermo == "langevin_viscous")
    th = "fix th all langevin " + T + " " + T + " " + d + " " + s + "\nfix vi all viscous 5.0";
  else if (thermo == "berendsen") th = "fix th all temp/berendsen " + T + " " + T + " " + d;
  else if (thermo == "rescale") th = "fix th all temp/rescale 1 " + T + " " + T + " 0.015 1.0";
  const std::string blocks = scratch_name("blocks_" + method + "_" + thermo + ".txt");
  const int nb = nrun / nblocks;
  const std::string input = R"LMP(
units lj
atom_style atomic
atom_modify map array
lattice fcc 0.8
region box block 0 )LMP" + std::to_string(cells) + " 0 " + std::to_string(cells) + " 0 " +
      std::to_string(cells) + R"LMP(
create_box 1 box
create_atoms 1 box
mass 1 1.0
pair_style lj/smooth/linear 2.5
pair_coeff 1 1 1.0 1.0 2.5
neighbor 0.3 bin
neigh_modify every 1 delay 0 check yes
comm_modify cutoff 3.0
velocity all create )LMP" + T + " " + s + R"LMP( dist gaussian
timestep 0.005
)LMP" + pre + "fix int all hardsphere/" + fix_style(method) + R"LMP( diameter 1.05
)LMP" + th + R"LMP(
thermo 1000
run )LMP" + std::to_string(equil) + R"LMP(
# step 0 again: the blocks of nrun/nblocks steps then end on multiples of it
reset_timestep 0
variable v2 atom (vx*vx+vy*vy+vz*vz)/3
variable v4 atom (vx^4+vy^4+vz^4)/3
compute r all reduce ave v_v2 v_v4
fix b all ave/time 5 )LMP" + std::to_string(nb / 5) + " " + std::to_string(nb) +
      " c_thermo_temp c_r[1] c_r[2] file " + blocks + R"LMP(
variable c0 equal f_int[1]
variable cstart equal ${c0}
run )LMP" + std::to_string(nrun) + R"LMP(
print "COLLISIONS $(f_int[1]-v_cstart) STEPS )LMP" + std::to_string(nrun) + R"LMP("
)LMP";
  RunResult res = expect_runs(input);
  std::smatch m;
  if (std::regex_search(res.output, m, std::regex(R"(\nCOLLISIONS ([0-9.eE+-]+) STEPS ([0-9]+))"))) {
    const double cps = std::stod(m[1]) / std::stod(m[2]);
    printf("[ %s %s ] %.2f collisions per step (%.1f steps per sphere per collision)\n",
           method.c_str(), thermo.c_str(), cps, NATOMS / (2.0 * cps));
    // the rate the tests promise: at least one collision per sphere per 20 steps
    EXPECT_GT(2.0 * cps / NATOMS, 1.0 / 20.0);
  } else
    ADD_FAILURE() << "no COLLISIONS line:\n" << res.output;
  if (log) *log = res.output;
  Blocks b = read_blocks(blocks);
  EXPECT_EQ(b.T.size(), (size_t) nblocks) << res.output;
  return b;
}

double expected_T(const std::string &thermo, double damp)
{
  const double dof = (3.0 * NATOMS) / (3.0 * NATOMS - 3.0);
  if (thermo == "langevin" || thermo == "langevin_spring") return T0 * dof;
  if (thermo == "langevin_viscous") {
    const double gL = 1.0 / damp, gv = 5.0;    // viscous gamma / mass 1
    return T0 * dof * gL / (gL + gv);
  }
  return T0;
}

// check <T> and the kurtosis of one run against statistical mechanics
void check_run(const std::string &method, const std::string &thermo, double damp,
               const Blocks &b, double se_max)
{
  if (b.T.size() < 2) return;
  double Tm, Tse;
  mean_se(b.T, Tm, Tse);
  std::vector<double> kap(b.T.size());
  for (size_t k = 0; k < kap.size(); k++) kap[k] = b.v4[k] / (b.v2[k] * b.v2[k]);
  double km, kse;
  mean_se(kap, km, kse);
  const double Tx = expected_T(thermo, damp);

  double klo = 3.0, khi = 3.0;
  if (thermo.rfind("langevin", 0) == 0) {
    // the drag rate per step; fix viscous adds its own (gamma 5, mass 1)
    const double rho = 1.0 - 0.005 * (1.0 / damp + (thermo == "langevin_viscous" ? 5.0 : 0.0));
    klo = 3.0 - 1.2 * (1 - rho * rho) * (1 - rho * rho) / (1 - rho * rho * rho * rho);
  } else
    klo = 3.0 * (3.0 * NATOMS - 3.0) / (3.0 * NATOMS - 1.0);

  printf("[ %s %s damp %g ] <T> = %.4f +- %.4f (expected %.4f, %+.2f %%); kurtosis %.4f +- "
         "%.4f (bounds [%.4f, %.4f])\n",
         method.c_str(), thermo.c_str(), damp, Tm, Tse, Tx, 100.0 * (Tm / Tx - 1.0), km, kse,
         klo, khi);
  EXPECT_LT(Tse / Tx, se_max) << "error bar too large for a meaningful check";
  // the weak-coupling runs check T to three error bars (their error bar is
  // about 0.5 %: the 1 % check is the damp 0.1 suite's). The 1 % check:
  // within 1 %, or within three error bars where an error bar exceeds 1/3 %
  // (at most 1.35 % with se_max 0.45 %): a bare 1 % at an error bar of
  // 0.4 % would fail one correct run in a hundred, and a dozen such cases
  // fail together whenever a round-off change reshuffles the trajectories
  const double tol = std::max(0.01, 3.0 * Tse / Tx);
  EXPECT_NEAR(Tm / Tx, 1.0, tol) << "<T> " << Tm << " +- " << Tse << ", expected " << Tx;
  // four error bars: 20 blocks give the error bar itself to ~16 % (100 to
  // ~7 %), and the
  // short blocks of the berendsen/rescale runs (0.5 time units) are not
  // quite independent
  EXPECT_GT(km, klo - 4.0 * kse);
  EXPECT_LT(km, khi + 4.0 * kse);
}

using Param = std::tuple<const char *, const char *>;
class Thermostat : public ::testing::TestWithParam<Param> {};

std::string case_name(const ::testing::TestParamInfo<Param> &info)
{
  return std::string(std::get<0>(info.param)) + "_" + std::get<1>(info.param);
}

}    // namespace

// <T> within 1 % or three error bars (error bar < 0.45 %; mcva: see below)
// and kurtosis bounds, damp 0.1
TEST_P(Thermostat, TemperatureAndMaxwellian)
{
  const std::string method = std::get<0>(GetParam()), thermo = std::get<1>(GetParam());
  // temp/berendsen and temp/rescale hold T close to its target: their error
  // bar is ~0.03 % after 2000 steps. mcva's global form costs ~60-80 ms per
  // step here (Newton stage solves on the global engine; ~120-240 ms before
  // lj/smooth/linear's derivatives were analytic):
  // berendsen and rescale get the 1 % check of the other methods over 1000
  // steps (error bar ~0.05 %, blocks of 50 steps = 2.5 damp); the three langevin
  // cases 800 steps each, checked to three error bars (2-4 %), which tells
  // the old behaviour (a third of the target for cva, a stop on step 10 for
  // mcva) from the right one. Their 1 % check needs the 18000 steps of the
  // other methods, ~20 CPU minutes each: examples/thermostats runs it
  // (rows "mcva (108 atoms, damp 0.1)" of its results.md).
  const bool rescaling = thermo == "berendsen" || thermo == "rescale";
  const bool mcva = method == "mcva_global";
  const bool short_run = mcva && !rescaling;
  // the langevin cases: 18000 steps in 100 blocks of 180 (0.9 time units,
  // ~20 correlation times of the kinetic energy at damp 0.1). 20 blocks
  // gave the error bar itself to +-16 %, and 12000 steps an error bar of
  // ~0.45 %, at the 0.45 % bound: about every other run failed the bound
  // (pcva_langevin_zero at 0.4503 % after a round-off change). Now ~0.37 %
  // +- 7 %: the bound is 3 of its own error bars away.
  const int nrun = short_run ? 800 : (rescaling ? (mcva ? 1000 : 2000) : 18000);
  const int nblocks = (short_run || rescaling) ? 20 : 100;
  const double se_max = short_run ? 0.03 : 0.0045;
  const double damp = 0.1;
  Blocks b = run_fluid(method, thermo, damp, nrun, 4711, mcva ? 200 : 1000, nullptr, nblocks);
  check_run(method, thermo, damp, b, se_max);
}

INSTANTIATE_TEST_SUITE_P(
    Fluid, Thermostat,
    ::testing::Combine(::testing::Values("psa", "cva", "pcva", "vci"),
                       ::testing::Values("langevin", "langevin_zero", "langevin_viscous",
                                         "berendsen", "rescale")),
    case_name);
// mcva's global form: every thermostat; the langevin cases shorter (see above)
INSTANTIATE_TEST_SUITE_P(MCVA, Thermostat,
                         ::testing::Combine(::testing::Values("mcva_global"),
                                            ::testing::Values("langevin", "langevin_zero",
                                                              "langevin_viscous", "berendsen",
                                                              "rescale")),
                         case_name);
// mcva's default, its local form (issue 21): every thermostat with the 1 %
// check of the other methods (langevin: 18000 steps, 100 blocks; ~6 ms per step)
INSTANTIATE_TEST_SUITE_P(MCVALocal, Thermostat,
                         ::testing::Combine(::testing::Values("mcva"),
                                            ::testing::Values("langevin", "langevin_zero",
                                                              "langevin_viscous", "berendsen",
                                                              "rescale")),
                         case_name);

// held smooth forces beside a thermostat (doc fix_hardsphere, "Held smooth
// forces"): the local methods run locally (no fall-back) and give langevin's
// temperature, the spring's force riding in the members' flows and the
// thermostat's as two half kicks (18000 steps, 100 blocks, as above)
class ThermostatSpring : public ::testing::TestWithParam<const char *> {};

TEST_P(ThermostatSpring, LangevinBesideHeldSpring)
{
  const std::string method = GetParam();
  std::string log;
  Blocks b = run_fluid(method, "langevin_spring", 0.1, 18000, 4711, 1000, &log, 100);
  check_run(method, "langevin_spring", 0.1, b, 0.0045);
  if (method != "psa") {
    EXPECT_NE(log.find("substep local (collisions sub-stepped per cluster)"), std::string::npos)
        << log;
    EXPECT_EQ(log.find("falls back"), std::string::npos) << log;
    EXPECT_NE(log.find("stay two half kicks"), std::string::npos) << log;
  }
}

INSTANTIATE_TEST_SUITE_P(Fluid, ThermostatSpring, ::testing::Values("psa", "cva", "pcva", "vci"),
                         [](const ::testing::TestParamInfo<const char *> &i) {
                           return std::string(i.param);
                         });
// mcva's local form: the spring's work in the ledger of its projection
INSTANTIATE_TEST_SUITE_P(MCVALocal, ThermostatSpring, ::testing::Values("mcva"),
                         [](const ::testing::TestParamInfo<const char *> &i) {
                           return std::string(i.param);
                         });

// the sharper kurtosis check: weak coupling (damp 0.5), where uniform random
// numbers change the kurtosis by at most 0.012
class ThermostatWeak : public ::testing::TestWithParam<const char *> {};

TEST_P(ThermostatWeak, LangevinMaxwellian)
{
  const std::string method = GetParam();
  Blocks b = run_fluid(method, "langevin", 0.5, 20000, 917);
  check_run(method, "langevin", 0.5, b, 0.008);
}

// (vci's kurtosis is checked at damp 0.1 only: its E_d solves make 20000
// steps cost minutes)
INSTANTIATE_TEST_SUITE_P(Fluid, ThermostatWeak, ::testing::Values("psa", "cva", "pcva"),
                         [](const ::testing::TestParamInfo<const char *> &i) {
                           return std::string(i.param);
                         });
