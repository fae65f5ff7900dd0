/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: collision clusters of the local sub-stepping engine
   (issue 10, `substep local`).

   Pure bookkeeping, no LAMMPS types, header-only, unit-tested on its own
   (unittest/math/test_cluster.cpp).

   One step is integrated as K_R(dt/2) . Phi_C(dt) . K_R(dt/2): C is the set
   of spheres that collide in the step ("members"), V_C the sum of every
   interaction term with an atom of C, V_R = V - V_C. Phi_C, the CVA flow
   (Bond & Leimkuhler 2007, section 2.2: Verlet sub-steps to each contact,
   impulse R) of K + V_C, moves the members and their interaction partners
   (the other atoms of V_C's terms). Phi_C splits into independent flows,
   one per cluster, only where no atom moves in two of them: a cluster is a
   connected component of the graph whose edges are the contacts and the
   terms that involve a member ("clusters that share an atom are one
   cluster"). A contact found inside a cluster's flow with a sphere that is
   not yet a member grows the clusters (its terms join V_C), and every
   cluster whose atoms or members changed is redone from the step's start.

   Indices are local indices 0..n-1 of the caller (owned and ghost atoms);
   a wall contact is a contact with j < 0. reset() is O(1) amortized (epoch
   stamps), every other call is O(the atoms it touches), so a step costs
   O(its clusters), not O(n).
------------------------------------------------------------------------- */

#ifndef LMP_HS_CLUSTER_H
#define LMP_HS_CLUSTER_H

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

namespace HardSphere {

// Union-find over 0..n-1 (union by size, path halving). Only the touched
// elements are stored as live: reset() bumps an epoch instead of clearing.
class UnionFind {
 public:
  void reset(int n)
  {
    if ((int) parent_.size() < n) {
      parent_.resize(n);
      size_.resize(n);
      stamp_.resize(n, 0);
    }
    n_ = n;
    if (++epoch_ == 0) {    // wrapped: clear the stamps once every 2^32 resets
      std::fill(stamp_.begin(), stamp_.end(), 0u);
      epoch_ = 1;
    }
  }
  int n() const { return n_; }
  // more elements within the current reset (their state: untouched)
  void grow(int n)
  {
    if ((int) parent_.size() < n) {
      parent_.resize(n);
      size_.resize(n);
      stamp_.resize(n, 0);
    }
    if (n > n_) n_ = n;
  }
  bool touched(int i) const { return stamp_[i] == epoch_; }
  int find(int i)
  {
    touch(i);
    while (parent_[i] != i) {
      parent_[i] = parent_[parent_[i]];
      i = parent_[i];
    }
    return i;
  }
  // true if i and j were in different sets
  bool unite(int i, int j)
  {
    int a = find(i), b = find(j);
    if (a == b) return false;
    if (size_[a] < size_[b]) std::swap(a, b);
    parent_[b] = a;
    size_[a] += size_[b];
    return true;
  }
  int set_size(int i) { return size_[find(i)]; }

 private:
  void touch(int i)
  {
    if (stamp_[i] != epoch_) {
      stamp_[i] = epoch_;
      parent_[i] = i;
      size_[i] = 1;
    }
  }
  std::vector<int> parent_, size_;
  std::vector<uint32_t> stamp_;
  uint32_t epoch_ = 0;
  int n_ = 0;
};

// Running counters of the clusters built (one build per step plus one per
// growth), for the fix's output vector.
struct ClusterCounters {
  double steps = 0;          // reset()s
  double clusters = 0;       // clusters of the final build of each step
  double atoms = 0;          // their atoms (members + partners), summed
  double members = 0;        // their members, summed
  int max_atoms = 0;         // largest cluster (atoms)
  int max_members = 0;       // largest cluster (members)
  double growths = 0;        // rebuilds after contacts with non-members
  double redone = 0;         // clusters those rebuilds asked to redo
  double mean_atoms() const { return clusters > 0 ? atoms / clusters : 0.0; }
  double mean_members() const { return clusters > 0 ? members / clusters : 0.0; }
};

class ClusterSet {
 public:
  // a new step over local indices 0..n-1: no members, no clusters
  void reset(int n)
  {
    flush_counters();
    uf_.reset(n);
    size_to(n);
    if (++epoch_ == 0) {
      std::fill(mstamp_.begin(), mstamp_.end(), 0u);
      epoch_ = 1;
    }
    touched_.clear();
    keyed_.clear();
    sorted_ = 0;
    new_members_.clear();
    nc_ = 0;    // (the per-cluster vectors keep their storage: see build())
    built_ = false;
    ++count_.steps;
  }

  // more elements within the current step (a set over dense ids that
  // grows as contacts name new atoms)
  void grow(int n)
  {
    uf_.grow(n);
    size_to(n);
  }
  // number clusters and sort members by order[i] instead of i (a set over
  // dense ids of atom IDs, replicated on every MPI rank, orders by ID so
  // that every rank numbers the clusters alike); nullptr: by i. The caller
  // keeps the vector alive.
  void set_order(const std::vector<int64_t> *order)
  {
    order_ = order;
    keyed_.clear();    // (the next build sorts every touched atom by the new order)
    sorted_ = 0;
  }
  // sphere i collides in this step (it is a member of C)
  void add_member(int i)
  {
    if (mstamp_[i] == epoch_) return;
    mstamp_[i] = epoch_;
    note(i);
    new_members_.push_back(i);
  }
  bool is_member(int i) const { return mstamp_[i] == epoch_; }

  // a contact of i with j (j < 0 or j == i: a wall, only i); both become
  // members of one cluster
  void add_contact(int i, int j)
  {
    add_member(i);
    if (j < 0 || j == i) return;
    add_member(j);
    uf_.unite(i, j);
  }

  // an interaction term (pair, bond, angle, ..., of k atoms, repeats
  // allowed): if it involves a member it is a term of V_C and all its atoms
  // join that member's cluster. Returns whether it is a term of V_C.
  bool add_term(const int *a, int k)
  {
    int m = -1;
    for (int t = 0; t < k && m < 0; ++t)
      if (is_member(a[t])) m = a[t];
    if (m < 0) return false;
    for (int t = 0; t < k; ++t) {
      if (!partners_join_ && !is_member(a[t])) continue;
      note(a[t]);
      uf_.unite(m, a[t]);
    }
    return true;
  }

  // true (default): the rule, a term's partners join the cluster
  // (they move inside Phi_C). false: the frozen-partner splitting
  // Phi_H1(dt/2) . Phi_H2(dt) . Phi_H1(dt/2) (unittest/math/
  // test_local_splitting.cpp), where only members move inside the collision
  // flow: a term joins only its members, clusters hold members only.
  // Set before the first add_term() of a step.
  void set_partners_join(bool yes) { partners_join_ = yes; }
  bool partners_join() const { return partners_join_; }
  bool add_pair(int i, int j)
  {
    const int a[2] = {i, j};
    return add_term(a, 2);
  }

  // the members added since the last build(): the caller adds their terms
  // (add_term) before building
  const std::vector<int> &new_members() const { return new_members_; }

  // group the touched atoms into clusters, numbered in the order of their
  // smallest atom; members and atoms of each sorted ascending
  void build()
  {
    if (++bepoch_ == 0) {
      std::fill(rstamp_.begin(), rstamp_.end(), 0u);
      std::fill(clstamp_.begin(), clstamp_.end(), 0u);
      std::fill(oldstamp_.begin(), oldstamp_.end(), 0u);
      bepoch_ = 1;
    }
    // every touched atom is a member or shares a term with one, so every
    // set of touched atoms is a cluster
    if (order_) {
      // (by (order, i) pairs: a comparison that reads order[] at two random
      // places cost twice as much; the orders are distinct, so the result
      // is the same)
      // touched_[0, sorted_) is in order since the last build (growth only
      // appends): sort the atoms added since and merge (keyed_ keeps the
      // sorted pairs), not the whole set again at every growth round
      const std::vector<int64_t> &o = *order_;
      for (size_t k = sorted_; k < touched_.size(); ++k)
        keyed_.emplace_back(o[touched_[k]], touched_[k]);
      std::sort(keyed_.begin() + sorted_, keyed_.end());
      std::inplace_merge(keyed_.begin(), keyed_.begin() + sorted_, keyed_.end());
      for (size_t k = 0; k < keyed_.size(); ++k) touched_[k] = keyed_[k].second;
    } else {
      std::sort(touched_.begin() + sorted_, touched_.end());
      std::inplace_merge(touched_.begin(), touched_.begin() + sorted_, touched_.end());
    }
    sorted_ = touched_.size();
    int nc = 0;
    for (int i : touched_) {
      const int r = uf_.find(i);
      if (rstamp_[r] != bepoch_) {
        rstamp_[r] = bepoch_;
        root_id_[r] = nc++;
      }
    }
    // the per-cluster vectors are reused from build to build and step to
    // step (thousands of clusters per step on a large system: new vectors
    // each time cost as much as the rest of build())
    if ((int) atoms_.size() < nc) {
      atoms_.resize(nc);
      members_.resize(nc);
    }
    for (int c = 0; c < nc; ++c) {
      atoms_[c].clear();
      members_[c].clear();
    }
    nc_ = nc;
    for (int i : touched_) {
      const int c = root_id_[uf_.find(i)];
      atoms_[c].push_back(i);
      if (is_member(i)) members_[c].push_back(i);
      cl_[i] = c;
      clstamp_[i] = bepoch_;
    }
    new_members_.clear();
    built_ = true;
    counted_ = false;
  }

  int nclusters() const { return nc_; }
  const std::vector<int> &members(int c) const { return members_[c]; }
  const std::vector<int> &atoms(int c) const { return atoms_[c]; }
  // the cluster of atom i after build(), -1 if i moves in none (it takes a
  // plain Verlet step)
  int cluster_of(int i) const
  {
    return (built_ && clstamp_[i] == bepoch_) ? cl_[i] : -1;
  }
  bool same(int i, int j) { return uf_.find(i) == uf_.find(j); }

  // --- growth: a contact (i, j) found inside a cluster's flow (j < 0: a
  // wall). Returns true if it involves a non-member, or members of two
  // clusters: then add the terms of new_members() and rebuild(). False if
  // nothing changes (i, j members of one cluster already).
  bool grow_contact(int i, int j)
  {
    const bool known = is_member(i) && (j < 0 || j == i || (is_member(j) && same(i, j)));
    if (known) return false;
    add_contact(i, j);
    return true;
  }

  // build() again after growth; returns the clusters (new numbering) that
  // must be redone from the step's start: those whose atoms or members are
  // not exactly the atoms and members of one cluster of the previous build
  // (a new member changes V_C even when it adds no atom)
  std::vector<int> rebuild()
  {
    const int nold = nclusters();
    const uint32_t prev = bepoch_;
    std::vector<int> old_atoms(nold), old_members(nold);
    for (int c = 0; c < nold; ++c) {
      old_atoms[c] = (int) atoms_[c].size();
      old_members[c] = (int) members_[c].size();
      for (int i : atoms_[c]) {
        old_[i] = c;
        oldstamp_[i] = prev;
      }
    }
    build();
    std::vector<int> redo;
    for (int c = 0; c < nclusters(); ++c) {
      const int i0 = atoms_[c][0];
      const int o = oldstamp_[i0] == prev ? old_[i0] : -1;
      bool same_set = o >= 0 && old_atoms[o] == (int) atoms_[c].size() &&
          old_members[o] == (int) members_[c].size();
      for (size_t t = 1; same_set && t < atoms_[c].size(); ++t) {
        const int i = atoms_[c][t];
        same_set = oldstamp_[i] == prev && old_[i] == o;
      }
      if (!same_set) redo.push_back(c);
    }
    ++count_.growths;
    count_.redone += (double) redo.size();
    return redo;
  }

  // counters; the current step's final clusters are added at the next
  // reset() or by flush_counters()
  const ClusterCounters &counters() const { return count_; }
  void flush_counters()
  {
    if (!built_ || counted_) return;
    counted_ = true;
    for (int c = 0; c < nclusters(); ++c) {
      const int na = (int) atoms_[c].size(), nm = (int) members_[c].size();
      count_.clusters += 1;
      count_.atoms += na;
      count_.members += nm;
      count_.max_atoms = std::max(count_.max_atoms, na);
      count_.max_members = std::max(count_.max_members, nm);
    }
  }
  void reset_counters() { count_ = ClusterCounters(); }
  // the current step's clusters are not counted (the step was given up)
  void abandon() { built_ = false; }

 private:
  void size_to(int n)
  {
    if ((int) mstamp_.size() < n) {
      mstamp_.resize(n, 0);
      rstamp_.resize(n, 0);
      root_id_.resize(n, -1);
      clstamp_.resize(n, 0);
      cl_.resize(n, -1);
      oldstamp_.resize(n, 0);
      old_.resize(n, -1);
    }
  }
  void note(int i)
  {
    if (!uf_.touched(i)) {
      touched_.push_back(i);
      uf_.find(i);
    }
  }

  UnionFind uf_;
  uint32_t epoch_ = 0;     // step: members
  uint32_t bepoch_ = 0;    // build: root numbers, cluster ids, snapshots
  std::vector<uint32_t> mstamp_, rstamp_, clstamp_, oldstamp_;
  std::vector<int> root_id_, cl_, old_;
  std::vector<int> touched_, new_members_;
  std::vector<std::vector<int>> members_, atoms_;    // [0, nc_) are the clusters
  int nc_ = 0;
  std::vector<std::pair<int64_t, int>> keyed_;    // (order, atom) of touched_[0, sorted_)
  size_t sorted_ = 0;                             // touched_[0, sorted_) in order (build())
  bool built_ = false, counted_ = false;
  bool partners_join_ = true;
  const std::vector<int64_t> *order_ = nullptr;
  ClusterCounters count_;
};

}    // namespace HardSphere

#endif
