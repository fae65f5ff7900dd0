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
     2 F_X(q_mid) - F_X(q0) in the second (issue 19). Their impulse over
     the step is dt F_X(q_mid), the exact flow of V_X in Phi_H2, but a kick
     between the halves does not commute with a contact's impulse R: R at
     t_c reverses only the cross momentum that came before t_c, so the
     kick leaves the normal velocity wrong by 2 min(t_c, dt - t_c) a_X.n,
     O(dt) per collision, a first-order engine on fluids. Spread over the
     halves, the cross momentum taken by any time is right to O(dt^2).
     On several ranks (issue 20) F_X(q0) needs the start positions of the
     cross neighbours' members and F_X(q_mid) their mid positions: the
     ghost x0 and the members' xm exchanged after the first halves, which
     the engine needs there anyway (its cross checks).

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
   conservative force of all its terms) as two half kicks at the step's
   start and end (as the global engine's K_held(dt/2) . Phi . K_held(dt/2)),
   a non-member with V_R in Phi_H2's kicks, as beside fix nve.

   Rows: V_C's forces come from rank-local interaction rows of the
   members' copies (HSLocalForces::compute_rows) and their contact
   candidates from rows of the same kind (crow()), both at the list build's
   positions: the form several ranks need, where a member may be a ghost
   (issue 20, doc/Developer_hardsphere.rst). The pair list restriction
   (HSLocalForces::compute) serves newton_pair off and neigh_modify exclude.

   Restrictions (FixHardSphere::choose_engine() falls back to the global
   engine, or errors when `substep local` was given): one MPI rank; pair,
   bond, angle, dihedral and improper styles HSLocalForces can restrict
   exactly (no kspace, many-body or hybrid pair styles); no fix with
   conservative forces except enforce2d.
------------------------------------------------------------------------- */

#ifndef LMP_HS_LOCAL_ENGINE_H
#define LMP_HS_LOCAL_ENGINE_H

#include "hs_cells.h"
#include "hs_cluster.h"
#include "hs_contact.h"
#include "hs_local_forces.h"
#include "hs_step_engine.h"
#include "hs_step_view.h"
#include "hs_types.h"
#include "lmptype.h"
#include "pointers.h"

#include <array>
#include <cstdint>
#include <deque>
#include <string>
#include <unordered_map>
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
  void step() override;
  bool finish() override;
  double counter(int k) override;

  // HSStepView: the step's clusters and state, for a method's own
  // bookkeeping (hs_local_modified.h); valid from step() to the end of
  // finish()
  int nclusters() const override { return cs.nclusters(); }
  const std::vector<int> &members(int c) const override { return cs.members(c); }
  const double *start_x(int i) const override { return x0[i]; }
  const double *start_v(int i) const override { return v0[i]; }
  void partner_kicks(int i, double *first, double *second) const override;
  HSLocalForces &local_forces() override { return *locf; }
  int owned(tagint t) const override;
  void put_v(int i, const double *vn) override { set_v(i, vn); }
  void put_x(int i, const double *xn) override { set_x(i, xn); }

 private:
  HSSystem *sys;    // the system layer (the plumbing every step shares)
  HSMethod &meth;
  HSLocalForces *locf;
  int local_step = 0;    // the current step ran by clusters
  // a step in which screening found spheres that may touch. Returns false
  // if no contact is predicted in the step at all (the caller takes fix
  // nve's step); else the step is done up to the closing kick
  bool step_clusters();
  // the closing half kick (final_integrate) of a step step_clusters() took
  void final_kick();
  const HardSphere::ClusterCounters &counters();
  double nrounds = 0.0;     // growth rounds (each redoes the changed clusters)
  double ncompute = 0.0;    // restricted force evaluations
  HardSphere::ClusterSet cs;

  using Vec = std::array<double, 3>;
  struct Seg {
    double t0, t1;
    Vec q, v, a;
  };
  // one cluster's flows; key: its smallest member
  struct Run {
    std::vector<int> members;    // owned indices, sorted
    std::vector<int> touched;    // members and partners (owned)
    HSLocalForces::Snapshot snap;    // its restricted lists
    std::vector<Vec> fk0;        // V_C's force of this cluster at the step's start, on touched
    bool a_done = false, b_done = false, contributed = false;
    std::vector<int> env;                    // static atoms of its flows (partners, contact candidates)
    std::vector<Vec> xm, vm;                 // members after Phi_H1(dt/2)
    std::vector<Vec> xe, ve;                 // members at the step's end
    std::vector<Vec> fx0, fx;                // members' cross-term forces F_X(q0), F_X(q_mid)
    std::vector<int> xnbrs;                  // clusters (keys) it has cross terms with
    std::vector<Vec> dvA, dvB, fend;         // on touched: partner velocity changes, end forces
    std::vector<std::vector<Seg>> segsA, segsB;    // per member, of each half's flow
    // what each half's flow adds to the fix's counters and virial (only the
    // flows of the final clusters count: redone ones are dropped)
    double npair[2] = {0.0, 0.0}, nwall[2] = {0.0, 0.0}, vir[2][6] = {};
    // back to a new run, keeping the vectors' storage
    void reset()
    {
      for (auto *v : {&members, &touched, &env, &xnbrs}) v->clear();
      for (auto *v : {&fk0, &xm, &vm, &xe, &ve, &fx0, &fx, &dvA, &dvB, &fend}) v->clear();
      for (auto &sg : segsA) sg.clear();
      for (auto &sg : segsB) sg.clear();
      a_done = b_done = contributed = false;
      for (int h = 0; h < 2; h++) {
        npair[h] = nwall[h] = 0.0;
        for (int k = 0; k < 6; k++) vir[h][k] = 0.0;
      }
    }
  };
  // the runs by key, their storage reused from step to step (a step makes
  // and drops thousands of them in a large system)
  class RunTable {
   public:
    using Map = std::unordered_map<int, Run *>;
    Map::iterator find(int k) { return map_.find(k); }
    Map::iterator begin() { return map_.begin(); }
    Map::iterator end() { return map_.end(); }
    Run *at(int k) { return map_.at(k); }
    Run &operator[](int k)
    {
      auto it = map_.find(k);
      if (it != map_.end()) return *it->second;
      Run *r;
      if (spare_.empty()) {
        store_.emplace_back();
        r = &store_.back();
      } else {
        r = spare_.back();
        spare_.pop_back();
      }
      r->reset();
      map_.emplace(k, r);
      return *r;
    }
    void erase(Map::iterator it)
    {
      spare_.push_back(it->second);
      map_.erase(it);
    }
    void clear()
    {
      for (auto &kv : map_) spare_.push_back(kv.second);
      map_.clear();
    }

   private:
    Map map_;
    std::deque<Run> store_;
    std::vector<Run *> spare_;
  };
  RunTable runs;

  // per owned atom, sized atom->nmax
  int nmax = 0;
  double **x0 = nullptr, **v0 = nullptr, **w = nullptr, **fcend = nullptr;
  double **fc0 = nullptr, **dvt = nullptr, **dvb = nullptr;
  // sums over the clusters run so far (fc0: V_C's start force, dvt: first-half
  // partner kicks) and how many clusters touch each atom
  std::vector<int> cnt, sums_used;
  std::vector<char> in_sums;
  std::vector<uint32_t> estamp;    // in V_C at the step's end (fcend, dvb)
  uint32_t eepoch = 0;
  // atoms whose path changed since the last Phi_H2 check, and the clusters
  // whose flows see each atom (for redoing only what a growth changed)
  std::vector<uint32_t> dstamp;
  uint32_t depoch = 0;
  std::vector<int> dirty;
  std::vector<uint32_t> hstamp;    // the same, since the last Phi_H2 check
  uint32_t hepoch = 0;
  std::vector<int> hdirty;
  std::vector<std::vector<int>> atom_runs;
  std::vector<int> runs_used;
  bool drifted = false;

  // contact candidates by owned atom (pair indices into fix->cand / 2)
  bigint cand_version = -1;
  std::vector<int> own;                     // owner of each local index (owned, ghosts)
  std::vector<int> adj_off, adj;            // owned atom -> candidate pairs
  std::vector<uint32_t> pstamp;             // candidate pair seen
  std::vector<int> act0;                    // owned atoms the screen marked active
  std::vector<uint32_t> astamp0;            // in act0 (pathv set)
  uint32_t pepoch0 = 0;
  std::vector<double> pathv;                // their Verlet path bound over the step
  std::vector<uint32_t> astamp;             // considered by h2_check
  uint32_t aepoch = 0;
  uint32_t pepoch = 0;
  void build_adjacency();

  struct Hit {
    int i, j;    // owned indices; j < 0: wall -1 - j
  };
  void grow_arrays();
  // the per-atom [nmax][3] arrays, allocated together
  std::array<double ***, 8> peratom()
  {
    return {&x0, &v0, &w, &fcend, &fc0, &dvt, &dvb, &held0};
  }
  int owner(int k) const { return own[k]; }
  void set_x(int i, const double *xn);
  void set_v(int i, const double *vn);
  void predict_all(std::vector<Hit> &hits);
  void add_terms(const std::vector<int> &newm);
  void grow_clusters(const std::vector<Hit> &hits);
  bool flow(Run &r, double h, bool first_half, std::vector<Hit> &hits);
  void cross_check(bool first_half, const std::vector<int> &fresh, std::vector<Hit> &hits);
  void h2_check(bool full, std::vector<Hit> &hits);
  void contribute(Run &r, double sign);
  void retire(Run &r);
  void mark_dirty(int i);
  void wvel(int i, double *wi) const;
  void h2_pos(int l, double *q) const;
  void check_pair(int p, std::vector<Hit> &hits);
  void check_walls(int i, std::vector<Hit> &hits);
  HardSphere::Contact wall_contact(int i, int wl, double g, double vd, double ad, double tmax);
  HardSphere::Contact pair_contact(int la, int lb, const double *dq, const double *dv,
                                   const double *da, double sigma, double tmax);
  std::vector<int> near_pairs, near_walls;    // near misses on fix nve's lines
  // scratch of flow(), kept to avoid allocations
  std::vector<Vec> scratch_env, scratch_fk, scratch_fk1, scratch_fc, scratch_env_x0;
  std::vector<int> scratch_mi;
  std::vector<double> scratch_im;
  void settle(const std::vector<Hit> &hits);
  // cluster labels on the local copies of members (HSLocalForces' cross terms)
  std::vector<int> lab, labelled;
  void label_members();
  void label_cluster(int c);
  void cross_at_mid();
  void cross_of(Run &r);
  void cross_at_start(Run &r);
  // work lists of cluster keys: first halves to run, second halves to run,
  // cross forces to recompute; flows not cross-checked yet
  std::vector<int> workA, workB, workX, wave2, uncheckedA, uncheckedB;

  std::vector<uint32_t> xstamp;
  uint32_t xepoch = 0;
  void held_at_start(const std::vector<int> &newm);
  double **held0 = nullptr;    // members' held force at the step's start
  // the step's members and partners (with V_C's end force) by tag, for the
  // closing kick: a neighbor list rebuild between step() and final_kick()
  // may sort the atoms (atom_modify sort), which changes local indices
  std::vector<tagint> end_mtags, end_ptags;
  std::vector<Vec> end_pfc;
  bigint end_ncalls = -1;
  std::vector<uint32_t> kstamp;    // members after a remap
  uint32_t kepoch = 0;
  void remap_after_rebuild();
  int bonded = 0;              // bonded styles present: their terms join clusters
  bool rows = false;           // V_C from rank-local rows (HSLocalForces::compute_rows)
  void vc(const int *c, int n);
  // contact candidates of any local copy (a cluster's members may be
  // ghosts on several ranks, which the fix's half contact list has no rows
  // for): every group atom within the contact list's cutoff at the list
  // build (HSSystem::xref), bonded partners included (as the fix's list,
  // HSSystem::reset_reference), not its images, in tag order; kept per build.
  // The pointer is valid until the next crow() of an atom without a row.
  const int *crow(int a, int &n);
  HardSphere::CellRows<int> crows;
  bigint crows_version = -1;
  void bump_epoch(uint32_t &e, std::vector<uint32_t> &stamp);
};

}    // namespace LAMMPS_NS

#endif
