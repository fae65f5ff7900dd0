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

   The terms are those HSLocalForces finds for the members: radial ones
   (pair and bond styles with single()) through the single path of
   HSPotential (phi'' analytic or by differences in r); the others (angles,
   dihedrals, impropers, bonds without single()) by their style's compute()
   on each term alone (HSLocalForces::bonded_term()), V_t'' v and V_t'' b
   by central differences of its forces (general_term()). kspace and
   fixes with an energy (not restrictable; the engine holds their forces
   G on the members) enter by the members' share of their energy change,
   minus G's work on them by the trapezoid rule (held_energy_change()). With held
   (thermostat) forces the ledger is that of the conservative map between the held half
   kicks: velocities after the first and before the last, conservative
   forces of members and partners from restricted evaluations of all their
   terms. Any number of MPI ranks: each rank evaluates its share of the
   terms (those its lists hold) on its copies, the per-atom sums go to the
   owners by reverse communication and the owners' velocities to the
   ghosts by forward communication, the clusters' centres of mass and
   A, B, C0 are summed over the ranks (MPI_Allreduce); after a list rebuild
   with migration, members and partners are found again by ID (remap()).
------------------------------------------------------------------------- */

#ifndef LMP_HS_LOCAL_MODIFIED_H
#define LMP_HS_LOCAL_MODIFIED_H

#include "hs_mpi.h"
#include "hs_step_view.h"

#include "atom.h"
#include "lmptype.h"
#include "pointers.h"

#include <array>
#include <cstdint>
#include <vector>

namespace LAMMPS_NS {

class HSSystem;
class HSPotential;

class HSLocalModified : protected Pointers {
 public:
  HSLocalModified(class LAMMPS *, HSSystem *, HSPotential *);
  ~HSLocalModified() override;

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
  // this rank's members' part of V_C from constant one-atom forces (fix
  // gravity: -F.q, unwrapped), at the step's start or end
  double const_energy(HSStepView &, bool at_start) const;
  // kspace or fixes with an energy (not fix gravity's) in V: the engine
  // holds their forces G = f - F_C on the members (riding inside their
  // flows, the closing kick making the impulse dt/2 (G0 + G1)); their
  // energy, not restrictable, changes by minus their work on each member,
  // taken by the trapezoid rule: -1/2 (G0 + G1).(q1 - q0) (doc
  // fix_hardsphere_pcva, "Held smooth forces")
  void set_held_work(bool on) { held_work = on; }
  // bytes of its per-copy columns and kept lists (the fix's memory_usage())
  double memory_usage() const;
  int nmembers() const { return (int) mem.size(); }

 private:
  HSSystem *sys;
  HSPotential *pot;
  using Vec = std::array<double, 3>;

  // a neighbor list rebuild between begin() and end() may sort the atoms
  // or move them to other ranks: what end() needs of the start is kept by
  // ID (remap())
  std::vector<tagint> mtag;           // members owned here
  bool held_work = false;
  // with held_work, per member (mtag's order): G and the unwrapped
  // position at the step's start
  struct MemberStart {
    Vec g0, q0;
  };
  std::vector<MemberStart> mstart;
  std::vector<MemberStart> remap_mst;
  // this rank's members' held forces' work -1/2 (G0 + G1).(q1 - q0) (end())
  double held_energy_change(HSStepView &);
  // G of member m now and its position x unwrapped (begin(): x0; end(): x)
  void held_state(HSStepView &, int m, const double *x, Vec &g, Vec &q) const;
  std::vector<int> mem, cid;          // their local indices, cluster index
  int ncl = 0;                        // the step's clusters (the same on every rank)
  struct Start {
    Vec v0, d1, d2, fr0;    // velocity, the two Phi_H1 kicks, F^R at the start
  };
  std::vector<tagint> ptag;           // the start's partners owned here (and their data)
  std::vector<Start> pstart;
  // remap()'s buffers (kept between steps: rebuilt each step they cost
  // page faults)
  struct RemapMember {
    int cid, rank, seq;    // cluster; rank and position in begin()'s list
    tagint tag;
    int src;               // its MemberStart: index in mstart, or -1 - offset in remap_all
  };
  std::vector<RemapMember> remap_ms;
  std::vector<std::pair<tagint, int>> remap_ps;    // ID, index in pstart or -1 - offset in remap_all
  std::vector<Start> remap_st;
  std::vector<double> remap_out;
  HardSphere::GatherBuffer<double> remap_all;
  std::vector<int> pidx;              // end(): their local indices now
  double L0 = 0.0;                    // this rank's part of L at the start

  // this rank's share of the members' terms (local copies), and the owned
  // atoms in a term on any rank: members first, then partners
  std::vector<int> tloc, toff, textra, tcopies;
  int npair = 0;
  bigint terms_ncalls = -1;           // neighbor->ncalls when they were found
  std::vector<int> owners;
  std::vector<char> is_mem;           // per owner
  std::vector<int> ghosted;           // the owners with a ghost copy in a term
  // a ghost copy's flag in red column 6 (an owned copy's is 1): exact in a
  // sum over any number of copies
  static constexpr double GHOST_COPY = 1048576.0;
  void mark_copies();
  std::vector<uint32_t> ostamp;
  uint32_t oepoch = 0;
  std::vector<Vec> rel;               // per member: b of the projection
  // per local copy: red = F of V_CX, V_CX'' v, a flag (summed into the
  // owners by reverse communication; zero outside red_rows), fwd = the
  // owners' velocities and b, forwarded to the ghosts
  int nmax = 0;
  double **red = nullptr, **fwd = nullptr;
  std::vector<int> red_rows;
  void grow();
  void zero_red();

  std::vector<char> pmark;            // owners_from_flags(): partners marked
  void list_terms(HSStepView &);
  void owners_from_flags();
  void find_terms(HSStepView &);    // list_terms(), flags reversed, owners_from_flags()
  void forward_state(bool with_rel);
  void remap();
  // this rank's E = V_CX, Q = sum v^T V_t'' v and (WITH_B; else 0) Qbb =
  // sum b^T V_t'' b over its terms at positions xpos(copy); red reversed
  // into the owners (flags: with the term copies' flags of find_terms() in
  // column 6). begin() needs no Qbb (the directions b come at the end)
  template <bool WITH_B, class X>
  void terms_eval(X xpos, double &E, double &Q, double &Qbb, bool flags);
  // term t when it is not a radial pair or bond term (terms_eval())
  template <bool WITH_B, class X>
  void general_term(int t, X xpos, double &E, double &Q, double &Qbb);
  int kend[4] = {0, 0, 0, 0};            // where each bonded kind's terms end
  class HSLocalForces *terms_lf = nullptr;    // who listed them (bonded_term())
  // general_term()'s displaced positions and forces (rows of its copies)
  double **xs = nullptr, **fs = nullptr;
  int nmax_xs = 0;
  // its central differences' displacement over L (general_term())
  static constexpr double FD_STEP = 1.0e-4;
  double local_L(double E, double Q, double T);
  // conservative forces and velocities (held forces taken out), per local
  // index. Without held forces they are f and v (v0 at the start) themselves,
  // read in place (direct): a copy of the owners' rows, about half of all
  // atoms at the fluid's collision rate, cost ~4 % of pcva's memory traffic
  std::vector<Vec> fcons_, vcons_;
  std::vector<uint32_t> cstamp;
  uint32_t cepoch = 0;
  // conservative_state()'s lists, kept: about half the atoms each at the
  // fluid's collision rate, so fresh vectors were fresh pages every step
  // (the kernel's page clearing 4 % of a pcva + langevin step at 2048000 atoms)
  std::vector<int> cs_atoms, cs_set, cs_moved;
  std::vector<Vec> cs_saved;
  bool cons_direct = false, cons_start = false;
  HSStepView *cons_view = nullptr;
  void conservative_state(HSStepView &, bool at_start);
  const double *cons(int i) const { return cons_direct ? atom->f[i] : fcons_[i].data(); }
  const double *vcons(int i) const
  {
    if (!cons_direct) return vcons_[i].data();
    return cons_start ? cons_view->start_v(i) : atom->v[i];
  }
  void relative();
};

}    // namespace LAMMPS_NS

#endif
