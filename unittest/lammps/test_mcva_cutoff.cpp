// fix hardsphere/mcva with a pair style cut off without smoothing (lj/cut:
// the force jumps by |phi'(rc)| = 0.039 eps/sigma at rc = 2.5 sigma, shift
// or not). The Gauss stage equations K = f(y0 + h A K) with such a field
// have no solution when a stage position puts a pair at the cutoff: the
// fixed-point iteration flipped that pair in and out on alternate sweeps
// (measured on the LJ fluid of examples/thermostats, 108 atoms, step 327:
// the count of pairs across the cutoff at stage 2 alternated 9, 8, 9, ...
// for 100 sweeps, relative change 2.0e-4). Every solve from a sub-step's
// start now takes the pairs inside their cutoff at that start
// (HSPotential::freeze_cutoff_set; doc/fix_hardsphere_mcva.rst).
//
// Expected values: the frozen set's forces and V''w are those of the pair
// potential continued past the cutoff (analytic LJ) for a frozen pair that
// left it, and zero for a pair that entered it; the live set gives the
// reverse. The fluid run must pass the step where the old iteration stopped.

#include "hs_test_main.h"

#include "hs_chain.h"

#include "compute_hamiltonian_modified.h"
#include "hs_potential.h"

#include "atom.h"
#include "memory.h"
#include "modify.h"

#include <cmath>
#include <regex>
#include <vector>

using LAMMPS_NS::HSPotential;

namespace {

const double RC = 2.5;

// phi'(r) of LJ (eps = sigma = 1): dV/dr
double dphi(double r)
{
  return 4.0 * (-12.0 * std::pow(r, -13) + 6.0 * std::pow(r, -7));
}
double d2phi(double r)
{
  return 4.0 * (156.0 * std::pow(r, -14) - 42.0 * std::pow(r, -8));
}

// two atoms at distance d0 (x and y = 0.3 apart), lj/cut 2.5 shifted, the
// derivative layer of compute hamiltonian/modified (path single)
const double DY = 0.3;
struct Pair2 {
  HSLammps h;
  HSPotential *pot = nullptr;
  explicit Pair2(double d0)
  {
    h.lines("units lj\natom_style atomic\natom_modify map array\nboundary p p p\n"
            "region box block -10 10 -10 10 -10 10\ncreate_box 1 box\nmass 1 1.0\n"
            "create_atoms 1 single 0 0 0 units box\n"
            "create_atoms 1 single " + hs_chain::f17(std::sqrt(d0 * d0 - DY * DY)) + " " +
            hs_chain::f17(DY) + " 0 units box\n"
            "pair_style lj/cut 2.5\npair_coeff 1 1 1.0 1.0\npair_modify shift yes\n"
            "neighbor 0.3 bin\ncompute hm all hamiltonian/modified path single\n"
            "thermo_style custom step pe c_hm[1]\nrun 0\n");
    auto *modify = h.lmp->modify;
    auto *c = dynamic_cast<LAMMPS_NS::ComputeHamiltonianModified *>(
        modify->compute[modify->find_compute("hm")]);
    pot = c ? c->potential() : nullptr;
  }
  // atom 2 to distance d (same y); returns its x
  double move(double d)
  {
    auto *atom = h.lmp->atom;
    const double x = std::sqrt(d * d - DY * DY);
    atom->x[atom->map(2)][0] = x;
    return x;
  }
  double fx(int tag) { return h.lmp->atom->f[h.lmp->atom->map(tag)][0]; }
};

}    // namespace

// a frozen pair that leaves the cutoff keeps its (continued) force and
// Hessian; the live set drops it
TEST(MCVACutoff, FrozenPairLeavingKeepsItsForce)
{
  Pair2 p(RC - 1e-3);
  ASSERT_NE(p.pot, nullptr);
  ASSERT_TRUE(p.pot->freeze_cutoff_set());
  const double d = RC + 2e-3;
  const double r = p.move(d);
  // F_2 = -phi'(d) (x_2 - x_1)/d
  const double f2 = -dphi(d) * r / d;
  p.pot->use_frozen_set(true);
  p.pot->evaluate(0);
  EXPECT_NEAR(p.fx(2), f2, 1e-12 * std::fabs(f2));
  EXPECT_NEAR(p.fx(1), -f2, 1e-12 * std::fabs(f2));
  // V'' w for w = e_x on atom 2: the xx block phi'' ex^2 + phi'/d (1 - ex^2)
  auto *atom = p.h.lmp->atom;
  double **w, **hw;
  p.h.lmp->memory->create(w, atom->nmax, 3, "test:w");
  p.h.lmp->memory->create(hw, atom->nmax, 3, "test:hw");
  for (int i = 0; i < atom->nlocal; i++) w[i][0] = w[i][1] = w[i][2] = 0.0;
  w[atom->map(2)][0] = 1.0;
  p.pot->hess_vec(w, hw);
  const double ex = r / d;
  const double kxx = d2phi(d) * ex * ex + dphi(d) / d * (1.0 - ex * ex);
  EXPECT_NEAR(hw[atom->map(2)][0], kxx, 1e-10 * std::fabs(kxx));
  int nterms = 0;
  p.pot->radial_terms([&](int, int, const double *, double, double, bool, bool) { nterms++; });
  EXPECT_EQ(nterms, 1);
  double jump = 0.0;
  EXPECT_EQ(p.pot->cutoff_crossings(jump), 1.0);
  EXPECT_NEAR(jump, std::fabs(dphi(RC)), 1e-10);    // 0.039: the force the cutoff cuts off
  // live set: outside, no force, no Hessian
  p.pot->use_frozen_set(false);
  p.pot->evaluate(0);
  EXPECT_EQ(p.fx(2), 0.0);
  p.pot->hess_vec(w, hw);
  EXPECT_EQ(hw[atom->map(2)][0], 0.0);
  p.h.lmp->memory->destroy(w);
  p.h.lmp->memory->destroy(hw);
}

// a pair outside at the freeze that enters the cutoff stays out of the
// frozen set; the live set has it
TEST(MCVACutoff, FrozenPairEnteringStaysOut)
{
  Pair2 p(RC + 1e-3);
  ASSERT_NE(p.pot, nullptr);
  ASSERT_TRUE(p.pot->freeze_cutoff_set());
  const double d = RC - 0.1;
  const double r = p.move(d);
  p.pot->use_frozen_set(true);
  p.pot->evaluate(0);
  EXPECT_EQ(p.fx(2), 0.0);
  EXPECT_EQ(p.fx(1), 0.0);
  int nterms = 0;
  p.pot->radial_terms([&](int, int, const double *, double, double, bool, bool) { nterms++; });
  EXPECT_EQ(nterms, 0);
  p.pot->use_frozen_set(false);
  p.pot->evaluate(0);
  const double f2 = -dphi(d) * r / d;
  EXPECT_NEAR(p.fx(2), f2, 1e-12 * std::fabs(f2));
}

// the LJ fluid of examples/thermostats (lj/cut 2.5 shifted, 108 atoms, kT
// 1.5, fix langevin): the fixed-point iteration without the frozen set
// stopped on step 327 ("did not converge"); both stage solvers now run
// through 350 steps, pairs do cross the cutoff inside Gauss sub-steps
// (output entry 12), and no solve needs more than a few iterations
static void fluid_run(const char *stages)
{
  {
    std::string input = hs_chain::slurp(std::string(hs_test_paths::source_dir) +
                                        "/examples/thermostats/in.lj-thermostat");
    const std::string anchor = "\nthermo      1000\n";
    const size_t at = input.find(anchor);
    ASSERT_NE(at, std::string::npos);
    input.insert(at + 1, std::string("fix_modify int stages ") + stages + "\n");
    input += "print \"CUTOFF $(f_int[1]) $(f_int[8]) $(f_int[12]) $(f_int[6]) $(f_int[9]) "
             "$(f_int[5]) $(f_int[7])\"\n";
    // the frozen cutoff set is the global form's (its stages evaluate the
    // whole system): substep global (-var engine global)
    RunResult r = run_lmp(input, {"-var", "method", "mcva", "-var", "engine", "global", "-var",
                                  "thermo", "langevin", "-var", "cells", "3", "-var", "equil",
                                  "250", "-var", "nrun", "100"});
    ASSERT_EQ(r.exit_code, 0) << r.output;
    std::smatch m;
    const std::regex re(R"((?:^|\n)CUTOFF (\S+) (\S+) (\S+) (\S+) (\S+) (\S+) (\S+))");
    ASSERT_TRUE(std::regex_search(r.output, m, re)) << r.output;
    const double ncoll = std::stod(m[1]), maxit = std::stod(m[2]), ncross = std::stod(m[3]),
                 iters = std::stod(m[4]), solves = std::stod(m[5]), nforce = std::stod(m[6]),
                 nsub = std::stod(m[7]);
    printf("[ %s ] %g collisions, %g cutoff crossings in Gauss sub-steps, %.2f stage iterations "
           "per solve (at most %g), %.1f per sub-step, %.1f force evaluations per collision\n",
           stages, ncoll, ncross, iters / solves, maxit, iters / nsub, nforce / ncoll);
    EXPECT_GT(ncoll, 700.0);    // ~4 per step
    EXPECT_GT(ncross, 100.0) << "the case must have pairs crossing the cutoff";
    EXPECT_LE(maxit, 15.0);
  }
}

TEST(MCVACutoff, LJCutFluidRunsThroughNewton)
{
  fluid_run("newton");
}

TEST(MCVACutoff, LJCutFluidRunsThroughFixedPoint)
{
  fluid_run("fixed");
}
