// fix hardsphere/mcva: invalid set-ups end in an ERROR naming the problem
// (LAMMPS here exits on errors: each case runs in its own lmp process).
// The keywords and set-up checks are the base class's (tested for every
// method, with its style name, in test_shared_errors.cpp); here the
// method's own failures, of its global form (substep global: the Gauss
// stages of the whole system) and of its local form (the default: each
// cluster's Gauss flow, Newton with the exact Jacobian).

#include "hs_errors.h"

#include <string>

using hs_errors::expect_error;

namespace {

std::string two_atoms(const std::string &fix)
{
  return "units lj\natom_style atomic\natom_modify map array\nboundary f f f\n"
         "region box block -5 5 -5 5 -5 5 units box\ncreate_box 1 box\n"
         "create_atoms 1 single -1 0 0 units box\ncreate_atoms 1 single 1 0 0 units box\n"
         "mass 1 1.0\ncomm_modify cutoff 3.0\n" +
      fix + "\nrun 10\n";
}

// sphere 2 sits on a harmonic bond to a fixed anchor (atom 1, not
// integrated); sphere 3 comes in along x and touches sphere 2 after t0
std::string anchored_pair(const std::string &bond_coeff, const std::string &x3,
                          const std::string &anchor_y, const std::string &dt,
                          const std::string &skin, const std::string &substep = " substep global")
{
  return "units lj\natom_style bond\natom_modify map array\nboundary f f f\n"
         "region box block -10 10 -10 10 -10 10\n"
         "create_box 2 box bond/types 1 extra/bond/per/atom 2 extra/special/per/atom 4\n"
         "create_atoms 1 single 0 " + anchor_y + " 0\ncreate_atoms 2 single 0 0 0\n"
         "create_atoms 2 single " + x3 + " 0 0\nmass * 1.0\nbond_style harmonic\n"
         "bond_coeff 1 " + bond_coeff + "\ncreate_bonds single/bond 1 1 2\n"
         "group mobile type 2\ngroup j id 3\nvelocity j set -1 0 0\n"
         "neighbor " + skin + " bin\ncomm_modify cutoff 5.0\n"
         "fix hs mobile hardsphere/mcva diameter 1.0" + substep + "\ntimestep " + dt +
      "\nrun 2\n";
}

}    // namespace

TEST(MCVAErrors, ValidBaselineRuns)
{
  expect_runs(two_atoms("fix hs all hardsphere/mcva diameter 1.0 wall xlo -4"), {}, {"ERROR"});
  // the stiff anchored pair at a sane timestep runs too (the cases below
  // differ only in the timestep or the bond)
  expect_runs(anchored_pair("1250 1.0", "1.05", "-1", "0.01", "1.0"));
  expect_runs(anchored_pair("10.0 0.5", "1.0001", "-0.1", "0.1", "2.0"));
  expect_runs(anchored_pair("1250 1.0", "1.05", "-1", "0.01", "1.0", ""),
              {"substep local (collisions"});
}

TEST(MCVAErrors, GaussStagesDoNotConverge)
{
  // omega = sqrt(2K/m) = 50, contact at tau = 0.05: h omega = 2.5 is far
  // beyond the fixed-point iteration's reach (|h omega| < 1/0.289 for Gauss
  // on a linear oscillator, less with H~'s dt^2 terms), and beyond Newton's
  // (default): there dq/dt = (I + dt^2/6 M^-1 V'') v has a factor 5.2 that
  // J0 leaves out (dt^2 omega^2 / 6 = 4.2), fine only where dt omega << 1
  expect_error(anchored_pair("1250 1.0", "1.05", "-1", "0.1", "1.0"),
               {"Gauss stage equations did not converge", "step 1", "sub-step tau 0.0",
                "relative change of the stage derivatives", "smaller timestep"});
}

TEST(MCVAErrors, ModifiedHamiltonianNotConvexAlongNormal)
{
  // the anchor bond (K = 10, r0 = 0.5) is compressed to r = 0.1 along y: its
  // curvature along x (the contact normal) is 2K (r - r0)/r = -80. With unit
  // masses u = (e_x, -e_x), w = u: u^T A u = u.w + dt^2/6 w^T V'' w
  // = 2 - 0.16/6 * 80 = -0.1333 for dt = 0.4 (0.8 > 0 for dt = 0.3)
  expect_error(anchored_pair("10.0 0.5", "1.0001", "-0.1", "0.4", "2.0"),
               {"not convex in the momenta", "atoms 2 and 3", "u^T A u = -0.1333",
                "timestep 0.4"});
  // the local form checks the same at the contact of its cluster flow
  expect_error(anchored_pair("10.0 0.5", "1.0001", "-0.1", "0.4", "2.0", ""),
               {"substep local", "not convex in the momenta", "atoms 2 and 3", "timestep 0.4"});
}

TEST(MCVAErrors, LocalFormConvergesWhereSimplifiedNewtonDoesNot)
{
  // the case of GaussStagesDoNotConverge in the local form: its Newton
  // iteration has the exact Jacobian of the cluster's stage equations, the
  // dt^2/6 M^-1 V'' v factor included, so it converges at h omega = 2.5
  // (and the impulse conserves the cluster's H~; not checked here)
  expect_runs(anchored_pair("1250 1.0", "1.05", "-1", "0.1", "1.0", ""),
              {"substep local (collisions"}, {"ERROR"});
}

TEST(MCVAErrors, FieldNotFinite)
{
  // fix addforce with a force that is 0 where atom 1 starts and NaN once it
  // moved 0.01 away (pow of a negative base: NaN without a LAMMPS error);
  // the first Gauss stage (c1 h = 0.0106) is there
  expect_error("units lj\natom_style atomic\natom_modify map array\nboundary f f f\n"
               "region box block -8 8 -8 8 -8 8\ncreate_box 1 box\n"
               "create_atoms 1 single -5 0 0\ncreate_atoms 1 single -3.95 0 0\nmass * 1.0\n"
               "group a id 1\nvelocity a set 1 0 0\n"
               "variable fx atom 0.0*((0.0001-(x+5.0)^2)^0.5)\n"
               "fix nan a addforce v_fx 0.0 0.0\nfix_modify nan energy yes\n"
               "neighbor 0.5 bin\ncomm_modify cutoff 3.0\n"
               "fix hs all hardsphere/mcva diameter 1.0 substep global\ntimestep 0.1\nrun 2\n",
               {"vector field of the modified Hamiltonian is not finite", "step 1",
                "iteration 1"});
  // (the local form holds fix addforce's force through the step, as the
  // other methods' local forms do: LAMMPS' own NaN, as under fix nve)
}
