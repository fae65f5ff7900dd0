// A pure hard-sphere fluid (500 spheres from fcc, packing fraction 0.3,
// T = 1, dt 0.01) in a given box, 500 steps and then 2000 averaged: the
// pressure from the collision (impulse) virial against the Carnahan-
// Starling equation of state (2 %), the collision count against the Enskog
// frequency (5 %), and the temperature conserved to round-off, since
// elastic collisions and free flight conserve it exactly. Shared by
// test_hardsphere_eos.cpp (an orthogonal box) and test_triclinic.cpp (a
// tilted one). Include after hs_test_main.h.
#ifndef HS_TEST_EOS_H
#define HS_TEST_EOS_H

#include "hs_test_main.h"

#include "library.h"

#include <cmath>
#include <functional>
#include <string>

namespace hs_eos {

inline double fix_value(HSLammps &h, const char *id, int i)
{
  auto *p = (double *) lammps_extract_fix(h.lmp, id, 0, 1, i, 0);
  if (!p) return NAN;
  double v = *p;
  lammps_free(p);
  return v;
}

// region: the "region box ..." command (in lattice units of the fcc at the
// fluid's density); at_start: checks of the box after its creation
inline void carnahan_starling(const std::string &method, const std::string &region,
                              const std::string &label,
                              const std::function<void(HSLammps &)> &at_start = nullptr)
{
  const double PI = 3.14159265358979323846;
  const double eta = 0.3;
  const double rho = 6.0 * eta / PI;
  const double zcs = (1 + eta + eta * eta - eta * eta * eta) / std::pow(1 - eta, 3);
  char rhos[32];
  snprintf(rhos, sizeof(rhos), "%.17g", rho);

  HSLammps h;
  h.lines(std::string("units lj\natom_style atomic\nlattice fcc ") + rhos + "\n" + region + R"(
create_box 1 box
create_atoms 1 box
mass 1 1.0
velocity all create 1.0 5287 mom yes rot yes dist gaussian
comm_modify cutoff 1.7
neighbor 0.3 bin
neigh_modify every 1 delay 0 check yes
timestep 0.01
thermo_style custom step temp press ke
thermo_modify norm no
run 0
)");
  const double T0 = h.thermo("temp");
  ASSERT_NEAR(T0, 1.0, 1e-12);
  ASSERT_EQ(h.thermo("atoms"), 500.0);
  if (at_start) at_start(h);
  h.cmd("fix hs all hardsphere/" + method + " diameter 1.0");
  h.lines(R"(
run 500
reset_timestep 0
variable dT equal abs(temp-1.0)
fix avg all ave/time 1 2000 2000 c_thermo_press c_thermo_temp
fix dTv all vector 10 v_dT
variable dTmax equal max(f_dTv)
run 2000
)");
  const double P = fix_value(h, "avg", 0);
  const double Tavg = fix_value(h, "avg", 1);
  const double ncoll = fix_value(h, "hs", 0);
  const double dTmax = h.variable("dTmax");
  printf("[ %s %s ] eta %.2f rho %.5f: <P> = %.5f, rho T Z_CS = %.5f (ratio %.4f), "
         "<T> - 1 = %.2e, max|T-1| = %.2e, %g collisions\n",
         method.c_str(), label.c_str(), eta, rho, P, rho * Tavg * zcs, P / (rho * Tavg * zcs),
         Tavg - 1.0, dTmax, ncoll);

  // Enskog: nu = 4 sigma^2 rho g(sigma) sqrt(pi T/m), contact value
  // g = (Z_CS-1)/(4 eta), over the 500 + 2000 steps the fix has counted
  const double rate = 4.0 * rho * (zcs - 1.0) / (4.0 * eta) * std::sqrt(PI * 1.0);
  const double expected = 0.5 * 500.0 * rate * 2500 * 0.01;    // pairs over 2500 steps
  EXPECT_NEAR(ncoll / expected, 1.0, 0.05) << ncoll << " vs " << expected;

  // temperature conserved to round-off
  EXPECT_NEAR(Tavg, 1.0, 1e-10);
  EXPECT_LT(dTmax, 1e-10);
  EXPECT_NEAR(h.thermo("temp"), 1.0, 1e-10);

  // Carnahan-Starling within 2 %
  EXPECT_NEAR(P / (rho * Tavg * zcs), 1.0, 0.02) << "P " << P << " expected " << rho * zcs;
}

}    // namespace hs_eos

#endif
