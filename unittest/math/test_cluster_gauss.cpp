// Unit tests for src/HARDSPHERE/hs_cluster_gauss.h: the Gauss-Legendre flow
// of one cluster's modified Hamiltonian H~ (Bond & Leimkuhler 2007, section
// 3, restricted to the cluster; issue 21), its stage equations by full
// Newton on the exact Jacobian, alpha-hat and contact times on the flow.
//
// Expected values, none from the kernel's own output:
// - the field is the Hamiltonian vector field of H~, with H~ written here
//   independently (its own V, gradient and Hessian of the radial terms) and
//   differentiated by a fourth-order central difference;
// - the Jacobian equals central differences of the field;
// - the method is of classical order 4 (fitted slope >= 3.8 against a
//   classical RK4 reference with a tiny step, an independent method), and
//   H~'s error over a fixed time falls at fourth order (>= 3.6);
// - Newton converges quadratically: a handful of iterations per step, each
//   error about the square of the last (rate >= 1.6 in the log);
// - alpha-hat keeps the test's H~ to round-off and, with c = 0, is the
//   elastic impulse (the normal relative velocity reversed);
// - the contact time on the flow is where the test's fine RK4 integration
//   of the same field finds the gap closing, to the Gauss step's O(t^5).

#include "hs_cluster_gauss.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <vector>

using namespace HardSphere;

namespace {

// kind 0: 4 (r^-12 - r^-6) (LJ, epsilon = sigma = 1); kind 1: spring
// 20/2 (r - 1.2)^2; kind 2: 30/2 r^2; phi^(k), k = 0..4
void phi(int kind, double r, int, double *d)
{
  if (kind == 0) {
    const double i = 1.0 / r, i2 = i * i, i6 = i2 * i2 * i2, i12 = i6 * i6;
    d[0] = 4.0 * (i12 - i6);
    d[1] = 4.0 * (-12.0 * i12 + 6.0 * i6) * i;
    d[2] = 4.0 * (156.0 * i12 - 42.0 * i6) * i2;
    d[3] = 4.0 * (-2184.0 * i12 + 336.0 * i6) * i2 * i;
    d[4] = 4.0 * (32760.0 * i12 - 3024.0 * i6) * i2 * i2;
  } else if (kind == 2) {    // k/2 r^2: V quadratic in q
    const double k = 30.0;
    d[0] = 0.5 * k * r * r;
    d[1] = k * r;
    d[2] = k;
    d[3] = 0.0;
    d[4] = 0.0;
  } else {
    const double k = 20.0, r0 = 1.2;
    d[0] = 0.5 * k * (r - r0) * (r - r0);
    d[1] = k * (r - r0);
    d[2] = k;
    d[3] = 0.0;
    d[4] = 0.0;
  }
}
using PhiFn = void (*)(int, double, int, double *);
using Cluster = ClusterGauss<PhiFn>;

// three members (masses 1, 2, 1.5) held together by springs, LJ between
// members 0 and 1, two static partners (LJ on member 0, spring on 2), a
// constant force on member 1
struct Scene {
  int n = 3;
  std::vector<double> im = {1.0, 0.5, 1.0 / 1.5};
  std::vector<double> fc = {0.0, 0.0, 0.0, 0.3, -0.2, 0.1, 0.0, 0.0, 0.0};
  std::vector<ClusterTerm> terms;
  std::vector<double> y0;
  Scene()
  {
    auto add = [&](int a, int b, int kind, std::array<double, 3> xb = {0, 0, 0}) {
      ClusterTerm t;
      t.a = a;
      t.b = b;
      t.kind = kind;
      for (int d = 0; d < 3; d++) t.xb[d] = xb[d];
      terms.push_back(t);
    };
    add(0, 1, 0);
    add(0, 1, 1);
    add(1, 2, 1);
    add(0, 2, 1);
    add(0, -1, 0, {-1.15, 0.2, 0.1});
    add(2, -1, 1, {0.6, 2.3, -0.1});
    y0 = {0.0, 0.0, 0.0, 1.12, 0.1, 0.05, 0.5, 1.05, 0.2,    // q
          0.4, -0.3, 0.2, -0.5, 0.6, 0.1, 0.2, 0.3, -0.7};    // v
  }
  Cluster make(double c) const { return Cluster(n, im.data(), fc.data(), c, terms, &phi); }
};

// the test's own H~: V and its derivatives written out per term
struct RefH {
  const Scene &s;
  double c;
  double operator()(const std::vector<double> &y) const
  {
    const int m = 3 * s.n;
    double V = 0.0;
    std::vector<double> g(m, 0.0);    // grad V
    std::vector<std::vector<double>> Hm(m, std::vector<double>(m, 0.0));
    for (int i = 0; i < m; i++) {
      V -= s.fc[i] * y[i];
      g[i] -= s.fc[i];
    }
    for (const ClusterTerm &t : s.terms) {
      double x[3];
      for (int d = 0; d < 3; d++) x[d] = y[3 * t.a + d] - (t.b >= 0 ? y[3 * t.b + d] : t.xb[d]);
      const double r = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
      double p[5];
      phi(t.kind, r, 4, p);
      V += p[0];
      double h[3][3];
      for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++)
          h[a][b] = p[2] * x[a] * x[b] / (r * r) +
              p[1] / r * ((a == b ? 1.0 : 0.0) - x[a] * x[b] / (r * r));
      for (int a = 0; a < 3; a++) {
        g[3 * t.a + a] += p[1] * x[a] / r;
        if (t.b >= 0) g[3 * t.b + a] -= p[1] * x[a] / r;
        for (int b = 0; b < 3; b++) {
          Hm[3 * t.a + a][3 * t.a + b] += h[a][b];
          if (t.b >= 0) {
            Hm[3 * t.b + a][3 * t.b + b] += h[a][b];
            Hm[3 * t.a + a][3 * t.b + b] -= h[a][b];
            Hm[3 * t.b + a][3 * t.a + b] -= h[a][b];
          }
        }
      }
    }
    double T = 0.0, vHv = 0.0, gMg = 0.0;
    for (int i = 0; i < m; i++) {
      const double mi = 1.0 / s.im[i / 3];
      T += 0.5 * mi * y[m + i] * y[m + i];
      gMg += g[i] * g[i] / mi;
      for (int j = 0; j < m; j++) vHv += y[m + i] * Hm[i][j] * y[m + j];
    }
    return T + V + c * vHv - 0.5 * c * gMg;
  }
};

// fourth-order central difference of f along coordinate k
template <class F> double diff4(const F &f, std::vector<double> y, int k, double e)
{
  const double y0 = y[k];
  auto at = [&](double dx) {
    y[k] = y0 + dx;
    return f(y);
  };
  return (8.0 * (at(e) - at(-e)) - (at(2 * e) - at(-2 * e))) / (12.0 * e);
}

double maxabs(const std::vector<double> &a)
{
  double m = 0.0;
  for (double v : a) m = std::max(m, std::fabs(v));
  return m;
}

// classical RK4 of the kernel's field (the independent reference method)
void rk4(const Cluster &C, std::vector<double> &y, double h, int nsteps)
{
  const int N = C.dim();
  std::vector<double> k1(N), k2(N), k3(N), k4(N), t(N);
  for (int s = 0; s < nsteps; s++) {
    C.field(y.data(), k1.data());
    for (int i = 0; i < N; i++) t[i] = y[i] + 0.5 * h * k1[i];
    C.field(t.data(), k2.data());
    for (int i = 0; i < N; i++) t[i] = y[i] + 0.5 * h * k2[i];
    C.field(t.data(), k3.data());
    for (int i = 0; i < N; i++) t[i] = y[i] + h * k3[i];
    C.field(t.data(), k4.data());
    for (int i = 0; i < N; i++) y[i] += h / 6.0 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
  }
}

TEST(ClusterGauss, FieldIsTheHamiltonianVectorFieldOfModifiedEnergy)
{
  Scene s;
  for (double c : {0.0, 0.004}) {    // c = dt^2/12: dt = 0 and dt ~ 0.22 (terms visible)
    const Cluster C = s.make(c);
    const RefH H{s, c};
    EXPECT_NEAR(C.energy(s.y0.data()), H(s.y0), 1e-12 * std::fabs(H(s.y0)) + 1e-12);
    const int m = 3 * s.n;
    std::vector<double> k(2 * m), ref(2 * m);
    C.field(s.y0.data(), k.data());
    // dq/dt = M^-1 dH/dv, dv/dt = -M^-1 dH/dq (v = M^-1 p)
    for (int i = 0; i < m; i++) {
      ref[i] = s.im[i / 3] * diff4(H, s.y0, m + i, 1e-3);
      ref[m + i] = -s.im[i / 3] * diff4(H, s.y0, i, 1e-4);
    }
    const double scale = maxabs(ref);
    for (int i = 0; i < 2 * m; i++)
      EXPECT_NEAR(k[i], ref[i], 2e-7 * scale) << "c " << c << " component " << i;
    // the modified part is really there
    if (c > 0.0) {
      std::vector<double> k0(2 * m);
      s.make(0.0).field(s.y0.data(), k0.data());
      double dmax = 0.0;
      for (int i = 0; i < 2 * m; i++) dmax = std::max(dmax, std::fabs(k[i] - k0[i]));
      EXPECT_GT(dmax, 1e3 * 2e-7 * scale);
    }
  }
}

// several static terms per member, in no order, most with partners (the
// engine's clusters: nearly every term is static): the field is still H~'s
// (the kernel sums a member's static terms by coefficient, not term by
// term), and the partners' forces that a field gathers balance the
// members' dp/dt: sum over members of M dv/dt + sum of partner forces =
// sum fc (momentum, as each term's force on its partner is minus its part)
TEST(ClusterGauss, ManyStaticTermsFieldAndPartnerForces)
{
  Scene s;
  auto add = [&](int a, int kind, std::array<double, 3> xb, int partner) {
    ClusterTerm t;
    t.a = a;
    t.b = -1;
    t.kind = kind;
    t.partner = partner;
    for (int d = 0; d < 3; d++) t.xb[d] = xb[d];
    s.terms.push_back(t);
  };
  add(1, 0, {2.2, 0.3, -0.2}, 0);
  add(0, 1, {-0.3, -1.1, 0.4}, 1);
  add(1, 1, {1.0, -1.0, 0.6}, 1);
  add(0, 0, {0.2, -0.4, -1.2}, 2);
  add(2, 0, {0.4, 2.2, 0.9}, 0);
  for (ClusterTerm &t : s.terms)
    if (t.b < 0 && t.partner < 0) t.partner = 3;
  // the first term static, then one between members: no grouping given
  std::swap(s.terms[0], s.terms[4]);
  const double c = 0.004;
  const Cluster C = s.make(c);
  const RefH H{s, c};
  EXPECT_NEAR(C.energy(s.y0.data()), H(s.y0), 1e-12 * std::fabs(H(s.y0)) + 1e-12);
  const int m = 3 * s.n;
  std::vector<double> k(2 * m), ref(2 * m), pf(3 * 4, 0.0);
  C.field(s.y0.data(), k.data(), nullptr, pf.data());
  for (int i = 0; i < m; i++) {
    ref[i] = s.im[i / 3] * diff4(H, s.y0, m + i, 1e-3);
    ref[m + i] = -s.im[i / 3] * diff4(H, s.y0, i, 1e-4);
  }
  const double scale = maxabs(ref);
  for (int i = 0; i < 2 * m; i++) EXPECT_NEAR(k[i], ref[i], 2e-7 * scale) << "component " << i;
  double fscale = 0.0;
  for (int d = 0; d < 3; d++) {
    double sum = 0.0;
    for (int i = 0; i < s.n; i++) {
      sum += k[m + 3 * i + d] / s.im[i] - s.fc[3 * i + d];
      fscale = std::max(fscale, std::fabs(k[m + 3 * i + d] / s.im[i]));
    }
    for (int p = 0; p < 4; p++) sum += pf[3 * p + d];
    EXPECT_NEAR(sum, 0.0, 1e-13 * fscale) << "momentum component " << d;
  }
  // and every partner took a force (each has a term within reach)
  for (int p = 0; p < 4; p++)
    EXPECT_GT(std::fabs(pf[3 * p]) + std::fabs(pf[3 * p + 1]) + std::fabs(pf[3 * p + 2]), 1e-6)
        << "partner " << p;
}

// a step's partners' forces (ClusterStepDetail::pf1, pf2) are those of its
// last iteration, also where the cold predictor is already the solution:
// two members tied to static partners by V_t = k/2 |q_a - x_b|^2 (V'''
// = 0: the leading Jacobian and the predictor's linear model are exact, and
// the first iteration's change is round-off; the kernel, which skips the
// partners' forces in a cold first iteration, must take one iteration
// more). The members' momentum change plus the partners' h (pf1 + pf2) / 2
// is h sum fc, and each partner's force at each stage is the test's own:
// minus the term's part of its member's dp/dt, -k x - c k a_a
TEST(ClusterGauss, PartnerForcesOfTheLastIterationAtAnExactPredictor)
{
  Scene s;
  s.n = 2;
  s.im = {1.0, 0.5};
  s.fc = {0.1, 0.0, -0.2, 0.0, 0.3, 0.0};
  s.terms.clear();
  auto add = [&](int a, std::array<double, 3> xb, int partner) {
    ClusterTerm t;
    t.a = a;
    t.b = -1;
    t.kind = 2;
    t.partner = partner;
    for (int d = 0; d < 3; d++) t.xb[d] = xb[d];
    s.terms.push_back(t);
  };
  add(0, {1.1, -0.2, 0.3}, 0);
  add(1, {-0.4, 0.9, 0.2}, 1);
  add(1, {0.3, 0.1, -1.0}, 0);
  s.y0 = {0.1, 0.2, -0.1, 0.5, -0.3, 0.2, 0.7, -0.4, 0.3, -0.2, 0.6, 0.5};
  const double c = 0.002, h = 0.01, k = 30.0;
  const Cluster C = s.make(c);
  const int m = 3 * s.n;
  std::vector<double> y1(2 * m);
  ClusterStepDetail det;
  const ClusterNewtonStatus st = C.step(s.y0.data(), h, y1.data(), ClusterNewtonOptions(), &det);
  ASSERT_TRUE(st.converged);
  std::printf("quadratic V: %d iterations, first relative change %.1e\n", st.iterations,
              st.history.front());
  // the path under test: the first change already below the tolerance
  ASSERT_LE(st.history.front(), ClusterNewtonOptions().tol);
  ASSERT_EQ((int) det.pf1.size(), 3 * 2);
  ASSERT_EQ((int) det.pf2.size(), 3 * 2);
  // momentum: the members' change and the partners' make h sum fc
  double scale = 0.0;
  for (int d = 0; d < 3; d++) {
    double sum = 0.0, fsum = 0.0;
    for (int i = 0; i < s.n; i++) {
      const double dp = (y1[m + 3 * i + d] - s.y0[m + 3 * i + d]) / s.im[i];
      sum += dp;
      fsum += s.fc[3 * i + d];
      scale = std::max(scale, std::fabs(dp));
    }
    for (int p = 0; p < 2; p++) sum += 0.5 * h * (det.pf1[3 * p + d] + det.pf2[3 * p + d]);
    EXPECT_NEAR(sum, h * fsum, 1e-12 * scale) << "momentum component " << d;
  }
  // each partner's force at each stage: for V_t = k/2 |x|^2 the member's
  // dp/dt from the term is -k x - c (grad_x(w^T V_t'' w) + V_t'' a_rel) =
  // -k x - c k a_a (V_t'' = k I, its gradient 0; a_rel = a_a = M^-1 F at
  // the stage, F = fc - k sum_t x_t); the partner takes minus it
  for (int stage = 0; stage < 2; stage++) {
    const std::vector<double> &Y = stage == 0 ? det.Y1 : det.Y2;
    const std::vector<double> &pf = stage == 0 ? det.pf1 : det.pf2;
    double a[2][3];
    for (int i = 0; i < 2; i++)
      for (int d = 0; d < 3; d++) a[i][d] = s.fc[3 * i + d];
    for (const ClusterTerm &t : s.terms)
      for (int d = 0; d < 3; d++) a[t.a][d] -= k * (Y[3 * t.a + d] - t.xb[d]);
    for (int i = 0; i < 2; i++)
      for (int d = 0; d < 3; d++) a[i][d] *= s.im[i];
    double ref[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    for (const ClusterTerm &t : s.terms)
      for (int d = 0; d < 3; d++)
        ref[3 * t.partner + d] += k * (Y[3 * t.a + d] - t.xb[d]) + c * k * a[t.a][d];
    for (int q = 0; q < 6; q++)
      EXPECT_NEAR(pf[q], ref[q], 1e-12 * (1.0 + std::fabs(ref[q]))) << "stage " << stage << " " << q;
  }
}

TEST(ClusterGauss, JacobianIsExact)
{
  Scene s;
  const Cluster C = s.make(0.004);
  const int N = C.dim();
  Eigen::MatrixXd J;
  std::vector<double> k(N);
  C.field(s.y0.data(), k.data(), &J);
  double scale = J.cwiseAbs().maxCoeff(), worst = 0.0;
  for (int col = 0; col < N; col++) {
    for (int row = 0; row < N; row++) {
      auto comp = [&](const std::vector<double> &y) {
        std::vector<double> f(N);
        C.field(y.data(), f.data());
        return f[row];
      };
      const double fd = diff4(comp, s.y0, col, 1e-4);
      worst = std::max(worst, std::fabs(J(row, col) - fd));
    }
  }
  std::printf("Jacobian: largest entry %.3e, largest difference from the field's %.3e\n", scale,
              worst);
  EXPECT_LE(worst, 1e-7 * scale);
}

// H~ of a step dt = 0.05 (c = dt^2/12), the sub-steps h <= dt
constexpr double CDYN = 0.05 * 0.05 / 12.0;

TEST(ClusterGauss, FourthOrderAndModifiedEnergyKept)
{
  Scene s;
  const Cluster C = s.make(CDYN);
  const double T = 0.4;
  std::vector<double> ref = s.y0;
  rk4(C, ref, T / 8000.0, 8000);
  const double H0 = C.energy(s.y0.data());
  std::vector<double> err, herr, hs;
  int iters = 0, steps = 0, maxit = 0;
  for (int nst : {8, 16, 32, 64}) {
    const double h = T / nst;
    std::vector<double> y = s.y0, y1(C.dim());
    double hmax = 0.0;
    ClusterNewtonOptions full;
    full.full = true;
    for (int st = 0; st < nst; st++) {
      const ClusterNewtonStatus ns = C.step(y.data(), h, y1.data(), full);
      ASSERT_TRUE(ns.converged) << "h " << h << " step " << st << " residual " << ns.residual;
      iters += ns.iterations;
      steps++;
      maxit = std::max(maxit, ns.iterations);
      y = y1;
      hmax = std::max(hmax, std::fabs(C.energy(y.data()) - H0));
    }
    double e = 0.0;
    for (int i = 0; i < C.dim(); i++) e = std::max(e, std::fabs(y[i] - ref[i]));
    err.push_back(e);
    herr.push_back(hmax);
    hs.push_back(h);
    std::printf("h %.4f: state error %.3e, max |H~ - H~0| %.3e\n", h, e, hmax);
  }
  auto slope = [&](const std::vector<double> &v) {
    return std::log(v.front() / v.back()) / std::log(hs.front() / hs.back());
  };
  std::printf("orders: state %.2f, H~ %.2f; Newton iterations per step %.2f (max %d)\n",
              slope(err), slope(herr), (double) iters / steps, maxit);
  EXPECT_GE(slope(err), 3.8);
  EXPECT_GE(slope(herr), 3.6);
  EXPECT_LE(maxit, 5);
}

TEST(ClusterGauss, NewtonConvergesQuadratically)
{
  Scene s;
  const Cluster C = s.make(CDYN);
  std::vector<double> y1(C.dim());
  ClusterNewtonOptions opt;
  opt.tol = 1e-15;
  opt.full = true;
  const ClusterNewtonStatus ns = C.step(s.y0.data(), 0.05, y1.data(), opt);
  EXPECT_TRUE(ns.converged);
  std::printf("h 0.05: iterations %d, relative changes:", ns.iterations);
  for (double r : ns.history) std::printf(" %.2e", r);
  std::printf("\n");
  EXPECT_LE(ns.iterations, 6);
  // each change about the square of the last while above round-off
  int checked = 0;
  for (size_t k = 0; k + 1 < ns.history.size(); k++) {
    const double a = ns.history[k], b = ns.history[k + 1];
    if (a < 1e-2 && b > 1e-13) {
      EXPECT_GE(std::log(b) / std::log(a), 1.6) << "iteration " << k + 1;
      checked++;
    }
  }
  EXPECT_GE(checked, 1);
}

// the Jacobian of the step's start kept for its iterations (the default),
// stopped by the contraction's estimate of the error left: the same step
// as full Newton's to the tolerance, in a few iterations at
// sub-steps of the fluid tests (h omega ~ 0.03), more at larger h
TEST(ClusterGauss, StartJacobianConvergesToTheSameStep)
{
  Scene s;
  const Cluster C = s.make(CDYN);
  ClusterNewtonOptions full, frozen;
  full.full = true;
  for (double h : {0.05, 0.0125, 0.003}) {
    std::vector<double> ya(C.dim()), yb(C.dim());
    const ClusterNewtonStatus a = C.step(s.y0.data(), h, ya.data(), full);
    const ClusterNewtonStatus b = C.step(s.y0.data(), h, yb.data(), frozen);
    ASSERT_TRUE(a.converged && b.converged);
    double d = 0.0;
    for (int i = 0; i < C.dim(); i++) d = std::max(d, std::fabs(ya[i] - yb[i]));
    std::printf("h %.4f: full Newton %d iterations (%d Jacobians), start Jacobian %d (%d); "
                "largest difference %.1e\n",
                h, a.iterations, a.jacobians, b.iterations, b.jacobians, d);
    // (both stop at the stages' relative tolerance, 1e-12 of K ~ 30 here,
    // times h)
    EXPECT_LE(d, 1e-12 * 30.0 * h);
    EXPECT_LE(b.jacobians, 1);
    if (h < 0.005) EXPECT_LE(b.iterations, 3);
    // a second step from the same start reuses its Jacobian (contact times)
    EXPECT_EQ(C.step(s.y0.data(), 0.5 * h, yb.data(), frozen).jacobians, 0);
  }
}

// the iterations' changes are recorded by default, one per iteration, each
// the relative change the convergence test saw (the last the status's
// residual); with
// history off (the cluster flows) none, and the same step to the bit
TEST(ClusterGauss, HistoryIsOptionalAndChangesNothing)
{
  Scene s;
  ClusterNewtonOptions on, off;
  off.history = false;
  for (double h : {0.05, 0.003}) {
    // (two kernels: a step's start and stages are kept per kernel)
    const Cluster Ca = s.make(CDYN), Cb = s.make(CDYN);
    std::vector<double> ya(Ca.dim()), yb(Cb.dim());
    ClusterStepDetail da, db;
    const ClusterNewtonStatus a = Ca.step(s.y0.data(), h, ya.data(), on, &da);
    const ClusterNewtonStatus b = Cb.step(s.y0.data(), h, yb.data(), off, &db);
    ASSERT_TRUE(a.converged && b.converged);
    ASSERT_EQ((int) a.history.size(), a.iterations);
    EXPECT_EQ(a.history.back(), a.residual);
    EXPECT_TRUE(b.history.empty());
    EXPECT_EQ(a.iterations, b.iterations);
    EXPECT_EQ(ya, yb);
    EXPECT_EQ(da.Y1, db.Y1);
    EXPECT_EQ(da.Y2, db.Y2);
  }
}

// the start's Jacobian by its leading part (from V'' alone, the default)
// or exact: both converge to full Newton's step, the leading one in at most
// one iteration more; and a step from the same start whose length differs
// by 1e-6 (a contact time's later trial) starts from the last solution and
// stops within one iteration at the same step as a cold start's
TEST(ClusterGauss, LeadingJacobianAndWarmStartGiveTheSameStep)
{
  Scene s;
  ClusterNewtonOptions full, exact, lead;
  full.full = true;
  exact.leading = false;
  for (double h : {0.05, 0.0125, 0.003}) {
    const double tol = 1e-12 * 30.0 * h;    // (the stages' tolerance, as above)
    const Cluster Cf = s.make(CDYN), Ce = s.make(CDYN), Cl = s.make(CDYN);
    std::vector<double> yf(Cf.dim()), ye(Cf.dim()), yl(Cf.dim());
    const ClusterNewtonStatus f = Cf.step(s.y0.data(), h, yf.data(), full);
    const ClusterNewtonStatus e = Ce.step(s.y0.data(), h, ye.data(), exact);
    const ClusterNewtonStatus l = Cl.step(s.y0.data(), h, yl.data(), lead);
    ASSERT_TRUE(f.converged && e.converged && l.converged) << h;
    double de = 0.0, dl = 0.0;
    for (int i = 0; i < Cf.dim(); i++) {
      de = std::max(de, std::fabs(ye[i] - yf[i]));
      dl = std::max(dl, std::fabs(yl[i] - yf[i]));
    }
    std::printf("h %.4f: exact start Jacobian %d iterations, leading %d; from full Newton's "
                "step %.1e, %.1e\n",
                h, e.iterations, l.iterations, de, dl);
    EXPECT_LE(de, tol);
    EXPECT_LE(dl, tol);
    EXPECT_LE(l.iterations, e.iterations + 1) << h;
    // a trial of length hh from Cl's start (warm: Cl solved from it
    // before) against a cold solve; the largest difference of their ends
    struct Pair {
      ClusterNewtonStatus w, c;
      double apart = 0.0;
    };
    auto warm_and_cold = [&](double hh) {
      Pair p;
      const Cluster Cc = s.make(CDYN);
      std::vector<double> yw(Cf.dim()), yc(Cf.dim());
      p.w = Cl.step(s.y0.data(), hh, yw.data(), lead);
      p.c = Cc.step(s.y0.data(), hh, yc.data(), lead);
      for (int i = 0; i < Cf.dim(); i++) p.apart = std::max(p.apart, std::fabs(yw[i] - yc[i]));
      return p;
    };
    // the warm trial (Cl solved h from this start) against a cold one
    const Pair t2 = warm_and_cold(h * (1.0 + 1e-6));
    ASSERT_TRUE(t2.w.converged && t2.c.converged) << h;
    std::printf("  length x (1 + 1e-6): warm %d iterations, cold %d; apart %.1e\n",
                t2.w.iterations, t2.c.iterations, t2.apart);
    EXPECT_LE(t2.apart, 2.0 * tol);
    if (h < 0.005) EXPECT_LE(t2.w.iterations, 1) << h;    // (the fluid tests' sub-steps)
    EXPECT_LT(t2.w.iterations, t2.c.iterations) << h;
    // a first trial at a fraction of the solved length (a contact time's
    // guess): the stages from the quadratic through f0 and the last
    // stages start within its interpolation error
    const Pair t3 = warm_and_cold(0.6 * h);
    ASSERT_TRUE(t3.w.converged && t3.c.converged) << h;
    std::printf("  length x 0.6: warm %d iterations (first change %.1e), cold %d (%.1e); apart "
                "%.1e\n",
                t3.w.iterations, t3.w.history.front(), t3.c.iterations, t3.c.history.front(),
                t3.apart);
    EXPECT_LE(t3.apart, 2.0 * tol);
    EXPECT_LT(t3.w.history.front(), (h < 0.02 ? 0.1 : 1.0) * t3.c.history.front()) << h;
  }
}

// the stage matrix of a leading-form Jacobian through one complex m x m LU
// (StageLU) against the test's own dense real LU of I - h A (x) J0,
// A written out from the Gauss-Legendre tableau: random blocks, not only
// those of leading_jacobian() (P, Q need not commute), m = 3, 6, 9 and 24
// (1, 2, 3 and 8 members: the fixed sizes and the dynamic one), one object
// for all in turn (as ClusterGauss keeps it from cluster to cluster), a
// small step and one where h |J0| is order 1
TEST(ClusterGauss, LeadingStageSolveEqualsTheDenseLU)
{
  const double s3 = std::sqrt(3.0);
  const double A[2][2] = {{0.25, 0.25 - s3 / 6.0}, {0.25 + s3 / 6.0, 0.25}};
  std::srand(4711);
  StageLU lu;
  for (int m : {6, 24, 3, 9, 6})
    for (double h : {0.003, 0.4}) {
      const int N = 2 * m;
      Eigen::MatrixXd J0 = Eigen::MatrixXd::Zero(N, N);
      J0.block(0, m, m, m) = Eigen::MatrixXd::Identity(m, m) + 0.3 * Eigen::MatrixXd::Random(m, m);
      J0.block(m, 0, m, m) = -4.0 * Eigen::MatrixXd::Random(m, m);
      Eigen::MatrixXd Mfull = Eigen::MatrixXd::Identity(2 * N, 2 * N);
      for (int a = 0; a < 2; a++)
        for (int b = 0; b < 2; b++) Mfull.block(a * N, b * N, N, N) -= h * A[a][b] * J0;
      const Eigen::VectorXd R = Eigen::VectorXd::Random(2 * N);
      const Eigen::VectorXd Dref = Mfull.partialPivLu().solve(R);
      lu.set_blocks(J0);
      lu.factor(h);
      Eigen::VectorXd D;
      lu.solve(R, D);
      const double err = (D - Dref).cwiseAbs().maxCoeff() / Dref.cwiseAbs().maxCoeff();
      std::printf("m %d, h %.3f: max |D - D_dense| / max |D_dense| %.1e, residual %.1e\n", m, h,
                  err, (Mfull * D - R).cwiseAbs().maxCoeff());
      EXPECT_LE(err, 1e-13) << m << " " << h;
      EXPECT_LE((Mfull * D - R).cwiseAbs().maxCoeff(), 1e-13 * R.cwiseAbs().maxCoeff() * 10.0);
    }
}

// the cold predictor (J0's leading form): the exact stages of the linear
// model with the parts J0 drops, f along the flow to O(t^2) but for O(c)
// terms; with c = dt^2 / 12 and sub-steps h = dt / 2, as the local form
// runs, the first Newton change (the predictor's error relative to the
// stages) falls at third order in h
TEST(ClusterGauss, ColdPredictorErrorFallsAtThirdOrder)
{
  Scene s;
  std::vector<double> hs = {0.02, 0.01, 0.005, 0.0025}, first;
  for (double h : hs) {
    const Cluster C = s.make((2.0 * h) * (2.0 * h) / 12.0);
    std::vector<double> y1(C.dim());
    const ClusterNewtonStatus st = C.step(s.y0.data(), h, y1.data(), ClusterNewtonOptions());
    ASSERT_TRUE(st.converged) << h;
    first.push_back(st.history.front());
    std::printf("h %.4f: cold start, %d iterations, first relative change %.3e\n", h,
                st.iterations, st.history.front());
  }
  const double order = std::log(first.front() / first.back()) / std::log(hs.front() / hs.back());
  std::printf("order of the predictor's error: %.2f\n", order);
  EXPECT_GE(order, 2.7);
}

TEST(ClusterGauss, AlphaHatKeepsModifiedEnergyAndIsElasticWithoutIt)
{
  Scene s;
  for (double c : {0.0, 0.004}) {
    const Cluster C = s.make(c);
    const RefH H{s, c};
    const int m = 3 * s.n;
    // a contact of members 0 and 1 along their line of centres
    double nrm[3], r = 0.0;
    for (int d = 0; d < 3; d++) {
      nrm[d] = s.y0[d] - s.y0[3 + d];
      r += nrm[d] * nrm[d];
    }
    r = std::sqrt(r);
    std::vector<double> u(m, 0.0);
    for (int d = 0; d < 3; d++) {
      u[d] = nrm[d] / r;
      u[3 + d] = -nrm[d] / r;
    }
    double alpha = 0.0;
    ASSERT_TRUE(C.alpha_hat(s.y0.data(), u.data(), alpha));
    std::vector<double> y = s.y0;
    for (int i = 0; i < m; i++) y[m + i] += alpha * s.im[i / 3] * u[i];
    EXPECT_NEAR(H(y), H(s.y0), 1e-13 * std::fabs(H(s.y0)) + 1e-13) << "c " << c;
    double vn0 = 0.0, vn1 = 0.0;
    for (int d = 0; d < 3; d++) {
      vn0 += (s.y0[m + d] - s.y0[m + 3 + d]) * u[d];
      vn1 += (y[m + d] - y[m + 3 + d]) * u[d];
    }
    if (c == 0.0) EXPECT_NEAR(vn1, -vn0, 1e-14);
    else EXPECT_GT(std::fabs(vn1 + vn0), 1e-6);    // alpha-hat differs from elastic
  }
}

TEST(ClusterGauss, ContactTimeOnTheFlow)
{
  Scene s;
  const Cluster C = s.make(CDYN);
  const int m = 3 * s.n;
  // members 0 and 1 approach (negative relative normal velocity at y0);
  // with sigma a little below their distance they touch a little later
  double dq[3], dv[3], r = 0.0, vn = 0.0;
  for (int d = 0; d < 3; d++) {
    dq[d] = s.y0[d] - s.y0[3 + d];
    dv[d] = s.y0[m + d] - s.y0[m + 3 + d];
    r += dq[d] * dq[d];
  }
  r = std::sqrt(r);
  for (int d = 0; d < 3; d++) vn += dq[d] * dv[d] / r;
  ASSERT_LT(vn, 0.0);
  std::vector<double> errs, times;
  for (double closer : {0.02, 0.01}) {
    const double sigma = r - closer, tmax = 4.0 * closer;
    const RootResult rr =
        C.contact_time(s.y0.data(), 0, 1, nullptr, sigma, closer / -vn, tmax, 1e-13);
    ASSERT_EQ(rr.status, ROOT_FOUND);
    // the independent reference: RK4 with a tiny step, bisection in time
    auto gap_rk = [&](double t) {
      std::vector<double> y = s.y0;
      const int n = 4000;
      rk4(C, y, t / n, n);
      double g = 0.0;
      for (int d = 0; d < 3; d++) g += (y[d] - y[3 + d]) * (y[d] - y[3 + d]);
      return std::sqrt(g) - sigma;
    };
    double lo = 0.0, hi = tmax;
    ASSERT_LT(gap_rk(hi), 0.0);
    for (int it = 0; it < 45; it++) {
      const double mid = 0.5 * (lo + hi);
      (gap_rk(mid) > 0.0 ? lo : hi) = mid;
    }
    std::printf("contact on one Gauss step at %.12f (%d steps tried), RK4 reference %.12f\n",
                rr.t, rr.nevals, lo);
    EXPECT_GE(rr.g, 0.0);
    EXPECT_LE(rr.g, 1e-12);
    EXPECT_LE(rr.nevals, 12);
    errs.push_back(std::fabs(rr.t - lo));
    times.push_back(lo);
  }
  // one Gauss step of length t errs from the flow by O(t^5): half the time,
  // 1/32 of the error (>= 16 allowed)
  const double order = std::log(errs[0] / errs[1]) / std::log(times[0] / times[1]);
  std::printf("contact time errors %.3e, %.3e: order %.2f\n", errs[0], errs[1], order);
  EXPECT_LE(errs[0], 1e-6);
  EXPECT_GE(order, 4.0);
}

}    // namespace
