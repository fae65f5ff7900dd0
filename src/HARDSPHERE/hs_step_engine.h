/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: how a step with contacts is sub-stepped (doc
   "Step engines"). The fix screens each step; a step in which some sphere
   may touch another goes to its engine, as LAMMPS' Verlet and Respa run
   styles order a step apart from the fixes that integrate:

   - HSGlobalEngine (hs_global_engine.h): the paper's algorithm, every atom
     sub-steps to every contact (section 2.2);
   - HSLocalEngine (hs_local_engine.h): the clusters of colliding spheres
     sub-step alone, inside a splitting with the rest of the system.

   Either drives the method (hs_method.h) through the same interface. An
   engine works on the shared system layer (hs_system.h) and knows no fix.
------------------------------------------------------------------------- */

#ifndef LMP_HS_STEP_ENGINE_H
#define LMP_HS_STEP_ENGINE_H

#include "pointers.h"

#include <string>

namespace LAMMPS_NS {

// derived from Pointers alone, so that its (virtual) destructor is
// Pointers' in every LAMMPS version (noexcept(false) since 2023)
class HSStepEngine : protected Pointers {
 public:
  explicit HSStepEngine(class LAMMPS *lmp) : Pointers(lmp) {}
  // from the fix's init(): "" if the engine can run this set-up, else why
  // not (the styles or fixes named)
  virtual std::string limits() { return ""; }
  // from the fix's init(), once this engine is chosen: what it needs of the
  // set-up before the run's set-up (the local engine: its ghost cutoff)
  virtual void chosen() {}
  // the ghost cutoff the engine needs, after chosen() (0: the contact
  // list's alone); the fix checks it where it cannot set it (comm_modify
  // mode multi)
  virtual double ghost_needed() const { return 0.0; }
  // true if the engine takes held forces as f less LAMMPS' own conservative
  // force when the fix can copy it (HSSystem::captured()): the whole held
  // force where every force in f but the held ones is in its restricted
  // evaluations, else the part the copy separates (the local engine's
  // held smooth forces beside a thermostat, HSLocalEngine::splits_held())
  virtual bool takes_captured_forces() const { return false; }
  // what the engine does instead when the fix cannot copy that force (for
  // the log)
  virtual std::string uncaptured_cost() const
  {
    return "the held forces come from a second evaluation of the conservative forces in "
           "each collisional step";
  }
  // initial_integrate of a step in which screening found spheres that may
  // touch: the step up to its closing half kick (collective). Returns false
  // if the engine declined the step, with the state left as before (the
  // local engine: a collision cluster outgrew the ghost atoms and the user
  // asked for `overflow global`): the caller takes it with another engine
  virtual bool step() = 0;
  // final_integrate: the closing of a step this engine took, if it needs
  // more than the plain closing kick; returns false if it does not
  virtual bool finish() = 0;
  // pre_exchange of a reneighboring step (before its exchange and borders)
  virtual void pre_exchange() {}
  // the engine's output entries (fix output vector, after the method's):
  // clusters, mean and largest members per cluster, growth rounds, steps
  // that fell back to the global engine, restricted force evaluations,
  // collective communications per step taken by clusters, steps whose
  // flagged spheres alone cleared the first guess, times the ghost cutoff
  // was widened (overflow widen), times ghost lazy's shell went from
  // LAMMPS' ghost cutoff to the engine's, the busiest rank's restricted
  // evaluations over the ranks' mean
  static constexpr int NCOUNTERS = 11;
  virtual double counter(int k) = 0;
  // bytes of the engine's own arrays (the fix's memory_usage())
  virtual double memory_usage() const { return 0.0; }
};

}    // namespace LAMMPS_NS

#endif
