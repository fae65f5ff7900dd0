/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: fix hardsphere/cva, the collision Verlet algorithm
   (Bond & Leimkuhler 2007, section 2.2): Verlet sub-steps to and from each
   collision, elastic impulse R of section 2 at the collision: the family's
   default method (hs_method.h), driven by the global engine (substep
   global, hs_global_engine.h) or per collision cluster by the local
   engine (substep local, hs_local_engine.h).
------------------------------------------------------------------------- */

#ifdef FIX_CLASS
// clang-format off
FixStyle(hardsphere/cva,FixHardSphereCVA);
// clang-format on
#else

#ifndef LMP_FIX_HARDSPHERE_CVA_H
#define LMP_FIX_HARDSPHERE_CVA_H

#include "fix_hardsphere.h"
#include "hs_method.h"

namespace LAMMPS_NS {

// substep local (the default where it applies) or global
class FixHardSphereCVA : public FixHardSphere {
 public:
  FixHardSphereCVA(class LAMMPS *lmp, int narg, char **arg) : FixHardSphere(lmp, narg, arg)
  {
    method = new HSMethod(lmp, *sys);
  }
};

}    // namespace LAMMPS_NS

#endif
#endif
