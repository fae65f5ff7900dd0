/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: what a method may see and try inside one cluster's
   flow of the local engine (Phi_H1 of hs_local_engine.h: the members'
   CVA flow of H1 = T_C + V_C, partners static, the cross terms as a
   constant force f_X). It is to the cluster what HSSystem's sub-stepping
   (kick, drift, predict, energy) is to the whole system for a method run
   by the global engine: fix hardsphere/vci matches the discrete energy of
   the sub-steps across a contact through it (doc/fix_hardsphere_vci.rst,
   "Local form").

   The flow's potential is V_C (the styles' own energies of the cluster's
   restricted terms, hs_local_forces.h) minus f_X . (q - q_start) summed
   over the members: the potential whose forces the flow integrates.
   Energies are kept only when the method asks (needs_flow_energy()).
   A flow runs on one rank (its cluster's runner): nothing here is
   collective.
------------------------------------------------------------------------- */

#ifndef LMP_HS_FLOW_VIEW_H
#define LMP_HS_FLOW_VIEW_H

#include "hs_types.h"

#include <cmath>
#include <vector>

namespace LAMMPS_NS {

// one cluster's flow run by its method instead of CVA's sub-steps
// (HSMethod::runs_cluster_flows(): mcva's local form, the Gauss flow of the
// cluster's modified Hamiltonian, hs_cluster_flow.h). The engine fills the
// input (its copies, rank-local, as the flow's own: atom->x and v hold the
// members' state at the flow's start) and applies the output: the members'
// end, their paths (the engine's checks of other clusters and atoms), the
// partners' kicks, the impulses (counts, virial)
struct HSClusterFlowJob {
  // ---- in
  double h = 0.0;                      // the flow's length
  std::vector<int> members;            // the members' copies
  std::vector<double> fc;              // [3 nm] constant force on each (cross terms, held)
  // the cluster's terms, as HSLocalForces lists them (term_local(), ...):
  // term t's copies tloc[toff[t] .. toff[t+1]), pairs first (npair), extra:
  // a pair's special index, a bond's type (<= 0: broken)
  const std::vector<int> *tloc = nullptr, *toff = nullptr, *textra = nullptr;
  int npair = 0;
  std::vector<int> statics;            // contact candidates that are not members (copies)
  std::vector<int> partners;           // copies that take the terms' momentum
  // ---- out
  enum { DONE = 0, GROWS = 1 };
  int result = DONE;
  int hit_member = -1, hit_static = -1;    // GROWS: a member's copy touches a static one
  std::vector<double> xend, vend;          // [3 nm] the members at the flow's end
  std::vector<double> dvp;                 // [3 np] the partners' velocity changes
  struct Seg {
    double t0, t1, q[3], v[3], a[3];    // q(t) = q + (t - t0) v + (t - t0)^2/2 a, q absolute
  };
  std::vector<std::vector<Seg>> segs;      // per member, in time order
  struct Kick {
    int i, j;             // member copies; j < 0: wall -1 - j
    double J[3], dq[3];   // momentum given to i (j: -J), contact normal (HSTypes::Impulse)
  };
  std::vector<Kick> kicks;
};

class HSFlowView {
 public:
  // a Verlet sub-step of the flow (kick, drift, forces, kick) of length
  // tau: kh = 1/2 |v_h|^2_M of the members, v_h their velocity after the
  // first half kick (= (q_end - q_start) / tau); v0, v1 the flow's
  // potential at its start and end. tau = 0: no sub-step (a contact at the
  // flow's start or at the instant of the last contact): kh the kinetic
  // energy now, v0 = v1 the potential now. A trial's dkh and dv1: the
  // derivatives of kh and v1 in lambda for the impulse lambda imp at lambda
  // = 1, with the sub-step's length held (NaN where it is not: the trial's
  // sub-step ends at a contact, whose time moves with the impulse, or has
  // length 0)
  struct Substep {
    double tau, kh, v0, v1;
    double dkh = NAN, dv1 = NAN;
  };
  // the last sub-step taken (at a contact: the one that led to it)
  virtual const Substep &last_substep() const = 0;
  // the sub-step the flow would take next if the contact got `imp` instead
  // of the impulse it is about to get: the impulse applied, the next
  // contact of the flow predicted in the time left (tau <= that time), the
  // sub-step's half kick and drift, the potential at its end. The flow's
  // state is left as it was
  virtual Substep trial(const HSTypes::Impulse &imp) = 0;
  // the contact about to get its impulse: the relative normal acceleration
  // of its two spheres (or of the sphere towards the wall) under the
  // flow's forces, positive if they pull them together
  virtual double approach_accel() const = 0;

 protected:
  ~HSFlowView() = default;
};

}    // namespace LAMMPS_NS

#endif
