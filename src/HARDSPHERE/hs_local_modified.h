/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: the change of the modified Hamiltonian H_[2,VV]
   (Bond & Leimkuhler 2007, section 3) over one step of the local engine
   (hs_local_engine.h), from the colliding spheres' terms only, and the
   projection of fix hardsphere/pcva with substep local.

   The engine's step is Phi_H1(dt/2) Phi_H2(dt) Phi_H1(dt/2) with H1 = T_C +
   V_C, H2 = T_N + V_R (C: the members of the step's clusters). Write
   H~ = H_[2,VV] and H~2 for velocity Verlet's modified Hamiltonian of H2
   (what Phi_H2, a smooth Verlet step of H2, keeps to O(dt^5)). Then

     L = H~ - H~2 = T_C + V_CX + dt^2/24 ( 2 sum_{t in V_CX} v^T V_t'' v
                    - sum_{i in C} |F_i|^2_M - sum_{p in P} (2 F^C_p.F^R_p + |F^C_p|^2)_M )

   is a sum over the terms with a member (V_CX = V_C + cross terms) and the
   forces on members and partners P (F^C: force of V_CX, F^R = F - F^C): a
   local function. H~2 changes only in the Phi_H1 flows, and only through
   what they change: the partners' momenta (V_C's kicks dv) and the cross
   terms' energy (in V_CX above). Its change there is

     dT_P + dt^2/6 sum_p (V_R'' v)_p . dv_p + O(dt^4),

   with (V_R'' v)_p = -dF^R_p/dt taken as -(F^R_p(end) - F^R_p(start))/dt
   (an O(dt) error, times dt^2 dv = O(dt^3): O(dt^4) per step with
   clusters, and clusters come at a fixed rate per unit time). So

     dH~(step) = L(end) - L(start) + dT_P + dt^2/6 sum_p g_p . dv_p + O(dt^4)

   from the cluster's terms alone. The derivation is in
   doc/fix_hardsphere_pcva.rst, "Local projection"; it is checked against
   compute hamiltonian/modified in unittest/lammps/test_pcva_local.cpp.

   The terms are evaluated through the single path of HSPotential (pair and
   bond styles with single(); phi'' analytic or by differences in r), on
   the terms HSLocalForces finds for the members. With held (thermostat)
   forces the ledger is that of the conservative map between the held half
   kicks: velocities after the first and before the last, conservative
   forces of members and partners from restricted evaluations of all their
   terms. One rank, as the engine.
------------------------------------------------------------------------- */

#ifndef LMP_HS_LOCAL_MODIFIED_H
#define LMP_HS_LOCAL_MODIFIED_H

#include "lmptype.h"
#include "pointers.h"

#include <array>
#include <cstdint>
#include <vector>

namespace LAMMPS_NS {

class HSSystem;
class HSStepView;
class HSPotential;

class HSLocalModified : protected Pointers {
 public:
  HSLocalModified(class LAMMPS *, HSSystem *, HSPotential *);

  // after the engine's step (HSMethod::cluster_step_begun) (atom->f: the step's start forces): the
  // members, their terms and L at the step's start
  void begin(HSStepView &);
  // after the engine's closing kick (x, v, f at the step's end): the
  // change of H~ over the step, and the coefficients of the projection
  // v_i -> v_i + beta b_i (i in C; b_i = v_i - the velocity of its
  // cluster's centre of mass, or v_i for a cluster of one sphere):
  // dH~(beta) = A beta^2 + B beta + C0
  void end(HSStepView &, double &A, double &B, double &C0);
  // v_i -> v_i + beta b_i on the members, with the b of end()
  void scale(HSStepView &, double beta);
  int nmembers() const { return (int) mem.size(); }

 private:
  HSSystem *sys;
  HSPotential *pot;
  using Vec = std::array<double, 3>;

  // a neighbor list rebuild between begin() and end() may sort the atoms:
  // what end() needs of the start is kept by tag
  std::vector<tagint> mtag;           // members
  std::vector<int> mem, cid;          // members' local indices, cluster index
  struct Start {
    Vec v0, d1, d2, fr0;    // velocity, the two Phi_H1 kicks, F^R at the start
  };
  std::vector<tagint> ptag;           // the start's partners (and their data)
  std::vector<Start> pstart;
  std::vector<int> pidx;              // end(): their local indices now
  double L0 = 0.0;

  // the terms of the members at the current lists, their distinct owners
  std::vector<int> tloc, toff, textra, tatoms;
  int npair = 0;
  bigint terms_ncalls = -1;           // neighbor->ncalls when they were found
  std::vector<int> owners;            // members first, then partners
  std::vector<int> slot;              // owner -> index in owners (stamp-checked)
  std::vector<uint32_t> sstamp;
  uint32_t sepoch = 0;
  std::vector<char> is_mem;           // per slot
  std::vector<Vec> fc, kv;            // per slot: F of V_CX, V_CX'' v
  std::vector<Vec> rel;               // per member: b of the projection

  void find_terms(HSStepView &);
  int slot_of(int i) const { return (i < (int) sstamp.size() && sstamp[i] == sepoch) ? slot[i] : -1; }
  // E = V_CX, Q = sum v^T V_t'' v and Qbb = sum b^T V_t'' b over its
  // terms, fc, kv at positions xpos(owner) + image offset, velocities
  // vel(owner) and the projection's directions bvel(owner)
  template <class X, class V, class B>
  void terms_eval(X xpos, V vel, B bvel, double &E, double &Q, double &Qbb);
  double local_L(double E, double Q, double T);
  // conservative forces and velocities (held forces taken out), per local index
  std::vector<Vec> fcons_, vcons_;
  std::vector<uint32_t> cstamp;
  uint32_t cepoch = 0;
  void conservative_state(HSStepView &, bool at_start);
  const double *cons(int i) const { return fcons_[i].data(); }
  const double *vcons(int i) const { return vcons_[i].data(); }
  void relative(HSStepView &);
};

}    // namespace LAMMPS_NS

#endif
