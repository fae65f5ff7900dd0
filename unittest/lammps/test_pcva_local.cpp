// fix hardsphere/pcva with substep local (hs_local_modified.h, doc
// fix_hardsphere_pcva "Local projection") on hard-core LJ fluids. Expected
// values come from the method's theory and from the global projection:
// - the local projection undoes each step's change of the modified
//   Hamiltonian H~ = H_[2,VV] up to O(dt^4) per step with clusters, which
//   come at a fixed rate per unit time: H~ (compute hamiltonian/modified, a
//   global evaluation independent of the local bookkeeping) drifts at
//   fourth order over a fixed time (fitted >= 3.6), far below local cva;
//   the pair style is lj/gromacs, whose V'' is continuous at the cutoff
//   (lj/smooth/linear's V'' jumps there, so H~ itself jumps by O(dt^2) at
//   each crossing, for fix nve as well: no fourth order to find);
// - scaling relative to each cluster's centre of mass keeps momentum;
// - local and global pcva sample the same fluid: energy error, pressure and
//   collision rate agree (block-average error bars) on 4000 spheres (the
//   energy error H - H0 of both is Verlet's smooth O(dt^2) fluctuation
//   H - H~, since both keep H~: they agree closely);
// - held (thermostat) forces: a zero one changes nothing (the thermostat
//   tests of test_thermostats.cpp run pcva local with every thermostat);
// - where the local projection cannot run, the fall-back and error name why.

#include "hs_chain.h"
#include "hs_errors.h"
#include "hs_fluid.h"
#include "hs_modified_energy.h"
#include "hs_test_main.h"

#include "library.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <regex>

using hs_errors::expect_error;

namespace {

// the fluid of test_local_engine.cpp with lj/gromacs 2.0 2.5 (V'' continuous
// at the cutoff)
std::string fluid(const std::string &fix, double dt, int seed = 87287, int cells = 5)
{
  return hs_fluid::fluid(fix, dt, seed, cells, "lj/gromacs 2.0 2.5");
}

// from here on, fix mx's vector entry 3 is the running max of |H~(t) -
// H~(0)| per atom (compute hamiltonian/modified's H_[2,VV])
void track_max_modified_error(HSLammps &L)
{
  L.lines(R"LMP(
compute hm all hamiltonian/modified
variable H2 equal c_hm[2]/atoms
thermo_style custom step etotal v_H2
run 0
variable E0 equal $(v_H2:%.17g)
variable dE equal abs(v_H2-v_E0)
fix mx all ave/histo 1 1 1 0.0 1.0 1 v_dE ave running
)LMP");
}

// max |H~(t) - H~(0)| per atom over time T
double max_modified_error(const std::string &method, double dt, double T, int seed,
                          double *nproj = nullptr)
{
  HSLammps L;
  L.lines(fluid("fix hs all hardsphere/" + method + " diameter 1.0 substep local", dt, seed));
  track_max_modified_error(L);
  L.cmd("run " + std::to_string((int) std::lround(T / dt)));
  if (nproj) *nproj = L.fix_vector("hs", 5);
  return L.fix_vector("mx", 3);
}


}    // namespace

// the max of one trajectory is set by a few events: the mean over 2 starts
TEST(PCVALocal, FluidModifiedHamiltonianFourthOrder)
{
  const std::vector<double> dts = {0.01, 0.005, 0.0025, 0.00125};
  std::vector<double> ep;
  for (double dt : dts) {
    double p = 0.0, c = 0.0, nproj = 0.0;
    for (int seed : {111, 222}) {
      p += 0.5 * max_modified_error("pcva", dt, 0.5, seed, &nproj);
      EXPECT_GT(nproj, 0.0) << "no local projection at dt " << dt;
      c += 0.5 * max_modified_error("cva", dt, 0.5, seed);
    }
    std::printf("dt %g mean max|dH~|/N: pcva local %.3e, cva local %.3e (%.0fx)\n", dt, p, c,
                c / p);
    EXPECT_GT(c, 10.0 * p) << "dt " << dt;
    ep.push_back(p);
  }
  const double order = hs_chain::loglog_slope(dts, ep);
  std::printf("pcva local: fitted order %.2f\n", order);
  EXPECT_GE(order, 3.6);
}

// fix gravity (fix_modify energy yes): m g is a one-atom term of V_C for the
// members, so the ledger holds their -m g.q (HSLocalModified::
// const_energy()); H~ with the field's energy is kept to fourth order as
// without it. 500 spheres settling onto the fix's wall at zlo (g 0.5, a
// wall at zhi), lj/gromacs, 0.5 time units, mean over 2 starts. Without
// the field's energy in the ledger the error was ~1e-2, first order
static double max_modified_error_gravity(const std::string &method, double dt, int seed)
{
  HSLammps L;
  L.lines(R"LMP(
units lj
atom_style atomic
atom_modify map array
boundary p p f
lattice fcc 0.5729578
region box block 0 5 0 5 -0.5 5
region fill block 0 5 0 5 0.0 4.5
create_box 1 box
create_atoms 1 region fill
mass 1 1.0
pair_style lj/gromacs 2.0 2.5
pair_coeff 1 1 1.0 1.0
neighbor 0.3 bin
neigh_modify every 1 delay 0 check yes
velocity all create 1.0 )LMP" + std::to_string(seed) + R"LMP( mom yes rot no dist gaussian
fix g all gravity 0.5 vector 0 0 -1
fix_modify g energy yes
fix hs all hardsphere/)LMP" + method + R"LMP( diameter 1.0 wall zlo EDGE wall zhi EDGE
timestep )LMP" + hs_chain::f17(dt) + "\n");
  track_max_modified_error(L);
  L.cmd("run " + std::to_string((int) std::lround(0.5 / dt)));
  // (steps that fell back: f_hs[10] of cva, f_hs[13] of pcva)
  // (the entry of steps that fell back: cva 10, pcva 13, mcva 18)
  EXPECT_EQ(L.fix_vector("hs", method == "cva" ? 9 : method == "mcva" ? 17 : 12), 0.0)
      << method << ": fell back to substep global";
  EXPECT_GT(L.fix_vector("hs", 2), 0.0) << method << ": no wall contact";
  return L.fix_vector("mx", 3);
}

TEST(PCVALocal, GravityModifiedHamiltonianFourthOrder)
{
  const std::vector<double> dts = {0.01, 0.005, 0.0025};
  std::vector<double> ep;
  for (double dt : dts) {
    double p = 0.0, c = 0.0;
    for (int seed : {111, 222}) {
      p += 0.5 * max_modified_error_gravity("pcva", dt, seed);
      c += 0.5 * max_modified_error_gravity("cva", dt, seed);
    }
    std::printf("gravity, dt %g mean max|dH~|/N: pcva local %.3e, cva local %.3e (%.0fx)\n", dt,
                p, c, c / p);
    // (measured 9x at dt 0.01, 28x at 0.005, 130x at 0.0025)
    EXPECT_GT(c, (dt > 0.006 ? 5.0 : 10.0) * p) << "dt " << dt;
    ep.push_back(p);
  }
  const double order = hs_chain::loglog_slope(dts, ep);
  std::printf("pcva local with gravity: fitted order %.2f\n", order);
  EXPECT_GE(order, 3.6);
}

// held smooth forces (kspace, fixes with an energy but fix gravity): the
// engine holds their force G = f - F_C on each member (riding in its flow,
// the closing kick making the impulse dt/2 (G0 + G1)); their energy is not
// restrictable, so the ledger takes the members' share of its change as
// minus their work, -1/2 (G0 + G1).(q1 - q0) (HSLocalModified::
// held_energy_change()). The rule's error is second order with the held
// terms' curvature as its constant (doc fix_hardsphere_pcva, "Held smooth
// forces"). max |H~(t) - H~(0)| per atom over 0.5 time units, no fall-back
static double max_modified_error_held(const std::string &method, double dt, int seed,
                                      const std::string &held, int cells = 5,
                                      const std::string &after = "")
{
  const bool ions = held == "ewald";
  HSLammps L;
  if (ions) {
    // the fluid with charges +-0.5 (pair_modify table 0: the real-space
    // forces are their energy's gradient)
    L.lines(R"LMP(
units lj
atom_style charge
atom_modify map array
lattice fcc 0.5729578
region box block 0 )LMP" + std::to_string(cells) + " 0 " + std::to_string(cells) + " 0 " +
            std::to_string(cells) + R"LMP(
create_box 2 box
create_atoms 1 box
variable odd atom id%2
group anion variable odd
set group anion type 2
set type 1 charge 0.5
set type 2 charge -0.5
mass * 1.0
pair_style hybrid/overlay lj/gromacs 2.0 2.5 coul/long 3.0
pair_coeff * * lj/gromacs 1.0 1.0
pair_coeff * * coul/long
pair_modify table 0
kspace_style ewald 1e-8
neighbor 0.3 bin
neigh_modify every 1 delay 0 check yes
velocity all create 1.0 )LMP" + std::to_string(seed) + R"LMP( mom yes rot no dist gaussian
fix hs all hardsphere/psa diameter 1.0
timestep 0.005
run 200
unfix hs
reset_timestep 0
)LMP");
  } else
    // tethered: fix spring/self with its energy
    L.lines(hs_fluid::fluid("fix ss all spring/self 5.0\nfix_modify ss energy yes", 0.005, seed,
                            cells, "lj/gromacs 2.0 2.5"));
  L.lines("timestep " + hs_chain::f17(dt) + "\nfix hs all hardsphere/" + method +
          " diameter 1.0 substep local\n" + after);
  track_max_modified_error(L);
  L.cmd("run " + std::to_string((int) std::lround(0.5 / dt)));
  // (the entry of steps that fell back: cva 10, pcva 13, mcva 18)
  EXPECT_EQ(L.fix_vector("hs", method == "cva" ? 9 : method == "mcva" ? 17 : 12), 0.0)
      << method << ": fell back to substep global";
  return L.fix_vector("mx", 3);
}

// method (pcva or mcva) local against cva local at each dt of dts (at
// least 10x below), and the fitted order of the method's error
static double held_order(const std::string &method, const std::string &held,
                         const std::vector<double> &dts, int cells)
{
  std::vector<double> ep;
  for (double dt : dts) {
    const double p = max_modified_error_held(method, dt, 111, held, cells),
                 c = max_modified_error_held("cva", dt, 111, held, cells);
    std::printf("%s, dt %g max|dH~|/N: %s local %.3e, cva local %.3e (%.0fx)\n", held.c_str(),
                dt, method.c_str(), p, c, c / p);
    EXPECT_GT(c, 10.0 * p) << method << " with " << held << " dt " << dt;
    ep.push_back(p);
  }
  const double order = hs_chain::loglog_slope(dts, ep);
  std::printf("%s local with %s: fitted order %.2f\n", method.c_str(), held.c_str(), order);
  return order;
}

// mcva's local form takes held forces into pcva's ledger too (its
// projection is pcva's): with ewald's ions and with spring/self, its H~
// error at least 10x below cva local's and of fourth or at least second
// order (the held terms' rule is second order with their curvature as its
// constant)
TEST(MCVALocalHeld, KspaceAndSpringEnergyByTheirWork)
{
  EXPECT_GE(held_order("mcva", "ewald", {0.01, 0.005}, 4), 1.8);
  EXPECT_GE(held_order("mcva", "spring", {0.01, 0.005}, 5), 1.8);
}

// 500 spheres tethered by fix spring/self (k 5, fix_modify energy yes).
// Measured: pcva 7.3e-6, 4.0e-7, 5.0e-8 (order 3.6), 18-138x below cva
TEST(PCVALocal, HeldSpringEnergyByItsWork)
{
  EXPECT_GE(held_order("pcva", "spring", {0.01, 0.005, 0.0025}, 5), 2.5);
}

// charged hard spheres: the fluid with charges +-0.5, coul/long 3.0 and
// ewald (held), 256 ions. Measured: pcva 1.6e-5, 1.0e-6 against cva's
// 5.8e-4, 1.7e-4; without the work in the ledger pcva was 2.1e-4, 8.5e-5
// (order 1.3), and with spring/self above 1.4e-2 .. 3.5e-3 (first order,
// 100x worse than cva)
TEST(PCVALocal, HeldKspaceEnergyByItsWork)
{
  EXPECT_GE(held_order("pcva", "ewald", {0.01, 0.005}, 4), 1.8);
}

// beside a thermostat's held forces (fix viscous here, after the
// integrator): the fix copies LAMMPS' force before the thermostat adds its
// own, which splits a member's held force into the thermostat's (two half
// kicks around the conservative map, out of the ledger) and the spring's
// (riding, its work in the ledger). A zero thermostat force must then
// change nothing: the same max |H~(t) - H~(0)| as without it, to round-off
// (the ledger's thermostat path sums in another order). Before, this input
// fell back to substep global; a ledger that took the thermostat's
// velocities for the spring's (or the spring's for the thermostat's) would
// be first order, as without the work term (1e-2 .. 3e-3)
TEST(PCVALocal, HeldSpringBesideZeroThermostat)
{
  for (double dt : {0.01, 0.005}) {
    const double p = max_modified_error_held("pcva", dt, 111, "spring", 5),
                 z = max_modified_error_held("pcva", dt, 111, "spring", 5,
                                             "fix vi all viscous 0.0\n");
    std::printf("spring, dt %g max|dH~|/N: pcva local %.6e, with fix viscous 0 after it %.6e\n",
                dt, p, z);
    EXPECT_GT(p, 0.0);
    EXPECT_NEAR(z, p, 1e-4 * p) << "dt " << dt;
  }
}

// a bead-spring melt with angle, dihedral and improper terms (the local projection's
// terms that are not radial: energy and forces by the styles' compute() on
// each term alone, V_t'' v and V_t'' b by differences, hs_local_modified.cpp
// general_term()). 60 chains of 10 beads (harmonic bonds 1.1, angle
// cosine/squared 60 at 110 degrees, dihedral harmonic, improper cvff on
// the same quadruples, lj/gromacs 2.0 2.5
// with sigma 0.9, hard cores 1.0, bonded neighbours colliding too), brought
// to T 1.5 by cva and fix langevin (500 steps), then run by the method over
// 0.5 time units. The angles are stiff enough that no angle nears 180
// degrees, where a dihedral's force turns over and H~ is not smooth
// (compute hamiltonian/modified then reports NaN). Returns max |H~(t) -
// H~(0)| per atom; fell_back: steps taken by the global engine
static double melt_max_modified_error(const std::string &method, double dt, double &fell_back)
{
  const std::string data = scratch_name("pcva_local_melt.data");
  {
    // chains along x on a square lattice in y, z with a small helical
    // offset (no straight angle to start from)
    const int n = 6, nb = 10;
    const double b = 1.1, c = 1.25, pi = std::acos(-1.0);
    std::string atoms, bonds, angles, dihedrals, impropers;
    int nbond = 0, nangle = 0, ndih = 0;
    for (int k = 0, tag = 0; k < n; k++)
      for (int j = 0; j < n; j++)
        for (int i = 0; i < nb; i++) {
          tag++;
          const double y = (j + 0.5) * c + 0.1 * std::cos(0.5 * pi * i);
          const double z = (k + 0.5) * c + 0.1 * std::sin(0.5 * pi * i);
          atoms += fmt::format("{} {} 1 {:.10f} {:.10f} {:.10f}\n", tag, (tag - 1) / nb + 1,
                               (i + 0.5) * b, y, z);
          if (i >= 1) bonds += fmt::format("{} 1 {} {}\n", ++nbond, tag - 1, tag);
          if (i >= 2) angles += fmt::format("{} 1 {} {} {}\n", ++nangle, tag - 2, tag - 1, tag);
          if (i >= 3) {
            dihedrals += fmt::format("{} 1 {} {} {} {}\n", ++ndih, tag - 3, tag - 2, tag - 1, tag);
            impropers += fmt::format("{} 1 {} {} {} {}\n", ndih, tag - 3, tag - 2, tag - 1, tag);
          }
        }
    FILE *f = std::fopen(data.c_str(), "w");
    if (!f) {
      ADD_FAILURE() << "cannot write " << data;
      return NAN;
    }
    std::fprintf(f, "%s",
                 fmt::format("bead-spring chains\n\n{} atoms\n{} bonds\n{} angles\n{} "
                             "dihedrals\n{} impropers\n1 atom types\n1 bond types\n1 angle "
                             "types\n1 dihedral types\n1 improper types\n\n0 {} xlo xhi\n0 {} "
                             "ylo yhi\n0 {} zlo zhi\n\nMasses\n\n1 1.0\n\nAtoms # molecular"
                             "\n\n{}\nBonds\n\n{}\nAngles\n\n{}\nDihedrals\n\n{}\nImpropers"
                             "\n\n{}",
                             n * n * nb, nbond, nangle, ndih, ndih, nb * b, n * c, n * c, atoms,
                             bonds, angles, dihedrals, impropers)
                     .c_str());
    std::fclose(f);
  }
  HSLammps L;
  L.lines(R"LMP(
units       lj
atom_style  molecular
atom_modify map array
read_data   )LMP" + data + R"LMP(
velocity    all create 1.5 4928459 mom yes rot no dist gaussian loop geom
pair_style  lj/gromacs 2.0 2.5
pair_coeff  1 1 1.0 0.9
bond_style  harmonic
bond_coeff  1 100.0 1.1
angle_style cosine/squared
angle_coeff 1 60.0 110.0
dihedral_style harmonic
dihedral_coeff 1 0.5 1 2
improper_style cvff
improper_coeff 1 0.5 1 2
special_bonds lj 0.0 1.0 1.0
neighbor    0.3 bin
neigh_modify every 1 delay 0 check yes
fix         hs all hardsphere/cva diameter 1.0
fix         lg all langevin 1.5 1.5 0.5 8732
timestep    0.004
run 500
unfix lg
unfix hs
reset_timestep 0
fix hs all hardsphere/)LMP" + method + R"LMP( diameter 1.0 substep local
timestep )LMP" + hs_chain::f17(dt) + R"LMP(
compute hm all hamiltonian/modified
variable H2 equal c_hm[2]/atoms
)LMP");
  std::remove(data.c_str());
  const std::string out = scratch_name("pcva_local_melt_" + method + ".txt");
  L.cmd("fix ser all ave/time 1 1 1 v_H2 file " + out + " format \" %.17g\"");
  const int nsteps = (int) std::lround(0.5 / dt);
  L.cmd("run " + std::to_string(nsteps));
  fell_back = L.fix_vector("hs", method == "cva" ? 9 : 12);
  const auto ser = hs_test::read_series(out);
  std::remove(out.c_str());
  EXPECT_EQ((int) ser.size(), nsteps + 1);
  double h0 = ser.begin()->second.at(0), emax = 0.0;
  for (const auto &[step, v] : ser) {
    EXPECT_TRUE(std::isfinite(v.at(0))) << method << " dt " << dt << ": H~ not smooth at step "
                                        << step;
    emax = std::max(emax, std::fabs(v.at(0) - h0));
  }
  return emax;
}

TEST(PCVALocal, MeltWithBondedTermsFourthOrder)
{
  const std::vector<double> dts = {0.004, 0.002, 0.001};
  std::vector<double> ep;
  for (double dt : dts) {
    double fb_p = -1.0, fb_c = -1.0;
    const double p = melt_max_modified_error("pcva", dt, fb_p);
    const double c = melt_max_modified_error("cva", dt, fb_c);
    std::printf("melt with angles, dihedrals, impropers, dt %g max|dH~|/N: pcva local %.3e, cva local "
                "%.3e (%.0fx)\n", dt, p, c, c / p);
    EXPECT_EQ(fb_p, 0.0) << "pcva fell back to substep global at dt " << dt;
    EXPECT_EQ(fb_c, 0.0) << "cva fell back to substep global at dt " << dt;
    // (measured 320x at dt 0.004, 1600x at 0.002, 10000x at 0.001)
    EXPECT_GT(c, 50.0 * p) << "dt " << dt;
    ep.push_back(p);
  }
  const double order = hs_chain::loglog_slope(dts, ep);
  std::printf("pcva local, melt with angles, dihedrals, impropers: fitted order %.2f\n", order);
  EXPECT_GE(order, 3.6);
}

TEST(PCVALocal, MomentumIsConserved)
{
  HSLammps L;
  L.lines(fluid("fix hs all hardsphere/pcva diameter 1.0 substep local", 0.005));
  double P, scale;
  hs_fluid::momentum_after(L, 400, P, scale);
  EXPECT_GT(L.fix_vector("hs", 5), 100.0);    // projections happened
  EXPECT_LT(P, 1e-11 * scale) << "P " << P << " scale " << scale;
}

namespace {
struct Stat {
  double mean, se;
};
Stat stat(const std::vector<double> &v)
{
  double m = 0, q = 0;
  for (double x : v) m += x;
  m /= v.size();
  for (double x : v) q += (x - m) * (x - m);
  return {m, std::sqrt(q / (v.size() - 1) / v.size())};
}
struct FluidRun {
  double emax;    // max |E - E0| per atom
  Stat rate, press;
};
// 4000 spheres from one equilibrated state: the max energy error, and
// block means of collisions per step and of the pressure
FluidRun run_4000(const std::string &substep)
{
  const int nblock = 10, len = 15;
  HSLammps L;
  L.lines(fluid("fix hs all hardsphere/pcva diameter 1.0 substep " + substep, 0.005, 87287, 10));
  hs_fluid::track_max_energy_error(L);
  std::vector<double> r, p;
  for (int b = 0; b < nblock; b++) {
    const double c0 = L.fix_vector("hs", 0);
    L.cmd("fix ap all ave/time 1 1 1 c_thermo_press ave running");
    L.cmd("run " + std::to_string(len));
    r.push_back((L.fix_vector("hs", 0) - c0) / len);
    auto *pv = (double *) lammps_extract_fix(L.lmp, "ap", 0, 0, 0, 0);
    p.push_back(*pv);
    lammps_free(pv);
    L.cmd("unfix ap");
  }
  return {L.fix_vector("mx", 3), stat(r), stat(p)};
}
}    // namespace

TEST(PCVALocal, AgreesWithGlobalOn4000Spheres)
{
  const FluidRun a = run_4000("local"), b = run_4000("global");
  std::printf("local: max|dE|/N %.3e, collisions/step %.2f +- %.2f, P %.4f +- %.4f\n", a.emax,
              a.rate.mean, a.rate.se, a.press.mean, a.press.se);
  std::printf("global: max|dE|/N %.3e, collisions/step %.2f +- %.2f, P %.4f +- %.4f\n", b.emax,
              b.rate.mean, b.rate.se, b.press.mean, b.press.se);
  EXPECT_GT(a.emax, 0.5 * b.emax);
  EXPECT_LT(a.emax, 2.0 * b.emax);
  EXPECT_LT(std::fabs(a.rate.mean - b.rate.mean),
            3.0 * std::hypot(a.rate.se, b.rate.se));
  EXPECT_LT(std::fabs(a.press.mean - b.press.mean),
            3.0 * std::hypot(a.press.se, b.press.se));
  // error bars that can tell something apart: a few per cent of the rate
  // and of the kinetic pressure rho T = 0.573 (the virial nearly cancels
  // it here: P is about 0.35)
  EXPECT_LT(a.rate.se, 0.05 * a.rate.mean);
  EXPECT_LT(a.press.se, 0.05 * 0.5729578);
}

// held (thermostat) forces: the projection works on the conservative map
// between the held half kicks, with the members' and partners' conservative
// forces from restricted evaluations. A held force that is zero (fix
// viscous 0) must then leave the trajectory as it is without it, to
// round-off, though every held-force path runs. Defined after the
// integrator, the conservative forces are LAMMPS' own, copied before fix
// viscous adds its zero: the held force is zero exactly, and so is the
// change
TEST(PCVALocal, ZeroHeldForceChangesNothing)
{
  double e[3], t[3], proj[3];
  for (int held = 0; held < 3; held++) {
    HSLammps L;
    const std::string hs = "fix hs all hardsphere/pcva diameter 1.0";
    L.lines(fluid(held == 0 ? hs
                      : held == 1 ? "fix vv all viscous 0.0\n" + hs
                                  : hs + "\nfix vv all viscous 0.0",
                  0.005));
    L.cmd("run 300");
    e[held] = lammps_get_thermo(L.lmp, "etotal");
    t[held] = lammps_get_thermo(L.lmp, "temp");
    proj[held] = L.fix_vector("hs", 5);
  }
  std::printf("etotal %.15g / %.15g / %.15g, projections %g / %g / %g\n", e[0], e[1], e[2],
              proj[0], proj[1], proj[2]);
  EXPECT_GT(proj[0], 100.0);
  EXPECT_EQ(proj[0], proj[1]);
  EXPECT_NEAR(e[0], e[1], 1e-10 * std::fabs(e[0]));
  EXPECT_NEAR(t[0], t[1], 1e-10);
  EXPECT_EQ(proj[0], proj[2]);
  EXPECT_EQ(e[0], e[2]);
  EXPECT_EQ(t[0], t[2]);
}

// where the local projection cannot run: the default falls back to the
// global engine with one warning naming why; substep local is an error
// atoms deleted within a step (fix evaporate at the step's reneighboring,
// between initial_integrate and final_integrate): H_[2,VV] at the step's end
// is another system's, and the projection must not carry the deleted atoms'
// energy into the others (global: it did, the whole kinetic energy of the
// evaporated atoms; local: it stopped, a deleted member not found). The
// evaporated atoms (type 2) have no interactions and move along x and y
// only, above a colliding fluid (type 1): the energy after the step is the
// energy before less their kinetic energy, up to one step's change of the
// fluid's own (~0.003 here). Two of them meet head-on in the step of the
// deletion (a cluster whose members are gone at the step's end)
TEST(PCVALocal, EvaporatedAtomsLeaveTheStepUnprojected)
{
  for (const char *sub : {"global", "local"}) {
    HSLammps L;
    L.lines(std::string(R"LMP(
units       lj
atom_style  atomic
atom_modify map array
boundary    p p f
lattice     fcc 0.6
region      box block 0 8 0 8 -0.3 14 units lattice
create_box  2 box
region      A block 0 8 0 8 0 6 units lattice
create_atoms 1 region A
region      B block 0 8 0 8 10 13 units lattice
create_atoms 2 single 0.5 0.5 11.0 units lattice
create_atoms 2 single 2.5 2.5 11.0 units lattice
create_atoms 2 single 4.5 4.5 11.0 units lattice
create_atoms 2 single 6.5 6.5 11.0 units lattice
create_atoms 2 single 2.5 6.5 12.0 units lattice
create_atoms 2 single 5.05 6.59 23.9 units box
create_atoms 2 single 10.01 6.59 23.9 units box
mass        * 1.0
group       A type 1
group       B type 2
velocity    A create 1.5 4711 dist gaussian loop geom
velocity    B set 20.0 7.0 0.0
group       C1 id 1670
group       C2 id 1671
velocity    C1 set 20.0 0.0 0.0 units box
velocity    C2 set -20.0 0.0 0.0 units box
pair_style  lj/cut 2.5
pair_coeff  1 1 1.0 1.0 2.5
pair_coeff  1 2 0.0 1.0 2.5
pair_coeff  2 2 0.0 1.0 2.5
pair_modify shift yes
neighbor    0.3 bin
fix         hs all hardsphere/pcva diameter 1.0 wall zlo EDGE wall zhi EDGE substep )LMP") +
            sub + R"LMP(
fix         ev all evaporate 50 10 B 4711
compute     kB B ke
timestep    0.002
variable    e equal etotal
variable    k equal c_kB
thermo_style custom step etotal v_k
thermo_modify norm no
run         49
)LMP");
    const double e49 = L.variable("e"), k49 = L.variable("k");
    // (the pair 1670-1671 is 1.04 apart, closing at 0.08 per step)
    EXPECT_EQ(L.thermo("atoms"), 1671.0);
    const double skip49 = L.fix_vector("hs", 6);
    L.cmd("run 1");
    const double e50 = L.variable("e");
    EXPECT_EQ(L.thermo("atoms"), 1664.0) << sub << ": the 7 atoms of B were not evaporated";
    EXPECT_GT(L.fix_vector("hs", 0), 100.0) << sub << ": the fluid does not collide";
    EXPECT_EQ(L.fix_vector("hs", 6) - skip49, 1.0) << sub << ": the step with the deletion";
    EXPECT_GT(k49, 3000.0);
    EXPECT_NEAR(e50, e49 - k49, 0.05) << sub << ": E(49) " << e49 << ", KE of the evaporated "
                                      << k49 << ", E(50) " << e50;
  }
}

TEST(PCVALocal, FallbacksAndErrorsNameTheCause)
{
  // a conservative fix with an energy of its own (fix spring/self,
  // fix_modify energy yes) is a held smooth force, whose work the ledger
  // counts; beside a thermostat's held forces (fix langevin) the fix's copy
  // of LAMMPS' force before the thermostat's tells the two apart: defined
  // after the integrator, it runs locally; before it, both would ride in
  // the members' flows, where the thermostat's work cannot be told apart
  const std::string base = R"LMP(units lj
atom_style atomic
atom_modify map array
boundary p p p
region box block -5 5 -5 5 -5 5
create_box 1 box
create_atoms 1 single 0 0 0
create_atoms 1 single 1.2 0 0
create_atoms 1 single 2.0 0.9 0
mass 1 1.0
pair_style lj/cut 2.5
pair_coeff 1 1 1.0 1.0
fix ss all spring/self 1.0
fix_modify ss energy yes
velocity all create 1.0 4321
timestep 0.005
)LMP";
  // alone it runs locally
  const auto alone = expect_runs(base + "fix hs all hardsphere/pcva diameter 1.0\nrun 5\n",
                                 {"substep local (collisions sub-stepped per cluster)"});
  EXPECT_EQ(alone.output.find("falls back"), std::string::npos) << alone.output;
  const std::string lg = "fix lg all langevin 1.0 1.0 1.0 4711\n";
  const auto split = expect_runs(base + "fix hs all hardsphere/pcva diameter 1.0\n" + lg +
                                     "run 5\n",
                                 {"substep local (collisions sub-stepped per cluster)",
                                  "the held thermostat forces of fix lg langevin stay two half "
                                  "kicks around the flows"});
  EXPECT_EQ(split.output.find("falls back"), std::string::npos) << split.output;
  // the fixes named, not the pair style beside them
  const auto r = expect_runs(base + lg + "fix hs all hardsphere/pcva diameter 1.0\nrun 5\n",
                             {"substep local is not available with fix ss spring/self beside "
                              "the held thermostat forces of fix lg langevin when fix lg "
                              "langevin come(s) before it in the input",
                              "define the thermostat after fix hs",
                              "falls back to substep global"});
  const size_t w = r.output.find("substep local is not available");
  ASSERT_NE(w, std::string::npos);
  const std::string warning = r.output.substr(w, r.output.find('\n', w) - w);
  EXPECT_EQ(warning.find("lj/cut"), std::string::npos) << warning;
  expect_error(base + lg + "fix hs all hardsphere/pcva diameter 1.0 substep local\nrun 5\n",
               {"Fix hardsphere/pcva substep local cannot run with fix ss spring/self beside "
                "the held thermostat forces"});
}
