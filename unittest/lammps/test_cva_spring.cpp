// fix hardsphere/cva: one sphere on a harmonic spring (anchored to an atom
// outside the group) bouncing off a hard wall, 1-D motion along x.
//
// Exact motion: bond K (r - r0)^2 with K = 1/2, r0 = 3, unit mass: omega = 1,
// equilibrium 3 away from the anchor. The sphere (radius 1/2) starts at
// equilibrium with speed 1 (amplitude 1) towards a wall placed so that its
// centre may not come closer than 0.5 to the anchor than equilibrium. So with s(t) = displacement from equilibrium
// towards the wall, s = sin(t) until s = 1/2 (t1 = pi/6), then the reflected
// harmonic motion: s = -sin(theta), theta = -pi/6 + ((t - t1) mod 4pi/3),
// i.e. one bounce every 4pi/3 (the free arc from -pi/6 to 7pi/6).
// Total energy 1/2, exactly conserved by the exact flow.

#include "hs_test_main.h"

#include "library.h"

#include <cmath>
#include <sstream>

namespace {

const double PI = 3.14159265358979323846;
const double T1 = PI / 6.0;              // first contact
const double TBOUNCE = 4.0 * PI / 3.0;   // time between contacts

double extract_fix(HSLammps &h, const char *id, int style, int type, int i)
{
  auto *p = (double *) lammps_extract_fix(h.lmp, id, style, type, i, 0);
  if (!p) return NAN;
  double v = *p;
  lammps_free(p);
  return v;
}


int exact_count(double T)
{
  if (T < T1) return 0;
  return (int) std::floor((T - T1) / TBOUNCE) + 1;
}

// exact displacement from equilibrium towards the wall, and its rate
void exact_state(double t, double &s, double &sdot)
{
  if (t <= T1) {
    s = std::sin(t);
    sdot = std::cos(t);
    return;
  }
  const double th = -PI / 6.0 + std::fmod(t - T1, TBOUNCE);
  s = -std::sin(th);
  sdot = -std::cos(th);
}

struct SpringResult {
  double dEmax;       // max_n |E(t_n) - E(0)|
  double ncoll, nwall, npair;
  int first_step;     // first step at which f_hs[3] >= 1
  double s, sdot;     // final displacement towards the wall, and its rate
  double E0;
};

// hi = false: 3-D, anchor at x = 0, sphere at 3, wall xlo 2.0
// hi = true : 2-D (enforce2d), anchor at x = 10, sphere at 7, wall xhi 8.0
SpringResult run_spring(double dt, double T, bool hi, bool stepwise = false)
{
  HSLammps h;
  const int nsteps = (int) std::lround(T / dt);
  std::string s = "units lj\natom_style bond\natom_modify map array\nboundary f p p\n";
  if (hi) {
    s += "dimension 2\nregion box block 0 11 -5 5 -0.5 0.5 units box\n";
  } else {
    s += "region box block -1 10 -5 5 -5 5 units box\n";
  }
  s += "create_box 2 box bond/types 1 extra/bond/per/atom 1 extra/special/per/atom 2\n";
  s += hi ? "create_atoms 1 single 10 0 0 units box\ncreate_atoms 2 single 7 0 0 units box\n"
          : "create_atoms 1 single 0 0 0 units box\ncreate_atoms 2 single 3 0 0 units box\n";
  s += R"(mass * 1.0
bond_style harmonic
bond_coeff 1 0.5 3.0
create_bonds single/bond 1 1 2
group s type 2
comm_modify cutoff 5.0
)";
  s += hi ? "velocity s set 1 0 0 units box\nfix hs s hardsphere/cva diameter 1.0 wall xhi 8.0\n"
             "fix 2d all enforce2d\n"
          : "velocity s set -1 0 0 units box\nfix hs s hardsphere/cva diameter 1.0 wall xlo 2.0\n";
  char buf[64];
  snprintf(buf, sizeof(buf), "timestep %.17g\n", dt);
  s += buf;
  s += R"(thermo_style custom step pe ke etotal
thermo_modify norm no
run 0
variable E0 equal $(etotal:%.17g)
variable dE equal abs(etotal-v_E0)
variable nw equal f_hs[3]
fix dEv all vector 1 v_dE
variable dEmax equal max(f_dEv)
)";
  SpringResult r;
  r.first_step = -1;
  if (stepwise) {
    // one step at a time until the wall counter f_hs[3] first increments
    h.lines(s);
    for (int n = 1; n <= nsteps; n++) {
      h.cmd("run 1 pre no post no");
      if (extract_fix(h, "hs", 0, 1, 2) >= 1.0) {
        r.first_step = n;
        break;
      }
    }
    return r;
  }
  s += "run " + std::to_string(nsteps) + "\n";
  h.lines(s);

  r.E0 = h.variable("E0");
  r.dEmax = h.variable("dEmax");
  r.ncoll = extract_fix(h, "hs", 0, 1, 0);
  r.npair = extract_fix(h, "hs", 0, 1, 1);
  r.nwall = extract_fix(h, "hs", 0, 1, 2);
  std::vector<double> x(6), v(6);
  lammps_gather_atoms(h.lmp, (char *) "x", 1, 3, x.data());
  lammps_gather_atoms(h.lmp, (char *) "v", 1, 3, v.data());
  // the anchor must not have moved
  EXPECT_EQ(x[0], hi ? 10.0 : 0.0);
  EXPECT_EQ(v[0], 0.0);
  // motion stays 1-D
  EXPECT_EQ(x[4], 0.0);
  EXPECT_EQ(x[5], 0.0);
  r.s = hi ? x[3] - 7.0 : 3.0 - x[3];
  r.sdot = hi ? v[3] : -v[3];
  return r;
}

}    // namespace

class CVASpring : public ::testing::TestWithParam<bool> {};

TEST_P(CVASpring, CountsContactTimeAndSecondOrderEnergy)
{
  const bool hi = GetParam();
  const double T = 20.0;    // contacts at 0.52, 4.71, 8.90, 13.09, 17.28 (next 21.47)
  const double dt = 0.05;
  SpringResult a = run_spring(dt, T, hi);
  SpringResult b = run_spring(0.5 * dt, T, hi);
  a.first_step = run_spring(dt, 1.0, hi, true).first_step;
  b.first_step = run_spring(0.5 * dt, 1.0, hi, true).first_step;

  EXPECT_NEAR(a.E0, 0.5, 1e-14);
  for (const SpringResult *r : {&a, &b}) {
    EXPECT_EQ(r->ncoll, (double) exact_count(T));
    EXPECT_EQ(r->nwall, (double) exact_count(T));
    EXPECT_EQ(r->npair, 0.0);
  }

  // first contact at pi/6 falls in the step that reported it: the step
  // (n-1)dt < t1 <= n dt, up to the O(dt^2) error of the Verlet trajectory
  EXPECT_GT(a.first_step, 0);
  EXPECT_LE((a.first_step - 1) * dt, T1 + dt * dt);
  EXPECT_GE(a.first_step * dt, T1 - dt * dt);
  EXPECT_LE((b.first_step - 1) * 0.5 * dt, T1 + 0.25 * dt * dt);
  EXPECT_GE(b.first_step * 0.5 * dt, T1 - 0.25 * dt * dt);

  // energy error small and second order
  EXPECT_LT(a.dEmax, 0.5 * dt * dt);
  EXPECT_GT(b.dEmax, 0.0);
  const double ratio = a.dEmax / b.dEmax;
  printf("[ cva spring ] max|dE| dt %g: %.4e, dt %g: %.4e, ratio %.3f; first contact steps %d, %d\n", dt,
         a.dEmax, 0.5 * dt, b.dEmax, ratio, a.first_step, b.first_step);
  EXPECT_GT(ratio, 3.0) << a.dEmax << " " << b.dEmax;
  EXPECT_LT(ratio, 5.3) << a.dEmax << " " << b.dEmax;

  // final state close to the exact reflected oscillation (phase error O(dt^2 T))
  double s, sdot;
  exact_state(T, s, sdot);
  EXPECT_NEAR(a.s, s, 2.0 * dt * dt) << "dt " << dt;
  EXPECT_NEAR(a.sdot, sdot, 2.0 * dt * dt);
  EXPECT_NEAR(b.s, s, 0.5 * dt * dt) << "dt " << 0.5 * dt;
  EXPECT_NEAR(b.sdot, sdot, 0.5 * dt * dt);
  // and the error shrinks like dt^2
  EXPECT_LT(std::fabs(b.s - s), 0.4 * std::fabs(a.s - s) + 1e-12);
}

INSTANTIATE_TEST_SUITE_P(Wall, CVASpring, ::testing::Values(false, true),
                         [](const ::testing::TestParamInfo<bool> &p) {
                           return p.param ? std::string("Xhi2d") : std::string("Xlo3d");
                         });
