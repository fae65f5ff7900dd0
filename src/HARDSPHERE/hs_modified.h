/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: pieces of the modified collision Verlet algorithm
   (MCVA, Bond & Leimkuhler 2007, section 3.1) that need no LAMMPS:

   - the modified collision strength alpha-hat, which conserves
     H_[2,VV] = 1/2 p^T M^-1 p + V + dt^2/12 p^T M^-1 V'' M^-1 p
                - dt^2/24 grad V^T M^-1 grad V
     under p -> p + alpha u. H_[2,VV] is quadratic in p with the matrix
     A = M^-1 + dt^2/6 M^-1 V'' M^-1, so H(p + alpha u) - H(p) =
     alpha (u^T A p + alpha/2 u^T A u) and the nonzero root is
     alpha-hat = -2 u^T A p / u^T A u;
   - a safeguarded scalar root finder for the collision time on a flow
     whose gap can only be evaluated (each evaluation is a Gauss solve).

   Unit-tested in unittest/math/test_modified_impulse.cpp.
------------------------------------------------------------------------- */

#ifndef LMP_HS_MODIFIED_H
#define LMP_HS_MODIFIED_H

#include <algorithm>
#include <cmath>
#include <limits>

namespace HardSphere {

/* ----------------------------------------------------------------------
   alpha-hat from the pieces of u^T A p and u^T A u, with w = M^-1 u,
   v = M^-1 p and c = dt^2/6:
     u^T A p = u.v + c w^T V'' v,   u^T A u = u.w + c w^T V'' w.
   Returns false (alpha untouched) if u^T A u <= 0: H_[2,VV] is then not
   convex in p along u (dt far too large for the curvature of V) and no
   collision strength conserves it with the right sign.
------------------------------------------------------------------------- */

inline bool modified_alpha(double uv, double uw, double wKv, double wKw, double c, double &alpha)
{
  const double uAu = uw + c * wKw;
  if (!(uAu > 0.0)) return false;
  alpha = -2.0 * (uv + c * wKv) / uAu;
  return true;
}

/* ----------------------------------------------------------------------
   Collision time on an evaluated flow: the first t in (0, tmax] at which a
   gap g(t) (g >= 0 allowed) reaches 0, started from a predicted time.
   phi(t, g, dg) evaluates g(t) and an estimate dg of g'(t) (it may be
   approximate: it only steers the steps). g(0) > 0 (or ~0 while separating)
   is known and not evaluated.

   Safeguarded secant: a bracket [lo, hi] with g(lo) > 0 >= g(hi) is kept
   once found; a secant step through the last two evaluations (the first
   step: Newton with the estimate) is taken while it stays inside the
   bracket and the bracket halves at least every second evaluation, else
   bisection. Without a bracket the steps go forward from the last positive
   point; tmax itself is tried before giving up.
   Returns the point of the final bracket on the allowed side (g >= 0),
   within ttol of the root, so the caller never steps past a contact.

   NONE: no contact found in (0, tmax] (g > 0 at the evaluated points and
   the gap opening, or still positive at tmax). A gap that dips below 0 and
   comes back between evaluated points can be missed (a grazing contact;
   the paper's prescreened variant has the same limitation).
------------------------------------------------------------------------- */

enum RootStatus { ROOT_FOUND = 0, ROOT_NONE = 1, ROOT_FAILED = 2 };

struct RootResult {
  RootStatus status = ROOT_FAILED;
  double t = 0.0;      // the contact time (FOUND) or the last point tried
  double g = 0.0;      // g(t)
  int nevals = 0;      // evaluations of phi
};

template <class Phi>
RootResult contact_root(Phi &&phi, double t_guess, double tmax, double ttol, int maxeval)
{
  RootResult r;
  double lo = 0.0, glo = HUGE_VAL;    // g(0) > 0 by assumption (not evaluated)
  double hi = 0.0;
  bool bracket = false, tried_tmax = false, have_prev = false;
  double tp = 0.0, gp = 0.0;              // the previous evaluation
  double width1 = tmax, width2 = tmax;    // bracket widths one and two evaluations ago
  double t = std::min(std::max(t_guess, 0.0), tmax);
  if (!(t > 0.0)) t = std::min(tmax, std::max(ttol, 1e-3 * tmax));

  while (r.nevals < maxeval) {
    double g, dg;
    phi(t, g, dg);
    r.nevals++;
    r.t = t;
    r.g = g;
    if (t >= tmax) tried_tmax = true;
    if (!(g == g)) return r;    // NaN: FAILED
    if (g > 0.0) {
      if (t > lo) {
        lo = t;
        glo = g;
      }
    } else {
      if (g == 0.0) {    // exactly at the contact (the allowed side)
        r.status = ROOT_FOUND;
        return r;
      }
      if (t <= ttol) {    // already in contact at t ~ 0
        r.status = ROOT_FOUND;
        r.t = 0.0;
        return r;
      }
      if (!bracket || t < hi) hi = t;
      bracket = true;
    }

    // slope: the secant through the last two evaluations (robust to a badly
    // scaled estimate), else the estimate dg
    double slope = dg;
    if (have_prev && t != tp) {
      const double sec = (g - gp) / (t - tp);
      if (sec == sec && sec != 0.0) slope = sec;
    }
    tp = t;
    gp = g;
    have_prev = true;

    double tn;
    if (bracket) {
      if (hi - lo <= ttol) {
        r.status = ROOT_FOUND;
        r.t = lo;
        r.g = glo;
        return r;
      }
      tn = (slope != 0.0) ? t - g / slope : -1.0;
      // the step must stay inside the bracket, and the bracket must halve
      // at least every second evaluation, else bisect
      const bool halving = (hi - lo) <= 0.5 * width2;
      if (!(tn > lo && tn < hi) || !halving) tn = 0.5 * (lo + hi);
      // a step within ttol of an end: probe ttol inside it, which closes
      // the bracket on the allowed side if the root is there
      if (tn - lo < ttol) tn = std::min(lo + ttol, 0.5 * (lo + hi));
      if (hi - tn < ttol) tn = std::max(hi - ttol, 0.5 * (lo + hi));
      width2 = width1;
      width1 = hi - lo;
    } else {
      // every point so far has g > 0: step forward
      if (!(slope < 0.0)) slope = dg;
      if (!(slope < 0.0)) {
        // the gap opens at the newest point: no contact ahead of it, unless
        // the end of the interval says otherwise
        if (tried_tmax) {
          r.status = ROOT_NONE;
          return r;
        }
        tn = tmax;
      } else {
        tn = t - g / slope;
        if (tn - t < ttol) tn = t + ttol;    // converged from the allowed side: confirm
        if (tn >= tmax) {
          if (tried_tmax) {
            r.status = ROOT_NONE;
            return r;
          }
          tn = tmax;
        }
      }
    }
    t = tn;
  }
  r.status = ROOT_FAILED;
  r.t = lo;
  r.g = glo;
  return r;
}

}    // namespace HardSphere

#endif
