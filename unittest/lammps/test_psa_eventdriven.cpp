// fix hardsphere/psa with no smooth forces is the classic event-driven
// hard-sphere algorithm (Bond & Leimkuhler 2007, section 2.1: the flow of
// H_a): checked against an independent brute-force event-driven reference
// written here (all pairs, all 27 periodic images, textbook contact time and
// impulse, everything advanced to each event), and for conservation of
// energy and momentum to round-off over thousands of collisions.

#include "hs_test_main.h"

#include "atom.h"
#include "library.h"

#include <array>
#include <cmath>
#include <random>
#include <string>
#include <vector>

namespace {

using Vec = std::array<double, 3>;

std::string fmt(double v)
{
  char buf[64];
  snprintf(buf, sizeof(buf), "%.17g", v);
  return buf;
}

struct Sys {
  std::vector<Vec> x, v;
  std::vector<double> r, m;
  double L = 0.0;          // box [0, L]^3
  bool periodic = true;    // else a hard wall on each face
};

// ---- the reference: O(N^2) per event, nothing shared with the fix
struct RefCounts {
  long pair = 0, wall = 0;
};

// earliest pair contact within 'best' (updated in place) over the images
// -nimg..nimg of each pair in each periodic direction (or the minimum image
// only, minimg = true); textbook formula t = (-b - sqrt(b^2 - a c)) / a
void earliest_pair(const Sys &s, int nimg, bool minimg, double &best, int &bi, int &bj, Vec &bshift)
{
  const int n = (int) s.x.size();
  for (int i = 0; i < n; i++)
    for (int j = i + 1; j < n; j++)
      for (int ix = -nimg; ix <= nimg; ix++)
        for (int iy = -nimg; iy <= nimg; iy++)
          for (int iz = -nimg; iz <= nimg; iz++) {
            Vec shift{ix * s.L, iy * s.L, iz * s.L};
            Vec dq, dv;
            for (int k = 0; k < 3; k++) {
              dq[k] = s.x[i][k] - s.x[j][k];
              if (minimg) shift[k] = -s.L * std::round(dq[k] / s.L);
              dq[k] += shift[k];
              dv[k] = s.v[i][k] - s.v[j][k];
            }
            const double b = dq[0] * dv[0] + dq[1] * dv[1] + dq[2] * dv[2];
            if (b >= 0.0) continue;
            const double a = dv[0] * dv[0] + dv[1] * dv[1] + dv[2] * dv[2];
            const double sig = s.r[i] + s.r[j];
            const double c = dq[0] * dq[0] + dq[1] * dq[1] + dq[2] * dq[2] - sig * sig;
            const double d = b * b - a * c;
            if (d <= 0.0) continue;
            double tc = (-b - std::sqrt(d)) / a;
            if (tc < -1e-9) ADD_FAILURE() << "reference: overlap of " << i << " and " << j;
            tc = std::max(tc, 0.0);
            if (tc < best) {
              best = tc;
              bi = i;
              bj = j;
              bshift = shift;
            }
          }
}

RefCounts reference_run(Sys &s, double T)
{
  const int n = (int) s.x.size();
  RefCounts cnt;
  double t = 0.0;
  double rmax = 0.0;
  for (double r : s.r) rmax = std::max(rmax, r);
  while (true) {
    double best = T - t;
    int bi = -1, bj = -1, bw = -1;
    Vec bshift{0, 0, 0};
    if (s.periodic) {
      // minimum images first: any other image is >= L/2 away along some
      // axis, so it cannot touch before (L/2 - 2 rmax) / (2 vmax); an event
      // found later than that is re-checked over all 27 images
      double vmax = 0.0;
      for (const Vec &v : s.v) vmax = std::max(vmax, std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
      earliest_pair(s, 0, true, best, bi, bj, bshift);
      if (best * 2.0 * vmax >= 0.5 * s.L - 2.0 * rmax) {
        best = T - t;
        bi = bj = -1;
        earliest_pair(s, 1, false, best, bi, bj, bshift);
      }
    } else
      earliest_pair(s, 0, false, best, bi, bj, bshift);
    if (!s.periodic)
      for (int i = 0; i < n; i++)
        for (int k = 0; k < 3; k++) {
          double tc = -1.0;
          if (s.v[i][k] < 0.0) tc = (s.x[i][k] - s.r[i]) / -s.v[i][k];
          else if (s.v[i][k] > 0.0) tc = (s.L - s.r[i] - s.x[i][k]) / s.v[i][k];
          if (tc < 0.0) continue;
          if (tc < best) {
            best = tc;
            bi = i;
            bj = -1;
            bw = k;
          }
        }
    for (int i = 0; i < n; i++)
      for (int k = 0; k < 3; k++) s.x[i][k] += best * s.v[i][k];
    t += best;
    if (bi < 0) break;
    if (bj >= 0) {
      Vec nrm, dv;
      double len = 0.0;
      for (int k = 0; k < 3; k++) {
        nrm[k] = s.x[bi][k] - s.x[bj][k] + bshift[k];
        dv[k] = s.v[bi][k] - s.v[bj][k];
        len += nrm[k] * nrm[k];
      }
      len = std::sqrt(len);
      double un = 0.0;
      for (int k = 0; k < 3; k++) {
        nrm[k] /= len;
        un += dv[k] * nrm[k];
      }
      const double mu = s.m[bi] * s.m[bj] / (s.m[bi] + s.m[bj]);
      for (int k = 0; k < 3; k++) {
        const double J = -2.0 * mu * un * nrm[k];
        s.v[bi][k] += J / s.m[bi];
        s.v[bj][k] -= J / s.m[bj];
      }
      cnt.pair++;
    } else {
      s.v[bi][bw] = -s.v[bi][bw];
      cnt.wall++;
    }
  }
  return cnt;
}

// spheres on a jittered cubic grid (g^3 sites, spacing a), Gaussian velocities
Sys make_system(int g, double a, bool periodic, bool polydisperse, unsigned seed)
{
  Sys s;
  s.L = g * a;
  s.periodic = periodic;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  std::normal_distribution<double> G(0.0, 1.0);
  for (int ix = 0; ix < g; ix++)
    for (int iy = 0; iy < g; iy++)
      for (int iz = 0; iz < g; iz++) {
        const double r = polydisperse ? 0.4 + 0.1 * (U(rng) + 1.0) : 0.5;
        const double m = polydisperse ? 0.5 + (U(rng) + 1.0) : 1.0;
        // centre within (a/2 - 0.05) - r of the site: no overlap, clear of the walls
        const double room = 0.5 * a - 0.05 - r;
        s.x.push_back({(ix + 0.5) * a + room * U(rng), (iy + 0.5) * a + room * U(rng),
                       (iz + 0.5) * a + room * U(rng)});
        s.v.push_back({G(rng), G(rng), G(rng)});
        s.r.push_back(r);
        s.m.push_back(m);
      }
  return s;
}

struct Result {
  std::vector<double> x, v;
  double pair = -1, wall = -1, fevals = -1;
};

Result run_psa(const Sys &s, double dt, int nsteps, bool polydisperse, bool map = true)
{
  HSLammps h;
  const int n = (int) s.x.size();
  std::string in = "units lj\n";
  in += polydisperse ? "atom_style sphere\n" : "atom_style atomic\n";
  in += s.periodic ? "boundary p p p\n" : "boundary f f f\n";
  if (map) in += "atom_modify map array\n";
  in += "region box block 0 " + fmt(s.L) + " 0 " + fmt(s.L) + " 0 " + fmt(s.L) + " units box\n";
  in += "create_box 1 box\n";
  for (int i = 0; i < n; i++)
    in += "create_atoms 1 single " + fmt(s.x[i][0]) + " " + fmt(s.x[i][1]) + " " +
        fmt(s.x[i][2]) + " units box\n";
  if (polydisperse)
    for (int i = 0; i < n; i++)
      in += "set atom " + std::to_string(i + 1) + " diameter " + fmt(2 * s.r[i]) + " mass " +
          fmt(s.m[i]) + "\n";
  else
    in += "mass 1 1.0\n";
  for (int i = 0; i < n; i++)
    in += "set atom " + std::to_string(i + 1) + " vx " + fmt(s.v[i][0]) + " vy " +
        fmt(s.v[i][1]) + " vz " + fmt(s.v[i][2]) + "\n";
  in += "neighbor 0.3 bin\nneigh_modify every 1 delay 0 check yes\ncomm_modify cutoff 2.0\n";
  in += "timestep " + fmt(dt) + "\n";
  in += std::string("fix hs all hardsphere/psa") + (polydisperse ? "" : " diameter 1.0") +
      (s.periodic ? "" : " wall xlo EDGE wall xhi EDGE wall ylo EDGE wall yhi EDGE wall zlo EDGE wall zhi EDGE") +
      "\n";
  in += "run " + std::to_string(nsteps) + "\n";
  h.lines(in);
  if (!map) EXPECT_EQ(h.lmp->atom->map_style, LAMMPS_NS::Atom::MAP_NONE);
  Result r;
  r.x.resize(3 * n);
  r.v.resize(3 * n);
  lammps_gather_atoms(h.lmp, (char *) "x", 1, 3, r.x.data());
  lammps_gather_atoms(h.lmp, (char *) "v", 1, 3, r.v.data());
  r.pair = h.fix_vector("hs", 1);
  r.wall = h.fix_vector("hs", 2);
  r.fevals = h.fix_vector("hs", 4);
  return r;
}

void compare_with_reference(const Sys &s0, double dt, int nsteps, bool poly, double tol,
                            long min_collisions, bool map = true)
{
  Sys ref = s0;
  const RefCounts cnt = reference_run(ref, dt * nsteps);
  Result got = run_psa(s0, dt, nsteps, poly, map);
  printf("[ psa ref  ] %zu spheres, %s, dt %g x %d: reference %ld pair + %ld wall collisions, "
         "psa %g + %g\n",
         s0.x.size(), s0.periodic ? "periodic" : "walls", dt, nsteps, cnt.pair, cnt.wall,
         got.pair, got.wall);
  EXPECT_GE(cnt.pair + cnt.wall, min_collisions);
  EXPECT_EQ(got.pair, (double) cnt.pair);
  EXPECT_EQ(got.wall, (double) cnt.wall);
  EXPECT_EQ(got.fevals, 0.0);
  double dxmax = 0.0, dvmax = 0.0;
  for (size_t i = 0; i < s0.x.size(); i++)
    for (int k = 0; k < 3; k++) {
      double dx = got.x[3 * i + k] - ref.x[i][k];
      if (s0.periodic) dx -= s0.L * std::round(dx / s0.L);
      dxmax = std::max(dxmax, std::fabs(dx));
      dvmax = std::max(dvmax, std::fabs(got.v[3 * i + k] - ref.v[i][k]));
    }
  printf("[ psa ref  ] max |x - x_ref| %.2e, max |v - v_ref| %.2e\n", dxmax, dvmax);
  EXPECT_LT(dxmax, tol);
  EXPECT_LT(dvmax, tol);
}

}    // namespace

TEST(PSAEventDriven, PeriodicFluidMatchesBruteForce)
{
  // 125 spheres, packing fraction 0.13; hundreds of collisions (few per
  // sphere, so round-off, amplified at each collision, stays small)
  Sys s = make_system(5, 1.6, true, false, 2024);
  compare_with_reference(s, 0.01, 150, false, 1e-7, 150);
}

TEST(PSAEventDriven, PeriodicFluidLargeStepMatchesBruteForce)
{
  // the same with 4x the step: the flight is exact whatever dt
  Sys s = make_system(5, 1.6, true, false, 2024);
  compare_with_reference(s, 0.04, 150 / 4 + 1, false, 1e-7, 150);
}

TEST(PSAEventDriven, DenserPeriodicFluidThousandCollisionsMatchesBruteForce)
{
  // 216 spheres, packing fraction 0.21, about a thousand collisions: still
  // short of the horizon where the chaotic amplification of round-off
  // (about 1e-16 growing by a factor per collision) makes any two exact
  // event-driven codes part
  Sys s = make_system(6, 1.35, true, false, 11);
  compare_with_reference(s, 0.01, 200, false, 1e-6, 1000);
}

TEST(PSAEventDriven, PeriodicFluidWithoutAtomMapMatchesBruteForce)
{
  // atom_style atomic without atom_modify map: the fix finds the copies of
  // the colliding atoms through its own sorted tag index
  Sys s = make_system(5, 1.6, true, false, 2024);
  compare_with_reference(s, 0.01, 150, false, 1e-7, 150, false);
}

TEST(PSAEventDriven, WalledPolydisperseMatchesBruteForce)
{
  // per-atom radii 0.4..0.5 and masses 0.5..2.5, hard walls on all faces
  Sys s = make_system(4, 1.5, false, true, 77);
  compare_with_reference(s, 0.01, 200, true, 1e-7, 150);
}

namespace {

struct Totals {
  double ke = 0, p[3] = {0, 0, 0}, pscale = 0;
};

Totals totals(HSLammps &h, const std::vector<double> &mass)
{
  const int n = (int) h.lmp->atom->natoms;
  std::vector<double> v(3 * n);
  lammps_gather_atoms(h.lmp, (char *) "v", 1, 3, v.data());
  Totals t;
  for (int i = 0; i < n; i++) {
    const double m = mass.empty() ? 1.0 : mass[i];
    double v2 = 0.0;
    for (int k = 0; k < 3; k++) {
      t.p[k] += m * v[3 * i + k];
      v2 += v[3 * i + k] * v[3 * i + k];
    }
    t.ke += 0.5 * m * v2;
    t.pscale += m * std::sqrt(v2);
  }
  return t;
}

}    // namespace

TEST(PSAEventDriven, PeriodicConservesEnergyAndMomentum)
{
  // 500 spheres at packing fraction 0.35, tens of thousands of collisions
  HSLammps h;
  h.lines(R"(
units lj
atom_style atomic
atom_modify map array
lattice fcc 0.66845
region box block 0 5 0 5 0 5
create_box 1 box
create_atoms 1 box
mass 1 1.0
velocity all create 1.0 4711 mom yes rot no dist gaussian
neighbor 0.3 bin
neigh_modify every 1 delay 0 check yes
comm_modify cutoff 1.7
timestep 0.02
fix hs all hardsphere/psa diameter 1.0
thermo_style custom step ke press
run 0
)");
  const Totals t0 = totals(h, {});
  h.cmd("run 1000");
  const Totals t1 = totals(h, {});
  const double ncoll = h.fix_vector("hs", 0);
  printf("[ psa cons ] %g collisions: |dKE|/KE = %.2e, |P|/sum|p| = %.2e -> %.2e\n", ncoll,
         std::fabs(t1.ke - t0.ke) / t0.ke,
         std::sqrt(t0.p[0] * t0.p[0] + t0.p[1] * t0.p[1] + t0.p[2] * t0.p[2]) / t0.pscale,
         std::sqrt(t1.p[0] * t1.p[0] + t1.p[1] * t1.p[1] + t1.p[2] * t1.p[2]) / t1.pscale);
  EXPECT_GT(ncoll, 20000.0);
  EXPECT_EQ(h.fix_vector("hs", 4), 0.0);
  EXPECT_LT(std::fabs(t1.ke - t0.ke), 1e-12 * t0.ke);
  for (int k = 0; k < 3; k++) EXPECT_LT(std::fabs(t1.p[k] - t0.p[k]), 1e-12 * t0.pscale);
  // the pressure is the collision virial: positive, finite
  EXPECT_GT(h.thermo("press"), 0.0);
}

TEST(PSAEventDriven, WalledConservesEnergy)
{
  HSLammps h;
  h.lines(R"(
units lj
atom_style atomic
atom_modify map array
boundary f f f
region box block 0 8 0 8 0 8 units box
create_box 1 box
region inner block 0.6 7.4 0.6 7.4 0.6 7.4 units box
lattice sc 1.0
create_atoms 1 region inner
mass 1 1.0
velocity all create 2.0 99 mom yes rot no dist gaussian
neighbor 0.3 bin
neigh_modify every 1 delay 0 check yes
comm_modify cutoff 1.7
timestep 0.02
fix hs all hardsphere/psa diameter 0.9 wall xlo EDGE wall xhi EDGE wall ylo EDGE wall yhi EDGE wall zlo EDGE wall zhi EDGE
run 0
)");
  const Totals t0 = totals(h, {});
  h.cmd("run 1000");
  const Totals t1 = totals(h, {});
  const double npair = h.fix_vector("hs", 1), nwall = h.fix_vector("hs", 2);
  printf("[ psa cons ] walls: %g pair + %g wall collisions: |dKE|/KE = %.2e\n", npair, nwall,
         std::fabs(t1.ke - t0.ke) / t0.ke);
  EXPECT_GT(npair, 5000.0);
  EXPECT_GT(nwall, 1000.0);
  EXPECT_LT(std::fabs(t1.ke - t0.ke), 1e-12 * t0.ke);
}
