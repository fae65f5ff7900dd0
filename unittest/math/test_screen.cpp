// hs_screen.h: the closing kick and the next step's screen, fast path.
// Against a reference written here (the kick v + (dtf / m) f, or none, and the
// screen's inequalities, each operation forced one at a time in the order
// the package's full test uses), and the AVX2 version against the scalar
// one: the same kicked velocities bit for bit, the same spheres listed in
// the same order, active zeroed, spheres outside the group untouched; with
// gaps that put s3 on g^2 and on the listing bound to the last bit, blocks
// of four with and without spheres outside the group, lengths of every
// value mod 4, and gaps above and below half the skin.

#include "hs_screen.h"

#include "gtest/gtest.h"

#include <cmath>
#include <random>
#include <vector>

using HardSphere::KickScreen;

namespace {

struct Data {
  int n = 0;
  std::vector<double> v, f, x, xref, gap, active;
  std::vector<int> type, mask;
  std::vector<double> mass{0.0, 1.0, 2.5, 0.7}, im;
  KickScreen k;
  void bind(bool list)
  {
    im.resize(mass.size());
    for (size_t t = 1; t < mass.size(); t++) im[t] = 1.3 / mass[t];
    k.v = v.data();
    k.active = active.data();
    k.f = f.data();
    k.x = x.data();
    k.xref = xref.data();
    k.gap = gap.data();
    k.type = type.data();
    k.mask = mask.data();
    k.mass = mass.data();
    k.im = im.data();
    k.groupbit = 4;
    k.dtf = 0.0025;
    k.t2 = 0.005 * 0.005;
    k.h4 = 0.25 * k.t2 * k.t2;
    k.half_skin = 0.15;
    k.list = list;
    k.margin = 0.02;
  }
};

// the sphere's three squared terms after its kick, one operation at a time
void terms_of(const Data &d, int i, const double *vk, double *t)
{
  volatile double dx = d.x[3 * i] - d.xref[3 * i], dy = d.x[3 * i + 1] - d.xref[3 * i + 1],
                  dz = d.x[3 * i + 2] - d.xref[3 * i + 2];
  volatile double d2 = dx * dx;
  d2 = d2 + dy * dy;
  d2 = d2 + dz * dz;
  volatile double vv = vk[0] * vk[0];
  vv = vv + vk[1] * vk[1];
  vv = vv + vk[2] * vk[2];
  volatile double v2 = d.k.t2 * vv;
  const double *f = &d.f[3 * i];
  volatile double ff = f[0] * f[0];
  ff = ff + f[1] * f[1];
  ff = ff + f[2] * f[2];
  volatile double c = d.k.h4 * d.im[d.type[i]];
  c = c * d.im[d.type[i]];
  volatile double a2 = c * ff;
  t[0] = d2;
  t[1] = v2;
  t[2] = a2;
}

double s3_of(const Data &d, int i, const double *vk)
{
  double t[3];
  terms_of(d, i, vk, t);
  volatile double s = t[0] + t[1];
  s = s + t[2];
  return 3.0 * s;
}

// the reference: kicked velocities and the list of spheres not cleared
void reference(const Data &d, std::vector<double> &v, std::vector<int> &todo)
{
  v = d.v;
  todo.clear();
  for (int i = 0; i < d.n; i++) {
    if (!(d.mask[i] & d.k.groupbit)) continue;
    volatile double dtfm = d.k.dtf / d.mass[d.type[i]];
    for (int c = 0; c < 3 && d.k.kick; c++) {
      volatile double p = dtfm * d.f[3 * i + c];
      v[3 * i + c] = v[3 * i + c] + p;
    }
    const double s3 = s3_of(d, i, &v[3 * i]);
    const double g = d.gap[i] < d.k.half_skin ? d.gap[i] : d.k.half_skin;
    bool cleared = s3 <= g * g;
    if (cleared && d.k.list) {
      const double gm = d.gap[i] - d.k.margin;
      volatile double s3m = s3 * (1.0 + 1.0e-12);
      cleared = gm > 0.0 && s3m <= gm * gm;
    }
    if (!cleared) todo.push_back(i);
  }
}

Data random_spheres(std::mt19937 &rng, int n, bool outsiders)
{
  std::uniform_real_distribution<double> U(-1.0, 1.0), P(0.0, 1.0);
  Data d;
  d.n = n;
  d.v.resize(3 * n);
  d.f.resize(3 * n);
  d.x.resize(3 * n);
  d.xref.resize(3 * n);
  d.gap.resize(n);
  d.active.assign(n, 1.0);
  d.type.resize(n);
  d.mask.resize(n);
  for (int i = 0; i < n; i++) {
    for (int c = 0; c < 3; c++) {
      d.v[3 * i + c] = 2.0 * U(rng);
      d.f[3 * i + c] = 40.0 * U(rng);
      d.x[3 * i + c] = 10.0 * U(rng);
      d.xref[3 * i + c] = d.x[3 * i + c] + 0.08 * U(rng);
    }
    d.type[i] = 1 + (int) (3 * P(rng)) % 3;
    d.mask[i] = (outsiders && P(rng) < 0.15) ? 1 : 5;
    d.gap[i] = 0.3 * P(rng);
  }
  return d;
}

void compare(Data &d, const char *what)
{
  std::vector<double> v0 = d.v, vref;
  std::vector<int> want;
  reference(d, vref, want);
  for (int kernel = 0; kernel < 2; kernel++) {
    d.v = v0;
    d.active.assign(d.n, 1.0);
    d.k.v = d.v.data();
    d.k.active = d.active.data();
    std::vector<HardSphere::Unscreened> listed;
#ifdef HS_SCREEN_AVX2
    if (kernel == 1 && !__builtin_cpu_supports("avx2")) continue;
    if (kernel == 1) HardSphere::kick_clear_avx2(d.k, 0, d.n, listed);
#else
    if (kernel == 1) continue;
#endif
    if (kernel == 0) HardSphere::kick_clear_scalar(d.k, 0, d.n, listed);
    std::vector<int> got;
    for (const auto &u : listed) {
      got.push_back(u.i);
      // the terms handed on are the sphere's own, bit for bit
      const int i = u.i;
      const double *vk = &vref[3 * i];
      double t[3];
      terms_of(d, i, vk, t);
      EXPECT_EQ(u.d2, t[0]) << what << " sphere " << i;
      EXPECT_EQ(u.v2, t[1]) << what << " sphere " << i;
      EXPECT_EQ(u.a2, t[2]) << what << " sphere " << i;
    }
    ASSERT_EQ(got, want) << what << (kernel ? " avx2" : " scalar") << " n " << d.n;
    for (int q = 0; q < 3 * d.n; q++)
      ASSERT_EQ(d.v[q], vref[q]) << what << (kernel ? " avx2" : " scalar") << " v entry " << q;
    for (int i = 0; i < d.n; i++) ASSERT_EQ(d.active[i], 0.0);
  }
}

}    // namespace

TEST(KickScreen, RandomSpheresAsTheReference)
{
  std::mt19937 rng(4242);
  int listed = 0, cleared = 0;
  for (int trial = 0; trial < 400; trial++) {
    Data d = random_spheres(rng, 1 + trial % 37, trial % 3 == 0);
    d.bind(trial % 2 == 0);
    d.k.kick = trial % 5 != 0;    // (the screen alone, HSSystem::screen())
    std::vector<double> vref;
    std::vector<int> want;
    reference(d, vref, want);
    listed += (int) want.size();
    cleared += d.n - (int) want.size();
    compare(d, "random");
  }
  EXPECT_GT(listed, 500);
  EXPECT_GT(cleared, 500);
}

// gaps with s3 == g^2 (and one bit either side), and on the listing bound
TEST(KickScreen, OnTheBoundsToTheLastBit)
{
  std::mt19937 rng(99);
  int on = 0;
  for (int trial = 0; trial < 300; trial++) {
    Data d = random_spheres(rng, 8 + trial % 9, false);
    d.bind(trial % 2 == 1);
    // the kicked velocities, to set each sphere's gap from its s3
    std::vector<double> vk;
    std::vector<int> dummy;
    reference(d, vk, dummy);
    for (int i = 0; i < d.n; i++) {
      const double s3 = s3_of(d, i, &vk[3 * i]);
      double g = std::sqrt(s3);
      const int shift = (int) (rng() % 3) - 1;
      if (d.k.list && i % 2) {
        // the listing bound: gm^2 against s3 (1 + 1e-12)
        g = std::sqrt(s3 * (1.0 + 1.0e-12)) + d.k.margin;
      }
      if (shift < 0) g = std::nextafter(g, 0.0);
      if (shift > 0) g = std::nextafter(g, 1.0);
      d.gap[i] = g;
      d.k.half_skin = 10.0;    // (the gap decides)
      if (g * g == s3) ++on;
    }
    compare(d, "bounds");
  }
  EXPECT_GT(on, 50) << "too few spheres exactly on the bound";
}

// kick_clear_chunked(): over lengths around and across its chunks, the
// spheres handed on are the reference's, in order, with their own terms,
// and every velocity is kicked as in one call over all of them
TEST(KickScreen, ChunkedAsOneCall)
{
  std::mt19937 rng(777);
  size_t listed = 0, total = 0;
  for (int n : {1, 4095, 4096, 4097, 10003}) {
    Data d = random_spheres(rng, n, n > 4096);
    d.bind(n % 2 == 1);
    std::vector<double> vref;
    std::vector<int> want;
    reference(d, vref, want);
    std::vector<HardSphere::Unscreened> buf;
    std::vector<int> got;
    HardSphere::kick_clear_chunked(d.k, d.n, buf, [&](const HardSphere::Unscreened &u) {
      got.push_back(u.i);
      double t[3];
      terms_of(d, u.i, &vref[3 * u.i], t);
      EXPECT_EQ(u.d2, t[0]) << "n " << n << " sphere " << u.i;
      EXPECT_EQ(u.v2, t[1]) << "n " << n << " sphere " << u.i;
      EXPECT_EQ(u.a2, t[2]) << "n " << n << " sphere " << u.i;
    });
    ASSERT_EQ(got, want) << "n " << n;
    listed += want.size();
    total += n;
    for (int q = 0; q < 3 * d.n; q++) ASSERT_EQ(d.v[q], vref[q]) << "n " << n << " entry " << q;
    for (int i = 0; i < d.n; i++) ASSERT_EQ(d.active[i], 0.0) << "n " << n;
  }
  // (both kinds in every chunk's worth: the order across chunks is tested)
  EXPECT_GT(listed, total / 10);
  EXPECT_LT(listed, total - total / 10);
}
