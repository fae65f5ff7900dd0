// The hard-core Yukawa fluid of examples/hard-core-yukawa, short version:
// MD with fix hardsphere/cva + fix langevin against an NVT Metropolis Monte
// Carlo of the same model written here (no LAMMPS in it). Both sample the
// Boltzmann weight of the potential the MD's forces derive from:
//   u(r) = -exp(-kappa (r - 1)) / r - u(rc),  1 <= r < rc  (sigma = eps = 1),
// shifted, because pair_style yukawa's forces have no impulse at rc (the
// reported energy U/N is the unshifted one in both). 108 spheres at
// rho* = 0.6, T* = 1.5, kappa = 1.8 and rc = 2.5 (the example's rc = 4
// needs 500 spheres for the minimum image of the MC; this keeps the test
// short). Checked, with error bars from block means:
//   - MD <T> = T0 (langevin zero yes: 3N - 3 thermalised components);
//   - U/N and Z = 1 + P_vir/(rho kT) of MD and MC agree;
//   - Z without the fix's impulse virial does not: the check sees the
//     collisional pressure (Z_MC's contact term from extrapolating the
//     cavity function g(r) exp(u/kT) to contact).

#include "hs_test_main.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <random>
#include <sstream>

namespace {

const double PI = 3.14159265358979323846;
const double RHO = 0.6, T0 = 1.5, KAPPA = 1.8, RC = 2.5;
const int CELLS = 3;    // fcc: 108 spheres
const int NB = 20;      // blocks

double u_yuk(double r)
{
  return -std::exp(-KAPPA * (r - 1.0)) / r;
}
// r du/dr
double rdu_yuk(double r)
{
  return std::exp(-KAPPA * (r - 1.0)) * (KAPPA * r + 1.0) / r;
}

struct MCResult {
  std::vector<double> U, Z;    // block means
};

// Metropolis MC, fcc start, NB blocks of `per_block` sweeps after `equil`
MCResult monte_carlo(long equil, long per_block, unsigned seed)
{
  const int n = 4 * CELLS * CELLS * CELLS;
  const double L = std::cbrt(n / RHO), uc = u_yuk(RC), rc2 = RC * RC;
  std::vector<double> x;
  const double a = L / CELLS;
  const double basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
  for (int i = 0; i < CELLS; ++i)
    for (int j = 0; j < CELLS; ++j)
      for (int k = 0; k < CELLS; ++k)
        for (auto &b : basis) {
          x.push_back((i + b[0]) * a);
          x.push_back((j + b[1]) * a);
          x.push_back((k + b[2]) * a);
        }
  auto d2 = [&](const double *p, const double *q) {
    double s = 0;
    for (int k = 0; k < 3; ++k) {
      double d = p[k] - q[k];
      if (d > 0.5 * L) d -= L;
      else if (d < -0.5 * L) d += L;
      s += d * d;
    }
    return s;
  };
  // energy of i at xi (shifted weight); infinite on overlap
  auto e_of = [&](int i, const double *xi) {
    double e = 0;
    for (int j = 0; j < n; ++j) {
      if (j == i) continue;
      const double s = d2(xi, &x[3 * j]);
      if (s < 1.0) return (double) INFINITY;
      if (s < rc2) e += u_yuk(std::sqrt(s)) - uc;
    }
    return e;
  };
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> U01(0.0, 1.0);
  double dmax = 0.15;
  long acc = 0, tries = 0;
  auto sweep = [&]() {
    for (int m = 0; m < n; ++m) {
      const int i = std::min(n - 1, (int) (U01(rng) * n));
      double xn[3];
      for (int k = 0; k < 3; ++k) {
        xn[k] = x[3 * i + k] + dmax * (2.0 * U01(rng) - 1.0);
        xn[k] -= L * std::floor(xn[k] / L);
      }
      ++tries;
      const double en = e_of(i, xn);
      if (!std::isfinite(en)) continue;
      const double de = en - e_of(i, &x[3 * i]);
      if (de <= 0 || U01(rng) < std::exp(-de / T0)) {
        std::copy(xn, xn + 3, &x[3 * i]);
        ++acc;
      }
    }
  };
  for (long s = 0; s < equil; ++s) {
    sweep();
    if ((s + 1) % 50 == 0) {
      dmax *= ((double) acc / tries > 0.4) ? 1.05 : 0.95;
      acc = tries = 0;
    }
  }
  // contact: y(r) = g(r) exp(u_w(r)/kT) in bins of 0.01 on [1, 1.08], ln y
  // fitted by a quadratic in r - 1 and taken at contact
  const int NFIT = 8;
  const double H = 0.01, ideal = 0.5 * n * (n - 1) / (L * L * L);
  MCResult res;
  for (int b = 0; b < NB; ++b) {
    std::vector<double> ybin(NFIT, 0.0);
    double su = 0, sw = 0;
    long ns = 0;
    for (long s = 0; s < per_block; ++s) {
      sweep();
      double Ut = 0, W = 0;
      for (int i = 0; i < n; ++i)
        for (int j = i + 1; j < n; ++j) {
          const double q = d2(&x[3 * i], &x[3 * j]);
          if (q >= rc2) continue;
          const double r = std::sqrt(q);
          Ut += u_yuk(r);
          W += rdu_yuk(r);
          const int k = (int) ((r - 1.0) / H);
          if (k >= 0 && k < NFIT) ybin[k] += std::exp((u_yuk(r) - uc) / T0);
        }
      su += Ut / n;
      sw += -W / (3.0 * n * T0);
      ++ns;
    }
    double A[3][4] = {{0}};
    for (int k = 0; k < NFIT; ++k) {
      const double r0 = 1.0 + k * H, r1 = r0 + H;
      const double y = ybin[k] / (ns * ideal * 4.0 / 3.0 * PI * (r1 * r1 * r1 - r0 * r0 * r0));
      const double t = 0.5 * (r0 + r1) - 1.0, f[3] = {1.0, t, t * t};
      for (int p = 0; p < 3; ++p) {
        for (int q = 0; q < 3; ++q) A[p][q] += f[p] * f[q];
        A[p][3] += f[p] * std::log(std::max(y, 1e-300));
      }
    }
    for (int c = 0; c < 3; ++c)
      for (int r = c + 1; r < 3; ++r) {
        const double m = A[r][c] / A[c][c];
        for (int k = c; k < 4; ++k) A[r][k] -= m * A[c][k];
      }
    double co[3];
    for (int r = 2; r >= 0; --r) {
      double v = A[r][3];
      for (int k = r + 1; k < 3; ++k) v -= A[r][k] * co[k];
      co[r] = v / A[r][r];
    }
    const double gc = std::exp(co[0]) * std::exp(-(u_yuk(1.0) - uc) / T0);
    res.U.push_back(su / ns);
    res.Z.push_back(1.0 + sw / ns + 2.0 * PI / 3.0 * RHO * gc);
  }
  return res;
}

}    // namespace

TEST(HardCoreYukawa, MDAgreesWithMonteCarlo)
{
  const int nequil = 1500, nrun = 30000, nb = nrun / NB;
  const std::string blocks = scratch_name("hcy_blocks.txt");
  char rhos[32];
  snprintf(rhos, sizeof(rhos), "%.17g", RHO);
  HSLammps h;
  h.lines(std::string("units lj\natom_style atomic\natom_modify map array\nlattice fcc ") + rhos +
          "\nregion box block 0 " + std::to_string(CELLS) + " 0 " + std::to_string(CELLS) + " 0 " +
          std::to_string(CELLS) + R"(
create_box 1 box
create_atoms 1 box
mass 1 1.0
pair_style yukawa 1.8 2.5
pair_coeff 1 1 -6.0496474644129465 2.5
neighbor 0.3 bin
neigh_modify every 1 delay 0 check yes
comm_modify cutoff 2.9
velocity all create 1.5 8123 mom yes rot yes dist gaussian
timestep 0.005
fix hs all hardsphere/cva diameter 1.0
fix th all langevin 1.5 1.5 2.0 8123 zero yes
)");
  h.cmd("run " + std::to_string(nequil));
  h.lines(R"(
compute pvir all pressure NULL virial
compute pfix all pressure NULL fix
variable upn equal c_thermo_pe/atoms
)");
  h.cmd("fix blk all ave/time 1 " + std::to_string(nb) + " " + std::to_string(nb) +
        " c_thermo_temp v_upn c_pvir c_pfix file " + blocks);
  h.cmd("run " + std::to_string(nrun));
  h.cmd("unfix blk");
  const double natoms = h.thermo("atoms"), vol = h.thermo("vol");
  ASSERT_EQ(natoms, 108.0);
  const double rho = natoms / vol;
  ASSERT_NEAR(rho, RHO, 1e-12);

  std::vector<double> T, U, Z, Zs;
  std::ifstream in(blocks);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    double step, t, u, pv, pf;
    if (ls >> step >> t >> u >> pv >> pf) {
      T.push_back(t);
      U.push_back(u);
      Z.push_back(1.0 + pv / (rho * T0));
      Zs.push_back(1.0 + (pv - pf) / (rho * T0));
    }
  }
  in.close();
  std::remove(blocks.c_str());
  ASSERT_EQ((int) T.size(), NB);

  const MCResult mc = monte_carlo(1000, 1000, 20251125u);
  double Tm, Tse, Um, Use, Zm, Zse, Zsm, Zsse, Ucm, Ucse, Zcm, Zcse;
  mean_se(T, Tm, Tse);
  mean_se(U, Um, Use);
  mean_se(Z, Zm, Zse);
  mean_se(Zs, Zsm, Zsse);
  mean_se(mc.U, Ucm, Ucse);
  mean_se(mc.Z, Zcm, Zcse);
  const double sU = std::hypot(Use, Ucse), sZ = std::hypot(Zse, Zcse);
  printf("[ hcy ] MD <T> %.4f +- %.4f (T0 %.1f); U/N MD %.4f +- %.4f MC %.4f +- %.4f (%.1f sigma); "
         "Z MD %.4f +- %.4f MC %.4f +- %.4f (%.1f sigma); Z without impulse virial %.4f (%.1f sigma)\n",
         Tm, Tse, T0, Um, Use, Ucm, Ucse, (Um - Ucm) / sU, Zm, Zse, Zcm, Zcse, (Zm - Zcm) / sZ, Zsm,
         (Zsm - Zcm) / std::hypot(Zsse, Zcse));
  // error bars small enough for the checks to mean something
  EXPECT_LT(sU, 0.01);
  EXPECT_LT(sZ, 0.05);
  // four combined error bars: 20 blocks give each error bar to ~16 %
  EXPECT_NEAR(Tm, T0, 4.0 * Tse);
  EXPECT_NEAR(Um, Ucm, 4.0 * sU);
  EXPECT_NEAR(Zm, Zcm, 4.0 * sZ);
  // the collisional part is most of Z here: leaving it out is far off
  EXPECT_GT(std::fabs(Zsm - Zcm), 10.0 * std::hypot(Zsse, Zcse));
}
