// hs_lj_terms.h: a member's static lj/cut terms four at a time. Against
// references written here: the geometry and lj/cut's phi, phi' (as
// PairLJCut::single() computes energy and force) and phi'', phi''', phi''''
// with every operation forced one at a time in the kernel's order, to the
// bit; the derivatives also against the analytic ones of 4 eps [(s/r)^12 -
// (s/r)^6] in long double, to round-off; the AVX2 versions against the
// scalar ones for every length mod 4 and every order; and
// hs_cluster_gauss.h's forces, field, Jacobian and energy the same bits
// whether its Phi names its lj/cut terms (the batched path) or not.

#include "hs_cluster_gauss.h"
#include "hs_lj_terms.h"

#include "gtest/gtest.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

using namespace HardSphere;

namespace {

// one operation at a time (no contraction, no reordering)
double op(double v)
{
  volatile double t = v;
  return t;
}

bool same_bits(double a, double b)
{
  return std::memcmp(&a, &b, sizeof(double)) == 0;
}

struct Terms {
  int n = 0;
  double q[3];
  std::vector<double> bx, by, bz, fl, coef;    // coef: 5 per term
  std::vector<const double *> c;
};

// n static atoms at 0.85 .. 2.6 from q in random directions, coefficients
// of eps in [0.5, 1.5], sigma in [0.9, 1.1], special factors 1, 0.5, 1/1.2 or 0
Terms make(std::mt19937 &g, int n)
{
  std::uniform_real_distribution<double> U(0.0, 1.0);
  Terms t;
  t.n = n;
  for (double &v : t.q) v = 10.0 * U(g) - 5.0;
  t.coef.resize(5 * n);
  for (int k = 0; k < n; k++) {
    double u[3], s = 0.0;
    for (double &v : u) {
      v = U(g) - 0.5;
      s += v * v;
    }
    const double r = 0.85 + 1.75 * U(g), f = r / std::sqrt(s);
    t.bx.push_back(t.q[0] - f * u[0]);
    t.by.push_back(t.q[1] - f * u[1]);
    t.bz.push_back(t.q[2] - f * u[2]);
    const double eps = 0.5 + U(g), sig = 0.9 + 0.2 * U(g);
    const double s6 = std::pow(sig, 6.0), s12 = s6 * s6;
    double *c = &t.coef[5 * k];
    c[0] = 48.0 * eps * s12;
    c[1] = 24.0 * eps * s6;
    c[2] = 4.0 * eps * s12;
    c[3] = 4.0 * eps * s6;
    c[4] = 0.1 * U(g);
    // (0.5 and 1 scale exactly: 1/1.2, AMBER's 1-4 factor, does not)
    const double fls[4] = {1.0, 0.5, 1.0 / 1.2, 0.0};
    t.fl.push_back(fls[(int) (4.0 * U(g)) % 4]);
  }
  for (int k = 0; k < n; k++) t.c.push_back(&t.coef[5 * k]);
  return t;
}

// the reference geometry: x = q - xb, r = sqrt((x0 x0 + x1 x1) + x2 x2),
// ir = 1 / r, e = x ir
void geometry_ref(const Terms &t, int k, double &r, double &ir, double e[3])
{
  const double x0 = op(t.q[0] - t.bx[k]), x1 = op(t.q[1] - t.by[k]), x2 = op(t.q[2] - t.bz[k]);
  const double s = op(op(op(x0 * x0) + op(x1 * x1)) + op(x2 * x2));
  r = op(std::sqrt(s));
  ir = op(1.0 / r);
  e[0] = op(x0 * ir);
  e[1] = op(x1 * ir);
  e[2] = op(x2 * ir);
}

// the reference phi^(k): single()'s energy and force, the higher ones from
// the same r2inv and r6inv (c12 = fl lj3 r6inv^2, c6 = -fl lj4 r6inv)
void phi_ref(const double *c, double fl, double r, int order, double d[5])
{
  const double rsq = op(r * r);
  const double r2inv = op(1.0 / rsq);
  const double r6inv = op(op(r2inv * r2inv) * r2inv);
  const double forcelj = op(r6inv * op(op(c[0] * r6inv) - c[1]));
  const double fforce = op(op(fl * forcelj) * r2inv);
  const double philj = op(op(r6inv * op(op(c[2] * r6inv) - c[3])) - c[4]);
  d[0] = op(fl * philj);
  d[1] = op(-fforce * r);
  d[2] = d[3] = d[4] = 0.0;
  if (order < 2) return;
  const double c12 = op(op(op(fl * c[2]) * r6inv) * r6inv);
  const double c6 = op(op(-fl * c[3]) * r6inv);
  d[2] = op(op(op(156.0 * c12) + op(42.0 * c6)) * r2inv);
  const double r4inv = op(r2inv * r2inv);
  if (order >= 3) d[3] = op(op(op(-2184.0 * c12) - op(336.0 * c6)) * op(r4inv * r));
  if (order >= 4) d[4] = op(op(op(32760.0 * c12) + op(3024.0 * c6)) * r4inv);
}

using GeomFn = void (*)(const double *, int, const double *, const double *, const double *,
                        double *, double *, double *, double *, double *);
using PhiFn = void (*)(const double *, int, const double *const *, const double *, int,
                       double *);

void check_geometry(GeomFn fn, const char *name)
{
  std::mt19937 g(11);
  for (int n = 0; n <= 13; n++) {
    const Terms t = make(g, n);
    std::vector<double> r(n), ir(n), ex(n), ey(n), ez(n);
    fn(t.q, n, t.bx.data(), t.by.data(), t.bz.data(), r.data(), ir.data(), ex.data(), ey.data(),
       ez.data());
    for (int k = 0; k < n; k++) {
      double rr, i, e[3];
      geometry_ref(t, k, rr, i, e);
      EXPECT_TRUE(same_bits(r[k], rr)) << name << " n " << n << " term " << k;
      EXPECT_TRUE(same_bits(ir[k], i)) << name << " n " << n << " term " << k;
      EXPECT_TRUE(same_bits(ex[k], e[0]) && same_bits(ey[k], e[1]) && same_bits(ez[k], e[2]))
          << name << " n " << n << " term " << k;
    }
  }
}

void check_phi(PhiFn fn, const char *name)
{
  std::mt19937 g(12);
  for (int order = 2; order <= 4; order++)
    for (int n = 0; n <= 13; n++) {
      const Terms t = make(g, n);
      std::vector<double> r(n), p(5 * n, -1.0);
      for (int k = 0; k < n; k++) r[k] = 0.85 + 1.75 * (k + 0.5) / (n + 1);
      fn(r.data(), n, t.c.data(), t.fl.data(), order, p.data());
      for (int k = 0; k < n; k++) {
        double d[5];
        phi_ref(t.c[k], t.fl[k], r[k], order, d);
        for (int j = 0; j < 5; j++)
          EXPECT_TRUE(same_bits(p[j * n + k], d[j]))
              << name << " order " << order << " n " << n << " term " << k << " phi^" << j << " "
              << p[j * n + k] << " vs " << d[j];
      }
    }
}

}    // namespace

TEST(LJTerms, GeometryScalarMatchesReference)
{
  check_geometry(static_geometry_scalar, "scalar");
}

TEST(LJTerms, GeometryDispatchMatchesReference)
{
  check_geometry(static_geometry, "dispatch");
}

TEST(LJTerms, PhiScalarMatchesReference)
{
  check_phi(lj_phi_scalar, "scalar");
}

TEST(LJTerms, PhiDispatchMatchesReference)
{
  check_phi(lj_phi, "dispatch");
}

#ifdef HS_LJ_TERMS_AVX2
TEST(LJTerms, Avx2MatchesReference)
{
  if (!__builtin_cpu_supports("avx2")) GTEST_SKIP() << "no AVX2 on this processor";
  check_geometry(static_geometry_avx2, "avx2");
  check_phi(lj_phi_avx2, "avx2");
}
#endif

// the derivatives are lj/cut's: phi^(k) of fl (4 eps [(s/r)^12 - (s/r)^6]
// - offset), from d^k/dr^k r^-m = (-m)(-m-1)...(-m-k+1) r^-m-k in long
// double, to a relative 1e-13 of the largest of the two power terms
TEST(LJTerms, DerivativesAreLJs)
{
  std::mt19937 g(13);
  const Terms t = make(g, 9);
  std::vector<double> r(9), p(45);
  for (int k = 0; k < 9; k++) r[k] = 0.85 + 0.2 * k;
  lj_phi(r.data(), 9, t.c.data(), t.fl.data(), 4, p.data());
  for (int k = 0; k < 9; k++) {
    const long double a12 = (long double) t.fl[k] * t.c[k][2],
                      a6 = (long double) t.fl[k] * t.c[k][3], rr = r[k];
    for (int j = 0; j <= 4; j++) {
      long double f12 = 1.0L, f6 = 1.0L;
      for (int i = 0; i < j; i++) {
        f12 *= -(12.0L + i);
        f6 *= -(6.0L + i);
      }
      const long double t12 = a12 * f12 * std::pow(rr, -12.0L - j),
                        t6 = a6 * f6 * std::pow(rr, -6.0L - j);
      long double exact = t12 - t6;
      if (j == 0) exact -= (long double) t.fl[k] * t.c[k][4];
      const double scale = (double) std::max(std::fabs(t12), std::fabs(t6)) + 1e-300;
      EXPECT_LE(std::fabs(p[j * 9 + k] - (double) exact), 1e-13 * scale)
          << "term " << k << " phi^" << j;
    }
  }
}

namespace {
// two radial functions with the same values: lj/cut terms by kind, and
// every fifth kind (k % 5 == 3) a harmonic bond 300 (r - 0.97)^2 written up
// to the order asked for; one names its lj/cut terms to ClusterGauss
// (lj_coef(): the batched path, the bonds after it), the other does not
// (each term by operator())
bool is_bond(int k)
{
  return k % 5 == 3;
}
struct PlainPhi {
  const std::vector<const double *> *c;
  const std::vector<double> *fl;
  void operator()(int k, double r, int order, double *d) const
  {
    if (!is_bond(k)) {
      lj_cut_phi04((*c)[k], (*fl)[k], r * r, r, order, d);
      return;
    }
    const double dr = r - 0.97;
    d[0] = 300.0 * dr * dr;
    d[1] = 600.0 * dr;
    if (order >= 2) d[2] = 600.0;
    if (order >= 3) d[3] = 0.0;
    if (order >= 4) d[4] = 0.0;
  }
};
struct NamingPhi : PlainPhi {
  const double *lj_coef(int k, double &f) const
  {
    f = (*fl)[k];
    return is_bond(k) ? nullptr : (*c)[k];
  }
};
static_assert(!PhiNamesLJ<PlainPhi>::value && PhiNamesLJ<NamingPhi>::value,
              "PhiNamesLJ detects lj_coef()");
}    // namespace

TEST(LJTerms, ClusterGaussSameBitsBatchedOrNot)
{
  std::mt19937 g(14);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  // three members in a row 1.05 apart, each with 5..11 static atoms (all
  // lengths mod 4; bonds among them), a pair term between members 0 and 1
  const int n = 3;
  const Terms all = make(g, 30);
  std::vector<ClusterTerm> terms;
  {
    ClusterTerm t;
    t.a = 0;
    t.b = 1;
    t.kind = 0;
    terms.push_back(t);
  }
  int k = 1;
  for (int a = 0; a < n; a++)
    for (int s = 0; s < 5 + 3 * a; s++, k++) {
      ClusterTerm t;
      t.a = a;
      t.b = -1;
      t.kind = k;
      t.partner = k % 4 == 0 ? -1 : k;
      // around member a's position (1.05 a, 0, 0)
      t.xb[0] = 1.05 * a + (all.bx[k] - all.q[0]);
      t.xb[1] = all.by[k] - all.q[1];
      t.xb[2] = all.bz[k] - all.q[2];
      terms.push_back(t);
    }
  const double im[3] = {1.0, 0.5, 2.0}, fc[9] = {0.1, 0, 0, 0, 0.2, 0, 0, 0, -0.1};
  PlainPhi plain{&all.c, &all.fl};
  NamingPhi naming;
  naming.c = &all.c;
  naming.fl = &all.fl;
  ClusterGauss<PlainPhi> A(n, im, fc, 1e-5, terms, plain);
  ClusterGauss<NamingPhi> B(n, im, fc, 1e-5, terms, naming);
  std::vector<double> y(6 * n);
  for (int a = 0; a < n; a++) {
    y[3 * a] = 1.05 * a + 0.02 * (U(g) - 0.5);
    y[3 * a + 1] = 0.02 * (U(g) - 0.5);
    y[3 * a + 2] = 0.02 * (U(g) - 0.5);
  }
  for (int r = 3 * n; r < 6 * n; r++) y[r] = U(g) - 0.5;
  const int N = 6 * n;
  std::vector<double> ka(N), kb(N), pa(3 * 40, 0.0), pb(3 * 40, 0.0);
  Eigen::MatrixXd Ja, Jb;
  A.field(y.data(), ka.data(), nullptr, pa.data());
  B.field(y.data(), kb.data(), nullptr, pb.data());
  for (int r = 0; r < N; r++) EXPECT_TRUE(same_bits(ka[r], kb[r])) << "field " << r;
  for (size_t r = 0; r < pa.size(); r++) EXPECT_TRUE(same_bits(pa[r], pb[r])) << "partner " << r;
  A.field(y.data(), ka.data(), &Ja);
  B.field(y.data(), kb.data(), &Jb);
  for (int r = 0; r < N; r++)
    for (int c = 0; c < N; c++) EXPECT_TRUE(same_bits(Ja(r, c), Jb(r, c))) << r << "," << c;
  EXPECT_TRUE(same_bits(A.energy(y.data()), B.energy(y.data())));
  // and one Gauss step
  std::vector<double> ya(N), yb(N);
  A.step(y.data(), 0.004, ya.data());
  B.step(y.data(), 0.004, yb.data());
  for (int r = 0; r < N; r++) EXPECT_TRUE(same_bits(ya[r], yb[r])) << "step " << r;
}

// a member's static field (ClusterGauss::static_field()'s arithmetic):
// its sums and its partners' forces against a reference with every
// operation forced, in the same order (each sum from its start value in term
// order), for every length mod 4, with and without the partners' rows
TEST(LJTerms, StaticFieldTermsMatchReference)
{
  std::mt19937 g(15);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  const double w[3] = {0.3, -1.2, 0.7}, ar[3] = {5.0, 2.5, -11.0}, c = 2.1e-6;
  const double ww = op(op(op(w[0] * w[0]) + op(w[1] * w[1])) + op(w[2] * w[2]));
  using Fn = void (*)(int, const double *, const double *, const double *, const double *,
                      const double *, const double *, const double *, const double *,
                      const double *, double, double, double *, double *);
  std::vector<std::pair<Fn, const char *>> fns = {{static_field_terms_scalar, "scalar"},
                                                  {static_field_terms, "dispatch"}};
#ifdef HS_LJ_TERMS_AVX2
  if (__builtin_cpu_supports("avx2")) fns.emplace_back(static_field_terms_avx2, "avx2");
#endif
  for (int n = 0; n <= 13; n++) {
    std::vector<double> p1(n), p2(n), p3(n), ir(n), ex(n), ey(n), ez(n);
    for (int t = 0; t < n; t++) {
      p1[t] = 10.0 * U(g);
      p2[t] = 100.0 * U(g);
      p3[t] = 1000.0 * U(g);
      ir[t] = 1.0 / (1.5 + U(g));
      double e[3], s = 0.0;
      for (double &v : e) {
        v = U(g);
        s += v * v;
      }
      ex[t] = e[0] / std::sqrt(s);
      ey[t] = e[1] / std::sqrt(s);
      ez[t] = e[2] / std::sqrt(s);
    }
    // start values of the sums: a caller's running sums continue
    double start[STATIC_FIELD_SUMS];
    for (double &v : start) v = U(g);
    // the reference: per term the products, added to each sum in term order
    double ref_sum[STATIC_FIELD_SUMS];
    std::copy(start, start + STATIC_FIELD_SUMS, ref_sum);
    std::vector<double> ref_partner(3 * n);
    for (int t = 0; t < n; t++) {
      const double B = op(p1[t] * ir[t]), A = op(p2[t] - B);
      const double Bp = op(A * ir[t]), Ap = op(p3[t] - Bp);
      const double s = op(op(op(ex[t] * w[0]) + op(ey[t] * w[1])) + op(ez[t] * w[2]));
      const double sa = op(op(op(ex[t] * ar[0]) + op(ey[t] * ar[1])) + op(ez[t] * ar[2]));
      const double cAs2 = op(op(op(2.0 * A) * s) * ir[t]);
      const double ce = op(op(op(op(Ap * s) * s) + op(Bp * ww)) - op(cAs2 * s));
      const double Asa = op(A * sa), As = op(A * s);
      const double ke = op(p1[t] + op(c * op(ce + Asa))), kw = op(c * cAs2), ka = op(c * B);
      const double e[3] = {ex[t], ey[t], ez[t]};
      for (int d = 0; d < 3; d++) {
        ref_sum[SF_AS_E + d] = op(ref_sum[SF_AS_E + d] + op(As * e[d]));
        ref_sum[SF_CE_E + d] = op(ref_sum[SF_CE_E + d] + op(ce * e[d]));
        ref_sum[SF_ASA_E + d] = op(ref_sum[SF_ASA_E + d] + op(Asa * e[d]));
        ref_partner[d * n + t] = op(op(op(ke * e[d]) + op(kw * w[d])) + op(ka * ar[d]));
      }
      ref_sum[SF_B] = op(ref_sum[SF_B] + B);
      ref_sum[SF_CAS2] = op(ref_sum[SF_CAS2] + cAs2);
    }
    const int used[11] = {SF_AS_E,  SF_AS_E + 1,  SF_AS_E + 2,  SF_B,         SF_CE_E,    SF_CE_E + 1,
                          SF_CE_E + 2, SF_CAS2, SF_ASA_E, SF_ASA_E + 1, SF_ASA_E + 2};
    for (auto [fn, name] : fns)
      for (bool with_partner : {true, false}) {
        double sum[STATIC_FIELD_SUMS];
        std::copy(start, start + STATIC_FIELD_SUMS, sum);
        std::vector<double> partner(3 * n, -7.0);
        fn(n, p1.data(), p2.data(), p3.data(), ir.data(), ex.data(), ey.data(), ez.data(), w,
           ar, ww, c, sum, with_partner ? partner.data() : nullptr);
        for (int k : used)
          EXPECT_TRUE(same_bits(sum[k], ref_sum[k])) << name << " n " << n << " sum " << k;
        for (int k = 0; k < 3 * n; k++)
          EXPECT_TRUE(same_bits(partner[k], with_partner ? ref_partner[k] : -7.0))
              << name << " n " << n << " partner row " << k / std::max(n, 1) << " term "
              << k % std::max(n, 1) << (with_partner ? "" : " (not asked: untouched)");
      }
  }
}

// a member's static terms' energy and force (ClusterGauss::static_terms()
// without the Jacobian) against the sums with every operation forced, each
// continued in term order from its start value, for every length mod 4
TEST(LJTerms, StaticForceSumsMatchReference)
{
  std::mt19937 g(16);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  using Fn = void (*)(int, const double *, const double *, const double *, const double *,
                      const double *, double *);
  std::vector<std::pair<Fn, const char *>> fns = {{static_force_sums_scalar, "scalar"},
                                                  {static_force_sums, "dispatch"}};
#ifdef HS_LJ_TERMS_AVX2
  if (__builtin_cpu_supports("avx2")) fns.emplace_back(static_force_sums_avx2, "avx2");
#endif
  for (int n = 0; n <= 13; n++) {
    std::vector<double> p0(n), p1(n), ex(n), ey(n), ez(n);
    for (int t = 0; t < n; t++) {
      p0[t] = 3.0 * U(g);
      p1[t] = 50.0 * U(g);
      ex[t] = U(g);
      ey[t] = U(g);
      ez[t] = U(g);
    }
    const double start[4] = {U(g), U(g), U(g), U(g)};
    double ref[4] = {start[0], start[1], start[2], start[3]};
    for (int t = 0; t < n; t++) {
      ref[0] = op(ref[0] + p0[t]);
      ref[1] = op(ref[1] - op(p1[t] * ex[t]));
      ref[2] = op(ref[2] - op(p1[t] * ey[t]));
      ref[3] = op(ref[3] - op(p1[t] * ez[t]));
    }
    for (auto [fn, name] : fns) {
      double acc[4] = {start[0], start[1], start[2], start[3]};
      fn(n, p0.data(), p1.data(), ex.data(), ey.data(), ez.data(), acc);
      for (int k = 0; k < 4; k++)
        EXPECT_TRUE(same_bits(acc[k], ref[k])) << name << " n " << n << " sum " << k;
    }
  }
}
