/* -*- c++ -*- ----------------------------------------------------------
   Shared helpers of the in-process tests that compare two runs bit for bit
   (a hardsphere fix against fix nve when nothing collides): the standard
   systems, gathering the final state, and the bitwise comparison.
   Include after hs_test_main.h.
------------------------------------------------------------------------- */

#ifndef HS_STATE_H
#define HS_STATE_H

#include "hs_test_main.h"

#include "atom.h"
#include "library.h"

#include <string>
#include <vector>

namespace hs_state {

// the final state of a run, gathered in atom-ID order
struct State {
  std::vector<double> x, v;
  std::vector<int> img;
  std::vector<double> counters;    // the fix "int"'s first entries (hardsphere runs only)
  double ncoll = -1.0, pe = 0.0, ke = 0.0;
};

// Run setup, the integrator line fixline (fix ID "int") and tail in a fresh
// instance; for a hardsphere fix also read ncounters entries of its vector
// (ncoll is entry [1], the number of collisions).
inline State run_case(const std::string &setup, const std::string &fixline,
                      const std::string &tail, int ncounters = 1)
{
  HSLammps h;
  h.lines(setup);
  h.cmd(fixline);
  h.lines(tail);
  State s;
  const int n = (int) h.lmp->atom->natoms;
  s.x.resize(3 * n);
  s.v.resize(3 * n);
  s.img.resize(n);
  lammps_gather_atoms(h.lmp, (char *) "x", 1, 3, s.x.data());
  lammps_gather_atoms(h.lmp, (char *) "v", 1, 3, s.v.data());
  lammps_gather_atoms(h.lmp, (char *) "image", 0, 1, s.img.data());
  if (fixline.find("hardsphere") != std::string::npos) {
    for (int k = 0; k < ncounters; k++) s.counters.push_back(h.fix_vector("int", k));
    s.ncoll = s.counters.at(0);
  }
  s.pe = h.thermo("pe");
  s.ke = h.thermo("ke");
  return s;
}

// positions, velocities, image flags, pe and ke all bitwise equal
inline void expect_identical(const State &a, const State &b)
{
  ASSERT_EQ(a.x.size(), b.x.size());
  int nx = 0, nv = 0, ni = 0;
  for (size_t k = 0; k < a.x.size(); k++) {
    if (a.x[k] != b.x[k] && nx++ < 5)
      ADD_FAILURE() << "x differs at " << k << ": " << a.x[k] << " vs " << b.x[k];
    if (a.v[k] != b.v[k] && nv++ < 5)
      ADD_FAILURE() << "v differs at " << k << ": " << a.v[k] << " vs " << b.v[k];
  }
  for (size_t k = 0; k < a.img.size(); k++)
    if (a.img[k] != b.img[k] && ni++ < 5) ADD_FAILURE() << "image differs at " << k;
  EXPECT_EQ(nx, 0);
  EXPECT_EQ(nv, 0);
  EXPECT_EQ(ni, 0);
  EXPECT_EQ(a.pe, b.pe);
  EXPECT_EQ(a.ke, b.ke);
}

// LJ liquid: fcc lattice at density 0.8 in a box of n^3 cells, T = 1; the
// LJ repulsion keeps centres > ~0.8 apart, so hard cores of diameter 0.5
// never touch
inline std::string lj_fluid(int n)
{
  const std::string b = std::to_string(n);
  return "units lj\natom_style atomic\natom_modify map array\nlattice fcc 0.8\n"
         "region box block 0 " + b + " 0 " + b + " 0 " + b + "\n"
         "create_box 1 box\ncreate_atoms 1 box\nmass 1 1.0\n"
         "velocity all create 1.0 4928459 mom yes rot yes dist gaussian\n"
         "pair_style lj/cut 2.5\npair_coeff 1 1 1.0 1.0 2.5\nneighbor 0.3 bin\n"
         "neigh_modify every 1 delay 0 check yes\ntimestep 0.005\n"
         "thermo_style custom step pe ke\nthermo_modify norm no\n";
}

// the pendulum chain of the paper (anchor atom 1 of type 1, five spheres of
// type 2 in group "chain"), springs only, no wall; integrate group chain with
// tiny spheres (1-2 pairs are excluded from the pair list, i.e. bonded
// contact candidates)
inline std::string bonded_chain()
{
  return R"(
units lj
dimension 2
atom_style bond
atom_modify map array
boundary f f p
region box block -8 8 -8 8 -0.5 0.5
create_box 2 box bond/types 1 extra/bond/per/atom 2 extra/special/per/atom 6
create_atoms 1 single 0 0 0
create_atoms 2 single 1 0 0
create_atoms 2 single 2 0 0
create_atoms 2 single 3 0 0
create_atoms 2 single 4 0 0
create_atoms 2 single 5 0 0
mass * 1.0
bond_style harmonic
bond_coeff 1 0.5 1.0
create_bonds single/bond 1 1 2
create_bonds single/bond 1 2 3
create_bonds single/bond 1 3 4
create_bonds single/bond 1 4 5
create_bonds single/bond 1 5 6
group chain type 2
group s2 id 3
group s4 id 5
velocity s2 set 0.6 0.8 0
velocity s4 set -0.28 0.96 0
comm_modify cutoff 2.0
fix 2d all enforce2d
timestep 0.02
thermo_style custom step pe ke
thermo_modify norm no
)";
}

}    // namespace hs_state

#endif
