/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: what a method of the family supplies to the step
   engines (doc/fix_hardsphere.rst, "How the code is organised"). The base
   class is the collision Verlet algorithm (Bond & Leimkuhler 2007, section
   2.2): Verlet sub-steps between contacts and the elastic impulse R of
   section 2. A method overrides what differs; it does not know which
   engine calls it, and calls only the system layer (hs_system.h).

   - the collision operator: collide_pair/collide_wall build the elastic
     impulse at contact (both engines call them); modify_impulse changes it
     in the global engine (mcva's alpha-hat, vci's E_d match),
     modify_impulse_in_flow in a cluster's flow of the local one (vci);
   - the smooth map between contacts of a step that sub-steps every atom
     (finish_step, advance_to_contact) and the bookkeeping around it
     (begin_collisional_step, end_substep, end_collisional_step): pcva's
     projection, mcva's Gauss flow, vci's energy match;
   - a step taken cluster by cluster (cluster_step_begun/done, seen through
     HSStepView): pcva's local projection; inside one cluster's flow
     (flow_begun, flow_substep, modify_impulse_in_flow, seen through
     HSFlowView, rank-local): vci's energy match;
   - which engines it supports, why a set-up rules out the local one, and
     its own counters (output entries after the fix's five, restart).
   All hooks are called on every rank together (collective), except those
   inside a cluster's flow (on the rank that runs it).
------------------------------------------------------------------------- */

#ifndef LMP_HS_METHOD_H
#define LMP_HS_METHOD_H

#include "hs_types.h"
#include "pointers.h"

#include <string>
#include <vector>

namespace LAMMPS_NS {

class HSSystem;
class HSStepView;
class HSFlowView;
struct HSClusterFlowJob;

class HSMethod : protected Pointers, public HSTypes {
 public:
  HSMethod(class LAMMPS *, HSSystem &);
  ~HSMethod() override = default;

  // which step engines can drive it
  enum { ENGINE_NONE = 0, ENGINE_GLOBAL_ONLY = 1, ENGINE_BOTH = 2 };
  virtual int engines_supported() const { return ENGINE_BOTH; }
  // which engine the fix chose (before init(): a method may say which form runs)
  virtual void engine_chosen(bool /*local*/) {}
  // its own reasons it cannot run cluster by cluster with this set-up ("" if none)
  virtual std::string local_limits() { return ""; }
  // 1 if it needs derivatives of V (HSPotential's paths set up in init)
  virtual int needs_derivatives() const { return 0; }
  // at the end of the fix's init(); fix_modify keywords of its own
  virtual void init() {}
  virtual int modify_param(int, char **) { return 0; }
  virtual double memory_usage() { return 0.0; }

  // --- collision operator R at contact, on the rank owning i: fills the
  // momentum J given to i (j receives -J) and imp.apply (0 for a grazing
  // contact with no approaching normal velocity, which gets no impulse)
  virtual void collide_pair(int i, int j, Impulse &);
  virtual void collide_wall(int i, const Wall &, Impulse &);
  // change the elastic impulse (imp.J, imp.reflect) built by collide_*()
  virtual void modify_impulse(Impulse &) {}

  // --- a step that sub-steps every atom to every contact ---
  // no contact in the remaining tleft: finish the step (set dtf_last)
  virtual void finish_step(double tleft);
  // move to the contact predicted at tau; may change tau; return false if
  // the method then finds no contact (it must have finished the step)
  virtual bool advance_to_contact(double &tau, double tleft, const Impulse &);
  // once per step, before its first sub-step, if the step has a contact
  virtual void begin_collisional_step() {}
  // after each contact's impulse (tau: the sub-step just taken)
  virtual void end_substep(double) {}
  // in final_integrate after the closing kick of a step that sub-stepped
  virtual void end_collisional_step() {}

  // --- a step taken cluster by cluster: after the engine's step (x, v as
  // the engine left them, f still the start forces), after its closing
  // kick (all at the end)
  virtual void cluster_step_begun(HSStepView &) {}
  virtual void cluster_step_done(HSStepView &) {}
  // inside one cluster's flow (hs_flow_view.h), on the rank that runs it
  // only (not collective): at its start, after each sub-step (also one of
  // length 0 between two contacts at the same instant), and at a contact
  // (the elastic impulse built by collide_*(); the global engine's methods
  // change it in modify_impulse()). A flow may be redone from its start
  // when its cluster grows. The flows keep their sub-steps' energies only
  // if needs_flow_energy()
  virtual bool needs_flow_energy() const { return false; }
  virtual void flow_begun(const HSFlowView &) {}
  virtual void flow_substep(const HSFlowView &) {}
  virtual void modify_impulse_in_flow(Impulse &, HSFlowView &) {}
  // the method's counts of the flow just ended, moved into out; the engine
  // keeps them with the flow and gives back those of the step's final flows
  // (not redone by a growth round) at the step's end, on the flow's rank
  virtual void take_flow_counts(std::vector<double> &out) { out.clear(); }
  virtual void add_flow_counts(const std::vector<double> &) {}
  // a method whose cluster flows are its own (mcva: the Gauss flow of the
  // cluster's modified Hamiltonian) instead of CVA's sub-steps: the engine
  // hands it each flow (hs_flow_view.h, HSClusterFlowJob; rank-local)
  virtual bool runs_cluster_flows() const { return false; }
  virtual void cluster_flow(HSClusterFlowJob &) {}

  // --- its own counters: output entries after the fix's, restart
  virtual int nvector() const { return 0; }
  virtual double vector(int) { return 0.0; }
  virtual std::vector<double *> counters() { return {}; }

 protected:
  HSSystem &S;
  // for the methods that keep an energy of the whole system (pcva's
  // H_[2,VV], mcva's, vci's E_d): an error naming each conservative fix
  // whose energy is not in the potential energy (its force would change the
  // kept energy, and the method would undo that change)
  void require_fix_energies(const char *what) const;
  // the local projection's own limit (pcva's and mcva's local forms,
  // hs_local_modified.h): "" or why the input's fix order rules it out;
  // held_work: the held energy terms whose work it counts ("" if none)
  std::string projection_limits(std::string &held_work) const;
};

}    // namespace LAMMPS_NS

#endif
