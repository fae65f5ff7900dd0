/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: the forces of pair style lj/cut on a (restricted)
   neighbor list, as PairLJCut::compute(0, 0) computes them, operation for
   operation: the same list order, the same products, quotient and sums
   (rsq = dx*dx + dy*dy + dz*dz; forcelj = r6inv (lj1 r6inv - lj2); fpair =
   factor_lj forcelj r2inv), f[i] += and f[j] -= in the same order, so the
   same bits (no fused multiply-add: the package is built without -mfma).

   Why: the local engine evaluates each cluster's terms ~6 times per step
   through the styles' own compute() on restricted lists (hs_local_forces.h);
   for lj/cut a call costs ~56 instructions per list entry there (the
   two-level coefficient and force-row reads of a general loop). Here f[i]
   is summed in registers (the same additions in the same order: j != i)
   and the coefficients come from one table. HSLocalForces checks the
   kernel against the style's compute() on the first restricted evaluation
   of each run and falls back to compute() for the run if a bit differs.
   Where the processor has AVX2, lj_cut_forces() takes four entries of a
   row at a time (lj_cut_forces_avx2(): the same operations lane by lane,
   the sums still in entry order), without a branch per entry on the
   cutoff test.

   coef: lj1, lj2, lj3, lj4 and offset of type pair (itype, jtype) at
   coef[stride * (itype * ntp1 + jtype)] and the next four doubles (ntp1 =
   ntypes + 1), as HSPotential rebuilds and checks them against
   PairLJCut::single() (force and energy). With the energy tally too
   (EFLAG): the evaluations of a method that needs the flows' energies
   (vci), which otherwise take compute(1, 0). And one term's phi, phi'
   (single()'s arithmetic) and phi'', ... (HSPotential's derivative layer,
   pcva's projection). LAMMPS-free (unit-tested alone:
   unittest/math/test_ljcut.cpp).
------------------------------------------------------------------------- */

#ifndef LMP_HS_LJCUT_H
#define LMP_HS_LJCUT_H

#include "hs_near.h"

#include <cstddef>

namespace HardSphere {

struct LJCutTable {
  // lj1, lj2, lj3, lj4, offset per type pair (above), then the epsilon and
  // sigma they came from; nullptr: none
  const double *coef = nullptr;
  int stride = 0, ntp1 = 0;
  // the coefficients of the type pair (itype, jtype)
  const double *of(int itype, int jtype) const
  {
    return coef + (size_t) stride * (itype * ntp1 + jtype);
  }
};

// one term's phi and phi'(r) = -fforce r, as PairLJCut::single() computes
// energy and fforce (c: lj1..lj4, offset of the type pair; fl: special_lj)
inline void lj_cut_phi01(const double *c, double fl, double rsq, double r, double phi[2])
{
  const double r2inv = 1.0 / rsq;
  const double r6inv = r2inv * r2inv * r2inv;
  const double forcelj = r6inv * (c[0] * r6inv - c[1]);
  const double fforce = fl * forcelj * r2inv;
  const double philj = r6inv * (c[2] * r6inv - c[3]) - c[4];
  phi[0] = fl * philj;
  phi[1] = -fforce * r;
}

// phi^(k)(r), k = 2..order (order <= 4), of fl 4 eps [(sigma/r)^12 -
// (sigma/r)^6]: d^k/dr^k r^-n = (-n)(-n-1)...(-n-k+1) r^-n-k
inline void lj_derivs(double eps, double sig, double fl, double rsq, double r, int order,
                      double phi[5])
{
  const double s2 = sig * sig / rsq, s6 = s2 * s2 * s2;
  const double c12 = 4.0 * eps * fl * s6 * s6, c6 = -4.0 * eps * fl * s6;
  const double rinv = 1.0 / r;
  phi[2] = (156.0 * c12 + 42.0 * c6) * rinv * rinv;
  if (order >= 3) phi[3] = (-2184.0 * c12 - 336.0 * c6) * rinv * rinv * rinv;
  if (order >= 4) phi[4] = (32760.0 * c12 + 3024.0 * c6) * rinv * rinv * rinv * rinv;
}

// phi^(k)(r), k = 0..order (order <= 4), of one lj/cut term in one pass:
// phi and phi' as lj_cut_phi01() (single()'s bits), the higher ones from
// the same 1/r^2 and r^-6 (the compiler shares them with lj_cut_phi01()'s)
// with 1/r = r / r^2: one division a term where lj_cut_phi01() +
// lj_derivs() take three (mcva's cluster flows evaluate ~3000 terms a
// collision)
inline void lj_cut_phi04(const double *c, double fl, double rsq, double r, int order,
                         double phi[5])
{
  lj_cut_phi01(c, fl, rsq, r, phi);
  phi[2] = phi[3] = phi[4] = 0.0;
  if (order < 2) return;
  const double r2inv = 1.0 / rsq;
  const double r6inv = r2inv * r2inv * r2inv;
  // fl 4 eps sigma^12 r^-12 and -fl 4 eps sigma^6 r^-6 (c[2], c[3]: lj3, lj4)
  const double c12 = fl * c[2] * r6inv * r6inv, c6 = -fl * c[3] * r6inv;
  phi[2] = (156.0 * c12 + 42.0 * c6) * r2inv;
  if (order >= 3) phi[3] = (-2184.0 * c12 - 336.0 * c6) * (r2inv * r2inv * r);
  if (order >= 4) phi[4] = (32760.0 * c12 + 3024.0 * c6) * (r2inv * r2inv);
}

// entry jr of a row of atom i (xi: its position; cuti, ci: its rows of
// cutoffs and coefficients): true within the cutoff, with del = xi - xj,
// PairLJCut::compute()'s fpair and with EFLAG its evdwl, operation for
// operation (lj_cut_forces() and lj_cut_row_force() share it)
template <int MASK, int SB, bool EFLAG>
inline bool lj_cut_entry(const double *xi, int jr, const double *x, const int *type,
                         const double *special_lj, const double *cuti, const double *ci,
                         int stride, double del[3], double &fpair, double &evdwl)
{
  const int j = jr & MASK;
  const double *xj = x + 3 * (size_t) j;
  del[0] = xi[0] - xj[0];
  del[1] = xi[1] - xj[1];
  del[2] = xi[2] - xj[2];
  const double rsq = del[0] * del[0] + del[1] * del[1] + del[2] * del[2];
  const int jtype = type[j];
  if (!(rsq < cuti[jtype])) return false;
  const double factor_lj = special_lj[jr >> SB & 3];
  const double *c = ci + (size_t) stride * jtype;
  const double r2inv = 1.0 / rsq;
  const double r6inv = r2inv * r2inv * r2inv;
  const double forcelj = r6inv * (c[0] * r6inv - c[1]);
  fpair = factor_lj * forcelj * r2inv;
  if (EFLAG) {
    evdwl = r6inv * (c[2] * r6inv - c[3]) - c[4];
    evdwl *= factor_lj;
  }
  return true;
}

namespace detail {
  // a pair (i, j) within the cutoff into row i's sums: p = del fpair to
  // f[i]'s register sums fs, subtracted from f[j] if newton_pair or j <
  // nlocal; EFLAG: evdwl to eng as Pair::ev_tally() adds it
  template <bool EFLAG>
  inline void lj_cut_add(int i, int j, const double p[3], double evdwl, double *f, int nlocal,
                         bool newton_pair, double fs[3], double &eng)
  {
    fs[0] += p[0];
    fs[1] += p[1];
    fs[2] += p[2];
    if (newton_pair || j < nlocal) {
      double *fj = f + 3 * (size_t) j;
      fj[0] -= p[0];
      fj[1] -= p[1];
      fj[2] -= p[2];
    }
    if (EFLAG) {
      if (newton_pair)
        eng += evdwl;
      else {
        const double half = 0.5 * evdwl;
        if (i < nlocal) eng += half;
        if (j < nlocal) eng += half;
      }
    }
  }

  // entries jlist[from..jnum) of row i one at a time into its sums fs
  template <int MASK, int SB, bool EFLAG>
  inline void lj_cut_entries(int i, const double xi[3], const int *jlist, int from, int jnum,
                             const double *x, double *f, const int *type,
                             const double *special_lj, int nlocal, bool newton_pair,
                             const double *cuti, const double *ci, int stride, double fs[3],
                             double &eng)
  {
    for (int jj = from; jj < jnum; jj++) {
      const int jr = jlist[jj];
      double del[3], fpair, evdwl = 0.0;
      if (!lj_cut_entry<MASK, SB, EFLAG>(xi, jr, x, type, special_lj, cuti, ci, stride, del,
                                         fpair, evdwl))
        continue;
      const double p[3] = {del[0] * fpair, del[1] * fpair, del[2] * fpair};
      lj_cut_add<EFLAG>(i, jr & MASK, p, evdwl, f, nlocal, newton_pair, fs, eng);
    }
  }
}    // namespace detail

// PairLJCut::compute(0, 0) on the list (inum, ilist, numneigh, firstneigh):
// entries carry the special bits above SB (factor special_lj[j >> SB & 3])
// and the index in MASK (LAMMPS' SBBITS and NEIGHMASK); f[j] -= only if
// newton_pair or j < nlocal. EFLAG: compute(1, 0) instead, whose energy
// tally (Pair::eng_vdwl, from 0) is returned: per pair within the cutoff
// evdwl = factor_lj (r6inv (lj3 r6inv - lj4) - offset), added as
// Pair::ev_tally() adds it (whole with newton_pair, else half for each
// atom below nlocal), in list order; without EFLAG 0. x and f are the
// rows' storage, atom i at 3 i (LAMMPS' per-atom 2d arrays are one block, as
// its OPT styles read them): no load of a row pointer per entry, a random
// read a pointer array's cache line costs on top of the row's
template <int MASK, int SB, bool EFLAG = false>
inline double lj_cut_forces_scalar(int inum, const int *ilist, const int *numneigh,
                                   int *const *firstneigh, const double *x, double *f,
                                   const int *type, const double *special_lj, int nlocal,
                                   bool newton_pair, const double *const *cutsq,
                                   const LJCutTable &t)
{
  double eng = 0.0;
  for (int ii = 0; ii < inum; ii++) {
    const int i = ilist[ii];
    // (i's position by value: the stores to f[j] could alias x)
    const double xi[3] = {x[3 * (size_t) i], x[3 * (size_t) i + 1], x[3 * (size_t) i + 2]};
    double *fi = f + 3 * (size_t) i;
    const int itype = type[i];
    double fs[3] = {fi[0], fi[1], fi[2]};
    detail::lj_cut_entries<MASK, SB, EFLAG>(
        i, xi, firstneigh[i], 0, numneigh[i], x, f, type, special_lj, nlocal, newton_pair,
        cutsq[itype], t.coef + (size_t) t.stride * itype * t.ntp1, t.stride, fs, eng);
    fi[0] = fs[0];
    fi[1] = fs[1];
    fi[2] = fs[2];
  }
  return eng;
}

#ifdef HS_NEAR_AVX2
// lj_cut_forces_scalar() four entries of a row at a time: their separations,
// squared distances, cutoff tests, fpair (and evdwl) in the four lanes, each
// lane the scalar operations in their order (no FMA), then each entry within
// its cutoff added to f[i]'s register sums and subtracted from f[j] in entry
// order: the same bits. No branch per entry on the cutoff test (~30 % of a
// row's entries lie beyond it, at random: the scalar loop's mispredictions)
template <int MASK, int SB, bool EFLAG = false>
__attribute__((target("avx2"))) inline double
lj_cut_forces_avx2(int inum, const int *ilist, const int *numneigh, int *const *firstneigh,
                   const double *x, double *f, const int *type, const double *special_lj,
                   int nlocal, bool newton_pair, const double *const *cutsq, const LJCutTable &t)
{
  double eng = 0.0;
  const __m256d one = _mm256_set1_pd(1.0);
  alignas(32) double px[4], py[4], pz[4], pe[4];
  for (int ii = 0; ii < inum; ii++) {
    const int i = ilist[ii];
    const double xi[3] = {x[3 * (size_t) i], x[3 * (size_t) i + 1], x[3 * (size_t) i + 2]};
    double *fi = f + 3 * (size_t) i;
    const int itype = type[i];
    const int *jlist = firstneigh[i];
    const int jnum = numneigh[i];
    const double *cuti = cutsq[itype];
    const double *ci = t.coef + (size_t) t.stride * itype * t.ntp1;
    const __m256d vx = _mm256_set1_pd(xi[0]), vy = _mm256_set1_pd(xi[1]),
                  vz = _mm256_set1_pd(xi[2]);
    double fs[3] = {fi[0], fi[1], fi[2]};
    int jj = 0;
    for (; jj + 4 <= jnum; jj += 4) {
      int jr[4], j[4];
      const double *c[4];
      double cut[4], fl[4];
      for (int l = 0; l < 4; l++) {
        jr[l] = jlist[jj + l];
        j[l] = jr[l] & MASK;
        const int jt = type[j[l]];
        cut[l] = cuti[jt];
        fl[l] = special_lj[jr[l] >> SB & 3];
        c[l] = ci + (size_t) t.stride * jt;
      }
      __m256d X, Y, Z;
      detail::rows4(x + 3 * (size_t) j[0], x + 3 * (size_t) j[1], x + 3 * (size_t) j[2],
                    x + 3 * (size_t) j[3], X, Y, Z);
      const __m256d dx = _mm256_sub_pd(vx, X), dy = _mm256_sub_pd(vy, Y),
                    dz = _mm256_sub_pd(vz, Z);
      const __m256d rsq = _mm256_add_pd(
          _mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)), _mm256_mul_pd(dz, dz));
      const int in = _mm256_movemask_pd(_mm256_cmp_pd(rsq, _mm256_loadu_pd(cut), _CMP_LT_OQ));
      if (!in) continue;
      const __m256d flv = _mm256_loadu_pd(fl);
      const __m256d c0 = _mm256_setr_pd(c[0][0], c[1][0], c[2][0], c[3][0]);
      const __m256d c1 = _mm256_setr_pd(c[0][1], c[1][1], c[2][1], c[3][1]);
      const __m256d r2inv = _mm256_div_pd(one, rsq);
      const __m256d r6inv = _mm256_mul_pd(_mm256_mul_pd(r2inv, r2inv), r2inv);
      const __m256d forcelj = _mm256_mul_pd(r6inv, _mm256_sub_pd(_mm256_mul_pd(c0, r6inv), c1));
      const __m256d fpair = _mm256_mul_pd(_mm256_mul_pd(flv, forcelj), r2inv);
      _mm256_store_pd(px, _mm256_mul_pd(dx, fpair));
      _mm256_store_pd(py, _mm256_mul_pd(dy, fpair));
      _mm256_store_pd(pz, _mm256_mul_pd(dz, fpair));
      if (EFLAG) {
        const __m256d c2 = _mm256_setr_pd(c[0][2], c[1][2], c[2][2], c[3][2]);
        const __m256d c3 = _mm256_setr_pd(c[0][3], c[1][3], c[2][3], c[3][3]);
        const __m256d c4 = _mm256_setr_pd(c[0][4], c[1][4], c[2][4], c[3][4]);
        const __m256d ev =
            _mm256_sub_pd(_mm256_mul_pd(r6inv, _mm256_sub_pd(_mm256_mul_pd(c2, r6inv), c3)), c4);
        _mm256_store_pd(pe, _mm256_mul_pd(ev, flv));
      }
      for (int l = 0; l < 4; l++) {
        if (!(in >> l & 1)) continue;
        const double p[3] = {px[l], py[l], pz[l]};
        detail::lj_cut_add<EFLAG>(i, j[l], p, EFLAG ? pe[l] : 0.0, f, nlocal, newton_pair, fs,
                                  eng);
      }
    }
    // (the row's last entries one by one)
    detail::lj_cut_entries<MASK, SB, EFLAG>(i, xi, jlist, jj, jnum, x, f, type, special_lj,
                                            nlocal, newton_pair, cuti, ci, t.stride, fs, eng);
    fi[0] = fs[0];
    fi[1] = fs[1];
    fi[2] = fs[2];
  }
  return eng;
}
#endif

// lj_cut_forces_avx2() where the processor has AVX2, else the scalar loop
template <int MASK, int SB, bool EFLAG = false>
inline double lj_cut_forces(int inum, const int *ilist, const int *numneigh,
                            int *const *firstneigh, const double *x, double *f,
                            const int *type, const double *special_lj, int nlocal,
                            bool newton_pair, const double *const *cutsq, const LJCutTable &t)
{
#ifdef HS_NEAR_AVX2
  if (has_avx2())
    return lj_cut_forces_avx2<MASK, SB, EFLAG>(inum, ilist, numneigh, firstneigh, x, f, type,
                                               special_lj, nlocal, newton_pair, cutsq, t);
#endif
  return lj_cut_forces_scalar<MASK, SB, EFLAG>(inum, ilist, numneigh, firstneigh, x, f, type,
                                               special_lj, nlocal, newton_pair, cutsq, t);
}

// the force on atom i (position xi, type itype) of the terms with the n
// entries ent[0..n) of its row (raw, as lj_cut_forces() reads them), summed
// from zero in entry order: the row of i that lj_cut_forces() leaves from a
// zeroed force when no other row's entry is i. EFLAG: their energy added to
// eng in the same order, as lj_cut_forces() tallies it with newton_pair on
template <int MASK, int SB, bool EFLAG = false>
inline void lj_cut_row_force(const double xi[3], int itype, const int *ent, int n, const double *x,
                             const int *type, const double *special_lj,
                             const double *const *cutsq, const LJCutTable &t, double out[3],
                             double &eng)
{
  const double *cuti = cutsq[itype];
  const double *ci = t.coef + (size_t) t.stride * itype * t.ntp1;
  double fx = 0.0, fy = 0.0, fz = 0.0;
  for (int k = 0; k < n; k++) {
    double del[3], fpair, evdwl;
    if (!lj_cut_entry<MASK, SB, EFLAG>(xi, ent[k], x, type, special_lj, cuti, ci, t.stride, del,
                                       fpair, evdwl))
      continue;
    fx += del[0] * fpair;
    fy += del[1] * fpair;
    fz += del[2] * fpair;
    if (EFLAG) eng += evdwl;
  }
  out[0] = fx;
  out[1] = fy;
  out[2] = fz;
}

}    // namespace HardSphere

#endif
