/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: fix hardsphere/vci, the variational collision
   integrator of Fetecau, Marsden, Ortiz and West in the form of Bond &
   Leimkuhler 2007, section 2.3: CVA's Verlet sub-steps, with the strength
   of each impulse chosen so that the discrete energy E_d of the sub-step
   after the contact equals that of the sub-step before (an implicit scalar
   equation: trial sub-steps with energy evaluations).
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

#include <vector>

namespace LAMMPS_NS {

class FixHardSphereVCI : public FixHardSphere {
 public:
  FixHardSphereVCI(class LAMMPS *, int, char **);
  double compute_vector(int) override;

 protected:
  std::vector<double *> extra_counters() override;

  // state of the current collisional step
  double Vk;           // V at the start of the current sub-step (= at the last contact)
  double Etarget;      // E_d^- for the next contact
  int have_target;     // Etarget is set (a sub-step of positive length, or H at the start)
  double tleft_after;  // time left in the step after the sub-step to the contact
  int pending;         // the last contact was solved: check the next sub-step's E_d
  double pending_target;

  // counters (global, identical on all ranks)
  double nsolved;      // contacts whose impulse matched E_d
  double nnoroot;      // elastic fallback: no root (or a jump of E_d^+)
  double nzero;        // elastic: the next sub-step has zero length
  double nevals;       // evaluations of E_d^+ (trial sub-steps)
  double maxevals;     // most evaluations for one contact
  double maxdiff;      // max |E_d(sub-step after) - E_d(sub-step before)| measured
  int warned;

  std::vector<double> xsave, vsave;

  void finish_step(double tleft) override;
  bool advance_to_contact(double &tau, double tleft, const Impulse &) override;
  void begin_collisional_step() override;
  void modify_impulse(Impulse &) override;

  double kinetic();
  double potential_at_new_x();
  double trial(const Impulse &, double s, double &scale, double &tau2);
  void check_pending(double Ed);
};

}    // namespace LAMMPS_NS

#endif
#endif
