// Virial coefficients B2, B3, B4 of hard spheres with the AO depletion
// attraction (the pair potential of potentials/, written out here from its
// formula), by Monte Carlo integration over chains of Mayer bonds. No LAMMPS.
//
//   u(r)/kT = -eta_p ((1+q)/q)^3 [1 - 3x/2 + x^3/2], x = r/(1+q), 1 <= r <= 1+q,
//   hard core r < 1 (sigma = 1), u = 0 beyond 1+q; eta_p = depth/(1 + 3/(2q)).
//   f(r) = exp(-u/kT) - 1 (f = -1 in the core, 0 beyond R = 1+q).
//
//   B2 = -(1/2) int f12 dr2
//   B3 = -(1/3) int f12 f23 f13 dr2 dr3
//   B4 = -(1/8) int f12 f23 f34 [3 f14 + 6 f14 f13 + f14 f13 f24] dr2 dr3 dr4
//
// (B_n = -(n-1)/n! sum over biconnected labelled graphs; for n = 4: 3 rings,
// 6 rings with one diagonal, the complete graph, each written with the path
// 1-2-3-4.) Every graph contains that path, so the bond vectors r12, r23,
// r34 are drawn independently from p(r) = |f(r)| / W, W = int |f| d^3r
// (W by Gauss-Legendre quadrature, the sampling exact: core r^2 law, well by
// rejection), and
//   int f12 f23 f34 F dr2 dr3 dr4 = W^3 < s12 s23 s34 F >,  s = sign f.
// The diagonal term uses (f13 + f24)/2 (equal by symmetry, less variance).
// Independent samples: the error bar is the standard error of block means.
//
// Checked on hard spheres (--depth 0): B3/b^2 = 5/8, B4/b^3 = 0.2869495
// (b = 2 pi/3); B2 and B3 of the AO case against virial.py's quadrature.
//
//   g++ -O2 -o mayer_b4 mayer_b4.cpp
//   ./mayer_b4 --q 0.2 --samples 1e9 --seed 1

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace {

const double PI = 3.14159265358979323846;

// xoshiro256+ (Blackman and Vigna): fast, good enough for integration
struct Rng {
  uint64_t s[4];
  explicit Rng(uint64_t seed)
  {
    for (auto &v : s) {    // splitmix64 to fill the state
      seed += 0x9e3779b97f4a7c15ULL;
      uint64_t z = seed;
      z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
      z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
      v = z ^ (z >> 31);
    }
  }
  static uint64_t rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  double operator()()
  {
    const uint64_t r = s[0] + s[3], t = s[1] << 17;
    s[2] ^= s[0];
    s[3] ^= s[1];
    s[1] ^= s[2];
    s[0] ^= s[3];
    s[2] ^= t;
    s[3] = rotl(s[3], 45);
    return (r >> 11) * 0x1.0p-53;    // [0, 1)
  }
};

struct AO {
  double q, depth, R, A;    // A = eta_p ((1+q)/q)^3, u(1) = -depth
  AO(double q_, double depth_) : q(q_), depth(depth_), R(1 + q_)
  {
    const double eta = depth / (1 + 1.5 / q);
    A = eta * std::pow((1 + q) / q, 3);
  }
  double u(double r) const
  {
    const double x = r / R;
    return -A * (1 - 1.5 * x + 0.5 * x * x * x);
  }
  double f(double r2) const
  {
    if (r2 < 1.0) return -1.0;
    if (r2 >= R * R) return 0.0;
    return std::expm1(-u(std::sqrt(r2)));
  }
};

// int_a^b g(r) dr, 64-point Gauss-Legendre on 64 panels (g smooth on [a, b])
template <class G> double quad(G g, double a, double b)
{
  static std::vector<double> x, w;
  if (x.empty()) {    // nodes by Newton on P_64
    const int n = 64;
    for (int i = 1; i <= n; ++i) {
      double z = std::cos(PI * (i - 0.25) / (n + 0.5)), dp = 0;
      for (int it = 0; it < 100; ++it) {
        double p0 = 1, p1 = z;
        for (int k = 2; k <= n; ++k) {
          const double p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
          p0 = p1;
          p1 = p2;
        }
        dp = n * (z * p1 - p0) / (z * z - 1);
        const double dz = p1 / dp;
        z -= dz;
        if (std::fabs(dz) < 1e-16) break;
      }
      x.push_back(z);
      w.push_back(2 / ((1 - z * z) * dp * dp));
    }
  }
  const int panels = 64;
  double tot = 0;
  for (int p = 0; p < panels; ++p) {
    const double lo = a + (b - a) * p / panels, hi = a + (b - a) * (p + 1) / panels;
    for (size_t i = 0; i < x.size(); ++i)
      tot += w[i] * 0.5 * (hi - lo) * g(0.5 * (hi - lo) * x[i] + 0.5 * (hi + lo));
  }
  return tot;
}

void usage()
{
  std::fprintf(stderr, "usage: mayer_b4 [--q Q] [--depth D] [--samples N] [--blocks B] [--seed S]\n");
  std::exit(2);
}

}    // namespace

int main(int argc, char **argv)
{
  double q = 0.2, depth = 3.0, nsamp = 1e8;
  long nblocks = 1000;
  uint64_t seed = 1;
  for (int a = 1; a < argc; ++a) {
    const std::string k = argv[a];
    if (a + 1 >= argc) usage();
    const char *v = argv[++a];
    if (k == "--q") q = std::atof(v);
    else if (k == "--depth") depth = std::atof(v);
    else if (k == "--samples") nsamp = std::atof(v);
    else if (k == "--blocks") nblocks = std::atol(v);
    else if (k == "--seed") seed = std::strtoull(v, nullptr, 10);
    else usage();
  }
  const AO ao(q, depth);
  // |f| weights of the core and the well; the well's |f| <= fmax (f is largest at contact)
  const double Wc = 4 * PI / 3;
  const double Ww = depth > 0 ? quad([&](double r) { return 4 * PI * r * r * std::expm1(-ao.u(r)); }, 1.0, ao.R) : 0.0;
  const double W = Wc + Ww, pc = Wc / W, fmax = std::expm1(depth), R3 = ao.R * ao.R * ao.R;
  // B2 exactly from the same weights: int f = -Wc + Ww
  const double B2 = -0.5 * (Ww - Wc);

  Rng rng(seed);
  auto bond = [&](double *d) {
    double r;
    if (rng() < pc) r = std::cbrt(rng());    // core: p ~ r^2 on [0, 1]
    else
      for (;;) {    // well: r^2 on [1, R], accepted with f(r)/fmax
        r = std::cbrt(1 + rng() * (R3 - 1));
        if (rng() * fmax < std::expm1(-ao.u(r))) break;
      }
    const double ct = 2 * rng() - 1, ph = 2 * PI * rng(), st = std::sqrt(1 - ct * ct);
    d[0] = r * st * std::cos(ph);
    d[1] = r * st * std::sin(ph);
    d[2] = r * ct;
    return r < 1 ? -1.0 : 1.0;
  };
  auto f2 = [&](const double *a, const double *b) {
    const double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    return ao.f(dx * dx + dy * dy + dz * dz);
  };

  const long per = std::max(1L, (long) (nsamp / nblocks));
  std::vector<double> b3(nblocks), b4(nblocks);
  const double x1[3] = {0, 0, 0};
  for (long blk = 0; blk < nblocks; ++blk) {
    double s3 = 0, s4 = 0;
    for (long i = 0; i < per; ++i) {
      double d12[3], d23[3], d34[3], x2[3], x3[3], x4[3];
      const double s12 = bond(d12), s23 = bond(d23), s = s12 * s23 * bond(d34);
      for (int k = 0; k < 3; ++k) {
        x2[k] = d12[k];
        x3[k] = x2[k] + d23[k];
        x4[k] = x3[k] + d34[k];
      }
      const double f13 = f2(x1, x3), f14 = f2(x1, x4), f24 = f2(x2, x4);
      s3 += s12 * s23 * f13;    // B3 from the first two bonds: f12 f23 f13
      if (f14 != 0) s4 += s * f14 * (3 + 3 * (f13 + f24) + f13 * f24);
    }
    b3[blk] = -(1.0 / 3) * W * W * s3 / per;
    b4[blk] = -(1.0 / 8) * W * W * W * s4 / per;
  }
  auto stats = [&](const std::vector<double> &v, double &m, double &se) {
    m = 0;
    for (double a : v) m += a;
    m /= v.size();
    double s = 0;
    for (double a : v) s += (a - m) * (a - m);
    se = std::sqrt(s / (v.size() - 1) / v.size());
  };
  double m3, e3, m4, e4;
  stats(b3, m3, e3);
  stats(b4, m4, e4);
  const double b = 2 * PI / 3;
  std::printf("# mayer_b4 q %g depth %g samples %ld blocks %ld seed %llu  W %.12g (core %.12g)\n", q, depth,
              per * nblocks, nblocks, (unsigned long long) seed, W, Wc);
  std::printf("RESULT B2 %.10f B3 %.6f %.6f B4 %.5f %.5f  B2/b %.6f B3/b^2 %.6f %.6f B4/b^3 %.6f %.6f\n", B2, m3,
              e3, m4, e4, B2 / b, m3 / (b * b), e3 / (b * b), m4 / (b * b * b), e4 / (b * b * b));
  return 0;
}
