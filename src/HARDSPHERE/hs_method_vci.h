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

#include <functional>
#include <string>
#include <vector>

namespace LAMMPS_NS {

class HSMethodVCI : public HSMethod {
 public:
  HSMethodVCI(class LAMMPS *, HSSystem &);

  int needs_derivatives() const override { return 1; }
  void init() override { require_fix_energies("the discrete energy E_d at each contact"); }

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

  // counts of the contacts' solves: solved (matched E_d), no root (elastic
  // fallback: no root, a jump of E_d^+, or a held contact), zero (elastic:
  // the next sub-step has zero length), evaluations of E_d^+ (trial
  // sub-steps); maxima: most evaluations for one contact, largest
  // |E_d(sub-step after) - E_d(before)|
  struct Tally {
    double n[4] = {0.0, 0.0, 0.0, 0.0};
    double mx[2] = {0.0, 0.0};
  };
  Tally all;     // the counters (global, identical on all ranks)
  Tally rank;    // local form: this rank's final flows since the last sum
  Tally flow;    // local form: the current flow's
  // the warnings printed once per fix, by kind (as the notes below)
  enum { WARN_NO_ROOT = 0, WARN_HELD = 1 };
  int warned[2] = {0, 0};
  // local form: a flow's warnings (no root, held contact) go with its
  // counts (a flow redone by a growth round drops its own) and are printed
  // by rank 0 at the step's end, the one of the lowest contact ID of the
  // step's final flows on any rank: once per fix, in the log, the same
  // message on any number of ranks
  struct Note {
    std::string text;
    double key = 0.0;    // the contact's lower atom ID
  };
  Note flow_note[2];                  // the current flow's first of each kind
  std::vector<Note> notes;            // of the step's flows, by index in their counts
  Note step_note[2];                  // of this rank's final flows: the lowest key
  void note(int kind, const Impulse &, const std::string &);
  // whether a contact of this kind still has a warning to give (its text
  // is formatted only then), and the warning given: at once by the global
  // form, as the flow's note by the local one
  bool wants_warning(int kind, bool all_ranks) const
  {
    return !warned[kind] && (all_ranks || flow_note[kind].text.empty());
  }
  void warn(int kind, const Impulse &, bool all_ranks, const std::string &);

  std::vector<double> xsave, vsave;

  // the impulse strength for imp, both forms: eval(s, scale, tau2) is
  // E_d^+(s) - E_d^- of a trial sub-step (tau2: its length); stops the run
  // if the root search does not converge, warns once if there is no root
  // (elastic impulse); counts into t
  // eval(s, scale, tau2, dF): F(s), its scale, the trial sub-step's length,
  // F'(s) (NaN where not known: the global form's trials)
  using Eval = std::function<double(double, double &, double &, double &)>;
  void solve(Impulse &imp, double slope, const Eval &eval, bool is_held, Tally &t,
             bool all_ranks);
  // a held contact (hs_method_vci.cpp, HELD): J2im = (2 v_n)^2, gn its
  // normal approach acceleration
  bool held(double J2im, double gn) const;

  double kinetic();
  double potential_at_new_x();
  double trial(const Impulse &, double s, double &scale, double &tau2);
  void check_pending(double Ed, Tally &t);
};

}    // namespace LAMMPS_NS

#endif
