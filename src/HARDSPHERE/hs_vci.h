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
   (smin = 1/2 keeps the contact separating): model steps from s = 1 with
   the slope a until the sign changes, then a bracketed secant (Illinois)
   with bisection as safeguard, to round-off. Where no sub-step follows
   the contact (the next one at the same instant), E_d^+ does not exist:
   eval returns NaN there and the solve reports no root.
------------------------------------------------------------------------- */

#ifndef LMP_HS_VCI_H
#define LMP_HS_VCI_H

#include <algorithm>
#include <cmath>
#include <limits>

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

// eval(s, scale) returns F(s) and sets scale, the size of the terms whose
// difference F is (|F| <= ftol_rel * scale counts as zero); NaN where F is
// not defined. f1 and scale1:
// F(1) and its scale, already evaluated by the caller. slope: dF/ds near 1
// (> 0; |J|^2_{M^-1} / 2 for the quadratic model).
template <class Eval>
VciRoot vci_root(Eval &&eval, double f1, double scale1, double slope, double smin, double smax,
                 int maxit, double ftol_rel = 64.0 * std::numeric_limits<double>::epsilon())
{
  const double eps = std::numeric_limits<double>::epsilon();
  VciRoot r{1.0, f1, 1.0, 1.0, 1, VCI_CONVERGED};
  if (std::fabs(f1) <= ftol_rel * scale1) return r;
  if (!(slope > 0.0) || !std::isfinite(slope)) slope = std::fabs(f1);

  // --- bracket: F is increasing through the nontrivial root, so the root
  // lies below 1 if F(1) > 0 and above it if F(1) < 0
  const double dir = (f1 > 0.0) ? -1.0 : 1.0;
  const double limit = (dir < 0.0) ? smin : smax;
  double a = 1.0, fa = f1;
  double s = 1.0 - f1 / slope;
  if (!std::isfinite(s) || (s - limit) * dir > 0.0) s = limit;
  double b = 0.0, fb = 0.0;
  bool bracketed = false;
  while (r.evals < maxit) {
    double scale;
    const double fs = eval(s, scale);
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
      bracketed = true;
      break;
    }
    if (s == limit) {
      r.lo = r.hi = s;
      r.s = 1.0;
      r.status = VCI_NO_ROOT;
      return r;
    }
    // secant through the last two points if it moves on towards the limit,
    // else twice the last step; never past the limit
    double next = s - fs * (s - a) / (fs - fa);
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

  // --- refine in [a, b] (F(a), F(b) of opposite signs): Illinois
  // regula falsi, bisection when it stalls
  int side = 0;
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
    double c = b - fb * (b - a) / (fb - fa);
    if (!(c > lo && c < hi)) c = 0.5 * (a + b);
    double scale;
    const double fc = eval(c, scale);
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
    if ((fc > 0.0) == (fb > 0.0)) {
      // c replaces b; a is kept: halve its weight if kept twice (Illinois)
      b = c;
      fb = fc;
      if (side == -1) fa *= 0.5;
      side = -1;
    } else {
      a = b;
      fa = fb;
      b = c;
      fb = fc;
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
