// fix hardsphere/pcva (Bond & Leimkuhler 2007, section 3.2): across every
// step with a collision the modified Hamiltonian
//   H_[2,VV] = H + dt^2/24 (2 v^T V'' v - grad V^T M^-1 grad V)
// keeps its value to round-off; steps without collisions are fix nve's.
// H_[2,VV] is evaluated here independently (hs_modified_energy.h: harmonic
// bonds written out by hand, unit factors from the LAMMPS units page) from
// dumped positions and velocities, in lj and in real units. The same check
// applied to hardsphere/cva must fail (it changes H_[2,VV] at collisions),
// which shows the check can fail.

#include "hs_test_main.h"

#include "hs_chain.h"
#include "hs_modified_energy.h"

#include "atom.h"
#include "library.h"

#include <array>
#include <iterator>
#include <utility>
#include <cmath>
#include <cstdio>

using namespace hs_test;

namespace {

const std::string CHAIN = hs_chain::chain_path();

struct Conservation {
  double max_coll = 0.0;      // max |dH~| over steps with projections (pcva) / collisions (cva)
  double max_free = 0.0;      // max |dH~| over the other steps
  double max_drift = 0.0;     // max |H~(t) - H~(0)|
  int ncoll_steps = 0, nfree_steps = 0;
  double nskip = -1.0, nproj = -1.0;
};

// runs 'nsteps' more steps on a set-up instance with a dump of every step;
// 'marker' is the fix vector column (1-based) whose increments mark the
// steps to hold to round-off
Conservation check_run(HSLammps &h, int nsteps, int marker, const std::vector<HarmonicBond> &bonds,
                       const std::map<int, double> &masses, double dt, double mvv2e, double ftm2v,
                       const std::string &tag)
{
  const std::string dump = scratch_name("pcva_dump_" + tag + ".txt"),
                    series = scratch_name("pcva_series_" + tag + ".txt");
  h.cmd("dump hsd all custom 1 " + dump + " id x y z vx vy vz");
  h.cmd("dump_modify hsd format float %.17g sort id");
  h.cmd("fix hsser all ave/time 1 1 1 f_hs[" + std::to_string(marker) + "] file " + series);
  h.cmd("run " + std::to_string(nsteps));
  h.cmd("undump hsd");
  h.cmd("unfix hsser");
  Conservation c;
  if (marker == 6) {    // pcva's columns
    c.nproj = h.fix_vector("hs", 5);
    c.nskip = h.fix_vector("hs", 6);
  }
  const std::vector<Frame> fr = read_dump(dump);
  const auto ser = read_series(series);
  std::remove(dump.c_str());
  std::remove(series.c_str());
  EXPECT_EQ((int) fr.size(), nsteps + 1);
  if (fr.size() < 2) return c;
  const double H0 = modified_energy(fr[0], bonds, masses, dt, mvv2e, ftm2v).Ht;
  double prevHt = H0, prevmark = -1.0;
  for (size_t k = 0; k < fr.size(); k++) {
    const double Ht = modified_energy(fr[k], bonds, masses, dt, mvv2e, ftm2v).Ht;
    const double mark = ser.count(fr[k].step) ? ser.at(fr[k].step)[0] : NAN;
    if (k > 0) {
      const double d = std::fabs(Ht - prevHt);
      if (mark > prevmark) {
        c.max_coll = std::max(c.max_coll, d);
        c.ncoll_steps++;
      } else {
        c.max_free = std::max(c.max_free, d);
        c.nfree_steps++;
      }
    }
    c.max_drift = std::max(c.max_drift, std::fabs(Ht - H0));
    prevHt = Ht;
    prevmark = mark;
  }
  return c;
}

Conservation chain(const std::string &method, double dt, int nsteps,
                   const std::string &substep = "global")
{
  char dts[32];
  snprintf(dts, sizeof(dts), "%.17g", dt);
  HSLammps h({"-var", "method", method, "-var", "dt", dts, "-var", "T", "0", "-var", "seed", "1",
              "-var", "substep", substep});
  h.file(CHAIN);
  std::vector<HarmonicBond> bonds;
  std::map<int, double> masses;
  for (int i = 1; i <= 5; i++) {
    bonds.push_back({i, i + 1, 0.5, 1.0});
    masses[i + 1] = 1.0;
  }
  // lj units: mvv2e = ftm2v = 1
  return check_run(h, nsteps, method == "pcva" ? 6 : 4, bonds, masses, dt, 1.0, 1.0,
                   method + substep);
}


}    // namespace

TEST(PCVAModified, PendulumChainKeepsModifiedHamiltonianAcrossCollisions)
{
  const double dt = 0.02;
  const int nsteps = 2500;    // T = 50
  Conservation p = chain("pcva", dt, nsteps);
  Conservation c = chain("cva", dt, nsteps);
  printf("[ pcva H~ ] dt %g: pcva max|dH~| collisional steps %.3e (%d), other steps %.3e, "
         "max|H~-H~0| %.3e; cva: %.3e (%d), %.3e, %.3e\n",
         dt, p.max_coll, p.ncoll_steps, p.max_free, p.max_drift, c.max_coll, c.ncoll_steps,
         c.max_free, c.max_drift);
  EXPECT_GT(p.ncoll_steps, 20);
  EXPECT_EQ(p.nskip, 0.0);
  EXPECT_GE(p.nproj, 2.0 * p.ncoll_steps);    // after the collision and at the step's end
  // round-off across the projected steps (H~ ~ 0.5 here)
  EXPECT_LT(p.max_coll, 1e-13);
  // the same measurement on cva: collisions change H~ far above round-off
  EXPECT_GT(c.ncoll_steps, 20);
  EXPECT_GT(c.max_coll, 1e3 * std::max(p.max_coll, 1e-16));
  // Verlet's own fluctuation of H~ in collision-free steps is O(dt^4)-small
  // but not round-off (so the split by steps is what makes the test pass)
  EXPECT_GT(p.max_free, 100 * std::max(p.max_coll, 1e-16));
}

// substep local: the colliding spheres are the members, their bond
// neighbours (and the anchor, outside the group) partners. The local
// projection undoes the step's change of H~ up to O(dt^4) per step with a
// collision (hs_local_modified.h), and collisions come at a fixed rate per
// unit time: H~ drifts at fourth order over a fixed time, far below cva's
// (second order: the impulse changes v^T V'' v)
TEST(PCVAModified, PendulumChainLocalFourthOrder)
{
  const double T = 50.0;
  std::vector<double> dts = {0.04, 0.02, 0.01, 0.005}, ep, ec;
  for (double dt : dts) {
    const int n = (int) std::lround(T / dt);
    Conservation p = chain("pcva", dt, n, "local");
    Conservation c = chain("cva", dt, n, "local");
    printf("[ pcva local H~ ] dt %g: max|H~-H~0| %.3e (max per collisional step %.3e, %d steps, "
           "%g projections, %g skipped); cva local %.3e\n",
           dt, p.max_drift, p.max_coll, p.ncoll_steps, p.nproj, p.nskip, c.max_drift);
    EXPECT_GT(p.ncoll_steps, 20);
    EXPECT_EQ(p.nskip, 0.0);
    EXPECT_GE(p.nproj, p.ncoll_steps);    // one per step with clusters
    EXPECT_GT(c.max_drift, 10.0 * p.max_drift) << "dt " << dt;
    ep.push_back(p.max_drift);
    ec.push_back(c.max_drift);
  }
  const double op = hs_chain::loglog_slope(dts, ep), oc = hs_chain::loglog_slope(dts, ec);
  printf("[ pcva local H~ ] fitted order pcva %.2f, cva %.2f\n", op, oc);
  EXPECT_GE(op, 3.6);
}

TEST(PCVAModified, RealUnitsBondAndWall)
{
  // two carbon-like spheres (12 g/mol, diameter 2 A) on a harmonic bond
  // (K = 2 kcal/mol/A^2, r0 = 2.5 A) hitting each other and a wall, real
  // units: checks the mvv2e and ftm2v factors of H_[2,VV]
  const double dt = 2.0;
  HSLammps h;
  h.lines(R"(units real
atom_style bond
atom_modify map array
boundary f p p
region box block -10 30 -10 10 -10 10 units box
create_box 1 box bond/types 1 extra/bond/per/atom 1 extra/special/per/atom 2
create_atoms 1 single 5.0 0 0 units box
create_atoms 1 single 7.5 0.3 0 units box
mass 1 12.0
bond_style harmonic
bond_coeff 1 2.0 2.5
create_bonds single/bond 1 1 2
group one id 1
group two id 2
velocity one set -0.012 0.002 0.001 units box
velocity two set -0.02 -0.003 0.0 units box
comm_modify cutoff 6.0
fix hs all hardsphere/pcva diameter 2.0 wall xlo 3.0 wall xhi 12.0
timestep 2.0
thermo_style custom step pe ke etotal
run 0
)");
  const double c = 48.88821291;    // real units: mvv2e = c^2, ftm2v = 1/c^2 (LAMMPS units page)
  Conservation p = check_run(h, 1500, 6, {{1, 2, 2.0, 2.5}}, {{1, 12.0}, {2, 12.0}}, dt, c * c,
                             1.0 / (c * c), "real");
  const double npair = h.fix_vector("hs", 1), nwall = h.fix_vector("hs", 2);
  printf("[ pcva real ] %g pair, %g wall collisions; max|dH~| collisional %.3e (%d steps), "
         "other %.3e\n",
         npair, nwall, p.max_coll, p.ncoll_steps, p.max_free);
  EXPECT_GT(npair, 2.0);
  EXPECT_GT(nwall, 2.0);
  EXPECT_EQ(p.nskip, 0.0);
  // H~ ~ 1 kcal/mol here
  EXPECT_LT(p.max_coll, 1e-12);
  EXPECT_GT(p.max_free, 100 * std::max(p.max_coll, 1e-16));
}

namespace {

// max |dH~| over steps with (pcva: projections, cva: collisions) and over
// the other steps, measured with compute hamiltonian/modified
std::pair<double, double> angle_chain(const std::string &method)
{
  HSLammps h;
  h.lines(R"(units lj
dimension 2
atom_style angle
boundary f f p
region box block -2 8 -8 8 -0.5 0.5
create_box 2 box bond/types 1 angle/types 1 extra/bond/per/atom 2 extra/angle/per/atom 3 extra/special/per/atom 6
create_atoms 1 single 0 0 0
create_atoms 2 single 1 0 0
create_atoms 2 single 2 0 0
create_atoms 2 single 3 0 0
create_atoms 2 single 4 0 0
create_atoms 2 single 5 0 0
mass * 1.0
bond_style harmonic
bond_coeff 1 0.5 1.0
angle_style cosine
angle_coeff 1 0.05
create_bonds single/bond 1 1 2
create_bonds single/bond 1 2 3
create_bonds single/bond 1 3 4
create_bonds single/bond 1 4 5
create_bonds single/bond 1 5 6
create_bonds single/angle 1 1 2 3
create_bonds single/angle 1 2 3 4
create_bonds single/angle 1 3 4 5
create_bonds single/angle 1 4 5 6
group chain type 2
velocity chain create 0.5 4928 loop geom
comm_modify cutoff 2.0
fix 2d all enforce2d
timestep 0.02
compute hm chain hamiltonian/modified
)");
  // (substep global: the global projection restores H~ exactly at every
  // contact, which is what this test measures; the local one keeps it to
  // O(dt^4) per step, test_pcva_local.cpp)
  h.cmd("fix hs chain hardsphere/" + method + " diameter 0.9 wall xlo 0.0 substep global");
  const std::string out = scratch_name("pcva_angle_" + method + ".txt");
  h.cmd(std::string("fix ser all ave/time 1 1 1 c_hm[2] f_hs[") + (method == "pcva" ? "6" : "4") +
        "] file " + out + " format \" %.17g\"");
  h.cmd("run 2500");
  const auto ser = read_series(out);
  std::remove(out.c_str());
  EXPECT_EQ(ser.size(), 2501u);
  double mc = 0.0, mf = 0.0;
  int nc = 0;
  for (auto it = std::next(ser.begin()); it != ser.end(); ++it) {
    const auto &prev = std::prev(it)->second, &cur = it->second;
    const double d = std::fabs(cur.at(0) - prev.at(0));
    if (cur.at(1) > prev.at(1)) {
      mc = std::max(mc, d);
      nc++;
    } else
      mf = std::max(mf, d);
  }
  EXPECT_GT(nc, 20) << method;
  return {mc, mf};
}

}    // namespace

TEST(PCVAModified, AngleChainThroughDifferencePath)
{
  // angle_style cosine (smooth also at 180 degrees, unlike harmonic with
  // theta0 = 180) has no analytic path in the derivative layer: V'' along v
  // comes from differences of force evaluations (the compute's log line says
  // "angle cosine: fdiff"). Measured with compute hamiltonian/modified over
  // T = 50.
  const auto p = angle_chain("pcva");
  const auto c = angle_chain("cva");
  printf("[ pcva angle ] max|dH~| collisional steps pcva %.3e, cva %.3e; other steps %.3e\n",
         p.first, c.first, p.second);
  EXPECT_LT(p.first, 1e-13);
  EXPECT_GT(c.first, 1e3 * std::max(p.first, 1e-16));
}
