/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: derivatives of a radial function f(x) = phi(|x|)
   along directions, for the modified Hamiltonian of Bond & Leimkuhler
   (2007), section 3 (H2 needs V''[v,v], H4 needs V''''[v,v,v,v],
   V'''[g,v,v] and V''v). LAMMPS-free; unit-tested in
   unittest/math/test_jet.cpp.

   - Taylor jets: truncated power series in s to order 4 of
     rho(s) = |x + s w| and phi(rho(s)), giving d^k/ds^k phi(|x + s w|)
     at s = 0 for k <= 4 from phi(r), ..., phi''''(r);
   - closed forms: the Hessian of a radial function,
       grad^2 f = phi'' e e^T + (phi'/r) (I - e e^T),   e = x/r,
     its products with vectors, and the gradient of w^T grad^2 f w
     (= f'''[w,w,.]);
   - finite-difference stencils in r for phi'', phi''', phi'''' from phi'
     (fourth-order accurate, steps balancing truncation and round-off).
------------------------------------------------------------------------- */

#ifndef LMP_HS_JET_H
#define LMP_HS_JET_H

#include <algorithm>
#include <cmath>
#include <limits>

namespace HardSphere {

// truncated power series a[0] + a[1] s + ... + a[4] s^4
struct Jet4 {
  double c[5];
};

inline Jet4 jet_mul(const Jet4 &a, const Jet4 &b)
{
  Jet4 r;
  for (int k = 0; k <= 4; k++) {
    double s = 0.0;
    for (int i = 0; i <= k; i++) s += a.c[i] * b.c[k - i];
    r.c[k] = s;
  }
  return r;
}

/* ----------------------------------------------------------------------
   d^k/ds^k phi(|x + s w|) at s = 0, k = 0..4, into out[k].
   phi[k] = phi^(k)(r) at r = |x| (k = 0..4; phi[0] only enters out[0]).
   rho(s)^2 = r^2 + 2 s x.w + s^2 w.w, rho = r sqrt(1 + t) with
   t = (2 s x.w + s^2 w.w)/r^2 (no constant term), so
   sqrt(1+t) = 1 + t/2 - t^2/8 + t^3/16 - 5 t^4/128 + O(s^5),
   and phi(r + d) = sum_k phi^(k)(r) d^k / k! with d = rho - r = O(s).
------------------------------------------------------------------------- */

inline void radial_directional(const double x[3], const double w[3], const double phi[5],
                               double out[5])
{
  const double r2 = x[0] * x[0] + x[1] * x[1] + x[2] * x[2];
  const double r = std::sqrt(r2);
  if (!(r > 0.0)) {
    for (int k = 0; k < 5; k++) out[k] = std::numeric_limits<double>::quiet_NaN();
    return;
  }
  const double xw = x[0] * w[0] + x[1] * w[1] + x[2] * w[2];
  const double ww = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];

  Jet4 t = {{0.0, 2.0 * xw / r2, ww / r2, 0.0, 0.0}};
  const Jet4 t2 = jet_mul(t, t);
  const Jet4 t3 = jet_mul(t2, t);
  const Jet4 t4 = jet_mul(t3, t);
  Jet4 d;    // rho - r
  for (int k = 0; k <= 4; k++)
    d.c[k] = r * (0.5 * t.c[k] - 0.125 * t2.c[k] + 0.0625 * t3.c[k] - 0.0390625 * t4.c[k]);
  const Jet4 d2 = jet_mul(d, d);
  const Jet4 d3 = jet_mul(d2, d);
  const Jet4 d4 = jet_mul(d3, d);
  Jet4 p;
  for (int k = 0; k <= 4; k++)
    p.c[k] = phi[1] * d.c[k] + phi[2] / 2.0 * d2.c[k] + phi[3] / 6.0 * d3.c[k] +
        phi[4] / 24.0 * d4.c[k];
  p.c[0] += phi[0];
  const double fact[5] = {1.0, 1.0, 2.0, 6.0, 24.0};
  for (int k = 0; k <= 4; k++) out[k] = fact[k] * p.c[k];
}

/* ----------------------------------------------------------------------
   the same derivatives in closed form (Faa di Bruno), cheaper than the
   series: rho rho' = r u + s w.w gives at s = 0, with u = e.w and
   q = w.w - u^2,
     rho' = u, rho'' = q/r, rho''' = -3 u q/r^2, rho'''' = (12 u^2 q - 3 q^2)/r^3
   and d^k/ds^k phi(rho(s)) by the chain rule
------------------------------------------------------------------------- */

inline void radial_directional_fdb(const double x[3], const double w[3], const double phi[5],
                                   double out[5])
{
  const double r2 = x[0] * x[0] + x[1] * x[1] + x[2] * x[2];
  const double r = std::sqrt(r2);
  if (!(r > 0.0)) {
    for (int k = 0; k < 5; k++) out[k] = std::numeric_limits<double>::quiet_NaN();
    return;
  }
  const double u = (x[0] * w[0] + x[1] * w[1] + x[2] * w[2]) / r;
  const double q = w[0] * w[0] + w[1] * w[1] + w[2] * w[2] - u * u;
  const double p1 = u, p2 = q / r, p3 = -3.0 * u * q / r2, p4 = (12.0 * u * u * q - 3.0 * q * q) / (r2 * r);
  out[0] = phi[0];
  out[1] = phi[1] * p1;
  out[2] = phi[2] * p1 * p1 + phi[1] * p2;
  out[3] = phi[3] * p1 * p1 * p1 + 3.0 * phi[2] * p1 * p2 + phi[1] * p3;
  out[4] = phi[4] * p1 * p1 * p1 * p1 + 6.0 * phi[3] * p1 * p1 * p2 +
      phi[2] * (3.0 * p2 * p2 + 4.0 * p1 * p3) + phi[1] * p4;
}

/* ----------------------------------------------------------------------
   closed forms with A = phi''(r), B = phi'(r)/r, e = x/r:
   grad^2 f w = A e (e.w) + B (w - e (e.w))
   a^T grad^2 f b = A (e.a)(e.b) + B (a.b - (e.a)(e.b))
   grad (w^T grad^2 f w) = [phi''' u^2 + (A - B)/r (w.w - u^2)] e
                           + 2 u (A - B)/r (w - u e),       u = e.w
   (dB/dr = (A - B)/r, grad u = (w - u e)/r)
------------------------------------------------------------------------- */

inline void radial_hess_vec(const double x[3], double phi1, double phi2, const double w[3],
                            double hw[3])
{
  const double r = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
  const double e[3] = {x[0] / r, x[1] / r, x[2] / r};
  const double u = e[0] * w[0] + e[1] * w[1] + e[2] * w[2];
  const double B = phi1 / r;
  for (int k = 0; k < 3; k++) hw[k] = phi2 * e[k] * u + B * (w[k] - e[k] * u);
}

inline double radial_hess_bilinear(const double x[3], double phi1, double phi2, const double a[3],
                                   const double b[3])
{
  const double r = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
  const double ea = (x[0] * a[0] + x[1] * a[1] + x[2] * a[2]) / r;
  const double eb = (x[0] * b[0] + x[1] * b[1] + x[2] * b[2]) / r;
  const double ab = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  return phi2 * ea * eb + phi1 / r * (ab - ea * eb);
}

inline void radial_third_ww(const double x[3], double phi1, double phi2, double phi3,
                            const double w[3], double tw[3])
{
  const double r = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
  const double e[3] = {x[0] / r, x[1] / r, x[2] / r};
  const double u = e[0] * w[0] + e[1] * w[1] + e[2] * w[2];
  const double ww = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
  const double AmB_r = (phi2 - phi1 / r) / r;
  const double ce = phi3 * u * u + AmB_r * (ww - u * u);
  const double cw = 2.0 * u * AmB_r;
  for (int k = 0; k < 3; k++) tw[k] = ce * e[k] + cw * (w[k] - u * e[k]);
}

/* ----------------------------------------------------------------------
   phi'', phi''', phi'''' at r from phi'(r) (dphi: callable double(double))
   by central differences with O(h^4) truncation error (Richardson
   extrapolation of the O(h^2) formulas with steps h and 2h):
     phi''   = [-g(2h) + 8 g(h) - 8 g(-h) + g(-2h)] / (12 h)
     phi'''  = [-g(2h) + 16 g(h) - 30 g(0) + 16 g(-h) - g(-2h)] / (12 h^2)
     phi'''' = [-g(3h) + 8 g(2h) - 13 g(h) + 13 g(-h) - 8 g(-2h) + g(-3h)] / (8 h^3)
   with g(d) = phi'(r + d). Round-off eps/h^k against truncation h^4 gives
   h_k ~ eps^(1/(k+4)) l for the k-th derivative of phi' (k = 1, 2, 3),
   l the length over which phi varies (the caller passes l, e.g. r/16 for
   an r^-12 repulsion). order = highest derivative wanted (2, 3 or 4);
   out[2..order] are filled, g0 = phi'(r) is passed in. Near rmax (a
   cutoff: dphi is not evaluated at or beyond it) backward stencils.
------------------------------------------------------------------------- */

template <class F>
inline void radial_derivs_fd(F dphi, double r, double g0, double ell, int order, double out[5],
                             double rmax = std::numeric_limits<double>::infinity())
{
  // eps^(1/5), eps^(1/6), eps^(1/7) for eps = 2.2e-16
  const double c2 = 7.4e-4, c3 = 2.5e-3, c4 = 5.8e-3;
  // a stencil that would reach rmax (a pair style's cutoff, beyond which
  // e.g. pair_style table has no values) is taken one-sided, backward, at
  // the same O(h^4) (Fornberg's coefficients; more round-off, ~7x)
  double reach = 2 * c2 * ell;
  if (order >= 3) reach = std::max(reach, 2 * c3 * ell);
  if (order >= 4) reach = std::max(reach, 3 * c4 * ell);
  if (r + reach >= rmax) {
    {
      const double h = c2 * ell;
      out[2] = (25 * g0 - 48 * dphi(r - h) + 36 * dphi(r - 2 * h) - 16 * dphi(r - 3 * h) +
                3 * dphi(r - 4 * h)) /
          (12 * h);
    }
    if (order >= 3) {
      const double h = c3 * ell;
      out[3] = (45 * g0 - 154 * dphi(r - h) + 214 * dphi(r - 2 * h) - 156 * dphi(r - 3 * h) +
                61 * dphi(r - 4 * h) - 10 * dphi(r - 5 * h)) /
          (12 * h * h);
    }
    if (order >= 4) {
      const double h = c4 * ell;
      out[4] = (49.0 / 8 * g0 - 29 * dphi(r - h) + 461.0 / 8 * dphi(r - 2 * h) -
                62 * dphi(r - 3 * h) + 307.0 / 8 * dphi(r - 4 * h) - 13 * dphi(r - 5 * h) +
                15.0 / 8 * dphi(r - 6 * h)) /
          (h * h * h);
    }
    return;
  }
  {
    const double h = c2 * ell;
    out[2] = (-dphi(r + 2 * h) + 8 * dphi(r + h) - 8 * dphi(r - h) + dphi(r - 2 * h)) / (12 * h);
  }
  if (order >= 3) {
    const double h = c3 * ell;
    out[3] = (-dphi(r + 2 * h) + 16 * dphi(r + h) - 30 * g0 + 16 * dphi(r - h) -
              dphi(r - 2 * h)) /
        (12 * h * h);
  }
  if (order >= 4) {
    const double h = c4 * ell;
    out[4] = (-dphi(r + 3 * h) + 8 * dphi(r + 2 * h) - 13 * dphi(r + h) + 13 * dphi(r - h) -
              8 * dphi(r - 2 * h) + dphi(r - 3 * h)) /
        (8 * h * h * h);
  }
}

// phi^(k)(r) for phi(r) = c r^-n, k = 0..4
inline void power_derivs(double c, double n, double r, double out[5])
{
  double coef = c;
  double rp = std::pow(r, -n);
  for (int k = 0; k <= 4; k++) {
    out[k] = coef * rp;
    coef *= -(n + k);
    rp /= r;
  }
}

}    // namespace HardSphere

#endif
