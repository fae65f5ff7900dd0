// hs_cluster.h: union-find and the collision clusters of the local engine,
// against an independent brute force (breadth-first search for connected
// components on an adjacency list), 10^4 random cases, growth and redo
// decisions, and adversarial cases (chains, self-loops, repeated pairs,
// walls, empty steps, terms with repeated atoms).

#include "hs_cluster.h"

#include "gtest/gtest.h"

#include <algorithm>
#include <map>
#include <queue>
#include <random>
#include <set>
#include <utility>
#include <vector>

using HardSphere::ClusterSet;
using HardSphere::UnionFind;

namespace {

using Groups = std::set<std::pair<std::vector<int>, std::vector<int>>>;    // (atoms, members)

struct Case {
  int n = 0;
  std::vector<std::pair<int, int>> contacts;    // j = -1: wall
  std::vector<std::vector<int>> terms;
};

// brute force: members are the atoms of contacts; a term with a member links
// all its atoms; clusters are the connected components (BFS) of the touched
// atoms under contact and term links
Groups brute(int n, const std::vector<std::pair<int, int>> &contacts,
             const std::vector<std::vector<int>> &terms, bool partners_join = true)
{
  std::vector<char> member(n, 0), touched(n, 0);
  std::vector<std::vector<int>> adj(n);
  for (auto &c : contacts) {
    member[c.first] = touched[c.first] = 1;
    if (c.second >= 0) {
      member[c.second] = touched[c.second] = 1;
      adj[c.first].push_back(c.second);
      adj[c.second].push_back(c.first);
    }
  }
  for (auto &t : terms) {
    bool has = false;
    for (int a : t) has = has || member[a];
    if (!has) continue;
    for (int a : t) {
      if (!partners_join && !member[a]) continue;
      touched[a] = 1;
      for (int b : t)
        if (partners_join || member[b]) adj[a].push_back(b);
    }
  }
  std::vector<char> seen(n, 0);
  Groups g;
  for (int s = 0; s < n; ++s) {
    if (!touched[s] || seen[s]) continue;
    std::vector<int> comp, mem;
    std::queue<int> q;
    q.push(s);
    seen[s] = 1;
    while (!q.empty()) {
      int a = q.front();
      q.pop();
      comp.push_back(a);
      for (int b : adj[a])
        if (!seen[b]) {
          seen[b] = 1;
          q.push(b);
        }
    }
    std::sort(comp.begin(), comp.end());
    for (int a : comp)
      if (member[a]) mem.push_back(a);
    g.insert({comp, mem});
  }
  return g;
}

Groups groups_of(const ClusterSet &cs)
{
  Groups g;
  for (int c = 0; c < cs.nclusters(); ++c) g.insert({cs.atoms(c), cs.members(c)});
  return g;
}

// the checks every build must pass: sorted lists, numbering by smallest
// atom, cluster_of consistent, members flagged
void check_consistency(const ClusterSet &cs, int n)
{
  std::vector<int> owner(n, -1);
  int prev_first = -1;
  for (int c = 0; c < cs.nclusters(); ++c) {
    const auto &a = cs.atoms(c);
    ASSERT_FALSE(a.empty());
    ASSERT_TRUE(std::is_sorted(a.begin(), a.end()));
    ASSERT_GT(a[0], prev_first);
    prev_first = a[0];
    for (int i : a) {
      ASSERT_EQ(owner[i], -1) << "atom in two clusters";
      owner[i] = c;
    }
    ASSERT_FALSE(cs.members(c).empty()) << "cluster without a member";
    for (int m : cs.members(c)) {
      ASSERT_EQ(owner[m], c);
      ASSERT_TRUE(cs.is_member(m));
    }
  }
  for (int i = 0; i < n; ++i) ASSERT_EQ(cs.cluster_of(i), owner[i]) << "atom " << i;
}

Case random_case(std::mt19937 &rng)
{
  Case k;
  k.n = std::uniform_int_distribution<int>(1, 40)(rng);
  std::uniform_int_distribution<int> atom(0, k.n - 1);
  const int nc = std::uniform_int_distribution<int>(0, k.n)(rng);
  for (int t = 0; t < nc; ++t) {
    const int i = atom(rng);
    int j = atom(rng);
    if (rng() % 5 == 0) j = -1;    // wall
    k.contacts.push_back({i, j});
  }
  const int nt = std::uniform_int_distribution<int>(0, 2 * k.n)(rng);
  for (int t = 0; t < nt; ++t) {
    const int len = std::uniform_int_distribution<int>(1, 4)(rng);
    std::vector<int> term;
    for (int u = 0; u < len; ++u) term.push_back(atom(rng));
    k.terms.push_back(term);
  }
  return k;
}

void build_case(ClusterSet &cs, const Case &k, bool partners_join = true)
{
  cs.set_partners_join(partners_join);
  cs.reset(k.n);
  for (auto &c : k.contacts) cs.add_contact(c.first, c.second);
  for (auto &t : k.terms) cs.add_term(t.data(), (int) t.size());
  cs.build();
}

}    // namespace

TEST(UnionFind, AgainstBruteForceLabels)
{
  std::mt19937 rng(7);
  UnionFind uf;
  for (int trial = 0; trial < 2000; ++trial) {
    const int n = std::uniform_int_distribution<int>(1, 50)(rng);
    uf.reset(n);
    std::vector<int> label(n);
    for (int i = 0; i < n; ++i) label[i] = i;
    const int ne = std::uniform_int_distribution<int>(0, 2 * n)(rng);
    for (int e = 0; e < ne; ++e) {
      const int a = rng() % n, b = rng() % n;
      const bool merged = uf.unite(a, b);
      // relabel the whole brute-force set: O(n) per union, independent
      const int la = label[a], lb = label[b];
      EXPECT_EQ(merged, la != lb);
      for (int &l : label)
        if (l == lb) l = la;
    }
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) ASSERT_EQ(uf.find(i) == uf.find(j), label[i] == label[j]);
    for (int i = 0; i < n; ++i)
      ASSERT_EQ(uf.set_size(i), (int) std::count(label.begin(), label.end(), label[i]));
  }
}

TEST(UnionFind, ResetForgetsEverything)
{
  UnionFind uf;
  uf.reset(10);
  uf.unite(1, 2);
  EXPECT_TRUE(uf.touched(1));
  uf.reset(5);    // smaller n: old state must not leak
  EXPECT_FALSE(uf.touched(1));
  EXPECT_NE(uf.find(1), uf.find(2));
  uf.reset(20);    // larger n
  EXPECT_TRUE(uf.unite(19, 0));
  EXPECT_EQ(uf.set_size(0), 2);
}

TEST(Clusters, RandomAgainstBFS)
{
  std::mt19937 rng(20240611);
  ClusterSet cs;    // reused across cases: stale state from earlier cases must not leak
  for (int trial = 0; trial < 10000; ++trial) {
    const Case k = random_case(rng);
    build_case(cs, k);
    ASSERT_EQ(groups_of(cs), brute(k.n, k.contacts, k.terms)) << "trial " << trial;
    check_consistency(cs, k.n);
    if (HasFatalFailure()) FAIL() << "trial " << trial;
  }
}

TEST(Clusters, GrowthAgainstBFSAndRedo)
{
  std::mt19937 rng(99);
  ClusterSet cs;
  int grew = 0, kept = 0;
  for (int trial = 0; trial < 10000; ++trial) {
    Case k = random_case(rng);
    build_case(cs, k);
    const Groups before = groups_of(cs);
    // contacts found inside the flows: of atoms that move in a cluster with
    // any atom (possibly outside every cluster) or a wall
    std::vector<int> moving;
    for (int i = 0; i < k.n; ++i)
      if (cs.cluster_of(i) >= 0) moving.push_back(i);
    if (moving.empty()) continue;
    const int nnew = 1 + rng() % 3;
    bool changed = false;
    auto contacts = k.contacts;
    for (int t = 0; t < nnew; ++t) {
      const int i = moving[rng() % moving.size()];
      int j = (int) (rng() % k.n);
      if (rng() % 6 == 0) j = -1;
      // expected: a change unless both are already members of one cluster
      const bool expect = !(cs.is_member(i) &&
                            (j < 0 || j == i || (cs.is_member(j) && cs.same(i, j))));
      ASSERT_EQ(cs.grow_contact(i, j), expect);
      changed = changed || expect;
      contacts.push_back({i, j});
    }
    if (!changed) {
      ++kept;
      continue;
    }
    ++grew;
    // the caller adds the terms of the new members only
    std::set<int> nm(cs.new_members().begin(), cs.new_members().end());
    for (auto &t : k.terms) {
      bool has = false;
      for (int a : t) has = has || nm.count(a);
      if (has) cs.add_term(t.data(), (int) t.size());
    }
    const std::vector<int> redo = cs.rebuild();
    const Groups after = brute(k.n, contacts, k.terms);
    ASSERT_EQ(groups_of(cs), after) << "trial " << trial;
    check_consistency(cs, k.n);
    // redo exactly the clusters that are not an unchanged old cluster
    std::set<std::vector<int>> want, got;
    for (auto &g : after)
      if (!before.count(g)) want.insert(g.first);
    for (int c : redo) got.insert(cs.atoms(c));
    ASSERT_EQ(got, want) << "trial " << trial;
    ASSERT_FALSE(redo.empty());    // something changed, so something is redone
  }
  EXPECT_GT(grew, 1000);
  EXPECT_GT(kept, 100);
}

TEST(Clusters, Empty)
{
  ClusterSet cs;
  cs.reset(0);
  cs.build();
  EXPECT_EQ(cs.nclusters(), 0);
  cs.reset(5);
  const int t[2] = {0, 1};
  EXPECT_FALSE(cs.add_term(t, 2));    // no member: not a term of V_C
  cs.build();
  EXPECT_EQ(cs.nclusters(), 0);
  for (int i = 0; i < 5; ++i) EXPECT_EQ(cs.cluster_of(i), -1);
}

TEST(Clusters, SelfLoopsWallsRepeats)
{
  ClusterSet cs;
  cs.reset(6);
  cs.add_contact(2, 2);     // self-loop: member 2 alone
  cs.add_contact(4, -1);    // wall
  cs.add_contact(0, 1);
  cs.add_contact(1, 0);     // repeated, reversed
  cs.add_contact(0, 1);
  const int rep[3] = {4, 4, 5};    // a term with a repeated atom
  EXPECT_TRUE(cs.add_term(rep, 3));
  cs.build();
  ASSERT_EQ(cs.nclusters(), 3);
  EXPECT_EQ(cs.atoms(0), (std::vector<int>{0, 1}));
  EXPECT_EQ(cs.atoms(1), (std::vector<int>{2}));
  EXPECT_EQ(cs.atoms(2), (std::vector<int>{4, 5}));
  EXPECT_EQ(cs.members(2), (std::vector<int>{4}));
  EXPECT_EQ(cs.cluster_of(3), -1);
  // contacts of members of one cluster change nothing
  EXPECT_FALSE(cs.grow_contact(1, 0));
  EXPECT_FALSE(cs.grow_contact(2, -1));
  EXPECT_FALSE(cs.grow_contact(4, 4));
  // partner 5 colliding with the wall becomes a member: redo cluster {4,5}
  // although its atoms did not change (V_C gained 5's terms)
  EXPECT_TRUE(cs.grow_contact(5, -1));
  EXPECT_EQ(cs.new_members(), (std::vector<int>{5}));
  auto redo = cs.rebuild();
  ASSERT_EQ(redo.size(), 1u);
  EXPECT_EQ(cs.atoms(redo[0]), (std::vector<int>{4, 5}));
  EXPECT_EQ(cs.members(redo[0]), (std::vector<int>{4, 5}));
  // two members of different clusters collide: the two merge, 2 is untouched
  EXPECT_TRUE(cs.grow_contact(1, 5));
  EXPECT_TRUE(cs.new_members().empty());
  redo = cs.rebuild();
  ASSERT_EQ(cs.nclusters(), 2);
  ASSERT_EQ(redo.size(), 1u);
  EXPECT_EQ(cs.atoms(redo[0]), (std::vector<int>{0, 1, 4, 5}));
  EXPECT_EQ(cs.cluster_of(2), 1 - redo[0]);
}

TEST(Clusters, LongChainsAnyOrder)
{
  std::mt19937 rng(3);
  ClusterSet cs;
  for (int n : {2, 3, 17, 1000, 100000}) {
    std::vector<std::pair<int, int>> e;
    for (int i = 0; i + 1 < n; ++i) e.push_back({i, i + 1});
    std::shuffle(e.begin(), e.end(), rng);
    cs.reset(n);
    for (auto &p : e) cs.add_contact(p.second, p.first);
    cs.build();
    ASSERT_EQ(cs.nclusters(), 1);
    ASSERT_EQ((int) cs.atoms(0).size(), n);
    ASSERT_EQ((int) cs.members(0).size(), n);
  }
  // a chain of partners: 0 collides with the wall, springs link 0-1-...-9;
  // only the spring of the member joins, the rest are terms of V_R
  cs.reset(10);
  cs.add_contact(0, -1);
  int joined = 0;
  for (int i = 0; i + 1 < 10; ++i) joined += cs.add_pair(i, i + 1);
  cs.build();
  EXPECT_EQ(joined, 1);
  ASSERT_EQ(cs.nclusters(), 1);
  EXPECT_EQ(cs.atoms(0), (std::vector<int>{0, 1}));
}

TEST(Clusters, Counters)
{
  ClusterSet cs;
  cs.reset_counters();
  // step 1: clusters {0,1} (members 0,1) and {5,6,7} (member 6)
  cs.reset(10);
  cs.add_contact(0, 1);
  cs.add_contact(6, -1);
  const int t1[3] = {5, 6, 7};
  cs.add_term(t1, 3);
  cs.build();
  // step 2: one cluster {2}, grown to {2,3} (one growth, one redo)
  cs.reset(10);
  cs.add_contact(2, -1);
  cs.build();
  EXPECT_TRUE(cs.grow_contact(2, 3));
  EXPECT_EQ(cs.rebuild().size(), 1u);
  cs.flush_counters();
  cs.flush_counters();    // idempotent
  const auto &k = cs.counters();
  EXPECT_EQ(k.steps, 2);
  EXPECT_EQ(k.clusters, 3);           // final builds only
  EXPECT_EQ(k.atoms, 2 + 3 + 2);
  EXPECT_EQ(k.members, 2 + 1 + 2);
  EXPECT_EQ(k.max_atoms, 3);
  EXPECT_EQ(k.max_members, 2);
  EXPECT_EQ(k.growths, 1);
  EXPECT_EQ(k.redone, 1);
  EXPECT_DOUBLE_EQ(k.mean_atoms(), 7.0 / 3.0);
  EXPECT_DOUBLE_EQ(k.mean_members(), 5.0 / 3.0);
}

// the frozen-partner rule: terms join only their members
TEST(Clusters, FrozenPartnersRandomAgainstBFS)
{
  std::mt19937 rng(4242);
  ClusterSet cs;
  for (int trial = 0; trial < 10000; ++trial) {
    const Case k = random_case(rng);
    build_case(cs, k, false);
    ASSERT_EQ(groups_of(cs), brute(k.n, k.contacts, k.terms, false)) << "trial " << trial;
    check_consistency(cs, k.n);
    if (HasFatalFailure()) FAIL() << "trial " << trial;
    for (int c = 0; c < cs.nclusters(); ++c) ASSERT_EQ(cs.atoms(c), cs.members(c));
  }
  // two members sharing a partner stay apart; a term of two members joins them
  cs.set_partners_join(false);
  cs.reset(6);
  cs.add_contact(0, -1);
  cs.add_contact(2, -1);
  cs.add_pair(0, 1);
  cs.add_pair(1, 2);    // 1 is a partner of both
  cs.build();
  EXPECT_EQ(cs.nclusters(), 2);
  EXPECT_EQ(cs.cluster_of(1), -1);
  cs.add_contact(4, -1);
  cs.add_contact(5, -1);
  cs.add_pair(4, 5);
  cs.build();
  EXPECT_EQ(cs.nclusters(), 3);
  EXPECT_EQ(cs.atoms(2), (std::vector<int>{4, 5}));
  cs.set_partners_join(true);
}

// a case's atoms as dense ids handed out in order of first use (as contacts
// name atoms), ordered by their atom IDs idval[t] (set_order), for one step
// of cs: the local engine's form
struct OrderedIds {
  ClusterSet &cs;
  std::vector<int64_t> idval;    // the atom ID of the case's index t
  std::vector<int> idof;         // the dense id of index t, -1 before its first use
  std::vector<int64_t> order;    // the atom ID of each dense id
  OrderedIds(ClusterSet &c, std::vector<int64_t> ids) :
      cs(c), idval(std::move(ids)), idof(idval.size(), -1)
  {
    cs.set_partners_join(false);
    cs.reset(0);
    cs.set_order(&order);
  }
  OrderedIds(const OrderedIds &) = delete;    // (cs keeps &order)
  ~OrderedIds() { cs.set_order(nullptr); }
  int id(int t)
  {
    if (t < 0) return -1;
    if (idof[t] < 0) {
      idof[t] = (int) order.size();
      order.push_back(idval[t]);
      cs.grow((int) order.size());
    }
    return idof[t];
  }
  // every term with a member so far, restricted to its members
  void add_member_terms(const Case &k)
  {
    for (auto &t : k.terms) {
      std::vector<int> ids;
      for (int a : t)
        if (idof[a] >= 0 && cs.is_member(idof[a])) ids.push_back(idof[a]);
      if (!ids.empty()) cs.add_term(ids.data(), (int) ids.size());
    }
  }
};

// the local engine's form (issue 20): a set over dense ids given in any
// order (as contacts name atoms), grown within the step, numbered and
// sorted by the atoms' IDs (set_order) so that every MPI rank agrees: the
// same clusters as the brute force on the IDs, numbered by smallest ID,
// members ascending in ID
TEST(Clusters, DenseIdsOrderedByAtomIDs)
{
  std::mt19937 rng(2026);
  ClusterSet cs;
  for (int trial = 0; trial < 3000; ++trial) {
    const Case k = random_case(rng);
    // IDs: any increasing map of the case's indices
    std::vector<int64_t> idval(k.n);
    for (int t = 0; t < k.n; ++t) idval[t] = 1000 + 7 * (int64_t) t;
    OrderedIds ids(cs, idval);
    const std::vector<int64_t> &order = ids.order;
    for (auto &c : k.contacts) {
      const int a = ids.id(c.first);
      cs.add_contact(a, ids.id(c.second));
    }
    ids.add_member_terms(k);
    cs.build();
    Groups got;
    int64_t last_key = -1;
    for (int c = 0; c < cs.nclusters(); ++c) {
      std::vector<int> m;
      for (int i : cs.members(c)) m.push_back((int) ((order[i] - 1000) / 7));
      ASSERT_TRUE(std::is_sorted(m.begin(), m.end())) << "trial " << trial;
      ASSERT_GT(order[cs.members(c)[0]], last_key) << "trial " << trial;
      last_key = order[cs.members(c)[0]];
      got.insert({m, m});
    }
    ASSERT_EQ(got, brute(k.n, k.contacts, k.terms, false)) << "trial " << trial;
  }
}

// the same, grown in rounds as the local engine grows it (contacts naming new
// ids after a build, then rebuild()): build() sorts only the atoms added
// since the last build and merges them into the sorted rest. Each round's
// clusters equal the brute force on the contacts so far, numbered by
// smallest ID, members ascending; and rebuild() redoes exactly the clusters
// that differ from the previous round's
TEST(Clusters, GrownInRoundsOrderedByAtomIDs)
{
  std::mt19937 rng(2027);
  ClusterSet cs;
  for (int trial = 0; trial < 2000; ++trial) {
    const Case k = random_case(rng);
    // IDs in a random order of the indices, so that ids handed out later
    // often sort before earlier ones
    std::vector<int64_t> idval(k.n);
    for (int t = 0; t < k.n; ++t) idval[t] = 5 + 3 * (int64_t) t;
    std::shuffle(idval.begin(), idval.end(), rng);
    OrderedIds ids(cs, idval);
    const std::vector<int> &idof = ids.idof;
    const std::vector<int64_t> &order = ids.order;
    // the clusters as sets of indices, in numbering order, checked sorted
    auto clusters = [&]() {
      std::vector<std::vector<int>> out;
      int64_t last_key = -1;
      for (int c = 0; c < cs.nclusters(); ++c) {
        std::vector<int64_t> ids;
        std::vector<int> m;
        for (int i : cs.members(c)) {
          ids.push_back(order[i]);
          for (int t = 0; t < k.n; ++t)
            if (idof[t] == i) m.push_back(t);
        }
        EXPECT_TRUE(std::is_sorted(ids.begin(), ids.end())) << "trial " << trial;
        EXPECT_GT(ids[0], last_key) << "trial " << trial;
        last_key = ids[0];
        std::sort(m.begin(), m.end());
        out.push_back(m);
      }
      return out;
    };
    const int nc = (int) k.contacts.size();
    const int rounds = 1 + (int) (rng() % 4);
    std::vector<std::vector<int>> prev;
    int done = 0;
    for (int r = 0; r < rounds; ++r) {
      const int upto = (r == rounds - 1) ? nc : done + (int) (rng() % (nc - done + 1));
      for (; done < upto; ++done) {
        const auto &c = k.contacts[done];
        const int a = ids.id(c.first);
        if (r == 0) cs.add_contact(a, ids.id(c.second));
        else cs.grow_contact(a, ids.id(c.second));
      }
      ids.add_member_terms(k);
      std::vector<int> redo;
      if (r == 0) cs.build();
      else redo = cs.rebuild();
      const std::vector<std::pair<int, int>> so_far(k.contacts.begin(), k.contacts.begin() + done);
      Groups want;
      for (auto &g : brute(k.n, so_far, k.terms, false)) want.insert(g);
      const auto got = clusters();
      Groups gg;
      for (auto &m : got) gg.insert({m, m});
      ASSERT_EQ(gg, want) << "trial " << trial << " round " << r;
      if (r > 0) {
        std::vector<int> want_redo;
        for (int c = 0; c < (int) got.size(); ++c)
          if (std::find(prev.begin(), prev.end(), got[c]) == prev.end()) want_redo.push_back(c);
        ASSERT_EQ(redo, want_redo) << "trial " << trial << " round " << r;
      }
      prev = got;
    }
  }
}
