// Stability stress tests, dense packing (issue 4): 108 hard spheres on an
// fcc lattice at packing fraction 0.58 (above melting at 0.545, the crystal
// stays), random velocities at T = 1, no smooth forces, every method.
//
// Expected, from theory: with no smooth forces every method is exact
// free flight plus elastic impulses, so the kinetic energy and the momentum
// are conserved to round-off over the ~5000 collisions; no overlap (the fix
// stops on one); and the mean pressure follows Speedy's equation of state of
// the hard-sphere fcc crystal (R. J. Speedy, J. Phys.: Condens. Matter 10
// (1998) 4387): Z = 3/(1 - x) - a (x - b)/(x - c), x = eta/eta_cp,
// eta_cp = pi/(3 sqrt 2), a = 0.5921, b = 0.7072, c = 0.601 (Z = 13.60 at
// eta = 0.58).  Statistical error of a 2-time-unit average over 108 spheres
// a few percent: tolerance 5 %.  Longer, larger and denser runs (eta up
// to 0.72) are in examples/stress.

#include "hs_test_main.h"

#include "library.h"

#include <cmath>
#include <string>

namespace {

double speedy_Z(double eta)
{
  const double PI = 3.14159265358979323846;
  const double x = eta / (PI / (3.0 * std::sqrt(2.0)));
  return 3.0 / (1.0 - x) - 0.5921 * (x - 0.7072) / (x - 0.601);
}
}    // namespace

class StressDense : public ::testing::TestWithParam<std::string> {};

TEST_P(StressDense, FccCrystalAtEta058)
{
  const std::string m = GetParam();
  const double eta = 0.58, dt = 0.01;
  const int nsteps = 200;
  HSLammps h;
  h.lines(R"(units lj
atom_style atomic
variable eta equal 0.58
lattice fcc $(6*v_eta/PI)
region box block 0 3 0 3 0 3
create_box 1 box
create_atoms 1 box
mass 1 1.0
velocity all create 1.0 4928459 mom yes rot no dist gaussian loop geom
neighbor 0.3 bin
comm_modify cutoff 2.0
compute p all pressure thermo_temp
variable px equal vcm(all,x)
thermo_style custom step ke press
thermo_modify norm no
thermo 0
timestep 0.01
)");
  h.cmd("fix hs all hardsphere/" + m + " diameter 1.0");
  h.cmd("fix pav all ave/time 1 " + std::to_string(nsteps) + " " + std::to_string(nsteps) + " c_p");
  h.lines(R"(run 0
variable K0 equal $(ke:%.17g)
variable rho equal $(atoms/vol:%.17g)
variable kT equal $(2*ke/(3*atoms):%.17g)
)");
  h.cmd("run " + std::to_string(nsteps));
  const double K0 = h.variable("K0"), rho = h.variable("rho"), kT = h.variable("kT");
  EXPECT_NEAR(rho, 6 * eta / 3.14159265358979323846, 1e-9);
  EXPECT_NEAR(h.thermo("ke"), K0, 1e-12 * K0) << m;
  EXPECT_NEAR(h.variable("px"), 0.0, 1e-11) << m;
  const double ncoll = h.fix_vector("hs", 0);
  auto *pp = (double *) lammps_extract_fix(h.lmp, "pav", 0, 0, 0, 0);
  ASSERT_NE(pp, nullptr);
  const double P = *pp;
  lammps_free(pp);
  const double Pth = rho * kT * speedy_Z(eta);
  printf("[ dense %s ] eta %.2f: %g collisions, P %.4f, Speedy %.4f (ratio %.4f)\n", m.c_str(),
         eta, ncoll, P, Pth, P / Pth);
  // virial route: a 2-time-unit run at ~43 collisions per sphere and unit time
  EXPECT_GT(ncoll, 3000.0);
  EXPECT_NEAR(P / Pth, 1.0, 0.05) << m;
}

INSTANTIATE_TEST_SUITE_P(Methods, StressDense,
                         ::testing::Values("psa", "cva", "pcva", "mcva", "vci"));
