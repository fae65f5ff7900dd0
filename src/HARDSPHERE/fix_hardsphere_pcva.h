/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: fix hardsphere/pcva, the projected collision Verlet
   algorithm (Bond & Leimkuhler 2007, section 3.2): CVA, and after every
   sub-step of a step with a collision the group's momenta are scaled so
   that the modified Hamiltonian H_[2,VV] keeps the value it had at the
   step's start. Collision-free steps are fix nve's. With substep local
   (the local engine) one projection per step of the colliding spheres'
   velocities keeps H_[2,VV] to fourth order (hs_local_modified.h).
   The method is HSMethodPCVA (hs_method_pcva.h).
   See doc/fix_hardsphere_pcva.rst.
------------------------------------------------------------------------- */

#ifdef FIX_CLASS
// clang-format off
FixStyle(hardsphere/pcva,FixHardSpherePCVA);
// clang-format on
#else

#ifndef LMP_FIX_HARDSPHERE_PCVA_H
#define LMP_FIX_HARDSPHERE_PCVA_H

#include "fix_hardsphere.h"
#include "hs_method_pcva.h"

namespace LAMMPS_NS {

// substep local (the default where it applies) or global
class FixHardSpherePCVA : public FixHardSphere {
 public:
  FixHardSpherePCVA(class LAMMPS *lmp, int narg, char **arg) : FixHardSphere(lmp, narg, arg)
  {
    method = new HSMethodPCVA(lmp, *sys);
  }
};

}    // namespace LAMMPS_NS

#endif
#endif
