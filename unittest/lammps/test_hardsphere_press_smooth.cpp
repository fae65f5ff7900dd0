// fix hardsphere/press with smooth forces and thermostats (issue 24):
// - hard-core Lennard-Jones: the mean density the barostat samples at P, put
//   into an NVT run, gives back P as the pressure LAMMPS reports (kinetic +
//   pair virial + the collisional virial of the hardsphere fix), within the
//   combined error bar (the density's error propagated with dP/drho from the
//   NPT volume fluctuation);
// - pure hard spheres with a thermostat beside cva and the barostat:
//   Carnahan-Starling's packing fraction within error bars;
// - charges with kspace (ewald, pppm): the energy change of a volume move
//   (output entry 8) equals the change of the total energy LAMMPS evaluates
//   afresh (run 0) at both volumes, kspace part included; a hard-core
//   restricted primitive model runs under the barostat without an overlap.
// Longer versions of the first: examples/hard-core-lj-npt.

#include "hs_npt.h"

#include "library.h"

#include <algorithm>
#include <cstdio>

using namespace hs_npt;

namespace {

// hard spheres of diameter 1 with LJ (epsilon = sigma = 1, cut 2.5, shifted:
// the MC moves sample the shifted energy, whose virial pressure has no
// impulsive cutoff term), cva + langevin at kT, n^3 fcc cells at density rho
std::string hclj_input(double rho, double kt, int seed)
{
  char buf[1024];
  snprintf(buf, sizeof(buf),
           "units lj\natom_style atomic\natom_modify map array\nlattice fcc %.17g\n"
           "region box block 0 3 0 3 0 3\ncreate_box 1 box\ncreate_atoms 1 box\nmass 1 1.0\n"
           "velocity all create %.17g %d mom yes rot no dist gaussian loop geom\n"
           "pair_style lj/cut 2.5\npair_coeff 1 1 1.0 1.0\npair_modify shift yes\n"
           "neighbor 0.3 bin\nneigh_modify every 1 delay 0 check yes\ntimestep 0.002\n"
           "fix hs all hardsphere/cva diameter 1.0\nfix th all langevin %.17g %.17g 0.5 %d\n"
           "thermo 10000\n",
           rho, kt, seed, kt, kt, seed + 7);
  return buf;
}

}    // namespace

// NPT at P = 1.5, kT = 2 (supercritical; 108 atoms, a move every 2 steps),
// then NVT at the sampled mean density: <P_NVT> = P. Without the smooth
// energy change in the acceptance the density would be that of bare hard
// spheres at beta P (Carnahan-Starling: 0.34 instead of 0.48); without the
// collisional virial (fix_modify hs virial no) P_NVT would be 0.16
TEST(PressHardCoreLJ, NptDensityGivesBackPressureInNvt)
{
  const int natoms = 108, every = 2, nprod = 80000, nvt = 60000;
  const double kt = 2.0, p = 1.5;
  Blocks br;
  double acc = 0.0;
  {
    HSLammps h;
    h.lines(hclj_input(0.5, kt, 4242));
    char buf[256];
    snprintf(buf, sizeof(buf),
             "fix press all hardsphere/press iso %g %g 0.01 temp %g seed 5151 every %d "
             "delta 0.01 adapt 1000",
             p, p, kt, every);
    h.cmd(buf);
    h.cmd("run 6000");
    h.cmd("variable rho equal density");
    h.cmd("fix rho all vector " + std::to_string(every) + " v_rho");
    h.cmd("run " + std::to_string(nprod));
    br = block_stats(fix_series(h, "rho", nprod / every), 20);
    acc = h.fix_vector("press", 5);
  }
  // d(beta P)/d rho from the NPT fluctuation: <d rho^2>/rho^2 = 1/(N d(beta P)/d rho)
  const double dpdrho = kt * br.mean * br.mean / (natoms * br.var);
  Blocks bp;
  {
    HSLammps h;
    h.lines(hclj_input(br.mean, kt, 977));
    h.cmd("run 4000");
    h.cmd("fix p all vector 1 c_thermo_press");
    h.cmd("run " + std::to_string(nvt));
    bp = block_stats(fix_series(h, "p", nvt), 20);
  }
  const double err_rho = dpdrho * br.err;
  const double err = std::hypot(bp.err, err_rho);
  printf("[ press hard-core LJ ] NPT P %g kT %g: <rho> = %.5f +- %.5f (acceptance %.3f), "
         "dP/drho %.3f; NVT at that rho: <P> = %.4f +- %.4f (+- %.4f from rho; combined "
         "%.4f): %+.2f %%, %.1f sigma\n",
         p, kt, br.mean, br.err, acc, dpdrho, bp.mean, bp.err, err_rho, err,
         100.0 * (bp.mean / p - 1.0), (bp.mean - p) / err);
  EXPECT_GT(acc, 0.15);
  EXPECT_LT(acc, 0.7);
  EXPECT_LT(std::fabs(bp.mean - p), 3.0 * err);
  EXPECT_LT(std::fabs(bp.mean / p - 1.0), 0.06);
  EXPECT_LT(err / p, 0.03);    // small enough for the check to mean something
}

// pure hard spheres, cva with a thermostat beside the barostat (P* = 5):
// Carnahan-Starling's packing fraction within 4 error bars and 2 %, and the
// kinetic temperature the thermostat's (the held forces are kept through a
// move, not drawn twice)
class PressThermostat : public ::testing::TestWithParam<const char *> {};

TEST_P(PressThermostat, HardSpheresNearCarnahanStarling)
{
  const std::string kind = GetParam();
  const double pstar = 5.0;
  const int nequil = 2000, nprod = 20000;
  HSLammps h;
  h.lines(fluid_input(pstar, "cva", 2468, "adapt 500 delta 0.002"));
  if (kind == "langevin") h.cmd("fix th all langevin 1.0 1.0 0.5 1357");
  else h.cmd("fix th all temp/berendsen 1.0 1.0 0.1");
  h.cmd("run " + std::to_string(nequil));
  h.cmd("variable vol equal vol");
  h.cmd("fix vol all vector 1 v_vol");
  h.cmd("fix t all vector 10 c_thermo_temp");
  h.cmd("run " + std::to_string(nprod));
  std::vector<double> eta;
  for (double v : fix_series(h, "vol", nprod)) eta.push_back(108 * PI / 6.0 / v);
  const Blocks be = block_stats(eta, 10);
  const Blocks bt = block_stats(fix_series(h, "t", nprod / 10), 10);
  const double eta_cs = cs_eta(pstar);
  printf("[ press %s ] P* %g: <eta> = %.5f +- %.5f, CS %.5f (%+.2f %%, %.1f sigma); "
         "<T> = %.4f +- %.4f; acceptance %.3f\n",
         kind.c_str(), pstar, be.mean, be.err, eta_cs, 100.0 * (be.mean / eta_cs - 1.0),
         (be.mean - eta_cs) / be.err, bt.mean, bt.err, h.fix_vector("press", 5));
  EXPECT_GT(h.fix_vector("press", 2), 0.0);
  EXPECT_LT(std::fabs(be.mean - eta_cs), 4.0 * be.err);
  EXPECT_LT(std::fabs(be.mean / eta_cs - 1.0), 0.02);
  // compute temp counts 3N - 3 degrees of freedom; langevin does not keep
  // the total momentum zero, so its <T> is 3N/(3N - 3) of the target
  const double t_expect = (kind == "langevin") ? 3.0 * 108 / (3.0 * 108 - 3.0) : 1.0;
  EXPECT_LT(std::fabs(bt.mean - t_expect), std::max(4.0 * bt.err, 0.005));
}

std::string param_name(const ::testing::TestParamInfo<const char *> &info)
{
  return info.param;
}

INSTANTIATE_TEST_SUITE_P(Cva, PressThermostat, ::testing::Values("langevin", "berendsen"),
                         param_name);

namespace {

// 128 ions of diameter 1 (CsCl arrangement of a bcc lattice, charges +-1,
// number density rho), pair coul/long 3.0 with kspace (ewald or pppm at a
// fixed splitting and mesh, so that every evaluation is the same function)
std::string rpm_input(const std::string &kspace, double rho, int seed)
{
  const std::string ks = kspace == "ewald"
      ? "kspace_style ewald 1e-6\nkspace_modify gewald 1.1\n"
      : "kspace_style pppm 1e-5\nkspace_modify gewald 1.1 mesh 16 16 16 order 5\n";
  char buf[1024];
  snprintf(buf, sizeof(buf),
           "units lj\natom_style charge\natom_modify map array\nlattice bcc %.17g\n"
           "region box block 0 4 0 4 0 4\ncreate_box 2 box\n"
           "create_atoms 1 box basis 1 1 basis 2 2\nmass * 1.0\n"
           "set type 1 charge 1.0\nset type 2 charge -1.0\n"
           "velocity all create 1.0 %d mom yes rot no dist gaussian loop geom\n"
           "pair_style coul/long 3.0\npair_coeff * *\n%s"
           "neighbor 0.3 bin\nneigh_modify every 1 delay 0 check yes\n"
           "thermo_style custom step pe ecoul elong vol\nthermo_modify norm no\n",
           rho, seed, ks.c_str());
  return buf;
}

}    // namespace

// the energy change of a move, as the acceptance used it (entry 8), against
// the total energy LAMMPS computes from scratch (run 0: kspace set up anew)
// at the volume before and after an accepted move. The kspace part changes
// by far more than the tolerance: a dU without it would fail
class PressKspace : public ::testing::TestWithParam<const char *> {};

TEST_P(PressKspace, MoveEnergyChangeIncludesKspace)
{
  const std::string kspace = GetParam();
  HSLammps h;
  h.lines(rpm_input(kspace, 0.3, 31));
  h.cmd("velocity all set 0.0 0.0 0.0");
  // at rest and dt tiny: the positions of a step's start and its end (where
  // the move is tried) differ by ~1e-16, so the energy before the move is
  // that of run 0
  h.lines(R"(
timestep 1e-8
fix hs all hardsphere/cva diameter 1.0
fix press all hardsphere/press iso 0.1 0.1 1e-8 temp 1e6 seed 8080 every 1 delta 0.04 adapt 0
)");
  int checked = 0;
  for (int k = 0; k < 40 && checked < 3; k++) {
    h.cmd("run 0");
    const double pe0 = h.thermo("pe"), el0 = h.thermo("elong"), v0 = h.thermo("vol");
    const double acc0 = h.fix_vector("press", 2);
    h.cmd("run 1");
    if (h.fix_vector("press", 2) == acc0) continue;    // rejected (a compression, mostly)
    const double du = h.fix_vector("press", 7);
    h.cmd("run 0");
    const double pe1 = h.thermo("pe"), el1 = h.thermo("elong"), v1 = h.thermo("vol");
    printf("[ press %s ] V %.6f -> %.6f: dU (fix) = %.10f, pe(V') - pe(V) = %.10f "
           "(kspace part %.6f)\n",
           kspace.c_str(), v0, v1, du, pe1 - pe0, el1 - el0);
    EXPECT_NE(v1, v0);
    EXPECT_NEAR(du, pe1 - pe0, 1e-9 * (1.0 + std::fabs(pe0)));
    EXPECT_GT(std::fabs(el1 - el0), 1e-3);
    checked++;
  }
  EXPECT_EQ(checked, 3) << "too few accepted moves in 40 attempts";
}

// a hard-core restricted primitive model under the barostat (cva +
// langevin, a move every 5 steps): runs, moves are accepted, and the
// smallest distance of any two ions, measured after every step, is never
// below the diameter
TEST_P(PressKspace, PrimitiveModelRunsWithoutOverlap)
{
  const std::string kspace = GetParam();
  const int nsteps = 1000;
  HSLammps h;
  h.lines(rpm_input(kspace, 0.3, 57));
  h.lines(R"(
timestep 0.003
fix hs all hardsphere/cva diameter 1.0
fix th all langevin 1.0 1.0 0.5 6543
fix press all hardsphere/press iso 0.4 0.4 0.015 temp 1.0 seed 7117 delta 0.02 adapt 200
compute pl all pair/local dist
)");
  const std::string inputs = lammps_version(h.lmp) >= 20230802 ? " inputs local" : "";
  h.cmd("compute dmin all reduce min c_pl" + inputs);
  h.cmd("fix dmin all vector 1 c_dmin");
  h.cmd("run " + std::to_string(nsteps));
  const std::vector<double> d = fix_series(h, "dmin", nsteps);
  const double worst = *std::min_element(d.begin(), d.end());
  printf("[ press rpm %s ] %d steps: smallest distance %.10f; %g attempts, %g accepted, %g "
         "rejected by overlap; V %.3f -> %.3f\n",
         kspace.c_str(), nsteps, worst, h.fix_vector("press", 1), h.fix_vector("press", 2),
         h.fix_vector("press", 3), 128 / 0.3, h.fix_vector("press", 0));
  EXPECT_EQ(h.fix_vector("press", 1), nsteps / 5.0);
  EXPECT_GT(h.fix_vector("press", 2), 40.0);
  EXPECT_GE(worst, 1.0 - 1e-9);
}

INSTANTIATE_TEST_SUITE_P(Rpm, PressKspace, ::testing::Values("ewald", "pppm"),
                         param_name);

// a volume move keeps the thermostats' forces (f less the conservative
// force) through the move. With fix viscous after the integrator that
// conservative force is LAMMPS' own, copied by the integrator before the
// viscous force is added (no evaluation); before it, one evaluation per
// move. The same forces to round-off: the same moves accepted and the same
// volume and energy to 1e-10 after 200 steps with 40 attempts (fix viscous
// 0.5 moves the energy by far more)
TEST(PressHeld, CopiedConservativeForceAsEvaluated)
{
  const std::string hs = "fix hs all hardsphere/cva diameter 1.0\n";
  const std::string vi = "fix vi all viscous 0.5\n";
  const std::string press = "fix press all hardsphere/press iso 1.5 1.5 1.0 temp 2.0 seed 8181 "
                            "every 5 delta 0.02\n";
  const std::string fixes[3] = {hs + vi + press, vi + hs + press, hs + press};
  double vol[3], acc[3], e[3];
  for (int k = 0; k < 3; k++) {
    HSLammps h;
    std::string in = hclj_input(0.5, 2.0, 4242);
    in = in.substr(0, in.find("fix hs")) + "thermo 10000\n";
    h.lines(in + fixes[k]);
    h.cmd("run 200");
    vol[k] = h.fix_vector("press", 0);
    acc[k] = h.fix_vector("press", 2);
    e[k] = h.thermo("etotal");
  }
  std::printf("volume %.15g / %.15g / %.15g, accepted %g / %g / %g, etotal %.15g / %.15g / "
              "%.15g\n",
              vol[0], vol[1], vol[2], acc[0], acc[1], acc[2], e[0], e[1], e[2]);
  EXPECT_GT(acc[0], 5.0);
  EXPECT_EQ(acc[0], acc[1]);
  EXPECT_NEAR(vol[0], vol[1], 1e-10 * vol[1]);
  EXPECT_NEAR(e[0], e[1], 1e-10 * std::fabs(e[1]));
  EXPECT_GT(std::fabs(e[0] - e[2]), 1e-3 * std::fabs(e[2]));
}
