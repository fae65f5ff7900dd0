// NVT Metropolis Monte Carlo of hard colloids with the Asakura-Oosawa
// depletion attraction, independent of LAMMPS and of the HARDSPHERE package:
// the reference for the MD of this example (adapted from
// examples/hard-core-yukawa/mc_hcy.cpp; the potential from its formula, not
// from the tables):
//
//   u(r)/kT = inf                                        r < sigma
//   u(r)/kT = -A [1 - 3x/2 + x^3/2],  x = r/(sigma(1+q))   sigma <= r < sigma(1+q)
//   A = eta_p ((1+q)/q)^3, eta_p = depth/(1 + 3/(2q)): u(sigma) = -depth kT
//
// (units sigma = kT = 1). u and u' vanish at the cutoff sigma(1+q), so no
// shift and no delta term there.
//
// Output (stdout): block means of U/N, Z_smooth = -(1/3N) sum r u'(r), and
// g(sigma+) from the contact extrapolation (see contact_value), then the
// averages with block errors; g(r) with --gr FILE.
//
//   g++ -O2 -o mc_ao mc_ao.cpp
//   ./mc_ao --q 0.2 --rho 0.3 --cells 6 --sweeps 40000 --seed 1

#include "../common/mc_stats.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

namespace {

struct Params {
  double rho = 0.3, q = 0.2, depth = 3.0, T = 1.0;
  int cells = 6;    // fcc cells per side: N = 4 cells^3
  long sweeps = 100000, equil = 5000, nblocks = 100;
  int sample_every = 5;
  unsigned seed = 1;
  std::string gr_file;
};

// contact histogram: bins of width H on [1, 1 + NCB H]
const double H = 0.01;
const int NCB = 12;
// fit ln y over the first NFIT bins with a quadratic (see contact_value)
const int NFIT = 8;
const double RCELL = 1.5;

struct System {
  Params p;
  int n = 0;
  double L = 0, R = 0, A = 0;    // box edge, cutoff sigma (1+q), amplitude
  std::vector<double> x;
  // linked cells of edge >= RCELL (the largest distance anything needs: g(r)
  // to 1.5): a move looks at 27 cells instead of all N spheres
  int nc = 0;
  std::vector<std::vector<int>> cell;
  std::vector<int> cell_of;

  int cell_index(const double *xi) const
  {
    int c[3];
    for (int k = 0; k < 3; ++k) c[k] = std::min(nc - 1, (int) (xi[k] / L * nc));
    return (c[0] * nc + c[1]) * nc + c[2];
  }
  void build_cells()
  {
    cell.assign(nc * nc * nc, {});
    cell_of.resize(n);
    for (int i = 0; i < n; ++i) {
      cell_of[i] = cell_index(&x[3 * i]);
      cell[cell_of[i]].push_back(i);
    }
  }
  void move(int i, const double *xn)
  {
    for (int k = 0; k < 3; ++k) x[3 * i + k] = xn[k];
    const int c = cell_index(xn);
    if (c == cell_of[i]) return;
    auto &v = cell[cell_of[i]];
    for (auto &j : v)
      if (j == i) {
        j = v.back();
        v.pop_back();
        break;
      }
    cell[c].push_back(i);
    cell_of[i] = c;
  }
  // calls fn(j) for every sphere j != i in the 27 cells around position xi
  template <class F> void neighbours(int i, const double *xi, F fn) const
  {
    const int c = cell_index(xi);
    const int cx = c / (nc * nc), cy = (c / nc) % nc, cz = c % nc;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const int a = (cx + dx + nc) % nc, b = (cy + dy + nc) % nc, d = (cz + dz + nc) % nc;
          for (int j : cell[(a * nc + b) * nc + d])
            if (j != i && !fn(j)) return;
        }
  }

  // in units of kT at T = 1 (--T rescales the Boltzmann factor only)
  double u(double r) const
  {
    const double x = r / R;
    return -A * (1.0 - 1.5 * x + 0.5 * x * x * x);
  }
  // r du/dr
  double rdu(double r) const
  {
    const double x = r / R;
    return 1.5 * A * (x - x * x * x);
  }
  double uw(double r) const { return u(r); }

  double dist2(const double *a, const double *b) const
  {
    double d2 = 0;
    for (int k = 0; k < 3; ++k) {
      double d = a[k] - b[k];    // positions are kept in [0, L)
      if (d > 0.5 * L) d -= L;
      else if (d < -0.5 * L) d += L;
      d2 += d * d;
    }
    return d2;
  }

  // weight energy of particle i at position xi with all others; +inf on overlap
  double energy_of(int i, const double *xi) const
  {
    const double rc2 = R * R;
    double e = 0;
    neighbours(i, xi, [&](int j) {
      const double d2 = dist2(xi, &x[3 * j]);
      if (d2 < 1.0) {
        e = INFINITY;
        return false;
      }
      if (d2 < rc2) e += uw(std::sqrt(d2));
      return true;
    });
    return e;
  }
};

using mc_stats::block_se;    // ../common/mc_stats.h
using mc_stats::contact_value;
using mc_stats::mean;

void usage()
{
  std::fprintf(stderr,
               "usage: mc_ao [--q Q] [--depth D] [--rho R] [--T T] [--cells C]\n"
               "             [--sweeps S] [--equil S] [--blocks B] [--every K] [--seed S] [--gr FILE]\n");
  std::exit(2);
}

}    // namespace

int main(int argc, char **argv)
{
  Params p;
  for (int a = 1; a < argc; ++a) {
    const std::string k = argv[a];
    if (a + 1 >= argc) usage();
    const char *v = argv[++a];
    if (k == "--rho") p.rho = std::atof(v);
    else if (k == "--T") p.T = std::atof(v);
    else if (k == "--q") p.q = std::atof(v);
    else if (k == "--depth") p.depth = std::atof(v);
    else if (k == "--cells") p.cells = std::atoi(v);
    else if (k == "--sweeps") p.sweeps = std::atol(v);
    else if (k == "--equil") p.equil = std::atol(v);
    else if (k == "--blocks") p.nblocks = std::atol(v);
    else if (k == "--every") p.sample_every = std::atoi(v);
    else if (k == "--seed") p.seed = (unsigned) std::atol(v);
    else if (k == "--gr") p.gr_file = v;
    else usage();
  }

  System s;
  s.p = p;
  s.n = 4 * p.cells * p.cells * p.cells;
  s.L = std::cbrt(s.n / p.rho);
  s.R = 1.0 + p.q;
  s.A = p.depth / (1.0 + 1.5 / p.q) * std::pow(s.R / p.q, 3);
  if (s.R > 0.5 * s.L) {
    std::fprintf(stderr, "cutoff %.3f > L/2 = %.3f: minimum image fails, use more cells\n", s.R, 0.5 * s.L);
    return 1;
  }
  // fcc start, as the MD's `lattice fcc rho`
  const double a = s.L / p.cells;
  const double basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
  for (int i = 0; i < p.cells; ++i)
    for (int j = 0; j < p.cells; ++j)
      for (int k = 0; k < p.cells; ++k)
        for (auto &b : basis) {
          s.x.push_back((i + b[0]) * a);
          s.x.push_back((j + b[1]) * a);
          s.x.push_back((k + b[2]) * a);
        }

  s.nc = (int) (s.L / RCELL);
  if (s.nc < 3) {
    std::fprintf(stderr, "box %.3f holds fewer than 3 cells of %.2f: use more fcc cells\n", s.L, RCELL);
    return 1;
  }
  s.build_cells();

  std::mt19937_64 rng(p.seed);
  std::uniform_real_distribution<double> U01(0.0, 1.0);
  double dmax = 0.1;
  long acc = 0, tries = 0;

  auto sweep = [&]() {
    for (int m = 0; m < s.n; ++m) {
      const int i = (int) (U01(rng) * s.n) % s.n;
      double xn[3];
      for (int k = 0; k < 3; ++k) {
        xn[k] = s.x[3 * i + k] + dmax * (2.0 * U01(rng) - 1.0);
        xn[k] -= s.L * std::floor(xn[k] / s.L);
      }
      const double en = s.energy_of(i, xn);
      ++tries;
      if (!std::isfinite(en)) continue;
      const double eo = s.energy_of(i, &s.x[3 * i]);
      const double de = en - eo;
      if (de <= 0 || U01(rng) < std::exp(-de / p.T)) {
        s.move(i, xn);
        ++acc;
      }
    }
  };

  // equilibration: tune the step towards 40 % acceptance
  for (long sw = 0; sw < p.equil; ++sw) {
    sweep();
    if ((sw + 1) % 100 == 0) {
      const double ratio = (double) acc / tries;
      dmax *= (ratio > 0.4) ? 1.05 : 0.95;
      dmax = std::min(dmax, 0.5 * s.L);
      acc = tries = 0;
    }
  }
  acc = tries = 0;

  // g(r) histogram (bins 0.005 to 1.5, as the MD's compute rdf) for --gr,
  // contact histogram for g(sigma+)
  const double GH = 0.005;
  const int ngr = (int) (RCELL / GH + 0.5);
  std::vector<double> gr(ngr, 0.0), ytot(NCB, 0.0), yblk(NCB, 0.0);
  std::vector<double> bU, bZ, bG;
  const long per_block = std::max(1L, p.sweeps / p.nblocks);
  double sumU = 0, sumW = 0;
  long nblk_samples = 0, ntot_samples = 0;
  const double rc2 = s.R * s.R, hi2 = std::pow(1.0 + NCB * H, 2);

  for (long sw = 0; sw < p.nblocks * per_block; ++sw) {
    sweep();
    if ((sw + 1) % p.sample_every == 0) {
      double U = 0, W = 0;
      for (int i = 0; i < s.n; ++i)
        s.neighbours(i, &s.x[3 * i], [&](int j) {
          if (j < i) return true;
          const double d2 = s.dist2(&s.x[3 * i], &s.x[3 * j]);
          if (d2 >= RCELL * RCELL) return true;
          const double r = std::sqrt(d2);
          if (d2 < rc2) {
            U += s.u(r);
            W += s.rdu(r);
          }
          const int g = (int) (r / GH);
          if (g < ngr) gr[g] += 1.0;
          if (d2 < hi2) {
            const int b = (int) ((r - 1.0) / H);
            if (b >= 0 && b < NCB) yblk[b] += std::exp(s.uw(r) / p.T);
          }
          return true;
        });
      sumU += U / s.n;
      sumW += -W / (3.0 * s.n * p.T);
      ++nblk_samples;
      ++ntot_samples;
    }
    if ((sw + 1) % per_block == 0) {
      bU.push_back(sumU / nblk_samples);
      bZ.push_back(sumW / nblk_samples);
      bG.push_back(contact_value(s, yblk, (double) nblk_samples, H, NFIT));
      for (int b = 0; b < NCB; ++b) {
        ytot[b] += yblk[b];
        yblk[b] = 0;
      }
      sumU = sumW = 0;
      nblk_samples = 0;
    }
  }

  const double PI = 3.14159265358979323846;
  const double gc = contact_value(s, ytot, (double) ntot_samples, H, NFIT);
  std::vector<double> bZtot(bZ.size());
  for (size_t b = 0; b < bZ.size(); ++b) bZtot[b] = 1.0 + bZ[b] + 2.0 * PI / 3.0 * p.rho * bG[b];
  std::printf("# mc_ao N %d rho %.6g q %.6g depth %.6g T %.6g sweeps %ld "
              "equil %ld blocks %ld every %d seed %u dmax %.4f acceptance %.4f\n",
              s.n, p.rho, p.q, p.depth, p.T,
              p.nblocks * per_block, p.equil, p.nblocks, p.sample_every, p.seed, dmax,
              (double) acc / tries);
  std::printf("# block U/N Z_smooth g_contact Z\n");
  for (size_t b = 0; b < bU.size(); ++b)
    std::printf("BLK %zu %.8f %.8f %.8f %.8f\n", b, bU[b], bZ[b], bG[b], bZtot[b]);
  std::printf("RESULT U/N %.6f %.6f Z_smooth %.6f %.6f g_contact %.6f %.6f Z_contact %.6f %.6f "
              "Z %.6f %.6f\n",
              mean(bU), block_se(bU), mean(bZ), block_se(bZ), gc, block_se(bG),
              2.0 * PI / 3.0 * p.rho * gc, 2.0 * PI / 3.0 * p.rho * block_se(bG), mean(bZtot),
              block_se(bZtot));

  if (!p.gr_file.empty()) {
    FILE *f = std::fopen(p.gr_file.c_str(), "w");
    if (!f) return 1;
    std::fprintf(f, "# r g(r)  (mc_ao, N %d rho %g q %g)\n", s.n, p.rho, p.q);
    const double ideal = 0.5 * s.n * (s.n - 1) / (s.L * s.L * s.L);
    for (int g = 0; g < ngr; ++g) {
      const double r0 = g * GH, r1 = r0 + GH;
      const double shell = 4.0 / 3.0 * PI * (r1 * r1 * r1 - r0 * r0 * r0);
      std::fprintf(f, "%.4f %.6f\n", 0.5 * (r0 + r1), gr[g] / (ntot_samples * ideal * shell));
    }
    std::fclose(f);
  }
  return 0;
}
