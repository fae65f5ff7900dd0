// hs_jet.h: directional derivatives of a radial function phi(|x + s w|),
// Hessian-vector products and V'''[w,w,.] in closed form, and r-derivatives
// by differences, against closed forms and brute-force differences.

#include "hs_jet.h"

#include "gtest/gtest.h"

#include <cmath>

using namespace HardSphere;

namespace {

// test potentials with exact r-derivatives phi^(k), k = 0..4
struct LJ {    // 4 (r^-12 - r^-6)
  void derivs(double r, double p[5]) const
  {
    double a[5], b[5];
    power_derivs(4.0, 12.0, r, a);
    power_derivs(-4.0, 6.0, r, b);
    for (int k = 0; k < 5; k++) p[k] = a[k] + b[k];
  }
};
struct Morse {    // D (1 - e^{-a (r - r0)})^2 = D (1 - 2 E + E^2), E = e^{-a (r-r0)}
  double D = 1.3, a = 1.7, r0 = 1.2;
  void derivs(double r, double p[5]) const
  {
    const double E = std::exp(-a * (r - r0));
    double m = 1.0;
    for (int k = 0; k < 5; k++) {
      // d^k/dr^k E = (-a)^k E, of E^2: (-2a)^k E^2
      p[k] = D * ((k == 0 ? 1.0 : 0.0) - 2.0 * m * E + std::pow(-2.0 * a, k) * E * E);
      m *= -a;
    }
  }
};

template <class P> double phi_at(const P &pot, const double *x)
{
  double p[5];
  pot.derivs(std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]), p);
  return p[0];
}

template <class P> void grad_at(const P &pot, const double *x, double g[3])
{
  const double r = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
  double p[5];
  pot.derivs(r, p);
  for (int k = 0; k < 3; k++) g[k] = p[1] * x[k] / r;
}

// the same potentials in long double, for brute force
long double lj_ld(long double r)
{
  const long double r6 = 1.0L / (r * r * r * r * r * r);
  return 4.0L * (r6 * r6 - r6);
}
long double morse_ld(long double r)
{
  const Morse m;
  const long double E = std::exp(-(long double) m.a * (r - (long double) m.r0));
  return (long double) m.D * (1.0L - E) * (1.0L - E);
}

// d^k/ds^k phi(|x + s w|): long-double O(h^4) central differences of phi
template <class F> double brute_directional(F phi, const double *x, const double *w, int k)
{
  auto f = [&](long double s) {
    long double y[3];
    for (int d = 0; d < 3; d++) y[d] = x[d] + s * w[d];
    return phi(std::sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]));
  };
  // steps balancing long-double round-off (1e-19/h^k) and truncation (h^4)
  const long double hs[5] = {0, 1e-4L, 3e-4L, 1e-3L, 2e-3L};
  const long double h = hs[k];
  switch (k) {
    case 1: return double((-f(2 * h) + 8 * f(h) - 8 * f(-h) + f(-2 * h)) / (12 * h));
    case 2:
      return double((-f(2 * h) + 16 * f(h) - 30 * f(0) + 16 * f(-h) - f(-2 * h)) / (12 * h * h));
    case 3:
      return double((-f(3 * h) + 8 * f(2 * h) - 13 * f(h) + 13 * f(-h) - 8 * f(-2 * h) +
                     f(-3 * h)) /
                    (8 * h * h * h));
    default:
      return double((-f(3 * h) + 12 * f(2 * h) - 39 * f(h) + 56 * f(0) - 39 * f(-h) +
                     12 * f(-2 * h) - f(-3 * h)) /
                    (6 * h * h * h * h));
  }
}

const double X[3] = {0.83, -0.41, 0.57};
const double W[3] = {0.31, 0.72, -0.44};
const double A[3] = {-0.6, 0.25, 0.9};

}    // namespace

// phi(r) = r^2: phi(|x + s w|) = r^2 + 2 s x.w + s^2 w.w exactly
TEST(Jet, SquareIsExact)
{
  const double r = std::sqrt(X[0] * X[0] + X[1] * X[1] + X[2] * X[2]);
  const double phi[5] = {r * r, 2 * r, 2.0, 0.0, 0.0};
  double out[5];
  radial_directional(X, W, phi, out);
  const double xw = X[0] * W[0] + X[1] * W[1] + X[2] * W[2];
  const double ww = W[0] * W[0] + W[1] * W[1] + W[2] * W[2];
  EXPECT_NEAR(out[0], r * r, 1e-15);
  EXPECT_NEAR(out[1], 2 * xw, 1e-14);
  EXPECT_NEAR(out[2], 2 * ww, 1e-14);
  EXPECT_NEAR(out[3], 0.0, 1e-13);
  EXPECT_NEAR(out[4], 0.0, 1e-12);
}

// w along x: phi(r + s |w|), derivatives phi^(k) |w|^k; w across x:
// rho = sqrt(r^2 + s^2 c^2): d2 = phi'/r c^2, d4 = 3 c^4 (phi''/r^2 - phi'/r^3)
TEST(Jet, ParallelAndPerpendicular)
{
  LJ lj;
  const double r = 1.13;
  const double x[3] = {r, 0, 0};
  double p[5];
  lj.derivs(r, p);
  const double wpar[3] = {0.7, 0, 0};
  double out[5];
  radial_directional(x, wpar, p, out);
  for (int k = 1; k <= 4; k++)
    EXPECT_NEAR(out[k], p[k] * std::pow(0.7, k), 1e-13 * std::fabs(p[k])) << k;
  const double c = 0.6;
  const double wperp[3] = {0, c, 0};
  radial_directional(x, wperp, p, out);
  EXPECT_NEAR(out[1], 0.0, 1e-12);
  EXPECT_NEAR(out[2], p[1] / r * c * c, 1e-12 * std::fabs(p[1]));
  EXPECT_NEAR(out[3], 0.0, 1e-10);
  EXPECT_NEAR(out[4], 3 * std::pow(c, 4) * (p[2] / (r * r) - p[1] / (r * r * r)),
              1e-12 * std::fabs(p[2]));
}

TEST(Jet, DirectionalMatchesBruteForce)
{
  Morse mo;
  LJ lj;
  double p[5], out[5];
  mo.derivs(std::sqrt(X[0] * X[0] + X[1] * X[1] + X[2] * X[2]), p);
  radial_directional(X, W, p, out);
  const double tol[5] = {0, 1e-11, 1e-10, 1e-9, 1e-8};    // relative
  for (int k = 1; k <= 4; k++)
    EXPECT_NEAR(out[k], brute_directional(morse_ld, X, W, k), tol[k] * (1 + std::fabs(out[k]))) << k;
  const double x2[3] = {0.9, 0.5, -0.3};    // r = 1.07: steep LJ repulsion
  lj.derivs(std::sqrt(x2[0] * x2[0] + x2[1] * x2[1] + x2[2] * x2[2]), p);
  radial_directional(x2, W, p, out);
  for (int k = 1; k <= 4; k++)
    EXPECT_NEAR(out[k], brute_directional(lj_ld, x2, W, k), tol[k] * (1 + std::fabs(out[k]))) << k;
}

// closed forms against differences of the gradient and each other
TEST(Jet, HessianAndThirdClosedForms)
{
  Morse mo;
  const double r = std::sqrt(X[0] * X[0] + X[1] * X[1] + X[2] * X[2]);
  double p[5], out[5];
  mo.derivs(r, p);
  double hw[3], tw[3];
  radial_hess_vec(X, p[1], p[2], W, hw);
  radial_third_ww(X, p[1], p[2], p[3], W, tw);
  radial_directional(X, W, p, out);

  // grad f(x + h w) - grad f(x - h w) over 2h -> H w
  const double h = 1e-5;
  double xp[3], xm[3], gp[3], gm[3];
  for (int k = 0; k < 3; k++) {
    xp[k] = X[k] + h * W[k];
    xm[k] = X[k] - h * W[k];
  }
  grad_at(mo, xp, gp);
  grad_at(mo, xm, gm);
  for (int k = 0; k < 3; k++) EXPECT_NEAR(hw[k], (gp[k] - gm[k]) / (2 * h), 1e-9) << k;

  // w.Hw = second directional derivative, a.H w = bilinear form
  EXPECT_NEAR(W[0] * hw[0] + W[1] * hw[1] + W[2] * hw[2], out[2], 1e-13);
  EXPECT_NEAR(A[0] * hw[0] + A[1] * hw[1] + A[2] * hw[2],
              radial_hess_bilinear(X, p[1], p[2], A, W), 1e-13);
  // tw.w = third directional derivative
  EXPECT_NEAR(W[0] * tw[0] + W[1] * tw[1] + W[2] * tw[2], out[3], 1e-12);

  // tw = grad (w^T H(x) w): difference of w.Hw along each axis
  for (int k = 0; k < 3; k++) {
    double y1[3] = {X[0], X[1], X[2]}, y2[3] = {X[0], X[1], X[2]};
    y1[k] += h;
    y2[k] -= h;
    double p1[5], p2[5], h1[3], h2[3];
    mo.derivs(std::sqrt(y1[0] * y1[0] + y1[1] * y1[1] + y1[2] * y1[2]), p1);
    mo.derivs(std::sqrt(y2[0] * y2[0] + y2[1] * y2[1] + y2[2] * y2[2]), p2);
    radial_hess_vec(y1, p1[1], p1[2], W, h1);
    radial_hess_vec(y2, p2[1], p2[2], W, h2);
    const double q1 = W[0] * h1[0] + W[1] * h1[1] + W[2] * h1[2];
    const double q2 = W[0] * h2[0] + W[1] * h2[1] + W[2] * h2[2];
    EXPECT_NEAR(tw[k], (q1 - q2) / (2 * h), 1e-8) << k;
  }
}

// phi'', phi''', phi'''' from phi' by the stencils of radial_derivs_fd
TEST(Jet, RadialDifferencesAccuracy)
{
  LJ lj;
  Morse mo;
  for (double r : {0.95, 1.12, 1.6, 2.4}) {
    double p[5], q[5] = {0, 0, 0, 0, 0};
    lj.derivs(r, p);
    auto dphi = [&](double rr) {
      double t[5];
      lj.derivs(rr, t);
      return t[1];
    };
    radial_derivs_fd(dphi, r, p[1], r / 16.0, 4, q);
    // relative to the sum of the two terms' magnitudes (they cancel at some r)
    double a[5], b[5];
    power_derivs(4.0, 12.0, r, a);
    power_derivs(4.0, 6.0, r, b);
    EXPECT_NEAR(q[2], p[2], 1e-11 * (a[2] + b[2])) << r;
    EXPECT_NEAR(q[3], p[3], 1e-9 * std::fabs(a[3] + b[3])) << r;
    EXPECT_NEAR(q[4], p[4], 1e-7 * (a[4] + b[4])) << r;

    mo.derivs(r, p);
    auto dmo = [&](double rr) {
      double t[5];
      mo.derivs(rr, t);
      return t[1];
    };
    radial_derivs_fd(dmo, r, p[1], r / 16.0, 4, q);
    const double sc = mo.D * std::pow(2 * mo.a, 4);
    EXPECT_NEAR(q[2], p[2], 1e-11 * sc) << r;
    EXPECT_NEAR(q[3], p[3], 1e-9 * sc) << r;
    // r/16 is a shorter length than Morse's 1/(2a): round-off dominates
    EXPECT_NEAR(q[4], p[4], 2e-5 * sc) << r;
  }
}

// near a cutoff rmax the stencils are backward: phi' is never asked for at
// or beyond rmax (pair_style table has no values there), and the
// derivatives keep O(h^4) accuracy (looser bounds: the one-sided
// coefficients carry ~7x the round-off)
TEST(Jet, RadialDifferencesBackwardNearCutoff)
{
  LJ lj;
  for (double r : {1.6, 2.4999}) {
    const double rmax = 2.5;
    double p[5], q[5] = {0, 0, 0, 0, 0};
    lj.derivs(r, p);
    double far = 0.0;
    auto dphi = [&](double rr) {
      far = std::max(far, rr);
      double t[5];
      lj.derivs(rr, t);
      return t[1];
    };
    radial_derivs_fd(dphi, r, p[1], r / 16.0, 4, q, r < 2.0 ? rmax : r + 1e-9);
    const double lim = r < 2.0 ? rmax : r + 1e-9;
    EXPECT_LT(far, lim) << r;
    double a[5], b[5];
    power_derivs(4.0, 12.0, r, a);
    power_derivs(4.0, 6.0, r, b);
    EXPECT_NEAR(q[2], p[2], 1e-10 * (a[2] + b[2])) << r;
    EXPECT_NEAR(q[3], p[3], 1e-8 * std::fabs(a[3] + b[3])) << r;
    EXPECT_NEAR(q[4], p[4], 1e-5 * (a[4] + b[4])) << r;
  }
}

// the closed form (Faa di Bruno) against the series, random directions
TEST(Jet, ClosedFormMatchesSeries)
{
  Morse mo;
  for (int t = 0; t < 20; t++) {
    const double x[3] = {std::sin(1.1 * t) + 0.2, std::cos(0.7 * t), 0.5 * std::sin(2.3 * t + 1)};
    const double w[3] = {std::cos(3.1 * t), std::sin(0.3 * t + 2), std::cos(1.9 * t + 0.5)};
    double p[5], a[5], b[5];
    mo.derivs(std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]), p);
    radial_directional(x, w, p, a);
    radial_directional_fdb(x, w, p, b);
    for (int k = 0; k < 5; k++) EXPECT_NEAR(a[k], b[k], 1e-12 * (1 + std::fabs(a[k]))) << t << " " << k;
  }
}

TEST(Jet, PowerDerivs)
{
  double p[5];
  power_derivs(2.0, 3.0, 1.5, p);
  EXPECT_NEAR(p[0], 2.0 / std::pow(1.5, 3), 1e-15);
  EXPECT_NEAR(p[1], -6.0 / std::pow(1.5, 4), 1e-14);
  EXPECT_NEAR(p[2], 24.0 / std::pow(1.5, 5), 1e-14);
  EXPECT_NEAR(p[3], -120.0 / std::pow(1.5, 6), 1e-13);
  EXPECT_NEAR(p[4], 720.0 / std::pow(1.5, 7), 1e-12);
}

TEST(Jet, ZeroDistanceIsNaN)
{
  const double x[3] = {0, 0, 0};
  const double p[5] = {1, 1, 1, 1, 1};
  double out[5];
  radial_directional(x, W, p, out);
  for (double o : out) EXPECT_TRUE(std::isnan(o));
}

// ---- the paper's H2 and H4 (section 3) on a 1-D anharmonic potential with
// a mass: one velocity Verlet step changes H_[4,VV] by O(h^7) (error ratio
// 2^7 when h is halved); with any one coefficient of H4 changed by 10% the
// change is O(h^5) (ratio 2^5), of H2 O(h^3). Long double throughout.

namespace {
// V = q^4/4 + q^3/3 + sin q, derivatives d[k] = V^(k)(q)
void vderivs(long double q, long double d[5])
{
  d[0] = q * q * q * q / 4 + q * q * q / 3 + std::sin(q);
  d[1] = q * q * q + q * q + std::cos(q);
  d[2] = 3 * q * q + 2 * q - std::sin(q);
  d[3] = 6 * q + 2 - std::cos(q);
  d[4] = 6 + std::sin(q);
}

// c: coefficients of H2 = c0 v V'' v + c1 V' M^-1 V',
// H4 = c2 V''''vvvv + c3 g V'' g + c4 (V''v) M^-1 (V''v) + c5 V'''[g,v,v]
long double hmod(const long double c[6], long double q, long double p, long double m,
                 long double h)
{
  long double d[5];
  vderivs(q, d);
  const long double v = p / m, g = d[1] / m;
  const long double H = p * p / (2 * m) + d[0];
  const long double H2 = c[0] * v * d[2] * v + c[1] * d[1] * d[1] / m;
  const long double H4 = c[2] * d[4] * v * v * v * v + c[3] * g * d[2] * g +
      c[4] * (d[2] * v) * (d[2] * v) / m + c[5] * d[3] * g * v * v;
  return H + h * h / 24 * H2 + h * h * h * h / 720 * H4;
}

long double step_change(const long double c[6], long double h)
{
  const long double m = 1.3L, q = 0.3L, p = 0.7L;
  long double d[5];
  vderivs(q, d);
  const long double ph = p - h / 2 * d[1];
  const long double q1 = q + h * ph / m;
  vderivs(q1, d);
  const long double p1 = ph - h / 2 * d[1];
  return hmod(c, q1, p1, m, h) - hmod(c, q, p, m, h);
}
}    // namespace

TEST(Jet, PaperModifiedHamiltonianOrders)
{
  const long double paper[6] = {2, -1, -1, -3, 12, 6};
  // h = 0.02: the O(h^8) term still shifts the log-ratio by about +0.1;
  // much smaller h meets long-double round-off (1e-19)
  const long double h = 0.02L;
  const double r = double(step_change(paper, h) / step_change(paper, h / 2));
  EXPECT_NEAR(std::log2(std::fabs(r)), 7.0, 0.3) << "paper's H2, H4: O(h^7) per step";
  for (int k = 0; k < 6; k++) {
    long double c[6];
    for (int i = 0; i < 6; i++) c[i] = paper[i];
    c[k] *= 1.1L;
    const double rk = double(step_change(c, h) / step_change(c, h / 2));
    const double expect = (k < 2) ? 3.0 : 5.0;
    EXPECT_NEAR(std::log2(std::fabs(rk)), expect, 0.3) << "coefficient " << k << " changed";
  }
}
