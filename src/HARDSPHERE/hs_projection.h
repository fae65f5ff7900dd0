/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: the momentum scaling of the projected collision
   Verlet algorithm (PCVA), Bond & Leimkuhler, SIAM J. Sci. Comput. 30(1)
   (2007), section 3.2.

   Pure math, no LAMMPS types, header-only, unit-tested on its own
   (unittest/math/test_projection.cpp).

   The second-order modified Hamiltonian of velocity Verlet (section 3,
   H_[2,VV] = H + dt^2/4! H2 with H2 = 2 v^T V'' v - grad V^T M^-1 grad V,
   v = M^-1 p) splits into a part quadratic in p and a part of q alone:

     H_[2,VV](q, p) = K~(q, p) + U(q),
     K~ = 1/2 p^T M^-1 p + dt^2/12 v^T V'' v,
     U  = V - dt^2/24 grad V^T M^-1 grad V.

   PCVA scales p -> alpha p after each collisional sub-step so that
   H_[2,VV](q, alpha p) = alpha^2 K~ + U equals the target H~0 (the value
   before the sub-step): alpha^2 = (H~0 - U) / K~, the root alpha > 0.
------------------------------------------------------------------------- */

#ifndef LMP_HS_PROJECTION_H
#define LMP_HS_PROJECTION_H

#include <cmath>

namespace HardSphere {

// the pieces of H_[2,VV] at one state, all in energy units:
//   kin  = 1/2 p^T M^-1 p            vhv  = v^T V'' v
//   pot  = V                         g2   = grad V^T M^-1 grad V
struct ModifiedEnergyParts {
  double kin, vhv, pot, g2;
};

// K~ (scales with alpha^2 under p -> alpha p)
inline double modified_kinetic(const ModifiedEnergyParts &e, double dt)
{
  return e.kin + dt * dt / 12.0 * e.vhv;
}

// U (independent of p)
inline double modified_potential(const ModifiedEnergyParts &e, double dt)
{
  return e.pot - dt * dt / 24.0 * e.g2;
}

// H_[2,VV] = H + dt^2/24 (2 v^T V'' v - |grad V|^2_{M^-1})
inline double modified_hamiltonian2(const ModifiedEnergyParts &e, double dt)
{
  return modified_kinetic(e, dt) + modified_potential(e, dt);
}

enum ScaleStatus {
  SCALE_OK = 0,          // alpha > 0 found
  SCALE_NO_ROOT = 1,     // alpha^2 = (H~0 - U)/K~ <= 0: no real positive root
  SCALE_BAD_KINETIC = 2  // K~ <= 0 (or not finite): H_[2,VV] is not convex in p here
};

// alpha > 0 with alpha^2 Kt + U = H0, i.e. alpha = sqrt((H0 - U) / Kt).
// On failure alpha is set to 1 (no scaling) and the status says why.
inline ScaleStatus pcva_scale(double H0, double U, double Kt, double &alpha)
{
  alpha = 1.0;
  if (!(Kt > 0.0) || !std::isfinite(Kt)) return SCALE_BAD_KINETIC;
  const double a2 = (H0 - U) / Kt;
  if (!(a2 > 0.0) || !std::isfinite(a2)) return SCALE_NO_ROOT;
  alpha = std::sqrt(a2);
  return SCALE_OK;
}

// the local projection (substep local, hs_local_modified.h): v_i -> v_i +
// beta b_i on the colliding spheres changes H_[2,VV] over the step by
// A beta^2 + B beta + C0 (A: the kinetic energy of b, B = 2 A + dt^2/6
// b^T V'' v; C0: the change without projection). beta: the root nearest
// zero, -2 C0 / (B + sqrt(B^2 - 4 A C0)) (no cancellation for small C0).
// On failure beta is set to 0 and the status says why.
inline ScaleStatus pcva_local_beta(double A, double B, double C0, double &beta)
{
  beta = 0.0;
  if (!(A > 0.0) || !(B > 0.0) || !std::isfinite(A) || !std::isfinite(B))
    return SCALE_BAD_KINETIC;
  const double disc = B * B - 4.0 * A * C0;
  if (!(disc >= 0.0) || !std::isfinite(C0)) return SCALE_NO_ROOT;
  beta = -2.0 * C0 / (B + std::sqrt(disc));
  return SCALE_OK;
}

}    // namespace HardSphere

#endif
