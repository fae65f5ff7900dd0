/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: a cluster member's static terms four at a time
   (hs_cluster_gauss.h, forces(): mcva's local Gauss flow evaluates a
   member's ~40 terms with static atoms ~20 times a collision).

   static_geometry(): each term's separation x = q - xb, r = |x|, 1/r and
   e = x / r; lj_phi(): phi^(k)(r), k = 0..order, of lj/cut terms, as
   lj_cut_phi04() (hs_ljcut.h) computes them. Per term these are a square
   root and two divisions, which one at a time held the scalar loop to the
   divider's latency (a third of forces()' samples on the 4000 fluid).

   The *_scalar() functions are the reference; the *_avx2() ones do four
   terms per instruction with the same operations in the same order (no
   fused multiply-add: the package is built without -mfma), so that every
   lane gives the scalar result's bits; the sums over terms
   (static_field_terms(), static_force_sums()) add each sum's terms in term
   order, four sums to a register after a 4 x 4 transpose. The dispatchers
   pick one at run time (hs_near.h's has_avx2()). Arrays are
   structure-of-arrays (bx, by, bz: the static atoms' coordinates; ir, ex,
   ey, ez: the outputs; p: five rows of n, p + k n holding phi^(k)).

   LAMMPS-free (unit-tested alone: unittest/math/test_lj_terms.cpp).
------------------------------------------------------------------------- */

#ifndef LMP_HS_LJ_TERMS_H
#define LMP_HS_LJ_TERMS_H

#include "hs_ljcut.h"
#include "hs_near.h"

#include <cmath>

#ifdef HS_NEAR_AVX2    // (hs_near.h's intrinsics and has_avx2())
#define HS_LJ_TERMS_AVX2 1
#endif

namespace HardSphere {

// x = q - (bx, by, bz)[t], r = sqrt(x0 x0 + x1 x1 + x2 x2), ir = 1 / r,
// e = x ir (forces()' arithmetic); r into r[t]
inline void static_geometry_scalar(const double *q, int n, const double *bx, const double *by,
                                   const double *bz, double *r, double *ir, double *ex,
                                   double *ey, double *ez)
{
  for (int t = 0; t < n; t++) {
    const double x0 = q[0] - bx[t], x1 = q[1] - by[t], x2 = q[2] - bz[t];
    const double rr = std::sqrt(x0 * x0 + x1 * x1 + x2 * x2);
    const double i = 1.0 / rr;
    r[t] = rr;
    ir[t] = i;
    ex[t] = x0 * i;
    ey[t] = x1 * i;
    ez[t] = x2 * i;
  }
}

// phi^(k)(r[t]) for k <= order (order 2..4; higher k: 0) of the lj/cut term
// with coefficients c[t] (lj1..lj4, offset) and special factor fl[t], as
// lj_cut_phi04(c[t], fl[t], r r, r, order, .)
// (rows of length stride: the AVX2 versions' last terms go into their rows)
namespace detail {
  inline void lj_phi_rows(const double *r, int n, const double *const *c, const double *fl,
                          int order, double *p, int stride)
  {
    for (int t = 0; t < n; t++) {
      double d[5];
      lj_cut_phi04(c[t], fl[t], r[t] * r[t], r[t], order, d);
      for (int k = 0; k < 5; k++) p[k * stride + t] = d[k];
    }
  }
}    // namespace detail

inline void lj_phi_scalar(const double *r, int n, const double *const *c, const double *fl,
                          int order, double *p)
{
  detail::lj_phi_rows(r, n, c, fl, order, p, n);
}

// a member's static field (ClusterGauss::static_field()'s arithmetic, any
// radial term) from phi', phi'', phi''' (p1, p2, p3), 1/r and e by column,
// the member's w and a_rel (w, ar), ww = |w|^2 and H~'s c: the sums over its
// n terms, each added in term order to sums[] (the field takes only these:
// sum A s e, sum B, sum ce e, sum cAs2, sum A sa e, at the indices below;
// index 11 is padding), and, if partner is not null, each term's force on
// its partner ke e + kw w + ka ar into three rows of n by component (ke =
// phi' + c (ce + A sa), kw = c cAs2, ka = c B)
enum StaticFieldSum : int {
  SF_AS_E = 0,
  SF_B = 3,
  SF_CE_E = 4,
  SF_CAS2 = 7,
  SF_ASA_E = 8,
  STATIC_FIELD_SUMS = 12
};
namespace detail {
  inline void static_field_rows(int n, const double *p1, const double *p2, const double *p3,
                                const double *ir, const double *ex, const double *ey,
                                const double *ez, const double *w, const double *ar, double ww,
                                double c, double *sums, double *partner, int stride)
  {
    const int m = stride;
    for (int t = 0; t < n; t++) {
      const double B = p1[t] * ir[t], A = p2[t] - B;
      const double Bp = A * ir[t], Ap = p3[t] - Bp;
      const double s = ex[t] * w[0] + ey[t] * w[1] + ez[t] * w[2];
      const double sa = ex[t] * ar[0] + ey[t] * ar[1] + ez[t] * ar[2];
      const double cAs2 = 2.0 * A * s * ir[t];
      const double ce = Ap * s * s + Bp * ww - cAs2 * s;
      const double As = A * s, Asa = A * sa;
      const double e[3] = {ex[t], ey[t], ez[t]};
      for (int d = 0; d < 3; d++) {
        sums[SF_AS_E + d] += As * e[d];
        sums[SF_CE_E + d] += ce * e[d];
        sums[SF_ASA_E + d] += Asa * e[d];
      }
      sums[SF_B] += B;
      sums[SF_CAS2] += cAs2;
      if (partner) {
        const double ke = p1[t] + c * (ce + Asa), kw = c * cAs2, ka = c * B;
        for (int d = 0; d < 3; d++) partner[d * m + t] = ke * e[d] + kw * w[d] + ka * ar[d];
      }
    }
  }
}    // namespace detail

inline void static_field_terms_scalar(int n, const double *p1, const double *p2,
                                      const double *p3, const double *ir, const double *ex,
                                      const double *ey, const double *ez, const double *w,
                                      const double *ar, double ww, double c, double *sums,
                                      double *partner)
{
  detail::static_field_rows(n, p1, p2, p3, ir, ex, ey, ez, w, ar, ww, c, sums, partner, n);
}

#ifdef HS_LJ_TERMS_AVX2
namespace detail {
  // acc += the columns of the 4 x 4 block (r0 r1 r2 r3) one after another:
  // lane k adds rk[0], rk[1], rk[2], rk[3] in that order, each lane's sum in
  // term order as the scalar loop adds it (a transpose, no reordering)
  __attribute__((target("avx2"))) inline __m256d add_columns(__m256d acc, __m256d r0,
                                                             __m256d r1, __m256d r2, __m256d r3)
  {
    const __m256d t0 = _mm256_unpacklo_pd(r0, r1), t1 = _mm256_unpackhi_pd(r0, r1);
    const __m256d t2 = _mm256_unpacklo_pd(r2, r3), t3 = _mm256_unpackhi_pd(r2, r3);
    acc = _mm256_add_pd(acc, _mm256_permute2f128_pd(t0, t2, 0x20));
    acc = _mm256_add_pd(acc, _mm256_permute2f128_pd(t1, t3, 0x20));
    acc = _mm256_add_pd(acc, _mm256_permute2f128_pd(t0, t2, 0x31));
    return _mm256_add_pd(acc, _mm256_permute2f128_pd(t1, t3, 0x31));
  }
}    // namespace detail

__attribute__((target("avx2"))) inline void static_field_terms_avx2(
    int n, const double *p1, const double *p2, const double *p3, const double *ir,
    const double *ex, const double *ey, const double *ez, const double *w, const double *ar,
    double ww, double c, double *sums, double *partner)
{
  const __m256d w0 = _mm256_set1_pd(w[0]), w1 = _mm256_set1_pd(w[1]), w2 = _mm256_set1_pd(w[2]);
  const __m256d a0 = _mm256_set1_pd(ar[0]), a1 = _mm256_set1_pd(ar[1]),
                a2 = _mm256_set1_pd(ar[2]);
  const __m256d vww = _mm256_set1_pd(ww), vc = _mm256_set1_pd(c), two = _mm256_set1_pd(2.0);
  const __m256d zero = _mm256_setzero_pd();
  // the sums four to a register, in the order of the StaticFieldSum indices
  __m256d s0 = _mm256_loadu_pd(sums), s1 = _mm256_loadu_pd(sums + 4),
          s2 = _mm256_loadu_pd(sums + 8);
  int t = 0;
  for (; t + 4 <= n; t += 4) {
    const __m256d i = _mm256_loadu_pd(ir + t), P1 = _mm256_loadu_pd(p1 + t);
    const __m256d X = _mm256_loadu_pd(ex + t), Y = _mm256_loadu_pd(ey + t),
                  Z = _mm256_loadu_pd(ez + t);
    const __m256d B = _mm256_mul_pd(P1, i), A = _mm256_sub_pd(_mm256_loadu_pd(p2 + t), B);
    const __m256d Bp = _mm256_mul_pd(A, i), Ap = _mm256_sub_pd(_mm256_loadu_pd(p3 + t), Bp);
    const __m256d s = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(X, w0), _mm256_mul_pd(Y, w1)),
                                    _mm256_mul_pd(Z, w2));
    const __m256d sa = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(X, a0), _mm256_mul_pd(Y, a1)),
                                     _mm256_mul_pd(Z, a2));
    const __m256d cAs2 = _mm256_mul_pd(_mm256_mul_pd(_mm256_mul_pd(two, A), s), i);
    const __m256d ce = _mm256_sub_pd(
        _mm256_add_pd(_mm256_mul_pd(_mm256_mul_pd(Ap, s), s), _mm256_mul_pd(Bp, vww)),
        _mm256_mul_pd(cAs2, s));
    const __m256d Asa = _mm256_mul_pd(A, sa), As = _mm256_mul_pd(A, s);
    s0 = detail::add_columns(s0, _mm256_mul_pd(As, X), _mm256_mul_pd(As, Y),
                             _mm256_mul_pd(As, Z), B);
    s1 = detail::add_columns(s1, _mm256_mul_pd(ce, X), _mm256_mul_pd(ce, Y),
                             _mm256_mul_pd(ce, Z), cAs2);
    s2 = detail::add_columns(s2, _mm256_mul_pd(Asa, X), _mm256_mul_pd(Asa, Y),
                             _mm256_mul_pd(Asa, Z), zero);
    if (partner) {
      const __m256d ke = _mm256_add_pd(P1, _mm256_mul_pd(vc, _mm256_add_pd(ce, Asa)));
      const __m256d kw = _mm256_mul_pd(vc, cAs2), ka = _mm256_mul_pd(vc, B);
      const __m256d E[3] = {X, Y, Z}, W[3] = {w0, w1, w2}, AR[3] = {a0, a1, a2};
      for (int d = 0; d < 3; d++)
        _mm256_storeu_pd(partner + d * n + t,
                         _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(ke, E[d]),
                                                     _mm256_mul_pd(kw, W[d])),
                                       _mm256_mul_pd(ka, AR[d])));
    }
  }
  _mm256_storeu_pd(sums, s0);
  _mm256_storeu_pd(sums + 4, s1);
  _mm256_storeu_pd(sums + 8, s2);
  // (the rest one by one, continuing the sums; partner rows of n)
  detail::static_field_rows(n - t, p1 + t, p2 + t, p3 + t, ir + t, ex + t, ey + t, ez + t, w, ar,
                            ww, c, sums, partner ? partner + t : nullptr, n);
}

__attribute__((target("avx2"))) inline void static_geometry_avx2(const double *q, int n,
                                                                 const double *bx,
                                                                 const double *by,
                                                                 const double *bz, double *r,
                                                                 double *ir, double *ex,
                                                                 double *ey, double *ez)
{
  const __m256d qx = _mm256_set1_pd(q[0]), qy = _mm256_set1_pd(q[1]), qz = _mm256_set1_pd(q[2]);
  const __m256d one = _mm256_set1_pd(1.0);
  int t = 0;
  for (; t + 4 <= n; t += 4) {
    const __m256d x0 = _mm256_sub_pd(qx, _mm256_loadu_pd(bx + t));
    const __m256d x1 = _mm256_sub_pd(qy, _mm256_loadu_pd(by + t));
    const __m256d x2 = _mm256_sub_pd(qz, _mm256_loadu_pd(bz + t));
    const __m256d r2 = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(x0, x0), _mm256_mul_pd(x1, x1)),
                                     _mm256_mul_pd(x2, x2));
    const __m256d rr = _mm256_sqrt_pd(r2);
    const __m256d i = _mm256_div_pd(one, rr);
    _mm256_storeu_pd(r + t, rr);
    _mm256_storeu_pd(ir + t, i);
    _mm256_storeu_pd(ex + t, _mm256_mul_pd(x0, i));
    _mm256_storeu_pd(ey + t, _mm256_mul_pd(x1, i));
    _mm256_storeu_pd(ez + t, _mm256_mul_pd(x2, i));
  }
  static_geometry_scalar(q, n - t, bx + t, by + t, bz + t, r + t, ir + t, ex + t, ey + t, ez + t);
}

__attribute__((target("avx2"))) inline void lj_phi_avx2(const double *r, int n,
                                                        const double *const *c, const double *fl,
                                                        int order, double *p)
{
  const __m256d one = _mm256_set1_pd(1.0), zero = _mm256_setzero_pd();
  const __m256d k156 = _mm256_set1_pd(156.0), k42 = _mm256_set1_pd(42.0);
  const __m256d k2184 = _mm256_set1_pd(-2184.0), k336 = _mm256_set1_pd(336.0);
  const __m256d k32760 = _mm256_set1_pd(32760.0), k3024 = _mm256_set1_pd(3024.0);
  const __m256d sign = _mm256_set1_pd(-0.0);
  int t = 0;
  for (; t + 4 <= n; t += 4) {
    const double *c0 = c[t], *c1 = c[t + 1], *c2 = c[t + 2], *c3 = c[t + 3];
    const __m256d l1 = _mm256_setr_pd(c0[0], c1[0], c2[0], c3[0]);
    const __m256d l2 = _mm256_setr_pd(c0[1], c1[1], c2[1], c3[1]);
    const __m256d l3 = _mm256_setr_pd(c0[2], c1[2], c2[2], c3[2]);
    const __m256d l4 = _mm256_setr_pd(c0[3], c1[3], c2[3], c3[3]);
    const __m256d off = _mm256_setr_pd(c0[4], c1[4], c2[4], c3[4]);
    const __m256d f = _mm256_loadu_pd(fl + t);
    const __m256d rr = _mm256_loadu_pd(r + t);
    // lj_cut_phi01(): r2inv = 1 / rsq, r6inv = r2inv r2inv r2inv,
    // forcelj = r6inv (lj1 r6inv - lj2), fforce = fl forcelj r2inv,
    // phi = fl (r6inv (lj3 r6inv - lj4) - offset), phi' = -fforce r
    const __m256d rsq = _mm256_mul_pd(rr, rr);
    const __m256d r2inv = _mm256_div_pd(one, rsq);
    const __m256d r6inv = _mm256_mul_pd(_mm256_mul_pd(r2inv, r2inv), r2inv);
    const __m256d forcelj = _mm256_mul_pd(r6inv, _mm256_sub_pd(_mm256_mul_pd(l1, r6inv), l2));
    const __m256d fforce = _mm256_mul_pd(_mm256_mul_pd(f, forcelj), r2inv);
    const __m256d philj =
        _mm256_sub_pd(_mm256_mul_pd(r6inv, _mm256_sub_pd(_mm256_mul_pd(l3, r6inv), l4)), off);
    _mm256_storeu_pd(p + t, _mm256_mul_pd(f, philj));
    _mm256_storeu_pd(p + n + t, _mm256_mul_pd(_mm256_xor_pd(fforce, sign), rr));
    __m256d d2 = zero, d3 = zero, d4 = zero;
    if (order >= 2) {
      // c12 = fl lj3 r6inv r6inv, c6 = -fl lj4 r6inv
      const __m256d c12 = _mm256_mul_pd(_mm256_mul_pd(_mm256_mul_pd(f, l3), r6inv), r6inv);
      const __m256d c6 = _mm256_mul_pd(_mm256_mul_pd(_mm256_xor_pd(f, sign), l4), r6inv);
      d2 = _mm256_mul_pd(_mm256_add_pd(_mm256_mul_pd(k156, c12), _mm256_mul_pd(k42, c6)), r2inv);
      const __m256d r4inv = _mm256_mul_pd(r2inv, r2inv);
      if (order >= 3)
        d3 = _mm256_mul_pd(_mm256_sub_pd(_mm256_mul_pd(k2184, c12), _mm256_mul_pd(k336, c6)),
                           _mm256_mul_pd(r4inv, rr));
      if (order >= 4)
        d4 = _mm256_mul_pd(_mm256_add_pd(_mm256_mul_pd(k32760, c12), _mm256_mul_pd(k3024, c6)),
                           r4inv);
    }
    _mm256_storeu_pd(p + 2 * n + t, d2);
    _mm256_storeu_pd(p + 3 * n + t, d3);
    _mm256_storeu_pd(p + 4 * n + t, d4);
  }
  // (the rest one by one, into the same rows of n)
  detail::lj_phi_rows(r + t, n - t, c + t, fl + t, order, p + t, n);
}
#endif

// the AVX2 versions where the processor has AVX2, else the scalar ones
inline void static_geometry(const double *q, int n, const double *bx, const double *by,
                            const double *bz, double *r, double *ir, double *ex, double *ey,
                            double *ez)
{
#ifdef HS_LJ_TERMS_AVX2
  if (has_avx2()) return static_geometry_avx2(q, n, bx, by, bz, r, ir, ex, ey, ez);
#endif
  static_geometry_scalar(q, n, bx, by, bz, r, ir, ex, ey, ez);
}

inline void static_field_terms(int n, const double *p1, const double *p2, const double *p3,
                               const double *ir, const double *ex, const double *ey,
                               const double *ez, const double *w, const double *ar, double ww,
                               double c, double *sums, double *partner)
{
#ifdef HS_LJ_TERMS_AVX2
  if (has_avx2())
    return static_field_terms_avx2(n, p1, p2, p3, ir, ex, ey, ez, w, ar, ww, c, sums, partner);
#endif
  static_field_terms_scalar(n, p1, p2, p3, ir, ex, ey, ez, w, ar, ww, c, sums, partner);
}

inline void lj_phi(const double *r, int n, const double *const *c, const double *fl, int order,
                   double *p)
{
#ifdef HS_LJ_TERMS_AVX2
  if (has_avx2()) return lj_phi_avx2(r, n, c, fl, order, p);
#endif
  lj_phi_scalar(r, n, c, fl, order, p);
}

// a member's static terms' energy and force (ClusterGauss::static_terms()
// without the Jacobian) from phi, phi' (p0, p1) and e by column, each
// continued in term order from its value in acc: acc[0] += phi, acc[1 + d]
// -= phi' e_d
inline void static_force_sums_scalar(int n, const double *p0, const double *p1,
                                     const double *ex, const double *ey, const double *ez,
                                     double *acc)
{
  for (int t = 0; t < n; t++) {
    acc[0] += p0[t];
    acc[1] -= p1[t] * ex[t];
    acc[2] -= p1[t] * ey[t];
    acc[3] -= p1[t] * ez[t];
  }
}

#ifdef HS_LJ_TERMS_AVX2
__attribute__((target("avx2"))) inline void static_force_sums_avx2(int n, const double *p0,
                                                                   const double *p1,
                                                                   const double *ex,
                                                                   const double *ey,
                                                                   const double *ez,
                                                                   double *acc)
{
  // acc[1 + d] - phi' e_d as acc[1 + d] + (-phi' e_d) (the same bits: x - y
  // is x + (-y)), so that all four lanes add their columns in term order
  const __m256d sign = _mm256_set1_pd(-0.0);
  __m256d a = _mm256_loadu_pd(acc);
  int t = 0;
  for (; t + 4 <= n; t += 4) {
    const __m256d P1 = _mm256_loadu_pd(p1 + t);
    a = detail::add_columns(a, _mm256_loadu_pd(p0 + t),
                            _mm256_xor_pd(_mm256_mul_pd(P1, _mm256_loadu_pd(ex + t)), sign),
                            _mm256_xor_pd(_mm256_mul_pd(P1, _mm256_loadu_pd(ey + t)), sign),
                            _mm256_xor_pd(_mm256_mul_pd(P1, _mm256_loadu_pd(ez + t)), sign));
  }
  _mm256_storeu_pd(acc, a);
  static_force_sums_scalar(n - t, p0 + t, p1 + t, ex + t, ey + t, ez + t, acc);
}
#endif

inline void static_force_sums(int n, const double *p0, const double *p1, const double *ex,
                              const double *ey, const double *ez, double *acc)
{
#ifdef HS_LJ_TERMS_AVX2
  if (has_avx2()) return static_force_sums_avx2(n, p0, p1, ex, ey, ez, acc);
#endif
  static_force_sums_scalar(n, p0, p1, ex, ey, ez, acc);
}

}    // namespace HardSphere

#endif
