// NVT Metropolis Monte Carlo of the hard-core Yukawa fluid, independent of
// LAMMPS and of the HARDSPHERE package: the reference for the MD example.
//
//   u(r) = inf                                   r < sigma
//   u(r) = -eps sigma exp(-kappa (r - sigma))/r   sigma <= r < rc,   0 beyond
//
// (units sigma = eps = k = 1). The MD (pair_style yukawa, unshifted) feels
// the force -du/dr only, with no impulse where a pair crosses rc: its
// dynamics conserves, and its thermostat samples, the Boltzmann weight of
// the *shifted* potential u(r) - u(rc). This program samples that weight
// too (--weight shifted, the default) and reports what the MD reports: the
// unshifted energy U/N and the virial from the forces. --weight unshifted
// samples the truncated, discontinuous model instead (for comparison only;
// its pressure would also need the delta term at rc, not computed here).
//
// Output (stdout): block means of U/N, Z_smooth = -(1/3NkT) sum r u'(r),
// and g(sigma+) from the contact extrapolation (see contact_value), then
// the averages with block errors; the full g(r) with --gr FILE.
//
//   g++ -O2 -o mc_hcy mc_hcy.cpp
//   ./mc_hcy --rho 0.6 --T 1.5 --cells 5 --sweeps 100000 --seed 1

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
  double rho = 0.6, T = 1.5, kappa = 1.8, rc = 4.0, eps = 1.0;
  int cells = 5;    // fcc cells per side: N = 4 cells^3
  long sweeps = 100000, equil = 5000, nblocks = 100;
  int sample_every = 5;
  unsigned seed = 1;
  bool shifted = true;
  std::string gr_file;
};

// contact histogram: bins of width H on [1, 1 + NCB H]
const double H = 0.01;
const int NCB = 12;
// fit ln y over the first NFIT bins with a quadratic (see contact_value)
const int NFIT = 8;

struct System {
  Params p;
  int n = 0;
  double L = 0, uc = 0;    // box edge, u(rc)
  std::vector<double> x;

  double u(double r) const { return -p.eps * std::exp(-p.kappa * (r - 1.0)) / r; }
  // r du/dr
  double rdu(double r) const { return p.eps * std::exp(-p.kappa * (r - 1.0)) * (p.kappa * r + 1.0) / r; }
  // Boltzmann-weight energy: shifted or not
  double uw(double r) const { return p.shifted ? u(r) - uc : u(r); }

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
    const double rc2 = p.rc * p.rc;
    double e = 0;
    for (int j = 0; j < n; ++j) {
      if (j == i) continue;
      const double d2 = dist2(xi, &x[3 * j]);
      if (d2 < 1.0) return INFINITY;
      if (d2 < rc2) e += uw(std::sqrt(d2));
    }
    return e;
  }
};

using mc_stats::block_se;    // ../common/mc_stats.h
using mc_stats::contact_value;
using mc_stats::mean;

void usage()
{
  std::fprintf(stderr,
               "usage: mc_hcy [--rho R] [--T T] [--kappa K] [--rc RC] [--eps E] [--cells C]\n"
               "              [--sweeps S] [--equil S] [--blocks B] [--every K] [--seed S]\n"
               "              [--weight shifted|unshifted] [--gr FILE]\n");
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
    else if (k == "--kappa") p.kappa = std::atof(v);
    else if (k == "--rc") p.rc = std::atof(v);
    else if (k == "--eps") p.eps = std::atof(v);
    else if (k == "--cells") p.cells = std::atoi(v);
    else if (k == "--sweeps") p.sweeps = std::atol(v);
    else if (k == "--equil") p.equil = std::atol(v);
    else if (k == "--blocks") p.nblocks = std::atol(v);
    else if (k == "--every") p.sample_every = std::atoi(v);
    else if (k == "--seed") p.seed = (unsigned) std::atol(v);
    else if (k == "--weight") p.shifted = std::string(v) != "unshifted";
    else if (k == "--gr") p.gr_file = v;
    else usage();
  }

  System s;
  s.p = p;
  s.n = 4 * p.cells * p.cells * p.cells;
  s.L = std::cbrt(s.n / p.rho);
  s.uc = s.u(p.rc);
  if (p.rc > 0.5 * s.L) {
    std::fprintf(stderr, "rc %.3f > L/2 = %.3f: minimum image fails, use more cells\n", p.rc, 0.5 * s.L);
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
        for (int k = 0; k < 3; ++k) s.x[3 * i + k] = xn[k];
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

  // g(r) histogram (bin 0.02 to L/2) for --gr, contact histogram for g(sigma+)
  const double GH = 0.02;
  const int ngr = (int) (0.5 * s.L / GH);
  std::vector<double> gr(ngr, 0.0), ytot(NCB, 0.0), yblk(NCB, 0.0);
  std::vector<double> bU, bZ, bG;
  const long per_block = std::max(1L, p.sweeps / p.nblocks);
  double sumU = 0, sumW = 0;
  long nblk_samples = 0, ntot_samples = 0;
  const double rc2 = p.rc * p.rc, hi2 = std::pow(1.0 + NCB * H, 2);

  for (long sw = 0; sw < p.nblocks * per_block; ++sw) {
    sweep();
    if ((sw + 1) % p.sample_every == 0) {
      double U = 0, W = 0;
      for (int i = 0; i < s.n; ++i)
        for (int j = i + 1; j < s.n; ++j) {
          const double d2 = s.dist2(&s.x[3 * i], &s.x[3 * j]);
          if (d2 >= rc2 && d2 >= 0.25 * s.L * s.L) continue;
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
        }
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
  std::printf("# mc_hcy N %d rho %.6g T %.6g kappa %.6g rc %.6g eps %.6g weight %s sweeps %ld "
              "equil %ld blocks %ld every %d seed %u dmax %.4f acceptance %.4f\n",
              s.n, p.rho, p.T, p.kappa, p.rc, p.eps, p.shifted ? "shifted" : "unshifted",
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
    std::fprintf(f, "# r g(r)  (mc_hcy, N %d rho %g T %g)\n", s.n, p.rho, p.T);
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
