/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: shared base of the hard-sphere integrator family
   (Bond & Leimkuhler, SIAM J. Sci. Comput. 30(1), 2007).

   The fix is the LAMMPS shell of the family (doc/fix_hardsphere.rst, "How
   the code is organised"): keywords, neighbor list requests, the checks of
   the fixes beside it, the choice of step engine, the screening that sends
   a step to fix nve's arithmetic or to the engine, communication hooks,
   output vector and restart. The system layer (hs_system.h) holds the
   plumbing every step shares, the step engines (hs_global_engine.h,
   hs_local_engine.h) order a step with contacts, and the method
   (hs_method.h and its subclasses) supplies what a method changes. A
   method's fix class only creates its method and handles its own keywords.
------------------------------------------------------------------------- */

#ifndef LMP_FIX_HARDSPHERE_H
#define LMP_FIX_HARDSPHERE_H

#include "fix.h"
#include "hs_types.h"

#include <string>

namespace LAMMPS_NS {

class HSMethod;
class HSStepEngine;
class HSSystem;

class FixHardSphere : public Fix, public HSTypes {
 public:
  FixHardSphere(class LAMMPS *, int, char **);
  ~FixHardSphere() override;
  void post_constructor() override;
  int setmask() override;
  void init() override;
  void init_list(int, class NeighList *) override;
  void setup(int) override;
  void post_run() override;
  void pre_exchange() override;
  void setup_post_neighbor() override;
  void post_neighbor() override;
  void initial_integrate(int) override;
  void post_force(int) override;
  void final_integrate() override;
  void reset_dt() override;
  double compute_vector(int) override;
  int modify_param(int, char **) override;
  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;
  int pack_reverse_comm(int, int, double *) override;
  void unpack_reverse_comm(int, int *, double *) override;
  void write_restart(FILE *) override;
  void restart(char *) override;
  double memory_usage() override;

  // for fix hardsphere/press (fix_hardsphere_press.h), which changes the
  // box: the contact radius of a sphere of the group, and the notice that
  // positions and the box changed at the end of a step (caches of the
  // step's end, the held-force split and the screening ahead, are stale)
  double sphere_radius(int i) const;
  // LAMMPS' conservative forces of this step's end, copied before the held
  // fixes' post_force (HSSystem::captured()); null if not copied
  double **captured_forces() const;
  void box_changed();

 protected:
  std::string style_name;    // e.g. "hardsphere/cva", for messages
  HSSystem *sys;             // the plumbing every step shares
  HSSystem &S;
  // the method (set by the method's fix class in its constructor; psa,
  // which takes its steps itself, has none)
  HSMethod *method = nullptr;
  enum { CONTACT_LIST_ID = 0, POT_LIST_ID = 1 };
  std::string path_told;    // the derivative paths last reported

  // step engines (doc "Step engines"): how a step with contacts is
  // sub-stepped. Each is created once and kept (its counters go on from
  // run to run); init() chooses the one of this run
  enum { SUBSTEP_DEFAULT = 0, SUBSTEP_LOCAL = 1, SUBSTEP_GLOBAL = 2 };
  int substep_mode = SUBSTEP_DEFAULT;    // the keyword
  HSStepEngine *stepped = nullptr;       // the engine that took the current step
  bigint virial_step = -1;               // the step whose collisions virial holds
  // a run that skips its set-up (run ... pre no) goes on from the last
  // run's end: HSSystem::state_fingerprint() then and at its first step
  bool set_up = false;                   // setup() ran since the last run ended
  bool ended = false;                    // a run ended (end_state valid)
  bool minimized = false;                // ... and it was a minimization
  uint64_t end_state = 0;
  void check_state_kept();
  // comm_modify mode multi: the ghost cutoffs of every collection (setup())
  void check_multi_ghosts();
  // the neigh_modify exclusion that removes pairs of the group, or ""
  std::string excluded_group_pairs() const;
  void begin_step_virial();              // a step's: from zero (initial_integrate())
  HSStepEngine *engine = nullptr;        // this run's, or none (psa)
  HSStepEngine *global_engine = nullptr, *local_engine = nullptr;
  int local_vec_offset = 5;              // first output entry of the engine's counters
  std::string local_why_told;
  void choose_engine();

  std::string unknown_told, held_told;    // fixes named in the log already
  // a constraint fix (shake, rattle) on atoms outside the group: fine with
  // substep local and psa, which evaluate no fix between LAMMPS' own
  // force stages; an error with the global engine (check_fixes_beside())
  std::string constraint_beside;
  std::string peratom_told;               // computes warned about already
  void check_fixes_beside();
  void capture_rule();
  std::string capture_told;    // why held forces are not captured, in the log already
  void check_peratom_virial();
  void check_other_integrators();
};

}    // namespace LAMMPS_NS

#endif
