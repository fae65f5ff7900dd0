/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: the candidate filter's kernel (HSSystem::
   reset_reference(), at every neighbor list build): of a point's neighbor
   list entries, those within the contact-list cutoff. The pair style's list
   reaches the neighbor cutoff (2.8 for LJ 2.5 + skin 0.3), so of its ~40
   entries per atom in a melt ~3 are kept: the scan is most of the fix's
   cost on a collision-free system (bench/overhead).

   near_scalar() is the reference; near_avx2() does four entries at a time
   (their rows loaded and transposed: no gathers, slow on this machine's
   AMD EPYC) and gives the same
   list bit for bit: the same subtractions, products and sums in the same
   order (dx*dx + dy*dy, then + dz*dz; no fused multiply-add), the same <=
   test, the kept indices in list order. near() picks one at run time.

   LAMMPS-free (unit-tested alone: unittest/math/test_near.cpp).
------------------------------------------------------------------------- */

#ifndef LMP_HS_NEAR_H
#define LMP_HS_NEAR_H

#include <cstddef>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define HS_NEAR_AVX2 1
#endif

namespace HardSphere {

// the entries j = jlist[k] & mask (k < n) whose position x[3j..3j+2] lies
// within sqrt(cut2) of (xi, yi, zi), in list order, written to out (room
// for n + 4 entries); returns their number. NGT: keep the squared
// distances "not greater than" cut2 (a NaN kept) instead of "<=" (a NaN
// left out), for callers whose own test had that form (hs_cells.h
// for_each_within(): the local engine's rows)
template <bool NGT = false>
inline int near_scalar(const int *jlist, int n, int mask, const double *x, double xi, double yi,
                       double zi, double cut2, int *out)
{
  int m = 0;
  for (int k = 0; k < n; k++) {
    const int j = jlist[k] & mask;
    const double *xj = x + 3 * (size_t) j;
    const double dx = xi - xj[0], dy = yi - xj[1], dz = zi - xj[2];
    out[m] = j;    // (branch-free: kept or overwritten by the next)
    const double d2 = dx * dx + dy * dy + dz * dz;
    m += NGT ? !(d2 > cut2) : (d2 <= cut2);
  }
  return m;
}

#ifdef HS_NEAR_AVX2
// whether this processor runs the AVX2 kernels (hs_near.h, hs_screen.h,
// hs_lj_terms.h pick theirs by it), asked once
inline bool has_avx2()
{
  static const bool avx2 = __builtin_cpu_supports("avx2");
  return avx2;
}

namespace detail {
  // byte shuffles that move the int lanes selected by a 4-bit mask to the
  // front, in order
  struct NearLUT {
    alignas(16) unsigned char b[16][16];
    NearLUT()
    {
      for (int bits = 0; bits < 16; bits++) {
        int p = 0;
        for (int l = 0; l < 4; l++)
          if (bits >> l & 1) {
            for (int q = 0; q < 4; q++) b[bits][4 * p + q] = (unsigned char) (4 * l + q);
            p++;
          }
        for (; p < 4; p++)
          for (int q = 0; q < 4; q++) b[bits][4 * p + q] = 0x80;
      }
    }
  };
  inline const NearLUT &near_lut()
  {
    static const NearLUT lut;
    return lut;
  }
  // rows p0 .. p3 (3 doubles each) as the x, y, z of four lanes: (x, y) of
  // rows 0 and 2, of rows 1 and 3, two at a time; z one by one (no read
  // past the last row). Also hs_screen.h's
  __attribute__((target("avx2"))) inline void rows4(const double *p0, const double *p1,
                                                    const double *p2, const double *p3,
                                                    __m256d &X, __m256d &Y, __m256d &Z)
  {
    const __m256d a02 = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(p0)),
                                             _mm_loadu_pd(p2), 1);
    const __m256d a13 = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(p1)),
                                             _mm_loadu_pd(p3), 1);
    X = _mm256_unpacklo_pd(a02, a13);
    Y = _mm256_unpackhi_pd(a02, a13);
    Z = _mm256_setr_pd(p0[2], p1[2], p2[2], p3[2]);
  }
}    // namespace detail

template <bool NGT = false>
__attribute__((target("avx2"))) inline int near_avx2(const int *jlist, int n, int mask,
                                                     const double *x, double xi, double yi,
                                                     double zi, double cut2, int *out)
{
  const detail::NearLUT &lut = detail::near_lut();
  const __m256d vx = _mm256_set1_pd(xi), vy = _mm256_set1_pd(yi), vz = _mm256_set1_pd(zi);
  const __m256d vc = _mm256_set1_pd(cut2);
  int m = 0, k = 0;
  for (; k + 4 <= n; k += 4) {
    const int j0 = jlist[k] & mask, j1 = jlist[k + 1] & mask, j2 = jlist[k + 2] & mask,
              j3 = jlist[k + 3] & mask;
    const double *p0 = x + 3 * (size_t) j0, *p1 = x + 3 * (size_t) j1,
                 *p2 = x + 3 * (size_t) j2, *p3 = x + 3 * (size_t) j3;
    __m256d px, py, pz;
    detail::rows4(p0, p1, p2, p3, px, py, pz);
    const __m256d dx = _mm256_sub_pd(vx, px), dy = _mm256_sub_pd(vy, py),
                  dz = _mm256_sub_pd(vz, pz);
    const __m256d d2 = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)),
                                     _mm256_mul_pd(dz, dz));
    const int bits = _mm256_movemask_pd(_mm256_cmp_pd(d2, vc, NGT ? _CMP_NGT_UQ : _CMP_LE_OQ));
    const __m128i js = _mm_setr_epi32(j0, j1, j2, j3);
    const __m128i sh = _mm_load_si128((const __m128i *) lut.b[bits]);
    _mm_storeu_si128((__m128i *) (out + m), _mm_shuffle_epi8(js, sh));
    m += __builtin_popcount(bits);
  }
  return m + near_scalar<NGT>(jlist + k, n - k, mask, x, xi, yi, zi, cut2, out + m);
}
#endif

// near_avx2() where the processor has AVX2, else near_scalar()
template <bool NGT = false>
inline int near(const int *jlist, int n, int mask, const double *x, double xi, double yi,
                double zi, double cut2, int *out)
{
#ifdef HS_NEAR_AVX2
  if (has_avx2()) return near_avx2<NGT>(jlist, n, mask, x, xi, yi, zi, cut2, out);
#endif
  return near_scalar<NGT>(jlist, n, mask, x, xi, yi, zi, cut2, out);
}

}    // namespace HardSphere

#endif
