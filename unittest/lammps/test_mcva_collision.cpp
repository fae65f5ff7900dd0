// fix hardsphere/mcva keeps the modified Hamiltonian
//   H~ = H_[2,VV] = 1/2 p^T M^-1 p + V + dt^2/12 v^T V'' v - dt^2/24 grad V^T M^-1 grad V
// through collisions (Bond & Leimkuhler 2007, section 3.1).
//
// With a potential that is exactly quadratic in the coordinates (harmonic
// bonds of rest length 0: V = K |q_a - q_b|^2), H~ is a quadratic function
// of (q, p). The Gauss-Legendre method conserves quadratic invariants
// exactly, and the modified collision operator alpha-hat conserves H~
// exactly, so every step that sub-steps (a predicted contact) must keep H~
// to round-off, collisions included. H~ is evaluated here independently,
// in closed form from the gathered x and v. The collision Verlet algorithm
// (hardsphere/cva) on the same system changes H~ at collisions by far more.
// The bound 1e-13 is a few hundred times round-off (~7e-16 is measured
// with the analytic bond derivatives) and far below CVA's change (5e-4) and
// the change with the paper's printed dt^2/12 coefficient in alpha-hat (2e-4).
// A second system in real units checks the unit conversions (ftm2v, mvv2e).

#include "hs_test_main.h"

#include "atom.h"
#include "force.h"
#include "update.h"

#include <cmath>
#include <map>

namespace {

struct Bond {
  int a, b;    // atom IDs
  double K;    // E = K r^2 (rest length 0)
};

struct System {
  std::string setup;    // up to the fix
  std::vector<Bond> bonds;
  int anchor;           // atom ID not integrated (coordinates not variables of V)
};

// H~ from x, v gathered by ID; the anchor's gradient is not a variable
double htilde(HSLammps &h, const System &s, double &scale)
{
  auto *lmp = h.lmp;
  const int n = (int) lmp->atom->natoms;
  std::vector<double> x(3 * n), v(3 * n), m(n);
  std::vector<int> type(n);
  lammps_gather_atoms(lmp, (char *) "x", 1, 3, x.data());
  lammps_gather_atoms(lmp, (char *) "v", 1, 3, v.data());
  lammps_gather_atoms(lmp, (char *) "type", 0, 1, type.data());
  for (int i = 0; i < n; i++) m[i] = lmp->atom->mass[type[i]];
  const double dt = lmp->update->dt, mvv2e = lmp->force->mvv2e, ftm2v = lmp->force->ftm2v;
  double ke = 0.0, V = 0.0, vHv = 0.0;
  std::vector<double> grad(3 * n, 0.0);
  for (int i = 0; i < n; i++) {
    if (i + 1 == s.anchor) continue;
    for (int d = 0; d < 3; d++) ke += 0.5 * mvv2e * m[i] * v[3 * i + d] * v[3 * i + d];
  }
  for (const Bond &b : s.bonds) {
    const int a = b.a - 1, c = b.b - 1;
    for (int d = 0; d < 3; d++) {
      const double dq = x[3 * c + d] - x[3 * a + d];
      const double va = (b.a == s.anchor) ? 0.0 : v[3 * a + d];
      const double vc = (b.b == s.anchor) ? 0.0 : v[3 * c + d];
      V += b.K * dq * dq;
      grad[3 * c + d] += 2.0 * b.K * dq;
      grad[3 * a + d] -= 2.0 * b.K * dq;
      vHv += 2.0 * b.K * (vc - va) * (vc - va);    // V'' = 2K on the pair block
    }
  }
  double g2 = 0.0;
  for (int i = 0; i < n; i++) {
    if (i + 1 == s.anchor) continue;
    for (int d = 0; d < 3; d++) g2 += grad[3 * i + d] * grad[3 * i + d] * ftm2v / m[i];
  }
  scale = ke + std::fabs(V);
  return ke + V + dt * dt / 12.0 * vHv - dt * dt / 24.0 * g2;
}

struct Tally {
  double max_sub = 0.0;      // max |dH~| / scale over steps that sub-stepped
  double max_plain = 0.0;    // ... over plain Verlet steps
  int nsub = 0, ncollsteps = 0;
  double ncoll = 0, npair = 0, nwall = 0;
};

// runs nsteps one at a time; the fix's collisional-step counter tells
// which steps collided (hardsphere/mcva: its Gauss sub-step counter tells
// which sub-stepped). mcva in its global form (substep global): the Gauss
// flow of the whole system keeps a quadratic H~ exactly; its local form
// (each cluster's flow, then pcva's projection) keeps it to fourth order
// (test_mcva_local.cpp)
Tally run_steps(const System &s, const std::string &style, int nsteps)
{
  HSLammps h;
  h.lines(s.setup);
  h.cmd("fix hs mobile hardsphere/" + style + " diameter " + "${diam}" + " wall xlo ${wall}" +
        (style == "mcva" ? " substep global" : ""));
  h.cmd("run 0");
  Tally t;
  double scale;
  double H0 = htilde(h, s, scale);
  double prev_sub = 0.0, prev_coll = 0.0;
  for (int k = 0; k < nsteps; k++) {
    h.cmd("run 1 pre no post no");
    double H1 = htilde(h, s, scale);
    const double coll = h.fix_vector("hs", 3);
    const double sub = (style == "mcva") ? h.fix_vector("hs", 6) : coll;
    const double rel = std::fabs(H1 - H0) / scale;
    if (sub > prev_sub) {
      t.max_sub = std::max(t.max_sub, rel);
      t.nsub++;
    } else
      t.max_plain = std::max(t.max_plain, rel);
    if (coll > prev_coll) t.ncollsteps++;
    prev_sub = sub;
    prev_coll = coll;
    H0 = H1;
  }
  t.ncoll = h.fix_vector("hs", 0);
  t.npair = h.fix_vector("hs", 1);
  t.nwall = h.fix_vector("hs", 2);
  return t;
}

// two spheres on zero-length springs: anchor (ID 1, fixed) - sphere 2 - sphere 3;
// the springs pull 3 onto 2 and 2 across the wall: pair and wall collisions
System spring_pair(const std::string &units, double lscale, double mscale, double kscale,
                   double vscale, double dt)
{
  System s;
  s.anchor = 1;
  const double K1 = 0.8 * kscale, K2 = 1.3 * kscale;
  s.bonds = {{1, 2, K1}, {2, 3, K2}};
  auto L = [&](double a) { return std::to_string(a * lscale); };
  auto Vv = [&](double a) { return std::to_string(a * vscale); };
  s.setup = "units " + units + R"(
atom_style bond
atom_modify map array
boundary f f f
region box block )" + L(-6) + " " + L(6) + " " + L(-6) + " " + L(6) + " " + L(-6) + " " + L(6) + R"(
create_box 3 box bond/types 2 extra/bond/per/atom 2 extra/special/per/atom 4
create_atoms 1 single 0 0 0
create_atoms 2 single )" + L(1.0) + " " + L(0.2) + " 0\ncreate_atoms 3 single " + L(2.2) + " " +
      L(0.3) + " " + L(0.1) + "\nmass 1 " + std::to_string(1.0 * mscale) + "\nmass 2 " +
      std::to_string(1.0 * mscale) + "\nmass 3 " + std::to_string(2.5 * mscale) + R"(
bond_style harmonic
bond_coeff 1 )" + std::to_string(K1) + R"( 0.0
bond_coeff 2 )" + std::to_string(K2) + R"( 0.0
create_bonds single/bond 1 1 2
create_bonds single/bond 2 2 3
special_bonds lj 0 1 1
group mobile type 2 3
velocity mobile set 0 0 0
set atom 2 vx )" + Vv(-0.9) + " vy " + Vv(0.4) + " vz " + Vv(0.1) + "\nset atom 3 vx " + Vv(0.3) +
      " vy " + Vv(-0.5) + " vz " + Vv(0.2) + R"(
neighbor )" + L(0.3) + R"( bin
comm_modify cutoff )" + L(3.0) + R"(
variable diam equal )" + L(0.9) + R"(
variable wall equal )" + L(-1.0) + R"(
timestep )" + std::to_string(dt) + R"(
thermo_style custom step pe ke etotal
)";
  return s;
}

}    // namespace

TEST(MCVACollision, QuadraticPotentialKeepsHtildeToRoundoff)
{
  const System s = spring_pair("lj", 1.0, 1.0, 1.0, 1.0, 0.05);
  const Tally m = run_steps(s, "mcva", 400);
  printf("[ mcva H~ ] lj: %g collisions (%g pair, %g wall) in %d steps; %d sub-stepped: max "
         "|dH~|/H %.2e; plain Verlet steps %.2e\n",
         m.ncoll, m.npair, m.nwall, m.ncollsteps, m.nsub, m.max_sub, m.max_plain);
  EXPECT_GT(m.npair, 3.0);
  EXPECT_GT(m.nwall, 1.0);
  EXPECT_GE(m.nsub, m.ncollsteps);
  EXPECT_LT(m.max_sub, 1e-13);
  // Verlet alone keeps H~ only to O(dt^4): the round-off above is not for free
  EXPECT_GT(m.max_plain, 1e-10);

  const Tally c = run_steps(s, "cva", 400);
  printf("[ mcva H~ ] lj: cva: %g collisions; max |dH~|/H over collisional steps %.2e\n", c.ncoll,
         c.max_sub);
  EXPECT_GT(c.ncoll, 3.0);
  EXPECT_GT(c.max_sub, 1e4 * std::max(m.max_sub, 1e-16));
}

TEST(MCVACollision, RealUnitsKeepHtildeToRoundoff)
{
  // lengths in Angstrom, masses 12 g/mol, dt in fs: ftm2v and mvv2e far from 1
  const System s = spring_pair("real", 2.0, 12.0, 0.05, 0.004, 20.0);
  const Tally m = run_steps(s, "mcva", 400);
  printf("[ mcva H~ ] real: %g collisions (%g pair, %g wall); %d sub-stepped: max |dH~|/H %.2e\n",
         m.ncoll, m.npair, m.nwall, m.nsub, m.max_sub);
  EXPECT_GT(m.npair, 1.0);
  EXPECT_GT(m.nwall, 0.0);
  EXPECT_LT(m.max_sub, 1e-13);
}

TEST(MCVACollision, ComputeHamiltonianModifiedAgreesWithClosedForm)
{
  // compute hamiltonian/modified (the derivative layer) and the closed form
  // above must give the same H~ along an MCVA run with collisions, in both
  // unit systems (cross-check of both evaluations and their unit handling)
  for (const bool real : {false, true}) {
    const System s = real ? spring_pair("real", 2.0, 12.0, 0.05, 0.004, 20.0)
                          : spring_pair("lj", 1.0, 1.0, 1.0, 1.0, 0.05);
    HSLammps h;
    h.lines(s.setup);
    h.cmd("fix hs mobile hardsphere/mcva diameter ${diam} wall xlo ${wall}");
    h.cmd("compute hm mobile hamiltonian/modified");
    h.cmd("thermo_style custom step etotal c_hm[1] c_hm[2]");
    h.cmd("thermo_modify norm no");
    h.cmd("run 0");
    double worst = 0.0;
    for (int k = 0; k < 120; k++) {
      h.cmd("run 1 pre no post no");
      double scale;
      const double mine = htilde(h, s, scale);
      // the compute's vector as of the thermo output at the run's last step
      auto *hm = (double *) lammps_extract_compute(h.lmp, "hm", LMP_STYLE_GLOBAL, LMP_TYPE_VECTOR);
      ASSERT_NE(hm, nullptr);
      worst = std::max(worst, std::fabs(hm[1] - mine) / scale);
    }
    EXPECT_GT(h.fix_vector("hs", 0), 0.0);
    EXPECT_LT(worst, 1e-13) << (real ? "real" : "lj");
    printf("[ mcva H~ ] %s: compute hamiltonian/modified vs closed form: max rel. diff %.2e\n",
           real ? "real" : "lj", worst);
  }
}

// Contacts the Verlet prescreen misses. Sphere C (ID 2) sits on a stiff
// zero-length spring to an anchor (K = 12.5, omega = 5, dt omega = 0.5) and
// on a soft one to sphere D (ID 5, K = 0.5: V'' couples C and D, so
// alpha-hat differs from the elastic alpha), and moves at unit speed towards
// the wall yhi; the free pair A-B (IDs 3, 4) collides at t = 0.05 and makes
// step 1 a Gauss step. The flow of H~ carries C ahead of the Verlet path
// (dq/dt = v + dt^2/6 M^-1 V'' v) by ~1e-3 at mid-step, so with the wall a
// little beyond C's Verlet reach:
//  - wall gap 0.0495: Verlet predicts A-B first (t = 0.05), the Gauss flow
//    reaches the wall before that: the sub-step stops at C's crossing and
//    drops A-B, which is collided next (advance_to_contact's path);
//  - wall gap 0.0931: after A-B, Verlet sees no contact in the rest of the
//    step, the Gauss flow reaches the wall before its end (finish_step's path).
// (The windows, found by scanning the gap: 0.0490-0.0500 and 0.0925-0.0937.)
// Either way both contacts are collided in step 1, no sphere ends in the
// wall, and H~ (quadratic) is kept to round-off through the whole step.
TEST(MCVACollision, ContactsMissedByThePrescreen)
{
  for (const double gap : {0.0495, 0.0931}) {
    System s;
    s.anchor = 1;
    s.bonds = {{1, 2, 12.5}, {2, 5, 0.5}};
    s.setup = R"(
units lj
atom_style bond
atom_modify map array
boundary f f f
region box block -8 8 -8 8 -8 8
create_box 5 box bond/types 2 extra/bond/per/atom 2 extra/special/per/atom 4
create_atoms 1 single 0 0 -0.3
create_atoms 2 single 0 0 0
create_atoms 3 single -5 0 0
create_atoms 4 single -3.95 0 0
create_atoms 5 single 0 -1.2 0
mass * 1.0
bond_style harmonic
bond_coeff 1 12.5 0.0
bond_coeff 2 0.5 0.0
create_bonds single/bond 1 1 2
create_bonds single/bond 2 2 5
group mobile type 2 3 4 5
group c id 2
group a id 3
group d id 5
velocity c set 0 1 0
velocity a set 1 0 0
velocity d set 0.3 0 0.4
neighbor 0.5 bin
comm_modify cutoff 3.0
timestep 0.1
thermo_style custom step pe ke etotal
)";
    HSLammps h;
    h.lines(s.setup);
    // (entry 10, missed contacts, counts the global form's)
    h.cmd("fix hs mobile hardsphere/mcva diameter 1.0 wall yhi " + std::to_string(0.5 + gap) +
          " substep global");
    h.cmd("run 0");
    double scale;
    const double H0 = htilde(h, s, scale);
    h.cmd("run 1 pre no post no");
    const double H1 = htilde(h, s, scale);
    EXPECT_EQ(h.fix_vector("hs", 9), 1.0) << "gap " << gap << ": one missed contact";
    EXPECT_EQ(h.fix_vector("hs", 1), 1.0) << "gap " << gap;    // A-B
    EXPECT_EQ(h.fix_vector("hs", 2), 1.0) << "gap " << gap;    // C-wall
    EXPECT_EQ(h.fix_vector("hs", 3), 1.0) << "gap " << gap;    // both in step 1
    EXPECT_LT(std::fabs(H1 - H0) / scale, 1e-13) << "gap " << gap;
    std::vector<double> x(15);
    lammps_gather_atoms(h.lmp, (char *) "x", 1, 3, x.data());
    EXPECT_LE(x[3 + 1] + 0.5, 0.5 + gap + 1e-12) << "C is inside the wall";
    EXPECT_GE(x[9] - x[6], 1.0 - 1e-12) << "A and B overlap";
    h.cmd("run 2 pre no post no");    // and the run goes on without an overlap
    printf("[ mcva missed ] wall gap %g: H~ %.17g -> %.17g, |dH~|/H over the step %.2e\n", gap,
           H0, H1, std::fabs(H1 - H0) / scale);
  }
}
