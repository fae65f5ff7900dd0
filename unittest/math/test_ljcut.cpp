// hs_ljcut.h: lj/cut's forces on a neighbor list, against a reference
// written here as PairLJCut::compute(0, 0) is written (LAMMPS 29Sep2021 and
// 4Feb2025): f[i] and f[j] updated in memory pair by pair, every operation
// forced one at a time. The kernel sums f[i] in registers; the forces must
// agree to the bit: random lists with special bits, several types with
// their own cutoffs and coefficients, pairs beyond the cutoff, ghosts
// (j >= nlocal) with newton on and off, rows that start nonzero. The
// dispatcher lj_cut_forces() and both of its kernels (the scalar loop and
// the AVX2 one, four entries at a time) are each held to the reference.

#include "hs_ljcut.h"

#include "gtest/gtest.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <vector>

namespace {

constexpr int SB = 30;
constexpr int MASK = 0x1FFFFFFF;

struct System {
  int nall = 0, nlocal = 0, ntypes = 0;
  std::vector<double> xs, fs;
  std::vector<double *> f;
  std::vector<const double *> x;
  std::vector<int> type;
  std::vector<std::vector<int>> rows;
  std::vector<int> ilist, numneigh;
  std::vector<int *> firstneigh;
  std::vector<double> cutsq_s, coef;
  std::vector<const double *> cutsq;
  // (1/1.2, AMBER's 1-4 factor, scales inexactly: a product taken in another
  // order shows)
  double special[4] = {1.0, 0.0, 0.5, 1.0 / 1.2};
};

System make(std::mt19937 &g, int nall, int ntypes)
{
  System s;
  s.nall = nall;
  s.nlocal = nall - nall / 3;
  s.ntypes = ntypes;
  std::uniform_real_distribution<double> U(0.0, 1.0);
  s.xs.resize(3 * nall);
  for (auto &v : s.xs) v = 4.0 * U(g);
  s.fs.resize(3 * nall);
  for (auto &v : s.fs) v = U(g) < 0.5 ? 0.0 : U(g) - 0.5;
  for (int i = 0; i < nall; i++) {
    s.x.push_back(&s.xs[3 * i]);
    s.f.push_back(&s.fs[3 * i]);
    s.type.push_back(1 + (int) (U(g) * ntypes));
  }
  const int ntp1 = ntypes + 1;
  s.cutsq_s.assign(ntp1 * ntp1, 0.0);
  s.coef.assign(7 * ntp1 * ntp1, 0.0);
  for (int a = 1; a <= ntypes; a++)
    for (int b = a; b <= ntypes; b++) {
      const double eps = 0.5 + U(g), sig = 0.8 + 0.4 * U(g), cut = 1.5 + U(g);
      for (auto [p, q] : {std::pair<int, int>{a, b}, {b, a}}) {
        s.cutsq_s[p * ntp1 + q] = cut * cut;
        s.coef[7 * (p * ntp1 + q)] = 48.0 * eps * std::pow(sig, 12.0);
        s.coef[7 * (p * ntp1 + q) + 1] = 24.0 * eps * std::pow(sig, 6.0);
        s.coef[7 * (p * ntp1 + q) + 2] = 4.0 * eps * std::pow(sig, 12.0);
        s.coef[7 * (p * ntp1 + q) + 3] = 4.0 * eps * std::pow(sig, 6.0);
        // (pair_modify shift yes for some type pairs)
        const double ratio = sig / cut;
        s.coef[7 * (p * ntp1 + q) + 4] =
            (a + b) % 2 ? 4.0 * eps * (std::pow(ratio, 12.0) - std::pow(ratio, 6.0)) : 0.0;
      }
    }
  for (int t = 0; t < ntp1; t++) s.cutsq.push_back(&s.cutsq_s[t * ntp1]);
  // rows (LAMMPS' per-atom numneigh, firstneigh) of a random subset of the
  // atoms (owned or ghost) in random order, entries any other atom, some
  // with special bits
  std::vector<int> order(nall);
  for (int i = 0; i < nall; i++) order[i] = i;
  std::shuffle(order.begin(), order.end(), g);
  const int nrow = 1 + (int) (U(g) * nall / 2);
  s.rows.resize(nall);
  for (int r = 0; r < nrow; r++) {
    const int i = order[r];
    s.ilist.push_back(i);
    const int len = (int) (U(g) * 40);
    for (int k = 0; k < len; k++) {
      int j = (int) (U(g) * nall);
      if (j == i) continue;
      const int sb = U(g) < 0.2 ? 1 + (int) (U(g) * 3) : 0;
      s.rows[i].push_back((int) ((unsigned) j | ((unsigned) sb << SB)));
    }
  }
  s.numneigh.resize(nall);
  s.firstneigh.resize(nall);
  for (int i = 0; i < nall; i++) {
    s.numneigh[i] = (int) s.rows[i].size();
    s.firstneigh[i] = s.rows[i].data();
  }
  return s;
}

// b = a with b's pointers into its own arrays
void repoint(System &b)
{
  for (int i = 0; i < b.nall; i++) {
    b.x[i] = &b.xs[3 * i];
    b.f[i] = &b.fs[3 * i];
    b.firstneigh[i] = b.rows[i].data();
  }
  for (int t = 0; t <= b.ntypes; t++) b.cutsq[t] = &b.cutsq_s[t * (b.ntypes + 1)];
}

// which kernel: lj_cut_forces() (the dispatcher), or one of its two
enum Kernel { DISPATCH, SCALAR, AVX2 };

// one kernel's forces into b.f; with energy, its tally returned
template <bool EFLAG> double run_kernel(Kernel which, System &b, bool newton)
{
  HardSphere::LJCutTable t;
  t.coef = b.coef.data();
  t.stride = 7;
  t.ntp1 = b.ntypes + 1;
  auto call = [&](auto fn) {
    return fn((int) b.ilist.size(), b.ilist.data(), b.numneigh.data(), b.firstneigh.data(),
              b.xs.data(), b.fs.data(), b.type.data(), b.special, b.nlocal, newton,
              b.cutsq.data(), t);
  };
#ifdef HS_NEAR_AVX2
  if (which == AVX2) return call(HardSphere::lj_cut_forces_avx2<MASK, SB, EFLAG>);
#endif
  if (which == SCALAR) return call(HardSphere::lj_cut_forces_scalar<MASK, SB, EFLAG>);
  return call(HardSphere::lj_cut_forces<MASK, SB, EFLAG>);
}

double kernel(System &b, bool newton, bool energy = false, Kernel which = DISPATCH)
{
  return energy ? run_kernel<true>(which, b, newton) : run_kernel<false>(which, b, newton);
}

// PairLJCut::compute(eflag, 0)'s loop, the list given row by row; returns
// Pair::eng_vdwl as ev_tally() sums it from ev_setup()'s zero (eflag 1)
double reference(System &s, bool newton, bool eflag = false)
{
  volatile double eng_vdwl = 0.0;
  const int ntp1 = s.ntypes + 1;
  for (size_t ii = 0; ii < s.ilist.size(); ii++) {
    const int i = s.ilist[ii];
    const double xtmp = s.x[i][0], ytmp = s.x[i][1], ztmp = s.x[i][2];
    const int itype = s.type[i];
    for (int jj = 0; jj < s.numneigh[i]; jj++) {
      int j = s.firstneigh[i][jj];
      const double factor_lj = s.special[j >> SB & 3];
      j &= MASK;
      volatile double delx = xtmp - s.x[j][0], dely = ytmp - s.x[j][1], delz = ztmp - s.x[j][2];
      volatile double a = delx * delx, b = dely * dely, c = delz * delz;
      volatile double ab = a + b;
      volatile double rsq = ab + c;
      const int jtype = s.type[j];
      if (rsq < s.cutsq[itype][jtype]) {
        const double *cf = &s.coef[7 * (itype * ntp1 + jtype)];
        volatile double r2inv = 1.0 / rsq;
        volatile double r4 = r2inv * r2inv;
        volatile double r6inv = r4 * r2inv;
        volatile double t1 = cf[0] * r6inv;
        volatile double t2 = t1 - cf[1];
        volatile double forcelj = r6inv * t2;
        volatile double t3 = factor_lj * forcelj;
        volatile double fpair = t3 * r2inv;
        s.f[i][0] += delx * fpair;
        s.f[i][1] += dely * fpair;
        s.f[i][2] += delz * fpair;
        if (newton || j < s.nlocal) {
          s.f[j][0] -= delx * fpair;
          s.f[j][1] -= dely * fpair;
          s.f[j][2] -= delz * fpair;
        }
        if (eflag) {
          // evdwl = r6inv*(lj3*r6inv-lj4) - offset; evdwl *= factor_lj
          volatile double e1 = cf[2] * r6inv;
          volatile double e2 = e1 - cf[3];
          volatile double e3 = r6inv * e2;
          volatile double evdwl = e3 - cf[4];
          evdwl = evdwl * factor_lj;
          // Pair::ev_tally()
          if (newton)
            eng_vdwl = eng_vdwl + evdwl;
          else {
            volatile double evdwlhalf = 0.5 * evdwl;
            if (i < s.nlocal) eng_vdwl = eng_vdwl + evdwlhalf;
            if (j < s.nlocal) eng_vdwl = eng_vdwl + evdwlhalf;
          }
        }
      }
    }
  }
  return eng_vdwl;
}

}    // namespace

TEST(LJCut, KernelIsComputeBitForBit)
{
  std::mt19937 g(20261128);
  int compared = 0, within = 0;
  for (int trial = 0; trial < 400; trial++) {
    const bool newton = trial % 2 == 0;
    System a = make(g, 2 + trial % 150, 1 + trial % 3);
    System b = a;
    repoint(b);
    reference(a, newton);
    kernel(b, newton);
    for (int k = 0; k < 3 * a.nall; k++) {
      ASSERT_EQ(0, std::memcmp(&a.fs[k], &b.fs[k], sizeof(double)))
          << "trial " << trial << " atom " << k / 3 << ": " << a.fs[k] << " vs " << b.fs[k];
      compared++;
    }
    for (int i : a.ilist)
      for (int e : a.rows[i]) {
        const int j = e & MASK;
        double d2 = 0.0;
        for (int d = 0; d < 3; d++) d2 += (a.x[i][d] - a.x[j][d]) * (a.x[i][d] - a.x[j][d]);
        within += d2 < a.cutsq[a.type[i]][a.type[j]];
      }
  }
  EXPECT_GT(within, 10000);    // (the test exercised the force branch)
  EXPECT_GT(compared, 10000);
}

// the kernel differs from a loop that sums f[i] in another order: the
// comparison above can fail (the same lists, f[i]'s sum from the last
// entry back)
TEST(LJCut, TheComparisonSeesTheOrderOfSums)
{
  std::mt19937 g(7);
  int differ = 0;
  for (int trial = 0; trial < 50; trial++) {
    System a = make(g, 120, 2);
    System b = a;
    for (auto &r : b.rows) std::reverse(r.begin(), r.end());
    repoint(b);
    reference(a, true);
    kernel(b, true);
    differ += std::memcmp(a.fs.data(), b.fs.data(), sizeof(double) * a.fs.size()) != 0;
  }
  EXPECT_GT(differ, 25);
}

// with the energy tally (compute(1, 0), vci's evaluations): forces and
// energy to the bit, newton on and off, shifted and unshifted type pairs
TEST(LJCut, KernelWithEnergyIsComputeBitForBit)
{
  std::mt19937 g(20261129);
  int energies = 0;
  for (int trial = 0; trial < 400; trial++) {
    const bool newton = trial % 2 == 0;
    System a = make(g, 2 + trial % 150, 1 + trial % 3);
    System b = a;
    repoint(b);
    const double ea = reference(a, newton, true);
    const double eb = kernel(b, newton, true);
    ASSERT_EQ(0, std::memcmp(&ea, &eb, sizeof(double)))
        << "trial " << trial << ": energy " << ea << " vs " << eb;
    energies += ea != 0.0;
    for (int k = 0; k < 3 * a.nall; k++)
      ASSERT_EQ(0, std::memcmp(&a.fs[k], &b.fs[k], sizeof(double)))
          << "trial " << trial << " atom " << k / 3 << ": " << a.fs[k] << " vs " << b.fs[k];
  }
  EXPECT_GT(energies, 300);
  // it can fail: a shift missed by one type pair changes the sum
  System a = make(g, 150, 2), b = a;
  repoint(b);
  for (size_t k = 4; k < b.coef.size(); k += 7) b.coef[k] *= 1.0 + 1e-9;
  const double ea = reference(a, true, true), eb = kernel(b, true, true);
  EXPECT_NE(0, std::memcmp(&ea, &eb, sizeof(double)));
}

// each kernel on its own (the dispatcher above takes one): forces and energy
// to the bit, newton on and off, rows of every length mod 4 (0..39 entries)
TEST(LJCut, ScalarAndAvx2KernelsAreComputeBitForBit)
{
  int kernels = 1;
#ifdef HS_NEAR_AVX2
  if (HardSphere::has_avx2()) kernels = 2;
#endif
  if (kernels == 1) std::printf("(no AVX2 on this processor: the scalar kernel only)\n");
  std::mt19937 g(20261206);
  for (int which = 0; which < kernels; which++)
    for (int trial = 0; trial < 300; trial++) {
      const bool newton = trial % 2 == 0, energy = trial % 3 == 0;
      System a = make(g, 2 + trial % 150, 1 + trial % 3);
      System b = a;
      repoint(b);
      const double ea = reference(a, newton, energy);
      const double eb = kernel(b, newton, energy, which == 0 ? SCALAR : AVX2);
      if (energy)
        ASSERT_EQ(0, std::memcmp(&ea, &eb, sizeof(double)))
            << "kernel " << which << " trial " << trial << ": energy " << ea << " vs " << eb;
      for (int k = 0; k < 3 * a.nall; k++)
        ASSERT_EQ(0, std::memcmp(&a.fs[k], &b.fs[k], sizeof(double)))
            << "kernel " << which << " trial " << trial << " atom " << k / 3 << ": " << a.fs[k]
            << " vs " << b.fs[k];
    }
}

// one term's phi and phi' as PairLJCut::single() computes them (energy and
// fforce, written here one operation at a time, phi' = -fforce r), and its
// phi'', phi''', phi'''' against the closed forms of 4 eps fl [(s/r)^12 -
// (s/r)^6] and against central differences of the next lower derivative;
// both ways the kernels give them: lj_cut_phi01() + lj_derivs(), and
// lj_cut_phi04() in one pass
TEST(LJCut, TermIsSinglesBitsAndItsDerivatives)
{
  std::mt19937 g(20261129);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  for (int trial = 0; trial < 4000; trial++) {
    const bool fused = trial % 4 >= 2;
    auto term = [&](const double *c, double fl, double rsq, double r, double *phi) {
      if (fused) HardSphere::lj_cut_phi04(c, fl, rsq, r, 4, phi);
      else {
        HardSphere::lj_cut_phi01(c, fl, rsq, r, phi);
        HardSphere::lj_derivs(c[5], c[6], fl, rsq, r, 4, phi);
      }
    };
    const double eps = 0.5 + U(g), sig = 0.8 + 0.4 * U(g), cut = 2.0 + U(g);
    const double fl = trial % 3 == 0 ? 1.0 : (trial % 3 == 1 ? 0.5 : 0.125);
    const double ratio = sig / cut;
    const double c[7] = {48.0 * eps * std::pow(sig, 12.0), 24.0 * eps * std::pow(sig, 6.0),
                         4.0 * eps * std::pow(sig, 12.0), 4.0 * eps * std::pow(sig, 6.0),
                         trial % 2 ? 4.0 * eps * (std::pow(ratio, 12.0) - std::pow(ratio, 6.0))
                                   : 0.0,
                         eps, sig};
    const double r = sig * (0.85 + (cut / sig - 0.85) * U(g)), rsq = r * r;
    double phi[5] = {0.0, 0.0, 0.0, 0.0, 0.0};
    term(c, fl, rsq, std::sqrt(rsq), phi);
    // single(): r2inv, r6inv, forcelj, fforce = factor_lj forcelj r2inv,
    // philj = r6inv (lj3 r6inv - lj4) - offset, returns factor_lj philj
    volatile double r2inv = 1.0 / rsq, r4 = r2inv * r2inv, r6inv = r4 * r2inv;
    volatile double t1 = c[0] * r6inv, t2 = t1 - c[1], forcelj = r6inv * t2;
    volatile double t3 = fl * forcelj, fforce = t3 * r2inv;
    volatile double e1 = c[2] * r6inv, e2 = e1 - c[3], e3 = r6inv * e2, philj = e3 - c[4];
    volatile double e0 = fl * philj, rr = std::sqrt(rsq), p1 = -fforce * rr;
    EXPECT_EQ(std::memcmp(&phi[0], (const double *) &e0, sizeof(double)), 0) << trial;
    EXPECT_EQ(std::memcmp(&phi[1], (const double *) &p1, sizeof(double)), 0) << trial;
    // closed forms: phi^(k) = 4 eps fl sum_n a_n (sigma^n) d^k r^-n
    const double s6 = std::pow(sig / r, 6.0), s12 = s6 * s6, k = 4.0 * eps * fl;
    const double exact[5] = {0.0, k * (-12.0 * s12 + 6.0 * s6) / r,
                             k * (156.0 * s12 - 42.0 * s6) / (r * r),
                             k * (-2184.0 * s12 + 336.0 * s6) / (r * r * r),
                             k * (32760.0 * s12 - 3024.0 * s6) / (r * r * r * r)};
    // each order's scale without cancellation: k (|a12| s12 + |a6| s6) / r^q
    const double a12[5] = {1.0, 12.0, 156.0, 2184.0, 32760.0}, a6[5] = {1.0, 6.0, 42.0, 336.0, 3024.0};
    double scale[5];
    for (int q = 0; q <= 4; q++) scale[q] = k * (a12[q] * s12 + a6[q] * s6) / std::pow(r, q);
    for (int q = 1; q <= 4; q++)
      EXPECT_NEAR(phi[q], exact[q], 1e-13 * scale[q]) << "trial " << trial << " order " << q;
    // phi^(q) as the central difference of phi^(q-1) (step h = 1e-4 r: error
    // h^2/6 phi^(q+2), below ~(q+13)(q+14)/6 1e-8 of the scale)
    const double h = 1e-4 * r;
    for (int q = 2; q <= 4; q++) {
      double pp[5] = {0.0, 0.0, 0.0, 0.0, 0.0}, pm[5] = {0.0, 0.0, 0.0, 0.0, 0.0};
      const double rp = r + h, rm = r - h;
      term(c, fl, rp * rp, rp, pp);
      term(c, fl, rm * rm, rm, pm);
      const double fd = (pp[q - 1] - pm[q - 1]) / (2.0 * h);
      EXPECT_NEAR(phi[q], fd, 1e-6 * scale[q])
          << "trial " << trial << " order " << q;
    }
  }
}
