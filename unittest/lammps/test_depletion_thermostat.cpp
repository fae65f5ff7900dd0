// The thermostat bias of examples/depletion (README, "The thermostat bias:
// mechanism"), short: hard spheres alone (pair_style zero), 500 at
// rho sigma^3 = 0.5 (packing fraction 0.262), fix hardsphere/cva, dt 0.005.
//
// fix langevin (damp 0.1: gamma dt = 0.05) acts, beside velocity Verlet and
// beside the fix alike, as two half kicks of a force -gamma m v + R held
// over the step; the velocities of the step's drift -- those at which
// spheres collide -- are then v_{n+1/2} = (1 - gamma dt) v_{n-1/2} + kicks,
// stationary at T_half = T / (1 - gamma dt / 2), while the full-step
// velocities are at T (elastic collisions conserve the drift's kinetic
// energy, so this holds with them). The collisional pressure is the
// impulses' momentum flux, so Z - 1 = (Z_hs - 1) T_half / T; Z_hs from
// Kolafa's equation of state. A thermostat that rescales velocities at the
// step's end (fix temp/berendsen) gives Z_hs itself.
//
// Checked, each within four standard errors (block means): <T> = T; the
// kinetic temperature of v - (dt/2) f/m (the drift velocities) against
// T / (1 - gamma dt / 2); Z under langevin against 1 + (Z_hs - 1) /
// (1 - gamma dt / 2) and, resolved from it, Z under berendsen against Z_hs.

#include "hs_test_main.h"

#include <cmath>
#include <fstream>
#include <sstream>

namespace {

const double PI = 3.14159265358979323846;
const double RHO = 0.5, DT = 0.005;

struct Blocks {
  std::vector<double> T, Th, Z;
};

Blocks run_hs(const std::string &thermostat, int seed)
{
  const int NB = 20, nrun = 20000, nb = nrun / NB;
  const std::string blocks = scratch_name("hs_thermostat_blocks.txt");
  char line[256];
  HSLammps h;
  snprintf(line, sizeof(line), "lattice fcc %.17g", RHO);
  h.lines(std::string("units lj\natom_style atomic\natom_modify map array\n") + line + R"(
region box block 0 5 0 5 0 5
create_box 1 box
create_atoms 1 box
mass 1 1.0
pair_style zero 1.2
pair_coeff * *
neighbor 0.3 bin
neigh_modify every 1 delay 0 check yes
comm_modify cutoff 2.0
)");
  snprintf(line, sizeof(line), "velocity all create 1.0 %d mom yes rot yes dist gaussian", seed);
  h.cmd(line);
  snprintf(line, sizeof(line), "timestep %.17g", DT);
  h.cmd(line);
  h.cmd("fix hs all hardsphere/cva diameter 1.0");
  h.cmd(thermostat);
  h.lines(R"(
run 2000
compute pvir all pressure NULL virial
)");
  snprintf(line, sizeof(line),
           "variable kh atom mass*((vx-0.5*%.17g*fx/mass)^2+(vy-0.5*%.17g*fy/mass)^2+(vz-0.5*%.17g*fz/mass)^2)", DT,
           DT, DT);
  h.cmd(line);
  h.lines(R"(
compute kh all reduce sum v_kh
variable Th equal c_kh/(3*atoms-3)
)");
  const std::string n1 = std::to_string(nb);
  h.cmd("fix blk all ave/time 1 " + n1 + " " + n1 + " c_thermo_temp v_Th c_pvir file " + blocks);
  h.cmd("run " + std::to_string(nrun));
  h.cmd("unfix blk");
  const double rho = h.thermo("atoms") / h.thermo("vol");
  EXPECT_NEAR(rho, RHO, 1e-12);

  Blocks b;
  std::ifstream in(blocks);
  std::string l;
  while (std::getline(in, l)) {
    if (l.empty() || l[0] == '#') continue;
    std::istringstream ls(l);
    double step, t, th, pv;
    if (ls >> step >> t >> th >> pv) {
      b.T.push_back(t);
      b.Th.push_back(th);
      b.Z.push_back(1.0 + pv / rho);    // kT = 1, the target
    }
  }
  std::remove(blocks.c_str());
  EXPECT_EQ((int) b.Z.size(), NB);
  return b;
}

}    // namespace

TEST(DepletionThermostat, LangevinDriftVelocitiesAndCollisionalPressure)
{
  const double eta = PI / 6.0 * RHO;
  const double Zhs = (1 + eta + eta * eta - 2.0 / 3.0 * eta * eta * eta * (1 + eta)) / std::pow(1 - eta, 3);
  const double damp = 0.1, gdt = DT / damp, hot = 1.0 / (1.0 - 0.5 * gdt);

  const Blocks lv = run_hs("fix th all langevin 1.0 1.0 0.1 4242 zero yes", 4242);
  const Blocks be = run_hs("fix th all temp/berendsen 1.0 1.0 0.1", 4343);

  double T, Tse, Th, Thse, Z, Zse, Tb, Tbse, Zb, Zbse, Thb, Thbse;
  mean_se(lv.T, T, Tse);
  mean_se(lv.Th, Th, Thse);
  mean_se(lv.Z, Z, Zse);
  mean_se(be.T, Tb, Tbse);
  mean_se(be.Th, Thb, Thbse);
  mean_se(be.Z, Zb, Zbse);
  const double Zlv = 1.0 + (Zhs - 1.0) * hot;
  printf("[ langevin, gamma dt %.3f ] <T> %.4f +- %.4f; T_half %.4f +- %.4f (1/(1 - gamma dt/2) = %.4f); "
         "Z %.4f +- %.4f against 1 + (Z_hs - 1) T_half/T = %.4f (%.1f sigma) and Z_hs = %.4f\n",
         gdt, T, Tse, Th, Thse, hot, Z, Zse, Zlv, (Z - Zlv) / Zse, Zhs);
  printf("[ berendsen ] <T> %.4f +- %.4f; T_half %.4f +- %.4f; Z %.4f +- %.4f against Z_hs = %.4f (%.1f sigma)\n", Tb,
         Tbse, Thb, Thbse, Zb, Zbse, Zhs, (Zb - Zhs) / Zbse);

  EXPECT_NEAR(T, 1.0, 4.0 * Tse);
  EXPECT_NEAR(Th, hot, 4.0 * Thse);
  EXPECT_LT(Zse, 0.015);
  EXPECT_NEAR(Z, Zlv, 4.0 * Zse);
  EXPECT_LT(Zbse, 0.015);
  EXPECT_NEAR(Zb, Zhs, 4.0 * Zbse);
  // the two predictions are resolved apart: the test sees the bias
  EXPECT_GT(Zlv - Zhs, 4.0 * std::hypot(Zse, Zbse));
}
