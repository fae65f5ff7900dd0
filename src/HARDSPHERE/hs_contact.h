/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: contact times and elastic collision operators.

   Pure math, no LAMMPS types, header-only, unit-tested on its own
   (unittest/math/test_contact.cpp).

   Bond & Leimkuhler, SIAM J. Sci. Comput. 30(1) (2007), section 2.2:
   on the Verlet trajectory q(t) = q + t v + t^2/2 a the squared distance of
   two spheres is a quartic in t and the distance of a sphere from a plane
   a quadratic. The collision time is the earliest t at which such a "gap"
   polynomial g(t) (g >= 0 is allowed space) passes from positive to <= 0.
------------------------------------------------------------------------- */

#ifndef LMP_HS_CONTACT_H
#define LMP_HS_CONTACT_H

#include <algorithm>
#include <cmath>
#include <limits>

namespace HardSphere {

// p(t) = c[0] + c[1] t + ... + c[n] t^n
inline double poly_eval(const double *c, int n, double t)
{
  double r = c[n];
  for (int k = n - 1; k >= 0; --k) r = r * t + c[k];
  return r;
}

inline int poly_degree(const double *c, int n)
{
  while (n > 0 && c[n] == 0.0) --n;
  return n;
}

inline void poly_derivative(const double *c, int n, double *d)
{
  for (int k = 1; k <= n; ++k) d[k - 1] = k * c[k];
}

// The single root of p in the bracket [lo, hi], where p(lo) and p(hi) have
// opposite signs (or p(hi) == 0) and p is monotone on the bracket.
// Safeguarded Newton: a Newton step is taken only while it stays inside the
// shrinking bracket and halves it; otherwise bisection. Returns a point on the
// lo side of the root (where p has the sign of p(lo)) to within round-off.
inline double poly_root_bracketed(const double *c, int n, double lo, double hi)
{
  const double plo = poly_eval(c, n, lo);
  const bool lo_pos = plo > 0.0;
  double d[4];
  poly_derivative(c, n, d);
  double x = 0.5 * (lo + hi);
  double width = hi - lo;
  // 1100 halvings reach any double, even when Newton never helps
  for (int it = 0; it < 1100; ++it) {
    const double px = poly_eval(c, n, x);
    if (px == 0.0) return x;
    if ((px > 0.0) == lo_pos) lo = x;
    else hi = x;
    if (!(hi - lo > 4.0 * std::numeric_limits<double>::epsilon() *
                     std::max(std::fabs(lo), std::fabs(hi))))
      break;
    const double dp = poly_eval(d, n - 1, x);
    double xn = (dp != 0.0) ? x - px / dp : lo;
    if (!(xn > lo && xn < hi) || (hi - lo) > 0.5 * width) xn = 0.5 * (lo + hi);
    width = hi - lo;
    x = xn;
  }
  return lo;
}

// All roots of p (degree n <= 4) in the open interval (a, b), ascending, by
// recursive isolation: the roots of p' split (a, b) into pieces on which p is
// monotone, and each piece with a sign change holds exactly one root.
// Returns the number of roots written to out (at most n).
inline int poly_roots_in(const double *c, int n, double a, double b, double *out)
{
  n = poly_degree(c, n);
  if (n == 0 || !(b > a)) return 0;
  if (n == 1) {
    const double r = -c[0] / c[1];
    if (r > a && r < b) {
      out[0] = r;
      return 1;
    }
    return 0;
  }
  double d[4], crit[4];
  poly_derivative(c, n, d);
  const int ncrit = poly_roots_in(d, n - 1, a, b, crit);
  double pts[6];
  int np = 0;
  pts[np++] = a;
  for (int k = 0; k < ncrit; ++k) pts[np++] = crit[k];
  pts[np++] = b;
  int nroot = 0;
  double plo = poly_eval(c, n, pts[0]);
  for (int k = 0; k + 1 < np; ++k) {
    const double phi = poly_eval(c, n, pts[k + 1]);
    if (phi == 0.0) {
      if (k + 1 < np - 1) out[nroot++] = pts[k + 1];    // root at a critical point
    } else if (plo != 0.0 && ((plo > 0.0) != (phi > 0.0))) {
      out[nroot++] = poly_root_bracketed(c, n, pts[k], pts[k + 1]);
    }
    plo = phi;
  }
  return nroot;
}

enum ContactStatus {
  NO_CONTACT = 0,     // g stays > 0 on (0, tmax] (or never enters g <= 0 approaching)
  CONTACT = 1,        // g passes from > 0 to <= 0 at t in (0, tmax]
  CONTACT_NOW = 2,    // touching at t = 0 (|g(0)| <= tol) and moving inward
  OVERLAP = 3         // g(0) < -tol: already inside, a missed collision
};

struct Contact {
  ContactStatus status;
  double t;
};

// Earliest approaching contact of a gap polynomial g (degree n <= 4) on
// (0, tmax]. |g(0)| <= tol counts as touching: inward (the first nonzero
// derivative at 0 is negative) is an immediate contact; outward (e.g. a pair
// that just collided and separates) measures the gap from the current contact,
// so round-off in g(0) can neither fake nor hide the next contact.
// A grazing trajectory whose minimum stays > 0 is no contact; one that dips to
// <= 0 is a contact at the downward crossing (double roots included).
inline Contact first_contact_searched(const double *c_in, int n, double tmax, double tol,
                                      bool timed = true);

// A cheap proof that g > 0 on (0, tmax] for a gap c0 > 0: g(t) >= c0 +
// sum_k min(c_k, 0) tmax^k there. When that bound exceeds 1e-12 of s = sum_k
// |c_k| tmax^k, far above the round-off of any evaluation of g on [0, tmax]
// (Horner: below 2n ulps of s), every evaluation first_contact_searched()
// would make is positive: its answer, NO_CONTACT, without the roots of g'.
// Most pairs a first guess or a flow tests are cleared so.
inline bool clear_by_bound(const double *c, int n, double tmax)
{
  double lb = c[0], s = c[0], tk = 1.0;
  for (int k = 1; k <= n; ++k) {
    tk *= tmax;
    lb += std::min(c[k], 0.0) * tk;
    s += std::fabs(c[k]) * tk;
  }
  return lb > 1.0e-12 * s;    // (false if anything overflowed to inf or nan)
}

// The same kind of proof that g' < 0 on [0, tmax] (d = g', degree n):
// d0 + sum_k max(d_k, 0) tmax^k below -1e-12 of sum_k |d_k| tmax^k. Then
// every evaluation of g' the search makes is negative: it finds no root of
// g', and g is monotone on all of (0, tmax]
inline bool decreasing_by_bound(const double *d, int n, double tmax)
{
  double ub = d[0], s = std::fabs(d[0]), tk = 1.0;
  for (int k = 1; k <= n; ++k) {
    tk *= tmax;
    ub += std::max(d[k], 0.0) * tk;
    s += std::fabs(d[k]) * tk;
  }
  return ub < -1.0e-12 * s;
}

// timed = false: a CONTACT's time is not computed (t is NaN), for callers
// that need to know only whether there is one
inline Contact first_contact(const double *c_in, int n, double tmax, double tol,
                             bool timed = true)
{
  constexpr double UNTIMED = std::numeric_limits<double>::quiet_NaN();
  // touching and separating (a pair just after its impulse): g = t h(t),
  // h = c1 + c2 t + ...; the search sees g > 0 on (0, tmax] where h's bound
  // holds (g's round-off is t times h's)
  if (tmax > 0.0 && n >= 1 && std::fabs(c_in[0]) <= tol && c_in[1] > 0.0 &&
      clear_by_bound(c_in + 1, n - 1, tmax))
    return {NO_CONTACT, 0.0};
  if (c_in[0] > tol && tmax > 0.0) {
    if (clear_by_bound(c_in, n, tmax)) return {NO_CONTACT, 0.0};
    // an approach through the whole interval (most pairs near contact):
    // the search's one piece, (0, tmax], with its evaluations and its root
    double c[5], d[4];
    for (int k = 0; k <= n; ++k) c[k] = c_in[k];
    const int m = poly_degree(c, n);
    poly_derivative(c, m, d);
    if (m >= 1 && decreasing_by_bound(d, m - 1, tmax)) {
      const double ghi = poly_eval(c, m, tmax);
      if (ghi > 0.0) return {NO_CONTACT, 0.0};
      if (ghi == 0.0) return {CONTACT, tmax};
      return {CONTACT, timed ? poly_root_bracketed(c, m, 0.0, tmax) : UNTIMED};
    }
  }
  return first_contact_searched(c_in, n, tmax, tol, timed);
}

// first_contact() by the roots of g': g is monotone between them
inline Contact first_contact_searched(const double *c_in, int n, double tmax, double tol,
                                      bool timed)
{
  double c[5];
  for (int k = 0; k <= n; ++k) c[k] = c_in[k];
  n = poly_degree(c, n);

  if (c[0] < -tol) return {OVERLAP, 0.0};
  if (c[0] <= tol) {
    for (int k = 1; k <= n; ++k) {
      if (c[k] < 0.0) return {CONTACT_NOW, 0.0};
      if (c[k] > 0.0) break;
    }
    c[0] = 0.0;    // touching and separating: the gap is measured from here
  }
  if (n == 0 || !(tmax > 0.0)) return {NO_CONTACT, 0.0};

  double d[4], crit[4];
  poly_derivative(c, n, d);
  const int ncrit = poly_roots_in(d, n - 1, 0.0, tmax, crit);
  double pts[6];
  int np = 0;
  pts[np++] = 0.0;
  for (int k = 0; k < ncrit; ++k) pts[np++] = crit[k];
  pts[np++] = tmax;

  // g is monotone on each piece; the first piece whose end is <= 0 holds the
  // contact (g > 0 at its start, or == 0 at t = 0 while separating)
  for (int k = 0; k + 1 < np; ++k) {
    const double ghi = poly_eval(c, n, pts[k + 1]);
    if (ghi <= 0.0) {
      const double glo = poly_eval(c, n, pts[k]);
      if (ghi == 0.0 || glo <= 0.0) return {CONTACT, pts[k + 1]};
      if (!timed) return {CONTACT, std::numeric_limits<double>::quiet_NaN()};
      return {CONTACT, poly_root_bracketed(c, n, pts[k], pts[k + 1])};
    }
  }
  return {NO_CONTACT, 0.0};
}

// Gap polynomial of two spheres on Verlet trajectories:
// g(t) = |dq + t dv + t^2/2 da|^2 - sigma^2, with dq = q_i - q_j etc.
inline void pair_gap_poly(const double *dq, const double *dv, const double *da, double sigma,
                          double *c)
{
  double aa = 0, ab = 0, ac = 0, bb = 0, bc = 0, cc = 0;
  for (int k = 0; k < 3; ++k) {
    const double A = dq[k], B = dv[k], C = 0.5 * da[k];
    aa += A * A;
    ab += A * B;
    ac += A * C;
    bb += B * B;
    bc += B * C;
    cc += C * C;
  }
  c[0] = aa - sigma * sigma;
  c[1] = 2.0 * ab;
  c[2] = bb + 2.0 * ac;
  c[3] = 2.0 * bc;
  c[4] = cc;
}

// Gap polynomial of a sphere and a plane along the outward normal:
// g(t) = dist + t vn + t^2/2 an, dist = centre distance from the plane - radius.
inline void wall_gap_poly(double dist, double vn, double an, double *c)
{
  c[0] = dist;
  c[1] = vn;
  c[2] = 0.5 * an;
}

// Elastic impulse of section 2: R(q,p) = (q, p + alpha u) with u the contact
// normal q_i - q_j and alpha from H o R = H,
// alpha = -2 u^T M^-1 p / u^T M^-1 u. Returns the momentum J added to sphere i
// (sphere j receives -J); dv = v_i - v_j.
inline void pair_impulse(const double *dq, const double *dv, double mi, double mj, double *J)
{
  const double uu = dq[0] * dq[0] + dq[1] * dq[1] + dq[2] * dq[2];
  const double uv = dq[0] * dv[0] + dq[1] * dv[1] + dq[2] * dv[2];
  const double mu = mi * mj / (mi + mj);
  const double s = -2.0 * mu * uv / uu;
  for (int k = 0; k < 3; ++k) J[k] = s * dq[k];
}

}    // namespace HardSphere

#endif
