/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: the closing kick of a collision-free step and the
   next step's screen, fast path (HSSystem::kick_and_screen(), every step:
   most of what a collision-free step costs beyond fix nve's, issue 22).

   Per sphere i in the group: v_i += dtf / m_i f_i (fix nve's kick), then
   the screen's test without a square root (HSSystem::screen_atom()):
     s3 = 3 (|x_i - xref_i|^2 + t2 |v_i|^2 + h4 im_i^2 |f_i|^2)
     cleared if s3 <= g^2, g = min(gap_i, skin / 2), and, when the caller
     lists near spheres, also with the smaller gap gm = gap_i - margin:
     gm > 0 and s3 (1 + 1e-12) <= gm^2.
   kick_clear() kicks every sphere of the group (unless told not to: the
   screen alone, HSSystem::screen()) and lists the ones it does
   not clear (ascending) with their three squared terms; the caller's full
   test goes on from those. kick_clear_avx2() does four spheres at a time (rows
   loaded by hs_near.h's detail::rows4()) and gives the same
   velocities and marks bit for bit: the same products and sums in the same
   order (no fused multiply-add), the same division for dtf / m, the same
   comparisons. kick_clear_scalar() is the reference; kick_clear() picks one
   at run time. Per-type masses only (the caller's rmass case stays scalar).

   LAMMPS-free (unit-tested alone: unittest/math/test_screen.cpp).
------------------------------------------------------------------------- */

#ifndef LMP_HS_SCREEN_H
#define LMP_HS_SCREEN_H

#include "hs_near.h"

#include <cstddef>
#include <vector>

#ifdef HS_NEAR_AVX2    // (hs_near.h's row loader)
#define HS_SCREEN_AVX2 1
#endif

namespace HardSphere {

struct KickScreen {
  // rows of 3 doubles, contiguous (row i at p + 3 i)
  double *v = nullptr;
  double *active = nullptr;    // per sphere: set to 0 (the caller's full test sets it)
  const double *f = nullptr, *x = nullptr, *xref = nullptr;
  const double *gap = nullptr;
  const int *type = nullptr, *mask = nullptr;
  const double *mass = nullptr;    // per type
  const double *im = nullptr;      // per type: ftm2v / mass
  int groupbit = 0;
  double dtf = 0.0, t2 = 0.0, h4 = 0.0, half_skin = 0.0;
  bool list = false;
  double margin = 0.0;
  bool kick = true;    // false: the screen alone (velocities as they are)
};

// a sphere the fast path did not clear, with its three squared terms (the
// caller's full test goes on from them: no second pass over its rows)
struct Unscreened {
  int i;
  double d2, v2, a2;
};

// the screen's test from a sphere's three squared terms, without a square
// root ((a+b+c)^2 <= 3(a^2+b^2+c^2)): CLEARED; CLEARED_NEAR (cleared with
// its gap, not with the smaller gap - margin: only when listing); OPEN (the
// full test decides). The one statement of it: HSSystem::screen_terms()
// and both kernels below
enum { CLEARED = 0, CLEARED_NEAR = 1, OPEN = 2 };
inline int screen_fast_test(double d2, double v2, double a2, double gap, double half_skin,
                            bool list, double margin)
{
  // (LAMMPS' MIN(gap, skin / 2))
  const double g = gap < half_skin ? gap : half_skin;
  const double s3 = 3.0 * (d2 + v2 + a2);
  if (!(s3 <= g * g)) return OPEN;
  if (!list) return CLEARED;
  // (a relative 1e-12 more than the round-off between this a^2 and one
  // from HSSystem::acc_of())
  const double gm = gap - margin;
  return (gm > 0.0 && s3 * (1.0 + 1.0e-12) <= gm * gm) ? CLEARED : CLEARED_NEAR;
}

// the test of one sphere whose velocity is kicked already: true if cleared;
// u gets its terms
inline bool screen_cleared(const KickScreen &k, int i, Unscreened &u)
{
  const double *xi = k.x + 3 * (size_t) i, *xr = k.xref + 3 * (size_t) i;
  const double *vi = k.v + 3 * (size_t) i, *fi = k.f + 3 * (size_t) i;
  const double im = k.im[k.type[i]];
  const double dx = xi[0] - xr[0], dy = xi[1] - xr[1], dz = xi[2] - xr[2];
  const double d2 = dx * dx + dy * dy + dz * dz;
  const double v2 = k.t2 * (vi[0] * vi[0] + vi[1] * vi[1] + vi[2] * vi[2]);
  const double a2 = k.h4 * im * im * (fi[0] * fi[0] + fi[1] * fi[1] + fi[2] * fi[2]);
  u = {i, d2, v2, a2};
  return screen_fast_test(d2, v2, a2, k.gap[i], k.half_skin, k.list, k.margin) == CLEARED;
}

// spheres [i0, i1): kick those of the group, append those not cleared to
// todo (not in the group: no kick, not listed)
inline void kick_clear_scalar(const KickScreen &k, int i0, int i1, std::vector<Unscreened> &todo)
{
  for (int i = i0; i < i1; i++) {
    k.active[i] = 0.0;
    if (!(k.mask[i] & k.groupbit)) continue;
    if (k.kick) {
      const double dtfm = k.dtf / k.mass[k.type[i]];
      double *vi = k.v + 3 * (size_t) i;
      const double *fi = k.f + 3 * (size_t) i;
      vi[0] += dtfm * fi[0];
      vi[1] += dtfm * fi[1];
      vi[2] += dtfm * fi[2];
    }
    Unscreened u;
    if (!screen_cleared(k, i, u)) todo.push_back(u);
  }
}

#ifdef HS_SCREEN_AVX2
namespace detail {
  // four consecutive rows of p (3 doubles each) as x, y, z of four lanes
  __attribute__((target("avx2"))) inline void load4(const double *p, __m256d &X, __m256d &Y,
                                                    __m256d &Z)
  {
    rows4(p, p + 3, p + 6, p + 9, X, Y, Z);
  }
  __attribute__((target("avx2"))) inline __m256d sq3(__m256d X, __m256d Y, __m256d Z)
  {
    return _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(X, X), _mm256_mul_pd(Y, Y)),
                         _mm256_mul_pd(Z, Z));
  }
}    // namespace detail

__attribute__((target("avx2"))) inline void kick_clear_avx2(const KickScreen &k, int i0, int i1,
                                                            std::vector<Unscreened> &todo)
{
  const __m256d dtf = _mm256_set1_pd(k.dtf), t2 = _mm256_set1_pd(k.t2),
                h4 = _mm256_set1_pd(k.h4), hs = _mm256_set1_pd(k.half_skin),
                three = _mm256_set1_pd(3.0);
  int i = i0;
  for (; i + 4 <= i1; i += 4) {
    const int *ty = k.type + i;
    const int m0 = k.mask[i] & k.groupbit, m1 = k.mask[i + 1] & k.groupbit,
              m2 = k.mask[i + 2] & k.groupbit, m3 = k.mask[i + 3] & k.groupbit;
    if (!(m0 && m1 && m2 && m3)) {    // (a block with spheres outside the group)
      kick_clear_scalar(k, i, i + 4, todo);
      continue;
    }
    _mm256_storeu_pd(k.active + i, _mm256_setzero_pd());
    double *vp = k.v + 3 * (size_t) i;
    __m256d VX, VY, VZ, FX, FY, FZ;
    detail::load4(vp, VX, VY, VZ);
    detail::load4(k.f + 3 * (size_t) i, FX, FY, FZ);
    if (k.kick) {
      const __m256d m =
          _mm256_setr_pd(k.mass[ty[0]], k.mass[ty[1]], k.mass[ty[2]], k.mass[ty[3]]);
      const __m256d dtfm = _mm256_div_pd(dtf, m);
      VX = _mm256_add_pd(VX, _mm256_mul_pd(dtfm, FX));
      VY = _mm256_add_pd(VY, _mm256_mul_pd(dtfm, FY));
      VZ = _mm256_add_pd(VZ, _mm256_mul_pd(dtfm, FZ));
      // the kicked rows back: (x, y) pairs, then z
      const __m256d lo = _mm256_unpacklo_pd(VX, VY), hi = _mm256_unpackhi_pd(VX, VY);
      _mm_storeu_pd(vp, _mm256_castpd256_pd128(lo));
      _mm_storeu_pd(vp + 3, _mm256_castpd256_pd128(hi));
      _mm_storeu_pd(vp + 6, _mm256_extractf128_pd(lo, 1));
      _mm_storeu_pd(vp + 9, _mm256_extractf128_pd(hi, 1));
      alignas(32) double z[4];
      _mm256_store_pd(z, VZ);
      vp[2] = z[0];
      vp[5] = z[1];
      vp[8] = z[2];
      vp[11] = z[3];
    }

    __m256d XX, XY, XZ, RX, RY, RZ;
    detail::load4(k.x + 3 * (size_t) i, XX, XY, XZ);
    detail::load4(k.xref + 3 * (size_t) i, RX, RY, RZ);
    const __m256d d2 =
        detail::sq3(_mm256_sub_pd(XX, RX), _mm256_sub_pd(XY, RY), _mm256_sub_pd(XZ, RZ));
    const __m256d v2 = _mm256_mul_pd(t2, detail::sq3(VX, VY, VZ));
    const __m256d im = _mm256_setr_pd(k.im[ty[0]], k.im[ty[1]], k.im[ty[2]], k.im[ty[3]]);
    const __m256d a2 =
        _mm256_mul_pd(_mm256_mul_pd(_mm256_mul_pd(h4, im), im), detail::sq3(FX, FY, FZ));
    const __m256d gap = _mm256_loadu_pd(k.gap + i);
    // (MIN(gap, half_skin): gap where gap < half_skin, else half_skin)
    const __m256d g = _mm256_blendv_pd(hs, gap, _mm256_cmp_pd(gap, hs, _CMP_LT_OQ));
    const __m256d s3 = _mm256_mul_pd(three, _mm256_add_pd(_mm256_add_pd(d2, v2), a2));
    int ok = _mm256_movemask_pd(_mm256_cmp_pd(s3, _mm256_mul_pd(g, g), _CMP_LE_OQ));
    if (k.list) {
      const __m256d gm = _mm256_sub_pd(gap, _mm256_set1_pd(k.margin));
      const __m256d s3m = _mm256_mul_pd(s3, _mm256_set1_pd(1.0 + 1.0e-12));
      ok &= _mm256_movemask_pd(_mm256_cmp_pd(gm, _mm256_setzero_pd(), _CMP_GT_OQ)) &
          _mm256_movemask_pd(_mm256_cmp_pd(s3m, _mm256_mul_pd(gm, gm), _CMP_LE_OQ));
    }
    if (ok != 0xF) {
      alignas(32) double t[3][4];
      _mm256_store_pd(t[0], d2);
      _mm256_store_pd(t[1], v2);
      _mm256_store_pd(t[2], a2);
      for (int l = 0; l < 4; l++)
        if (!(ok >> l & 1)) todo.push_back({i + l, t[0][l], t[1][l], t[2][l]});
    }
  }
  kick_clear_scalar(k, i, i1, todo);
}
#endif

// kick_clear_avx2() where the processor has AVX2, else kick_clear_scalar(),
// on spheres [i0, i1)
inline void kick_clear(const KickScreen &k, int i0, int i1, std::vector<Unscreened> &todo)
{
#ifdef HS_SCREEN_AVX2
  if (has_avx2()) {
    kick_clear_avx2(k, i0, i1, todo);
    return;
  }
#endif
  kick_clear_scalar(k, i0, i1, todo);
}

// kick_clear() over spheres [0, n) in chunks, each chunk's spheres not
// cleared handed to fn(u) in increasing index before the next chunk: the
// list of them stays in the cache (on a dense fluid most spheres are not
// cleared: at 256000 atoms a list of all of them is 6 MB, written and read
// back from memory). The same calls in the same order as kick_clear() over
// [0, n) followed by fn over its list, as long as fn(u) reads and writes
// nothing of the spheres after u.i but its own results
template <class F> inline void kick_clear_chunked(const KickScreen &k, int n,
                                                  std::vector<Unscreened> &todo, F fn)
{
  constexpr int CHUNK = 4096;
  for (int i0 = 0; i0 < n; i0 += CHUNK) {
    todo.clear();
    kick_clear(k, i0, i0 + CHUNK < n ? i0 + CHUNK : n, todo);
    for (const Unscreened &u : todo) fn(u);
  }
}

}    // namespace HardSphere

#endif
