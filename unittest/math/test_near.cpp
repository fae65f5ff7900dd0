// hs_near.h: the candidate filter's kernel. Against a reference written
// here (each entry's squared distance by the same double operations, forced
// one at a time, against the cutoff; the list entries' high bits set as
// LAMMPS' special bits are), and the AVX2
// version against the scalar one entry for entry: the same kept indices in
// the same order, also for distances that equal the cutoff to the last bit,
// lists of every length mod 4, and the last row of the position block (read
// without touching memory after it).

#include "hs_near.h"

#include "gtest/gtest.h"

#include <cmath>
#include <cstdlib>
#include <random>
#include <vector>

namespace {

constexpr int MASK = 0x3fffffff;

// the reference: entries whose exact squared distance (the same double
// operations as the kernel, whose rounding the kernel must reproduce) is
// within cut2, in list order
std::vector<int> reference(const std::vector<int> &jl, const std::vector<double> &x, double xi,
                           double yi, double zi, double cut2)
{
  std::vector<int> out;
  for (int e : jl) {
    const int j = e & MASK;
    volatile double dx = xi - x[3 * j], dy = yi - x[3 * j + 1], dz = zi - x[3 * j + 2];
    volatile double a = dx * dx, b = dy * dy, c = dz * dz;
    volatile double s = a + b;
    volatile double d2 = s + c;
    if (d2 <= cut2) out.push_back(j);
  }
  return out;
}

struct Case {
  std::vector<double> x;    // positions, exactly 3 per point (no slack after the last)
  std::vector<int> jl;      // entries with special bits above MASK
};

Case make_case(std::mt19937 &g, int npts, int nlist, double box)
{
  Case c;
  std::uniform_real_distribution<double> U(0.0, box);
  // on a lattice of spacing 0.25 half the time: many distances are exact
  // (squared distances sums of multiples of 1/16) and equal the cutoff
  std::bernoulli_distribution lattice(0.5);
  c.x.resize(3 * (size_t) npts);
  for (auto &v : c.x) v = lattice(g) ? 0.25 * std::floor(U(g) / 0.25) : U(g);
  std::uniform_int_distribution<int> J(0, npts - 1), S(0, 3);
  for (int k = 0; k < nlist; k++) c.jl.push_back(J(g) | (S(g) << 30));
  c.jl.push_back((npts - 1) | (1 << 30));    // the last row, always
  return c;
}

}    // namespace

TEST(Near, ScalarMatchesTheReference)
{
  std::mt19937 g(42);
  for (int trial = 0; trial < 200; trial++) {
    const int nlist = trial % 53;
    Case c = make_case(g, 64, nlist, 2.0);
    const double xi = 0.25 * (trial % 8), yi = 0.5, zi = 0.75, cut2 = 0.5625 + 0.0625 * (trial % 5);
    std::vector<int> out(c.jl.size() + 4);
    const int m = HardSphere::near_scalar(c.jl.data(), (int) c.jl.size(), MASK, c.x.data(), xi,
                                          yi, zi, cut2, out.data());
    out.resize(m);
    EXPECT_EQ(out, reference(c.jl, c.x, xi, yi, zi, cut2)) << "trial " << trial;
  }
}

TEST(Near, AVX2MatchesScalarEntryForEntry)
{
#ifdef HS_NEAR_AVX2
  if (!__builtin_cpu_supports("avx2")) GTEST_SKIP() << "no AVX2 on this processor";
  std::mt19937 g(7);
  for (int trial = 0; trial < 2000; trial++) {
    const int nlist = trial % 61;    // every length mod 4, empty lists too
    const int npts = 1 + trial % 97;
    Case c = make_case(g, npts, nlist, 1.5 + (trial % 3));
    // the position block exactly as long as its points: a read past the
    // last row would be outside the vector (caught by ASan/valgrind runs)
    std::vector<double> x(c.x);
    x.shrink_to_fit();
    const double xi = 0.25 * (trial % 7), yi = 0.25 * (trial % 5), zi = 0.25 * (trial % 3);
    const double cut2 = 0.0625 * (trial % 23);
    std::vector<int> a(c.jl.size() + 4), b(c.jl.size() + 4);
    const int na = HardSphere::near_scalar(c.jl.data(), (int) c.jl.size(), MASK, x.data(), xi, yi,
                                           zi, cut2, a.data());
    const int nb = HardSphere::near_avx2(c.jl.data(), (int) c.jl.size(), MASK, x.data(), xi, yi,
                                         zi, cut2, b.data());
    ASSERT_EQ(na, nb) << "trial " << trial;
    a.resize(na);
    b.resize(nb);
    ASSERT_EQ(a, b) << "trial " << trial;
  }
#else
  GTEST_SKIP() << "not an x86-64 GNU build";
#endif
}

TEST(Near, DispatchGivesTheScalarList)
{
  std::mt19937 g(3);
  Case c = make_case(g, 500, 400, 3.0);
  std::vector<int> a(c.jl.size() + 4), b(c.jl.size() + 4);
  const int na = HardSphere::near_scalar(c.jl.data(), (int) c.jl.size(), MASK, c.x.data(), 1.5,
                                         1.5, 1.5, 1.0, a.data());
  const int nb =
      HardSphere::near(c.jl.data(), (int) c.jl.size(), MASK, c.x.data(), 1.5, 1.5, 1.5, 1.0, b.data());
  ASSERT_EQ(na, nb);
  a.resize(na);
  b.resize(nb);
  EXPECT_EQ(a, b);
  EXPECT_GT(na, 10);
}

// near<true>(): "not greater than" the cutoff, as the local engine's rows
// test it: the same list as near<false>() but for NaN distances, which it
// keeps (near<false>() leaves them out); AVX2 and scalar the same, entry
// for entry, on lists with NaN positions and distances at the cutoff
TEST(Near, NotGreaterKeepsWhatLessOrEqualKeepsAndNaN)
{
  std::mt19937 g(11);
  int nans = 0;
  for (int trial = 0; trial < 500; trial++) {
    const int nlist = trial % 61, npts = 1 + trial % 97;
    Case c = make_case(g, npts, nlist, 2.0);
    // a NaN coordinate in some points
    for (int p = 0; p < npts; p += 7 + trial % 5) c.x[3 * p + trial % 3] = std::nan("");
    const double xi = 0.25 * (trial % 7), yi = 0.5, zi = 0.25 * (trial % 3);
    const double cut2 = 0.0625 * (trial % 23);
    std::vector<int> le(c.jl.size() + 4), ngt(c.jl.size() + 4);
    const int nle = HardSphere::near_scalar<false>(c.jl.data(), (int) c.jl.size(), MASK,
                                                   c.x.data(), xi, yi, zi, cut2, le.data());
    const int ngs = HardSphere::near_scalar<true>(c.jl.data(), (int) c.jl.size(), MASK,
                                                  c.x.data(), xi, yi, zi, cut2, ngt.data());
    le.resize(nle);
    ngt.resize(ngs);
    // the reference: <= plus the entries whose distance is NaN, in list order
    std::vector<int> want;
    for (int e : c.jl) {
      const int j = e & MASK;
      volatile double dx = xi - c.x[3 * j], dy = yi - c.x[3 * j + 1], dz = zi - c.x[3 * j + 2];
      volatile double a = dx * dx, b = dy * dy, cc = dz * dz;
      volatile double s = a + b;
      volatile double d2 = s + cc;
      if (!(d2 > cut2)) want.push_back(j);
      nans += std::isnan(d2);
    }
    ASSERT_EQ(ngt, want) << "trial " << trial;
    ASSERT_LE(le.size(), ngt.size());
#ifdef HS_NEAR_AVX2
    if (__builtin_cpu_supports("avx2")) {
      std::vector<int> v(c.jl.size() + 4);
      const int nv = HardSphere::near_avx2<true>(c.jl.data(), (int) c.jl.size(), MASK,
                                                 c.x.data(), xi, yi, zi, cut2, v.data());
      v.resize(nv);
      ASSERT_EQ(v, ngt) << "trial " << trial;
    }
#endif
  }
  EXPECT_GT(nans, 100);
}
