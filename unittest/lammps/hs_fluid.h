// The hard-core LJ fluid of the local-engine tests (500 spheres for cells
// 5, packing fraction 0.3 at diameter 1, T = 1), equilibrated by 200 psa
// steps, then timestep dt and the fix command: an input text for HSLammps.
#ifndef HS_TEST_FLUID_H
#define HS_TEST_FLUID_H

#include "hs_chain.h"
#include "hs_test_main.h"

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace hs_fluid {

inline std::string fluid(const std::string &fix, double dt, int seed = 87287, int cells = 5,
                         const std::string &pair = "lj/smooth/linear 2.5")
{
  const std::string c = std::to_string(cells);
  return R"LMP(
units lj
atom_style atomic
atom_modify map array
boundary p p p
lattice fcc 0.5729578
region box block 0 )LMP" +
      c + " 0 " + c + " 0 " + c + R"LMP(
create_box 1 box
create_atoms 1 box
mass 1 1.0
pair_style )LMP" +
      pair + R"LMP(
pair_coeff 1 1 1.0 1.0
neighbor 0.3 bin
neigh_modify every 1 delay 0 check yes
velocity all create 1.0 )LMP" +
      std::to_string(seed) + R"LMP( mom yes rot no dist gaussian
fix hs all hardsphere/psa diameter 1.0
timestep 0.005
run 200
unfix hs
reset_timestep 0
timestep )LMP" + hs_chain::f17(dt) + "\n" +
      fix + "\n";
}

// from here on, fix mx's vector entry 3 is the running max of |E(t) - E(0)|
// per atom (E: total energy; fix ave/histo's running maximum)
inline void track_max_energy_error(HSLammps &L)
{
  L.lines(R"LMP(
thermo_modify norm yes
run 0
variable E0 equal $(etotal:%.17g)
variable dE equal abs(etotal-v_E0)
fix mx all ave/histo 1 1 1 0.0 1.0 1 v_dE ave running
)LMP");
}

// max |E(t) - E(0)| per atom over T time units of the fluid at dt with the
// fix command fix, from the start of the given seed
inline double max_energy_error(const std::string &fix, double dt, double T, int seed)
{
  HSLammps L;
  L.lines(fluid(fix, dt, seed));
  track_max_energy_error(L);
  L.cmd("run " + std::to_string((int) std::lround(T / dt)));
  return L.fix_vector("mx", 3);
}

// |total momentum| after nsteps more steps, and the scale sqrt(2 M KE) to
// compare it with (velocity create ... mom yes: zero at the start)
inline void momentum_after(HSLammps &L, int nsteps, double &P, double &scale)
{
  L.lines(R"LMP(
variable px equal vcm(all,x)*mass(all)
variable py equal vcm(all,y)*mass(all)
variable pz equal vcm(all,z)*mass(all)
variable p1 equal sqrt(mass(all)*ke*2.0)
)LMP");
  L.cmd("run " + std::to_string(nsteps));
  P = std::sqrt(std::pow(L.variable("px"), 2) + std::pow(L.variable("py"), 2) +
                std::pow(L.variable("pz"), 2));
  scale = L.variable("p1");
}

// collisions per step (fix hs's entry 1) and the mean pressure (fix
// ave/time) of each of nblocks blocks of 50 steps (0.25 time units at dt
// 0.005) of the fluid set up in L
struct Blocks {
  std::vector<double> rate, press;
};
inline Blocks sample_blocks(HSLammps &L, int nblocks)
{
  L.cmd("compute pr all pressure thermo_temp");
  L.cmd("fix pa all ave/time 1 50 50 c_pr");
  L.cmd("variable pa equal f_pa");
  Blocks b;
  double last = 0.0;
  for (int k = 0; k < nblocks; k++) {
    L.cmd("run 50");
    const double n = L.fix_vector("hs", 0);
    b.rate.push_back((n - last) / 50.0);
    last = n;
    b.press.push_back(L.variable("pa"));
  }
  return b;
}

// two integrators sample the same fluid: their block means of the
// collision rate and the pressure agree within 4 combined standard errors
inline void expect_same_fluid(const Blocks &a, const Blocks &b, const std::string &la,
                              const std::string &lb)
{
  auto check = [&](const char *what, const std::vector<double> &x, const std::vector<double> &y) {
    double m1, s1, m2, s2;
    mean_se(x, m1, s1);
    mean_se(y, m2, s2);
    std::printf("%s: %s %.4f +- %.4f, %s %.4f +- %.4f\n", what, la.c_str(), m1, s1, lb.c_str(),
                m2, s2);
    EXPECT_LE(std::fabs(m1 - m2), 4.0 * std::sqrt(s1 * s1 + s2 * s2)) << what;
  };
  check("collisions per step", a.rate, b.rate);
  check("pressure", a.press, b.press);
}

}    // namespace hs_fluid

#endif
