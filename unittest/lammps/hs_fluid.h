// The hard-core LJ fluid of the local-engine tests (500 spheres for cells
// 5, packing fraction 0.3 at diameter 1, T = 1), equilibrated by 200 psa
// steps, then timestep dt and the fix command: an input text for HSLammps.
#ifndef HS_TEST_FLUID_H
#define HS_TEST_FLUID_H

#include "hs_chain.h"
#include "hs_test_main.h"

#include <cmath>
#include <string>

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

}    // namespace hs_fluid

#endif
