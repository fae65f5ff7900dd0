/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: forces of V_C, the interaction terms that involve a
   given set C of atoms, through LAMMPS' own styles (issue 10, the local
   sub-stepping engine: Phi_C needs -grad V_C at every sub-step, at a cost
   of O(the terms of C), not of a force evaluation of the whole system).

   The styles' own compute() runs on sub-lists that hold only the terms of C:
   pair: the rows of the neighbor list restricted to pairs (i,j) with i or j
   (or an image of it) in C; bond/angle/dihedral/improper: the entries of
   neighbor->bondlist, anglelist, ... with an atom (or an image) in C. The
   list pointers (pair->list's inum/ilist/numneigh/firstneigh,
   neighbor->bondlist/nbondlist, ...) and atom->f are swapped for the call
   and restored after it, as are the styles' energy and virial tallies, so
   the state of LAMMPS (f, tallies, lists) is bit-identical afterwards.
   Because every term that acts on an atom of C involves it, the force on an
   atom of C equals its force in a full evaluation; a partner (an atom that
   shares a term with C) receives only the part of its force from V_C.

   Exact only for styles whose energy is a sum of terms over the list
   entries: unrestrictable() names the others (many-body pair styles, pair
   styles with ghost neighbours, pair hybrid/molecular, accelerator
   variants with thread-private force arrays); the engine then
   falls back to `global`. Pair hybrid (and hybrid/overlay, hybrid/scaled):
   the restricted rows are split among the sub-styles' own lists by the
   type skips LAMMPS built them with, and hybrid's compute() runs on those.
   Fixes' forces and kspace are not part of V_C here: the engine decides
   about them (it holds kspace: the real-space part of coul/long & co. is
   an ordinary pair style).

   Version notes: compiled and tested against LAMMPS 29Sep2021 update 2
   (Debian 20220106)
   headers only; the members used are believed unchanged in 4Feb2025 (not
   compiled against it here):
   Pair::list, NeighList::{inum,ilist,numneigh,firstneigh}, Neighbor::
   {bondlist,nbondlist,...,improperlist,nimproperlist,ncalls}, Atom::{map(),
   sametag}, NEIGHMASK, the styles' tallies (Pair::eng_vdwl, eng_coul,
   virial; Bond/Angle/...::energy, virial); for pair hybrid Neighbor::
   {lists,nlist,requests,old_requests}, NeighList::{requestor,iskip,ijskip,
   listskip}, Force::pair_match_ptr() (a request's requestor through
   hs_compat.h). No neighbor request is made (the pair style's own lists
   are used).

   MPI (compute() is collective): the tags of C are gathered on every rank
   (MPI_Allgatherv, O(|C|)), each rank restricts its own lists to terms with
   an owned or ghost copy of an atom of C. Single rank: the styles write
   into a swapped atom->f and the ghosts' forces are folded into their owners
   through atom->map(), O(terms). Several ranks: comm->reverse_comm() packs
   through AtomVec's cached f pointer, not atom->f, so the evaluation runs in
   atom->f itself (saved and restored: O(atoms) per call) and the ghosts'
   forces go back by a full reverse communication (O(ghosts)). A local
   engine wants instead a reverse communication of only the touched ghosts
   through its Fix's pack_reverse_comm(). Tested on 1-4 ranks
   (unittest/mpi/test_mpi_local_forces.sh).
------------------------------------------------------------------------- */

#ifndef LMP_HS_LOCAL_FORCES_H
#define LMP_HS_LOCAL_FORCES_H

#include "hs_cells.h"
#include "hs_ljcut.h"
#include "pointers.h"

#include <array>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

namespace LAMMPS_NS {

class HSLocalForces : protected Pointers {
 public:
  // owner: for error messages, e.g. "fix hardsphere/cva"
  HSLocalForces(class LAMMPS *, const std::string &owner);
  ~HSLocalForces() override;

  // call from the owner's init(): checks the styles and the atom map
  void init();
  double memory_usage() const;    // bytes of its per-copy arrays and rows
  // "" when every contribution can be restricted exactly, else why not
  // (the styles named); valid after init()
  const std::string &unrestrictable() const { return why_; }
  bool exact() const { return why_.empty(); }

  // -grad V_C at the current x (ghosts current), C = c[0..nc) (owned local
  // indices; collective: every rank passes its own part of C). Afterwards
  // forces()[i] holds it for every owned atom i in touched() (C and the
  // partners); other entries are unspecified. atom->x, atom->f, the lists
  // and the styles' tallies are left as they were.
  // labels over the local indices (owned and ghost; -1: none), or nullptr:
  // with labels, a pair term of two atoms with different labels >= 0 is a
  // "cross" term. NORMAL: compute() leaves cross terms out; CROSS: it keeps
  // only them (pair terms; C should hold every labelled atom). Bonded terms
  // are never left out. The caller keeps the array alive and unchanged
  // while a snapshot of it is in use.
  enum Mode { NORMAL = 0, CROSS = 1 };
  void set_labels(const int *label, Mode mode = NORMAL)
  {
    label_ = label;
    mode_ = mode;
  }
  // record_terms false: term_local() etc. are not filled (faster)
  void compute(const int *c, int nc, bool record_terms = true);
  double **forces() const { return fl_; }
  // while set, each evaluation also sums the styles' own energy tallies of
  // the restricted terms (eflag 1 for the call; the tallies are restored
  // after it): V_C at the current x, energy units. This rank's terms only
  // (compute_rows(), or compute() on one rank)
  void keep_energy(bool on) { keep_energy_ = on; }
  // lj/cut's forces by hs_ljcut.h's kernel instead of the style's compute()
  // (coef nullptr: compute(); init() forgets the table). The first
  // evaluation with forces after init() computes both and keeps the kernel
  // for the run only if every force agrees bit for bit; lj_kernel(): 1 in
  // use, 0 refused this run, -1 not tried yet or no table. The same, apart,
  // for the evaluations that also sum the energy (keep_energy(); the energy
  // tally must agree too): lj_energy_kernel()
  void set_lj_table(const HardSphere::LJCutTable &t) { lj_ = t; }
  int lj_kernel() const { return lj_.coef ? lj_state_ : -1; }
  int lj_energy_kernel() const { return lj_.coef ? lj_estate_ : -1; }
  double energy() const { return energy_; }
  // the same again at the current x, for the C of the last compute(), with
  // its restricted lists (one rank; no list build since): O(its terms)
  // without the bookkeeping of compute()
  void recompute();
  // only the terms of C (term_local(), npair_last()): no
  // lists are built, no forces evaluated (invalidates recompute())
  void terms(const int *c, int nc);
  // the restricted lists of the last compute(), kept by the caller to
  // evaluate the same terms again later in the step without rebuilding them
  // (one rank; no list build in between)
  struct Snapshot {
    std::vector<int> ilist, counts, offs, neigh, zero_list, touched, fold;
    bool rows = false;
    std::vector<int *> sub[4];
    std::vector<int> own[4];    // rows mode with a topology: the rows themselves
    int64_t ncalls = -1;
  };
  void save(Snapshot &) const;
  void recompute(const Snapshot &);
  // a snapshot's lists made the current ones, nothing evaluated: the
  // caller holds their forces at these positions already (recompute()
  // then works on them); forces() and energy() are not theirs until it
  void restore(const Snapshot &);
  const std::vector<int> &touched() const { return touched_owned_; }

  // ---- rank-local rows (issue 20: the local engine on several ranks)
  // compute() restricts the pair style's own half list, which on several
  // ranks holds a pair of an owned atom and a ghost on one of the two ranks
  // only and has no row for a ghost; so it gathers C on every rank and
  // reverse-communicates (a collective per call). compute_rows() needs
  // neither: C = c[0..nc) are any local copies (owned or ghost; the local
  // engine takes each member's copy nearest the cluster's key), and the pair
  // terms come from on-demand rows of every local atom within the neighbor
  // cutoff (cutforce + skin) of each member, found in a cell list of all
  // local atoms (hs_cells.h, built once per list build). A pair of two
  // members (by tag, whichever images) is taken once, from the lower tag's
  // row; rows run in tag order and each row's entries in tag order, so two
  // ranks sum V_C's forces in the same order. Every image of an atom of C
  // folds into its copy in C, every other atom's images into atom->map()'s
  // copy (one rank: the owned copy); touched() then holds those copies
  // (in the order the rows first reach them, not sorted: the engine reads
  // it atom by atom, and a sort per evaluation was ~1 % of a cva step),
  // forces() their forces. Terms of an atom with its own image are left
  // out: their forces on the atom cancel. Bonded terms as compute(), or
  // from a topology (set_topology(), below). recompute() and
  // save()/recompute(snapshot) work as for compute().
  // "" if compute_rows() can be used with the styles defined, else why not
  std::string rows_unsupported() const;
  // the positions of all local atoms (owned and ghost) at the current
  // neighbor list build: a row holds the atoms within the neighbor cutoff
  // there (LAMMPS' own criterion: valid while atoms move less than skin/2),
  // and is kept until the next build. Call after every list build, before
  // compute_rows(); the array must stay unchanged until the next build.
  void set_reference(double **xb);
  // record_terms: term_local() etc. list the terms evaluated (each once)
  void compute_rows(const int *c, int nc, bool record_terms = false);
  // the cross terms of C = c[0..nc) straight from C's rows (built since
  // the list build): with labels set, the pair terms of a copy of C with a
  // copy labelled otherwise (>= 0), what compute_rows() in mode CROSS gives
  // C's copies, bit for bit, without restricted lists, stamps or folds:
  // f[k] is c[k]'s force, labels gets the other label of every such entry
  // (within the cutoff or not: the atoms compute_rows() would touch), and
  // energy() is theirs with keep_energy(). Only where lj/cut's kernel is in
  // use (C's members' terms in row order from a zero force); false, with
  // nothing done, elsewhere (the caller evaluates). A cluster's cross forces
  // are asked for ~1.6 times a step, most of them zero: 23 % of a cva
  // step's restricted evaluations (bench/scaling/README.md)
  bool cross_rows(const int *c, int nc, double (*f)[3], std::vector<int> &labels);
  // contact neighbours from the rows' own scan (the local engine's contact
  // candidates, HSLocalEngine::crow(), asked for right after a member's
  // row): while set, building the row of a also lists every copy j of an
  // atom of groupbit within cut of a at the reference positions (not a, not
  // its images; bonded partners the lists leave out included), in (ID,
  // index) order. near_row(a) gives that list until the next list build;
  // nullptr if a's row was not built since, or built while cut exceeded
  // the neighbor cutoff (the scan did not reach it)
  void set_near(double cut, int groupbit)
  {
    near_cut2_ = cut * cut;
    near_groupbit_ = groupbit;
  }
  const int *near_row(int a, int &n) const
  {
    if (near_cut2_ < 0.0 || cells_ncalls_ != list_epoch()) return nullptr;
    return near_.built(a, n);
  }

  // ---- molecular systems in rows mode (issue 20): a ghost carries no
  // special neighbours, and a rank's bonded lists hold only the terms it
  // computes (a member run on a ghost copy has terms on other ranks). The
  // caller gathers, by atom ID, the special lists and bonded terms of the
  // atoms it will put in C (collect_topology() on every rank, then
  // everyone's records merged) and sets them here; compute_rows() then
  // takes C's bonded terms from it (each once, in C's ID order, each atom
  // as its copy in C or the image nearest the member's copy) and special
  // bits from it. The terms are evaluated with newton_bond on (every copy
  // gets its force; the fold sums images), so each must be listed once.
  struct Topology {
    struct Term {
      int kind = 0, type = 0;    // kind: 0 bond, 1 angle, 2 dihedral, 3 improper
      tagint id[4] = {0, 0, 0, 0};
      int width() const { return kind == 0 ? 2 : kind == 1 ? 3 : 4; }    // atoms in it
    };
    std::vector<Term> terms;
    std::unordered_map<tagint, std::vector<int>> of;    // atom ID -> its terms
    // atom ID -> {n12, n13, n14 (cumulative, as atom->nspecial), IDs...}
    std::unordered_map<tagint, std::vector<tagint>> special;
    void clear()
    {
      terms.clear();
      of.clear();
      special.clear();
    }
  };
  void set_topology(const Topology *t) { topo_ = t; }
  // this rank's records for the atoms ids: every bonded term of its lists
  // with one of them (a bond's IDs ascending: newton_bond off lists it on
  // both atoms' ranks in either order), and the special lists of those it
  // owns. Appended to out as doubles: {kind 0-3, type, 4 IDs} per term,
  // {4, ID, n12, n13, n14, IDs...} per special list
  void collect_topology(const std::vector<tagint> &ids, std::vector<double> &out);

  // the terms of V_C of the last compute() as their atoms' local indices
  // (images as they are): term t is term_local()[off[t] .. off[t+1]); and
  // how many of them (the first ones) are pair terms
  const std::vector<int> &term_offsets() const { return term_off_; }
  const std::vector<int> &term_local() const { return term_local_; }
  // the same three arrays handed over (swapped with the caller's, whose old
  // contents this object then holds as scratch: the accessors above are
  // empty until the next compute() that records terms); no copy of a
  // whole step's terms (a pcva step lists every member's)
  void take_terms(std::vector<int> &local, std::vector<int> &off, std::vector<int> &extra)
  {
    local.swap(term_local_);
    off.swap(term_off_);
    extra.swap(term_extra_);
    term_local_.clear();
    term_off_.assign(1, 0);
    term_extra_.clear();
  }
  int npair_last() const { return npair_last_; }
  // the bonded terms come kind by kind after the pair terms: those of kind
  // b (0 bond, 1 angle, 2 dihedral, 3 improper) end at term kind_end(b)
  int kind_end(int b) const { return kind_end_[b]; }
  // one bonded term of kind b (1-3, or 0 for a bond style without single())
  // with the atoms a[0 .. width) (local copies) and type, by its style's own
  // compute() on a list of that term alone, at positions x (rows of those
  // copies; the style reads no other) with its forces added into f (rows of
  // those copies, zeroed by the caller; with newton_bond off the style adds
  // only to owned copies, as LAMMPS does). Returns the style's energy tally
  // of it (newton_bond off: the owned copies' share, as LAMMPS tallies it).
  // atom->x, atom->f, the lists and the style's tallies are left as they
  // were. pcva's local projection (hs_local_modified.cpp) differentiates
  // such terms by it
  double bonded_term(int b, const int *a, int type, double **x, double **f);
  // per term: a pair's special index (j >> SBBITS & 3), a bonded term's type
  const std::vector<int> &term_extra() const { return term_extra_; }

  // counters: calls, and pair / bonded terms evaluated, since construction
  double ncalls = 0, npair_terms = 0, nbonded_terms = 0;

 private:
  std::string owner_, why_;
  int initialized_ = 0;

  // stamps over nlocal + nghost
  uint32_t epoch_ = 0;
  std::vector<uint32_t> in_c_, zeroed_;
  bool inC(int i) const { return in_c_[i] == epoch_; }
  void next_epoch();    // a new epoch_ for every stamp array kept with it

  // inverse indices, rebuilt when the lists change (list_epoch())
  int64_t built_ncalls_ = -1;
  int built_nall_ = -1;
  class NeighList *built_list_ = nullptr;
  std::vector<int> pinv_off_, pinv_row_, pinv_val_;    // j -> (row i, raw j entry)
  std::vector<char> has_row_;
  struct Bonded {
    std::vector<int> off, rows;    // atom -> rows of the list
    std::vector<uint32_t> stamp;   // row already in sub in this call
    std::vector<int *> sub;        // restricted list: row pointers
  } bonded_[4];                    // bond, angle, dihedral, improper
  bool pair_index_ = false;    // pinv_* and has_row_ built for built_ncalls_
  void build_index(bool pair);
  void build_bonded_index();
  void presence(bool present[4]) const;

  // restricted pair list storage
  std::vector<int> ilist_, neigh_;
  std::vector<std::pair<int, int>> extra_;    // (row i, raw j) for rows i not in C
  // HardSphere::sort_by_row()'s per-row counts (kept zero between calls),
  // rows present and scratch copy, for extra_
  std::vector<int> xcount_, xrows_;
  std::vector<std::pair<int, int>> xtmp_;
  int nmax_ = 0;
  int *numneigh_ = nullptr;
  int **firstneigh_ = nullptr;
  double **fl_ = nullptr;
  // atom styles with torque (sphere): what a style writes there during a
  // restricted evaluation (run_styles())
  double **tq_ = nullptr;
  bool keep_energy_ = false;
  HardSphere::LJCutTable lj_;
  int lj_state_ = -1, lj_estate_ = -1;
  std::vector<double> lj_check_;
  void pair_forces(class NeighList *L, int eflag);
  double energy_ = 0.0;

  std::vector<int> zero_list_, touched_owned_, term_off_, term_local_, term_extra_;
  std::vector<int> marked_, starts_;    // evaluate()'s scratch (no allocation per call)
  int npair_last_ = 0;
  int kind_end_[4] = {0, 0, 0, 0};
  // rows mode: the cell list of all local atoms (per list build) and the
  // folds (image j -> copy k) of the last compute_rows()
  bool rows_ = false;
  double **ref_ = nullptr;
  int64_t ref_ncalls_ = -1, cells_ncalls_ = -1;
  // rows by local atom, kept per list build: entries (tag, raw j)
  HardSphere::CellRows<std::pair<tagint, int>> rows_cache_;
  void build_row(int a, std::vector<std::pair<tagint, int>> &out);
  // set_near(): the contact neighbours found by build_row(), per copy
  double near_cut2_ = -1.0;
  int near_groupbit_ = 0;
  HardSphere::CellRows<int> near_;    // (its grid unused: rows_cache_'s scan fills it)
  std::vector<std::pair<tagint, int>> near_excl_;    // scratch: bonded partners left out
  int64_t list_epoch() const;
  int64_t run_epoch_ = 0;    // init() calls: one per run (list_epoch())
  // how LAMMPS' lists carry the pair (a, tj) (a local, tj a tag): 0 plain,
  // 1-3 a special pair with its bits, -1 a special pair left out
  // (special_flag 0)
  int special_code(int a, tagint tj) const;
  // neigh_modify exclude: does LAMMPS' list build leave the pair of copies
  // i, j out? (NPair::exclusion()'s tests, on Neighbor's tables)
  bool excluded(int i, int j) const;
  const Topology *topo_ = nullptr;
  std::vector<int> topo_rows_[4];     // rows mode with topo_: C's bonded rows
  std::vector<uint32_t> tstamp_;      // per topology term: taken in this call
  std::vector<int> fold_;    // pairs j, k
  std::vector<std::pair<tagint, int>> ctag_;
  std::vector<int> kept_;    // cross_rows()' scratch
  std::vector<char> fold_src_;    // all 0 between calls
  void evaluate(const int *c, int nc, bool record_terms);
  // copy i's force row to zero, once per evaluation (inline: ~6.5 million
  // calls per 10 steps at 256000 atoms, from evaluate()'s term loop)
  void zero(int i)
  {
    if (zeroed_[i] == epoch_) return;
    zeroed_[i] = epoch_;
    // (row i of the block, as lj_cut_forces() reads it: no row pointer load)
    double *fi = fl_[0] + 3 * (size_t) i;
    fi[0] = fi[1] = fi[2] = 0.0;
    zero_list_.push_back(i);
  }
  // pair hybrid (hs_local_forces.cpp, "pair hybrid")
  bool hybrid_ = false;
  struct SubList {
    class Pair *style = nullptr;
    class NeighList *list = nullptr;
    std::vector<int> ilist, neigh, starts, num;    // its restricted list
    std::vector<int *> first;
  };
  std::vector<SubList> subs_;
  class NeighList *hyb_all_ = nullptr;
  std::vector<char> covered_;    // [itype * (ntypes + 1) + jtype]: some sub-style computes it
  bool all_covered_ = true;
  int64_t hyb_run_ = -1;
  std::vector<std::string> sub_style_names() const;
  void find_sub_lists();
  void hybrid_forces(int eflag);
  class NeighList *pair_list() const;
  void grow();
  void run_styles(class NeighList *L, const bool present[4], bool first = true);
  void compute_kind_on(int b, int n, int **rows, int ef);
  int64_t last_ncalls_ = -1;
  int last_nc_ = -1;
  bool terms_only_ = false;
  const int *label_ = nullptr;
  Mode mode_ = NORMAL;
};

}    // namespace LAMMPS_NS

#endif
