// Stability stress tests, collisions (issue 4): Newton's cradle, grazing
// contacts, a light sphere trapped between a wall and a heavy sphere, and a
// resting contact, for every hard-sphere method.
//
// Every expected value comes from theory, computed here independently of
// the fixes:
// - Newton's cradle: equal masses in a touching row, one incoming: all the
//   momentum ends up in the last sphere.  In a uniform field g (the same
//   force on every sphere) the relative motion is the force-free one and
//   every sphere's position gains g t^2/2 (equivalence principle); velocity
//   Verlet and the kick-flight-kick of psa are exact for a constant force,
//   so psa, cva, pcva and mcva must reproduce it to round-off.  vci changes the
//   impulse strength to match a discrete energy which depends on the
//   sub-step lengths (doc/fix_hardsphere_vci.rst), an O(dt^2) change.
// - grazing contacts: free flight and one elastic impulse at the analytic
//   contact time; at impact parameter sigma(1+eps) no contact at all.
// - trapped sphere: Galperin's billiard (G. Galperin, Regul. Chaotic Dyn.
//   8 (2003) 375): a heavy sphere (mass M) pushing a light one (mass m) at
//   rest against a wall makes exactly ceil(pi/theta) - 1 collisions,
//   theta = atan(sqrt(m/M)) (31, 314, 3141 for M/m = 1e2, 1e4, 1e6),
//   many of them in one timestep; final velocities from an exact 1-D
//   event loop written here.
// - resting contact: the documented error for the Verlet-substep methods;
//   psa (kick, flight, kick) resolves it as one bounce per step.

#include "hs_test_main.h"

#include "library.h"

#include <cmath>
#include <string>
#include <vector>

namespace {

const double PI = 3.14159265358979323846;

std::string fmtd(double v)
{
  char buf[64];
  snprintf(buf, sizeof(buf), "%.17g", v);
  return buf;
}

std::vector<std::string> methods()
{
  return {"psa", "cva", "pcva", "mcva", "vci"};
}

struct State {
  std::vector<double> x, v;
  double ncoll = -1, npair = -1, nwall = -1, etotal = NAN, e0 = NAN;
};


// run a prepared input (everything but fix hs and the run) and gather the state
State run_case(const std::string &setup, const std::string &fixline, double dt, int nsteps,
               int natoms)
{
  HSLammps h;
  std::string s = setup;
  s += fixline + "\n";
  s += "timestep " + fmtd(dt) + "\n";
  s += "thermo_style custom step pe ke etotal\nthermo_modify norm no\nthermo 0\n";
  s += "run 0\nvariable E0 equal $(etotal:%.17g)\n";
  s += "run " + std::to_string(nsteps) + "\n";
  if (getenv("HS_TEST_VERBOSE")) fprintf(stderr, "%s", s.c_str());
  h.lines(s);
  State st;
  st.x.resize(3 * natoms);
  st.v.resize(3 * natoms);
  lammps_gather_atoms(h.lmp, (char *) "x", 1, 3, st.x.data());
  lammps_gather_atoms(h.lmp, (char *) "v", 1, 3, st.v.data());
  st.ncoll = h.fix_vector("hs", 0);
  st.npair = h.fix_vector("hs", 1);
  st.nwall = h.fix_vector("hs", 2);
  st.etotal = h.thermo("etotal");
  st.e0 = h.variable("E0");
  return st;
}

}    // namespace

// ---------------------------------------------------------------------------
// Newton's cradle: sphere 1 at x = -2 with speed 1 hits the touching row
// 0, 1, 2, 3, 4 (diameter 1) at t = 1; five collisions at that instant.
// ---------------------------------------------------------------------------

struct CradleParam {
  std::string method;
  double dt, g;
};

class StressCradle : public ::testing::TestWithParam<CradleParam> {};

TEST_P(StressCradle, MomentumPassedToTheLastSphere)
{
  const CradleParam p = GetParam();
  const int nsteps = (int) std::lround(3.0 / p.dt);
  const double T = nsteps * p.dt;
  std::string s = R"(units lj
atom_style atomic
atom_modify map array
boundary f p p
region box block -10 20 -5 5 -5 5 units box
create_box 1 box
create_atoms 1 single -2 0 0 units box
create_atoms 1 single 0 0 0 units box
create_atoms 1 single 1 0 0 units box
create_atoms 1 single 2 0 0 units box
create_atoms 1 single 3 0 0 units box
create_atoms 1 single 4 0 0 units box
mass 1 1.0
group inc id 1
velocity inc set 1 0 0 units box
comm_modify cutoff 3.0
)";
  if (p.g != 0.0) s += "fix g all addforce " + fmtd(p.g) + " 0 0\nfix_modify g energy yes\n";
  State st = run_case(s, "fix hs all hardsphere/" + p.method + " diameter 1.0", p.dt, nsteps, 6);

  // exact: x0 + free-frame motion + g T^2/2, v = free-frame + g T
  const double xs[6] = {-1.0, 0.0, 1.0, 2.0, 3.0, 4.0 + (T - 1.0)};
  const double vs[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 1.0};
  // psa, cva, pcva: exact for a constant force (round-off only); vci:
  // O(dt^2) from the discrete-energy impulse, bound 2 g^2 dt^2 (measured
  // 0.6 g^2 dt^2 at dt 0.013)
  const bool exact = p.method != "vci" || p.g == 0.0;
  const double tolx = exact ? 1e-12 : 2.0 * p.g * p.g * p.dt * p.dt * T;
  const double tolv = exact ? 1e-12 : 2.0 * p.g * p.g * p.dt * p.dt;
  for (int i = 0; i < 6; i++) {
    EXPECT_NEAR(st.x[3 * i], xs[i] + 0.5 * p.g * T * T, tolx) << "sphere " << i + 1;
    EXPECT_NEAR(st.v[3 * i], vs[i] + p.g * T, tolv) << "sphere " << i + 1;
    for (int k = 1; k < 3; k++) {
      EXPECT_EQ(st.x[3 * i + k], 0.0);
      EXPECT_EQ(st.v[3 * i + k], 0.0);
    }
  }
  // H = 1/2 + V, V = -g sum x: conserved exactly by the flow
  EXPECT_NEAR(st.etotal, st.e0, exact ? 1e-12 : 2.0 * p.g * p.g * p.dt * p.dt);
  // five collisions in theory.  pcva, mcva and vci (with g != 0) count extra
  // contacts between spheres left touching with relative speeds of
  // round-off size (recorded in examples/stress/README.md); they carry no
  // momentum, as the state above shows
  printf("[ cradle %s dt %g g %g ] %g sphere-sphere collisions\n", p.method.c_str(), p.dt, p.g,
         st.npair);
  if (p.method == "pcva" || p.method == "mcva" || p.method == "vci") {
    EXPECT_GE(st.npair, 5.0);
    EXPECT_LE(st.npair, 20.0);
  } else {
    EXPECT_EQ(st.npair, 5.0);
  }
  EXPECT_EQ(st.nwall, 0.0);
}

std::vector<CradleParam> cradle_params()
{
  std::vector<CradleParam> v;
  for (const auto &m : methods())
    for (double dt : {0.01, 0.013, 0.02})
      for (double g : {0.0, 0.01}) v.push_back({m, dt, g});
  return v;
}

INSTANTIATE_TEST_SUITE_P(Methods, StressCradle, ::testing::ValuesIn(cradle_params()),
                         [](const ::testing::TestParamInfo<CradleParam> &i) {
                           return i.param.method + "_dt" + std::to_string((int) std::lround(1000 * i.param.dt)) +
                               (i.param.g == 0.0 ? "_free" : "_field");
                         });

// ---------------------------------------------------------------------------
// Grazing contacts: sphere 2 at (-3, b, 0) with velocity (1, 0, 0) passes
// sphere 1 at rest at the origin; b = sigma (1 -/+ eps).
// ---------------------------------------------------------------------------

struct GrazeParam {
  std::string method;
  double eps;    // > 0: b = 1 - eps (contact); < 0: b = 1 + |eps| (miss); 0: tangent
};

class StressGrazing : public ::testing::TestWithParam<GrazeParam> {};

TEST_P(StressGrazing, ExactOutcome)
{
  const GrazeParam p = GetParam();
  const double b = 1.0 - p.eps, dt = 0.01;
  const int nsteps = 600;
  const double T = nsteps * dt;
  std::string s = R"(units lj
atom_style atomic
atom_modify map array
boundary f f f
region box block -10 10 -10 10 -10 10 units box
create_box 1 box
create_atoms 1 single 0 0 0 units box
)";
  s += "create_atoms 1 single -3 " + fmtd(b) + " 0 units box\n";
  s += "mass 1 1.0\ngroup mov id 2\nvelocity mov set 1 0 0 units box\ncomm_modify cutoff 3.0\n";
  State st = run_case(s, "fix hs all hardsphere/" + p.method + " diameter 1.0", dt, nsteps, 2);

  // exact: contact when |(-3 + t, b)| = 1, i.e. t_c = 3 - sqrt(1 - b^2);
  // normal n = (-sqrt(1-b^2), b); equal masses exchange the normal components
  double x1[2] = {0, 0}, v1[2] = {0, 0}, x2[2] = {-3 + T, b}, v2[2] = {1, 0};
  double ncoll = 0;
  if (p.eps > 0) {
    const double c = std::sqrt(1.0 - b * b);    // = sqrt(eps (2 - eps)), no cancellation issue
    const double tc = 3.0 - c;
    const double n[2] = {-c, b};
    const double un = 1.0 * n[0];    // (v2 - v1) . n
    for (int k = 0; k < 2; k++) {
      v2[k] = (k == 0 ? 1.0 : 0.0) - un * n[k];
      v1[k] = un * n[k];
      x1[k] = v1[k] * (T - tc);
      x2[k] = (k == 0 ? -3.0 + tc : b) + v2[k] * (T - tc);
    }
    ncoll = 1;
  }
  // exactly tangent (b = sigma): the flight touches with zero normal speed.
  // The doc says no impulse and no count; with the rounded positions of the
  // flight the fix may see a contact approaching at round-off speed and
  // count it (observed: 1, with a velocity change of 2e-14; recorded in
  // examples/stress/README.md): accept 0 or 1, the outcome must be the miss
  if (p.eps == 0.0)
    EXPECT_LE(st.ncoll, 1.0);
  else
    EXPECT_EQ(st.ncoll, ncoll);
  for (int k = 0; k < 2; k++) {
    EXPECT_NEAR(st.x[k], x1[k], 1e-12) << k;
    EXPECT_NEAR(st.v[k], v1[k], 1e-12) << k;
    EXPECT_NEAR(st.x[3 + k], x2[k], 1e-12) << k;
    EXPECT_NEAR(st.v[3 + k], v2[k], 1e-12) << k;
  }
  if (p.eps < 0) {
    // a miss: the flight is untouched, bit for bit
    EXPECT_EQ(st.v[3], 1.0);
    EXPECT_EQ(st.v[4], 0.0);
    EXPECT_EQ(st.v[0], 0.0);
  }
  EXPECT_NEAR(st.etotal, 0.5, 1e-15);
}

std::vector<GrazeParam> graze_params()
{
  std::vector<GrazeParam> v;
  for (const auto &m : methods())
    for (double e : {1e-2, 1e-5, 1e-8, 0.0, -1e-8, -1e-5}) v.push_back({m, e});
  return v;
}

INSTANTIATE_TEST_SUITE_P(Methods, StressGrazing, ::testing::ValuesIn(graze_params()),
                         [](const ::testing::TestParamInfo<GrazeParam> &i) {
                           const double e = i.param.eps;
                           std::string tag = e > 0 ? "inside" : (e < 0 ? "outside" : "tangent");
                           if (e != 0) tag += std::to_string((int) std::lround(-std::log10(std::fabs(e))));
                           return i.param.method + "_" + tag;
                         });

// ---------------------------------------------------------------------------
// Galperin's billiard: light sphere (mass 1) at x = 1.5 at rest between the
// wall xlo 0 and a heavy sphere (mass M) at x = 2.6 moving at -U.
// ---------------------------------------------------------------------------

namespace {
struct Billiard {
  int ncoll = 0;
  double tlast = 0, xl, vl, xh, vh;
};

// exact 1-D event loop (no LAMMPS): light sphere at xl, heavy at xh, radius 1/2
Billiard galperin_exact(double M, double U, double T)
{
  Billiard b;
  double t = 0, xl = 1.5, vl = 0, xh = 2.6, vh = -U;
  for (;;) {
    double tw = (vl < 0) ? (xl - 0.5) / -vl : INFINITY;
    double tp = (vl > vh) ? (xh - xl - 1.0) / (vl - vh) : INFINITY;
    double tn = std::fmin(tw, tp);
    if (!(t + tn <= T)) break;
    xl += vl * tn;
    xh += vh * tn;
    t += tn;
    if (tw < tp) {
      vl = -vl;
    } else {
      const double a = ((1 - M) * vl + 2 * M * vh) / (1 + M);
      const double c = ((M - 1) * vh + 2 * vl) / (1 + M);
      vl = a;
      vh = c;
    }
    b.ncoll++;
    b.tlast = t;
  }
  b.xl = xl + vl * (T - t);
  b.xh = xh + vh * (T - t);
  b.vl = vl;
  b.vh = vh;
  return b;
}
}    // namespace

struct TrapParam {
  std::string method;
  double M;
};

class StressTrapped : public ::testing::TestWithParam<TrapParam> {};

TEST_P(StressTrapped, GalperinCountAndExactState)
{
  const TrapParam p = GetParam();
  const double U = 0.01, dt = 0.01;
  // the light sphere reaches U sqrt(M/m) (10 for M = 1e6): 0.1 per step < skin
  const Billiard probe = galperin_exact(p.M, U, 1e6);
  const int theory = (int) std::ceil(PI / std::atan(std::sqrt(1.0 / p.M))) - 1;
  ASSERT_EQ(probe.ncoll, theory) << "the exact event loop disagrees with Galperin's count";
  const int nsteps = (int) std::ceil((probe.tlast + 5.0) / dt);
  const double T = nsteps * dt;
  const Billiard ex = galperin_exact(p.M, U, T);

  std::string s = R"(units lj
atom_style atomic
atom_modify map array
boundary f p p
region box block 0 40 0 10 0 10 units box
create_box 2 box
create_atoms 1 single 1.5 5 5 units box
create_atoms 2 single 2.6 5 5 units box
mass 1 1.0
)";
  s += "mass 2 " + fmtd(p.M) + "\ngroup heavy type 2\n";
  s += "velocity heavy set " + fmtd(-U) + " 0 0 units box\ncomm_modify cutoff 3.0\n";
  State st = run_case(s, "fix hs all hardsphere/" + p.method + " diameter 1.0 wall xlo 0.0", dt,
                      nsteps, 2);
  EXPECT_EQ(st.ncoll, (double) theory);
  EXPECT_EQ(st.npair + st.nwall, st.ncoll);
  const double E = 0.5 * p.M * U * U;
  EXPECT_NEAR(st.etotal, E, 1e-12 * E);
  // final state after ~3000 collisions: round-off grows with the count
  EXPECT_NEAR(st.v[0], ex.vl, 1e-9 * U * std::sqrt(p.M));
  EXPECT_NEAR(st.v[3], ex.vh, 1e-12);
  EXPECT_NEAR(st.x[0], ex.xl, 1e-8);
  EXPECT_NEAR(st.x[3], ex.xh, 1e-8);
  // in the end the heavy sphere recedes faster than the light one: no more collisions
  EXPECT_GE(st.v[3], st.v[0]);
  EXPECT_GE(st.v[0], 0.0);
}

std::vector<TrapParam> trap_params()
{
  std::vector<TrapParam> v;
  for (const auto &m : methods())
    for (double M : {1e4, 1e6}) v.push_back({m, M});
  return v;
}

INSTANTIATE_TEST_SUITE_P(Methods, StressTrapped, ::testing::ValuesIn(trap_params()),
                         [](const ::testing::TestParamInfo<TrapParam> &i) {
                           return i.param.method + "_M1e" +
                               std::to_string((int) std::lround(std::log10(i.param.M)));
                         });

// ---------------------------------------------------------------------------
// Resting contact: a sphere at rest touching the wall xlo, pressed against
// it by a compressed spring to an anchor at x = 3 (bond K 0.5, r0 4: force
// 1 + x towards the wall).
// ---------------------------------------------------------------------------

namespace {
std::string resting_input(const std::string &method, double dt)
{
  return R"(units lj
atom_style bond
atom_modify map array
boundary f p p
region box block 0 10 0 10 0 10 units box
create_box 2 box bond/types 1 extra/bond/per/atom 1 extra/special/per/atom 2
create_atoms 1 single 3 5 5 units box
create_atoms 2 single 0.5 5 5 units box
mass * 1.0
bond_style harmonic
bond_coeff 1 0.5 4.0
create_bonds single/bond 1 1 2
group s type 2
comm_modify cutoff 7.0
)" + std::string("fix hs s hardsphere/") +
      method + " diameter 1.0 wall xlo 0.0\ntimestep " + fmtd(dt) + "\n";
}
}    // namespace

TEST(StressResting, VerletSubstepMethodsStopWithTheDocumentedError)
{
  // (mcva: its local form, the default, and its global form)
  std::vector<std::string> ms = methods();
  ms.push_back("mcva substep global");
  for (const auto &m : ms) {
    if (m == "psa") continue;
    RunResult r = run_lmp(resting_input(m, 0.01) + "run 10\n");
    EXPECT_NE(r.exit_code, 0) << m;
    EXPECT_NE(r.output.find("(a resting contact)"), std::string::npos) << m << "\n" << r.output;
    EXPECT_NE(r.output.find("atom 2 and wall xlo"), std::string::npos) << m;
  }
}

TEST(StressResting, PsaBouncesWithoutError)
{
  // psa: kick towards the wall (a dt/2), reflection at t = 0, flight, kick
  // back: the resting contact becomes a bouncing ball, with no error and
  // never through the wall.  First step: one collision, height a dt^2/2
  // (a = 1.5 at the wall).  Its energy is NOT bounded by O(dt^2): the
  // first-order error per collision of section 2.1 accumulates (measured in
  // examples/stress, README.md); here only a short run is checked.
  const double dt = 0.01;
  HSLammps h;
  h.lines(resting_input("psa", dt) + R"(thermo_style custom step pe ke etotal
thermo_modify norm no
run 1
variable xs equal x[2]
fix xv all vector 1 v_xs
variable xmin equal min(f_xv)
)");
  EXPECT_EQ(h.fix_vector("hs", 2), 1.0);
  std::vector<double> x(6);
  lammps_gather_atoms(h.lmp, (char *) "x", 1, 3, x.data());
  EXPECT_NEAR(x[3], 0.5 + 1.5 * dt * dt / 2, 1e-14);
  h.cmd("run 1000");
  EXPECT_GE(h.fix_vector("hs", 2), 500.0);
  EXPECT_GE(h.variable("xmin"), 0.5 * (1 - 1e-12));
  EXPECT_LT(std::fabs(h.thermo("etotal") - 1.125), 1e-3);
}
