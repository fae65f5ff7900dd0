/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: the method of fix hardsphere/vci, the variational collision
   integrator of Fetecau, Marsden, Ortiz and West in the form of Bond &
   Leimkuhler 2007, section 2.3: CVA's Verlet sub-steps, with the strength
   of each impulse chosen so that the discrete energy E_d of the sub-step
   after the contact equals that of the sub-step before (an implicit scalar
   equation: trial sub-steps with energy evaluations).
   See doc/fix_hardsphere_vci.rst.
------------------------------------------------------------------------- */

#ifndef LMP_HS_METHOD_VCI_H
#define LMP_HS_METHOD_VCI_H

#include "hs_method.h"

#include <vector>

namespace LAMMPS_NS {

class HSMethodVCI : public HSMethod {
 public:
  HSMethodVCI(class LAMMPS *, HSSystem &);

  int engines_supported() const override { return ENGINE_GLOBAL_ONLY; }
  int needs_derivatives() const override { return 1; }

  void finish_step(double tleft) override;
  bool advance_to_contact(double &tau, double tleft, const Impulse &) override;
  void begin_collisional_step() override;
  void modify_impulse(Impulse &) override;

  int nvector() const override { return 6; }
  double vector(int) override;
  std::vector<double *> counters() override;

 private:
  // state of the current collisional step
  double Vk = 0.0;           // V at the start of the current sub-step (= at the last contact)
  double Etarget = 0.0;      // E_d^- for the next contact
  int have_target = 0;     // Etarget is set (a sub-step of positive length, or H at the start)
  double tleft_after = 0.0;  // time left in the step after the sub-step to the contact
  int pending = 0;         // the last contact was solved: check the next sub-step's E_d
  double pending_target = 0.0;

  // counters (global, identical on all ranks)
  double nsolved = 0.0;      // contacts whose impulse matched E_d
  double nnoroot = 0.0;      // elastic fallback: no root (or a jump of E_d^+)
  double nzero = 0.0;        // elastic: the next sub-step has zero length
  double nevals = 0.0;       // evaluations of E_d^+ (trial sub-steps)
  double maxevals = 0.0;     // most evaluations for one contact
  double maxdiff = 0.0;      // max |E_d(sub-step after) - E_d(sub-step before)| measured
  int warned = 0;

  std::vector<double> xsave, vsave;

  double kinetic();
  double potential_at_new_x();
  double trial(const Impulse &, double s, double &scale, double &tau2);
  void check_pending(double Ed);
};

}    // namespace LAMMPS_NS

#endif
