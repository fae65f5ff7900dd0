/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: fix hardsphere/vci, the variational collision
   integrator of Fetecau, Marsden, Ortiz and West in the form of Bond &
   Leimkuhler 2007, section 2.3: CVA's Verlet sub-steps, with the strength
   of each impulse chosen so that the discrete energy E_d of the sub-step
   after the contact equals that of the sub-step before (an implicit scalar
   equation: trial sub-steps with energy evaluations).
   The method is HSMethodVCI (hs_method_vci.h).
   See doc/fix_hardsphere_vci.rst.
------------------------------------------------------------------------- */

#ifdef FIX_CLASS
// clang-format off
FixStyle(hardsphere/vci,FixHardSphereVCI);
// clang-format on
#else

#ifndef LMP_FIX_HARDSPHERE_VCI_H
#define LMP_FIX_HARDSPHERE_VCI_H

#include "fix_hardsphere.h"
#include "hs_method_vci.h"

namespace LAMMPS_NS {

class FixHardSphereVCI : public FixHardSphere {
 public:
  FixHardSphereVCI(class LAMMPS *lmp, int narg, char **arg) : FixHardSphere(lmp, narg, arg)
  {
    method = new HSMethodVCI(lmp, *sys);
  }
};

}    // namespace LAMMPS_NS

#endif
#endif
