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
inline double lj_cut_forces(int inum, const int *ilist, const int *numneigh,
                            int *const *firstneigh, const double *x, double *f,
                            const int *type, const double *special_lj, int nlocal,
                            bool newton_pair, const double *const *cutsq, const LJCutTable &t)
{
  double eng = 0.0;
  for (int ii = 0; ii < inum; ii++) {
    const int i = ilist[ii];
    const double *xi = x + 3 * (size_t) i;
    double *fi = f + 3 * (size_t) i;
    const double xtmp = xi[0], ytmp = xi[1], ztmp = xi[2];
    const int itype = type[i];
    const int *jlist = firstneigh[i];
    const int jnum = numneigh[i];
    const double *cuti = cutsq[itype];
    const double *ci = t.coef + (size_t) t.stride * itype * t.ntp1;
    double fx = fi[0], fy = fi[1], fz = fi[2];
    for (int jj = 0; jj < jnum; jj++) {
      const int jr = jlist[jj];
      const int j = jr & MASK;
      const double *xj = x + 3 * (size_t) j;
      const double delx = xtmp - xj[0], dely = ytmp - xj[1], delz = ztmp - xj[2];
      const double rsq = delx * delx + dely * dely + delz * delz;
      const int jtype = type[j];
      if (rsq < cuti[jtype]) {
        const double factor_lj = special_lj[jr >> SB & 3];
        const double *c = ci + (size_t) t.stride * jtype;
        const double r2inv = 1.0 / rsq;
        const double r6inv = r2inv * r2inv * r2inv;
        const double forcelj = r6inv * (c[0] * r6inv - c[1]);
        const double fpair = factor_lj * forcelj * r2inv;
        fx += delx * fpair;
        fy += dely * fpair;
        fz += delz * fpair;
        if (newton_pair || j < nlocal) {
          double *fj = f + 3 * (size_t) j;
          fj[0] -= delx * fpair;
          fj[1] -= dely * fpair;
          fj[2] -= delz * fpair;
        }
        if (EFLAG) {
          double evdwl = r6inv * (c[2] * r6inv - c[3]) - c[4];
          evdwl *= factor_lj;
          if (newton_pair)
            eng += evdwl;
          else {
            const double half = 0.5 * evdwl;
            if (i < nlocal) eng += half;
            if (j < nlocal) eng += half;
          }
        }
      }
    }
    fi[0] = fx;
    fi[1] = fy;
    fi[2] = fz;
  }
  return eng;
}

}    // namespace HardSphere

#endif
