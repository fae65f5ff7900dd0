/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: fix hardsphere/mcva, the modified collision Verlet
   algorithm (Bond & Leimkuhler 2007, section 3.1).

   A step with no (Verlet-)predicted contact is plain Verlet (the family's
   fix nve step). In a step with a predicted contact every sub-step is the
   2-stage Gauss-Legendre method on the flow of the modified Hamiltonian
   H~ = H_[2,VV] = 1/2 p M^-1 p + V + dt^2/12 v^T V'' v - dt^2/24 grad V^T M^-1 grad V,
   the contact time is refined on that flow, and the impulse conserves H~
   (alpha-hat). The method is HSMethodMCVA (hs_method_mcva.h).
   See doc/fix_hardsphere_mcva.rst.
------------------------------------------------------------------------- */

#ifdef FIX_CLASS
// clang-format off
FixStyle(hardsphere/mcva,FixHardSphereMCVA);
// clang-format on
#else

#ifndef LMP_FIX_HARDSPHERE_MCVA_H
#define LMP_FIX_HARDSPHERE_MCVA_H

#include "fix_hardsphere.h"
#include "hs_method_mcva.h"

namespace LAMMPS_NS {

class FixHardSphereMCVA : public FixHardSphere {
 public:
  FixHardSphereMCVA(class LAMMPS *lmp, int narg, char **arg) : FixHardSphere(lmp, narg, arg)
  {
    method = new HSMethodMCVA(lmp, *sys);
  }
};

}    // namespace LAMMPS_NS

#endif
#endif
