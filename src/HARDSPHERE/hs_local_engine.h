/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: the local step engine (`substep local`, issue 10).

   The global engine (the paper's algorithm, hs_global_engine.h)
   sub-steps every atom to every contact with a full force evaluation, so a
   step costs O(N) per collision. This engine makes a collision cost
   O(its neighbours). Per step, C is the spheres that collide in it
   ("members"), grouped into clusters (spheres that touch, or share a
   bonded term); V_C is every interaction term with a member except the
   pair terms between members of two clusters (cross terms V_X);
   V_R = V - V_C. With T_C, T_N the kinetic energies of members and
   non-members, H = H1 + H2, H1 = T_C + V_C, H2 = T_N + V_R, integrated as

     Phi_H1(dt/2) . Phi_H2(dt) . Phi_H1(dt/2)

   - Phi_H1(h): only members move, by the CVA flow (Bond & Leimkuhler 2007,
     section 2.2) of T_C + V_C; other atoms stay put and take V_C's
     momentum (trapezoid kicks of the sub-steps). No term of V_C couples
     two clusters and partners do not move: one independent flow per
     cluster, each with its own terms only (HSLocalForces).
   - Phi_H2(dt): one velocity-Verlet step of the non-members under V_R;
     members do not move in it. An atom in no term of V_C takes fix nve's
     step.
   - The cross terms V_X (in V_R, on members only) act inside both halves
     of the members' flow, as a constant force F_X(q0) in the first and
     F_X(q1) at the members' ends in the second (issue 19; q1 by one
     corrector step from the extrapolation 2 F_X(q_mid) - F_X(q0), which
     alone made the step time-asymmetric at O(dt^3) and the energy drift:
     cross_at_end()). Their impulse over the step is dt F_X(q_mid) to
     O(dt^3), the exact flow of V_X in Phi_H2, but a kick
     between the halves does not commute with a contact's impulse R: R at
     t_c reverses only the cross momentum that came before t_c, so the
     kick leaves the normal velocity wrong by 2 min(t_c, dt - t_c) a_X.n,
     O(dt) per collision, a first-order engine on fluids. Spread over the
     halves, the cross momentum taken by any time is right to O(dt^2).
     On several ranks (issue 20) F_X(q0) needs the start positions of the
     cross neighbours' members, F_X(q_mid) their mid positions and
     F_X(q1) their ends: the ghost x0 and the members' displacements in
     the packets of each half, which the engine exchanges anyway (its
     cross checks).

   Inside a flow the method sees the cluster through HSFlowView
   (hs_flow_view.h): the sub-steps' energies (V_C from the restricted
   evaluation's tallies, minus f_X . dq) and trial sub-steps after a
   contact; vci matches its discrete energy there (issue 21). Its counts
   are kept per flow (Run::mcount) and summed from the step's final flows.

   Each flow is exact for its Hamiltonian up to CVA's / Verlet's own error;
   the step is second order (measured, doc "Step engines") and conserves
   momentum (V_X's forces at q0 and at q_mid are equal and opposite on the
   two clusters). A contact found in either flow with a non-member, or
   between members of two clusters, grows C; a growth round redoes only
   the clusters that changed and the atoms around them.

   Why not the partners-join splitting K_R(dt/2) . Phi_C(dt) . K_R(dt/2)
   of the issue, or clusters joined by pair terms: both percolate in
   dense fluids (bench/scaling/README.md; doc "Step engines"). Both
   splittings are checked against brute force in
   unittest/math/test_local_splitting.cpp.

   Held (thermostat) forces: a member takes its held force (f minus the
   conservative force of all its terms: LAMMPS' own, copied by the fix
   before the held fixes' post_force when the input's order allows,
   HSSystem::captured(); else evaluated) as two half kicks at the step's
   start and end (as the global engine's K_held(dt/2) . Phi . K_held(dt/2)),
   a non-member with V_R in Phi_H2's kicks, as beside fix nve. Held smooth
   forces (kspace, fixes that only add a force: limits()) are in the same
   f - F_C; with them it rides inside the members' flows instead (its start
   value as a constant force in both halves, the end's in the closing
   kick: rides()), since a kick before a flow errs by O(dt) at a contact.
   With both, a thermostat's part H = f - (the copy) stays two half kicks
   and only G = (the copy) - F_C rides (splits_held()); without the copy
   (the input's fix order) both ride.

   Rows: V_C's forces come from rank-local interaction rows of the
   members' copies (HSLocalForces::compute_rows) and their contact
   candidates from rows of the same kind (crow()), both at the list build's
   positions (newton_pair on or off, neigh_modify exclude applied), on any
   number of ranks.

   Any number of MPI ranks, one code (issue 20, doc/Developer_hardsphere.
   rst): the step's clusters are a ClusterSet over dense ids of the
   members' atom IDs, ordered by ID, the same on every rank (every hit is
   gathered before anyone grows). A cluster is run by the owner of one of
   its members (runner_of(); its key is the lowest member ID) on its
   copies: an owned member by its owned copy, another by its ghost copy
   nearest the runner's (its rows must be complete:
   member_copies() checks the ghost cutoff, chosen() raises it). Per growth
   round a constant number of collectives: the first halves' packets
   (members' mid displacement, velocity, path segments) and the flows'
   hits in one MPI_Allgatherv; the cross checks' hits; the partners' sums
   (V_C's start force, first-half kicks) reversed into the owners, which
   set Phi_H2's velocities w and forward them; Phi_H2's hits (each pair
   checked by the rank listing it) and the largest line deviation; the
   cross neighbours; the second halves' packets and hits; their cross
   checks' hits. Each rank detects the copies whose Phi_H2 path changed
   itself (no dirty lists are sent). The closing kick finds members and
   partners' end forces by ID after a list rebuild (sort or migration).
   After a step whose first guess was empty, the next first tests the
   flagged spheres' pairs and walls alone (quick_clear(): one sparse
   forward and one reduction), the full first guess only if that finds a
   contact or cannot decide.

   Restrictions (FixHardSphere::choose_engine() falls back to the global
   engine, or errors when `substep local` was given): an atom map; pair,
   bond, angle, dihedral and improper styles HSLocalForces can restrict
   exactly (no many-body pair styles or hybrid/molecular), through rows
   (molecular systems with the members' topology gathered by ID,
   gather_topology());
   no fix with conservative forces but enforce2d, gravity and those that
   only add a force (held).
------------------------------------------------------------------------- */

#ifndef LMP_HS_LOCAL_ENGINE_H
#define LMP_HS_LOCAL_ENGINE_H

#include "hs_cells.h"
#include "hs_cluster.h"
#include "hs_contact.h"
#include "hs_flatmap.h"
#include "hs_flow_view.h"
#include "hs_local_forces.h"
#include "hs_mpi.h"
#include "hs_stamp.h"
#include "hs_step_engine.h"
#include "hs_step_view.h"
#include "hs_types.h"
#include "lmptype.h"
#include "pointers.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <deque>
#include <map>
#include <string>
#include <vector>

namespace LAMMPS_NS {

class HSLocalForces;
class HSMethod;
class HSSystem;

class HSLocalEngine : public HSStepEngine, public HSStepView, public HSTypes {
 public:
  HSLocalEngine(class LAMMPS *, HSSystem &, HSMethod &);
  ~HSLocalEngine() override;

  // HSStepEngine
  std::string limits() override;
  // the ghost cutoff the engine needs (a cluster's member may be a ghost
  // copy whose interaction rows must be complete): raised by the engine if
  // the input's is smaller, with a line in the log
  void chosen() override;
  double ghost_needed() const override { return ghost_wide; }
  bool step() override;
  bool finish() override;
  void pre_exchange() override;
  double counter(int k) override;
  double memory_usage() const override;
  // (with kspace or fixes that only add a force, held by limits(), the
  // copy splits a member's held force into the thermostat's and theirs)
  bool takes_captured_forces() const override;
  std::string uncaptured_cost() const override;

  // HSStepView: the step's clusters and state, for a method's own
  // bookkeeping (hs_local_modified.h); valid from step() to the
  // end of finish()
  int nclusters() const override { return cs.nclusters(); }
  const std::vector<int> &members(int c) const override;
  const double *start_x(int i) const override { return x0[i]; }
  const double *start_v(int i) const override { return v0[i]; }
  const double *const *start_x_rows() const override { return x0; }
  const double *const *start_v_rows() const override { return v0; }
  void partner_kicks(int i, double *first, double *second) const override;
  HSLocalForces &local_forces() override { return *locf; }
  void const_force(int i, double *out) const override;
  int owned(tagint t) const override;
  void put_v(int i, const double *vn) override { set_v(i, vn); }
  void put_x(int i, const double *xn) override { set_x(i, xn); }

 private:
  HSSystem *sys;    // the system layer (the plumbing every step shares)
  HSMethod &meth;
  HSLocalForces *locf;
  int local_step = 0;    // the current step ran by clusters
  int nprocs = 1, me = 0;
  // a step in which screening found spheres that may touch. Returns false
  // if no contact is predicted in the step at all, on any rank (the caller
  // takes fix nve's step); else the step is done up to the closing kick
  // -1: a cluster outgrew the ghost atoms (overflow global; error and widen
  // in step()): the state is
  // as at the step's start, the step is the global engine's; NEEDS_WIDE: a
  // contact is predicted and the ghost shell is LAMMPS' own (ghost lazy),
  // nothing changed
  int step_clusters();
  // the closing half kick (final_integrate) of a step step_clusters() took
  void final_kick();
  double nrounds = 0.0;     // growth rounds (each redoes the changed clusters)
  double ncompute = 0.0;    // restricted force evaluations (all ranks)
  double ncompute_here = 0.0;    // this rank's, since the run began
  double ncompute_summed = 0.0;  // ncompute_here at the last sum into ncompute
  double ncollective = 0.0;      // collective communications in collisional steps
  double ncoll_steps = 0.0;      // collisional steps taken by clusters
  double nquick = 0.0;           // steps quick_clear() found free of contacts

  // ---- the step's clusters, the same on every rank: a ClusterSet over
  // dense ids of the members' atom IDs, ordered by ID (keys: lowest ID)
  HardSphere::ClusterSet cs;
  HardSphere::FlatMap<tagint, int> idof;    // member ID -> dense id
  std::vector<int64_t> idtag;              // dense id -> ID
  int id_of(tagint t);                     // adds t if new
  std::vector<int> mid;                    // per local copy: its dense id, -1 if not a member
  std::vector<int> mid_set;                // copies with mid set
  bool is_member(int l) const { return mid[l] >= 0; }
  int cluster_of(int l) const { return mid[l] >= 0 ? cs.cluster_of(mid[l]) : -1; }
  tagint key_of(int c) const { return idtag[cs.members(c)[0]]; }
  // the member whose owner runs cluster c (its flows): the least
  // mix64() of the members' IDs, not the key: IDs that grow with x
  // (create_atoms, lattices) would give the rank on a face's lower side
  // every cluster across it, and rank 0 those across the periodic face too
  tagint runner_of(int c) const;
  static tagint runner_of(const tagint *ids, int n);
  std::vector<std::vector<int>> view_members;    // members(c): the members owned here

  using Vec = std::array<double, 3>;
  struct Seg {
    double t0, t1;
    Vec q, v, a;    // q: displacement from the copy's start position
  };
  // one cluster's flows, by key (its lowest member ID). The runner (the
  // owner of runner_of()'s member) keeps everything; other ranks keep what the packets of
  // each half carry (the replicated registry): members' IDs, mid and end
  // displacements and velocities, and each half's path segments
  struct Run {
    bool mine = false;
    std::vector<tagint> mtags;      // member IDs, ascending
    std::vector<int> members;       // runner: the members' copies (nearest the runner's)
    std::vector<int> touched;       // runner: members and partners (copies)
    HSLocalForces::Snapshot snap;   // runner: its restricted lists
    // runner, for a method's own flow (HSMethod::runs_cluster_flows()): the
    // terms of snap's lists, recorded by the evaluation that made them
    // (HSLocalForces::take_terms()), pairs first (tnpair of them)
    std::vector<int> tloc, toff, textra;
    int tnpair = 0;
    std::vector<Vec> fk0;           // runner: V_C's force at the step's start, on touched
    bool a_done = false, b_done = false;
    bool in_sa = false;    // runner: its first half's sums are in sa (sa_change)
    uint32_t xmark = 0;    // runner: its cross forces redone in this cross_at_mid() (xepoch)
    std::vector<int> env;           // runner: static copies of its flows
    std::vector<Vec> dxm, vm;       // members after Phi_H1(dt/2): displacement from x0, v
    std::vector<Vec> dxe, ve;       // members at the step's end
    std::vector<Vec> dxp;           // their ends after the provisional second half
    std::vector<Vec> xm;            // runner: members' positions after the first half
    std::vector<Vec> fx0, fx;       // runner: members' cross-term forces F_X(q0), F_X(q_mid)
    std::vector<Vec> fx1;           // runner: F_X at the members' ends (the corrector's)
    std::vector<tagint> xnbrs;      // runner: clusters (keys) it has cross terms with
    std::vector<Vec> dvA, dvB, fend;    // runner, on touched: partner velocity changes, end forces
    std::vector<Vec> fkB, xB;    // runner: V_C's force on touched at its provisional second
                                 // half's start, and every copy in its terms (snap.zero_list) then
    double eB = 0.0;             // runner: V_C there (a method that reads the flows' energies)
    std::vector<std::vector<Seg>> segsA, segsB;    // per member, of each half's flow
    double npair[2] = {0.0, 0.0}, nwall[2] = {0.0, 0.0}, vir[2][6] = {};
    std::vector<double> mcount[2];    // runner: the method's counts of each half's last flow
    void reset()
    {
      mine = false;
      for (auto *v : {&members, &touched, &env, &tloc, &toff, &textra}) v->clear();
      tnpair = 0;
      mtags.clear();
      xnbrs.clear();
      for (auto *v :
           {&fk0, &dxm, &vm, &dxe, &dxp, &ve, &xm, &fx0, &fx, &fx1, &dvA, &dvB, &fend, &fkB,
            &xB})
        v->clear();
      for (auto &sg : segsA) sg.clear();
      for (auto &sg : segsB) sg.clear();
      a_done = b_done = in_sa = false;
      xmark = 0;
      for (int h = 0; h < 2; h++) {
        mcount[h].clear();
        npair[h] = nwall[h] = 0.0;
        for (int k = 0; k < 6; k++) vir[h][k] = 0.0;
      }
    }
  };
  // the runs by key, their storage reused from step to step (a step makes
  // and drops thousands of them in a large system; a flat table: lookups
  // by key are frequent)
  class RunTable {
   public:
    Run *find(tagint k)
    {
      Run **r = map_.find(k);
      return r ? *r : nullptr;
    }
    Run &operator[](tagint k)
    {
      if (Run *old = find(k)) return *old;
      Run *r;
      if (spare_.empty()) {
        store_.emplace_back();
        r = &store_.back();
      } else {
        r = spare_.back();
        spare_.pop_back();
      }
      r->reset();
      map_.insert(k, r);
      return *r;
    }
    void erase(tagint k)
    {
      if (Run *r = find(k)) {
        spare_.push_back(r);
        map_.erase(k);
      }
    }
    void clear()
    {
      map_.for_each([&](tagint, Run *&r) { spare_.push_back(r); });
      map_.clear();
    }
    // fn(key, run) for every run, in no particular order
    template <class F> void for_each(F fn)
    {
      map_.for_each([&](tagint k, Run *&r) { fn(k, *r); });
    }

   private:
    HardSphere::FlatMap<tagint, Run *> map_;
    std::deque<Run> store_;
    std::vector<Run *> spare_;
  };
  RunTable runs;
  Run *run_of(tagint key) { return runs.find(key); }
  // runs of this rank in key order (the order of every sum it makes)
  std::vector<tagint> my_keys();

  // ---- per local copy (owned and ghost), sized atom->nmax
  int nmax = 0;
  double **x0 = nullptr, **v0 = nullptr;    // the step's start
  double **held0 = nullptr;                 // members' held force at the step's start
  // with held smooth forces beside a thermostat and the fix's copy of the
  // conservative force (splits_held()): the thermostat's part of held0,
  // f - the copy, at the step's start on every copy (forwarded)
  double **kick0 = nullptr;
  bool split_ = false;    // this step: splits_held(), the same on every rank
  // fix gravity (limits()): a constant force per atom, m g, in the members'
  // V_C (inside their flows, as part of the constant force of each half)
  // and in V_R for everyone else (LAMMPS' forces); const_force() is that
  // force on copy i, as the fix's post_force() adds it: per fix, its
  // group bit and its gvec (Fix::extract(), taken once per run; the fix
  // updates the values in place)
  struct Gravity {
    int groupbit;
    const double *gvec;
  };
  std::vector<Gravity> gravity;
  // kspace and additive force fixes, held (limits(), rides()): their
  // names, "" if none
  std::string held_smooth, held_smooth_told;
  // members take a held force (f minus their V_C force) as two half kicks
  bool holds() const;
  // ... as a constant force inside their flows (held smooth forces, and
  // then thermostats' too) instead of kicks before and after them
  bool rides() const;
  // riding, with the fix's copy of the conservative force at the step's
  // start: a thermostat's part (kick0) stays two half kicks, the held
  // smooth forces' (held0 - kick0) rides
  bool splits_held() const;
  // the part of copy i's held force that rides inside its flow: all of
  // held0, or held0 - kick0 when this step splits
  double riding(int i, int d) const { return held0[i][d] - (split_ ? kick0[i][d] : 0.0); }
  // Phi_H2's velocity w (0-2) and "may touch in Phi_H2" (3): the owner's,
  // forwarded to the ghosts
  double **wq = nullptr;
  // on owned copies, sums over the live clusters' first halves: V_C's start
  // force (0-2), partner kicks (3-5), clusters touching (6); kept up to date
  // by changes (dsa: what this rank's runs added or took back since the
  // last h2_velocities(), on their copies, reversed into the owners)
  double **sa = nullptr, **dsa = nullptr;
  std::vector<int> dsa_rows, sa_used;    // rows of dsa that may be nonzero; owned rows of sa in use
  std::vector<char> in_used;             // listed in sa_used
  std::vector<uint32_t> dstamp_sa;
  uint32_t dsepoch = 0;
  // a run's first-half sums into dsa (sign 1) or out of it (-1)
  void sa_change(Run &r, double sign);
  // the same over the final clusters' second halves: V_C's end force,
  // partner kicks, touched
  double **sb = nullptr;
  // rows of sb that may be nonzero (zeroed before the next sums: no pass
  // over all copies per round); copies whose w changed in this round
  std::vector<int> sb_rows, wchanged;
  int end_moved = 0;    // step_clusters(): an owned atom moved half a skin (HSSystem::moved_half_skin())
  std::vector<int> scratch_paths;
  // member copies placed anew since the last check (new members, new mid
  // positions): with wchanged, the copies whose Phi_H2 path changed
  std::vector<int> moved;
  void note_moved(tagint t);
  // copies whose Phi_H2 path changed: since the last check (hdirty), since
  // the last drift (ddirty, dstamp)
  std::vector<int> hdirty, ddirty;
  std::vector<uint32_t> dstamp;
  uint32_t depoch = 0;
  std::vector<uint32_t> hstampv;    // copies with held0 this step
  uint32_t heldepoch = 0;
  std::vector<uint32_t> kstamp;     // owned members at the closing kick
  uint32_t kepoch = 0;
  HardSphere::RowLists<tagint> atom_runs;    // runner: keys of the runs whose flows saw a copy
  bool drifted = false;
  std::vector<uint32_t> estamp;    // owned atoms with a row in sb at the step's end
  uint32_t eepoch = 0;

  // contact candidates by local copy (pair indices into fix->cand / 2)
  bigint cand_version = -1;
  std::vector<int> adj_off, adj;            // local copy -> candidate pairs
  std::vector<int> cand_ghosts;             // ghost copies in a candidate pair
  std::vector<int> adj_pos;                 // scratch of build_adjacency()
  // candidate pair's distance at the list build less its reach without
  // paths (contact distance and line margin, a relative 1e-10 more)
  std::vector<double> cand_slack;
  std::vector<uint32_t> pstamp;             // candidate pair seen
  std::vector<int> act0;                    // owned atoms the screen marked active
  std::vector<uint32_t> astamp;             // considered by h2_check
  uint32_t aepoch = 0;
  uint32_t pepoch = 0;
  void build_adjacency();

  struct Hit {
    tagint i, j;    // atom IDs; j < 0: wall -1 - j
    bool operator<(const Hit &o) const { return i != o.i ? i < o.i : j < o.j; }
    bool operator==(const Hit &o) const { return i == o.i && j == o.j; }
  };
  void grow_arrays();
  // the per-atom arrays, allocated together (columns)
  std::array<std::pair<double ***, int>, 10> peratom()
  {
    return {{{&x0, 3},
             {&v0, 3},
             {&held0, 3},
             {&kick0, 3},
             {&wq, 4},
             {&sa, 7},
             {&sb, 7},
             {&cols, 2},
             {&dsa, 7},
             {&qrow, 7}}};
  }
  double **cols = nullptr;    // free gap (0) and the screen's flag (1), forwarded by predict_all()
  std::vector<double> pathv;    // predict_all(): the path bound of each copy
  std::vector<char> flagv;      // predict_all(): 1 if the copy is flagged (cols[k][1])
  std::vector<double> awayv;    // predict_all(): path bound + distance from the list build
  void set_x(int i, const double *xn);
  void set_v(int i, const double *vn);
  void set_xv(int i, const double *xn, const double *vn);
  void predict_all(std::vector<Hit> &hits);
  // the first guess's tests of one pair within reach, or of a wall
  enum { GUESS_NONE = 0, GUESS_NEAR = 1, GUESS_HIT = 2 };
  int guess_pair(int i, int j, const double *dq, double r2, double sigma, const double *vi,
                 const double *vj, const double *ai, const double *aj);
  int guess_wall(int i, int wl, const double *vi, const double *ai, double Di);
  static double path_bound(const double *v, const double *a, double dt);
  bool flagged_atom(int i, const double *a, double t2, double h4, double mhalf) const;
  // both from the squares |v|^2 (vv), |a|^2 (aa), |x - xref|^2 (d2), and g
  // = the free gap less mhalf (predict_all()'s pass has them at hand)
  static double path_of(double vv, double aa, double dt)
  {
    return dt * sqrt(vv) + 0.5 * dt * dt * sqrt(aa);
  }
  static bool flagged_of(double active, double d2, double vv, double aa, double g, double t2,
                         double h4)
  {
    if (active != 0.0) return true;
    // as HSSystem::screen_atom(): (a+b+c)^2 <= 3(a^2+b^2+c^2)
    const double v2 = t2 * vv, a2 = h4 * aa;
    if (g > 0.0 && 3.0 * (d2 + v2 + a2) <= g * g) return false;
    if (sqrt(d2) + sqrt(v2) + sqrt(a2) <= g) return false;
    return true;
  }
  // the first guess of the flagged spheres only, after an empty one
  bool quick_clear();
  bool quick_next = false;
  double **qrow = nullptr;    // quick_clear(): stamp, v, a of the flagged copies
  double qstamp_now = 0.0;
  std::vector<int> qlist, qrecv;
  void grow_clusters(std::vector<Hit> &hits);
  void add_members(const std::vector<int> &newids);
  bool flow(Run &r, double h, bool first_half, std::vector<Hit> &hits);
  void cross_check(bool first_half, const std::vector<int> &fresh, std::vector<Hit> &hits);
  void h2_check(bool full, std::vector<Hit> &hits);
  void retire(tagint key);
  // full: every owned atom's w; else only where the sums or membership changed
  void h2_velocities(bool full);
  // h2_velocities(true)'s largest deviation of a line from fix nve's on
  // this rank, for the h2_check(true) that follows it
  double line_dev = 0.0;
  bool line_dev_valid = false;
  std::vector<int> scratch_wrows, scratch_wsend;
  HardSphere::RowSet rowset;    // listed rows in index order (h2_velocities(), step_clusters())
  std::vector<uint32_t> wstamp;    // rows done by this h2_velocities()
  uint32_t wepoch = 0;
  void update_paths(bool full);
  void h2_pos(int l, double *q) const;
  void check_pair(int p, std::vector<Hit> &hits);
  void check_walls(int i, std::vector<Hit> &hits);
  // (timed = false: whether there is a contact, not when: HardSphere::first_contact())
  HardSphere::Contact wall_contact(int i, int wl, double g, double vd, double ad, double tmax,
                                   bool timed = true);
  HardSphere::Contact pair_contact(int la, int lb, const double *dq, const double *dv,
                                   const double *da, double sigma, double tmax,
                                   bool timed = true);
  std::vector<int> near_pairs, near_walls;    // near misses on fix nve's lines
  // scratch of flow(), kept to avoid allocations
  std::vector<Vec> scratch_env, scratch_fk, scratch_fk1, scratch_fc, scratch_fx;
  std::vector<int> scratch_others;    // cross_forces()' other labels
  std::vector<Vec> scratch_xs, scratch_sv, scratch_sx;    // flow(): the method's energies
  std::vector<int> scratch_mi;
  // flow(): one copy per atom of a cluster's environment, by the slot of
  // atom->map()'s copy (stamped this epoch: its copy of lowest index so far)
  std::vector<uint32_t> envstamp;
  std::vector<int> envbest, scratch_slots;
  uint32_t envepoch = 0;
  std::vector<double> scratch_im;
  HSClusterFlowJob scratch_job;    // flow(): a method's own flow (HSMethod::runs_cluster_flows())
  std::vector<int> scratch_pk;
  bool settle(std::vector<Hit> &hits);
  // cluster labels (the key's dense id) on every local copy of the members
  // (HSLocalForces' cross terms)
  std::vector<int> lab, labelled;
  void label_cluster(int c);
  void cross_at_mid();
  bool cross_at_end();
  // a run with cross terms whose second half still has the extrapolated
  // cross force: cross_at_end() runs that half again (and flow() takes
  // its first run as provisional)
  bool awaits_corrector(const Run &r) const;
  std::vector<std::pair<int, Vec>> xend_saved;
  uint32_t xepoch = 0;
  void cross_of(Run &r);
  // the cross terms' forces on a run's members at their copies' positions
  // others: the labels of the other clusters in its cross terms (the
  // restricted evaluation's touched() otherwise; then only where the
  // caller reads that instead: HSLocalForces::cross_rows())
  void cross_forces(const Run &r, std::vector<Vec> &out, std::vector<int> *others = nullptr);
  void cross_at_start(Run &r, const std::vector<Vec> &fk, const std::vector<int> &mi);
  void cross_at_start_evaluated(Run &r);
  std::vector<std::pair<int, Vec>> scratch_away;
  void held_of(Run &r);
  // the member copies of a cluster this rank runs: the key's owned copy and
  // for every other member its copy nearest it; checked against the ghost
  // cutoff
  // false if one is beyond the ghost atoms (overflow error: with the error
  // in outgrown_msg, which overflow_error() raises on every rank)
  bool member_copies(Run &r);
  std::string outgrown_msg;
  // the bonded-partner form of that error: each missing partner's ID and
  // its member's copy here, for overflow_error() to name the cutoff that
  // holds them (their owners know where they are)
  std::vector<std::pair<tagint, std::array<double, 3>>> missing;
  void overflow_error();
  // work lists of cluster keys; runs not cross-checked yet
  std::vector<tagint> workA, workB, workX, uncheckedA, uncheckedB;
  std::vector<int> clusters_of(std::vector<tagint> &keys);
  std::vector<int> in_memory_order(std::vector<int> clusters);
  std::vector<std::pair<int, int>> scratch_order;
  int clusters_of_key(tagint key) const;

  // ---- the replicated registry: packets of each half, shared by one
  // collective per phase
  std::vector<double> sendbuf;
  HardSphere::GatherBuffer<double> recvbuf;
  void allgather(HardSphere::GatherBuffer<double> &out);    // sendbuf of every rank, in rank order
  void gather_hits(std::vector<Hit> &hits);
  bool gather_grow(std::vector<Hit> &hits);
  size_t npk_pos = 0;    // where sendbuf counts its packets
  void start_packets(const std::vector<Hit> &hits);
  void share_half(const std::vector<Hit> &hits, const std::vector<tagint> &ran, bool first_half,
                  std::vector<Hit> &gathered, std::vector<tagint> &arrived);
  void pack_run(const Run &r, bool first_half);
  void unpack_runs(std::vector<Hit> &hits, std::vector<tagint> *arrived);
  static void sort_unique(std::vector<Hit> &hits);
  void place_members(const Run &r);
  double max_all(double v);

  // the step's members (IDs) and partners' end forces by ID, for the
  // closing kick after a neighbor list rebuild (sorting or migration)
  std::vector<tagint> end_mtags, end_ptags;
  std::vector<Vec> end_pfc;
  bigint end_ncalls = -1;
  int bonded = 0;              // bonded styles present: their terms join clusters
  // molecular: the members' special lists and bonded terms by ID, gathered
  // when they join (add_members(); ghosts carry neither), for their rows
  // and for the clusters' bonded joins
  bool molecular = false;
  HSLocalForces::Topology topo;
  std::map<std::array<int64_t, 6>, int> term_index;    // a term's (kind, type, IDs) -> topo.terms
  void gather_topology(const std::vector<int> &newids);
  // overflow widen: a step whose cluster outgrew the ghost atoms is taken
  // again with them one contact-list cutoff farther (widen())
  bool widening() const;
  void widen();
  double nwiden = 0.0;         // times the ghost cutoff was widened
  // ghost lazy N (several ranks): LAMMPS' own ghost cutoff (ghost_narrow)
  // while no contact is predicted; a step with one is taken with ghosts to
  // ghost_wide (to_wide()), kept until a reneighboring N steps after the
  // last step taken by clusters (pre_exchange())
  static constexpr int NEEDS_WIDE = -2;    // step_clusters(): a contact, the shell narrow
  bool lazy = false;
  std::string lazy_told;       // the ghost lazy log line, as last written
  bool narrow = false;         // the ghost shell is ghost_narrow now
  double ghost_user = 0.0;     // the input's comm_modify cutoff
  double ghost_set = -1.0;     // the comm_modify cutoff this engine set last
  double ghost_narrow = 0.0;
  double ghost_wide = 0.0;     // the cutoff the engine asks for (cluster steps; errors name it)
  double ghost_widened = 0.0;  // overflow widen's cutoff (kept from run to run)
  bigint last_cluster_step = -1;
  double nwide = 0.0;          // times the shell went from narrow to wide
  void set_ghost_cutoff(double cut);
  void to_wide();
  void reborder();
  void resize_shell();
  double cutneigh = 0.0;       // the rows' reach: neighbor cutoff (chosen())
  // V_C's restricted forces on the copies c (record_terms: and their terms,
  // HSLocalForces::term_local())
  void vc(const int *c, int n, bool record_terms = false);
  // contact candidates of any local copy: every group atom within the
  // contact list's cutoff at the list build (HSSystem::xref), bonded
  // partners included (as the fix's list, HSSystem::reset_reference), not
  // its images, in ID order; kept per build. A member's come from the scan
  // of its interaction row (HSLocalForces::set_near(): the row is built
  // first, by vc()); any other's from the engine's own grid. The pointer is
  // valid until the next crow() of an atom without a row or the next
  // restricted evaluation that scans a new interaction row.
  const int *crow(int a, int &n);
  HardSphere::CellRows<int> crows;
  bigint crows_version = -1;
};

}    // namespace LAMMPS_NS

#endif
