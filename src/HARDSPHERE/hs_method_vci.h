/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: the method of fix hardsphere/vci, the variational collision
   integrator of Fetecau, Marsden, Ortiz and West in the form of Bond &
   Leimkuhler 2007, section 2.3: CVA's Verlet sub-steps, with the strength
   of each impulse chosen so that the discrete energy E_d of the sub-step
   after the contact equals that of the sub-step before (an implicit scalar
   equation: trial sub-steps with energy evaluations).
   Local form (the local engine, hs_local_engine.h): the same match inside
   each cluster's flow, on the flow's own energy (members' kinetic energy,
   V_C of the cluster's terms, the cross terms' constant force), its trial
   sub-steps through HSFlowView: a contact costs the cluster's terms, not
   the system's. See doc/fix_hardsphere_vci.rst.
------------------------------------------------------------------------- */

#ifndef LMP_HS_METHOD_VCI_H
#define LMP_HS_METHOD_VCI_H

#include "hs_method.h"

#include <vector>

namespace HardSphere {
struct VciRoot;
}

namespace LAMMPS_NS {

class HSMethodVCI : public HSMethod {
 public:
  HSMethodVCI(class LAMMPS *, HSSystem &);

  int needs_derivatives() const override { return 1; }

  void finish_step(double tleft) override;
  bool advance_to_contact(double &tau, double tleft, const Impulse &) override;
  void begin_collisional_step() override;
  void modify_impulse(Impulse &) override;

  // local form (rank-local inside a flow; the counters are summed over the
  // ranks at the end of each step taken by clusters)
  bool needs_flow_energy() const override { return true; }
  void flow_begun(const HSFlowView &) override;
  void flow_substep(const HSFlowView &) override;
  void modify_impulse_in_flow(Impulse &, HSFlowView &) override;
  void cluster_step_done(HSStepView &) override;
  void take_flow_counts(std::vector<double> &out) override;
  void add_flow_counts(const std::vector<double> &) override;

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

  // local form: this rank's counts since the last sum (as the counters
  // above: solved, no root, zero, evaluations; largest evaluations, |dE_d|)
  double lcount[4] = {0.0, 0.0, 0.0, 0.0}, lmax[2] = {0.0, 0.0};
  double fcount[4] = {0.0, 0.0, 0.0, 0.0}, fmax[2] = {0.0, 0.0};    // the current flow's
  void local_check(double Ed);
  // the root search's outcome: stops the run if it did not converge, warns
  // once if no root (elastic impulse); true if imp was scaled to the root
  bool take_root(const struct HardSphere::VciRoot &, Impulse &, double f1, bool all_ranks);

  double kinetic();
  double potential_at_new_x();
  double trial(const Impulse &, double s, double &scale, double &tau2);
  void check_pending(double Ed);
};

}    // namespace LAMMPS_NS

#endif
