/* ----------------------------------------------------------------------
   HARDSPHERE package: forces of the interaction terms of a set of atoms
   through LAMMPS' own styles. See hs_local_forces.h.
------------------------------------------------------------------------- */

#include "hs_local_forces.h"
#include "hs_compat.h"
#include "hs_mpi.h"
#include "hs_stamp.h"

#include "angle.h"
#include "atom.h"
#include "bond.h"
#include "comm.h"
#include "dihedral.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "improper.h"
#include "memory.h"
#include "neigh_list.h"
#include "neigh_request.h"
#include "neighbor.h"
#include "pair.h"

#include <algorithm>
#include <cstring>
#include <limits>
#include <mpi.h>

using namespace LAMMPS_NS;

namespace {
// the tallies a style keeps; compute(0, 0) should not touch them, but a
// style may reset them in ev_init(): they are saved and restored anyway
struct Tally {
  double e1 = 0.0, e2 = 0.0, v[6] = {0, 0, 0, 0, 0, 0};
};

bool has_suffix(const char *style, const char *suf)
{
  const size_t n = strlen(style), m = strlen(suf);
  return n >= m && strcmp(style + n - m, suf) == 0;
}
}    // namespace

/* ---------------------------------------------------------------------- */

HSLocalForces::HSLocalForces(LAMMPS *lmp, const std::string &owner) : Pointers(lmp), owner_(owner)
{
}

HSLocalForces::~HSLocalForces()
{
  memory->destroy(numneigh_);
  memory->sfree(firstneigh_);
  memory->destroy(fl_);
  memory->destroy(tq_);
}

/* ---------------------------------------------------------------------- */

void HSLocalForces::init()
{
  if (atom->map_style == 0)
    error->all(FLERR, "{} with substep local needs an atom map to find the periodic images of "
                      "colliding atoms: use atom_modify map array (or yes)", owner_);
  why_.clear();
  auto add = [this](const std::string &s) { why_ += (why_.empty() ? "" : "; ") + s; };
  // (kspace is not a style of V_C's terms: the real-space part of a
  // coul/long pair style restricts like any pair style, and the engine
  // holds the reciprocal part with LAMMPS' forces, HSLocalEngine::limits())
  hybrid_ = false;
  if (force->pair) {
    const char *ps = force->pair_style;
    // (hybrid's manybody_flag and ghostneigh are those of any sub-style)
    if (force->pair->manybody_flag)
      add(std::string("pair style ") + ps + " (many-body)");
    else if (force->pair->ghostneigh)
      add(std::string("pair style ") + ps + " (needs neighbours of ghost atoms)");
    std::vector<std::string> names{ps};
    if (strncmp(ps, "hybrid", 6) == 0) {
      // the restricted rows are split among the sub-styles' lists by their
      // type skips (hybrid_forces())
      hybrid_ = true;
      if (strcmp(ps, "hybrid/molecular") == 0)
        add("pair style hybrid/molecular (its sub-styles' lists are split by molecule, not by "
            "atom type)");
      names = sub_style_names();
    }
    for (const std::string &n : names)
      for (const char *suf : {"/omp", "/gpu", "/kk", "/kk/host", "/kk/device", "/intel"})
        if (has_suffix(n.c_str(), suf))
          add("pair style " + n + " (accelerator variant: thread-private forces)");
  }
  // bonded styles: hybrid splits neighbor->bondlist (anglelist, ...) into
  // its sub-styles' lists only at a list build (neighbor->ago == 0), so a
  // restricted list swapped in is ignored in other steps (every term's
  // forces were computed) and, in a list build's step, kept for LAMMPS' own
  // evaluations after it (terms lost); accelerator variants keep their
  // forces in thread-private arrays
  if (atom->molecular != Atom::ATOMIC) {
    const std::pair<const char *, const char *> bonded[4] = {
        {"bond", force->bond ? force->bond_style : nullptr},
        {"angle", force->angle ? force->angle_style : nullptr},
        {"dihedral", force->dihedral ? force->dihedral_style : nullptr},
        {"improper", force->improper ? force->improper_style : nullptr}};
    for (const auto &[kind, name] : bonded) {
      if (!name) continue;
      if (strncmp(name, "hybrid", 6) == 0)
        add(fmt::format("{} style {} (it splits LAMMPS' {} list among its sub-styles only at "
                        "a list build)",
                        kind, name, kind));
      for (const char *suf : {"/omp", "/gpu", "/kk", "/kk/host", "/kk/device", "/intel"})
        if (has_suffix(name, suf))
          add(fmt::format("{} style {} (accelerator variant: thread-private forces)", kind, name));
    }
  }
  // on several ranks a restricted evaluation without rows (held forces of
  // pcva's projection, newton_pair off) sums the ghosts' forces with
  // comm->reverse_comm(), which also sums what else the atom style reverses
  // (torques are saved and restored in run_styles(); electron's or spin's
  // extra force arrays are not)
  if (comm->nprocs > 1 && !HSCompat::reverse_is_force_and_torque(atom))
    add(fmt::format("atom style {} on several ranks (its reverse communication carries more "
                    "than forces and torques)",
                    atom->atom_style));
  initialized_ = 1;
  lj_ = HardSphere::LJCutTable();    // (set again by the caller, checked again in every run)
  lj_state_ = lj_estate_ = -1;
  built_ncalls_ = -1;
  // Neighbor::init() sets neighbor->ncalls back to 0 at every run: the
  // run's number keeps the builds of two runs apart (list_epoch())
  ++run_epoch_;
}

/* ----------------------------------------------------------------------
   pair hybrid. Its sub-styles compute on their own lists, which LAMMPS
   derives from one list of all pairs by type skips (NeighList::iskip,
   ijskip; a sub-style that takes every type pair gets a plain list or a
   copy). The restricted rows are those of that list of all pairs (or
   compute_rows()' own rows), split by the same skips into one restricted
   list per sub-style; hybrid's compute() then runs every sub-style on its
   own, with its own special factors and scaling.
------------------------------------------------------------------------- */

// the keywords of the hybrid sub-styles, from this run's neighbor requests
// (made by the pair style's init() before the fixes' init(); after a run,
// the kept copies of them)
std::vector<std::string> HSLocalForces::sub_style_names() const
{
  std::vector<std::string> out;
  const bool pending = neighbor->nrequest > 0;
  const int n = pending ? neighbor->nrequest : neighbor->old_nrequest;
  for (int r = 0; r < n; r++) {
    NeighRequest *req = pending ? neighbor->requests[r] : neighbor->old_requests[r];
    void *who = req ? HSCompat::request_requestor(req) : nullptr;
    if (!who || who == force->pair) continue;
    // (pointer comparisons only: a fix's pointer matches no sub-style)
    const char *kw = force->pair_match_ptr(static_cast<Pair *>(who));
    if (kw && std::find(out.begin(), out.end(), kw) == out.end()) out.emplace_back(kw);
  }
  return out;
}

// the sub-styles' lists of this run (Neighbor::init() made them), which
// type pairs some sub-style computes, and the list of all pairs
void HSLocalForces::find_sub_lists()
{
  subs_.clear();
  hyb_all_ = nullptr;
  for (int l = 0; l < neighbor->nlist; l++) {
    NeighList *nl = neighbor->lists[l];
    if (!nl || nl->requestor_type != NeighList::PAIR || !nl->requestor ||
        nl->requestor == force->pair)
      continue;
    auto *p = static_cast<Pair *>(nl->requestor);
    const char *kw = force->pair_match_ptr(p);
    if (!kw) continue;
    if (p->list != nl || nl->ghost)
      error->all(FLERR, "{}: pair hybrid sub-style {} reads a neighbor list other than one half "
                 "list of its own, which substep local cannot restrict; use substep global",
                 owner_, kw);
    for (const SubList &s : subs_)
      if (s.style == p)
        error->all(FLERR, "{}: pair hybrid sub-style {} has two neighbor lists, which substep "
                   "local cannot restrict; use substep global", owner_, kw);
    SubList s;
    s.style = p;
    s.list = nl;
    subs_.push_back(std::move(s));
    // the list the skips were taken from holds every pair; a sub-style's
    // list without skips holds every pair itself (a list LAMMPS copied
    // from an identical request's holds what that one holds)
    NeighList *all = nl;
    while (all->listskip || all->listcopy) all = all->listskip ? all->listskip : all->listcopy;
    if (!hyb_all_) hyb_all_ = all;
  }
  if (subs_.empty() || !hyb_all_)
    error->all(FLERR, "{}: pair style {} has no sub-style with a neighbor list to restrict",
               owner_, force->pair_style);
  const int ntp1 = atom->ntypes + 1;
  covered_.assign((size_t) ntp1 * ntp1, 0);
  for (const SubList &s : subs_)
    for (int i = 1; i < ntp1; i++)
      for (int j = 1; j < ntp1; j++)
        if (!s.list->ijskip || !s.list->ijskip[i][j]) covered_[i * ntp1 + j] = 1;
  all_covered_ = true;
  for (int i = 1; i < ntp1; i++)
    for (int j = 1; j < ntp1; j++) all_covered_ = all_covered_ && covered_[i * ntp1 + j];
  hyb_run_ = run_epoch_;
}

// the list whose rows are restricted: the pair style's own, or with pair
// hybrid the list of all pairs its sub-styles' lists are derived from
// (hybrid: found by evaluate() once per run)
NeighList *HSLocalForces::pair_list() const
{
  if (!force->pair || !force->pair->compute_flag) return nullptr;
  return hybrid_ ? hyb_all_ : force->pair->list;
}

// hybrid's compute() on the restricted rows (ilist_, numneigh_,
// firstneigh_) split into each sub-style's list by its type skips, as
// LAMMPS' skip lists split the full list (npair_skip.cpp); the sub-styles'
// tallies and lists are restored after it
void HSLocalForces::hybrid_forces(int eflag)
{
  const int *type = atom->type;
  const size_t nall = atom->nlocal + atom->nghost;
  struct Saved {
    int inum;
    int *ilist, *numneigh;
    int **firstneigh;
    Tally t;
  };
  std::vector<Saved> saved(subs_.size());
  for (size_t m = 0; m < subs_.size(); m++) {
    SubList &s = subs_[m];
    if (s.num.size() < nall) {
      s.num.resize(nall);
      s.first.resize(nall);
    }
    const int *iskip = s.list->iskip;
    int **ijskip = s.list->ijskip;
    s.ilist.clear();
    s.neigh.clear();
    s.starts.clear();
    for (int i : ilist_) {
      const int ti = type[i];
      if (iskip && iskip[ti]) continue;
      const int *jl = firstneigh_[i];
      const int n0 = (int) s.neigh.size();
      for (int k = 0; k < numneigh_[i]; k++)
        if (!ijskip || !ijskip[ti][type[jl[k] & NEIGHMASK]]) s.neigh.push_back(jl[k]);
      if ((int) s.neigh.size() == n0) continue;
      s.ilist.push_back(i);
      s.num[i] = (int) s.neigh.size() - n0;
      s.starts.push_back(n0);
    }
    for (size_t k = 0; k < s.ilist.size(); k++) s.first[s.ilist[k]] = s.neigh.data() + s.starts[k];
    NeighList *L = s.list;
    Pair *p = s.style;
    Saved &sv = saved[m];
    sv.inum = L->inum;
    sv.ilist = L->ilist;
    sv.numneigh = L->numneigh;
    sv.firstneigh = L->firstneigh;
    sv.t.e1 = p->eng_vdwl;
    sv.t.e2 = p->eng_coul;
    for (int k = 0; k < 6; k++) sv.t.v[k] = p->virial[k];
    L->inum = (int) s.ilist.size();
    L->ilist = s.ilist.data();
    L->numneigh = s.num.data();
    L->firstneigh = s.first.data();
  }
  force->pair->compute(eflag, 0);
  for (size_t m = 0; m < subs_.size(); m++) {
    NeighList *L = subs_[m].list;
    Pair *p = subs_[m].style;
    const Saved &sv = saved[m];
    L->inum = sv.inum;
    L->ilist = sv.ilist;
    L->numneigh = sv.numneigh;
    L->firstneigh = sv.firstneigh;
    p->eng_vdwl = sv.t.e1;
    p->eng_coul = sv.t.e2;
    for (int k = 0; k < 6; k++) p->virial[k] = sv.t.v[k];
  }
}

/* ---------------------------------------------------------------------- */

void HSLocalForces::grow()
{
  if (atom->nmax > nmax_) {
    memory->destroy(numneigh_);
    memory->sfree(firstneigh_);
    memory->destroy(fl_);
    memory->destroy(tq_);
    nmax_ = atom->nmax;
    memory->create(numneigh_, nmax_, "hs_local_forces:numneigh");
    firstneigh_ = (int **) memory->smalloc(nmax_ * sizeof(int *), "hs_local_forces:firstneigh");
    memory->create(fl_, nmax_, 3, "hs_local_forces:f");
  }
  if (atom->torque_flag && !tq_ && nmax_ > 0) memory->create(tq_, nmax_, 3, "hs_local_forces:torque");
  const size_t nall = atom->nlocal + atom->nghost;
  if (in_c_.size() < nall) {
    in_c_.resize(nall, 0);
    zeroed_.resize(nall, 0);
  }
}

double HSLocalForces::memory_usage() const
{
  const auto bytes = [](const auto &vec) { return HardSphere::capacity_bytes(vec); };
  // fl_ (3 doubles), numneigh_, firstneigh_ per copy; tq_ (3) with torques
  double b = (double) nmax_ * ((tq_ ? 6 : 3) * sizeof(double) + sizeof(int) + sizeof(int *));
  b += bytes(in_c_) + bytes(zeroed_) + bytes(has_row_) + bytes(pinv_off_) + bytes(pinv_row_) +
      bytes(pinv_val_) + bytes(ilist_) + bytes(neigh_) + bytes(zero_list_) + bytes(term_local_) +
      bytes(term_off_) + bytes(term_extra_) + bytes(covered_) + bytes(extra_) + bytes(xcount_) +
      bytes(xrows_) + bytes(xtmp_) + bytes(tstamp_) + bytes(touched_owned_) + bytes(marked_) +
      bytes(starts_);
  for (const auto &B : bonded_)
    b += bytes(B.off) + bytes(B.rows) + bytes(B.stamp) + bytes(B.sub);
  for (const SubList &sl : subs_)
    b += bytes(sl.ilist) + bytes(sl.neigh) + bytes(sl.starts) + bytes(sl.num) + bytes(sl.first);
  return b;
}

void HSLocalForces::next_epoch()
{
  if (++epoch_ != 0) return;
  std::fill(in_c_.begin(), in_c_.end(), 0u);
  std::fill(zeroed_.begin(), zeroed_.end(), 0u);
  std::fill(tstamp_.begin(), tstamp_.end(), 0u);
  for (auto &B : bonded_) std::fill(B.stamp.begin(), B.stamp.end(), 0u);
  epoch_ = 1;
}

// which of bond, angle, dihedral, improper contribute (molecular system,
// style defined)
void HSLocalForces::presence(bool present[4]) const
{
  const bool mol = atom->molecular != Atom::ATOMIC;
  const bool style[4] = {force->bond != nullptr, force->angle != nullptr,
                         force->dihedral != nullptr, force->improper != nullptr};
  // (not the rank's list itself: LAMMPS allocates it at the first term the
  // rank lists, so on a rank that never had one it is null with a count of
  // 0, while the terms gathered by ID (compute_rows()) can still hold such
  // terms. Up to 30 Nov 2026 the list decided: a rank running a cluster
  // whose angles LAMMPS listed only on other ranks left them out, and 4
  // ranks gave another trajectory than 1 and 2)
  for (int b = 0; b < 4; b++) present[b] = mol && style[b];
}

/* ----------------------------------------------------------------------
   inverse indices: for every local atom j, where it appears in the bonded
   lists and (pair true) in the pair list (row i, the raw entry with its
   special bits). O(list size), at most once per neighbor list build each;
   rows mode (compute_rows()) takes its pair terms from its own rows and
   never needs the pair index.
------------------------------------------------------------------------- */

void HSLocalForces::build_index(bool pair)
{
  const int nall = atom->nlocal + atom->nghost;
  NeighList *L = pair_list();
  if (list_epoch() != built_ncalls_ || nall != built_nall_ || L != built_list_) {
    build_bonded_index();
    built_ncalls_ = list_epoch();
    built_nall_ = nall;
    built_list_ = L;
    pair_index_ = false;
  }
  if (!pair || pair_index_) return;
  pair_index_ = true;
  if (L) {
    has_row_.assign(nall, 0);
    pinv_off_.assign(nall + 1, 0);
    for (int ii = 0; ii < L->inum; ii++) {
      const int i = L->ilist[ii];
      has_row_[i] = 1;
      const int *jl = L->firstneigh[i];
      for (int k = 0; k < L->numneigh[i]; k++) pinv_off_[(jl[k] & NEIGHMASK) + 1]++;
    }
    for (int j = 0; j < nall; j++) pinv_off_[j + 1] += pinv_off_[j];
    pinv_row_.resize(pinv_off_[nall]);
    pinv_val_.resize(pinv_off_[nall]);
    std::vector<int> pos(pinv_off_.begin(), pinv_off_.end() - 1);
    for (int ii = 0; ii < L->inum; ii++) {
      const int i = L->ilist[ii];
      const int *jl = L->firstneigh[i];
      for (int k = 0; k < L->numneigh[i]; k++) {
        const int p = pos[jl[k] & NEIGHMASK]++;
        pinv_row_[p] = i;
        pinv_val_[p] = jl[k];
      }
    }
  }
}

void HSLocalForces::build_bonded_index()
{
  const int nall = atom->nlocal + atom->nghost;
  // a list and its count are defined only when the style exists (the
  // count of an absent style is never initialized)
  bool present[4];
  presence(present);
  int **lists[4] = {neighbor->bondlist, neighbor->anglelist, neighbor->dihedrallist,
                    neighbor->improperlist};
  int counts[4] = {neighbor->nbondlist, neighbor->nanglelist, neighbor->ndihedrallist,
                   neighbor->nimproperlist};
  const int width[4] = {2, 3, 4, 4};
  for (int b = 0; b < 4; b++) {
    Bonded &B = bonded_[b];
    B.off.assign(nall + 1, 0);
    B.rows.clear();
    if (!present[b]) counts[b] = 0;
    B.stamp.assign(counts[b], 0u);
    if (!present[b]) continue;
    for (int r = 0; r < counts[b]; r++)
      for (int k = 0; k < width[b]; k++) B.off[lists[b][r][k] + 1]++;
    for (int j = 0; j < nall; j++) B.off[j + 1] += B.off[j];
    B.rows.resize(B.off[nall]);
    std::vector<int> pos(B.off.begin(), B.off.end() - 1);
    for (int r = 0; r < counts[b]; r++)
      for (int k = 0; k < width[b]; k++) B.rows[pos[lists[b][r][k]]++] = r;
  }
}

/* ---------------------------------------------------------------------- */

void HSLocalForces::set_reference(double **xb)
{
  ref_ = xb;
  ref_ncalls_ = list_epoch();
}

// a number of the current neighbor list build, distinct for every build of
// every run: what the caches below are keyed by (neighbor->ncalls alone
// restarts at each run, so a second run's build could pass for the first
// run's with the same count, and rows of the old lists would be reused)
int64_t HSLocalForces::list_epoch() const
{
  return (run_epoch_ << 32) + (int64_t) neighbor->ncalls;
}

// the row of local atom a: every local atom within the neighbor cutoff at
// the list build's positions (not a, not its images), in tag order, with
// its special bits as LAMMPS' lists carry them; with set_near(), a's
// contact neighbours from the same scan (near_row())
void HSLocalForces::build_row(int a, std::vector<std::pair<tagint, int>> &out)
{
  const tagint *tag = atom->tag;
  const int *mask = atom->mask;
  const tagint ta = tag[a];
  const double cut2 = neighbor->cutneighmax * neighbor->cutneighmax;
  const double *xa = ref_[a];
  const bool mol = atom->molecular != Atom::ATOMIC && atom->nspecial;
  const size_t start = out.size();
  // a contact neighbour is marked in its entry by the bit below the special
  // bits (SBBITS up), taken off again below (LAMMPS 29Sep2021's NEIGHMASK
  // has it, 4Feb2025's not: the sort masks it out, and it is used only
  // while the local indices stay below it); one the lists leave out waits
  // in near_excl_
  constexpr int NEAR = 1 << (SBBITS - 1);
  constexpr int INDEX = NEIGHMASK & ~NEAR;
  const bool near = near_cut2_ >= 0.0 && near_cut2_ <= cut2 &&
      atom->nlocal + atom->nghost <= NEAR;
  const double ncut2 = near_cut2_;
  const int nbit = near_groupbit_;
  // neigh_modify exclude: the pairs LAMMPS' lists leave out, left out of
  // the rows too (the fix allows none of two group atoms: contacts)
  const bool ex = HSCompat::excludes(neighbor);
  near_excl_.clear();
  // (the constants by value: read once, not through the closure per entry)
  // (the grid's kernel keeps r2 not greater than cut2; r2 again here, the
  // same operations, for the contact test)
  auto scan = [&, near, ncut2, mol, ex, a, ta](int j, const double *xj) {
    const double dx = xa[0] - xj[0], dy = xa[1] - xj[1], dz = xa[2] - xj[2];
    const double r2 = dx * dx + dy * dy + dz * dz;
    const tagint tj = tag[j];
    if (j == a || tj == ta) return;    // itself, its own images
    // (as HSLocalEngine::crow()'s own scan decides; its group test below)
    const bool nj = near && !(r2 > ncut2);
    // (LAMMPS' lists test the exclusions before the special bits)
    const int code = (ex && excluded(a, j)) ? -1 : mol ? special_code(a, tj) : 0;
    if (code < 0) {    // excluded
      if (nj && (mask[j] & nbit)) near_excl_.emplace_back(tj, j);
      return;
    }
    out.emplace_back(tj, (code ? j ^ (code << SBBITS) : j) | (nj ? NEAR : 0));
  };
  rows_cache_.grid.for_each_within(xa, cut2, scan);
  std::sort(out.begin() + start, out.end(),
            [](const std::pair<tagint, int> &p, const std::pair<tagint, int> &q) {
              return p.first != q.first ? p.first < q.first
                                        : (p.second & INDEX) < (q.second & INDEX);
            });
  if (!near) return;
  // the contact neighbours in (ID, index) order: the marked entries of the
  // sorted row merged with the excluded ones
  std::sort(near_excl_.begin(), near_excl_.end());
  int n;
  bool filled = false;
  near_.row(a, n, [&](std::vector<int> &nout) {
    filled = true;
    size_t e = 0;
    for (size_t k = start; k < out.size(); k++) {
      if (!(out[k].second & NEAR)) continue;
      out[k].second &= ~NEAR;
      const int j = out[k].second & INDEX;
      if (!(mask[j] & nbit)) continue;
      for (; e < near_excl_.size() && near_excl_[e] < std::make_pair(out[k].first, j); e++)
        nout.push_back(near_excl_[e].second);
      nout.push_back(j);
    }
    for (; e < near_excl_.size(); e++) nout.push_back(near_excl_[e].second);
  });
  if (!filled)
    for (size_t k = start; k < out.size(); k++) out[k].second &= ~NEAR;
}

int HSLocalForces::special_code(int a, tagint tj) const
{
  if (atom->molecular == Atom::ATOMIC || !atom->nspecial) return 0;
  // the caller's topology (by ID), else the owned copy's list (ghosts
  // carry none)
  const tagint ta = atom->tag[a];
  tagint ns[3];
  const tagint *sp = nullptr;
  const std::vector<tagint> *rec = nullptr;
  if (topo_) {
    auto it = topo_->special.find(ta);
    if (it != topo_->special.end()) rec = &it->second;
  }
  if (rec) {
    for (int k = 0; k < 3; k++) ns[k] = (*rec)[k];
    sp = rec->data() + 3;
  } else {
    const int o = atom->map(ta);
    if (o < 0 || o >= atom->nlocal)
      error->one(FLERR, "{}: the special neighbours of atom {} are not known on rank {} (a "
                 "ghost copy here; the local engine gathers those of its clusters' members)",
                 owner_, ta, comm->me);
    for (int k = 0; k < 3; k++) ns[k] = atom->nspecial[o][k];
    sp = atom->special[o];
  }
  int which = 0;
  for (tagint k = 0; k < ns[2]; k++)
    if (sp[k] == tj) {
      which = (k < ns[0]) ? 1 : (k < ns[1]) ? 2 : 3;
      break;
    }
  if (which == 0) return 0;
  if (neighbor->special_flag[which] == 0) return -1;
  return neighbor->special_flag[which] == 2 ? which : 0;
}

// NPair::exclusion() (npair.cpp, the same in 29Sep2021 and 4Feb2025) on
// Neighbor's tables, which Neighbor::init() fills for the run: by type
// pair, by a pair of groups (either way round), by molecule within one
// group (intra: the same molecule; inter: different ones). Ghost copies
// carry type, mask and molecule (borders), so every rank decides alike
bool HSLocalForces::excluded(int i, int j) const
{
  const Neighbor *nb = neighbor;
  const int *type = atom->type, *mask = atom->mask;
  if (nb->nex_type && nb->ex_type[type[i]][type[j]]) return true;
  for (int m = 0; m < nb->nex_group; m++)
    if (((mask[i] & nb->ex1_bit[m]) && (mask[j] & nb->ex2_bit[m])) ||
        ((mask[i] & nb->ex2_bit[m]) && (mask[j] & nb->ex1_bit[m])))
      return true;
  const tagint *molecule = atom->molecule;
  for (int m = 0; m < nb->nex_mol; m++)
    if ((mask[i] & nb->ex_mol_bit[m]) && (mask[j] & nb->ex_mol_bit[m]) &&
        ((molecule[i] == molecule[j]) == (nb->ex_mol_intra[m] != 0)))
      return true;
  return false;
}

void HSLocalForces::compute_rows(const int *c, int nc, bool record_terms)
{
  const std::string why = rows_unsupported();
  if (!why.empty())
    error->one(FLERR, "{}: rank-local interaction rows are not exact with {}", owner_, why);
  rows_ = true;
  evaluate(c, nc, record_terms);
}

bool HSLocalForces::cross_rows(const int *c, int nc, double (*f)[3], std::vector<int> &labels)
{
  // what evaluate() does in this case, term for term (rows, mode CROSS, no
  // pair hybrid, lj/cut's kernel verified): it keeps the entries of C's rows
  // whose atom is labelled >= 0 and otherwise than the row's (another
  // cluster's member; a pair within C has one label), sums each row's terms
  // from a zeroed force in entry order (no other row holds a copy of C:
  // those entries are C's own pairs, left out) and folds nothing into C's
  // copies; with energy, the kernel's tally in C's tag order
  NeighList *L = pair_list();
  const int state = keep_energy_ ? lj_estate_ : lj_state_;
  if (!initialized_ || !exact() || hybrid_ || !L || !label_ || !lj_.coef || state != 1 ||
      !force->pair || !force->pair->compute_flag || ref_ncalls_ != list_epoch() ||
      cells_ncalls_ != list_epoch())
    return false;
  if (!rows_unsupported().empty()) return false;
  ctag_.clear();
  for (int k = 0; k < nc; k++) {
    int len;
    if (!rows_cache_.built(c[k], len)) return false;    // (evaluate() would build it)
    ctag_.emplace_back(atom->tag[c[k]], k);
  }
  std::sort(ctag_.begin(), ctag_.end());
  const double *x = atom->x[0];
  const int *type = atom->type;
  double eng = 0.0;
  constexpr int AHEAD = HardSphere::PREFETCH_AHEAD;
  for (const auto &ta : ctag_) {
    const int a = c[ta.second], la = label_[a];
    int len;
    const std::pair<tagint, int> *row = rows_cache_.built(a, len);
    kept_.clear();
    for (int k = 0; k < len; k++) {
      if (k + AHEAD < len) __builtin_prefetch(label_ + (row[k + AHEAD].second & NEIGHMASK));
      const int raw = row[k].second;
      const int lj = label_[raw & NEIGHMASK];
      if (la >= 0 && lj >= 0 && lj != la) {
        kept_.push_back(raw);
        labels.push_back(lj);
      }
    }
    const double xa[3] = {x[3 * (size_t) a], x[3 * (size_t) a + 1], x[3 * (size_t) a + 2]};
    if (keep_energy_)
      HardSphere::lj_cut_row_force<NEIGHMASK, SBBITS, true>(
          xa, type[a], kept_.data(), (int) kept_.size(), x, type,
          force->special_lj, force->pair->cutsq, lj_, f[ta.second], eng);
    else
      HardSphere::lj_cut_row_force<NEIGHMASK, SBBITS>(
          xa, type[a], kept_.data(), (int) kept_.size(), x, type,
          force->special_lj, force->pair->cutsq, lj_, f[ta.second], eng);
  }
  // (run_styles() sums 0 + the pair's tally + its zero Coulomb part + the
  // bonded styles' zeros from their empty lists: eng + 0.0, the same bits,
  // a -0.0 made +0.0)
  if (keep_energy_) energy_ = eng + 0.0;
  ncalls += 1.0;
  return true;
}

void HSLocalForces::compute(const int *c, int nc, bool record_terms)
{
  rows_ = false;
  evaluate(c, nc, record_terms);
}

std::string HSLocalForces::rows_unsupported() const
{
  std::string why = why_;
  auto add = [&why](const std::string &s) { why += (why.empty() ? "" : "; ") + s; };
  if (comm->nprocs > 1 && atom->molecular != Atom::ATOMIC && !topo_)
    add("a molecular system on several ranks without the members' topology (ghost atoms carry "
        "no special neighbours or bonded terms)");
  return why;
}

// (error->one here and below: on several ranks a cluster's evaluation runs
// on the rank that runs it alone; error->all would wait for the others)
void HSLocalForces::evaluate(const int *c, int nc, bool record_terms)
{
  if (!initialized_) error->one(FLERR, "{}: local forces used before init()", owner_);
  if (!exact())
    error->one(FLERR, "{}: local forces are not exact with {}; use substep global", owner_, why_);

  const int nlocal = atom->nlocal;
  const int nall = nlocal + atom->nghost;
  const int nprocs = comm->nprocs;
  grow();
  next_epoch();
  if (hybrid_ && hyb_run_ != run_epoch_) find_sub_lists();
  NeighList *L = pair_list();
  if (force->pair && force->pair->compute_flag && !L)
    error->one(FLERR, "{}: pair style {} has no neighbor list to restrict", owner_,
               force->pair_style);
  build_index(!rows_);

  // ---- C and every image of it (all ranks: C's tags are gathered)
  std::vector<int> &marked = marked_;
  marked.clear();
  auto mark_chain = [&](int i) {
    for (; i >= 0; i = atom->sametag[i])
      if (in_c_[i] != epoch_) {
        in_c_[i] = epoch_;
        marked.push_back(i);
      }
  };
  for (int k = 0; k < nc; k++)
    if (c[k] < 0 || c[k] >= (rows_ ? nall : nlocal))
      error->one(FLERR, "{}: local forces asked for atom index {} which is not {} (nlocal {}, "
                 "nall {})", owner_, c[k], rows_ ? "local" : "owned", nlocal, nall);
  // rows: C's tags (sorted, with their copies in C) decide member pairs
  std::vector<std::pair<tagint, int>> &ctag = ctag_;
  ctag.clear();
  if (rows_) {
    for (int k = 0; k < nc; k++) ctag.emplace_back(atom->tag[c[k]], c[k]);
    std::sort(ctag.begin(), ctag.end());
    for (size_t k = 1; k < ctag.size(); k++)
      if (ctag[k].first == ctag[k - 1].first)
        error->one(FLERR, "{}: local forces asked for two copies of atom {}", owner_,
                   ctag[k].first);
  }
  // the copy in C of the atom with tag t, -1 if t is not in C
  auto copy_in_c = [&ctag](tagint t) {
    auto it = std::lower_bound(ctag.begin(), ctag.end(), std::make_pair(t, -1));
    return (it != ctag.end() && it->first == t) ? it->second : -1;
  };
  if (rows_ || nprocs == 1) {
    // (the chain of copies starts at atom->map()'s)
    for (int k = 0; k < nc; k++) mark_chain(rows_ ? atom->map(atom->tag[c[k]]) : c[k]);
  } else {
    std::vector<tagint> mine(nc), all;
    for (int k = 0; k < nc; k++) mine[k] = atom->tag[c[k]];
    HardSphere::allgatherv(world, MPI_LMP_TAGINT, mine, all);
    for (tagint t : all) mark_chain(atom->map(t));
  }

  zero_list_.clear();
  term_local_.clear();
  term_extra_.clear();
  term_off_.assign(1, 0);
  // the owned copy of local atom j (-1: owned by another rank)
  auto owner_of = [&](int j) -> int {
    if (j < nlocal) return j;
    const int o = atom->map(atom->tag[j]);
    return (o >= 0 && o < nlocal) ? o : -1;
  };
  int nterm = 0;
  const bool record = record_terms || terms_only_;
  // extra: a pair's special index, a bonded term's type
  // (inline: called per term; GCC left it out of line once evaluate() grew)
  auto add_term = [&](const int *a, int k, int extra) __attribute__((always_inline)) {
    ++nterm;
    if (!terms_only_)
      for (int t = 0; t < k; t++) zero(a[t]);
    if (!record) return;
    for (int t = 0; t < k; t++) term_local_.push_back(a[t]);
    term_off_.push_back((int) term_local_.size());
    term_extra_.push_back(extra);
  };

  // ---- pair: full rows of C, and the entries of C's images in other rows
  ilist_.clear();
  neigh_.clear();
  extra_.clear();
  // labels (set_labels()): a pair of two atoms with different labels >= 0
  // is a cross term, left out (NORMAL) or the only one kept (CROSS)
  auto cross = [&](int a, int b) {
    return label_ && label_[a] >= 0 && label_[b] >= 0 && label_[a] != label_[b];
  };
  const bool only_cross = (mode_ == CROSS);
  // a pair left out: by its labels, or (pair hybrid) because no sub-style
  // computes its types (pair_coeff ... none)
  const bool some_uncovered = hybrid_ && !all_covered_;
  const int *type = atom->type;
  const int ntp1 = atom->ntypes + 1;
  auto left_out = [&](int a, int b) {
    return cross(a, b) != only_cross ||
        (some_uncovered && !covered_[type[a] * ntp1 + type[b]]);
  };
  fold_.clear();
  if (rows_ && L) {
    // on-demand rows of C's copies in tag order (hs_local_forces.h)
    if (ref_ncalls_ != list_epoch())
      error->one(FLERR, "{}: interaction rows asked for without the positions of this neighbor "
                 "list build (set_reference)", owner_);
    if (cells_ncalls_ != list_epoch()) {
      rows_cache_.rebuild(ref_, nall, neighbor->cutneighmax, 2);
      near_.forget(nall);
      cells_ncalls_ = list_epoch();
    }
    std::vector<int> &starts = starts_;
    starts.clear();
    for (size_t q = 0; q < ctag.size(); q++) {
      const auto &ta = ctag[q];
      const int a = ta.second;
      int len;
      const std::pair<tagint, int> *row =
          rows_cache_.row(a, len, [&](std::vector<std::pair<tagint, int>> &out) {
            build_row(a, out);
          });
      const int n0 = (int) neigh_.size();
      // a pair with another atom of C is taken from the lower tag's row:
      // the row and ctag both ascend in tag, so one forward search over
      // ctag[0..q) finds them (by tag, as inC() by copy: no per-atom array
      // read at a random place for every entry). It jumps by bisection
      // where much of ctag is left: a walk from ctag's start for every row
      // made an evaluation of a large C (final_kick()'s of every member,
      // with held forces) quadratic in |C|
      size_t p = 0;
      auto seek = [&](tagint tj) {
        if (q - p > 16)
          p = std::lower_bound(ctag.begin() + p, ctag.begin() + q,
                               std::make_pair(tj, std::numeric_limits<int>::min())) -
              ctag.begin();
        else
          while (p < q && ctag[p].first < tj) p++;
      };
      // the entries' atoms are all over memory: their label, stamp, force
      // and position rows (read here and by the styles' compute()) are
      // asked for ahead, so the misses overlap (HardSphere::prefetch_row())
      constexpr int AHEAD = HardSphere::PREFETCH_AHEAD;
      for (int k = 0; k < len; k++) {
        if (k + AHEAD < len) {
          const int jn = row[k + AHEAD].second & NEIGHMASK;
          if (label_) __builtin_prefetch(label_ + jn);
          __builtin_prefetch(&zeroed_[jn]);
          HardSphere::prefetch_row(atom->x[0], 3, jn);
          HardSphere::prefetch_row(fl_[0], 3, jn, true);
        }
        const tagint tj = row[k].first;
        const int raw = row[k].second;
        if (tj < ta.first) {
          seek(tj);
          if (p < q && ctag[p].first == tj) continue;    // from tj's row
        }
        if (left_out(a, raw & NEIGHMASK)) continue;
        neigh_.push_back(raw);
        const int pr[2] = {a, raw & NEIGHMASK};
        add_term(pr, 2, raw >> SBBITS & 3);
      }
      if ((int) neigh_.size() == n0) continue;
      ilist_.push_back(a);
      numneigh_[a] = (int) neigh_.size() - n0;
      starts.push_back(n0);
    }
    for (size_t k = 0; k < ilist_.size(); k++) firstneigh_[ilist_[k]] = neigh_.data() + starts[k];
    npair_terms += (double) nterm;
  } else if (L) {
    for (int a : marked) {
      if (a < (int) has_row_.size() && has_row_[a]) {
        const int *jl = L->firstneigh[a];
        const int nj = L->numneigh[a];
        bool whole = !only_cross;
        if (whole && ((label_ && label_[a] >= 0) || some_uncovered))
          for (int k = 0; k < nj && whole; k++) whole = !left_out(a, jl[k] & NEIGHMASK);
        if (whole) {
          if (!terms_only_) {
            ilist_.push_back(a);
            numneigh_[a] = nj;
            firstneigh_[a] = L->firstneigh[a];
          }
          for (int k = 0; k < nj; k++) {
            const int pr[2] = {a, jl[k] & NEIGHMASK};
            add_term(pr, 2, jl[k] >> SBBITS & 3);
          }
        } else
          // a row with some entries left out: rebuilt below from its kept ones
          for (int k = 0; k < nj; k++)
            if (!left_out(a, jl[k] & NEIGHMASK)) {
              if (terms_only_) {
                const int pr[2] = {a, jl[k] & NEIGHMASK};
                add_term(pr, 2, jl[k] >> SBBITS & 3);
              } else
                extra_.emplace_back(a, jl[k]);
            }
      }
      for (int p = pinv_off_[a]; p < pinv_off_[a + 1]; p++) {
        if (inC(pinv_row_[p]) || left_out(pinv_row_[p], a)) continue;
        if (terms_only_) {    // the term only, no restricted row
          const int pr[2] = {pinv_row_[p], pinv_val_[p] & NEIGHMASK};
          add_term(pr, 2, pinv_val_[p] >> SBBITS & 3);
        } else
          extra_.emplace_back(pinv_row_[p], pinv_val_[p]);
      }
    }
    // in the order std::sort gives the pairs (row, then raw j), which the
    // restricted lists and so the forces' round-off follow, by per-row
    // counts: one sort of all of them was O(E log E) for pcva's evaluations
    // of every owner's terms with held forces (C about half the atoms)
    HardSphere::sort_by_row(extra_, nall, xcount_, xrows_, xtmp_);
    std::vector<int> &starts = starts_;
    starts.clear();
    for (size_t k = 0; k < extra_.size(); k++) {
      const int i = extra_[k].first;
      if (k == 0 || extra_[k - 1].first != i) {
        ilist_.push_back(i);
        numneigh_[i] = 0;
        starts.push_back((int) neigh_.size());
      }
      numneigh_[i]++;
      neigh_.push_back(extra_[k].second);
      const int pr[2] = {i, extra_[k].second & NEIGHMASK};
      add_term(pr, 2, extra_[k].second >> SBBITS & 3);
    }
    // pointers into neigh_ only now that it no longer grows
    for (size_t k = 0, s = 0; k < extra_.size(); k++)
      if (k == 0 || extra_[k - 1].first != extra_[k].first)
        firstneigh_[extra_[k].first] = neigh_.data() + starts[s++];
    npair_terms += (double) nterm;
  }

  // ---- bonded: the entries with an atom of C (or an image)
  int **lists[4] = {neighbor->bondlist, neighbor->anglelist, neighbor->dihedrallist,
                    neighbor->improperlist};
  const int width[4] = {2, 3, 4, 4};
  bool present[4];
  presence(present);
  const int npair_t = nterm;
  npair_last_ = nterm;
  if (rows_ && topo_ && !only_cross) {
    // the caller's terms of C, each once: C's atoms in ID order, each
    // atom of a term as its copy in C or the image nearest the member's
    // (hs_local_forces.h)
    if (tstamp_.size() < topo_->terms.size()) tstamp_.resize(topo_->terms.size(), 0u);
    for (auto &R : topo_rows_) R.clear();
    for (const auto &ta : ctag) {
      auto it = topo_->of.find(ta.first);
      if (it == topo_->of.end()) continue;
      for (int ti : it->second) {
        if (tstamp_[ti] == epoch_) continue;
        tstamp_[ti] = epoch_;
        const Topology::Term &T = topo_->terms[ti];
        if (!present[T.kind]) continue;
        const int w = T.width();
        for (int k = 0; k < w; k++) {
          // (another member's copy in C may be a far image: the fold
          // brings the near one's force to it)
          int l = T.id[k] == ta.first ? ta.second : -1;
          if (l < 0) {
            const int m = atom->map(T.id[k]);
            if (m < 0)
              error->one(FLERR, "{}: atom {} of a bonded term of atom {} is not on rank {}: "
                         "the ghost cutoff is too small (comm_modify cutoff)", owner_, T.id[k],
                         ta.first, comm->me);
            l = domain->closest_image(ta.second, m);
          }
          topo_rows_[T.kind].push_back(l);
        }
        topo_rows_[T.kind].push_back(T.type);
      }
    }
    for (int b = 0; b < 4; b++) {
      Bonded &B = bonded_[b];
      B.sub.clear();
      std::vector<int> &R = topo_rows_[b];
      for (size_t r = 0; r < R.size(); r += width[b] + 1) {
        B.sub.push_back(R.data() + r);
        add_term(R.data() + r, width[b], R[r + width[b]]);
      }
      kind_end_[b] = nterm;
    }
  }
  for (int b = 0; b < 4; b++) {
    if (rows_ && topo_ && !only_cross) break;
    Bonded &B = bonded_[b];
    B.sub.clear();
    kind_end_[b] = nterm;
    if (!present[b] || only_cross) continue;
    for (int a : marked)
      for (int p = B.off[a]; p < B.off[a + 1]; p++) {
        const int r = B.rows[p];
        if (B.stamp[r] == epoch_) continue;    // a term with two atoms of C
        B.stamp[r] = epoch_;
        int *row = lists[b][r];
        B.sub.push_back(row);
        add_term(row, width[b], row[width[b]]);
      }
    kind_end_[b] = nterm;
  }
  nbonded_terms += (double) (nterm - npair_t);
  if (terms_only_) return;

  // rows: every image folds into its copy in C, other atoms' into
  // atom->map()'s copy (zeroed too)
  if (rows_) {
    const tagint *tag = atom->tag;
    const size_t nz = zero_list_.size();
    for (size_t k = 0; k < nz; k++) {
      const int j = zero_list_[k];
      // (C's copies are stamped: only they need the search by ID; an owned
      // copy of another atom is atom->map()'s own, which maps an ID to its
      // lowest index: no read of the map at a random place)
      const int to = inC(j) ? copy_in_c(tag[j]) : j < nlocal ? j : atom->map(tag[j]);
      if (to != j) {
        fold_.push_back(j);
        fold_.push_back(to);
      }
    }
    for (size_t k = 1; k < fold_.size(); k += 2) zero(fold_[k]);
    for (int k = 0; k < nc; k++) zero(c[k]);
  } else if (nprocs == 1) {
    // owners of the ghosts in the terms receive their forces: zeroed too
    const size_t nz = zero_list_.size();
    for (size_t k = 0; k < nz; k++)
      if (zero_list_[k] >= nlocal) zero(owner_of(zero_list_[k]));
    for (int k = 0; k < nc; k++) zero(c[k]);
  }

  run_styles(L, present);
  last_ncalls_ = list_epoch();
  last_nc_ = nc;
  ncalls += 1.0;
}

/* ----------------------------------------------------------------------
   the style of bonded kind b (0 bond, 1 angle, 2 dihedral, 3 improper)
   computed on the list (n, rows), swapped into Neighbor's for the call
------------------------------------------------------------------------- */

void HSLocalForces::compute_kind_on(int b, int n, int **rows, int ef)
{
  int *nlist[4] = {&neighbor->nbondlist, &neighbor->nanglelist, &neighbor->ndihedrallist,
                   &neighbor->nimproperlist};
  int ***plist[4] = {&neighbor->bondlist, &neighbor->anglelist, &neighbor->dihedrallist,
                     &neighbor->improperlist};
  const int n0 = *nlist[b];
  int **l0 = *plist[b];
  *nlist[b] = n;
  *plist[b] = rows;
  if (b == 0) force->bond->compute(ef, 0);
  if (b == 1) force->angle->compute(ef, 0);
  if (b == 2) force->dihedral->compute(ef, 0);
  if (b == 3) force->improper->compute(ef, 0);
  *nlist[b] = n0;
  *plist[b] = l0;
}

/* ----------------------------------------------------------------------
   one bonded term by its style's compute() (hs_local_forces.h)
------------------------------------------------------------------------- */

double HSLocalForces::bonded_term(int b, const int *a, int type, double **x, double **f)
{
  const int width = b == 0 ? 2 : b == 1 ? 3 : 4;
  int row[5];
  for (int k = 0; k < width; k++) row[k] = a[k];
  row[width] = type;
  int *one[1] = {row};
  double *energy = nullptr, *virial = nullptr;
  if (b == 0 && force->bond) energy = &force->bond->energy, virial = force->bond->virial;
  if (b == 1 && force->angle) energy = &force->angle->energy, virial = force->angle->virial;
  if (b == 2 && force->dihedral)
    energy = &force->dihedral->energy, virial = force->dihedral->virial;
  if (b == 3 && force->improper)
    energy = &force->improper->energy, virial = force->improper->virial;
  if (!energy)
    error->one(FLERR, "{}: internal error: a bonded term of kind {} without its style", owner_, b);
  const double e_saved = *energy;
  double v_saved[6];
  for (int k = 0; k < 6; k++) v_saved[k] = virial[k];
  // (a style may tally a part into the pair style's through Pair::ev_tally(),
  // e.g. dihedral charmm's 1-4 terms: that part is the term's too. That
  // tally follows the pair style's own flags, those of its last compute():
  // set to the global energy alone for the call, so that the part is
  // counted and no per-atom array of the pair style is written)
  Pair *pair = force->pair;
  double pv_saved[6] = {0, 0, 0, 0, 0, 0}, pe_saved[2] = {0.0, 0.0};
  int pflags[7] = {0, 0, 0, 0, 0, 0, 0};
  int *pf[7] = {nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr};
  if (pair) {
    pe_saved[0] = pair->eng_vdwl;
    pe_saved[1] = pair->eng_coul;
    for (int k = 0; k < 6; k++) pv_saved[k] = pair->virial[k];
    int *flags[7] = {&pair->eflag_either, &pair->eflag_global, &pair->eflag_atom,
                     &pair->vflag_either, &pair->vflag_global, &pair->vflag_atom,
                     &pair->cvflag_atom};
    for (int k = 0; k < 7; k++) {
      pf[k] = flags[k];
      pflags[k] = *pf[k];
      *pf[k] = k < 2 ? 1 : 0;
    }
  }
  double **x_saved = atom->x, **f_saved = atom->f;
  atom->x = x;
  atom->f = f;
  compute_kind_on(b, 1, one, 1);
  double e = *energy;
  if (pair) {
    e += (pair->eng_vdwl - pe_saved[0]) + (pair->eng_coul - pe_saved[1]);
    pair->eng_vdwl = pe_saved[0];
    pair->eng_coul = pe_saved[1];
    for (int k = 0; k < 6; k++) pair->virial[k] = pv_saved[k];
    for (int k = 0; k < 7; k++) *pf[k] = pflags[k];
  }
  atom->x = x_saved;
  atom->f = f_saved;
  *energy = e_saved;
  for (int k = 0; k < 6; k++) virial[k] = v_saved[k];
  return e;
}

/* ----------------------------------------------------------------------
   this rank's topology records for the atoms ids (hs_local_forces.h)
------------------------------------------------------------------------- */

void HSLocalForces::collect_topology(const std::vector<tagint> &ids, std::vector<double> &out)
{
  if (atom->molecular == Atom::ATOMIC) return;
  build_index(false);
  const tagint *tag = atom->tag;
  const int nlocal = atom->nlocal;
  bool present[4];
  presence(present);
  int **lists[4] = {neighbor->bondlist, neighbor->anglelist, neighbor->dihedrallist,
                    neighbor->improperlist};
  const int width[4] = {2, 3, 4, 4};
  next_epoch();
  for (tagint t : ids) {
    const int o = atom->map(t);
    if (o >= 0 && o < nlocal && atom->nspecial) {
      const int *ns = atom->nspecial[o];
      out.push_back(4.0);
      out.push_back((double) t);
      for (int k = 0; k < 3; k++) out.push_back((double) ns[k]);
      for (int k = 0; k < ns[2]; k++) out.push_back((double) atom->special[o][k]);
    }
    for (int l = o; l >= 0; l = atom->sametag[l])
      for (int b = 0; b < 4; b++) {
        if (!present[b]) continue;
        Bonded &B = bonded_[b];
        for (int p = B.off[l]; p < B.off[l + 1]; p++) {
          const int r = B.rows[p];
          if (B.stamp[r] == epoch_) continue;
          B.stamp[r] = epoch_;
          const int *row = lists[b][r];
          tagint id[4] = {0, 0, 0, 0};
          for (int k = 0; k < width[b]; k++) id[k] = tag[row[k]];
          if (b == 0 && id[1] < id[0]) std::swap(id[0], id[1]);
          out.push_back((double) b);
          out.push_back((double) row[width[b]]);
          for (int k = 0; k < 4; k++) out.push_back((double) id[k]);
        }
      }
  }
}

/* ----------------------------------------------------------------------
   the terms of C only (term_local(), npair_last()), without
   building the restricted lists or evaluating them
------------------------------------------------------------------------- */

void HSLocalForces::terms(const int *c, int nc)
{
  terms_only_ = true;
  compute(c, nc);
  terms_only_ = false;
  last_nc_ = -1;    // no restricted lists to recompute
}

/* ----------------------------------------------------------------------
   -grad V_C again for the C of the last compute(), at the current x: the
   restricted lists are reused (one rank, no list build since)
------------------------------------------------------------------------- */

void HSLocalForces::recompute()
{
  if ((comm->nprocs > 1 && !rows_) || last_ncalls_ != list_epoch() || last_nc_ < 0)
    error->one(FLERR, "{}: local forces recomputed without a compute() on this list", owner_);
  for (int j : zero_list_) fl_[j][0] = fl_[j][1] = fl_[j][2] = 0.0;
  bool present[4];
  presence(present);
  NeighList *L = pair_list();
  run_styles(L, present, false);
  ncalls += 1.0;
}

void HSLocalForces::save(Snapshot &sn) const
{
  NeighList *L = pair_list();
  sn.ilist = ilist_;
  sn.counts.resize(ilist_.size());
  sn.offs.resize(ilist_.size());
  for (size_t k = 0; k < ilist_.size(); k++) {
    const int i = ilist_[k];
    sn.counts[k] = numneigh_[i];
    // rows mode: every row is in neigh_ (and i may be a ghost, which the
    // pair style's list has no entry for)
    sn.offs[k] = (!rows_ && L && firstneigh_[i] == L->firstneigh[i])
        ? -1
        : (int) (firstneigh_[i] - neigh_.data());
  }
  sn.neigh = neigh_;
  for (int b = 0; b < 4; b++) {
    sn.own[b].clear();
    sn.sub[b] = bonded_[b].sub;
    // rows from a topology live in topo_rows_, which the next call reuses
    if (rows_ && topo_ && !bonded_[b].sub.empty()) {
      sn.own[b] = topo_rows_[b];
      sn.sub[b].clear();
    }
  }
  sn.zero_list = zero_list_;
  sn.touched = touched_owned_;
  sn.ncalls = last_ncalls_;
  sn.rows = rows_;
  sn.fold = fold_;
}

void HSLocalForces::recompute(const Snapshot &sn)
{
  restore(sn);
  recompute();
}

void HSLocalForces::restore(const Snapshot &sn)
{
  if ((comm->nprocs > 1 && !sn.rows) || sn.ncalls != list_epoch())
    error->one(FLERR, "{}: local forces restored from a snapshot of another list", owner_);
  rows_ = sn.rows;
  fold_ = sn.fold;
  NeighList *L = pair_list();
  ilist_ = sn.ilist;
  neigh_ = sn.neigh;
  for (size_t k = 0; k < ilist_.size(); k++) {
    const int i = ilist_[k];
    numneigh_[i] = sn.counts[k];
    firstneigh_[i] = (sn.offs[k] < 0) ? L->firstneigh[i] : neigh_.data() + sn.offs[k];
  }
  const int width[4] = {2, 3, 4, 4};
  for (int b = 0; b < 4; b++) {
    bonded_[b].sub = sn.sub[b];
    for (size_t r = 0; r < sn.own[b].size(); r += width[b] + 1)
      bonded_[b].sub.push_back(const_cast<int *>(sn.own[b].data()) + r);
  }
  zero_list_ = sn.zero_list;
  touched_owned_ = sn.touched;
  last_ncalls_ = sn.ncalls;
  last_nc_ = 1;
}

/* ----------------------------------------------------------------------
   the pair style's forces (eflag: and its energy tally) on the restricted
   list L (swapped in), into atom->f, whose rows in zero_list_ are zero
   (every row a term writes is there): compute(eflag, 0), or lj/cut's kernel
   (hs_ljcut.h) once it gave the same bits as compute() in this run (with
   and without the energy: each checked on its own first use)
------------------------------------------------------------------------- */

void HSLocalForces::pair_forces(NeighList *L, int eflag)
{
  Pair *pair = force->pair;
  int &state = eflag ? lj_estate_ : lj_state_;
  if (!lj_.coef || state == 0) {
    pair->compute(eflag, 0);
    return;
  }
  const bool newton = force->newton_pair != 0;
  double eng = 0.0;
  if (eflag) {
    eng = HardSphere::lj_cut_forces<NEIGHMASK, SBBITS, true>(
        L->inum, L->ilist, L->numneigh, L->firstneigh, atom->x[0], atom->f[0], atom->type,
        force->special_lj, atom->nlocal, newton, pair->cutsq, lj_);
    // (as compute(1, 0) leaves them: its ev_setup() zeroes both, ev_tally()
    // adds a zero Coulomb energy)
    pair->eng_vdwl = eng;
    pair->eng_coul = 0.0;
  } else
    HardSphere::lj_cut_forces<NEIGHMASK, SBBITS>(
        L->inum, L->ilist, L->numneigh, L->firstneigh, atom->x[0], atom->f[0], atom->type,
        force->special_lj, atom->nlocal, newton, pair->cutsq, lj_);
  if (state == 1) return;
  // the first evaluation of the run: compute() again from the same zero
  // rows; the kernel stays only if every row (and the energy) agrees to
  // the bit
  double **f = atom->f;
  lj_check_.resize(3 * zero_list_.size());
  for (size_t k = 0; k < zero_list_.size(); k++)
    for (int d = 0; d < 3; d++) {
      lj_check_[3 * k + d] = f[zero_list_[k]][d];
      f[zero_list_[k]][d] = 0.0;
    }
  pair->compute(eflag, 0);
  bool same = true, forces = false;
  if (eflag) {
    const double zero = 0.0;
    same = memcmp(&eng, &pair->eng_vdwl, sizeof(double)) == 0 &&
        memcmp(&zero, &pair->eng_coul, sizeof(double)) == 0;
  }
  for (size_t k = 0; k < zero_list_.size() && same; k++) {
    const double *fk = f[zero_list_[k]];
    same = memcmp(&lj_check_[3 * k], fk, 3 * sizeof(double)) == 0;
    forces = forces || fk[0] != 0.0 || fk[1] != 0.0 || fk[2] != 0.0;
  }
  // (decided on an evaluation with forces; else asked again next time)
  if (!same) state = 0;
  else if (forces) state = 1;
}

/* ----------------------------------------------------------------------
   the styles' own compute() on the restricted lists, then the ghosts'
   forces to their owners
------------------------------------------------------------------------- */

void HSLocalForces::run_styles(NeighList *L, const bool present[4], bool first)
{
  const int nlocal = atom->nlocal;
  const int nall = nlocal + atom->nghost;
  const int nprocs = comm->nprocs;
  Tally tal[5];
  auto save = [](Tally &t, double e1, double e2, const double *v) {
    t.e1 = e1;
    t.e2 = e2;
    for (int k = 0; k < 6; k++) t.v[k] = v[k];
  };
  auto put = [](const Tally &t, double &e1, double &e2, double *v) {
    e1 = t.e1;
    e2 = t.e2;
    for (int k = 0; k < 6; k++) v[k] = t.v[k];
  };
  double d1 = 0.0, d2 = 0.0;
  const int ef = keep_energy_ ? 1 : 0;
  if (force->pair) save(tal[0], force->pair->eng_vdwl, force->pair->eng_coul, force->pair->virial);
  if (force->bond) save(tal[1], force->bond->energy, d1, force->bond->virial);
  if (force->angle) save(tal[2], force->angle->energy, d1, force->angle->virial);
  if (force->dihedral) save(tal[3], force->dihedral->energy, d1, force->dihedral->virial);
  if (force->improper) save(tal[4], force->improper->energy, d1, force->improper->virial);

  // single rank: the styles write into fl_ through a swapped atom->f.
  // Several ranks: comm->reverse_comm() packs through the atom style's own
  // cached f pointer (AtomVec::f), not atom->f, so the evaluation runs in
  // atom->f itself, saved to fl_ before and swapped back after (O(atoms);
  // a reverse communication of only the touched ghosts needs a Fix's
  // pack_reverse_comm(): the engine's job)
  double **f_saved = atom->f;
  const size_t nbytes = 3 * sizeof(double) * nall;
  const bool swap_f = nprocs == 1 || rows_;    // rows: no communication
  if (swap_f)
    atom->f = fl_;
  else if (nall) {
    memcpy(&fl_[0][0], &atom->f[0][0], nbytes);
    memset(&atom->f[0][0], 0, nbytes);
  }
  // torques (atom style sphere, ...): the fix moves the spheres' centres
  // only, and LAMMPS' torques of the step must stay as LAMMPS computed them.
  // A style that writes torques writes the restricted terms' into tq_ (a
  // pointer swap; swap_f), or, where reverse_comm() sums the atom style's
  // torque array too, into atom->torque zeroed and restored after
  // (tq_ is sized with fl_ by grow(), which evaluate() called)
  double **t_saved = atom->torque;
  const bool torque = atom->torque_flag && t_saved && nall;
  if (torque && !tq_)
    error->one(FLERR, "{}: internal error: no torque buffer for {} atoms", owner_, nall);
  if (torque) {
    if (swap_f)
      atom->torque = tq_;
    else {
      memcpy(&tq_[0][0], &t_saved[0][0], nbytes);
      memset(&t_saved[0][0], 0, nbytes);
    }
  }
  // rows list each term once, a ghost's included (member pairs from the
  // lower tag's row): every copy takes its force as with newton_pair on,
  // whatever the input says (off: the styles would leave the ghosts' out)
  const int newton_pair = force->newton_pair;
  if (rows_) force->newton_pair = 1;
  if (L && hybrid_)
    hybrid_forces(ef);
  else if (L) {
    const int inum0 = L->inum;
    int *ilist0 = L->ilist, *numneigh0 = L->numneigh;
    int **firstneigh0 = L->firstneigh;
    L->inum = (int) ilist_.size();
    L->ilist = ilist_.data();
    L->numneigh = numneigh_;
    L->firstneigh = firstneigh_;
    pair_forces(L, ef);
    L->inum = inum0;
    L->ilist = ilist0;
    L->numneigh = numneigh0;
    L->firstneigh = firstneigh0;
  }
  // a topology's terms are listed once: every copy takes its force
  const int newton_bond = force->newton_bond;
  if (rows_ && topo_) force->newton_bond = 1;
  for (int b = 0; b < 4; b++)
    if (present[b]) compute_kind_on(b, (int) bonded_[b].sub.size(), bonded_[b].sub.data(), ef);
  force->newton_bond = newton_bond;
  force->newton_pair = newton_pair;
  if (swap_f)
    atom->f = f_saved;
  else if (nall) {
    // (reverse_comm() also sums the atom style's torque, restored below;
    // other per-atom force arrays are refused by init())
    if (force->newton_pair || force->newton_bond) comm->reverse_comm();
    for (int i = 0; i < nall; i++)
      for (int k = 0; k < 3; k++) std::swap(fl_[i][k], atom->f[i][k]);
  }
  if (torque) {
    if (swap_f)
      atom->torque = t_saved;
    else
      memcpy(&t_saved[0][0], &tq_[0][0], nbytes);
  }

  if (keep_energy_) {
    energy_ = 0.0;
    if (L) energy_ += force->pair->eng_vdwl + force->pair->eng_coul;
    if (present[0]) energy_ += force->bond->energy;
    if (present[1]) energy_ += force->angle->energy;
    if (present[2]) energy_ += force->dihedral->energy;
    if (present[3]) energy_ += force->improper->energy;
  }
  if (force->pair) put(tal[0], force->pair->eng_vdwl, force->pair->eng_coul, force->pair->virial);
  if (force->bond) put(tal[1], force->bond->energy, d2, force->bond->virial);
  if (force->angle) put(tal[2], force->angle->energy, d2, force->angle->virial);
  if (force->dihedral) put(tal[3], force->dihedral->energy, d2, force->dihedral->virial);
  if (force->improper) put(tal[4], force->improper->energy, d2, force->improper->virial);

  // ---- rows: images into their copies (C's, or atom->map()'s)
  if (rows_) {
    for (size_t k = 0; k < fold_.size(); k += 2)
      for (int d = 0; d < 3; d++) fl_[fold_[k + 1]][d] += fl_[fold_[k]][d];
    if (!first) return;
    touched_owned_.clear();
    // (the fold sources marked and unmarked again: no pass over all atoms)
    std::vector<char> &src = fold_src_;
    if ((int) src.size() < nall) src.resize(nall, 0);
    for (size_t k = 0; k < fold_.size(); k += 2) src[fold_[k]] = 1;
    for (int j : zero_list_)
      if (!src[j]) touched_owned_.push_back(j);
    for (size_t k = 0; k < fold_.size(); k += 2) src[fold_[k]] = 0;
    return;
  }
  // ---- ghosts' forces to their owners, the touched owned atoms
  if (!first) {    // recompute(): same atoms as before
    for (int j : zero_list_)
      if (j >= nlocal) {
        const int o = atom->map(atom->tag[j]);
        for (int k = 0; k < 3; k++) fl_[o][k] += fl_[j][k];
      }
    return;
  }
  touched_owned_.clear();
  if (nprocs == 1) {
    for (int j : zero_list_)
      if (j >= nlocal) {
        const int o = atom->map(atom->tag[j]);    // one rank: the owned copy
        for (int k = 0; k < 3; k++) fl_[o][k] += fl_[j][k];
      }
    for (int j : zero_list_)
      if (j < nlocal) touched_owned_.push_back(j);
  } else {
    for (int i = 0; i < nlocal; i++)
      if (zeroed_[i] == epoch_ || fl_[i][0] != 0.0 || fl_[i][1] != 0.0 || fl_[i][2] != 0.0)
        touched_owned_.push_back(i);
  }
  std::sort(touched_owned_.begin(), touched_owned_.end());
}
