/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: the global step engine (`substep global`): the
   paper's algorithm (Bond & Leimkuhler 2007, section 2.2). While time is
   left in the step, every atom sub-steps by the method's smooth map to the
   earliest contact anywhere, the method's impulse is applied there, and
   the loop repeats; the last sub-step's closing half kick is done in
   final_integrate with the forces LAMMPS computes at the step's end.
   Each contact costs a force evaluation of the whole system and a few
   collectives: the reference, exact to the paper. Held (thermostat)
   forces split the step as K_held(dt/2) . Phi(dt) . K_held(dt/2) (doc
   "Fixes beside the integrator").
------------------------------------------------------------------------- */

#ifndef LMP_HS_GLOBAL_ENGINE_H
#define LMP_HS_GLOBAL_ENGINE_H

#include "hs_step_engine.h"
#include "hs_types.h"

#include <vector>

namespace LAMMPS_NS {

class HSMethod;
class HSSystem;

class HSGlobalEngine : public HSStepEngine, public HSTypes {
 public:
  HSGlobalEngine(class LAMMPS *, HSSystem &, HSMethod &);
  bool step() override;
  bool finish() override;
  bool takes_captured_forces() const override;
  double counter(int k) override;

 private:
  HSSystem &S;
  HSMethod &M;
  void begin_held_split();
  void end_held_split();
  // forces of owned atoms outside the group, while another fix integrates
  // some: the sub-step evaluations overwrite them
  std::vector<double> fother;
  void save_other_forces();
  void restore_other_forces();
};

}    // namespace LAMMPS_NS

#endif
