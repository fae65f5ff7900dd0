/* ----------------------------------------------------------------------
   HARDSPHERE package: the local step engine (`substep local`).
   See hs_local_engine.h and doc/fix_hardsphere.rst, "Step engines".

   One code for any number of MPI ranks (issue 20, doc/Developer_
   hardsphere.rst "The local engine on several ranks"): the step's clusters
   are a ClusterSet over the members' atom IDs, the same on every rank; a
   cluster's flows are run by the owner of one member (runner_of(): the
   least of a mix of the members' IDs; its key is the lowest ID) on its
   own copies (owned or ghost); what they produce goes to the other ranks as
   packets (MPI_Allgatherv, one per phase) or, for the partners' sums,
   through the ghosts' reverse communication; Phi_H2's velocities go from
   the owners to the ghosts by a forward communication. Every discrete
   decision is made by one rank and shared: a contact by the rank that
   lists the pair (the fix's half list) or runs the flow.
------------------------------------------------------------------------- */

#include "hs_local_engine.h"

#include "hs_compat.h"
#include "hs_contact.h"
#include "hs_fix_rule.h"
#include "hs_flow_view.h"
#include "hs_local_forces.h"
#include "hs_mix.h"
#include "hs_mpi.h"
#include "hs_method.h"
#include "hs_potential.h"
#include "hs_system.h"

#include "atom.h"
#include "atom_vec.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix.h"
#include "force.h"
#include "kspace.h"
#include "memory.h"
#include "modify.h"
#include "neighbor.h"
#include "pair.h"
#include "update.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>

using namespace LAMMPS_NS;
using HardSphere::bump_epoch;
using HardSphere::Contact;

// Phi_H2's lines of atoms near a cluster deviate from fix nve's by the V_C
// kicks; pairs (walls) that pass fix nve's lines farther than this
// (relative to the contact distance) need no check in Phi_H2 as long as
// every deviation stays below half of it (checked, else all are checked)
static constexpr double LINE_MARGIN = 1.0e-3;
// growth rounds of one step beyond which something is wrong
static constexpr int MAX_ROUNDS = 10000;
// doubles per path segment in a packet: t0, t1, q, v, a
static constexpr int SEG_DOUBLES = 11;

/* ---------------------------------------------------------------------- */

HSLocalEngine::HSLocalEngine(LAMMPS *lmp, HSSystem &system, HSMethod &method) :
    HSStepEngine(lmp), sys(&system), meth(method)
{
  locf = new HSLocalForces(lmp, "Fix " + system.style_name);
  nprocs = comm->nprocs;
  me = comm->me;
}

HSLocalEngine::~HSLocalEngine()
{
  delete locf;
  for (auto &a : peratom()) memory->destroy(*a.first);
}

/* ----------------------------------------------------------------------
   can this set-up run locally? "" if yes, else the reasons
------------------------------------------------------------------------- */

std::string HSLocalEngine::limits()
{
  std::string why;
  auto add = [&why](const std::string &s) { why += (why.empty() ? "" : "; ") + s; };
  nprocs = comm->nprocs;
  me = comm->me;
  // an atom's copies are found through the atom map: an input without
  // atom_modify map (LAMMPS' default for atomic styles) gets one, as
  // velocity ... loop all and reset_atoms_id make theirs, and keeps it
  // (LAMMPS maintains any map at each exchange and borders); without it
  // the default engine fell back to the global one, ~25x slower on 4000 atoms
  if (atom->map_style == Atom::MAP_NONE) {
    // (without ghosts, as velocity and delete_atoms make theirs: the ghost
    // rows may be stale, e.g. after delete_atoms without a map, and hold IDs
    // beyond the owned atoms' largest, the map's size; the run's setup()
    // rebuilds them, and init() is always followed by it)
    atom->nghost = 0;
    atom->map_init();
    atom->map_set();
    if (me == 0)
      utils::logmesg(lmp, "fix {}: substep local made an atom map (atom_modify map yes)\n",
                     sys->style_name);
  }
  locf->init();
  if (!locf->exact()) add(locf->unrestrictable());
  // kspace and the fixes that only add a force of the positions: not
  // evaluated at sub-steps. On a member their force G = f - F_C (f minus its
  // restricted V_C force, held_of(), as a thermostat's) at the step's start
  // rides inside both halves of its flow as a constant force, and the
  // closing kick makes the step's impulse dt/2 (G(q0) + G(q1)) (flow(); doc
  // fix_hardsphere "Held smooth forces"); everyone else takes them in
  // LAMMPS' forces, as beside fix nve
  held_smooth.clear();
  auto hold = [this](const std::string &s) {
    held_smooth += (held_smooth.empty() ? "" : ", ") + s;
  };
  if (force->kspace && force->kspace->compute_flag)
    hold(std::string("kspace style ") + force->kspace_style);
  // fixes with conservative forces: not part of the restricted V_C
  gravity.clear();
  for (int k = 0; k < modify->nfix; k++) {
    Fix *other = modify->fix[k];
    if (!(modify->fmask[k] & FixConst::POST_FORCE) || HardSphere::package_fix(other->style))
      continue;
    const std::string base = HardSphere::base_style(other->style);
    if (base == "enforce2d") continue;    // zero z forces: V_C's are zero in z already
    // (a frozen wall or piston of atoms beside the spheres: its fix changes
    // no force of theirs)
    if (HardSphere::own_group_only(base) && sys->group_apart(other->igroup)) continue;
    // m g on every atom of its group, whatever the positions: known on
    // every copy (const_force()), so the members' flows take it with V_C
    // (pcva's ledger holds its energy, HSLocalModified::const_energy();
    // vci's flows count -F.dq of their constant force in their potential)
    int dim = 0;
    const void *gvec = base == "gravity" ? other->extract("gvec", dim) : nullptr;
    if (gvec) {
      gravity.push_back({other->groupbit, static_cast<const double *>(gvec)});
      continue;
    }
    if (HardSphere::adds_force_only(other->style)) {
      hold(fmt::format("fix {} {}", other->id, other->style));
      continue;
    }
    const auto kind = HardSphere::fix_force_kind(other->style);
    if (kind != HardSphere::FixForceKind::CONSERVATIVE && kind != HardSphere::FixForceKind::UNKNOWN)
      continue;
    const char *what = kind == HardSphere::FixForceKind::UNKNOWN
        ? "a fix the package does not know"
        : "its forces replace or depend on f";
    add(fmt::format("fix {} {} ({}: it does not only add a force to f, so the local engine "
                    "cannot hold it as it holds kspace and force fixes)",
                    other->id, other->style, what));
  }
  // V_C's forces from rank-local rows, on any number of ranks (one code:
  // 1 and n ranks sum them alike); molecular: the members' topology comes
  // by ID (gather_topology())
  molecular = atom->molecular != Atom::ATOMIC;
  locf->set_topology(molecular ? &topo : nullptr);
  if (locf->exact() && !locf->rows_unsupported().empty())
    add(fmt::format("{} (the local engine's interaction rows)", locf->rows_unsupported()));
  cand_version = -1;
  crows_version = -1;
  bonded = (atom->molecular != Atom::ATOMIC) &&
      (force->bond || force->angle || force->dihedral || force->improper);
  // (measured: cva 9x fix nve at 4000 atoms, 2x as hybrid or one style;
  // bench/scaling/hybrid.sh)
  if (why.empty() && me == 0 && force->pair && strcmp(force->pair_style, "hybrid/scaled") == 0)
    utils::logmesg(lmp, "fix {}: pair hybrid/scaled copies the forces of every atom at each "
                   "evaluation, the local engine's restricted ones too: its collisions cost a "
                   "pass over all atoms each (pair hybrid/overlay does not)\n",
                   sys->style_name);
  return why;
}

/* ----------------------------------------------------------------------
   the ghost cutoff: the rank that runs a cluster takes a member owned
   elsewhere by its ghost copy nearest the runner's (on several ranks), which
   needs all atoms within the neighbor cutoff, so ghosts must reach that far
   beyond the farthest such member. The engine asks for the neighbor cutoff
   plus two contact-list cutoffs (three members in a row across a rank's
   face) and checks every cluster (member_copies()); on one rank for the
   contact list's cutoff only.
   ghost lazy N (the default, several ranks): a step without a predicted
   contact needs no more ghosts than LAMMPS' own (the first guess reads
   candidate pairs, within the contact list's cutoff), and every ghost costs
   LAMMPS' forwards, reverses and binning in every step. So the shell stays
   at LAMMPS' cutoff until a contact is predicted; that step is taken with
   the engine's shell (to_wide(): ghosts rebuilt at the step's start, as
   overflow widen does), kept until a reneighboring finds N steps without a
   step taken by clusters (pre_exchange()). The steps' arithmetic is the
   same in either shell (a ghost beyond the pair cutoff adds no force)
------------------------------------------------------------------------- */

void HSLocalEngine::chosen()
{
  // beside a thermostat: its forces stay half kicks if the fix can copy
  // LAMMPS' force before them (FixHardSphere::capture_rule(), splits_held())
  std::string thermo;
  if (sys->nheld) {
    const std::string order = sys->pot->capture_order(sys->host);
    thermo = order.empty()
        ? fmt::format("; the held thermostat forces of {} stay two half kicks around the flows "
                      "(the fix copies LAMMPS' force before them)",
                      sys->pot->held_names())
        : fmt::format("; the held thermostat forces of {} ride with them, since {}",
                      sys->pot->held_names(), order);
  }
  const std::string told = held_smooth + thermo;
  if (!held_smooth.empty() && told != held_smooth_told && me == 0)
    utils::logmesg(lmp,
                   "fix {}: substep local holds the forces of {} through collisional steps: "
                   "on the colliding spheres their force at the step's start acts as a "
                   "constant force inside the sub-stepped flows, the end's in the closing "
                   "kick (second order; substep global evaluates them at every contact){}\n",
                   sys->style_name, held_smooth, thermo);
  held_smooth_told = told;
  locf->keep_energy(meth.needs_flow_energy());
  locf->set_near(sys->list_cutoff, sys->groupbit);
  cutneigh = sys->list_cutoff;
  if (force->pair && force->pair->cutforce > 0.0)
    cutneigh = std::max(cutneigh, force->pair->cutforce + neighbor->skin);
  // one rank: every member is owned, its rows complete; only the contact
  // list's periodic images must reach its cutoff (a pair cutoff below it,
  // e.g. WCA's, would leave them short). Several ranks: the cutoff above
  // (beyond the pair cutoff plus skin, so that comm_modify cutoff decides)
  const bool one_rank = comm->nprocs == 1;
  double needed = one_rank ? sys->list_cutoff : cutneigh + 2.0 * sys->list_cutoff;
  if (!one_rank) needed = std::max(needed, ghost_widened);
  ghost_wide = needed;
  // comm_modify mode multi (multi/old) takes its ghost cutoffs per
  // collection (type) from cutoff/multi and the pair cutoffs; comm_modify
  // cutoff, which this engine sets, is not read there: the fix checks them
  // against ghost_wide at set-up (FixHardSphere::check_multi_ghosts()), and
  // neither ghost lazy nor overflow widen can change them
  const bool multi = comm->mode != Comm::SINGLE;
  if (multi) {
    lazy = narrow = false;
    if (!one_rank && sys->overflow == HSSystem::OVERFLOW_WIDEN)
      error->all(FLERR,
                 "Fix {} overflow widen needs comm_modify mode single: it widens the ghost "
                 "cutoff within a step, which mode multi takes per collection from "
                 "cutoff/multi (use overflow global or a larger comm_modify cutoff/multi)",
                 sys->style_name);
    return;
  }
  // the input's own comm_modify cutoff, unless it is the one this engine set
  if (comm->cutghostuser != ghost_set) ghost_user = comm->cutghostuser;
  comm->cutghostuser = ghost_user;
  const double cutghost = HSCompat::ghost_cutoff_at_init(lmp);
  // (the first guess's candidate pairs need the contact list's cutoff; not
  // below LAMMPS' own, which Comm would take instead with a warning at every
  // set-up, "Communication cutoff adjusted", about a cutoff the input never set)
  ghost_narrow = std::max(cutghost, sys->list_cutoff);
  // (comm_style brick only: the ghosts rebuilt within a step (reborder())
  // come from owned atoms that may have left their sub-domain since the
  // last exchange; brick's first swaps send every atom on the side of a
  // face (slabs to -BIG / BIG), tiled's send boxes are clipped to the
  // sub-domain (CommTiled::setup()), so such an atom's ghosts are missing:
  // a 2-rank fluid whose shell went wide every few steps lost pair terms in
  // LAMMPS' own forces, pe 0.18 off after 300 steps. overflow widen
  // rebuilds them the same way: an error)
  lazy = !one_rank && sys->ghost_lazy > 0 && cutghost < needed && comm->style == 0;
  // (one engine only: two would set the one ghost cutoff each by its own
  // steps, and one's narrowing would leave the other's clusters short)
  for (int k = 0; k < modify->nfix && lazy; k++) {
    const std::string st = HardSphere::base_style(modify->fix[k]->style);
    if (modify->fix[k] != sys->host && st.rfind("hardsphere/", 0) == 0 && st != "hardsphere/press")
      lazy = false;
  }
  if (!one_rank && sys->overflow == HSSystem::OVERFLOW_WIDEN && comm->style != 0)
    error->all(FLERR,
               "Fix {} overflow widen needs comm_style brick: it rebuilds the ghost atoms "
               "within a step, which comm_style tiled does not serve (use overflow global or "
               "a larger comm_modify cutoff)",
               sys->style_name);
  // a run that follows one with recent contacts starts wide (a step of
  // contacts numbered after this run's start, as after a reset_timestep to
  // an earlier step, counts as recent: else the shell stayed wide until the
  // clock passed that step again)
  if (last_cluster_step > update->ntimestep) last_cluster_step = update->ntimestep;
  narrow = lazy &&
      (last_cluster_step < 0 || update->ntimestep - last_cluster_step >= sys->ghost_lazy);
  if (cutghost < needed && me == 0) {
    const std::string why = one_rank
        ? std::string("the contact list's cutoff, contact distance + 2 x skin")
        : fmt::format("the neighbor cutoff {:.8g} plus two contact-list cutoffs {:.8g}, so "
                      "that a collision cluster's members have their interaction rows on the "
                      "rank that runs it",
                      cutneigh, sys->list_cutoff);
    if (lazy) {
      // (once, not at every run's set-up)
      const std::string told = fmt::format(
          "fix {}: substep local keeps the ghost cutoff {:.8g} while no contact is "
          "predicted; a step with one is taken with comm_modify cutoff {:.8g} ({}), "
          "kept until {} steps pass without one (ghost lazy; ghost wide: always)\n",
          sys->style_name, ghost_narrow, needed, why, sys->ghost_lazy);
      if (told != lazy_told) utils::logmesg(lmp, told);
      lazy_told = told;
    }
    else
      utils::logmesg(lmp,
                     "fix {}: substep local sets comm_modify cutoff {:.8g} (the ghost cutoff "
                     "was {:.8g}): {}\n",
                     sys->style_name, needed, cutghost, why);
  }
  set_ghost_cutoff(narrow ? ghost_narrow : (cutghost < needed ? needed : ghost_user));
}

void HSLocalEngine::set_ghost_cutoff(double cut)
{
  comm->cutghostuser = cut;
  ghost_set = cut;
}

/* ----------------------------------------------------------------------
   the ghost atoms rebuilt for the current comm_modify cutoff at the step's
   start positions, as a reneighboring does without its exchange (owned
   atoms stay where they are, within skin/2 of their sub-domain, which
   borders() allows for): the swaps and bins (resize_shell()), LAMMPS'
   lists and the fixes' post-neighbor state (the contact list) with them
------------------------------------------------------------------------- */

void HSLocalEngine::reborder()
{
  // (the fix's copy of the conservative force stays valid: no owned atom
  // moves to another index; held forces split the same on any number of
  // ranks, splits_held())
  const bigint ncalls_before = neighbor->ncalls;
  resize_shell();
  // (as exchange() begins: the map cleared while it still lists the ghosts)
  if (atom->map_style != Atom::MAP_NONE) atom->map_clear();
  atom->nghost = 0;
  atom->avec->clear_bonus();
  // (borders() works in box fractions in a triclinic box, as Verlet calls it)
  if (domain->triclinic) domain->x2lamda(atom->nlocal);
  comm->borders();
  if (domain->triclinic) domain->lamda2x(atom->nlocal + atom->nghost);
  modify->pre_neighbor();
  neighbor->build(1);
  modify->post_neighbor();
  sys->capture_kept(ncalls_before);
}

/* ----------------------------------------------------------------------
   overflow widen: a step whose cluster reaches beyond the ghost atoms is
   taken again from its start (step_clusters() restored it) after the ghost
   atoms were rebuilt one contact-list cutoff farther (a member one more
   contact away). The wider cutoff stays (comm_modify cutoff; a log line
   names it, to set from the start)
------------------------------------------------------------------------- */

bool HSLocalEngine::widening() const
{
  return sys->overflow == HSSystem::OVERFLOW_WIDEN && nprocs > 1;
}

void HSLocalEngine::widen()
{
  const double was = HSCompat::ghost_cutoff_at_init(lmp);
  const double wider = was + sys->list_cutoff;
  // a cluster as long as the box (a percolating one) is no case for this
  double span = 0.0;
  for (int d = 0; d < domain->dimension; d++) span = std::max(span, domain->prd[d]);
  if (wider > span)
    error->all(FLERR,
               "Fix {} substep local: a collision cluster on step {} reaches beyond the ghost "
               "cutoff {}, and overflow widen would need more than the box's length {}: "
               "the clusters percolate (a smaller timestep, substep global)",
               sys->style_name, update->ntimestep, was, span);
  if (me == 0)
    utils::logmesg(lmp,
                   "fix {}: step {}: a collision cluster reaches beyond the ghost cutoff "
                   "{:.8g}; overflow widen sets comm_modify cutoff {:.8g} and takes the step "
                   "again (set it from the start to avoid this)\n",
                   sys->style_name, update->ntimestep, was, wider);
  set_ghost_cutoff(wider);
  ghost_wide = ghost_widened = wider;
  nwiden += 1.0;
  reborder();
}

// ghost lazy: a contact is predicted while the shell is LAMMPS' own; the
// step is taken from its start with the engine's
void HSLocalEngine::to_wide()
{
  set_ghost_cutoff(ghost_wide);
  narrow = false;
  nwide += 1.0;
  reborder();
}

// ghost lazy: back to LAMMPS' own shell at a reneighboring (before its
// exchange and borders) that finds N steps without a step taken by clusters
void HSLocalEngine::pre_exchange()
{
  if (!lazy || narrow) return;
  if (last_cluster_step >= 0 && update->ntimestep - last_cluster_step < sys->ghost_lazy) return;
  narrow = true;
  set_ghost_cutoff(ghost_narrow);
  resize_shell();
}

// Comm's swaps and Neighbor's bins for the current comm_modify cutoff, as
// Verlet sets them up after a box change (the bins must cover every ghost:
// LAMMPS does not clamp a ghost beyond them into them)
void HSLocalEngine::resize_shell()
{
  comm->setup();
  if (neighbor->style) neighbor->setup_bins();
}

/* ---------------------------------------------------------------------- */

// -grad V_C for the copies c[0..n) (HSLocalForces)
void HSLocalEngine::vc(const int *c, int n, bool record_terms)
{
  // the rows are taken at the list build's positions (HSSystem::xref,
  // owned and ghosts, set at every build)
  locf->set_reference(sys->xref);
  locf->compute_rows(c, n, record_terms);
  ncompute_here += 1.0;
}

const int *HSLocalEngine::crow(int a, int &n)
{
  HSSystem &F = *sys;
  // a member's row of V_C (built first, vc()) lists them from its own scan
  if (const int *r = locf->near_row(a, n)) return r;
  if (crows_version != F.cand_version) {
    crows.rebuild(F.xref, atom->nlocal + atom->nghost, F.list_cutoff, 2);
    crows_version = F.cand_version;
  }
  return crows.row(a, n, [&](std::vector<int> &out) {
    const int *mask = atom->mask;
    const tagint *tag = atom->tag;
    const double cut2 = F.list_cutoff * F.list_cutoff;
    const double *xa = F.xref[a];
    const size_t s0 = out.size();
    // (bonded partners too: the fix adds those LAMMPS' lists leave out)
    crows.grid.for_each_within(xa, cut2, [&](int j, const double *) {
      if (j == a || tag[j] == tag[a] || !(mask[j] & F.groupbit)) return;
      out.push_back(j);
    });
    std::sort(out.begin() + s0, out.end(), [tag](int p, int q) {
      return tag[p] != tag[q] ? tag[p] < tag[q] : p < q;
    });
  });
}

void HSLocalEngine::grow_arrays()
{
  if (atom->nmax > nmax) {
    nmax = atom->nmax;
    for (auto &a : peratom()) {
      memory->destroy(*a.first);
      memory->create(*a.first, nmax, a.second, "hardsphere/local:peratom");
    }
    // the sums are kept zero outside the rows listed in sa_used, dsa_rows,
    // sb_rows
    for (int l = 0; l < nmax; l++)
      for (int d = 0; d < 7; d++) sa[l][d] = sb[l][d] = dsa[l][d] = 0.0;
    // quick_clear()'s stamps start below any call's (a fresh block may hold
    // another array's old values, e.g. a 1.0 that would pass for a stamp)
    for (int l = 0; l < nmax; l++) qrow[l][0] = 0.0;
    sa_used.clear();
    std::fill(in_used.begin(), in_used.end(), 0);
    dsa_rows.clear();
    sb_rows.clear();
  }
  if ((int) mid.size() < nmax) {
    mid.resize(nmax, -1);
    lab.resize(nmax, -1);
    atom_runs.resize(nmax);
    estamp.resize(nmax, 0);
    astamp.resize(nmax, 0);
    envstamp.resize(nmax, 0);
    envbest.resize(nmax, -1);
    wstamp.resize(nmax, 0);
    dstamp_sa.resize(nmax, 0);
    in_used.resize(nmax, 0);
    dstamp.resize(nmax, 0);
  }
}

int HSLocalEngine::id_of(tagint t)
{
  if (const int *known = idof.find(t)) return *known;
  const int id = (int) idtag.size();
  idof.insert(t, id);
  idtag.push_back((int64_t) t);
  cs.grow(id + 1);
  return id;
}

/* ----------------------------------------------------------------------
   the contact candidates by local copy, once per list build (each pair
   is listed on one rank: the fix's half list)
------------------------------------------------------------------------- */

void HSLocalEngine::build_adjacency()
{
  if (sys->cand_version == cand_version) return;
  const int nall = atom->nlocal + atom->nghost;
  const tagint *tag = atom->tag;
  const std::vector<int> &cand = sys->cand;
  const int np = (int) cand.size() / 2;
  // a pair of an atom with its own image (left out) is within the list
  // cutoff only in a periodic dimension shorter than that: else no pair's
  // tags are read
  bool images = false;
  for (int d = 0; d < domain->dimension; d++)
    images = images || (domain->periodicity[d] && domain->prd[d] <= sys->list_cutoff);
  auto skip = [&](int a, int b) { return images && tag[a] == tag[b]; };
  adj_off.assign(nall + 1, 0);
  for (int p = 0; p < np; p++) {
    const int a = cand[2 * p], b = cand[2 * p + 1];
    if (skip(a, b)) continue;
    adj_off[a + 1]++;
    adj_off[b + 1]++;
  }
  for (int i = 0; i < nall; i++) adj_off[i + 1] += adj_off[i];
  adj.resize(adj_off[nall]);
  std::vector<int> &pos = adj_pos;
  pos.assign(adj_off.begin(), adj_off.end() - 1);
  for (int p = 0; p < np; p++) {
    const int a = cand[2 * p], b = cand[2 * p + 1];
    if (skip(a, b)) continue;
    adj[pos[a]++] = p;
    adj[pos[b]++] = p;
  }
  // the ghost copies in a candidate pair: with the owned atoms, every copy
  // the first guess looks at (on several ranks the ghost region is some
  // 40 % of the copies, most of them beyond the contact-list cutoff)
  cand_ghosts.clear();
  const int nlocal = atom->nlocal;
  for (int g = nlocal; g < nall; g++)
    if (adj_off[g + 1] > adj_off[g]) cand_ghosts.push_back(g);
  // (predict_all(): a pair whose copies moved less than this since the
  // build, paths included, is out of reach)
  const std::vector<double> &r0 = sys->cand_r;
  cand_slack.resize(np);
  if (sys->diameter_flag) {
    // (radius_of() of both: 0.5 d + 0.5 d = d exactly)
    const double sm = sys->diameter * (1.0 + LINE_MARGIN) * (1.0 + 1.0e-10);
    for (int p = 0; p < np; p++) cand_slack[p] = r0[p] - sm;
  } else
    for (int p = 0; p < np; p++) {
      const double sm =
          (sys->radius_of(cand[2 * p]) + sys->radius_of(cand[2 * p + 1])) * (1.0 + LINE_MARGIN);
      cand_slack[p] = r0[p] - sm * (1.0 + 1.0e-10);
    }
  pstamp.assign(np, 0u);
  pepoch = 0;
  cand_version = sys->cand_version;
}

/* ----------------------------------------------------------------------
   move local copy i (and every other copy of its atom on this rank) to
   xn, resp. give them velocity vn
------------------------------------------------------------------------- */

// every copy of atom i to position xn (the others keep their image
// offsets) and velocity vn, as SET_X and SET_V say (fixed at compile time:
// the walk is on every sub-step's path). One walk over the copies sets
// both (a member's every sub-step)
template <bool SET_X, bool SET_V>
static void put_copies(Atom *atom, int i, const double *xn, const double *vn)
{
  double **x = atom->x, **v = atom->v;
  double d[3] = {0.0, 0.0, 0.0};
  if (SET_X)
    for (int e = 0; e < 3; e++) d[e] = xn[e] - x[i][e];
  for (int k = atom->map(atom->tag[i]); k >= 0; k = atom->sametag[k]) {
    if (SET_V)
      for (int e = 0; e < 3; e++) v[k][e] = vn[e];
    if (SET_X && k != i)
      for (int e = 0; e < 3; e++) x[k][e] += d[e];
  }
  if (SET_X)
    for (int e = 0; e < 3; e++) x[i][e] = xn[e];
}

void HSLocalEngine::set_x(int i, const double *xn)
{
  put_copies<true, false>(atom, i, xn, nullptr);
}

void HSLocalEngine::set_v(int i, const double *vn)
{
  put_copies<false, true>(atom, i, nullptr, vn);
}

void HSLocalEngine::set_xv(int i, const double *xn, const double *vn)
{
  put_copies<true, true>(atom, i, xn, vn);
}

/* ----------------------------------------------------------------------
   the collectives of a step: every rank's sendbuf, in rank order (one
   MPI_Allgather of the sizes and one MPI_Allgatherv), and a maximum
------------------------------------------------------------------------- */

void HSLocalEngine::allgather(HardSphere::GatherBuffer<double> &out)
{
  ncollective += 1.0;
  HardSphere::allgatherv(world, MPI_DOUBLE, sendbuf, out);
}

double HSLocalEngine::max_all(double v)
{
  ncollective += 1.0;
  if (nprocs == 1) return v;
  double g;
  MPI_Allreduce(&v, &g, 1, MPI_DOUBLE, MPI_MAX, world);
  return g;
}

// every rank's hits, sorted and unique (the same list on every rank)
void HSLocalEngine::gather_hits(std::vector<Hit> &hits)
{
  if (nprocs == 1) {    // (what unpack_runs() makes of this rank's own)
    ncollective += 1.0;
    sort_unique(hits);
    return;
  }
  start_packets(hits);
  allgather(recvbuf);
  unpack_runs(hits, nullptr);
}

// every rank's hits gathered into hits; if there are any, the clusters grow
// by them (a growth round follows): true
bool HSLocalEngine::gather_grow(std::vector<Hit> &hits)
{
  gather_hits(hits);
  if (hits.empty()) return false;
  grow_clusters(hits);
  return true;
}

/* ----------------------------------------------------------------------
   the packets of a run's half: members' IDs, displacements from their
   start and velocities after the half, its path segments (displacements
   from the start too), its collision counts. Layout: key, half, nmembers,
   npair, nwall, then per member: ID, dx(3), v(3), nseg, nseg x SEG_DOUBLES
------------------------------------------------------------------------- */

void HSLocalEngine::pack_run(const Run &r, bool first_half)
{
  const int h = first_half ? 0 : 1;
  const int nm = (int) r.mtags.size();
  sendbuf.push_back((double) r.mtags[0]);
  // (2: a provisional second half, whose ends the corrector reads)
  sendbuf.push_back((double) (first_half ? 0 : (awaits_corrector(r) ? 2 : 1)));
  sendbuf.push_back((double) nm);
  sendbuf.push_back(r.npair[h]);
  sendbuf.push_back(r.nwall[h]);
  const std::vector<Vec> &dx = first_half ? r.dxm : r.dxe;
  const std::vector<Vec> &vv = first_half ? r.vm : r.ve;
  const std::vector<std::vector<Seg>> &segs = first_half ? r.segsA : r.segsB;
  for (int k = 0; k < nm; k++) {
    sendbuf.push_back((double) r.mtags[k]);
    for (int d = 0; d < 3; d++) sendbuf.push_back(dx[k][d]);
    for (int d = 0; d < 3; d++) sendbuf.push_back(vv[k][d]);
    sendbuf.push_back((double) segs[k].size());
    for (const Seg &s : segs[k]) {
      sendbuf.push_back(s.t0);
      sendbuf.push_back(s.t1);
      for (int d = 0; d < 3; d++) sendbuf.push_back(s.q[d]);
      for (int d = 0; d < 3; d++) sendbuf.push_back(s.v[d]);
      for (int d = 0; d < 3; d++) sendbuf.push_back(s.a[d]);
    }
  }
}

// hits first (count, pairs), then packets; the hits of every rank go to
// hits (sorted, unique), the packets of other ranks' runs into the
// registry; arrived: the keys of every packet (own ones too)
void HSLocalEngine::unpack_runs(std::vector<Hit> &hits, std::vector<tagint> *arrived)
{
  hits.clear();
  const HardSphere::GatherBuffer<double> &b = recvbuf;
  size_t m = 0;
  const size_t n = b.size();
  while (m < n) {
    const int nh = (int) b[m++];
    for (int k = 0; k < nh; k++, m += 2) hits.push_back({(tagint) b[m], (tagint) b[m + 1]});
    const int npk = (int) b[m++];
    for (int pk = 0; pk < npk; pk++) {
      const tagint key = (tagint) b[m];
      const int half = (int) b[m + 1];
      const int h = half == 0 ? 0 : 1;
      const int nm = (int) b[m + 2];
      Run *rp = run_of(key);
      const bool mine = rp && rp->mine;
      if (arrived) arrived->push_back(key);
      Run &r = mine ? *rp : runs[key];
      const double np = b[m + 3], nw = b[m + 4];
      m += 5;
      // one walk over the members: where the packet ends, and (another
      // rank's run) the members' IDs and whether any has a copy here. A
      // run with none (on many ranks, most of the other ranks' runs) keeps
      // its IDs and counts only: its segments are read through a member's
      // copy (cross_check()), its positions and velocities put on the
      // members' copies (place_members(), step_clusters()): never, here
      if (!mine) r.mtags.resize(nm);
      bool here = false;
      size_t end = m;
      for (int k = 0; k < nm; k++) {
        if (!mine) {
          r.mtags[k] = (tagint) b[end];
          here = here || atom->map(r.mtags[k]) >= 0;
        }
        end += 8 + SEG_DOUBLES * (size_t) b[end + 7];
      }
      if (mine) {    // (this rank's own state)
        m = end;
        continue;
      }
      std::vector<Vec> &dx = h == 0 ? r.dxm : r.dxe;
      std::vector<Vec> &vv = h == 0 ? r.vm : r.ve;
      std::vector<std::vector<Seg>> &segs = h == 0 ? r.segsA : r.segsB;
      r.npair[h] = np;
      r.nwall[h] = nw;
      if (!here) {
        dx.clear();
        vv.clear();
        for (auto &sg : segs) sg.clear();
      } else {
        dx.resize(nm);
        vv.resize(nm);
        segs.resize(nm);
        for (int k = 0; k < nm; k++) {
          m++;    // (the ID, taken above)
          for (int d = 0; d < 3; d++) dx[k][d] = b[m++];
          for (int d = 0; d < 3; d++) vv[k][d] = b[m++];
          const int ns = (int) b[m++];
          segs[k].resize(ns);
          for (int q = 0; q < ns; q++) {
            Seg &s = segs[k][q];
            s.t0 = b[m++];
            s.t1 = b[m++];
            for (int d = 0; d < 3; d++) s.q[d] = b[m++];
            for (int d = 0; d < 3; d++) s.v[d] = b[m++];
            for (int d = 0; d < 3; d++) s.a[d] = b[m++];
          }
        }
      }
      // the provisional ends, kept through the corrected run's packet
      if (half == 0) r.dxp.clear();
      if (half == 2) r.dxp = r.dxe;
      m = end;
      if (h == 0) {
        r.a_done = true;
        r.b_done = false;
        if (here) place_members(r);
      } else
        r.b_done = true;
    }
  }
  sort_unique(hits);
}

void HSLocalEngine::sort_unique(std::vector<Hit> &hits)
{
  std::sort(hits.begin(), hits.end());
  hits.erase(std::unique(hits.begin(), hits.end()), hits.end());
}

// every local copy of the members of another rank's run waits at its mid
// position (x0 + the run's displacement) with its mid velocity
void HSLocalEngine::place_members(const Run &r)
{
  double **x = atom->x, **v = atom->v;
  for (size_t k = 0; k < r.mtags.size(); k++)
    for (int l = atom->map(r.mtags[k]); l >= 0; l = atom->sametag[l]) {
      moved.push_back(l);
      for (int d = 0; d < 3; d++) {
        x[l][d] = x0[l][d] + r.dxm[k][d];
        v[l][d] = r.vm[k][d];
      }
    }
}

// one half's hits and the packets of the runs this rank ran in it, to and
// from every rank: gathered, every rank's hits; arrived, every packet's key
void HSLocalEngine::share_half(const std::vector<Hit> &hits, const std::vector<tagint> &ran,
                               bool first_half, std::vector<Hit> &gathered,
                               std::vector<tagint> &arrived)
{
  // one rank: every packet would be this rank's own run, which
  // unpack_runs() skips; the packing (~1 % of a cva step at 32000 atoms)
  // and the gather's copy are left out, the result is the same
  if (nprocs == 1) {
    ncollective += 1.0;
    gathered = hits;
    sort_unique(gathered);
    arrived = ran;
    return;
  }
  start_packets(hits);
  for (tagint key : ran) {
    pack_run(*run_of(key), first_half);
    sendbuf[npk_pos] += 1.0;
  }
  allgather(recvbuf);
  arrived.clear();
  unpack_runs(gathered, &arrived);
}

void HSLocalEngine::start_packets(const std::vector<Hit> &hits)
{
  sendbuf.clear();
  sendbuf.push_back((double) hits.size());
  for (const Hit &h : hits) {
    sendbuf.push_back((double) h.i);
    sendbuf.push_back((double) h.j);
  }
  npk_pos = sendbuf.size();
  sendbuf.push_back(0.0);
}

/* ----------------------------------------------------------------------
   every contact of the step on the unsplit Verlet paths q + t v + t^2/2 a
   (the first guess of C): walls of active spheres, candidate pairs with an
   active sphere (this rank's part; the caller gathers them)
------------------------------------------------------------------------- */

void HSLocalEngine::predict_all(std::vector<Hit> &hits)
{
  HSSystem &F = *sys;
  double **x = atom->x, **v = atom->v, **acc = F.acc;
  const int nlocal = atom->nlocal, nall = nlocal + atom->nghost;
  const int *mask = atom->mask;
  const tagint *tag = atom->tag;
  const double dt = F.dtv;
  // the screen's active spheres, and those within LINE_MARGIN / 2 of being
  // active (Phi_H2's lines may deviate that much from fix nve's, below);
  // flags and free gaps go to the ghosts (cols: gap, flag)
  act0.clear();
  near_pairs.clear();
  near_walls.clear();
  const double mhalf = 0.5 * LINE_MARGIN * 2.0 * F.rmax;
  const double t2 = dt * dt, h4 = 0.25 * t2 * t2;
  const double ftm2v = force->ftm2v;
  pathv.resize(nall);
  flagv.resize(nall);
  awayv.resize(nall);
  // the path bound dt |v| + dt^2/2 |a| of fix nve's step and the flag of
  // every copy, once per copy in two contiguous arrays: the pair loop reads
  // them for each of its ~5 pairs per atom (the bound per pair of an
  // unflagged atom, and the flags through cols, cost more); and how far the
  // copy can be from its list build position by the step's end
  double **xref = F.xref;
  auto bound = [&](int k) {
    pathv[k] = path_bound(v[k], acc[k], dt);
    flagv[k] = cols[k][1] != 0.0;
    const double d[3] = {x[k][0] - xref[k][0], x[k][1] - xref[k][1], x[k][2] - xref[k][2]};
    awayv[k] = pathv[k] + sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  };
  // one pass over the owned atoms (each array read once, as fix nve's
  // kick reads it: the passes are bound by memory, not arithmetic): the
  // acceleration (HSSystem::set_acc()), the start state (x0, v0: used if
  // anything is hit, which on a dense fluid is nearly every step), the
  // flag and the path bound. The flag, the bound and the distance from the
  // list build share their squares here (flagged_of(), path_of(): what
  // flagged_atom() and path_bound() compute from the same squares)
  const double *active = F.active, *gap = F.gap;
  const int groupbit = F.groupbit;
  for (int i = 0; i < nlocal; i++) {
    F.set_acc_row(i, ftm2v);
    const double *xi = x[i], *vi = v[i], *xr = xref[i], *ai = acc[i];
    for (int d = 0; d < 3; d++) {
      x0[i][d] = xi[d];
      v0[i][d] = vi[d];
    }
    cols[i][0] = gap[i];
    const double dx = xi[0] - xr[0], dy = xi[1] - xr[1], dz = xi[2] - xr[2];
    const double d2 = dx * dx + dy * dy + dz * dz;
    const double vv = vi[0] * vi[0] + vi[1] * vi[1] + vi[2] * vi[2];
    const double aa = ai[0] * ai[0] + ai[1] * ai[1] + ai[2] * ai[2];
    const double path = path_of(vv, aa, dt);
    const bool fl = (mask[i] & groupbit) && flagged_of(active[i], d2, vv, aa, gap[i] - mhalf, t2, h4);
    cols[i][1] = fl ? 1.0 : 0.0;
    if (fl) act0.push_back(i);
    pathv[i] = path;
    flagv[i] = fl;
    awayv[i] = path + sqrt(d2);
  }
  // with v and a, in one exchange
  sys->forward_vel_acc(cols, 2);
  ncollective += 1.0;
  for (int k : cand_ghosts) bound(k);
  const double *pv = pathv.data();
  const char *fv = flagv.data();
  const double *av = awayv.data();
  const double *slack = cand_slack.data();
  for (int i : act0)
    for (int wl = 0; wl < (int) F.walls.size(); wl++) {
      const int g = guess_wall(i, wl, v[i], acc[i], pathv[i]);
      if (g == GUESS_HIT) hits.push_back({tag[i], -1 - (tagint) wl});
      else if (g == GUESS_NEAR) near_walls.push_back(i);
    }
  // candidate pairs with an active sphere (each listed on one rank)
  const std::vector<int> &cand = F.cand;
  const int np = (int) cand.size() / 2;
  // the pairs the filters below leave (~10 % of a dense fluid's, their
  // partners' rows all over memory: at 256000 atoms each read of x[j] was a
  // miss, the loop's hottest line) are tested in batches, their x[j]
  // fetched while the batch fills; in the order of the pairs, as before
  HardSphere::Batch<32> batch;
  auto test = [&](int p) {
    const int i = cand[2 * p], j = cand[2 * p + 1];
    const double sigma = F.radius_of(i) + F.radius_of(j);
    const double dq[3] = {x[i][0] - x[j][0], x[i][1] - x[j][1], x[i][2] - x[j][2]};
    const double r2 = dq[0] * dq[0] + dq[1] * dq[1] + dq[2] * dq[2];
    const double sm = sigma * (1.0 + LINE_MARGIN);
    const double reach = sm + pv[i] + pv[j];
    if (r2 > reach * reach) return;
    if (tag[i] == tag[j]) return;    // (two images of one atom: a ghost with no bound)
    const int g = guess_pair(i, j, dq, r2, sigma, v[i], v[j], acc[i], acc[j]);
    if (g == GUESS_HIT) hits.push_back({tag[i], tag[j]});
    else if (g == GUESS_NEAR) near_pairs.push_back(p);
  };
  for (int p = 0; p < np; p++) {
    const int i = cand[2 * p], j = cand[2 * p + 1];
    if (!(fv[i] | fv[j])) continue;
    // out of reach by the distance at the build less the copies' moves
    // since (triangle inequality; with the slack's 1e-10, also for the
    // rounded test, which would skip the pair too): most of a dense
    // fluid's pairs, without reading the copies' positions
    if (slack[p] > av[i] + av[j]) continue;
    HardSphere::prefetch_row(x[0], 3, j);    // (not x[j]: no row pointer to load first)
    batch.push(p, test);
  }
  batch.flush(test);
}

// the first guess's test of a pair within reach of each other's paths (dq,
// r2: the copies' separation; v, a: their velocities and accelerations): a
// contact on the Verlet paths, or on fix nve's straight lines (Phi_H2's,
// up to the V_C kicks of the partners), is a hit; a near miss within the
// margin on the lines is listed for Phi_H2's check
int HSLocalEngine::guess_pair(int i, int j, const double *dq, double r2, double sigma,
                              const double *vi, const double *vj, const double *ai,
                              const double *aj)
{
  const double dt = sys->dtv;
  double c[5];
  const double sm = sigma * (1.0 + LINE_MARGIN);
  const double dv[3] = {vi[0] - vj[0], vi[1] - vj[1], vi[2] - vj[2]};
  const double da[3] = {ai[0] - aj[0], ai[1] - aj[1], ai[2] - aj[2]};
  // (whether, not when: the flows find the time)
  const Contact ct = pair_contact(i, j, dq, dv, da, sigma, dt, false);
  if (ct.status != HardSphere::NO_CONTACT) return GUESS_HIT;
  const double dw[3] = {dv[0] + 0.5 * dt * da[0], dv[1] + 0.5 * dt * da[1],
                        dv[2] + 0.5 * dt * da[2]};
  const double zero[3] = {0.0, 0.0, 0.0};
  if (r2 >= sm * sm) {
    HardSphere::pair_gap_poly(dq, dw, zero, sm, c);
    if (HardSphere::first_contact(c, 4, dt, TOUCH_TOL * sm * sm, false).status ==
        HardSphere::NO_CONTACT)
      return GUESS_NONE;
  }
  HardSphere::pair_gap_poly(dq, dw, zero, sigma, c);
  const Contact cl = HardSphere::first_contact(c, 4, dt, TOUCH_TOL * sigma * sigma, false);
  return cl.status != HardSphere::NO_CONTACT ? GUESS_HIT : GUESS_NEAR;
}

// the same for wall wl and owned atom i whose path bound is Di
int HSLocalEngine::guess_wall(int i, int wl, const double *vi, const double *ai, double Di)
{
  HSSystem &F = *sys;
  const double dt = F.dtv, r = F.radius_of(i);
  double c[5];
  const Wall &W = F.walls[wl];
  const double g = F.wall_gap(W, atom->x[i], r);
  if (g > Di) return GUESS_NONE;
  const double s = (W.side < 0) ? 1.0 : -1.0;
  const Contact ct = wall_contact(i, wl, g, vi[W.dim], ai[W.dim], dt, false);
  if (ct.status != HardSphere::NO_CONTACT) return GUESS_HIT;
  const double m = LINE_MARGIN * 2.0 * r;
  const double wn = s * (vi[W.dim] + 0.5 * dt * ai[W.dim]);
  HardSphere::wall_gap_poly(g - m, wn, 0.0, c);
  if (HardSphere::first_contact(c, 2, dt, TOUCH_TOL * 2.0 * r, false).status ==
      HardSphere::NO_CONTACT)
    return GUESS_NONE;
  HardSphere::wall_gap_poly(g, wn, 0.0, c);
  const Contact cl = HardSphere::first_contact(c, 2, dt, TOUCH_TOL * 2.0 * r, false);
  return cl.status != HardSphere::NO_CONTACT ? GUESS_HIT : GUESS_NEAR;
}

// fix nve's path bound over the step, dt |v| + dt^2/2 |a|
double HSLocalEngine::path_bound(const double *v, const double *a, double dt)
{
  return path_of(v[0] * v[0] + v[1] * v[1] + v[2] * v[2], a[0] * a[0] + a[1] * a[1] + a[2] * a[2],
                 dt);
}

// may owned atom i (in the group, acceleration a) touch something in the
// step? The screen's flag, or within mhalf of its free gap: Phi_H2's lines
// may deviate that much from fix nve's
bool HSLocalEngine::flagged_atom(int i, const double *a, double t2, double h4,
                                 double mhalf) const
{
  const double *xi = atom->x[i], *xr = sys->xref[i], *vi = atom->v[i];
  const double dx = xi[0] - xr[0], dy = xi[1] - xr[1], dz = xi[2] - xr[2];
  return flagged_of(sys->active[i], dx * dx + dy * dy + dz * dz,
                    vi[0] * vi[0] + vi[1] * vi[1] + vi[2] * vi[2],
                    a[0] * a[0] + a[1] * a[1] + a[2] * a[2], sys->gap[i] - mhalf, t2, h4);
}

/* ----------------------------------------------------------------------
   the first guess of a step whose flagged spheres are few (a collision-
   free melt flags a handful of 32000 at a time; predict_all() would make
   its passes over every copy and forward 9 columns to every ghost for
   them): only the pairs and walls of the flagged spheres, with
   predict_all()'s own tests. True when every rank finds none that can
   touch; then the step is fix nve's, as after an empty first guess. A
   partner's velocity and acceleration are its owner's (an image on this
   rank), the forwarded ones of a flagged atom of another rank, or for an
   unflagged atom of another rank only its path bound, dt |v| + dt^2/2 |a|
   <= its free gap - the margin - its distance from the list build's
   position (the owner's flag test; this copy's gap, from the pairs listed
   here, is no smaller than the owner's). A pair that bound cannot clear
   leaves the step undecided: predict_all() then decides it
------------------------------------------------------------------------- */

bool HSLocalEngine::quick_clear()
{
  HSSystem &F = *sys;
  double **x = atom->x, **v = atom->v;
  double **xref = F.xref;
  const int nlocal = atom->nlocal;
  const int *mask = atom->mask, *sametag = atom->sametag;
  const tagint *tag = atom->tag;
  const double dt = F.dtv, ftm2v = force->ftm2v;
  const double mhalf = 0.5 * LINE_MARGIN * 2.0 * F.rmax;
  const double t2 = dt * dt, h4 = 0.25 * t2 * t2;
  // the flagged owned atoms: rows (stamp, v, a) marked with this call's stamp
  qstamp_now += 1.0;
  qlist.clear();
  auto flag_row = [&](int i) {
    if (!(mask[i] & F.groupbit)) return;
    double *q = qrow[i];
    double a[3];
    F.acc_of(i, ftm2v, a);
    if (!flagged_atom(i, a, t2, h4, mhalf)) return;
    q[0] = qstamp_now;
    for (int d = 0; d < 3; d++) {
      q[1 + d] = v[i][d];
      q[4 + d] = a[d];
    }
    qlist.push_back(i);
  };
  // the candidates the closing kick listed (HSSystem::near_atoms: every
  // atom it did not clear with the free gap less mhalf, in index order),
  // if it screened for this step with this margin; else every owned atom.
  // The next closing kick lists them from now on.
  const bool listed = F.near_step == update->ntimestep &&
      update->ntimestep > update->firststep + 1 && F.near_used_margin == mhalf;
  F.near_margin = mhalf;
  if (listed)
    for (int i : F.near_atoms) flag_row(i);
  else
    for (int i = 0; i < nlocal; i++) flag_row(i);
  // theirs to their ghost copies (this rank's flagged remote atoms: qrecv)
  qrecv.clear();
  if (nprocs > 1) {
    F.forward_columns(qrow, 7, &qrecv, 1, &qlist);
    ncollective += 1.0;
  }
  // a copy's velocity, acceleration and path bound: 1 flagged, 0 not, -1
  // only a bound (pv) of an unflagged atom of another rank
  double scratch[2][6];
  auto state = [&](int k, int s, const double *&vk, const double *&ak, double &pv) {
    int o = k;
    if (k >= nlocal) {
      const int m = atom->map(tag[k]);
      if (m >= 0 && m < nlocal) o = m;
    }
    // flagged: on this rank (owned, or an image of an owned atom), or on
    // another, whose row the forward brought
    const double *q = qrow[o];
    if (q[0] == qstamp_now) {
      vk = q + 1;
      ak = q + 4;
      pv = path_bound(vk, ak, dt);
      return 1;
    }
    if (o < nlocal) {
      for (int d = 0; d < 3; d++) scratch[s][d] = v[o][d];
      F.acc_of(o, ftm2v, scratch[s] + 3);
      vk = scratch[s];
      ak = scratch[s] + 3;
      pv = path_bound(vk, ak, dt);
      return 0;
    }
    const double dx = x[k][0] - xref[k][0], dy = x[k][1] - xref[k][1], dz = x[k][2] - xref[k][2];
    const double eps = 1.0e-9 * (F.skin + fabs(x[k][0]) + fabs(x[k][1]) + fabs(x[k][2]));
    pv = std::max(0.0, F.gap[k] - mhalf - sqrt(dx * dx + dy * dy + dz * dz)) + eps;
    return -1;
  };
  bool clear = true;
  bump_epoch(pepoch, pstamp);
  const std::vector<int> &cand = F.cand;
  auto pairs_of = [&](int c) {
    for (int e = adj_off[c]; e < adj_off[c + 1] && clear; e++) {
      const int p = adj[e];
      if (pstamp[p] == pepoch) continue;
      pstamp[p] = pepoch;
      const int i = cand[2 * p], j = cand[2 * p + 1];
      if (tag[i] == tag[j]) continue;
      const double *vi, *vj, *ai, *aj;
      double pvi, pvj;
      const int si = state(i, 0, vi, ai, pvi), sj = state(j, 1, vj, aj, pvj);
      if (si <= 0 && sj <= 0) continue;    // (neither flagged: not in the guess)
      const double sigma = F.radius_of(i) + F.radius_of(j);
      const double dq[3] = {x[i][0] - x[j][0], x[i][1] - x[j][1], x[i][2] - x[j][2]};
      const double r2 = dq[0] * dq[0] + dq[1] * dq[1] + dq[2] * dq[2];
      const double reach = sigma * (1.0 + LINE_MARGIN) + pvi + pvj;
      if (r2 > reach * reach) continue;
      if (si < 0 || sj < 0 || guess_pair(i, j, dq, r2, sigma, vi, vj, ai, aj) == GUESS_HIT)
        clear = false;
    }
  };
  for (int i : qlist) {
    for (int wl = 0; wl < (int) F.walls.size() && clear; wl++)
      if (guess_wall(i, wl, qrow[i] + 1, qrow[i] + 4, path_bound(qrow[i] + 1, qrow[i] + 4, dt)) ==
          GUESS_HIT)
        clear = false;
    for (int c = atom->map(tag[i]); c >= 0 && clear; c = sametag[c]) pairs_of(c);
    if (!clear) break;
  }
  for (int g : qrecv) {
    if (!clear) break;
    pairs_of(g);
  }
  int mine = clear ? 1 : 0, all = mine;
  if (nprocs > 1) {
    MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_MIN, world);
    ncollective += 1.0;
  }
  return all == 1;
}

/* ----------------------------------------------------------------------
   new members (dense ids): their local copies are marked; their bonded
   terms join clusters (pair terms between members do not: cross terms, a
   constant force in each half of the flow)
------------------------------------------------------------------------- */

void HSLocalEngine::add_members(const std::vector<int> &newids)
{
  std::vector<int> copies;
  for (int id : newids)
    for (int l = atom->map((tagint) idtag[id]); l >= 0; l = atom->sametag[l]) {
      if (mid[l] < 0) mid_set.push_back(l);
      mid[l] = id;
      moved.push_back(l);
      if (l < atom->nlocal) copies.push_back(l);
    }
  if (newids.empty() || !molecular) return;
  gather_topology(newids);
}

/* ----------------------------------------------------------------------
   the new members' special lists and bonded terms, by ID from every rank
   (one collective; the same records on every rank): their rows need them
   on whichever copy runs them, and a bonded term joins the members in it
   into one cluster
------------------------------------------------------------------------- */

void HSLocalEngine::gather_topology(const std::vector<int> &newids)
{
  std::vector<tagint> ids;
  for (int id : newids) ids.push_back((tagint) idtag[id]);
  std::sort(ids.begin(), ids.end());
  sendbuf.clear();
  locf->collect_topology(ids, sendbuf);
  HardSphere::GatherBuffer<double> all;
  allgather(all);
  auto is_new = [&ids](tagint t) { return std::binary_search(ids.begin(), ids.end(), t); };
  std::vector<int> fresh;    // the terms of this gather, once each
  std::vector<char> seen;
  for (size_t p = 0; p < all.size();) {
    const int code = (int) all[p];
    if (code == 4) {
      const tagint t = (tagint) all[p + 1];
      const int n = (int) all[p + 4];
      topo.special[t].assign(n + 3, 0);
      for (int k = 0; k < n + 3; k++) topo.special[t][k] = (tagint) all[p + 2 + k];
      p += 5 + n;
      continue;
    }
    std::array<int64_t, 6> key;
    for (int k = 0; k < 6; k++) key[k] = (int64_t) all[p + k];
    p += 6;
    auto ins = term_index.emplace(key, (int) topo.terms.size());
    const int ti = ins.first->second;
    if (ins.second) {
      HSLocalForces::Topology::Term T;
      T.kind = (int) key[0];
      T.type = (int) key[1];
      for (int k = 0; k < 4; k++) T.id[k] = (tagint) key[2 + k];
      topo.terms.push_back(T);
    }
    if ((int) seen.size() <= ti) seen.resize(ti + 1, 0);
    if (seen[ti]) continue;    // (newton_bond off: listed on several ranks)
    seen[ti] = 1;
    fresh.push_back(ti);
  }
  // each new member's terms in the order of their content (the same for
  // any number of ranks: the order V_C's bonded forces are summed in)
  for (int ti : fresh) {
    const auto &T = topo.terms[ti];
    const int w = T.width();
    for (int k = 0; k < w; k++)
      if (is_new(T.id[k])) {
        topo.of[T.id[k]].push_back(ti);    // (fresh lists each term once)
      }
  }
  auto content = [this](int a, int b) {
    const auto &A = topo.terms[a], &B = topo.terms[b];
    if (A.kind != B.kind) return A.kind < B.kind;
    for (int k = 0; k < 4; k++)
      if (A.id[k] != B.id[k]) return A.id[k] < B.id[k];
    return A.type < B.type;
  };
  for (tagint t : ids) {
    auto it = topo.of.find(t);
    if (it != topo.of.end()) std::sort(it->second.begin(), it->second.end(), content);
  }
  // the bonded joins
  std::vector<int> members;
  for (int ti : fresh) {
    const auto &T = topo.terms[ti];
    const int w = T.width();
    members.clear();
    for (int k = 0; k < w; k++) {
      if (const int *id = idof.find(T.id[k])) members.push_back(*id);
    }
    if (members.size() > 1) cs.add_term(members.data(), (int) members.size());
  }
}

// the ID of n (id(k), k < n) with the least mix64() (hs_mix.h: a bijection,
// so no two IDs tie; the same on every rank, unrelated to where IDs lie)
template <class ID> static tagint least_rank(int n, ID id)
{
  tagint best = id(0);
  uint64_t rb = HardSphere::mix64((uint64_t) best);
  for (int k = 1; k < n; k++) {
    const tagint t = id(k);
    const uint64_t rk = HardSphere::mix64((uint64_t) t);
    if (rk < rb) {
      rb = rk;
      best = t;
    }
  }
  return best;
}

tagint HSLocalEngine::runner_of(const tagint *ids, int n)
{
  return least_rank(n, [ids](int k) { return ids[k]; });
}

tagint HSLocalEngine::runner_of(int c) const
{
  const std::vector<int> &m = cs.members(c);
  return least_rank((int) m.size(), [&](int k) { return (tagint) idtag[m[k]]; });
}

// the cluster labels (the key's dense id) on every local copy of its members
void HSLocalEngine::label_cluster(int c)
{
  const int key = cs.members(c)[0];
  for (int id : cs.members(c))
    for (int l = atom->map((tagint) idtag[id]); l >= 0; l = atom->sametag[l]) {
      lab[l] = key;
      labelled.push_back(l);
    }
}

/* ----------------------------------------------------------------------
   the member copies of a cluster this rank runs: a member it owns by its
   owned copy, another by its ghost copy nearest the runner's (runner_of(),
   owned here). A ghost member
   must have all atoms within the neighbor cutoff as local copies (its
   interaction rows): its list-build position at least the neighbor cutoff
   inside the ghost region. (The flows need no particular images: rows fold
   images into the members' copies, contacts are taken copy to copy.)
------------------------------------------------------------------------- */

bool HSLocalEngine::member_copies(Run &r)
{
  const int nm = (int) r.mtags.size();
  r.members.resize(nm);
  const tagint rtag = runner_of(r.mtags.data(), nm);
  const int runner = atom->map(rtag);
  double reach_needed = 0.0;    // the ghost cutoff the members' rows need
  int kout = -1;                 // the first member beyond it
  bool reach_known = true;       // (false: a member with no copy here at all)
  for (int k = 0; k < nm; k++) {
    // an owned copy has its rows; of a ghost, the copy nearest the runner
    int l = atom->map(r.mtags[k]);
    if (l >= atom->nlocal) l = domain->closest_image(runner, l);
    bool inside = l >= 0;
    if (inside && l >= atom->nlocal) {
      // the list build's position, in the ghost region's coordinates
      double p[3] = {sys->xref[l][0], sys->xref[l][1], sys->xref[l][2]};
      const double *lo = domain->sublo, *hi = domain->subhi;
      double cut[3] = {cutneigh, cutneigh, cutneigh};
      if (domain->triclinic) {
        domain->x2lamda(p, p);
        lo = domain->sublo_lamda;
        hi = domain->subhi_lamda;
        const double *h_inv = domain->h_inv;
        cut[0] *= sqrt(h_inv[0] * h_inv[0] + h_inv[5] * h_inv[5] + h_inv[4] * h_inv[4]);
        cut[1] *= sqrt(h_inv[1] * h_inv[1] + h_inv[3] * h_inv[3]);
        cut[2] *= h_inv[2];
      }
      for (int d = 0; d < 3; d++) {
        if (d == 2 && domain->dimension == 2) break;
        // (how far the ghosts must reach for this member, as a distance:
        // cut[d] is the neighbor cutoff in this dimension's units)
        const double reach = std::max(lo[d] - (p[d] - cut[d]), p[d] + cut[d] - hi[d]);
        if (reach > comm->cutghost[d]) inside = false;
        reach_needed = std::max(reach_needed, reach * cutneigh / cut[d]);
      }
    }
    if (!inside && (sys->overflow == HSSystem::OVERFLOW_GLOBAL || widening())) return false;
    // (overflow error: every rank learns of it in the step's next gather
    // and step() raises it on all ranks, so that rank 0 writes it to the
    // log: error->one() here wrote it only to this rank's screen. The
    // other members still count for the reach the message names)
    if (!inside) {
      if (kout < 0) kout = k;
      if (l < 0) reach_known = false;
      continue;
    }
    r.members[k] = l;
  }
  if (kout >= 0) {
    std::string ids;
    for (int q = 0; q < nm && q < 8; q++) ids += fmt::format(" {}", r.mtags[q]);
    // (rounded up: the reach at the list build's positions)
    const double need = std::ceil(reach_needed * 100.0) / 100.0;
    missing.clear();
    outgrown_msg = fmt::format(
        "Fix {} substep local: the collision cluster of atoms{}{} on step {} reaches beyond "
        "what the ghost cutoff {:.6g} covers (atom {} needs every atom within the neighbor "
        "cutoff {:.6g} of it on the rank of atom {}){}: use a larger comm_modify cutoff (the "
        "engine's default is {:.6g}), a smaller timestep, substep global, overflow global (such steps taken "
        "globally) or overflow widen (the engine widens the ghost cutoff and takes the step "
        "again)",
        sys->style_name, ids, nm > 8 ? " ..." : "", update->ntimestep, comm->cutghostuser,
        r.mtags[kout], cutneigh, rtag,
        reach_known ? fmt::format("; this cluster needs comm_modify cutoff {:.6g} ({:.6g} also "
                                  "covers one a contact longer)",
                                  need, need + sys->list_cutoff)
                    : std::string(),
        ghost_wide);
    return false;
  }
  // a member's bonded partners: their images nearest its copy (rows take
  // them so), which must be here and be the bonded image: less than half a
  // period from it along every periodic direction, in box fractions (as
  // LAMMPS bounds a bonded term's extent); a copy a period away is not.
  // (Before 30 Nov 2026 the bound was half the shortest period in every
  // direction: a box with one short side refused partners across its long
  // ones, an error that no comm_modify cutoff removed)
  if (!molecular || nprocs == 1) return true;
  const double *h_inv = domain->h_inv;
  const int *periodic = domain->periodicity;
  const int dim = domain->dimension;
  auto bonded_image = [&](const double *a, const double *b) {
    const double d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    const double s[3] = {h_inv[0] * d[0] + h_inv[5] * d[1] + h_inv[4] * d[2],
                         h_inv[1] * d[1] + h_inv[3] * d[2], h_inv[2] * d[2]};
    for (int k = 0; k < dim; k++)
      if (periodic[k] && !(fabs(s[k]) < 0.5)) return false;
    return true;
  };
  double **x = atom->x;
  missing.clear();
  for (int k = 0; k < nm; k++) {
    auto it = topo.of.find(r.mtags[k]);
    if (it == topo.of.end()) continue;
    for (int ti : it->second) {
      const auto &T = topo.terms[ti];
      const int w = T.width();
      for (int q = 0; q < w; q++) {
        const tagint t = T.id[q];
        if (t == r.mtags[k]) continue;
        const int m = atom->map(t);
        bool here = m >= 0;
        if (here) {
          const int c = domain->closest_image(r.members[k], m);
          here = bonded_image(x[r.members[k]], x[c]);
        }
        if (here) continue;
        if (sys->overflow == HSSystem::OVERFLOW_GLOBAL || widening()) return false;
        if (missing.empty())
          outgrown_msg = fmt::format(
              "Fix {} substep local: atom {}, bonded to atom {} of a collision cluster on step "
              "{}, has no copy near it on the rank of atom {} (ghost cutoff {:.6g}): use a "
              "larger comm_modify cutoff, substep global, overflow global (such steps taken "
              "globally) or overflow widen",
              sys->style_name, t, r.mtags[k], update->ntimestep, rtag, comm->cutghostuser);
        // (every missing partner of the cluster, for overflow_error() to name
        // a cutoff that holds them all)
        missing.push_back({t, {x[r.members[k]][0], x[r.members[k]][1], x[r.members[k]][2]}});
      }
    }
  }
  return missing.empty();
}

/* ----------------------------------------------------------------------
   the held (thermostat) force f - F(x0) of a run's members that have none
   yet this step: their conservative force at the step's start from all
   their terms, with every atom in them put back at x0 for the evaluation.
   f from the forwarded acceleration (a member may be a ghost here)
------------------------------------------------------------------------- */

void HSLocalEngine::held_of(Run &r)
{
  if (!holds()) return;
  // an owned member's f less LAMMPS' own conservative force of the start,
  // when the fix could copy it (HSSystem::capture_forces()): no evaluation.
  // A ghost copy's (a member owned by another rank) is evaluated below.
  // Riding, held0 is all of f - F_C (the copy holds the held smooth
  // forces too): evaluated
  double **fcap = rides() ? nullptr : sys->captured(true);
  const int nlocal = atom->nlocal;
  std::vector<int> need;
  for (int l : r.members) {
    if (hstampv[l] == heldepoch) continue;
    if (fcap && l < nlocal) {
      const double *fl = atom->f[l];
      for (int d = 0; d < 3; d++) held0[l][d] = fl[d] - fcap[l][d];
      hstampv[l] = heldepoch;
      continue;
    }
    need.push_back(l);
  }
  if (need.empty()) return;
  double **x = atom->x, **acc = sys->acc;
  locf->set_labels(nullptr);
  vc(need.data(), (int) need.size());
  // the terms at x0: the atoms in them that are elsewhere (other clusters'
  // members at their mid positions, drifted atoms after a growth round)
  // back to x0 and evaluated again; where none is, vc()'s forces are
  // those of x0 already (most runs of a step's first round)
  std::vector<std::pair<int, Vec>> &away = scratch_away;
  away.clear();
  for (int t : locf->touched())
    if (x[t][0] != x0[t][0] || x[t][1] != x0[t][1] || x[t][2] != x0[t][2]) {
      away.push_back({t, Vec{x[t][0], x[t][1], x[t][2]}});
      set_x(t, x0[t]);
    }
  if (!away.empty()) {
    locf->recompute();
    ncompute_here += 1.0;
  }
  double **fl = locf->forces();
  const double ftm2v = force->ftm2v;
  double fc[3] = {0.0, 0.0, 0.0};
  for (int i : need) {
    const double m = sys->mass_of(i) / ftm2v;
    if (!gravity.empty()) const_force(i, fc);    // (in V_C, not held)
    for (int d = 0; d < 3; d++) held0[i][d] = acc[i][d] * m - fl[i][d] - fc[d];
    hstampv[i] = heldepoch;
  }
  for (const auto &a : away) set_x(a.first, a.second.data());
  locf->set_labels(lab.data());
}

bool HSLocalEngine::holds() const
{
  return sys->nheld || !held_smooth.empty();
}

bool HSLocalEngine::rides() const
{
  return !held_smooth.empty();
}

bool HSLocalEngine::takes_captured_forces() const
{
  return sys->nheld != 0;
}

std::string HSLocalEngine::uncaptured_cost() const
{
  if (rides())
    return "the held thermostat forces ride inside the colliding spheres' flows with the "
           "held smooth forces, instead of two half kicks around them (pcva: substep global)";
  return HSStepEngine::uncaptured_cost();
}

// (captured(): the same answer on every rank)
bool HSLocalEngine::splits_held() const
{
  return sys->nheld && rides() && sys->captured(true) != nullptr;
}

// fix gravity's force on copy i (force units; f += m g in its post_force(),
// the same on every copy and rank); zero without one
void HSLocalEngine::const_force(int i, double *out) const
{
  out[0] = out[1] = out[2] = 0.0;
  for (const Gravity &g : gravity) {
    if (!(atom->mask[i] & g.groupbit)) continue;
    const double m = atom->rmass ? atom->rmass[i] : atom->mass[atom->type[i]];
    for (int d = 0; d < 3; d++) out[d] += m * g.gvec[d];
  }
}

/* ----------------------------------------------------------------------
   the cross terms' force on a cluster's members at the step's start,
   F_X(x0), with every atom in them put back at x0 (issue 19, doc "Step
   engines"): the cross force acts inside both halves of the members'
   flow, as F_X(x0) in the first and F_X at the members' ends in the
   second (cross_at_end()), instead of a kick dt F_X(x_mid) between them.
   A kick between the halves gives a contact inside a half the wrong
   normal velocity by 2 min(t_c, dt - t_c) a_X.n, O(dt); a constant force
   within each half errs by O(dt^2) at any time, and the total impulse is
   dt F_X(x_mid) to O(dt^3). Momentum is kept: each half's cross forces
   are those of the same positions on both clusters, equal and opposite.
------------------------------------------------------------------------- */

void HSLocalEngine::cross_at_start(Run &r, const std::vector<Vec> &fk, const std::vector<int> &mi)
{
  // F_X(x0) without an evaluation of its own: every term's force on a
  // member at x0 is LAMMPS' force of the step's start (its acceleration,
  // forwarded to ghost copies, so every rank computes the same) less the
  // held forces; the cluster's own and partner terms at x0 are fk (the
  // first half's start). What is left is the cross terms'
  const int nm = (int) r.members.size();
  r.fx0.assign(nm, Vec{0.0, 0.0, 0.0});
  // (fix gravity's force is in LAMMPS' start force and in no term of fk:
  // it is in F_X(x0) here, as cross_forces() puts it in F_X elsewhere)
  if (!force->pair && gravity.empty()) return;
  double **acc = sys->acc;
  const double ftm2v = force->ftm2v;
  const bool held = holds();
  for (int k = 0; k < nm; k++) {
    const int i = r.members[k];
    const double m = sys->mass_of(i) / ftm2v;
    for (int d = 0; d < 3; d++) {
      const double fall = acc[i][d] * m - (held ? held0[i][d] : 0.0);
      r.fx0[k][d] = fall - fk[mi[k]][d];
    }
  }
}

// F_X(x0) by an evaluation of the cross terms, where another fix integrates
// atoms outside the group: the shortcut above takes LAMMPS' force of the
// step's start, at those atoms' old positions, while fk sees them where that
// fix moved them before this one's turn (doc "Which pairs collide"), so
// the difference was no cross force: V_C's change by their move (on a
// solvent at density 0.6, 0.7 on a member whose force is 30), which the
// second half then took with the opposite sign (2 F_X(q_mid) - F_X(q0)) or
// not at all (the corrector's F_X(q_end), for clusters with a cross
// neighbour within the rows' reach): a trajectory that depended on when the
// lists were built. Other clusters' members whose first halves ran wait at
// their mid positions: back to x0 for the evaluation (all their copies, then
// restored bit for bit). Afterwards V_C's lists are the last evaluation
// again, for the flow's sub-steps
void HSLocalEngine::cross_at_start_evaluated(Run &r)
{
  const int nm = (int) r.members.size();
  r.fx0.assign(nm, Vec{0.0, 0.0, 0.0});
  if (!force->pair) {
    for (int k = 0; k < nm && !gravity.empty(); k++) const_force(r.members[k], r.fx0[k].data());
    return;
  }
  double **x = atom->x;
  const int key = lab[r.members[0]];
  cross_forces(r, r.fx0);
  std::vector<std::pair<int, Vec>> &away = scratch_away;
  away.clear();
  for (int t : locf->touched()) {
    if (lab[t] < 0 || lab[t] == key) continue;
    for (int k = atom->map(atom->tag[t]); k >= 0; k = atom->sametag[k])
      if (x[k][0] != x0[k][0] || x[k][1] != x0[k][1] || x[k][2] != x0[k][2]) {
        away.push_back({k, Vec{x[k][0], x[k][1], x[k][2]}});
        for (int d = 0; d < 3; d++) x[k][d] = x0[k][d];
      }
  }
  if (!away.empty()) {
    cross_forces(r, r.fx0);
    for (const auto &a : away)
      for (int d = 0; d < 3; d++) x[a.first][d] = a.second[d];
  }
  locf->recompute(r.snap);
  ncompute_here += 1.0;
}

/* ----------------------------------------------------------------------
   the cross terms (pair terms between members of two clusters) at the
   members' mid positions: F_X(x_mid), which sets the constant cross force
   of the second halves (see cross_at_start()). A cluster whose members'
   cross forces changed redoes its second half. The clusters whose members
   moved (ran a first half) recompute theirs; their cross neighbours before
   and after, on any rank, are told by one gather and recompute theirs
------------------------------------------------------------------------- */

void HSLocalEngine::cross_at_mid()
{
  if (!force->pair) {
    workX.clear();
    return;
  }
  // this rank's runs among the keys: their cross forces again, once each
  // (a mark on the run: a list searched for every key made this loop
  // quadratic in the clusters, 1.5 % of a step at 256000 atoms)
  if (++xepoch == 0) {
    runs.for_each([](tagint, Run &r) { r.xmark = 0; });
    xepoch = 1;
  }
  auto redo = [&](tagint key, std::vector<tagint> *nbrs) {
    const int c = clusters_of_key(key);
    if (c < 0) return;
    Run *r = run_of(key);
    if (!r || !r->mine || !r->a_done || r->xmark == xepoch) return;
    r->xmark = xepoch;
    std::vector<tagint> old = r->xnbrs;
    cross_of(*r);
    if (nbrs) {
      nbrs->insert(nbrs->end(), old.begin(), old.end());
      nbrs->insert(nbrs->end(), r->xnbrs.begin(), r->xnbrs.end());
    }
  };
  std::vector<tagint> wave2;
  std::sort(workX.begin(), workX.end());
  workX.erase(std::unique(workX.begin(), workX.end()), workX.end());
  for (tagint key : workX) {
    Run *r = run_of(key);
    if (r && r->mine) redo(key, &wave2);
    else wave2.push_back(key);    // another rank's (a neighbour of a run retired here)
  }
  workX.clear();
  // the neighbours, whichever rank runs them
  std::sort(wave2.begin(), wave2.end());
  wave2.erase(std::unique(wave2.begin(), wave2.end()), wave2.end());
  sendbuf.clear();
  for (tagint k : wave2) sendbuf.push_back((double) k);
  allgather(recvbuf);
  std::vector<tagint> all;
  for (double k : recvbuf) all.push_back((tagint) k);
  std::sort(all.begin(), all.end());
  all.erase(std::unique(all.begin(), all.end()), all.end());
  for (tagint key : all) redo(key, nullptr);
}

// the cross-term forces on one cluster's members (from all their cross
// terms at the members' current positions) and its cross neighbours
void HSLocalEngine::cross_forces(const Run &r, std::vector<Vec> &out, std::vector<int> *others)
{
  const int nm = (int) r.members.size();
  locf->set_labels(lab.data(), HSLocalForces::CROSS);
  out.resize(nm);
  // straight from the members' rows where that gives the evaluation's bits
  // (counted as the restricted evaluation it stands for)
  bool direct = false;
  static_assert(sizeof(Vec) == 3 * sizeof(double), "a Vec is three contiguous doubles");
  if (others) {
    others->clear();
    locf->set_reference(sys->xref);
    direct = locf->cross_rows(r.members.data(), nm, reinterpret_cast<double(*)[3]>(out.data()),
                              *others);
    if (direct) ncompute_here += 1.0;
  }
  if (!direct) vc(r.members.data(), nm);
  locf->set_labels(lab.data());
  double **fl = locf->forces();
  double fc[3] = {0.0, 0.0, 0.0};
  for (int k = 0; k < nm; k++) {
    const int i = r.members[k];
    // fix gravity's constant force rides with the cross force: a constant
    // force in each half of the members' flows (cross_at_start())
    if (!gravity.empty()) const_force(i, fc);
    const double *fi = direct ? out[k].data() : fl[i];
    out[k] = {fi[0] + fc[0], fi[1] + fc[1], fi[2] + fc[2]};
  }
  if (others && !direct)
    for (int t : locf->touched()) others->push_back(lab[t]);
}

void HSLocalEngine::cross_of(Run &r)
{
  std::vector<Vec> &fn = scratch_fx;
  std::vector<int> &others = scratch_others;
  cross_forces(r, fn, &others);
  const int key = lab[r.members[0]];
  r.xnbrs.clear();
  for (int l : others)
    if (l >= 0 && l != key) r.xnbrs.push_back((tagint) idtag[l]);
  std::sort(r.xnbrs.begin(), r.xnbrs.end());
  r.xnbrs.erase(std::unique(r.xnbrs.begin(), r.xnbrs.end()), r.xnbrs.end());
  const bool changed = fn != r.fx;
  r.fx.swap(fn);
  if (changed) r.fx1.clear();    // (its corrector's force, from other cross terms)
  if (changed && r.b_done) {
    r.b_done = false;
    workB.push_back(r.mtags[0]);
  }
}

/* ----------------------------------------------------------------------
   the corrector of the second halves' cross force (see cross_at_start()).
   A second half first runs with the extrapolation 2 F_X(q_mid) - F_X(q0),
   which is not time-symmetric: the reversed step would start its first
   half with F_X(q_end). Once the clusters are final, each of this rank's
   runs with cross terms takes F_X at the members' ends (its own and its
   cross neighbours', on any rank: the second halves' packets) and runs its
   second half again with it, once: a fixed-point iteration towards the
   time-symmetric F_X(q_end), whose one step leaves an O(dt^4) difference
   in the force (the extrapolation's O(dt^2), times (dt/2)^2 / m F_X';
   O(dt) and O(dt^3) with a contact in the second half).
   Collective; true if any rank redoes a second half
------------------------------------------------------------------------- */

bool HSLocalEngine::awaits_corrector(const Run &r) const
{
  return force->pair && !r.xnbrs.empty() && r.fx1.empty();
}

bool HSLocalEngine::cross_at_end()
{
  int redo = 0;
  if (force->pair) {
    double **x = atom->x;
    std::vector<tagint> keys;
    runs.for_each([&](tagint key, Run &r) {
      if (r.mine && r.b_done && awaits_corrector(r)) keys.push_back(key);
    });
    if (!keys.empty()) {
      // every member copy with a known end at its end (they wait at their
      // mid positions: put back below)
      std::vector<std::pair<int, Vec>> &saved = xend_saved;
      saved.clear();
      // (a run the corrector has run again: its provisional ends, so that
      // F_X(q_end) is the same whether a neighbour was corrected in an
      // earlier round of this step or not; a later round's correction of a
      // regrown cluster otherwise read its neighbours' corrected ends, and
      // the step's result depended on its number of rounds)
      runs.for_each([&](tagint, Run &r) {
        if (!r.b_done || r.dxe.size() != r.mtags.size()) return;
        const std::vector<Vec> &dx = r.dxp.size() == r.mtags.size() ? r.dxp : r.dxe;
        for (size_t k = 0; k < r.mtags.size(); k++)
          for (int l = atom->map(r.mtags[k]); l >= 0; l = atom->sametag[l]) {
            saved.push_back({l, {x[l][0], x[l][1], x[l][2]}});
            for (int d = 0; d < 3; d++) x[l][d] = x0[l][d] + dx[k][d];
          }
      });
      // in key order (the flows' order is free; this keeps the restricted
      // evaluations' sequence the same on any number of ranks)
      std::sort(keys.begin(), keys.end());
      for (tagint key : keys) {
        Run &r = *run_of(key);
        cross_forces(r, r.fx1, &scratch_others);
        r.b_done = false;
        workB.push_back(key);
        redo = 1;
      }
      for (auto it = saved.rbegin(); it != saved.rend(); ++it)
        for (int d = 0; d < 3; d++) x[it->first][d] = it->second[d];
    }
  }
  int any = redo;
  if (nprocs > 1) MPI_Allreduce(&redo, &any, 1, MPI_INT, MPI_MAX, world);
  ncollective += 1.0;
  return any != 0;
}

/* ----------------------------------------------------------------------
   the clusters grow by the hits (the same on every rank): a cluster that
   changed, or whose flows (on this rank) saw a new member as a partner or
   a static atom, is redone
------------------------------------------------------------------------- */

void HSLocalEngine::grow_clusters(std::vector<Hit> &hits)
{
  for (const Hit &h : hits) cs.grow_contact(id_of(h.i), h.j < 0 ? -1 : id_of(h.j));
  const std::vector<int> newm = cs.new_members();
  add_members(newm);
  const std::vector<int> redo = cs.rebuild();
  // a run whose flows saw a new member as a partner or a static atom is
  // redone too: the terms between them are cross terms now
  for (int m : newm)
    for (int l = atom->map((tagint) idtag[m]); l >= 0; l = atom->sametag[l])
      atom_runs.for_each(l, [&](tagint key) {
        Run *r = run_of(key);
        if (!r || !r->mine || r->members.empty()) return;
        retire(key);
        const int *id = idof.find(key);
        if (!id)
          error->one(FLERR, "Fix {} substep local: internal error: run {} is no member's",
                     sys->style_name, key);
        const int c = cs.cluster_of(*id);
        if (c >= 0) workA.push_back(key_of(c));
      });
  for (int c : redo) {
    label_cluster(c);
    workA.push_back(key_of(c));
    for (int m : cs.members(c)) retire((tagint) idtag[m]);
  }
  nrounds += 1.0;
}

// a run that is dropped (on every rank: its packets go too)
void HSLocalEngine::retire(tagint key)
{
  Run *rp = runs.find(key);
  if (!rp) return;
  Run &r = *rp;
  if (r.mine)
    for (tagint k : r.xnbrs) workX.push_back(k);    // their cross terms with it change
  if (r.in_sa) sa_change(r, -1.0);    // its sums go (h2_velocities)
  runs.erase(key);
}

// the cluster of a key, -1 if it is no longer a cluster's key
int HSLocalEngine::clusters_of_key(tagint key) const
{
  const int *id = idof.find(key);
  if (!id) return -1;
  const int c = cs.cluster_of(*id);
  return (c >= 0 && cs.members(c)[0] == *id) ? c : -1;
}

// clusters in the order of their runners' local copies (LAMMPS sorts atoms
// by space: neighbouring clusters share cells and pages). A flow reads and
// changes only its own cluster's atoms (other clusters' members enter
// through cross terms, evaluated apart), so the order is free
std::vector<int> HSLocalEngine::in_memory_order(std::vector<int> cl)
{
  std::vector<std::pair<int, int>> &o = scratch_order;
  o.clear();
  for (int c : cl) {
    const int l = atom->map(runner_of(c));
    o.emplace_back(l < 0 ? INT_MAX : l, c);
  }
  std::sort(o.begin(), o.end());
  for (size_t k = 0; k < o.size(); k++) cl[k] = o[k].second;
  return cl;
}

// keys -> cluster indices, once each, ascending (keys is emptied)
std::vector<int> HSLocalEngine::clusters_of(std::vector<tagint> &keys)
{
  std::vector<int> out;
  for (tagint key : keys) {
    const int c = clusters_of_key(key);
    if (c >= 0) out.push_back(c);
  }
  keys.clear();
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

/* ----------------------------------------------------------------------
   Phi_H1(h) of one cluster this rank runs: CVA sub-steps of its members
   under its terms of V_C; everyone else stays put (members of other
   clusters are checked afterwards, cross_check()). first_half: from the
   step's start (x0, v0 and the held half kick), else from the state after
   the first half with the non-members at their end positions. Returns
   false (hits gets the contact) if a member touches a non-member: C must
   grow.
------------------------------------------------------------------------- */

namespace {
// a cluster's flow as a method sees it (hs_flow_view.h)
class FlowView : public HSFlowView {
 public:
  Substep last{0.0, 0.0, 0.0, 0.0};
  std::function<Substep(const HSTypes::Impulse &)> trial_fn;
  const Substep &last_substep() const override { return last; }
  Substep trial(const HSTypes::Impulse &imp) override { return trial_fn(imp); }
  double gn = 0.0;    // set by the flow before a contact's modify_impulse_in_flow
  double approach_accel() const override { return gn; }
};
}    // namespace

bool HSLocalEngine::flow(Run &r, double h, bool first_half, std::vector<Hit> &hits)
{
  // a first half done again: its old sums go (h2_velocities)
  if (first_half && r.in_sa) sa_change(r, -1.0);
  HSSystem &F = *sys;
  double **x = atom->x, **v = atom->v;
  const tagint *tag = atom->tag;
  const double ftm2v = force->ftm2v;
  const std::vector<int> &M = r.members;
  const int nm = (int) M.size();
  const int c = cluster_of(M[0]);

  if (first_half) {
    held_of(r);
    for (int i : M) set_x(i, x0[i]);
  } else
    for (int k = 0; k < nm; k++) set_x(M[k], r.xm[k].data());
  // the flow's energies, if the method asks (hs_flow_view.h)
  const bool energies = meth.needs_flow_energy();
  // a provisional second half: F_X at the members' ends is not known yet
  // (cross terms, cross_at_end() not run since fx changed), so the
  // corrector runs this half again with it (awaits_corrector(): what
  // cross_at_end() picks; settle() runs it after every growth). Until then
  // only the run's end positions, contacts and segments are read: its last
  // sub-step stops at the drift (no evaluation at the step's end, no
  // closing kick, partner sums or method's check of that sub-step: the run
  // again replaces them, and only a final run's counts reach the method,
  // step_clusters())
  const bool provisional = !first_half && awaits_corrector(r);
  // the corrector's run again of a provisional second half, from where that
  // started (the same lists, every copy in its terms at the same place),
  // takes the forces of that start again (kept by the provisional run)
  bool same_start = !first_half && r.xB.size() == r.snap.zero_list.size() &&
      r.fkB.size() == r.touched.size();
  for (size_t k = 0; same_start && k < r.xB.size(); k++) {
    const double *xk = x[r.snap.zero_list[k]];
    same_start = xk[0] == r.xB[k][0] && xk[1] == r.xB[k][1] && xk[2] == r.xB[k][2];
  }
  // (a method's own flow takes the terms of these lists: recorded here,
  // with the lists the snapshot below keeps for the second half; an
  // evaluation of their own was 5 % of an mcva step)
  const bool own_flow = meth.runs_cluster_flows();
  if (first_half) {
    vc(M.data(), nm, own_flow);
    if (own_flow) {
      r.tnpair = locf->npair_last();
      locf->take_terms(r.tloc, r.toff, r.textra);
    }
  } else if (same_start)
    locf->restore(r.snap);
  else {
    locf->recompute(r.snap);    // the lists of the first half
    ncompute_here += 1.0;
  }
  std::vector<Vec> &env_saved = scratch_env;
  env_saved.clear();
  if (first_half) {
    locf->save(r.snap);
    r.touched = locf->touched();
    r.fkB.clear();    // (of the last snapshot's lists)
    r.xB.clear();
    // the static atoms of this flow: partners and contact candidates
    r.env.clear();
    for (int t : r.touched)
      if (!is_member(t)) r.env.push_back(t);
    for (int i : M) {
      int nc;
      const int *cr = crow(i, nc);
      for (int e = 0; e < nc; e++)
        if (!is_member(cr[e])) r.env.push_back(cr[e]);
    }
    // one copy per atom (set_x() moves all of an atom's copies together):
    // its lowest index here, as a sort by (ID, index) would keep (set_x()
    // places the other copies from it). The order is free: the list is
    // only set and restored copy by copy and enrolled atom by atom, so it
    // stays in the order found (a sort was ~1.3 % of a step at 32000 atoms)
    const tagint *tg = atom->tag;
    bump_epoch(envepoch, envstamp);
    std::vector<int> &slots = scratch_slots;
    slots.clear();
    for (int e : r.env) {
      const int c = atom->map(tg[e]);    // (any of its copies': the same slot)
      if (envstamp[c] != envepoch) {
        envstamp[c] = envepoch;
        envbest[c] = e;
        slots.push_back(c);
      } else if (e < envbest[c])
        envbest[c] = e;
    }
    r.env.clear();
    for (int c : slots) r.env.push_back(envbest[c]);
    // after the drift of Phi_H2 (a later growth round) they wait at x0 for
    // this flow, and go back to their end positions after it
    if (drifted) {
      env_saved.resize(r.env.size());
      for (size_t k = 0; k < r.env.size(); k++) {
        const int e = r.env[k];
        env_saved[k] = {x[e][0], x[e][1], x[e][2]};
        set_x(e, x0[e]);
      }
      locf->recompute();
      ncompute_here += 1.0;
    }
  } else if (locf->touched() != r.touched)
    error->one(FLERR, "Fix {} substep local: the terms of a cluster changed within step {}",
               F.style_name, update->ntimestep);
  const std::vector<int> &T = r.touched;
  const int nt = (int) T.size();
  std::vector<Vec> &fk = scratch_fk, &fk1 = scratch_fk1;
  fk.resize(nt);
  fk1.resize(nt);
  double **fl = locf->forces();
  if (same_start)
    fk = r.fkB;
  else
    for (int k = 0; k < nt; k++) fk[k] = {fl[T[k]][0], fl[T[k]][1], fl[T[k]][2]};
  if (provisional && !same_start) {
    r.fkB = fk;
    r.eB = energies ? locf->energy() : 0.0;
    const std::vector<int> &Z = r.snap.zero_list;
    r.xB.resize(Z.size());
    for (size_t k = 0; k < Z.size(); k++) r.xB[k] = {x[Z[k]][0], x[Z[k]][1], x[Z[k]][2]};
  }
  // where each member sits in T
  std::vector<int> &mi = scratch_mi;
  mi.resize(nm);
  for (int k = 0; k < nm; k++) {
    const auto it = std::find(T.begin(), T.end(), M[k]);
    if (it == T.end())
      error->one(FLERR, "Fix {} substep local: internal error: member {} not in its own terms",
                 F.style_name, r.mtags[k]);
    mi[k] = (int) (it - T.begin());
  }
  if (first_half) {
    if (F.other_integrator) cross_at_start_evaluated(r);
    else cross_at_start(r, fk, mi);
  }
  // the constant cross force on the members in this half: F_X(q0) in the
  // first; in the second F_X at the members' ends once cross_at_end() found
  // it (fx1), before that the extrapolation 2 F_X(q_mid) - F_X(q0) (fx once
  // cross_at_mid() ran, else F_X(q0) again)
  std::vector<Vec> &fc = scratch_fc;
  const bool mid_known = (int) r.fx.size() == nm;
  fc.resize(nm);
  for (int k = 0; k < nm; k++)
    for (int d = 0; d < 3; d++)
      fc[k][d] = (first_half || !mid_known) ? r.fx0[k][d] :
          ((int) r.fx1.size() == nm ? r.fx1[k][d] : 2.0 * r.fx[k][d] - r.fx0[k][d]);
  // held smooth forces (kspace, force fixes) ride as the constant force
  // G(q0) = f - F_C in both halves, as the cross force does: held as a kick
  // before the flow, a contact at t_c inside the step would get the normal
  // velocity wrong by O(G dt) (a sphere bouncing under a constant force:
  // first order in energy, measured); inside, by O(dt^2). The closing kick
  // makes the step's impulse dt/2 (G(q0) + G(q1)) (second halves' end)
  // (split_: the thermostat's part, kick0, stays a half kick; G rides)
  if (rides())
    for (int k = 0; k < nm; k++)
      for (int d = 0; d < 3; d++) fc[k][d] += riding(M[k], d);
  if (first_half) {
    r.fk0 = fk;
    // the held forces' half kick (f - F_C: LAMMPS' forces minus V_C's)
    for (int k = 0; k < nm; k++) {
      const int i = M[k];
      double vn[3] = {v0[i][0], v0[i][1], v0[i][2]};
      if ((holds() && !rides()) || split_) {
        const double dtfm = F.dtf / F.mass_of(i);
        double **h = split_ ? kick0 : held0;
        for (int d = 0; d < 3; d++) vn[d] += dtfm * h[i][d];
      }
      set_v(i, vn);
    }
  } else
    for (int k = 0; k < nm; k++) set_v(M[k], r.vm[k].data());

  std::vector<Vec> &dv = first_half ? r.dvA : r.dvB;
  dv.assign(nt, Vec{0.0, 0.0, 0.0});
  std::vector<std::vector<Seg>> &segs = first_half ? r.segsA : r.segsB;
  segs.resize(nm);
  for (auto &sg : segs) sg.clear();
  std::vector<double> &im = scratch_im;
  im.resize(nm);
  for (int k = 0; k < nm; k++) im[k] = ftm2v / F.mass_of(M[k]);
  auto member_k = [&](int o) {    // index of copy o's atom in M, -1 if not in this cluster
    if (cluster_of(o) != c) return -1;
    return (int) (std::lower_bound(r.mtags.begin(), r.mtags.end(), tag[o]) - r.mtags.begin());
  };

  // this flow's collisions and impulse virial, kept apart from the fix's
  const int half = first_half ? 0 : 1;
  double vir_saved[6], npair_saved = F.ncoll_pair, nwall_saved = F.ncoll_wall;
  for (int k = 0; k < 6; k++) vir_saved[k] = F.host->virial[k];
  auto keep_counts = [&]() {
    r.npair[half] = F.ncoll_pair - npair_saved;
    r.nwall[half] = F.ncoll_wall - nwall_saved;
    for (int k = 0; k < 6; k++) {
      r.vir[half][k] = F.host->virial[k] - vir_saved[k];
      F.host->virial[k] = vir_saved[k];
    }
    F.ncoll_pair = npair_saved;
    F.ncoll_wall = nwall_saved;
    meth.take_flow_counts(r.mcount[half]);
  };

  // the next contact of the flow within tau: members against each other,
  // their contact candidates (a static non-member: the cluster grows) and
  // the walls, on the Verlet paths of the current sub-step
  struct Next {
    double t = BIG;
    int bi = -1, bwall = -1, bli = -1, blj = -1;
    bool bstatic = false;
  };
  auto search = [&](double tau) {
    Next b;
    for (int k = 0; k < nm; k++) {
      const int i = M[k];
      const double *a = fk[mi[k]].data();
      const double ai[3] = {(a[0] + fc[k][0]) * im[k], (a[1] + fc[k][1]) * im[k],
                            (a[2] + fc[k][2]) * im[k]};
      const double vv = sqrt(v[i][0] * v[i][0] + v[i][1] * v[i][1] + v[i][2] * v[i][2]);
      const double aa = sqrt(ai[0] * ai[0] + ai[1] * ai[1] + ai[2] * ai[2]);
      const double Di = tau * vv + 0.5 * tau * tau * aa;
      const double ri = F.radius_of(i);
      for (int wl = 0; wl < (int) F.walls.size(); wl++) {
        const Wall &W = F.walls[wl];
        const double g = F.wall_gap(W, x[i], ri);
        if (g > Di) continue;
        const Contact ct = wall_contact(i, wl, g, v[i][W.dim], ai[W.dim], tau);
        if (ct.status != HardSphere::NO_CONTACT && ct.t < b.t) {
          b.t = ct.t;
          b.bi = i;
          b.bwall = wl;
          b.bli = i;
          b.blj = -1;
          b.bstatic = false;
        }
      }
      int ncr;
      const int *cr = crow(i, ncr);
      for (int e = 0; e < ncr; e++) {
        const int theirs = cr[e];
        const int ko = member_k(theirs);
        double vo[3] = {0.0, 0.0, 0.0}, ao[3] = {0.0, 0.0, 0.0}, Do = 0.0;
        if (ko >= 0) {
          if (tag[theirs] < tag[i]) continue;    // the pair is handled from its lower member
          const int o = M[ko];
          const double *bb = fk[mi[ko]].data();
          for (int d = 0; d < 3; d++) {
            vo[d] = v[o][d];
            ao[d] = (bb[d] + fc[ko][d]) * im[ko];
          }
          Do = tau * sqrt(vo[0] * vo[0] + vo[1] * vo[1] + vo[2] * vo[2]) +
              0.5 * tau * tau * sqrt(ao[0] * ao[0] + ao[1] * ao[1] + ao[2] * ao[2]);
        } else if (is_member(theirs))
          continue;    // another cluster's member: cross_check()
        const double sigma = ri + F.radius_of(theirs);
        const double dq[3] = {x[i][0] - x[theirs][0], x[i][1] - x[theirs][1],
                              x[i][2] - x[theirs][2]};
        const double r2 = dq[0] * dq[0] + dq[1] * dq[1] + dq[2] * dq[2];
        const double reach = sigma + Di + Do;
        if (r2 > reach * reach) continue;
        const double dvv[3] = {v[i][0] - vo[0], v[i][1] - vo[1], v[i][2] - vo[2]};
        const double da[3] = {ai[0] - ao[0], ai[1] - ao[1], ai[2] - ao[2]};
        const Contact ct = pair_contact(i, theirs, dq, dvv, da, sigma, tau);
        if (ct.status != HardSphere::NO_CONTACT && ct.t < b.t) {
          b.t = ct.t;
          b.bi = i;
          b.bwall = -1;
          b.bli = i;
          b.blj = theirs;
          b.bstatic = ko < 0;
        }
      }
    }
    return b;
  };
  // the first half kick and drift of a sub-step of length d (the members)
  auto kick_drift = [&](double d) {
    const double dtfk = 0.5 * d * ftm2v;
    for (int k = 0; k < nm; k++) {
      const int i = M[k];
      const double dtfm = dtfk / F.mass_of(i);
      double vn[3], xn[3];
      for (int dd = 0; dd < 3; dd++) {
        vn[dd] = v[i][dd] + dtfm * (fk[mi[k]][dd] + fc[k][dd]);
        xn[dd] = x[i][dd] + d * vn[dd];
      }
      set_xv(i, xn, vn);
    }
  };

  // the flow's energies (above): V_C of the restricted terms minus
  // f_X . (q - q_start), 1/2 |v|^2_M of the members
  std::vector<Vec> &xs = scratch_xs;
  if (energies) {
    xs.resize(nm);
    for (int k = 0; k < nm; k++) xs[k] = {x[M[k]][0], x[M[k]][1], x[M[k]][2]};
  }
  auto potential = [&]() {
    double V = locf->energy();
    for (int k = 0; k < nm; k++)
      for (int d = 0; d < 3; d++) V -= fc[k][d] * (x[M[k]][d] - xs[k][d]);
    return V;
  };
  auto kinetic = [&]() {
    double K = 0.0;
    for (int i : M) K += F.mass_of(i) * (v[i][0] * v[i][0] + v[i][1] * v[i][1] + v[i][2] * v[i][2]);
    return 0.5 * force->mvv2e * K;
  };
  double t = 0.0;
  FlowView view;
  double Vnow = 0.0;
  // the last trial's sub-step (vci): a root is the impulse of the root
  // solve's last trial, bit for bit, so the sub-step after the contact is
  // that trial's: its contact search, and its end evaluation, which the
  // restricted forces still hold (the trial restores x and v only)
  bool kept = false, kept_eval = false, reuse = false, reuse_eval = false;
  Impulse kept_imp;
  Next kept_nb;
  auto same_impulse = [](const Impulse &a, const Impulse &b) {
    return a.type == b.type && a.itag == b.itag && a.jtag == b.jtag && a.wall == b.wall &&
        a.apply == b.apply && a.reflect == b.reflect && a.J[0] == b.J[0] && a.J[1] == b.J[1] &&
        a.J[2] == b.J[2];
  };
  if (energies) {
    Vnow = same_start ? r.eB : potential();    // (at the start x = xs)
    view.last = {0.0, kinetic(), Vnow, Vnow};
    meth.flow_begun(view);
    // the sub-step the flow would take after the contact's impulse imp
    view.trial_fn = [&](const Impulse &ti) {
      std::vector<Vec> &sv = scratch_sv, &sx = scratch_sx;
      sv.resize(nm);
      sx.resize(nm);
      for (int k = 0; k < nm; k++) {
        sv[k] = {v[M[k]][0], v[M[k]][1], v[M[k]][2]};
        sx[k] = {x[M[k]][0], x[M[k]][1], x[M[k]][2]};
      }
      F.apply_impulse(ti);
      const Next nb = search(h - t);
      HSFlowView::Substep s{nb.t <= h - t ? nb.t : h - t, 0.0, Vnow, Vnow};
      if (s.tau > 0.0) {
        kick_drift(s.tau);
        s.kh = kinetic();
        locf->recompute();
        ncompute_here += 1.0;
        s.v1 = potential();
        // d/dlambda of kh and v1 for the impulse lambda J (the sub-step's
        // length held: not where it ends at a contact): the members' v_h
        // and q_end move by +-J/m and +-tau J/m (i: +, j: -), so dkh =
        // mvv2e (v_h,i - v_h,j) . J and dv1 = -sum (f + f_X) . dq_end
        if (nb.t > h - t) {
          double **fe = locf->forces();
          s.dkh = s.dv1 = 0.0;
          for (int k = 0; k < nm; k++) {
            const int i = M[k];
            const double sg = tag[i] == ti.itag ? 1.0 :
                (ti.type == PAIR_EVENT && tag[i] == ti.jtag) ? -1.0 : 0.0;
            if (sg == 0.0) continue;
            const double dq = sg * s.tau / F.mass_of(i);
            for (int dd = 0; dd < 3; dd++) {
              s.dkh += sg * force->mvv2e * v[i][dd] * ti.J[dd];
              s.dv1 -= (fe[i][dd] + fc[k][dd]) * dq * ti.J[dd];
            }
          }
        }
      } else
        s.kh = kinetic();
      kept = true;
      kept_eval = s.tau > 0.0;
      kept_imp = ti;
      kept_nb = nb;
      for (int k = 0; k < nm; k++) {
        set_xv(M[k], sx[k].data(), sv[k].data());
      }
      return s;
    };
  }
  // a method's own flow (mcva): the members' end, paths, partner kicks and
  // impulses from it; the end forces from V_C's terms as after CVA's last
  // sub-step (a provisional second half keeps the start's, as above)
  bool method_ran = false;
  if (own_flow) {
    HSClusterFlowJob &job = scratch_job;
    job.h = h;
    job.members = M;
    job.fc.resize(3 * nm);
    for (int k = 0; k < nm; k++)
      for (int d = 0; d < 3; d++) job.fc[3 * k + d] = fc[k][d];
    // (the terms of r.snap's lists, as the first half's start recorded them)
    job.tloc = &r.tloc;
    job.toff = &r.toff;
    job.textra = &r.textra;
    job.npair = r.tnpair;
    // the static spheres it may touch: the members' contact candidates
    // that are no member (another cluster's: cross_check())
    job.statics.clear();
    for (int i : M) {
      int ncr;
      const int *cr = crow(i, ncr);
      for (int e = 0; e < ncr; e++)
        if (!is_member(cr[e]) &&
            std::find(job.statics.begin(), job.statics.end(), cr[e]) == job.statics.end())
          job.statics.push_back(cr[e]);
    }
    job.partners.clear();
    std::vector<int> &pk = scratch_pk;    // the partners' index in T
    pk.clear();
    for (int k = 0; k < nt; k++) {
      const int p = T[k];
      if (is_member(p) || !(atom->mask[p] & F.groupbit)) continue;
      job.partners.push_back(p);
      pk.push_back(k);
    }
    meth.cluster_flow(job);
    if (job.result == HSClusterFlowJob::GROWS) {
      hits.push_back({tag[job.hit_member], tag[job.hit_static]});
      r.a_done = false;
      keep_counts();
      for (size_t k = 0; k < env_saved.size(); k++) set_x(r.env[k], env_saved[k].data());
      return false;
    }
    for (int k = 0; k < nm; k++) {
      for (const HSClusterFlowJob::Seg &js : job.segs[k]) {
        Seg sg;
        sg.t0 = js.t0;
        sg.t1 = js.t1;
        for (int dd = 0; dd < 3; dd++) {
          sg.q[dd] = js.q[dd] - x0[M[k]][dd];
          sg.v[dd] = js.v[dd];
          sg.a[dd] = js.a[dd];
        }
        segs[k].push_back(sg);
      }
      set_xv(M[k], &job.xend[3 * k], &job.vend[3 * k]);
    }
    for (size_t q = 0; q < pk.size(); q++)
      for (int dd = 0; dd < 3; dd++) dv[pk[q]][dd] += job.dvp[3 * q + dd];
    for (const HSClusterFlowJob::Kick &kk : job.kicks) {
      Impulse imp;
      memset(&imp, 0, sizeof(imp));
      imp.type = kk.j < 0 ? WALL_EVENT : PAIR_EVENT;
      imp.itag = tag[kk.i];
      imp.jtag = kk.j < 0 ? 0 : tag[kk.j];
      imp.wall = kk.j < 0 ? -1 - kk.j : 0;
      imp.apply = 1;
      for (int dd = 0; dd < 3; dd++) {
        imp.J[dd] = kk.J[dd];
        imp.dq[dd] = kk.dq[dd];
      }
      F.add_impulse_virial(imp);
      (kk.j < 0 ? F.ncoll_wall : F.ncoll_pair) += 1.0;
    }
    // (V_C's lists are r.snap's still: the method's flow evaluates its own
    // terms, and the terms it took were recorded at the first half's start)
    if (!provisional) {
      locf->recompute();
      ncompute_here += 1.0;
      fl = locf->forces();
      for (int k = 0; k < nt; k++) fk[k] = {fl[T[k]][0], fl[T[k]][1], fl[T[k]][2]};
    }
    method_ran = true;
  }
  int stuck = 0;
  bigint nsub = 0;
  while (!method_ran) {
    const double tau = h - t;
    const Next b = reuse ? kept_nb : search(tau);
    reuse = false;
    const bool hit = b.t <= tau;
    if (hit && b.bstatic) {    // a non-member: it joins C, the cluster is redone
      hits.push_back({tag[b.bli], tag[b.blj]});
      r.a_done = false;
      keep_counts();
      for (size_t k = 0; k < env_saved.size(); k++) set_x(r.env[k], env_saved[k].data());
      return false;
    }
    const double d = hit ? b.t : tau;
    if (d > 0.0) {
      const double dtfk = 0.5 * d * ftm2v;
      for (int k = 0; k < nm; k++) {
        const int i = M[k];
        Seg s;
        s.t0 = t;
        s.t1 = t + d;
        for (int dd = 0; dd < 3; dd++) {
          s.q[dd] = x[i][dd] - x0[i][dd];
          s.v[dd] = v[i][dd];
          s.a[dd] = (fk[mi[k]][dd] + fc[k][dd]) * im[k];
        }
        segs[k].push_back(s);
      }
      kick_drift(d);
      if (provisional && !hit) break;    // (above)
      const double kh = energies ? kinetic() : 0.0;
      if (!reuse_eval) {
        locf->recompute();    // the same terms: their restricted lists again
        ncompute_here += 1.0;
      }
      reuse_eval = false;
      fl = locf->forces();
      // the new forces, and in the same pass the partners, which stay put
      // and take V_C's momentum (trapezoid over the sub-step)
      const int *mask = atom->mask;
      for (int k = 0; k < nt; k++) {
        const int p = T[k];
        fk1[k] = {fl[p][0], fl[p][1], fl[p][2]};
        if (is_member(p) || !(mask[p] & F.groupbit)) continue;
        const double dtfm = dtfk / F.mass_of(p);
        for (int dd = 0; dd < 3; dd++) dv[k][dd] += dtfm * (fk[k][dd] + fk1[k][dd]);
      }
      for (int k = 0; k < nm; k++) {
        const int i = M[k];
        const double dtfm = dtfk / F.mass_of(i);
        const double vn[3] = {v[i][0] + dtfm * (fk1[mi[k]][0] + fc[k][0]),
                              v[i][1] + dtfm * (fk1[mi[k]][1] + fc[k][1]),
                              v[i][2] + dtfm * (fk1[mi[k]][2] + fc[k][2])};
        set_v(i, vn);
      }
      fk.swap(fk1);
      stuck = 0;
      if (energies) {
        const double V1 = potential();
        view.last = {d, kh, Vnow, V1};
        Vnow = V1;
        meth.flow_substep(view);
      }
    } else if (hit && energies && t > 0.0) {
      view.last = {0.0, kinetic(), Vnow, Vnow};
      meth.flow_substep(view);
    }
    if (!hit) break;

    // the contact: the method's collision operator (CVA: R of section 2)
    Impulse imp;
    memset(&imp, 0, sizeof(imp));
    imp.type = (b.bwall >= 0) ? WALL_EVENT : PAIR_EVENT;
    imp.itag = tag[b.bi];
    imp.jtag = (b.bwall >= 0) ? 0 : tag[b.blj];
    imp.wall = b.bwall;
    if (b.bwall >= 0) meth.collide_wall(b.bli, F.walls[b.bwall], imp);
    else meth.collide_pair(b.bli, b.blj, imp);
    t += d;
    if (imp.apply && energies) {
      // the contact's normal approach acceleration (HSFlowView::approach_accel)
      auto acc_of = [&](int i, double *a) {
        const int k = member_k(i);
        for (int dd = 0; dd < 3; dd++) a[dd] = (fk[mi[k]][dd] + fc[k][dd]) * im[k];
      };
      double ai[3], ao[3] = {0.0, 0.0, 0.0};
      acc_of(b.bi, ai);
      if (b.bwall < 0) acc_of(b.blj, ao);
      view.gn = F.approach_accel(imp, ai, ao);
    }
    if (imp.apply) meth.modify_impulse_in_flow(imp, view);
    if (imp.apply) F.add_impulse_virial(imp);
    F.apply_impulse(imp);
    // (the state is the last trial's after its impulse: trials restore it)
    reuse = kept && same_impulse(imp, kept_imp);
    reuse_eval = reuse && kept_eval;
    kept = false;
    if (imp.apply) {
      if (b.bwall >= 0) F.ncoll_wall += 1.0;
      else F.ncoll_pair += 1.0;
    } else if (d == 0.0 && ++stuck > MAX_STUCK)
      F.resting_contact_error(imp, false);
    F.check_runaway(++nsub, false);
  }

  keep_counts();
  if (first_half) {
    r.xm.resize(nm);
    r.dxm.resize(nm);
    r.vm.resize(nm);
    for (int k = 0; k < nm; k++) {
      const int i = M[k];
      r.xm[k] = {x[i][0], x[i][1], x[i][2]};
      r.dxm[k] = {x[i][0] - x0[i][0], x[i][1] - x0[i][1], x[i][2] - x0[i][2]};
      r.vm[k] = {v[i][0], v[i][1], v[i][2]};
    }
    r.a_done = true;
    r.dxp.clear();
    for (size_t k = 0; k < env_saved.size(); k++) set_x(r.env[k], env_saved[k].data());
  } else {
    // the end state is kept; the members wait at xm again (where Phi_H2's
    // checks of later growth rounds see them)
    r.fend = fk;
    r.dxe.resize(nm);
    r.ve.resize(nm);
    for (int k = 0; k < nm; k++) {
      const int i = M[k];
      r.dxe[k] = {x[i][0] - x0[i][0], x[i][1] - x0[i][1], x[i][2] - x0[i][2]};
      r.ve[k] = {v[i][0], v[i][1], v[i][2]};
      // (riding: the closing kick adds dt/2 G(q1); here -dt/2 G(q0))
      if (rides()) {
        const double dtfm = F.dtf / F.mass_of(i);
        for (int d = 0; d < 3; d++) r.ve[k][d] -= dtfm * riding(i, d);
      }
      set_xv(i, r.xm[k].data(), r.vm[k].data());
    }
    r.b_done = true;
    if (provisional) r.dxp = r.dxe;
  }
  return true;
}

/* ----------------------------------------------------------------------
   contacts between members of two clusters, whose flows ran apart: on
   their piecewise Verlet paths (the segments of the last flow, from the
   registry for another rank's cluster). Only pairs with a cluster in fresh
   (the same on every rank): the others were checked; each pair by the
   runner of its fresh cluster (of the lower one if both are fresh)
------------------------------------------------------------------------- */

void HSLocalEngine::cross_check(bool first_half, const std::vector<int> &fresh,
                                std::vector<Hit> &hits)
{
  HSSystem &F = *sys;
  const tagint *tag = atom->tag;
  double cc[5];
  std::vector<char> isfresh(cs.nclusters(), 0);
  for (int c : fresh) isfresh[c] = 1;
  auto pos = [](const Seg &s, double t, int d) {
    const double h = t - s.t0;
    return s.q[d] + h * s.v[d] + 0.5 * h * h * s.a[d];
  };
  auto vel = [](const Seg &s, double t, int d) { return s.v[d] + (t - s.t0) * s.a[d]; };
  auto path = [](const std::vector<Seg> &S) {
    double p = 0.0;
    for (const Seg &s : S) {
      const double d = s.t1 - s.t0;
      p += d * sqrt(s.v[0] * s.v[0] + s.v[1] * s.v[1] + s.v[2] * s.v[2]) +
          0.5 * d * d * sqrt(s.a[0] * s.a[0] + s.a[1] * s.a[1] + s.a[2] * s.a[2]);
    }
    return p;
  };
  for (int c : fresh) {
    const Run *rp = run_of(key_of(c));
    if (!rp || !rp->mine) continue;
    const Run &r = *rp;
    const std::vector<int> &M = r.members;
    for (int k = 0; k < (int) M.size(); k++) {
      const int i = M[k];
      int ncr;
      const int *cr = crow(i, ncr);
      for (int e = 0; e < ncr; e++) {
        const int o = cr[e];
        if (!is_member(o)) continue;
        const int oc = cluster_of(o);
        if (oc == c || (isfresh[oc] && oc < c)) continue;    // same, or done from oc
        const Run *rop = run_of(key_of(oc));
        if (!rop) continue;
        const Run &ro = *rop;
        const int ko = (int) (std::lower_bound(ro.mtags.begin(), ro.mtags.end(), tag[o]) -
                              ro.mtags.begin());
        const std::vector<std::vector<Seg>> &Si = first_half ? r.segsA : r.segsB;
        const std::vector<std::vector<Seg>> &Sj = first_half ? ro.segsA : ro.segsB;
        if (k >= (int) Si.size() || ko >= (int) Sj.size()) continue;
        const std::vector<Seg> &si = Si[k], &sj = Sj[ko];
        if (si.empty() || sj.empty()) continue;
        // segments are displacements from each copy's start position
        double base[3];
        for (int d = 0; d < 3; d++) base[d] = x0[i][d] - x0[o][d];
        const double sigma = F.radius_of(i) + F.radius_of(o);
        double dq0[3];
        for (int d = 0; d < 3; d++) dq0[d] = base[d] + si[0].q[d] - sj[0].q[d];
        const double r0 = sqrt(dq0[0] * dq0[0] + dq0[1] * dq0[1] + dq0[2] * dq0[2]);
        if (r0 > sigma + path(si) + path(sj)) continue;
        // walk the common breakpoints
        size_t a = 0, b = 0;
        double t = si[0].t0;
        const double tend_all = std::min(si.back().t1, sj.back().t1);
        bool found = false;
        while (!found && t < tend_all && a < si.size() && b < sj.size()) {
          const double tend = std::min(si[a].t1, sj[b].t1);
          if (tend > t) {
            double dq[3], dv[3], da[3];
            for (int d = 0; d < 3; d++) {
              dq[d] = base[d] + (pos(si[a], t, d) - pos(sj[b], t, d));
              dv[d] = vel(si[a], t, d) - vel(sj[b], t, d);
              da[d] = si[a].a[d] - sj[b].a[d];
            }
            HardSphere::pair_gap_poly(dq, dv, da, sigma, cc);
            const Contact ct = HardSphere::first_contact(cc, 4, tend - t,
                                                         TOUCH_TOL * sigma * sigma, false);
            if (ct.status != HardSphere::NO_CONTACT) found = true;
          }
          t = tend;
          if (si[a].t1 <= t) a++;
          if (b < sj.size() && sj[b].t1 <= t) b++;
        }
        if (found) hits.push_back({tag[i], tag[o]});
      }
    }
  }
}

/* ----------------------------------------------------------------------
   Phi_H2's velocities: the sums over the live clusters' first halves
   (V_C's start force, partner kicks, count) on every copy they touch are
   reversed into the owners, which set w = v0 + dt/2 (f - F_C(x0)) / m plus
   the first half's partner kicks (zero for a member; fix nve's kick for an
   atom in no term of V_C), the "may touch" flag and the free gap, and
   forward them to the ghosts
------------------------------------------------------------------------- */

void HSLocalEngine::sa_change(Run &r, double sign)
{
  const int *mask = atom->mask;
  const size_t nt = r.touched.size();
  // (rows all over memory, added in key order: HardSphere::prefetch_row())
  for (size_t k = 0; k < nt; k++) {
    if (k + HardSphere::PREFETCH_AHEAD < nt)
      HardSphere::prefetch_row(dsa[0], 7, r.touched[k + HardSphere::PREFETCH_AHEAD], true);
    const int p = r.touched[k];
    if (dstamp_sa[p] != dsepoch) {
      dstamp_sa[p] = dsepoch;
      dsa_rows.push_back(p);
    }
    double *row = HardSphere::row_at(dsa[0], 7, p);
    for (int d = 0; d < 3; d++) row[d] += sign * r.fk0[k][d];
    if (mask[p] & sys->groupbit)
      for (int d = 0; d < 3; d++) row[3 + d] += sign * r.dvA[k][d];
    row[6] += sign;
  }
  r.in_sa = sign > 0.0;
}

void HSLocalEngine::h2_velocities(bool full)
{
  HSSystem &F = *sys;
  const int nlocal = atom->nlocal;
  const int *mask = atom->mask;
  double **f = atom->f;
  if (full) {    // a new step: the last step's sums (and changes left) back to zero
    for (int l : sa_used) {
      for (int d = 0; d < 7; d++) sa[l][d] = 0.0;
      in_used[l] = 0;
    }
    sa_used.clear();
    for (int l : dsa_rows)
      for (int d = 0; d < 7; d++) dsa[l][d] = 0.0;
    bump_epoch(dsepoch, dstamp_sa);
    dsa_rows.clear();
  }
  // the runs whose first half is new since the last call add their sums
  // (those redone or retired took theirs back already), in key order; the
  // changes go to the owners, who add them to their sums
  for (tagint key : my_keys()) {
    Run &r = *run_of(key);
    if (r.a_done && !r.in_sa) sa_change(r, 1.0);
  }
  F.reverse_columns(dsa, 7, &dsa_rows);
  ncollective += 1.0;
  std::vector<int> &rows = scratch_wrows;
  rows.clear();
  // the owned rows with changes, in index order: dsa_rows lists the runs'
  // members and partners cluster by cluster, all over memory (~140000 rows
  // per step at 256000 atoms on one rank); in index order the reads of dsa,
  // sa and in_used go forward through memory (RowSet sorts and dedupes)
  rowset.reset(nlocal);
  for (int l : dsa_rows) {
    if (l < nlocal)
      rowset.add(l);
    else    // (a ghost's changes went to its owner)
      for (int d = 0; d < 7; d++) dsa[l][d] = 0.0;
  }
  auto add_changes = [&](int l) {
    double *a = sa[l];
    for (int d = 0; d < 7; d++) {
      a[d] += dsa[l][d];
      dsa[l][d] = 0.0;
    }
    // no cluster left on it: exactly fix nve's kick again (no round-off
    // of sums that cancel)
    if (a[6] == 0.0)
      for (int d = 0; d < 6; d++) a[d] = 0.0;
    if (!in_used[l]) {
      in_used[l] = 1;
      sa_used.push_back(l);
    }
  };
  // (full: in the pass over every owned row below, which reads the same
  // rows of sa)
  if (!full)
    rowset.for_each([&](int l) {
      add_changes(l);
      rows.push_back(l);
    });
  bump_epoch(dsepoch, dstamp_sa);
  dsa_rows.clear();
  wchanged.clear();
  // owned row i of w: velocity and "may touch" flag (a row with partner
  // sums is in sa_used: in_used first, so a full pass reads sa only there);
  // dev: the largest deviation of a line with sums from fix nve's,
  // |w - (v0 + dtfm f)|, so far
  auto w_row = [&](int i, double *wn, double *dev) {
    const bool sums = in_used[i] && sa[i][6] > 0.0;
    if (!(mask[i] & F.groupbit) || is_member(i))
      wn[0] = wn[1] = wn[2] = 0.0;
    else {
      const double dtfm = F.dtf / F.mass_of(i);
      if (sums) {
        for (int d = 0; d < 3; d++) wn[d] = v0[i][d] + dtfm * (f[i][d] - sa[i][d]) + sa[i][3 + d];
        if (dev) {
          double d2 = 0.0;
          for (int d = 0; d < 3; d++) {
            const double e = wn[d] - (v0[i][d] + dtfm * f[i][d]);
            d2 += e * e;
          }
          *dev = std::max(*dev, sqrt(d2));
        }
      } else
        for (int d = 0; d < 3; d++) wn[d] = v0[i][d] + dtfm * f[i][d];
    }
    return (cols[i][1] != 0.0 || sums || is_member(i)) ? 1.0 : 0.0;
  };
  if (full) {
    // every owned row, every ghost row forwarded: nothing to compare (the
    // changes a later call lists are relative to this one). In the same
    // pass, the sums' changes (in index order, as above) and the largest
    // deviation of a line from fix nve's, |w - (v0 + dtfm f)| over the
    // rows with sums, for h2_check(true): read here, where the rows are
    // read in order, it costs no pass of its own over those rows (at
    // 256000 atoms ~140000 of them, listed in the order clusters first
    // touched them: a miss per row)
    double dev = 0.0;
    for (int i = 0; i < nlocal; i++) {
      if (rowset.has(i)) add_changes(i);
      double *wi = wq[i];
      wi[3] = w_row(i, wi, &dev);
    }
    line_dev = dev;
    line_dev_valid = true;
    F.forward_columns(wq, 4);
    ncollective += 1.0;
    return;
  }
  rows.insert(rows.end(), moved.begin(), moved.end());    // new members: w = 0
  std::vector<int> &send = scratch_wsend;
  send.clear();
  // each owned row once (a new member may also have had its sums changed)
  bump_epoch(wepoch, wstamp);
  for (int i : rows) {
    if (i >= nlocal || wstamp[i] == wepoch) continue;
    wstamp[i] = wepoch;
    double *wi = wq[i];
    double wn[3];
    const double flag = w_row(i, wn, nullptr);
    bool ch = flag != wi[3];
    wi[3] = flag;
    if (wn[0] != wi[0] || wn[1] != wi[1] || wn[2] != wi[2]) {
      wchanged.push_back(i);
      ch = true;
    }
    wi[0] = wn[0];
    wi[1] = wn[1];
    wi[2] = wn[2];
    if (ch) send.push_back(i);
  }
  // (the ghosts whose w changed join wchanged). After the step's first
  // (full) forward, only the owners' rows that changed travel: the other
  // ghosts' rows are still those of that forward
  F.forward_columns(wq, 4, &wchanged, 3, &send);
  ncollective += 1.0;
}

// this rank's runs, in key order
std::vector<tagint> HSLocalEngine::my_keys()
{
  std::vector<tagint> k;
  runs.for_each([&](tagint key, Run &r) {
    if (r.mine) k.push_back(key);
  });
  std::sort(k.begin(), k.end());
  return k;
}

/* ----------------------------------------------------------------------
   the copies whose Phi_H2 path (start position, w, member) changed since
   the last check: hdirty (Phi_H2's next check), ddirty (drift and second
   halves, until consumed). A path changes only where w changed (wchanged:
   owners compare, the forward lists the ghosts) or a member copy was
   placed anew (moved): no pass over all copies. full: the first check of
   the step, which looks at everything
------------------------------------------------------------------------- */

void HSLocalEngine::update_paths(bool full)
{
  const int *mask = atom->mask;
  hdirty.clear();
  if (!full)
    for (const std::vector<int> *L : {&wchanged, &moved})
      for (int l : *L) {
        if (!(mask[l] & sys->groupbit)) continue;
        hdirty.push_back(l);
        if (dstamp[l] != depoch) {
          dstamp[l] = depoch;
          ddirty.push_back(l);
        }
      }
  moved.clear();
}

// every local copy of atom t moved (a member placed anew)
void HSLocalEngine::note_moved(tagint t)
{
  for (int l = atom->map(t); l >= 0; l = atom->sametag[l]) moved.push_back(l);
}

/* ----------------------------------------------------------------------
   Phi_H2(dt): non-members on straight lines from x0 with velocity w,
   members waiting at their mid positions. Any contact in it grows C.
   full: every copy that may touch something (the screen's active ones: an
   atom in no term of V_C stays within the screen's bound of its Verlet
   path; and every atom V_C touched); else only the copies whose path
   changed since (hdirty). Each pair is checked by the rank that lists it,
   walls by the owner
------------------------------------------------------------------------- */

void HSLocalEngine::h2_check(bool full, std::vector<Hit> &hits)
{
  HSSystem &F = *sys;
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal, nall = nlocal + atom->nghost;
  const double dt = F.dtv, skin = F.skin;
  double **xref = F.xref;
  bump_epoch(aepoch, astamp);
  std::vector<int> act;
  // an copy that may touch something in Phi_H2. always: check all its
  // pairs (its path changed while its partners' did not: only the pairs of
  // an atom outside its gap can touch, and that may be the partner)
  auto consider = [&](int i, bool always) {
    if (astamp[i] == aepoch || !(mask[i] & F.groupbit)) return;
    astamp[i] = aepoch;
    double q[3];
    const double *wi = wq[i];
    h2_pos(i, q);
    const double D = dt * sqrt(wi[0] * wi[0] + wi[1] * wi[1] + wi[2] * wi[2]);
    const double dx = q[0] - xref[i][0], dy = q[1] - xref[i][1], dz = q[2] - xref[i][2];
    const double reach = sqrt(dx * dx + dy * dy + dz * dz) + D;
    if (!always && reach <= cols[i][0]) return;    // the free gap (forwarded by predict_all)
    if (reach > skin)
      error->one(FLERR,
                 "Fix {}: atom {} may be {} away from where the neighbor list was built, "
                 "more than the skin {} (the fix rebuilds lists at skin/2): use a smaller "
                 "timestep or a larger neighbor skin",
                 F.style_name, atom->tag[i], reach, skin);
    act.push_back(i);
  };
  // the pairs to check, in batches (as predict_all()'s): a pair's other
  // copy is anywhere in memory, its rows (mid, x0, wq) fetched while the
  // batch fills; checked in the order queued, as one at a time would
  HardSphere::Batch<32> batch;
  const std::vector<int> &cand = F.cand;
  auto check = [&](int p) { check_pair(p, hits); };
  auto flush = [&]() { batch.flush(check); };
  auto queue = [&](int p) {
    for (int l : {cand[2 * p], cand[2 * p + 1]}) {
      __builtin_prefetch(&mid[l]);
      HardSphere::prefetch_row(x0[0], 3, l);
      HardSphere::prefetch_row(wq[0], 4, l);
    }
    batch.push(p, check);
  };
  // full: if every line deviates from fix nve's by less than LINE_MARGIN / 2
  // of the contact distance (on every rank), only the pairs predict_all()
  // listed as near misses and the pairs with a member can touch
  bool lists = false;
  if (full) {
    // (this rank's largest deviation, from h2_velocities(true) just before)
    if (!line_dev_valid)
      error->one(FLERR, "Fix {} substep local: internal error: Phi_H2's full check without "
                 "its velocities", F.style_name);
    line_dev_valid = false;
    const double dev = max_all(line_dev);
    lists = dt * dev <= 0.5 * LINE_MARGIN * 2.0 * F.rmax * 0.999;
    if (!lists)
      for (int l = 0; l < nall; l++)
        if (wq[l][3] != 0.0) consider(l, false);
  } else
    for (int l : hdirty) consider(l, true);
  if (lists) {
    // members: every candidate pair; the listed near misses; walls
    for (int l : mid_set) consider(l, true);
    bump_epoch(pepoch, pstamp);
    for (int p : near_pairs) pstamp[p] = pepoch;    // checked below, with act's
    for (int p : near_pairs) queue(p);
    flush();
    for (int i : near_walls)
      if (!is_member(i)) check_walls(i, hits);
  } else
    bump_epoch(pepoch, pstamp);

  for (int i : act) {
    if (!F.walls.empty() && !is_member(i) && i < nlocal) {
      flush();    // (the walls' hits after the pairs queued before them)
      check_walls(i, hits);
    }
    for (int e = adj_off[i]; e < adj_off[i + 1]; e++) {
      const int p = adj[e];
      if (pstamp[p] == pepoch) continue;
      pstamp[p] = pepoch;
      queue(p);
    }
  }
  flush();
}

// the position of copy l at the start of Phi_H2 (members wait at their mid
// positions)
void HSLocalEngine::h2_pos(int l, double *q) const
{
  const double *p = is_member(l) ? atom->x[l] : x0[l];
  q[0] = p[0];
  q[1] = p[1];
  q[2] = p[2];
}

// a contact of candidate pair p on Phi_H2's lines
void HSLocalEngine::check_pair(int p, std::vector<Hit> &hits)
{
  HSSystem &F = *sys;
  const std::vector<int> &cand = F.cand;
  const int la = cand[2 * p], lb = cand[2 * p + 1];
  if (is_member(la) && is_member(lb)) return;    // both wait
  const double dt = F.dtv;
  double qa[3], qb[3];
  const double *wa = wq[la], *wb = wq[lb];
  h2_pos(la, qa);
  h2_pos(lb, qb);
  const double sigma = F.radius_of(la) + F.radius_of(lb);
  const double dq[3] = {qa[0] - qb[0], qa[1] - qb[1], qa[2] - qb[2]};
  const double dv[3] = {wa[0] - wb[0], wa[1] - wb[1], wa[2] - wb[2]};
  const double r2 = dq[0] * dq[0] + dq[1] * dq[1] + dq[2] * dq[2];
  const double reach = sigma + dt * sqrt(dv[0] * dv[0] + dv[1] * dv[1] + dv[2] * dv[2]);
  if (r2 > reach * reach) return;
  const double da[3] = {0.0, 0.0, 0.0};
  if (pair_contact(la, lb, dq, dv, da, sigma, dt, false).status != HardSphere::NO_CONTACT)
    hits.push_back({atom->tag[la], atom->tag[lb]});
}

// wall contacts of owned non-member i on its Phi_H2 line
void HSLocalEngine::check_walls(int i, std::vector<Hit> &hits)
{
  HSSystem &F = *sys;
  for (int wl = 0; wl < (int) F.walls.size(); wl++) {
    const Wall &W = F.walls[wl];
    const double g = F.wall_gap(W, x0[i], F.radius_of(i));
    if (wall_contact(i, wl, g, wq[i][W.dim], 0.0, F.dtv, false).status != HardSphere::NO_CONTACT)
      hits.push_back({atom->tag[i], -1 - (tagint) wl});
  }
}

/* ----------------------------------------------------------------------
   the first approaching contact in (0, tmax] of sphere i with wall W
   (gap g now; velocity vd and acceleration ad along the wall's axis), resp.
   of local atoms la, lb on the relative path dq + t dv + t^2/2 da; an
   overlap now is the fix's missed-collision error
------------------------------------------------------------------------- */

Contact HSLocalEngine::wall_contact(int i, int wl, double g, double vd, double ad, double tmax,
                                    bool timed)
{
  const double s = (sys->walls[wl].side < 0) ? 1.0 : -1.0, r = sys->radius_of(i);
  double c[5];
  HardSphere::wall_gap_poly(g, s * vd, s * ad, c);
  const Contact ct = HardSphere::first_contact(c, 2, tmax, TOUCH_TOL * 2.0 * r, timed);
  if (ct.status == HardSphere::OVERLAP)
    error->one(FLERR, "Fix {}: atom {} is {} through a wall on step {}: a collision was missed",
               sys->style_name, atom->tag[i], -g, update->ntimestep);
  return ct;
}

Contact HSLocalEngine::pair_contact(int la, int lb, const double *dq, const double *dv,
                                   const double *da, double sigma, double tmax, bool timed)
{
  double c[5];
  HardSphere::pair_gap_poly(dq, dv, da, sigma, c);
  const Contact ct = HardSphere::first_contact(c, 4, tmax, TOUCH_TOL * sigma * sigma, timed);
  if (ct.status == HardSphere::OVERLAP)
    sys->pair_overlap_error(la, lb, sqrt(dq[0] * dq[0] + dq[1] * dq[1] + dq[2] * dq[2]), sigma);
  return ct;
}

/* ----------------------------------------------------------------------
   the clusters of the step from the first guess hits (every rank's),
   grown until no flow has a contact with a non-member. After the first
   round, a round redoes only what a growth changed (its clusters, the
   paths of their atoms and the clusters around them). Every rank goes
   through the same rounds and phases: a phase's hits and packets are
   gathered before anyone decides on them
------------------------------------------------------------------------- */

bool HSLocalEngine::settle(std::vector<Hit> &hits)
{
  HSSystem &F = *sys;
  double **x = atom->x;
  const int *mask = atom->mask;
  const int nall = atom->nlocal + atom->nghost;
  const double dt = F.dtv;

  // per-copy bookkeeping of the previous step
  atom_runs.clear();
  for (int l : mid_set) mid[l] = -1;
  mid_set.clear();
  for (int l : labelled) lab[l] = -1;
  labelled.clear();
  bump_epoch(depoch, dstamp);
  ddirty.clear();
  hdirty.clear();
  moved.clear();
  bump_epoch(heldepoch, hstampv);
  drifted = false;
  bool checked = false;    // Phi_H2 checked in full once
  double corrected_at = -1.0;    // nrounds when the cross forces' corrector last ran
  bool b_ran = false;      // a second half ran (its results may need redoing)
  bool redo_b = false;     // this round redoes the corrector's second halves only

  idof.clear();
  idtag.clear();
  topo.clear();
  term_index.clear();
  cs.reset(0);
  cs.set_order(&idtag);
  cs.set_partners_join(false);
  for (const Hit &h : hits) {
    const int a = id_of(h.i);
    cs.add_contact(a, h.j < 0 ? -1 : id_of(h.j));
  }
  const std::vector<int> first = cs.new_members();
  add_members(first);
  cs.build();
  runs.clear();
  for (int c = 0; c < cs.nclusters(); c++) label_cluster(c);
  locf->set_labels(lab.data());

  auto enroll = [&](int a, tagint key) {
    atom_runs.append(a, key);
  };
  auto mine = [&](int c) {
    const int l = atom->map(runner_of(c));
    return l >= 0 && l < atom->nlocal;
  };

  workA.clear();
  workB.clear();
  workX.clear();
  uncheckedA.clear();
  uncheckedB.clear();
  for (int c = 0; c < cs.nclusters(); c++) workA.push_back(key_of(c));

  std::vector<Hit> ev, gathered;
  std::vector<tagint> arrived;
  for (int round = 0;; round++) {
    if (round > MAX_ROUNDS)
      error->one(FLERR, "Fix {} substep local: the collision clusters of step {} did not settle "
                 "in {} rounds", F.style_name, update->ntimestep, MAX_ROUNDS);
    // a round after the corrector (cross_at_end()) redoes second halves
    // only: no first half, sum, path or cross force changed since the last
    // round (no growth came between), so its first part, whose collectives
    // would all carry nothing, is skipped on every rank alike
    if (redo_b && !(workA.empty() && uncheckedA.empty() && workX.empty() && moved.empty() &&
                    ddirty.empty()))
      error->one(FLERR, "Fix {} substep local: internal error: work before the corrector's "
                 "second halves on step {}", F.style_name, update->ntimestep);
    if (!redo_b) {
      // Phi_H1(dt/2) of this rank's clusters not run yet, their static atoms at x0
      ev.clear();
      std::vector<tagint> ranA;
      bool outgrown = false;
      for (int c : in_memory_order(clusters_of(workA))) {
        const tagint key = key_of(c);
        if (!mine(c)) continue;
        Run &r = runs[key];
        if (r.a_done) continue;
        r.mine = true;
        r.mtags.clear();
        for (int id : cs.members(c)) r.mtags.push_back((tagint) idtag[id]);
        if (!member_copies(r)) {
          outgrown = true;
          break;
        }
        r.b_done = false;
        if (!flow(r, 0.5 * dt, true, ev)) continue;
        for (tagint t : r.mtags) note_moved(t);
        for (int a : r.env) enroll(a, key);
        for (int a : r.members) enroll(a, key);
        workX.push_back(key);
        workB.push_back(key);
        ranA.push_back(key);
      }
      // their packets and contacts to every rank (a cluster beyond the ghost
      // atoms as the impossible hit of atom 0: every rank gives up the step)
      if (outgrown) ev.push_back({0, 0});
      share_half(ev, ranA, true, gathered, arrived);
      if (!gathered.empty() && gathered[0].i == 0) {
        locf->set_labels(nullptr);
        return false;
      }
      uncheckedA.insert(uncheckedA.end(), arrived.begin(), arrived.end());
      if (!gathered.empty()) {
        grow_clusters(gathered);
        continue;
      }
      // the flows not yet checked against the others (a round that grew
      // before its check leaves some for the next)
      ev.clear();
      cross_check(true, clusters_of(uncheckedA), ev);
      if (gather_grow(ev)) continue;
      // Phi_H2(dt): its contacts; then the non-members' drift
      h2_velocities(!checked);
      update_paths(!checked);
      ev.clear();
      h2_check(!checked, ev);
      checked = true;
      if (gather_grow(ev)) continue;
      auto drift = [&](int l) {
        if ((mask[l] & F.groupbit) && !is_member(l)) {
          x[l][0] = x0[l][0] + dt * wq[l][0];
          x[l][1] = x0[l][1] + dt * wq[l][1];
          x[l][2] = x0[l][2] + dt * wq[l][2];
        }
      };
      if (!drifted) {
        for (int l = 0; l < nall; l++) drift(l);
        drifted = true;
      } else
        for (int l : ddirty) drift(l);
      // the cross terms' forces at the members' mid positions (second halves)
      cross_at_mid();
    }
    redo_b = false;
    // Phi_H1(dt/2) of the clusters whose start or surroundings changed
    if (b_ran)    // (the first time there is nothing to invalidate)
      for (int a : ddirty)
        atom_runs.for_each(a, [&](tagint key) {
          Run *r = run_of(key);
          if (r && r->mine && r->b_done) {
            r->b_done = false;
            workB.push_back(key);
          }
        });
    b_ran = true;
    bump_epoch(depoch, dstamp);
    ddirty.clear();
    ev.clear();
    std::vector<tagint> ranB;
    for (int c : in_memory_order(clusters_of(workB))) {
      const tagint key = key_of(c);
      Run *r = run_of(key);
      if (!r || !r->mine || r->b_done || !r->a_done) continue;
      if (flow(*r, 0.5 * dt, false, ev)) ranB.push_back(key);
    }
    share_half(ev, ranB, false, gathered, arrived);
    uncheckedB.insert(uncheckedB.end(), arrived.begin(), arrived.end());
    if (!gathered.empty()) {
      grow_clusters(gathered);
      continue;
    }
    ev.clear();
    cross_check(false, clusters_of(uncheckedB), ev);
    if (gather_grow(ev)) continue;
    // the second halves' cross force from their ends (once the clusters
    // are final; again after a growth round it causes, for the new runs)
    if (corrected_at != nrounds) {
      corrected_at = nrounds;
      if (cross_at_end()) {
        redo_b = true;
        continue;
      }
    }
    break;
  }
  locf->set_labels(nullptr);
  return true;
}

/* ----------------------------------------------------------------------
   a step with spheres that may touch (HSStepEngine): by clusters if a
   contact is predicted on any rank, else fix nve's step; the method sees
   the step through HSStepView
------------------------------------------------------------------------- */

bool HSLocalEngine::step()
{
  HSSystem &F = *sys;
  // another fix integrates atoms outside the group: those it moved before
  // this fix's turn have ghost copies at their old positions (LAMMPS
  // forwards x after every fix's initial_integrate()), and the clusters'
  // terms read them. Forwarded, every copy is where its owner is (where the
  // global engine's evaluations see them), on any number of ranks
  if (F.other_integrator) comm->forward_comm();
  const double nrounds0 = nrounds;
  int status = step_clusters();
  // ghost lazy: a contact predicted with LAMMPS' own ghost shell (every
  // rank knows; nothing was changed): the step with the engine's
  if (status == NEEDS_WIDE) {
    to_wide();
    status = step_clusters();
  }
  // a cluster outgrew the ghost atoms (every rank knows; the state is the
  // step's start): overflow widen takes the step again with a wider ghost
  // shell (the given-up attempts' growth rounds not counted: the counts
  // stay those of one rank), overflow global hands it to the global engine
  while (status < 0 && widening()) {
    nrounds = nrounds0;
    widen();
    status = step_clusters();
  }
  if (status < 0 && sys->overflow == HSSystem::OVERFLOW_ERROR) overflow_error();
  if (status < 0) return false;
  if (status > 0) {
    local_step = 1;
    last_cluster_step = update->ntimestep;
    if (F.step_collided) F.ncoll_steps += 1.0;
    meth.cluster_step_begun(*this);
    F.request_rebuild(end_moved);
  } else {    // no contact after all: fix nve's step
    F.nve_initial();
    F.dtf_last = F.dtf;
    F.request_rebuild();
  }
  return true;
}

// overflow error: a cluster outgrew the ghost atoms on some rank (every
// rank knows: step_clusters() returned -1 on all). The lowest rank that
// found one sends its message to all, and all stop with it (error->all():
// rank 0 writes it to the screen and the log)
void HSLocalEngine::overflow_error()
{
  std::string msg;
  msg.swap(outgrown_msg);
  // the bonded-partner form (member_copies()): the rank that raises it
  // (the lowest with a message) sends the missing partners' IDs with the
  // copies of their members and its sub-domain; each partner's owner
  // measures how far the partner's image nearest that copy lies outside
  // the sub-domain along each direction (LAMMPS keeps the ghosts within the
  // cutoff of each face), and the message names the largest. Orthogonal
  // boxes (a triclinic one's sub-domain is in box fractions)
  const int nprocs = comm->nprocs;
  int mine = msg.empty() ? nprocs : comm->me, from = nprocs;
  MPI_Allreduce(&mine, &from, 1, MPI_INT, MPI_MIN, world);
  std::vector<double> buf;
  if (comm->me == from && !domain->triclinic)
    for (const auto &mp : missing) {
      buf.push_back((double) mp.first);
      for (int d = 0; d < 3; d++) buf.push_back(mp.second[d]);
    }
  int n = (int) buf.size();
  if (from < nprocs) MPI_Bcast(&n, 1, MPI_INT, from, world);
  if (n > 0) {
    double box[6];
    for (int d = 0; d < 3; d++) {
      box[d] = domain->sublo[d];
      box[3 + d] = domain->subhi[d];
    }
    MPI_Bcast(box, 6, MPI_DOUBLE, from, world);
    buf.resize(n);
    MPI_Bcast(buf.data(), n, MPI_DOUBLE, from, world);
    double out = -1.0, all = -1.0;
    for (int p = 0; p < n; p += 4) {
      const int m = atom->map((tagint) buf[p]);
      if (m < 0 || m >= atom->nlocal) continue;
      double d[3] = {atom->x[m][0] - buf[p + 1], atom->x[m][1] - buf[p + 2],
                     atom->x[m][2] - buf[p + 3]};
      domain->minimum_image(d);
      for (int k = 0; k < domain->dimension; k++) {
        const double q = buf[p + 1 + k] + d[k];
        out = MAX(out, MAX(box[k] - q, q - box[3 + k]));
      }
    }
    MPI_Allreduce(&out, &all, 1, MPI_DOUBLE, MPI_MAX, world);
    if (all > 0.0 && comm->me == from)
      msg += fmt::format(". The farthest of the cluster's {} bonded atom(s) without a copy there "
                         "lies {:.6g} beyond that rank's sub-domain: comm_modify cutoff {:.6g} "
                         "would hold them",
                         n / 4, all, std::ceil(all * 100.0) / 100.0);
  }
  sys->error_from_lowest(msg);
  error->all(FLERR,
             "Fix {} substep local: a collision cluster on step {} reaches beyond the ghost "
             "atoms (no rank kept its message: internal error)",
             sys->style_name, update->ntimestep);
}

// the closing kick of a step taken by clusters
bool HSLocalEngine::finish()
{
  if (!local_step) return false;
  HSSystem &F = *sys;
  final_kick();
  meth.cluster_step_done(*this);
  local_step = 0;
  F.step_substeps = 0;
  F.screened_step = -1;
  return true;
}

// clusters, mean and largest members, growth rounds, fall-backs, restricted
// evaluations, collectives per step taken by clusters, quick-cleared steps,
// overflow widenings, ghost lazy's widenings, the busiest rank's share of the
// restricted evaluations (max over mean)
double HSLocalEngine::counter(int k)
{
  if (k == 4) return sys->nfallback;
  const HardSphere::ClusterCounters &c = cs.counters();
  switch (k) {
    case 0:
      return c.clusters;
    case 1:
      return c.mean_members();
    case 2:
      return c.max_members;
    case 3:
      return nrounds;
    case 5: {
      // every rank's since the last call (output is computed on every
      // rank, as fix langevin's compute_scalar() sums over them)
      double mine = ncompute_here - ncompute_summed, nc = mine;
      if (nprocs > 1) MPI_Allreduce(&mine, &nc, 1, MPI_DOUBLE, MPI_SUM, world);
      ncompute += nc;
      ncompute_summed = ncompute_here;
      return ncompute;
    }
    case 6:
      return ncoll_steps > 0.0 ? ncollective / ncoll_steps : 0.0;
    case 7:
      return nquick;
    case 8:
      return nwiden;
    case 9:
      return nwide;
    case 10: {
      // the balance of the clusters' work: the rank that runs most of it
      // sets the pace, the others wait at the step's collectives
      double mx = ncompute_here, sum = ncompute_here;
      if (nprocs > 1) {
        MPI_Allreduce(&ncompute_here, &mx, 1, MPI_DOUBLE, MPI_MAX, world);
        MPI_Allreduce(&ncompute_here, &sum, 1, MPI_DOUBLE, MPI_SUM, world);
      }
      return sum > 0.0 ? mx * nprocs / sum : 0.0;
    }
  }
  return 0.0;
}

// the per-copy columns (peratom()), the per-copy stamps and bounds, the
// candidate pairs' adjacency, and the restricted evaluations' arrays
double HSLocalEngine::memory_usage() const
{
  const auto bytes = [](const auto &vec) { return HardSphere::capacity_bytes(vec); };
  double b = 0.0;
  for (const auto &a : const_cast<HSLocalEngine *>(this)->peratom())
    b += (double) nmax * a.second * sizeof(double);
  b += bytes(mid) + bytes(lab) + bytes(estamp) + bytes(astamp) + bytes(envstamp) +
      bytes(envbest) + bytes(wstamp) + bytes(dstamp_sa) + bytes(in_used) + bytes(dstamp) +
      bytes(hstampv) + bytes(kstamp) + atom_runs.bytes() + bytes(pathv) + bytes(flagv) +
      bytes(awayv) + bytes(adj_off) + bytes(adj) + bytes(cand_ghosts) + bytes(cand_slack) +
      bytes(pstamp);
  return b + locf->memory_usage();
}

const std::vector<int> &HSLocalEngine::members(int c) const
{
  return view_members[c];
}

/* ----------------------------------------------------------------------
   one step: Phi_H1(dt/2) . Phi_H2(dt) . Phi_H1(dt/2) with C grown until no
   flow has a contact with a non-member
------------------------------------------------------------------------- */

int HSLocalEngine::step_clusters()
{
  HSSystem &F = *sys;
  grow_arrays();
  build_adjacency();
  if ((int) hstampv.size() < nmax) hstampv.resize(nmax, 0u);
  // (the owned atoms' a, x0 and v0 are set by predict_all(); the ghosts'
  // v, a go with the first guess's flags)
  const double ncoll0 = ncollective;
  split_ = false;
  // after a step whose first guess was empty, the flagged spheres alone
  // first (quick_clear(); the same decision, made on every rank)
  if (quick_next && quick_clear()) {
    ncollective = ncoll0;
    nquick += 1.0;
    return 0;
  }
  std::vector<Hit> hits;
  predict_all(hits);
  gather_hits(hits);
  quick_next = hits.empty();
  if (hits.empty()) {
    ncollective = ncoll0;    // (counted for steps taken by clusters only)
    return 0;
  }
  if (narrow) {
    ncollective = ncoll0;
    return NEEDS_WIDE;
  }
  ncoll_steps += 1.0;
  // held smooth forces beside a thermostat: the thermostat's part of each
  // copy's start force, f - the fix's copy of the conservative force, from
  // its owner (one exchange; only such inputs)
  split_ = splits_held();
  if (split_) {
    double **fcap = sys->captured(true), **f = atom->f;
    for (int i = 0; i < atom->nlocal; i++)
      for (int d = 0; d < 3; d++) kick0[i][d] = f[i][d] - fcap[i][d];
    comm->forward_comm_array(3, kick0);
    ncollective += 1.0;
  }
  // lj/cut: the restricted evaluations by its kernel (hs_ljcut.h), with
  // the coefficients of this step (fix adapt may change them)
  locf->set_lj_table(F.pot->lj_cut_table());

  double **x = atom->x, **v = atom->v;
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal, nall = nlocal + atom->nghost;
  for (int l = nlocal; l < nall; l++)    // (the owned ones in predict_all())
    for (int d = 0; d < 3; d++) {
      x0[l][d] = x[l][d];
      v0[l][d] = v[l][d];
    }
  if (!settle(hits)) {
    // a cluster beyond the ghost atoms, overflow global: back to the start
    // (velocities and positions of every copy; impulses and flows touched
    // only those) for the global engine
    for (int l = 0; l < nall; l++)
      for (int d = 0; d < 3; d++) {
        x[l][d] = x0[l][d];
        v[l][d] = v0[l][d];
      }
    F.step_collided = 0;
    ncoll_steps -= 1.0;
    runs.clear();
    cs.abandon();
    return -1;
  }

  // the final clusters: members' end states (owned copies), collisions
  // (every rank counts all), impulse virial (the runner's), and on the
  // touched copies V_C's end forces and the partners' second-half kicks,
  // reversed into the owners
  // (the last step's rows, in index order: RowSet)
  rowset.reset(nmax);
  for (int l : sb_rows) rowset.add(l);
  rowset.for_each([&](int l) {
    for (int d = 0; d < 7; d++) sb[l][d] = 0.0;
  });
  sb_rows.clear();
  view_members.assign(cs.nclusters(), {});
  for (int c = 0; c < cs.nclusters(); c++) {
    const Run *rp = run_of(key_of(c));
    if (!rp)
      error->one(FLERR, "Fix {} substep local: internal error: cluster {} has no run",
                 F.style_name, key_of(c));
    const Run &r = *rp;
    // (a provisional second half has no closing kick: never a final one)
    if (r.mine && awaits_corrector(r))
      error->one(FLERR, "Fix {} substep local: internal error: cluster {} ends step {} with a "
                 "provisional second half", F.style_name, key_of(c), update->ntimestep);
    for (size_t k = 0; k < r.mtags.size(); k++) {
      const int l = atom->map(r.mtags[k]);
      if (l < 0 || l >= nlocal) continue;
      const double xn[3] = {x0[l][0] + r.dxe[k][0], x0[l][1] + r.dxe[k][1],
                            x0[l][2] + r.dxe[k][2]};
      set_xv(l, xn, r.ve[k].data());
      view_members[c].push_back(l);
    }
    for (int h = 0; h < 2; h++) {
      F.ncoll_pair += r.npair[h];
      F.ncoll_wall += r.nwall[h];
      if (r.npair[h] + r.nwall[h] > 0.0) F.step_collided = 1;
      if (r.mine) {
        for (int k = 0; k < 6; k++) F.host->virial[k] += r.vir[h][k];
        if (!r.mcount[h].empty()) meth.add_flow_counts(r.mcount[h]);
      }
    }
    if (!r.mine) continue;
    const size_t nt = r.touched.size();
    // (rows all over memory, added in key order: HardSphere::prefetch_row())
    for (size_t k = 0; k < nt; k++) {
      if (k + HardSphere::PREFETCH_AHEAD < nt)
        HardSphere::prefetch_row(sb[0], 7, r.touched[k + HardSphere::PREFETCH_AHEAD], true);
      const int p = r.touched[k];
      sb_rows.push_back(p);
      double *row = HardSphere::row_at(sb[0], 7, p);
      for (int d = 0; d < 3; d++) {
        row[d] += r.fend[k][d];
        row[3 + d] += r.dvB[k][d];
      }
      row[6] += 1.0;
    }
  }
  F.reverse_columns(sb, 7, &sb_rows);
  ncollective += 1.0;

  // the non-members' velocities: w plus the second half's partner kicks
  bump_epoch(eepoch, estamp);
  const tagint *tag = atom->tag;
  end_ptags.clear();
  end_pfc.clear();
  // the owners with second-half sums are in sb_rows (listed, or received
  // by the reverse): a RowSet of them, so the pass below reads a bit per
  // atom and a row of the 7-column sb only there, in index order
  rowset.reset(nlocal);
  for (int l : sb_rows)
    if (l < nlocal) rowset.add(l);
  // (with HSSystem::moved_half_skin()'s test of the final positions, read
  // here rather than in a pass of their own)
  end_moved = 0;
  for (int i = 0; i < nlocal; i++) {
    const bool ends = rowset.has(i) && sb[i][6] > 0.0 && !is_member(i);
    if (ends) {
      estamp[i] = eepoch;
      end_ptags.push_back(tag[i]);
      end_pfc.push_back({sb[i][0], sb[i][1], sb[i][2]});
    }
    if (!(mask[i] & F.groupbit)) continue;
    if (F.moved_half(i)) end_moved = 1;
    if (is_member(i)) continue;
    if (ends)
      for (int d = 0; d < 3; d++) v[i][d] = wq[i][d] + sb[i][3 + d];
    else
      for (int d = 0; d < 3; d++) v[i][d] = wq[i][d];
  }
  // what the closing kick needs, by ID (see final_kick())
  end_mtags.clear();
  for (int c = 0; c < cs.nclusters(); c++)
    for (int id : cs.members(c)) end_mtags.push_back((tagint) idtag[id]);
  end_ncalls = neighbor->ncalls;
  cs.flush_counters();
  // (the restricted evaluations are summed over the ranks when the output
  // asks, counter(): a reduction here, every step, would be one more point
  // where the ranks wait for each other)
  return 1;
}

/* ----------------------------------------------------------------------
   closing half kick with f - F_C(end): V_R and held forces. Members' V_C
   kick closed their last sub-step; without held forces they take none.
   A neighbor list rebuild since step() may have sorted the atoms or moved
   them to other ranks: then members and partners are found by ID (the
   partners' end forces gathered from every rank)
------------------------------------------------------------------------- */

void HSLocalEngine::final_kick()
{
  HSSystem &F = *sys;
  double **v = atom->v, **f = atom->f;
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  const bool remapped = neighbor->ncalls != end_ncalls;
  if ((int) estamp.size() < atom->nmax) estamp.resize(atom->nmax, 0u);
  if ((int) kstamp.size() < atom->nmax) kstamp.resize(atom->nmax, 0u);
  grow_arrays();
  if (remapped) {
    // a partner still owned here keeps its end force; only those of atoms
    // that changed rank travel (each atom is listed on one rank)
    bump_epoch(eepoch, estamp);
    auto take = [&](int i, const double *fc) {
      estamp[i] = eepoch;
      sb_rows.push_back(i);
      for (int d = 0; d < 3; d++) sb[i][d] = fc[d];
    };
    sendbuf.clear();
    for (size_t k = 0; k < end_ptags.size(); k++) {
      const int i = atom->map(end_ptags[k]);
      if (i >= 0 && i < nlocal) {
        take(i, end_pfc[k].data());
        continue;
      }
      sendbuf.push_back((double) end_ptags[k]);
      for (int d = 0; d < 3; d++) sendbuf.push_back(end_pfc[k][d]);
    }
    allgather(recvbuf);
    for (size_t m = 0; m + 3 < recvbuf.size(); m += 4) {
      const int i = atom->map((tagint) recvbuf[m]);
      if (i < 0 || i >= nlocal) continue;
      take(i, &recvbuf[m + 1]);
    }
  }
  bump_epoch(kepoch, kstamp);
  std::vector<int> all;
  for (tagint t : end_mtags) {
    const int i = atom->map(t);
    if (i < 0 || i >= nlocal) continue;
    kstamp[i] = kepoch;
    all.push_back(i);
  }
  // members' held forces: f - their conservative force from all their terms
  // (LAMMPS' own, if the fix copied it before the held fixes added theirs;
  // riding, the kick is all of f - F_C: G's start value left the flow's end)
  double **fcap = (holds() && !rides()) ? sys->captured(false) : nullptr;
  // (pcva's ledger takes the thermostat's closing kick from the end's copy)
  if (split_ && !sys->captured(false))
    error->all(FLERR,
               "Fix {} substep local: internal error: the conservative force was copied at "
               "the start of step {} but not at its end",
               sys->style_name, update->ntimestep);
  if (fcap)
    for (int i : all) {
      const double dtfm = F.dtf / F.mass_of(i);
      for (int d = 0; d < 3; d++) v[i][d] += dtfm * (f[i][d] - fcap[i][d]);
    }
  else if (holds() && !all.empty()) {
    locf->set_labels(nullptr);
    vc(all.data(), (int) all.size());
    double **fl = locf->forces();
    double fc[3] = {0.0, 0.0, 0.0};
    for (int i : all) {
      const double dtfm = F.dtf / F.mass_of(i);
      if (!gravity.empty()) const_force(i, fc);    // (in the members' flows)
      for (int d = 0; d < 3; d++) v[i][d] += dtfm * (f[i][d] - fl[i][d] - fc[d]);
    }
  }
  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & F.groupbit)) continue;
    if (kstamp[i] == kepoch) continue;    // above
    const double dtfm = F.dtf / F.mass_of(i);
    if (estamp[i] == eepoch) {
      for (int d = 0; d < 3; d++) v[i][d] += dtfm * (f[i][d] - sb[i][d]);
    } else
      for (int d = 0; d < 3; d++) v[i][d] += dtfm * f[i][d];
  }
}

int HSLocalEngine::owned(tagint t) const
{
  const int i = atom->map(t);
  if (i < 0 || i >= atom->nlocal)
    error->one(FLERR, "Fix {} substep local: atom {} of a collision cluster is not owned at the "
               "step's end (after a neighbor list rebuild)", sys->style_name, t);
  return i;
}

void HSLocalEngine::partner_kicks(int i, double *first, double *second) const
{
  const bool a = sa[i][6] > 0.0 && (atom->mask[i] & sys->groupbit);
  const bool b = estamp[i] == eepoch;
  for (int d = 0; d < 3; d++) {
    first[d] = a ? sa[i][3 + d] : 0.0;
    second[d] = b ? sb[i][3 + d] : 0.0;
  }
}
