/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: the scalar root solve of the variational collision
   integrator (VCI) of Fetecau, Marsden, Ortiz and West, as described in
   Bond & Leimkuhler, SIAM J. Sci. Comput. 30(1) (2007), section 2.3.

   Pure math, no LAMMPS types, header-only, unit-tested on its own
   (unittest/math/test_vci.cpp).

   The impulse at a contact is s times the elastic one (s = 1: elastic),
   and s solves F(s) = E_d^+(s) - E_d^- = 0, the discrete energy
   E_d(q^{k+1}, q^k, tau) = 1/2 |(q^{k+1} - q^k)/tau|^2_M + (V(q^{k+1}) + V(q^k))/2
   of the sub-step after the contact equal to that of the sub-step before.
   F is expensive (a trial sub-step and an energy evaluation per call),
   roughly quadratic in s (F ~ a (s^2 - s) + F(1) with a = |J|^2_{M^-1}/2
   when V is flat: roots near 0, the trivial one, and near 1) and may jump
   where the length of the next sub-step (the time to the next contact)
   changes with s. vci_root() finds the nontrivial root in [smin, smax]
   (smin = 1/2 keeps the contact separating): steps from s = 1 on the
   model a (s^2 - s) + F(1), then on secants corrected by the known
   quadratic term a s^2 (quad_secant(): exact where F is that term plus a
   linear one), until the sign changes; then a bracketed secant (Illinois)
   with bisection as safeguard, to round-off; where eval also gives F'(s)
   (the local form's trials), from each point on the model through it with
   that slope (quad_newton()). Where no sub-step follows
   the contact (the next one at the same instant), E_d^+ does not exist:
   eval returns NaN there and the solve reports no root.
------------------------------------------------------------------------- */

#ifndef LMP_HS_VCI_H
#define LMP_HS_VCI_H

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

namespace HardSphere {

enum VciStatus {
  VCI_CONVERGED = 0,     // |F(s)| within the tolerance
  VCI_NO_ROOT = 1,       // F keeps its sign from s = 1 to the end of [smin, smax],
                         // or is undefined (NaN) at a point the search reached
  VCI_JUMP = 2,          // the bracket shrank to round-off around a jump of F
  VCI_NOT_CONVERGED = 3  // maxit evaluations without either
};

struct VciRoot {
  double s;       // the root (1 unless VCI_CONVERGED)
  double F;       // residual at s (at the last point for failures)
  double lo, hi;  // last bracket (lo = hi = last point if none was found)
  int evals;      // evaluations of F, including the one at s = 1
  VciStatus status;
};

// the root nearest x1 of a x^2 + G(x), G the line through (x0, f0 - a x0^2)
// and (x1, f1 - a x1^2): the secant step of F less its kinetic quadratic
// term a s^2 (exact for E_d^+ when V is linear along the trial sub-step's
// move; a plain secant errs by a (x - x0)(x - x1) there). NaN if there is
// no real root
inline double quad_secant(double x0, double f0, double x1, double f1, double a)
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (!(a > 0.0) || x1 == x0) return nan;
  const double g0 = f0 - a * x0 * x0, g1 = f1 - a * x1 * x1;
  const double m = (g1 - g0) / (x1 - x0);
  const double c = g1 - m * x1;
  const double disc = m * m - 4.0 * a * c;
  if (!(disc >= 0.0) || !std::isfinite(disc)) return nan;
  // the two roots without cancellation: q / a and c / q
  const double q = -0.5 * (m + std::copysign(std::sqrt(disc), m));
  const double r1 = q / a, r2 = (q != 0.0) ? c / q : nan;
  if (!std::isfinite(r2)) return r1;
  return (std::fabs(r1 - x1) <= std::fabs(r2 - x1)) ? r1 : r2;
}

// the root nearest x of f + df (s - x) + a (s - x)^2: a Newton step that
// keeps F's known quadratic term a s^2 (with V linear along the trial
// sub-step's move, as quad_secant(), but from one point and its slope).
// NaN if there is none, or df is not known (NaN)
inline double quad_newton(double x, double f, double df, double a)
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (!std::isfinite(df) || !(a >= 0.0)) return nan;
  const double disc = df * df - 4.0 * a * f;
  if (!(disc >= 0.0) || !std::isfinite(disc)) return nan;
  // (the root of small |d| without cancellation: -2 f / (df + sign(df) sqrt(disc)))
  const double q = df + std::copysign(std::sqrt(disc), df);
  if (q == 0.0) return nan;
  return x - 2.0 * f / q;
}

// eval(s, scale) returns F(s) and sets scale, the size of the terms whose
// difference F is (|F| <= ftol_rel * scale counts as zero); NaN where F is
// not defined. An eval(s, scale, dF) may also set dF = F'(s), NaN where it
// is not known. f1 and scale1: F(1) and its scale, already evaluated by the
// caller, df1 = F'(1) if known. slope: the coefficient of F's quadratic
// term (> 0; |J|^2_{M^-1} / 2, the kinetic energy's, for the quadratic
// model). Where F' is known, each step is quad_newton() from the last
// point: exact for the quadratic plus a line, as quad_secant() is from two
// points, so the first step from s = 1 lands on the root up to V's
// curvature along the move (F(1), F'(1) and one more evaluation where the
// secants took F(1) and two or three more)
template <class Eval>
VciRoot vci_root(Eval &&eval, double f1, double scale1, double slope, double smin, double smax,
                 int maxit, double ftol_rel = 64.0 * std::numeric_limits<double>::epsilon(),
                 double df1 = std::numeric_limits<double>::quiet_NaN())
{
  const double eps = std::numeric_limits<double>::epsilon();
  VciRoot r{1.0, f1, 1.0, 1.0, 1, VCI_CONVERGED};
  if (std::fabs(f1) <= ftol_rel * scale1) return r;
  if (!(slope > 0.0) || !std::isfinite(slope)) slope = std::fabs(f1);
  // F(s) and, where eval gives it, F'(s) (else NaN)
  auto call = [&](double s, double &scale, double &df) {
    df = std::numeric_limits<double>::quiet_NaN();
    if constexpr (std::is_invocable_v<Eval &, double, double &, double &>)
      return eval(s, scale, df);
    else
      return eval(s, scale);
  };

  // --- bracket: F is increasing through the nontrivial root, so the root
  // lies below 1 if F(1) > 0 and above it if F(1) < 0
  const double dir = (f1 > 0.0) ? -1.0 : 1.0;
  const double limit = (dir < 0.0) ? smin : smax;
  double a = 1.0, fa = f1;
  // the model's root near 1: a (s^2 - s) + F(1) = 0 (F'(1) = a), the line
  // F(1) + a (s - 1) where it has none
  const double disc = 0.25 - f1 / slope;
  double s = disc >= 0.0 ? 0.5 + std::sqrt(disc) : 1.0 - f1 / slope;
  // (F'(1) known: the model with it, which carries V's slope along the move)
  const double sn = quad_newton(1.0, f1, df1, slope);
  if (std::isfinite(sn) && (sn - 1.0) * dir > 0.0) s = sn;
  if (!std::isfinite(s) || (s - limit) * dir > 0.0) s = limit;
  double b = 0.0, fb = 0.0, db = 0.0;
  bool bracketed = false;
  while (r.evals < maxit) {
    double scale, ds;
    const double fs = call(s, scale, ds);
    r.evals++;
    r.s = s;
    r.F = fs;
    if (std::isnan(fs)) {
      r.lo = r.hi = s;
      r.s = 1.0;
      r.status = VCI_NO_ROOT;
      return r;
    }
    if (std::fabs(fs) <= ftol_rel * scale) {
      r.lo = r.hi = s;
      r.status = VCI_CONVERGED;
      return r;
    }
    if ((fs > 0.0) != (fa > 0.0)) {
      b = s;
      fb = fs;
      db = ds;
      bracketed = true;
      break;
    }
    if (s == limit) {
      r.lo = r.hi = s;
      r.s = 1.0;
      r.status = VCI_NO_ROOT;
      return r;
    }
    // secant through the last two points (less the quadratic term) if it
    // moves on towards the limit, else twice the last step; never past the
    // limit
    double next = quad_newton(s, fs, ds, slope);
    if (!std::isfinite(next)) next = quad_secant(a, fa, s, fs, slope);
    if (!std::isfinite(next)) next = s - fs * (s - a) / (fs - fa);
    if (!std::isfinite(next) || (next - s) * dir <= 0.0) next = s + 2.0 * (s - a);
    if ((next - limit) * dir > 0.0) next = limit;
    a = s;
    fa = fs;
    s = next;
  }
  if (!bracketed) {
    r.lo = r.hi = r.s;
    r.s = 1.0;
    r.status = VCI_NOT_CONVERGED;
    return r;
  }

  // --- refine in [a, b] (F(a), F(b) of opposite signs): the secant less
  // the quadratic term on the true values (ta: F(a) before Illinois halves
  // fa), Illinois regula falsi where it leaves the bracket or the same end
  // was kept last time, bisection when that stalls
  int side = 0;
  double ta = fa;
  bool newton = true;
  while (r.evals < maxit) {
    const double lo = std::min(a, b), hi = std::max(a, b);
    if (hi - lo <= 4.0 * eps * std::max(std::fabs(lo), std::fabs(hi))) {
      // no point of the double grid in between: a jump, not a root
      const bool ua = std::fabs(fa) <= std::fabs(fb);
      r.s = 1.0;
      r.F = ua ? fa : fb;
      r.lo = lo;
      r.hi = hi;
      r.status = VCI_JUMP;
      return r;
    }
    // (b: the last point; from it with F'(b) where known, while those
    // steps at least halve |F|: converging from one side, they need no
    // Illinois turn)
    double c = newton ? quad_newton(b, fb, db, slope) : std::numeric_limits<double>::quiet_NaN();
    const bool by_newton = c > lo && c < hi;
    if (!by_newton && side != -1) c = quad_secant(a, ta, b, fb, slope);
    if (!(c > lo && c < hi)) c = b - fb * (b - a) / (fb - fa);
    if (!(c > lo && c < hi)) c = 0.5 * (a + b);
    double scale, dc;
    const double fc = call(c, scale, dc);
    r.evals++;
    if (std::isnan(fc)) {
      r.s = 1.0;
      r.F = fc;
      r.lo = lo;
      r.hi = hi;
      r.status = VCI_NO_ROOT;
      return r;
    }
    if (std::fabs(fc) <= ftol_rel * scale) {
      r.s = c;
      r.F = fc;
      r.lo = r.hi = c;
      r.status = VCI_CONVERGED;
      return r;
    }
    if (by_newton && !(std::fabs(fc) <= 0.5 * std::fabs(fb))) newton = false;
    if ((fc > 0.0) == (fb > 0.0)) {
      // c replaces b; a is kept: halve its weight if kept twice (Illinois)
      b = c;
      fb = fc;
      db = dc;
      if (side == -1) fa *= 0.5;
      side = -1;
    } else {
      a = b;
      fa = ta = fb;
      b = c;
      fb = fc;
      db = dc;
      side = +1;
    }
  }
  r.s = 1.0;
  r.F = fb;
  r.lo = std::min(a, b);
  r.hi = std::max(a, b);
  r.status = VCI_NOT_CONVERGED;
  return r;
}

}    // namespace HardSphere

#endif
