// fix hardsphere/pcva without collisions is velocity Verlet (section 3.2:
// only steps with collisions are projected): a run in which no contact
// happens must reproduce fix nve bit for bit, with no projection.

#include "hs_test_main.h"

#include "atom.h"
#include "library.h"

namespace {

struct State {
  std::vector<double> x, v;
  double ncoll = -1.0, nproj = -1.0, pe = 0.0, ke = 0.0;
};

State run_case(const std::string &setup, const std::string &fixline, const std::string &tail)
{
  HSLammps h;
  h.lines(setup);
  h.cmd(fixline);
  h.lines(tail);
  State s;
  const int n = (int) h.lmp->atom->natoms;
  s.x.resize(3 * n);
  s.v.resize(3 * n);
  lammps_gather_atoms(h.lmp, (char *) "x", 1, 3, s.x.data());
  lammps_gather_atoms(h.lmp, (char *) "v", 1, 3, s.v.data());
  if (fixline.find("hardsphere") != std::string::npos) {
    s.ncoll = h.fix_vector("int", 0);
    s.nproj = h.fix_vector("int", 5);
  }
  s.pe = h.thermo("pe");
  s.ke = h.thermo("ke");
  return s;
}

void expect_identical(const State &a, const State &b)
{
  ASSERT_EQ(a.x.size(), b.x.size());
  int nx = 0, nv = 0;
  for (size_t k = 0; k < a.x.size(); k++) {
    if (a.x[k] != b.x[k] && nx++ < 5) ADD_FAILURE() << "x differs at " << k << ": " << a.x[k] << " vs " << b.x[k];
    if (a.v[k] != b.v[k] && nv++ < 5) ADD_FAILURE() << "v differs at " << k << ": " << a.v[k] << " vs " << b.v[k];
  }
  EXPECT_EQ(nx, 0);
  EXPECT_EQ(nv, 0);
  EXPECT_EQ(a.pe, b.pe);
  EXPECT_EQ(a.ke, b.ke);
}

}    // namespace

TEST(PCVANoCollision, LJFluidBitwiseFixNVE)
{
  const std::string setup = R"(
units lj
atom_style atomic
atom_modify map array
lattice fcc 0.8
region box block 0 4 0 4 0 4
create_box 1 box
create_atoms 1 box
mass 1 1.0
velocity all create 1.0 4928459 mom yes rot yes dist gaussian
pair_style lj/cut 2.5
pair_coeff 1 1 1.0 1.0 2.5
neighbor 0.3 bin
neigh_modify every 1 delay 0 check yes
timestep 0.005
thermo_style custom step pe ke
thermo_modify norm no
)";
  // the LJ repulsion keeps centres > ~0.8 apart at T ~ 1: hard cores of
  // diameter 0.5 never touch, but come within the screening distance
  State nve = run_case(setup, "fix int all nve", "run 200\n");
  State hs = run_case(setup, "fix int all hardsphere/pcva diameter 0.5", "run 200\n");
  EXPECT_EQ(hs.ncoll, 0.0);
  EXPECT_EQ(hs.nproj, 0.0);
  expect_identical(nve, hs);
  EXPECT_GT(nve.ke, 0.0);
}

TEST(PCVANoCollision, BondedChainBitwiseFixNVE)
{
  const std::string setup = R"(
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
  State nve = run_case(setup, "fix int chain nve", "run 500\n");
  State hs = run_case(setup, "fix int chain hardsphere/pcva diameter 0.05", "run 500\n");
  EXPECT_EQ(hs.ncoll, 0.0);
  EXPECT_EQ(hs.nproj, 0.0);
  expect_identical(nve, hs);
}
