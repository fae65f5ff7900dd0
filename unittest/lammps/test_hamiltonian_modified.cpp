// compute hamiltonian/modified: closed forms for the harmonic oscillator,
// the exact modified Hamiltonian of velocity Verlet, orders of conservation
// of H, H_[2,VV], H_[4,VV] under plain Verlet, and input errors.

#include "hs_test_main.h"

#include "atom.h"
#include "compute_hamiltonian_modified.h"
#include "hs_potential.h"
#include "modify.h"
#include "force.h"
#include "library.h"
#include "update.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace {

std::vector<double> compute_vector(HSLammps &h, const char *id)
{
  auto *v = (double *) lammps_extract_compute(h.lmp, id, LMP_STYLE_GLOBAL, LMP_TYPE_VECTOR);
  if (!v) return {NAN, NAN, NAN};
  return {v[0], v[1], v[2]};
}

// ---- 3-D isotropic harmonic oscillator: one atom on fix spring tether
// (V = K/2 |x|^2, an energy fix: the FDIFF path with fix_modify energy yes)
struct HO {
  const char *units;
  double mass, K, h;    // h = time step
};

std::string ho_input(const HO &p, int nsteps)
{
  return std::string("units ") + p.units +
      "\natom_style atomic\natom_modify map array\nboundary p p p\n"
      "region box block -10 10 -10 10 -10 10\ncreate_box 1 box\n"
      "create_atoms 1 single 0.7 -0.3 0.4 units box\n"
      "mass 1 " + std::to_string(p.mass) + "\n" +
      "fix sp all spring tether " + std::to_string(p.K) + " 0.0 0.0 0.0 0.0\n"
      "fix_modify sp energy yes\nfix nve all nve\n"
      "timestep " + std::to_string(p.h) + "\n"
      "compute hm all hamiltonian/modified\n"
      "thermo_style custom step pe c_hm[1] c_hm[2] c_hm[3]\n"
      "thermo 1000000\n";
}

void ho_check(const HO &p, double vscale)
{
  HSLammps h;
  h.lines(ho_input(p, 0));
  h.cmd("velocity all set " + std::to_string(0.5 * vscale) + " " + std::to_string(0.2 * vscale) +
        " " + std::to_string(-0.8 * vscale) + " units box");
  h.cmd("run 7");
  auto *atom = h.lmp->atom;
  const double ftm2v = h.lmp->force->ftm2v, mvv2e = h.lmp->force->mvv2e;
  const double *x = atom->x[0], *v = atom->v[0];
  const double m = p.mass, K = p.K, dt = h.lmp->update->dt;
  const double xx = x[0] * x[0] + x[1] * x[1] + x[2] * x[2];
  const double vv = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
  const double Ke = 0.5 * mvv2e * m * vv, V = 0.5 * K * xx;

  // paper's H2, H4 for V'' = K I, grad V = K x, M_c^-1 = ftm2v / m
  const double H2 = 2.0 * K * vv - ftm2v * K * K * xx / m;
  const double H4 = -3.0 * K * K * K * (ftm2v / m) * (ftm2v / m) * xx + 12.0 * K * K * vv * ftm2v / m;
  const double H = Ke + V;
  const double Hm2 = H + dt * dt / 24.0 * H2, Hm4 = Hm2 + std::pow(dt, 4) / 720.0 * H4;
  auto c = compute_vector(h, "hm");
  EXPECT_NEAR(c[0], H, 1e-13 * H) << p.units;
  // HSPotential::energy() with an energy fix (fix spring, fdiff path)
  auto *cm = dynamic_cast<LAMMPS_NS::ComputeHamiltonianModified *>(
      h.lmp->modify->compute[h.lmp->modify->find_compute("hm")]);
  ASSERT_NE(cm, nullptr);
  EXPECT_NEAR(cm->potential()->energy(), V, 1e-14 * V) << p.units;
  EXPECT_NEAR(c[1], Hm2, 1e-13 * H) << p.units;
  EXPECT_NEAR(c[2], Hm4, 1e-13 * H) << p.units;

  // Verlet's exact invariant: H~ = theta/(h w~) E_h, E_h = K_e + V (1 - h^2 w^2/4),
  // theta = 2 asin(h w/2), w~ = w sqrt(1 - h^2 w^2/4) (the map is a rotation
  // by theta). Expanded in h: H~ = H + h^2/24 H2 + h^4/720 H4 + R6 + O(h^8),
  // R6 = (h w)^6 (K_e/140 - V/840), R4 = (h w)^4 (K_e/30 - V/120),
  // R8 = (h w)^8 (K_e/630 - V/5040) (series of H~ in h, by sympy)
  const double w = std::sqrt(K * ftm2v / m), hw = dt * w;
  const double Eh = Ke + V * (1.0 - hw * hw / 4.0);
  const double Ht = 2.0 * std::asin(hw / 2.0) / (hw * std::sqrt(1.0 - hw * hw / 4.0)) * Eh;
  const double R6 = std::pow(hw, 6) * (Ke / 140.0 - V / 840.0);
  const double R4 = std::pow(hw, 4) * (Ke / 30.0 - V / 120.0);
  const double R8 = std::pow(hw, 8) * (Ke / 630.0 - V / 5040.0);
  // the remainder after R8 is O((h w)^10): 1e-3 of R6 at h w = 0.3
  EXPECT_NEAR(c[2], Ht - R6 - R8, 1e-3 * std::fabs(R6)) << p.units << " H_[4,VV] vs exact";
  EXPECT_NEAR(c[1], Ht - R4 - R6 - R8, 1e-3 * std::fabs(R6)) << p.units << " H_[2,VV] vs exact";
  if (getenv("HS_TEST_VERBOSE"))
    printf("%s: H~ %.15g  H4 %.15g  H~-H4 %.3e R6 %.3e  H~-H2 %.3e R4 %.3e\n", p.units, Ht, c[2],
           Ht - c[2], R6, Ht - c[1], R4);
}

}    // namespace

TEST(HamiltonianModified, HarmonicOscillatorLJUnits)
{
  // w = sqrt(K/m) = 1.5, h w = 0.3
  ho_check(HO{"lj", 2.0, 4.5, 0.2}, 1.0);
}

TEST(HamiltonianModified, HarmonicOscillatorRealUnits)
{
  // w^2 = K ftm2v / m (ftm2v = 1/48.88821291^2), h w = 0.3
  const double m = 12.0, K = 0.5;
  const double w = std::sqrt(K / (48.88821291 * 48.88821291) / m);
  ho_check(HO{"real", m, K, 0.3 / w}, 0.01);
}

TEST(HamiltonianModified, HarmonicOscillatorMetalUnits)
{
  // metal: ftm2v = 1/1.0364269e-4, time in ps
  const double m = 4.0, K = 2.0;
  const double w = std::sqrt(K / 1.0364269e-4 / m);
  ho_check(HO{"metal", m, K, 0.25 / w}, 10.0);
}

// ---- orders of conservation under plain Verlet (fix nve), collision-free

namespace {

// max_n |Hk(t_n) - Hk(0)|, k = 1..3, over T = nsteps dt (fix vector every step)
std::vector<double> max_drift(const std::string &system, double dt, double T,
                              const std::string &args)
{
  HSLammps h;
  h.lines(system);
  const int nsteps = (int) std::lround(T / dt);
  h.cmd("timestep " + std::to_string(dt));
  h.cmd("compute hm all hamiltonian/modified " + args);
  h.cmd("fix hv all vector 1 c_hm[1] c_hm[2] c_hm[3]");
  h.cmd("run " + std::to_string(nsteps));
  std::vector<double> d(3, 0.0), h0(3);
  for (int n = 0; n <= nsteps; n++)
    for (int k = 0; k < 3; k++) {
      auto *p = (double *) lammps_extract_fix(h.lmp, "hv", LMP_STYLE_GLOBAL, LMP_TYPE_ARRAY, n, k);
      const double val = *p;
      lammps_free(p);
      if (n == 0) h0[k] = val;
      d[k] = std::max(d[k], std::fabs(val - h0[k]));
    }
  return d;
}

double slope(const std::vector<double> &dts, const std::vector<double> &errs)
{
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const int n = (int) dts.size();
  for (int i = 0; i < n; i++) {
    const double x = std::log(dts[i]), y = std::log(errs[i]);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

void check_orders(const std::string &system, const std::vector<double> &dts, double T,
                  const char *what, const std::string &args = "")
{
  std::vector<std::vector<double>> e(3);
  for (double dt : dts) {
    auto d = max_drift(system, dt, T, args);
    for (int k = 0; k < 3; k++) e[k].push_back(d[k]);
  }
  const double expect[3] = {2.0, 4.0, 6.0};
  const char *name[3] = {"H", "H_[2,VV]", "H_[4,VV]"};
  for (int k = 0; k < 3; k++) {
    const double s = slope(dts, e[k]);
    EXPECT_NEAR(s, expect[k], 0.3) << what << " " << name[k];
    printf("[ orders   ] %s %-9s slope %.2f  max drift", what, name[k], s);
    for (double v : e[k]) printf(" %.3e", v);
    printf("\n");
  }
}

// 4-atom chain: harmonic bonds K = 20, r0 = 1; lj/cut (cutoff 8, never
// crossed) on the 1-3 and 1-4 pairs and to a fifth free atom
const char *CHAIN = R"(units lj
atom_style bond
atom_modify map array
boundary p p p
region box block -20 20 -20 20 -20 20
create_box 1 box bond/types 1 extra/bond/per/atom 2 extra/special/per/atom 6
mass 1 1.0
create_atoms 1 single 0.0 0.0 0.0 units box
create_atoms 1 single 1.0 0.1 0.0 units box
create_atoms 1 single 1.6 0.9 0.2 units box
create_atoms 1 single 2.5 1.2 -0.3 units box
create_atoms 1 single 0.8 1.6 1.1 units box
pair_style lj/cut 8.0
pair_coeff 1 1 0.5 1.0
bond_style harmonic
bond_coeff 1 20.0 1.0
special_bonds lj 0.0 1.0 1.0
create_bonds single/bond 1 1 2
create_bonds single/bond 1 2 3
create_bonds single/bond 1 3 4
velocity all create 0.5 4928459 loop geom
fix nve all nve
thermo_style custom step pe
thermo 1000000
)";

// LJ octahedron (edge 2^(1/6)) with a little thermal motion, cutoff 8
const char *CLUSTER = R"(units lj
atom_style atomic
atom_modify map array
boundary p p p
region box block -20 20 -20 20 -20 20
create_box 1 box
mass 1 1.0
create_atoms 1 single 0.7937 0 0 units box
create_atoms 1 single -0.7937 0 0 units box
create_atoms 1 single 0 0.7937 0 units box
create_atoms 1 single 0 -0.7937 0 units box
create_atoms 1 single 0 0 0.7937 units box
create_atoms 1 single 0 0 -0.7937 units box
pair_style lj/cut 8.0
pair_coeff 1 1 1.0 1.0
velocity all create 0.3 87287 loop geom
fix nve all nve
thermo_style custom step pe
thermo 1000000
)";

}    // namespace

TEST(HamiltonianModified, ConservationOrdersChain)
{
  check_orders(CHAIN, {0.02, 0.01, 0.005}, 2.0, "chain");
}

// the chain with harmonic angles, everything by differences of force
// evaluations (path fdiff): V''v, V'''[v,v,.] and V''''[v,v,v,v] are
// accurate enough for the sixth order to show
TEST(HamiltonianModified, ConservationOrdersChainAnglesFdiff)
{
  std::string sys = CHAIN;
  auto rep = [&](const std::string &a, const std::string &b) {
    sys.replace(sys.find(a), a.size(), b);
  };
  rep("atom_style bond", "atom_style molecular");
  rep("extra/bond/per/atom 2", "angle/types 1 extra/bond/per/atom 2 extra/angle/per/atom 2");
  rep("special_bonds", "angle_style harmonic\nangle_coeff 1 3.0 120.0\nspecial_bonds");
  rep("velocity", "create_bonds single/angle 1 1 2 3\ncreate_bonds single/angle 1 2 3 4\nvelocity");
  check_orders(sys, {0.02, 0.01, 0.005}, 2.0, "chain+angles fdiff", "path fdiff");
}

TEST(HamiltonianModified, ConservationOrdersCluster)
{
  check_orders(CLUSTER, {0.02, 0.01, 0.005}, 2.0, "cluster");
}

// ---- fix ave/time invokes the compute on steps without thermo output:
// LAMMPS tallies the energy there (peflag), the values are those of the step
TEST(HamiltonianModified, FixAveTimeOnNonThermoSteps)
{
  HSLammps h;
  h.lines(CLUSTER);
  h.cmd("compute hm all hamiltonian/modified");
  h.cmd("fix av all ave/time 5 1 5 c_hm[1] c_hm[2] c_hm[3] c_hm");
  h.cmd("thermo 7");
  h.cmd("thermo_style custom step pe");
  h.cmd("run 20");
  // at step 20 (a fix ave/time step, and the last thermo step) both agree
  auto c = compute_vector(h, "hm");
  for (int k = 0; k < 3; k++) EXPECT_DOUBLE_EQ(h.fix_vector("av", k), c[k]) << k;
  EXPECT_DOUBLE_EQ(h.fix_vector("av", 3), c[1]);
  EXPECT_GT(std::fabs(c[1] - c[0]), 0.0);
}

// ---- errors

TEST(HamiltonianModified, Errors)
{
  const std::string base = "units lj\natom_style molecular\nregion box block 0 5 0 5 0 5\n"
                           "create_box 1 box bond/types 1 angle/types 1 extra/bond/per/atom 2\n"
                           "create_atoms 1 single 1 1 1\ncreate_atoms 1 single 2 1 1\n"
                           "mass 1 1.0\npair_style lj/cut 2.5\npair_coeff 1 1 1.0 1.0\n"
                           "bond_style harmonic\nbond_coeff 1 1.0 1.0\n";
  struct Case {
    std::string text, msg;
  } cases[] = {
      {"compute hm all hamiltonian/modified bogus\n",
       "Unknown compute hamiltonian/modified keyword: bogus"},
      {"compute hm all hamiltonian/modified path\n", "path needs a value"},
      {"compute hm all hamiltonian/modified path nope\n",
       "path must be auto, single or fdiff, got nope"},
      {"angle_style harmonic\nangle_coeff 1 1.0 90.0\n"
       "compute hm all hamiltonian/modified path single\nthermo_style custom step c_hm\nrun 0\n",
       "path single is not available for angle style harmonic"},
      {"fix sp all spring tether 1.0 0 0 0 0\nfix_modify sp energy yes\n"
       "compute hm all hamiltonian/modified path single\nthermo_style custom step c_hm\nrun 0\n",
       "path single is not available for fix sp spring"},
  };
  for (auto &c : cases) {
    auto r = run_lmp(base + c.text);
    EXPECT_NE(r.exit_code, 0) << c.text;
    EXPECT_NE(r.output.find(c.msg), std::string::npos) << c.text << "\n---\n" << r.output;
  }
}
