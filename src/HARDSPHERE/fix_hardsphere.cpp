/* ----------------------------------------------------------------------
   HARDSPHERE package: shared base of the hard-sphere integrator family.
   See fix_hardsphere.h and doc/fix_hardsphere.rst.
------------------------------------------------------------------------- */

#include "fix_hardsphere.h"

#include "hs_compat.h"
#include "hs_contact.h"
#include "hs_fix_rule.h"
#include "hs_local_engine.h"
#include "hs_potential.h"

#include "angle.h"
#include "atom.h"
#include "atom_vec.h"
#include "bond.h"
#include "comm.h"
#include "dihedral.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "group.h"
#include "improper.h"
#include "kspace.h"
#include "memory.h"
#include "modify.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "pair.h"
#include "update.h"

#include <cmath>
#include <cstring>
#include <mpi.h>

using namespace LAMMPS_NS;
using namespace FixConst;
using HardSphere::Contact;


/* ---------------------------------------------------------------------- */

FixHardSphere::FixHardSphere(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), style_name(arg[2]), diameter(0.0), diameter_flag(0), list(nullptr),
    nmax_hs(0), xref(nullptr), gap(nullptr), active(nullptr), acc(nullptr), ncoll_pair(0.0),
    ncoll_wall(0.0), ncoll_steps(0.0), nforce_evals(0.0)
{
  pot = nullptr;
  time_integrate = 1;
  vector_flag = 1;
  size_vector = 5;
  global_freq = 1;
  extvector = 0;
  virial_global_flag = 1;
  thermo_virial = 1;
  comm_forward = 7;
  comm_reverse = 1;
  restart_global = 1;
  force_reneighbor = 1;    // we ask for a list build when a sphere moved skin/2
  next_reneighbor = -1;
  dtf_last = 0.0;
  screened_step = -1;
  screened_flags = 0;

  int iarg = 3;
  while (iarg < narg) {
    if (strcmp(arg[iarg], "diameter") == 0) {
      if (iarg + 2 > narg)
        error->all(FLERR, "Illegal fix {} command: diameter needs a value", style_name);
      diameter = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
      if (!(diameter > 0.0))
        error->all(FLERR, "Fix {} diameter must be > 0, got {}", style_name, arg[iarg + 1]);
      diameter_flag = 1;
      iarg += 2;
    } else if (strcmp(arg[iarg], "wall") == 0) {
      if (iarg + 3 > narg)
        error->all(FLERR, "Illegal fix {} command: wall needs a face and a coordinate",
                   style_name);
      Wall w;
      const std::string face = arg[iarg + 1];
      if (face == "xlo" || face == "xhi") w.dim = 0;
      else if (face == "ylo" || face == "yhi") w.dim = 1;
      else if (face == "zlo" || face == "zhi") w.dim = 2;
      else
        error->all(FLERR, "Fix {} wall face must be xlo, xhi, ylo, yhi, zlo or zhi, got {}",
                   style_name, face);
      w.side = (face.substr(1) == "lo") ? -1 : 1;
      for (const Wall &o : walls)
        if (o.dim == w.dim && o.side == w.side)
          error->all(FLERR, "Fix {} wall {} given twice", style_name, face);
      if (strcmp(arg[iarg + 2], "EDGE") == 0) {
        w.edge = 1;
        w.coord = 0.0;
      } else {
        w.edge = 0;
        w.coord = utils::numeric(FLERR, arg[iarg + 2], false, lmp);
      }
      walls.push_back(w);
      iarg += 3;
    } else if (strcmp(arg[iarg], "substep") == 0) {
      if (iarg + 2 > narg)
        error->all(FLERR, "Illegal fix {} command: substep needs local or global", style_name);
      if (strcmp(arg[iarg + 1], "local") == 0) substep_mode = SUBSTEP_LOCAL;
      else if (strcmp(arg[iarg + 1], "global") == 0) substep_mode = SUBSTEP_GLOBAL;
      else
        error->all(FLERR, "Fix {} substep must be local or global, got {}", style_name,
                   arg[iarg + 1]);
      iarg += 2;
    } else
      error->all(FLERR, "Unknown fix {} keyword: {}", style_name, arg[iarg]);
  }

  if (!diameter_flag && !atom->radius_flag)
    error->all(FLERR,
               "Fix {} needs the diameter keyword, or an atom style with a per-atom "
               "radius (atom_style sphere)",
               style_name);
  if (domain->triclinic)
    error->all(FLERR, "Fix {} does not support triclinic boxes", style_name);
  for (const Wall &w : walls) {
    std::string name;
    wall_name(w, name);
    if (w.dim == 2 && domain->dimension == 2)
      error->all(FLERR, "Fix {} wall {} is not allowed in a 2d simulation", style_name, name);
    if (domain->periodicity[w.dim])
      error->all(FLERR, "Fix {} wall {} is on a periodic dimension", style_name, name);
  }

  pot = new HSPotential(lmp, groupbit, "fix " + style_name);
}

/* ---------------------------------------------------------------------- */

FixHardSphere::~FixHardSphere()
{
  delete local_engine;
  delete pot;
  memory->destroy(xref);
  memory->destroy(gap);
  memory->destroy(active);
  memory->destroy(acc);
  memory->destroy(ftot);
  memory->destroy(fcons);
  memory->destroy(fheld);
}

/* ---------------------------------------------------------------------- */

int FixHardSphere::setmask()
{
  return INITIAL_INTEGRATE | FINAL_INTEGRATE | POST_NEIGHBOR;
}

/* ----------------------------------------------------------------------
   the engine's counters follow the method's own output entries
------------------------------------------------------------------------- */

void FixHardSphere::post_constructor()
{
  local_vec_offset = size_vector;
  size_vector += 6;
}

/* ---------------------------------------------------------------------- */

void FixHardSphere::init()
{
  if (domain->triclinic)
    error->all(FLERR, "Fix {} does not support triclinic boxes", style_name);
  check_other_integrators();

  // the largest radius in the group sets the contact list cutoff

  double rloc = 0.0;
  const int nlocal = atom->nlocal;
  const int *mask = atom->mask;
  for (int i = 0; i < nlocal; i++)
    if (mask[i] & groupbit) {
      const double r = radius_of(i);
      if (!(r > 0.0))
        error->one(FLERR, "Fix {}: atom {} has radius {}, hard spheres need radius > 0",
                   style_name, atom->tag[i], r);
      rloc = MAX(rloc, r);
    }
  MPI_Allreduce(&rloc, &rmax, 1, MPI_DOUBLE, MPI_MAX, world);
  max_substeps = MAX_SUBSTEPS_BASE + MAX_SUBSTEPS_PER_SPHERE * group->count(igroup);
  if (rmax == 0.0) rmax = diameter_flag ? 0.5 * diameter : 0.0;

  // the list holds every pair within 2 rmax + 2 skin of each other when it
  // was built; with LAMMPS rebuilding once an atom moved skin/2, no sphere
  // moves more than skin before the next build, so pairs outside the list
  // cannot touch (checked in screen())

  skin = neighbor->skin;
  list_cutoff = 2.0 * rmax + 2.0 * skin;

  // contact candidates come from a half list. When the pair cutoffs of all
  // type pairs in the group reach the list cutoff, LAMMPS copies the pair
  // style's list for free; otherwise the list gets its own cutoff and build.

  const int ntypes = atom->ntypes;
  std::vector<int> tloc(ntypes + 1, 0), tall(ntypes + 1, 0);
  for (int i = 0; i < nlocal; i++)
    if (mask[i] & groupbit) tloc[atom->type[i]] = 1;
  MPI_Allreduce(tloc.data(), tall.data(), ntypes + 1, MPI_INT, MPI_MAX, world);
  own_list = (force->pair == nullptr) ? 1 : 0;
  for (int a = 1; a <= ntypes && !own_list; a++)
    for (int b = 1; b <= ntypes && !own_list; b++)
      if (tall[a] && tall[b] && sqrt(force->pair->cutsq[a][b]) + skin < list_cutoff) own_list = 1;

  // the contact list needs ghost atoms out to its cutoff: checked here,
  // before newer LAMMPS (4Feb2025) checks the request with a vaguer message

  const double cutghost = HSCompat::ghost_cutoff_at_init(lmp);
  if (cutghost < list_cutoff)
    error->all(FLERR,
               "Fix {} needs ghost atoms out to {} (contact distance {} + 2 x skin {}), "
               "but the ghost cutoff is {}: use comm_modify cutoff {} or a pair style "
               "with a larger cutoff",
               style_name, list_cutoff, 2.0 * rmax, skin, cutghost, list_cutoff);
  HSCompat::request_half_list(lmp, this, instance_me, own_list ? list_cutoff : 0.0,
                              CONTACT_LIST_ID);

  // the derivative layer decides its paths now, and asks for a second
  // list if its path needs one
  if (derivs_needed) {
    pot->init(HSPotential::AUTO);
    pot->request_list(this, instance_me, POT_LIST_ID);
    const std::string path = pot->describe();
    if (comm->me == 0 && path != path_told)
      utils::logmesg(lmp, "fix {}: derivatives of V: {}\n", style_name, path);
    path_told = path;
  }

  // with no smooth forces at all, sub-steps need no force re-evaluation

  forces_present = 0;
  if (force->pair && force->pair->compute_flag && strcmp(force->pair_style, "zero") != 0)
    forces_present = 1;
  if (atom->molecular != Atom::ATOMIC &&
      (force->bond || force->angle || force->dihedral || force->improper))
    forces_present = 1;
  if (force->kspace && force->kspace->compute_flag) forces_present = 1;
  for (int k = 0; k < modify->nfix; k++)
    if (modify->fmask[k] & (FixConst::PRE_FORCE | FixConst::PRE_REVERSE | FixConst::POST_FORCE))
      forces_present = 1;

  check_fixes_beside();
  choose_engine();
  reset_dt();
}

/* ----------------------------------------------------------------------
   the step engine of this run (doc "Step engines"): local where the method
   and the set-up allow it, unless substep global was given; an explicit
   substep local that cannot run is an error naming why
------------------------------------------------------------------------- */

void FixHardSphere::choose_engine()
{
  use_local = 0;
  fallback_counting = 0;
  const int support = engines_supported();
  if (support == ENGINE_NONE || substep_mode == SUBSTEP_GLOBAL) return;
  if (support == ENGINE_GLOBAL_ONLY) {
    if (substep_mode == SUBSTEP_LOCAL)
      error->all(FLERR,
                 "Fix {} substep local is not available yet: only hardsphere/cva and /pcva "
                 "(and psa, local by construction) have the local engine; use substep global",
                 style_name);
    return;
  }
  if (!local_engine) local_engine = new HSLocalEngine(lmp, this);
  std::string why = local_engine->init();
  const std::string own = local_limits();
  if (!own.empty()) why += (why.empty() ? "" : "; ") + own;
  if (why.empty()) {
    use_local = 1;
    if (comm->me == 0 && local_why_told != "local")
      utils::logmesg(lmp, "fix {}: substep local (collisions sub-stepped per cluster)\n",
                     style_name);
    local_why_told = "local";
    return;
  }
  if (substep_mode == SUBSTEP_LOCAL)
    error->all(FLERR, "Fix {} substep local cannot run with {}: use substep global", style_name,
               why);
  fallback_counting = 1;
  if (comm->me == 0 && local_why_told != why)
    error->warning(FLERR,
                   "Fix {}: substep local is not available with {}; this run falls back to "
                   "substep global (a force evaluation of the whole system per collision)",
                   style_name, why);
  local_why_told = why;
}

/* ----------------------------------------------------------------------
   the fixes beside the integrator (hs_fix_rule.h, doc "Fixes beside the
   integrator"): box changes and constraint fixes are refused, thermostat
   forces are held through collisional steps, unknown forces are named
------------------------------------------------------------------------- */

void FixHardSphere::check_fixes_beside()
{
  for (int k = 0; k < modify->nfix; k++) {
    Fix *other = modify->fix[k];
    if (other == this) continue;
    if (other->box_change & (Fix::BOX_CHANGE_SIZE | Fix::BOX_CHANGE_SHAPE))
      error->all(FLERR,
                 "Fix {} cannot run beside fix {} {}: it changes the box during the run and "
                 "rescales positions without regard to the spheres' contacts, which makes "
                 "hard spheres overlap. Run at constant volume (a box changed between runs "
                 "is checked for overlaps at set-up)",
                 style_name, other->id, other->style);
    const std::string base = HardSphere::base_style(other->style);
    if (HardSphere::fix_force_kind(other->style) == HardSphere::FixForceKind::REFUSED)
      error->all(FLERR,
                 "Fix {} cannot run beside fix {} {}: its constraint forces are computed for "
                 "one velocity-Verlet step of dt, which the collisional sub-steps break",
                 style_name, other->id, other->style);
    if (base == "langevin" &&
        (modify->fmask[k] & (FixConst::INITIAL_INTEGRATE | FixConst::POST_INTEGRATE)))
      error->all(FLERR,
                 "Fix {} cannot run beside fix {} langevin with the gjf keyword: GJF changes "
                 "positions and velocities as one velocity-Verlet step of dt, which the "
                 "collisional sub-steps break; use gjf no",
                 style_name, other->id);
  }

  pot->init_fixes();
  const std::string unknown = pot->unknown_names();
  if (!unknown.empty() && comm->me == 0 && unknown != unknown_told)
    error->warning(FLERR,
                   "Fix {}: the forces of {} are of a kind it does not know; they are "
                   "treated as conservative (a function of the positions) and evaluated again "
                   "at every collisional sub-step. If they are stochastic or depend on "
                   "velocities, statistics will be wrong",
                   style_name, unknown);
  unknown_told = unknown;
  nheld = pot->held_any() ? 1 : 0;
  const std::string held = pot->held_names();
  if (nheld && comm->me == 0 && held != held_told)
    utils::logmesg(lmp,
                   "fix {}: forces of {} held through collisional steps (two half kicks "
                   "around the method's conservative map)\n",
                   style_name, held);
  held_told = held;
}

/* ----------------------------------------------------------------------
   another time integrator on atoms of our group would move spheres into
   each other behind our back: an error, not only LAMMPS' warning
------------------------------------------------------------------------- */

void FixHardSphere::check_other_integrators()
{
  const int nlocal = atom->nlocal;
  const int *mask = atom->mask;
  others_integrate = 0;
  for (int k = 0; k < modify->nfix; k++) {
    Fix *other = modify->fix[k];
    if (other == this || !other->time_integrate) continue;
    others_integrate = 1;
    int shared = 0;
    for (int i = 0; i < nlocal; i++)
      if ((mask[i] & groupbit) && (mask[i] & other->groupbit)) shared = 1;
    int any;
    MPI_Allreduce(&shared, &any, 1, MPI_INT, MPI_MAX, world);
    if (any)
      error->all(FLERR,
                 "Fix {} {} and fix {} {} both time-integrate atoms of group {}: use one "
                 "integrator per atom",
                 id, style_name, other->id, other->style, group->names[igroup]);
  }
}

/* ---------------------------------------------------------------------- */

void FixHardSphere::init_list(int id, NeighList *ptr)
{
  if (id == POT_LIST_ID) pot->init_list(ptr);
  else list = ptr;
}

// "atoms I and J" or "atom I and wall F", for messages
std::string FixHardSphere::contact_name(const Impulse &imp) const
{
  if (imp.type == WALL_EVENT) {
    std::string name;
    wall_name(walls[imp.wall], name);
    return fmt::format("atom {} and wall {}", imp.itag, name);
  }
  return fmt::format("atoms {} and {}", imp.itag, imp.jtag);
}

// impulse virial, averaged over the step: r (x) J / (dt ftm2v); tallied by
// the one rank that built the impulse
void FixHardSphere::add_impulse_virial(const Impulse &imp)
{
  const double s = 1.0 / (dtv * force->ftm2v);
  virial[0] += s * imp.dq[0] * imp.J[0];
  virial[1] += s * imp.dq[1] * imp.J[1];
  virial[2] += s * imp.dq[2] * imp.J[2];
  virial[3] += s * imp.dq[0] * imp.J[1];
  virial[4] += s * imp.dq[0] * imp.J[2];
  virial[5] += s * imp.dq[1] * imp.J[2];
}

void FixHardSphere::pair_overlap_error(int i, int j, double r, double sigma)
{
  error->one(FLERR,
             "Fix {}: atoms {} and {} overlap by {} (distance {} < contact distance {}) "
             "on step {}: a collision was missed",
             style_name, atom->tag[i], atom->tag[j], sigma - r, r, sigma, update->ntimestep);
}

void FixHardSphere::check_runaway(bigint ncollisions)
{
  if (ncollisions > max_substeps)
    error->all(FLERR,
               "Fix {}: more than {} collisions in step {}: a sequence of contacts that does "
               "not end (e.g. a sphere pressed against a wall or a neighbour with almost no "
               "normal velocity) or a timestep far too large for this system",
               style_name, max_substeps, update->ntimestep);
}

void FixHardSphere::resting_contact_error(const Impulse &imp)
{
  error->all(FLERR,
             "Fix {}: {} stay in contact with no normal velocity on step {} "
             "(a resting contact), which impulsive hard spheres cannot resolve",
             style_name, contact_name(imp), update->ntimestep);
}

// a touching contact that a method found separating on its own flow:
// predict() passes over it while it touches, until a sub-step moves on
void FixHardSphere::release_contact(const Impulse &imp)
{
  released.type = imp.type;
  released.itag = imp.itag;
  released.jtag = imp.jtag;
  released.wall = imp.wall;
}

bool FixHardSphere::is_released(int type, tagint itag, tagint jtag, int wall) const
{
  if (released.type != type) return false;
  if (type == WALL_EVENT) return released.itag == itag && released.wall == wall;
  return (released.itag == itag && released.jtag == jtag) ||
         (released.itag == jtag && released.jtag == itag);
}

double FixHardSphere::force_evals() const
{
  return nforce_evals + pot->nevals();
}

/* ---------------------------------------------------------------------- */

void FixHardSphere::reset_dt()
{
  dtv = update->dt;
  dtf = 0.5 * update->dt * force->ftm2v;
}

/* ---------------------------------------------------------------------- */

void FixHardSphere::setup(int)
{
  // per-type ftm2v / m for the screening pass (mass may change between runs)

  if (!atom->rmass) {
    ftm2v_mass.assign(atom->ntypes + 1, 0.0);
    for (int t = 1; t <= atom->ntypes; t++) ftm2v_mass[t] = force->ftm2v / atom->mass[t];
  }

  // Neighbor::init() (after ours) sets neighbor->exclude: checked here

  if (neighbor->exclude)
    error->all(FLERR,
               "Fix {} cannot be used with neigh_modify exclude: excluded pairs would "
               "pass through each other",
               style_name);

  for (int k = 0; k < 6; k++) virial[k] = 0.0;
  dtf_last = dtf;
  screened_step = -1;
  held_step = -1;
  step_split = 0;
}

/* ---------------------------------------------------------------------- */

void FixHardSphere::setup_post_neighbor()
{
  reset_reference(1);
}

void FixHardSphere::post_neighbor()
{
  reset_reference(0);
}

/* ---------------------------------------------------------------------- */

void FixHardSphere::grow_peratom()
{
  if (atom->nmax <= nmax_hs) return;
  nmax_hs = atom->nmax;
  memory->destroy(xref);
  memory->destroy(gap);
  memory->destroy(active);
  memory->destroy(acc);
  memory->create(xref, nmax_hs, 3, "hardsphere:xref");
  memory->create(gap, nmax_hs, "hardsphere:gap");
  memory->create(active, nmax_hs, "hardsphere:active");
  for (int i = 0; i < nmax_hs; i++) active[i] = 0.0;
  memory->create(acc, nmax_hs, 3, "hardsphere:acc");
}

/* ---------------------------------------------------------------------- */


/* ---------------------------------------------------------------------- */

void FixHardSphere::update_walls()
{
  for (Wall &w : walls)
    if (w.edge) w.coord = (w.side < 0) ? domain->boxlo[w.dim] : domain->boxhi[w.dim];
}

// distance of a sphere's surface from the wall plane, >= 0 where allowed
double FixHardSphere::wall_gap(const Wall &w, const double *x, double r) const
{
  return (w.side < 0) ? (x[w.dim] - w.coord) - r : (w.coord - x[w.dim]) - r;
}

void FixHardSphere::wall_name(const Wall &w, std::string &name) const
{
  name = std::string(1, "xyz"[w.dim]) + (w.side < 0 ? "lo" : "hi");
}

/* ----------------------------------------------------------------------
   at each neighbor list build: remember positions, collect the candidate
   pairs (within the list cutoff, both in the group, bonded pairs the lists
   leave out included), and for each sphere the distance it may travel
   before it could touch anything (half the smallest surface gap to a
   candidate partner, its gap to a wall, at most the skin). Any overlap
   found here is an error naming the atoms.
------------------------------------------------------------------------- */

void FixHardSphere::reset_reference(int at_setup)
{
  grow_peratom();
  update_walls();

  double **x = atom->x;
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  const int nall = nlocal + atom->nghost;
  const tagint *tag = atom->tag;
  // at set-up the likely cause is the input, not a missed collision
  const char *when = at_setup
      ? "at set-up (the initial configuration, or a change_box, displace_atoms, set, "
        "create_atoms or read_data since the last run, placed them closer than their "
        "contact distance)"
      : "after a step (a collision was missed)";
  const double cut2 = list_cutoff * list_cutoff;

  for (int i = 0; i < nlocal; i++) {
    xref[i][0] = x[i][0];
    xref[i][1] = x[i][1];
    xref[i][2] = x[i][2];
  }
  for (int i = 0; i < nall; i++) gap[i] = skin;
  ++cand_version;
  const size_t ncand_before = cand.size();
  cand.clear();
  cand.reserve(ncand_before + ncand_before / 4);

  auto candidate = [&](int i, int j) {
    if (!(mask[j] & groupbit)) return;
    const double dx = x[i][0] - x[j][0], dy = x[i][1] - x[j][1], dz = x[i][2] - x[j][2];
    const double r2 = dx * dx + dy * dy + dz * dz;
    if (r2 > cut2) return;    // cannot touch before the next build
    const double sigma = radius_of(i) + radius_of(j);
    const double r = sqrt(r2);
    if (r < sigma * (1.0 - TOUCH_TOL))
      error->one(FLERR,
                 "Fix {}: atoms {} and {} overlap by {} (distance {} < contact distance {}) "
                 "on step {} {}",
                 style_name, tag[i], tag[j], sigma - r, r, sigma, update->ntimestep, when);
    const double g = 0.5 * (r - sigma);
    gap[i] = MIN(gap[i], g);
    gap[j] = MIN(gap[j], g);
    cand.push_back(i);
    cand.push_back(j);
  };

  // the list may be the pair style's, with a longer cutoff: the distance
  // test comes first, as most of its pairs are out of reach

  const int inum = list->inum;
  const int *ilist = list->ilist;
  const int *numneigh = list->numneigh;
  int **firstneigh = list->firstneigh;
  for (int ii = 0; ii < inum; ii++) {
    const int i = ilist[ii];
    if (!(mask[i] & groupbit)) continue;
    const double xi = x[i][0], yi = x[i][1], zi = x[i][2];
    const int *jlist = firstneigh[i];
    const int jnum = numneigh[i];
    // branch-free compaction of the few pairs within reach (a branch taken
    // at random for ~10 % of the pairs costs more than the arithmetic)
    if ((int) near.size() < jnum) near.resize(jnum);
    int nnear = 0;
    for (int jj = 0; jj < jnum; jj++) {
      const int j = jlist[jj] & NEIGHMASK;
      const double dx = xi - x[j][0], dy = yi - x[j][1], dz = zi - x[j][2];
      near[nnear] = j;
      nnear += (dx * dx + dy * dy + dz * dz <= cut2);
    }
    for (int k = 0; k < nnear; k++) candidate(i, near[k]);
  }

  // bonded partners the neighbor lists leave out (special_bonds weight 0),
  // each pair once: from its lower atom ID. A partner that is not even a
  // ghost is farther than the ghost cutoff >= list cutoff: it cannot touch.

  if (atom->molecular != Atom::ATOMIC && atom->special) {
    int **nspecial = atom->nspecial;
    tagint **special = atom->special;
    for (int i = 0; i < nlocal; i++) {
      if (!(mask[i] & groupbit)) continue;
      for (int m = 0; m < nspecial[i][2]; m++) {
        const int level = (m < nspecial[i][0]) ? 1 : (m < nspecial[i][1]) ? 2 : 3;
        if (neighbor->special_flag[level] != 0 || special[i][m] < tag[i]) continue;
        const int j = atom->map(special[i][m]);
        if (j >= 0) candidate(i, domain->closest_image(i, j));
      }
    }
  }

  // a ghost's gaps belong to its owner
  HSCompat::reverse_comm_fix(comm, this);

  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    for (const Wall &w : walls) {
      const double g = wall_gap(w, x[i], radius_of(i));
      if (g < -TOUCH_TOL * 2.0 * radius_of(i)) {
        std::string name;
        wall_name(w, name);
        error->one(FLERR, "Fix {}: atom {} is {} through wall {} at {} on step {} {}",
                   style_name, tag[i], -g, name, w.coord, update->ntimestep, when);
      }
      gap[i] = MIN(gap[i], g);
    }
  }
}

int FixHardSphere::pack_reverse_comm(int n, int first, double *buf)
{
  for (int k = 0; k < n; k++) buf[k] = gap[first + k];
  return n;
}

void FixHardSphere::unpack_reverse_comm(int n, int *list_, double *buf)
{
  for (int k = 0; k < n; k++) gap[list_[k]] = MIN(gap[list_[k]], buf[k]);
}

/* ----------------------------------------------------------------------
   mark the spheres that may touch something within tleft: displacement
   since the list build plus a bound on the Verlet path |t v + t^2/2 a|
   exceeds their gap. Returns ACTIVE if any sphere on this rank is marked,
   plus FAR if any may end the step more than skin/2 from where the list
   was built (then the step must check whether to rebuild).
------------------------------------------------------------------------- */

inline int FixHardSphere::screen_atom(int i, double t2, double h4, double im)
{
  double **x = atom->x;
  double **v = atom->v;
  double **f = atom->f;
  const double dx = x[i][0] - xref[i][0], dy = x[i][1] - xref[i][1], dz = x[i][2] - xref[i][2];
  const double d2 = dx * dx + dy * dy + dz * dz;
  const double v2 = t2 * (v[i][0] * v[i][0] + v[i][1] * v[i][1] + v[i][2] * v[i][2]);
  const double a2 = h4 * im * im * (f[i][0] * f[i][0] + f[i][1] * f[i][1] + f[i][2] * f[i][2]);
  // (a+b+c)^2 <= 3(a^2+b^2+c^2): most spheres are cleared without a sqrt
  const double g = MIN(gap[i], 0.5 * skin);
  if (3.0 * (d2 + v2 + a2) <= g * g) return 0;
  const double w = sqrt(d2) + sqrt(v2) + sqrt(a2);
  int flags = (w > 0.5 * skin) ? FAR : 0;
  if (w <= gap[i]) return flags;
  if (w > skin)
    error->one(FLERR,
               "Fix {}: atom {} may be {} away from where the neighbor list was built, "
               "more than the skin {} (the fix rebuilds lists at skin/2): use a smaller "
               "timestep or a larger neighbor skin",
               style_name, atom->tag[i], w, skin);
  active[i] = 1.0;
  return flags | ACTIVE;
}

int FixHardSphere::screen(double tleft)
{
  const double *rmass = atom->rmass;
  const int *type = atom->type;
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  const double ftm2v = force->ftm2v;
  const double t2 = tleft * tleft;
  const double h4 = 0.25 * t2 * t2;
  int flags = 0;

  for (int i = 0; i < nlocal; i++) {
    active[i] = 0.0;
    if (!(mask[i] & groupbit)) continue;
    flags |= screen_atom(i, t2, h4, rmass ? ftm2v / rmass[i] : ftm2v_mass[type[i]]);
  }
  return flags;
}

/* ----------------------------------------------------------------------
   accelerations of owned atoms, then v, a and the active flag to the ghosts
------------------------------------------------------------------------- */

void FixHardSphere::comm_vel_acc()
{
  double **f = atom->f;
  const int nlocal = atom->nlocal;
  const double ftm2v = force->ftm2v;
  for (int i = 0; i < nlocal; i++) {
    const double im = ftm2v / mass_of(i);
    acc[i][0] = f[i][0] * im;
    acc[i][1] = f[i][1] * im;
    acc[i][2] = f[i][2] * im;
  }
  HSCompat::forward_comm_fix(comm, this);
}

int FixHardSphere::pack_forward_comm(int n, int *list_, double *buf, int, int *)
{
  double **v = atom->v;
  int m = 0;
  for (int k = 0; k < n; k++) {
    const int j = list_[k];
    buf[m++] = v[j][0];
    buf[m++] = v[j][1];
    buf[m++] = v[j][2];
    buf[m++] = acc[j][0];
    buf[m++] = acc[j][1];
    buf[m++] = acc[j][2];
    buf[m++] = active[j];
  }
  return m;
}

void FixHardSphere::unpack_forward_comm(int n, int first, double *buf)
{
  double **v = atom->v;
  int m = 0;
  const int last = first + n;
  for (int i = first; i < last; i++) {
    v[i][0] = buf[m++];
    v[i][1] = buf[m++];
    v[i][2] = buf[m++];
    acc[i][0] = buf[m++];
    acc[i][1] = buf[m++];
    acc[i][2] = buf[m++];
    active[i] = buf[m++];
  }
}

/* ----------------------------------------------------------------------
   earliest approaching contact within tleft among walls of active spheres
   and candidate pairs with an active sphere; returns its time (BIG if
   none) and the event
------------------------------------------------------------------------- */

double FixHardSphere::predict(double tleft, Event &ev)
{
  double **x = atom->x;
  double **v = atom->v;
  const int nlocal = atom->nlocal;
  const tagint *tag = atom->tag;
  double tbest = BIG;
  double c[5];

  auto path = [&](int k) {
    const double vv = sqrt(v[k][0] * v[k][0] + v[k][1] * v[k][1] + v[k][2] * v[k][2]);
    const double aa = sqrt(acc[k][0] * acc[k][0] + acc[k][1] * acc[k][1] + acc[k][2] * acc[k][2]);
    return tleft * vv + 0.5 * tleft * tleft * aa;
  };

  for (int i = 0; i < nlocal; i++) {
    if (active[i] == 0.0) continue;
    const double Di = path(i);
    for (int w = 0; w < (int) walls.size(); w++) {
      const Wall &wl = walls[w];
      const double r = radius_of(i);
      const double g = wall_gap(wl, x[i], r);
      if (g > Di) continue;
      const double s = (wl.side < 0) ? 1.0 : -1.0;
      HardSphere::wall_gap_poly(g, s * v[i][wl.dim], s * acc[i][wl.dim], c);
      const Contact ct = HardSphere::first_contact(c, 2, tleft, TOUCH_TOL * 2.0 * r);
      if (ct.status == HardSphere::OVERLAP) {
        std::string name;
        wall_name(wl, name);
        error->one(FLERR,
                   "Fix {}: atom {} is {} through wall {} on step {}: a collision was missed",
                   style_name, tag[i], -g, name, update->ntimestep);
      }
      if (ct.status == HardSphere::CONTACT_NOW && is_released(WALL_EVENT, tag[i], 0, w)) continue;
      if (ct.status != HardSphere::NO_CONTACT && ct.t < tbest) {
        tbest = ct.t;
        ev.type = WALL_EVENT;
        ev.i = i;
        ev.j = -1;
        ev.wall = w;
      }
    }
  }

  const int ncand = (int) cand.size();
  for (int k = 0; k < ncand; k += 2) {
    const int i = cand[k], j = cand[k + 1];
    if (active[i] == 0.0 && active[j] == 0.0) continue;
    const double sigma = radius_of(i) + radius_of(j);
    const double dq[3] = {x[i][0] - x[j][0], x[i][1] - x[j][1], x[i][2] - x[j][2]};
    const double r2 = dq[0] * dq[0] + dq[1] * dq[1] + dq[2] * dq[2];
    const double reach = sigma + path(i) + path(j);
    if (r2 > reach * reach) continue;
    const double dv[3] = {v[i][0] - v[j][0], v[i][1] - v[j][1], v[i][2] - v[j][2]};
    const double da[3] = {acc[i][0] - acc[j][0], acc[i][1] - acc[j][1], acc[i][2] - acc[j][2]};
    HardSphere::pair_gap_poly(dq, dv, da, sigma, c);
    const Contact ct = HardSphere::first_contact(c, 4, tleft, TOUCH_TOL * sigma * sigma);
    if (ct.status == HardSphere::OVERLAP) {
      pair_overlap_error(i, j, sqrt(r2), sigma);
    }
    if (ct.status == HardSphere::CONTACT_NOW && is_released(PAIR_EVENT, tag[i], tag[j], -1))
      continue;
    if (ct.status != HardSphere::NO_CONTACT && ct.t < tbest) {
      tbest = ct.t;
      ev.type = PAIR_EVENT;
      ev.i = i;
      ev.j = j;
      ev.wall = -1;
    }
  }
  return tbest;
}

/* ----------------------------------------------------------------------
   velocity Verlet pieces: the exact operations of fix nve
------------------------------------------------------------------------- */

void FixHardSphere::nve_initial()
{
  double **x = atom->x;
  double **v = atom->v;
  double **f = atom->f;
  double *rmass = atom->rmass;
  double *mass = atom->mass;
  int *type = atom->type;
  int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  double dtfm;

  // the updates of fix nve, to the bit

  if (rmass) {
    for (int i = 0; i < nlocal; i++)
      if (mask[i] & groupbit) {
        dtfm = dtf / rmass[i];
        v[i][0] += dtfm * f[i][0];
        v[i][1] += dtfm * f[i][1];
        v[i][2] += dtfm * f[i][2];
        x[i][0] += dtv * v[i][0];
        x[i][1] += dtv * v[i][1];
        x[i][2] += dtv * v[i][2];
      }
  } else {
    for (int i = 0; i < nlocal; i++)
      if (mask[i] & groupbit) {
        dtfm = dtf / mass[type[i]];
        v[i][0] += dtfm * f[i][0];
        v[i][1] += dtfm * f[i][1];
        v[i][2] += dtfm * f[i][2];
        x[i][0] += dtv * v[i][0];
        x[i][1] += dtv * v[i][1];
        x[i][2] += dtv * v[i][2];
      }
  }
}

int FixHardSphere::moved_half_skin()
{
  double **x = atom->x;
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  const double trigger = 0.25 * skin * skin;
  for (int i = 0; i < nlocal; i++)
    if (mask[i] & groupbit) {
      const double dx = x[i][0] - xref[i][0], dy = x[i][1] - xref[i][1],
                   dz = x[i][2] - xref[i][2];
      if (dx * dx + dy * dy + dz * dz > trigger) return 1;
    }
  return 0;
}

/* ----------------------------------------------------------------------
   with every sphere within skin/2 of where the list was built at a step's
   start, and moving less than skin/2 in the step, the contact list holds
   every pair that can touch: rebuild this step if anyone went further
   (LAMMPS' own check yes criterion, whatever neigh_modify says). Only
   called when screen() found a sphere that might have.
------------------------------------------------------------------------- */

void FixHardSphere::request_rebuild()
{
  int moved = moved_half_skin(), any;
  MPI_Allreduce(&moved, &any, 1, MPI_INT, MPI_MAX, world);
  if (any) next_reneighbor = update->ntimestep;
}

void FixHardSphere::kick(double tau)
{
  kick_dtf((tau == dtv) ? dtf : 0.5 * tau * force->ftm2v);
}

// v += dtfk f / m, in the form of fix nve's kicks (dtf / m first), so a
// kick with dtfk = dtf is bit for bit fix nve's; force: atom->f unless given
// (the held thermostat forces)
void FixHardSphere::kick_dtf(double dtfk, double **force)
{
  double **v = atom->v;
  double **f = force ? force : atom->f;
  const double *rmass = atom->rmass;
  const double *mass = atom->mass;
  const int *type = atom->type;
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  double dtfm;

  if (rmass) {
    for (int i = 0; i < nlocal; i++)
      if (mask[i] & groupbit) {
        dtfm = dtfk / rmass[i];
        v[i][0] += dtfm * f[i][0];
        v[i][1] += dtfm * f[i][1];
        v[i][2] += dtfm * f[i][2];
      }
  } else {
    for (int i = 0; i < nlocal; i++)
      if (mask[i] & groupbit) {
        dtfm = dtfk / mass[type[i]];
        v[i][0] += dtfm * f[i][0];
        v[i][1] += dtfm * f[i][1];
        v[i][2] += dtfm * f[i][2];
      }
  }
}

void FixHardSphere::kick_drift(double tau)
{
  kick(tau);
  double **x = atom->x;
  double **v = atom->v;
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  for (int i = 0; i < nlocal; i++)
    if (mask[i] & groupbit) {
      x[i][0] += tau * v[i][0];
      x[i][1] += tau * v[i][1];
      x[i][2] += tau * v[i][2];
    }
}

/* ----------------------------------------------------------------------
   forces at the current positions, as Verlet::run computes them
------------------------------------------------------------------------- */

void FixHardSphere::recompute_forces()
{
  if (forces_present) pot->evaluate(0);    // forwards ghost positions first
  else comm->forward_comm();               // ghost positions, for the prediction
}

/* ----------------------------------------------------------------------
   the collision operator R of section 2 at contact, on the rank owning i:
   fills the momentum J given to i (j receives -J) and imp.apply (0 for a
   grazing contact with no approaching normal velocity, which gets no impulse)
------------------------------------------------------------------------- */

void FixHardSphere::collide_pair(int i, int j, Impulse &imp)
{
  double **x = atom->x;
  double **v = atom->v;
  const double dv[3] = {v[i][0] - v[j][0], v[i][1] - v[j][1], v[i][2] - v[j][2]};
  for (int k = 0; k < 3; k++) imp.dq[k] = x[i][k] - x[j][k];
  const double un = imp.dq[0] * dv[0] + imp.dq[1] * dv[1] + imp.dq[2] * dv[2];
  imp.apply = un < 0.0;
  if (imp.apply) HardSphere::pair_impulse(imp.dq, dv, mass_of(i), mass_of(j), imp.J);
}

void FixHardSphere::collide_wall(int i, const Wall &w, Impulse &imp)
{
  double **v = atom->v;
  const double vn = (w.side < 0) ? v[i][w.dim] : -v[i][w.dim];
  imp.apply = vn < 0.0;
  imp.reflect = 1;
  imp.dq[w.dim] = atom->x[i][w.dim] - w.coord;
  if (imp.apply) imp.J[w.dim] = -2.0 * mass_of(i) * v[i][w.dim];
}

/* ---------------------------------------------------------------------- */

void FixHardSphere::apply_impulse(const Impulse &imp)
{
  if (!imp.apply) return;
  double **v = atom->v;
  const int dim = (imp.type == WALL_EVENT) ? walls[imp.wall].dim : 0;

  // every copy of the atoms on this rank, owned and ghost, gets the same
  // update, so ghosts stay current without communication; a plane reflects
  // the normal velocity exactly, v_n -> -v_n
  auto update = [&](int k) {
    const tagint t = atom->tag[k];
    if (imp.type == WALL_EVENT && imp.reflect) {
      if (t == imp.itag) v[k][dim] = -v[k][dim];
      return;
    }
    double s;
    if (t == imp.itag) s = 1.0 / mass_of(k);
    else if (t == imp.jtag) s = -1.0 / mass_of(k);
    else return;
    v[k][0] += s * imp.J[0];
    v[k][1] += s * imp.J[1];
    v[k][2] += s * imp.J[2];
  };

  if (atom->map_style != Atom::MAP_NONE) {
    for (int k = atom->map(imp.itag); k >= 0; k = atom->sametag[k]) update(k);
    if (imp.type == PAIR_EVENT)
      for (int k = atom->map(imp.jtag); k >= 0; k = atom->sametag[k]) update(k);
  } else {
    // no atom map (atomic styles without atom_modify map): scan the copies
    const int nall = atom->nlocal + atom->nghost;
    for (int k = 0; k < nall; k++) update(k);
  }
}

/* ----------------------------------------------------------------------
   one step of the collision Verlet algorithm (section 2.2):
   while time is left, sub-step with Verlet to the earliest contact, apply
   the impulse there, repeat; the last sub-step's closing half kick is done
   in final_integrate with the forces LAMMPS computes at the step's end.
   A step with no predicted contact is exactly fix nve's step.
   The method classes change the pieces marked "hook" (all collective).
------------------------------------------------------------------------- */

void FixHardSphere::initial_integrate(int)
{
  for (int k = 0; k < 6; k++) virial[k] = 0.0;
  grow_peratom();
  update_walls();
  step_collided = 0;
  released.type = -1;

  double tleft = dtv;
  // screened ahead in the previous step's final_integrate unless velocities
  // may have changed since (end_of_step fixes) or a run began (even with
  // run ... pre no, which skips setup())
  const bool ahead = screened_step == update->ntimestep && update->ntimestep > update->firststep + 1;
  int flags = ahead ? screened_flags : screen(tleft), allflags;
  MPI_Allreduce(&flags, &allflags, 1, MPI_INT, MPI_BOR, world);
  if (!(allflags & ACTIVE)) {
    nve_initial();
    dtf_last = dtf;
    if (allflags & FAR) request_rebuild();
    return;
  }

  if (use_local) {    // the local engine (hs_local_engine.h)
    if (local_engine->step()) {
      local_step = 1;
      if (step_collided) ncoll_steps += 1.0;
      local_step_begun();
    } else {    // no contact after all: fix nve's step
      nve_initial();
      dtf_last = dtf;
    }
    request_rebuild();
    return;
  }

  // the sub-steps evaluate forces of all atoms: keep those of atoms that
  // another integrator moves
  save_other_forces();
  if (nheld) {
    begin_held_split();    // K_held(dt/2); atom->f is conservative from here
    screen(tleft);         // velocities changed: which spheres may touch
  }

  int stuck = 0;
  bigint nsub = 0;
  bool contact_seen = false;

  while (true) {
    comm_vel_acc();    // ghosts' v, a and active flags for the prediction
    Event ev{PAIR_EVENT, -1, -1, -1};
    struct {
      double t;
      int rank;
    } mine{predict(tleft, ev), comm->me}, first;
    MPI_Allreduce(&mine, &first, 1, MPI_DOUBLE_INT, MPI_MINLOC, world);

    if (first.t >= tleft) {    // no contact in the rest of the step
      finish_step(tleft);      // hook
      break;
    }

    // every rank learns which contact comes first (tags), for the hooks
    Impulse imp;
    memset(&imp, 0, sizeof(imp));
    if (comm->me == first.rank) {
      imp.type = ev.type;
      imp.itag = atom->tag[ev.i];
      imp.jtag = (ev.type == PAIR_EVENT) ? atom->tag[ev.j] : 0;
      imp.wall = ev.wall;
    }
    MPI_Bcast(&imp, sizeof(Impulse), MPI_BYTE, first.rank, world);
    if (!contact_seen) {
      begin_collisional_step();    // hook: state at the step's start
      contact_seen = true;
    }

    double tau = first.t;
    if (!advance_to_contact(tau, tleft, imp)) break;    // hook: the step ended without it
    if (tau > 0.0) released.type = -1;    // the sub-step moved the released pair apart

    // the rank that found the contact builds the impulse from the state at
    // contact and sends it to all; each applies it to its copies of the atoms

    if (comm->me == first.rank) {
      if (imp.type == PAIR_EVENT) collide_pair(ev.i, ev.j, imp);
      else collide_wall(ev.i, walls[ev.wall], imp);
    }
    MPI_Bcast(&imp, sizeof(Impulse), MPI_BYTE, first.rank, world);
    if (imp.apply) modify_impulse(imp);    // hook: another collision operator
    if (imp.apply && comm->me == first.rank) add_impulse_virial(imp);
    apply_impulse(imp);
    if (imp.apply) {
      if (imp.type == PAIR_EVENT) ncoll_pair += 1.0;
      else ncoll_wall += 1.0;
      step_collided = 1;
    } else if (tau == 0.0 && ++stuck > MAX_STUCK) {
      resting_contact_error(imp);
    }
    if (tau > 0.0) stuck = 0;
    end_substep(tau);    // hook: after each collisional sub-step

    tleft -= tau;
    screen(tleft);
    check_runaway(++nsub);
  }
  if (step_collided) ncoll_steps += 1.0;
  if (contact_seen && fallback_counting) nfallback += 1.0;
  step_substeps = contact_seen;
  restore_other_forces();
  request_rebuild();
}

/* ----------------------------------------------------------------------
   held (thermostat) forces, doc "Fixes beside the integrator": a step with
   collisions is K_held(dt/2) . Phi(dt) . K_held(dt/2), Phi the method's
   map with conservative forces only. Held forces f_h are LAMMPS' own,
   evaluated once per step at its end as beside fix nve: each random force
   acts for dt in all, and the drag sees the velocities fix nve's would.
   A step without collisions stays fix nve's step with f = f_c + f_h.
------------------------------------------------------------------------- */

// at the current x with atom->f = f_c + f_h (LAMMPS' forces): ftot = that,
// fcons = f_c (one conservative evaluation, left in atom->f), fheld = f_h
void FixHardSphere::split_held_forces()
{
  if (atom->nmax > nmax_held) {
    nmax_held = atom->nmax;
    memory->destroy(ftot);
    memory->destroy(fcons);
    memory->destroy(fheld);
    memory->create(ftot, nmax_held, 3, "hardsphere:ftot");
    memory->create(fcons, nmax_held, 3, "hardsphere:fcons");
    memory->create(fheld, nmax_held, 3, "hardsphere:fheld");
  }
  double **f = atom->f;
  const int nlocal = atom->nlocal;
  for (int i = 0; i < nlocal; i++)
    for (int k = 0; k < 3; k++) ftot[i][k] = f[i][k];
  pot->evaluate(0);
  for (int i = 0; i < nlocal; i++)
    for (int k = 0; k < 3; k++) {
      fcons[i][k] = f[i][k];
      fheld[i][k] = ftot[i][k] - f[i][k];
    }
}

void FixHardSphere::begin_held_split()
{
  if (held_step == update->ntimestep) {
    // split at these positions at the end of the last step
    double **f = atom->f;
    for (int i = 0; i < atom->nlocal; i++)
      for (int k = 0; k < 3; k++) f[i][k] = fcons[i][k];
  } else
    split_held_forces();
  kick_dtf(dtf, fheld);    // K_held(dt/2)
  step_split = 1;
}

void FixHardSphere::end_held_split()
{
  split_held_forces();    // at the step's end
  kick_dtf(dtf_last);     // the method's closing kick, conservative forces
  if (step_substeps) end_collisional_step();
  kick_dtf(dtf, fheld);    // K_held(dt/2)
  // LAMMPS' forces again, for output and the next step
  double **f = atom->f;
  for (int i = 0; i < atom->nlocal; i++)
    for (int k = 0; k < 3; k++) f[i][k] = ftot[i][k];
  held_step = update->ntimestep + 1;
  step_split = 0;
  screened_step = -1;
}

// forces of owned atoms outside the group, while another fix integrates
// some: the sub-step evaluations overwrite them
void FixHardSphere::save_other_forces()
{
  fother.clear();
  if (!others_integrate) return;
  double **f = atom->f;
  const int *mask = atom->mask;
  for (int i = 0; i < atom->nlocal; i++)
    if (!(mask[i] & groupbit)) fother.insert(fother.end(), f[i], f[i] + 3);
}

void FixHardSphere::restore_other_forces()
{
  if (!others_integrate) return;
  double **f = atom->f;
  const int *mask = atom->mask;
  size_t m = 0;
  for (int i = 0; i < atom->nlocal; i++)
    if (!(mask[i] & groupbit))
      for (int k = 0; k < 3; k++) f[i][k] = fother[m++];
}

/* ----------------------------------------------------------------------
   CVA's pieces of the sub-step loop (the hooks' defaults)
------------------------------------------------------------------------- */

// no contact in the remaining tleft: plain Verlet to the step's end (its
// closing half kick in final_integrate)
void FixHardSphere::finish_step(double tleft)
{
  if (tleft == dtv) nve_initial();
  else kick_drift(tleft);
  dtf_last = (tleft == dtv) ? dtf : 0.5 * tleft * force->ftm2v;
}

// Verlet sub-step of length tau to the predicted contact; returns false if
// the method found no contact after all (it then finished the step)
bool FixHardSphere::advance_to_contact(double &tau, double, const Impulse &)
{
  if (tau > 0.0) {
    kick_drift(tau);
    recompute_forces();
    kick(tau);
    comm_vel_acc();    // ghosts' velocities at contact, for the impulse
  }
  return true;
}

void FixHardSphere::begin_collisional_step() {}
void FixHardSphere::modify_impulse(Impulse &) {}
void FixHardSphere::end_substep(double) {}
void FixHardSphere::end_collisional_step() {}

/* ---------------------------------------------------------------------- */

void FixHardSphere::final_integrate()
{
  if (local_step) {    // the local engine's closing kick
    local_engine->final_kick();
    local_step_done();
    local_step = 0;
    step_substeps = 0;
    screened_step = -1;
    return;
  }
  if (step_split) {    // closing half kicks of a split step (doc: the rule)
    end_held_split();
    return;
  }
  // no end_of_step fix can change velocities before the next step: screen
  // for it now, in the same pass as the kick, while v and f are in cache

  if (modify->n_end_of_step) {
    kick_dtf(dtf_last);
    if (step_substeps) end_collisional_step();
    return;
  }
  if (step_substeps) {    // a method may change v after the kick: screen afresh
    kick_dtf(dtf_last);
    end_collisional_step();
    screened_step = -1;
    return;
  }

  double **v = atom->v;
  double **f = atom->f;
  const double *rmass = atom->rmass;
  const double *mass = atom->mass;
  const int *type = atom->type;
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  const double t2 = dtv * dtv, h4 = 0.25 * t2 * t2;
  int flags = 0;
  double dtfm;

  // the kick is kick_dtf()'s (fix nve's) arithmetic
  for (int i = 0; i < nlocal; i++) {
    active[i] = 0.0;
    if (!(mask[i] & groupbit)) continue;
    dtfm = rmass ? dtf_last / rmass[i] : dtf_last / mass[type[i]];
    v[i][0] += dtfm * f[i][0];
    v[i][1] += dtfm * f[i][1];
    v[i][2] += dtfm * f[i][2];
    flags |= screen_atom(i, t2, h4, rmass ? force->ftm2v / rmass[i] : ftm2v_mass[type[i]]);
  }
  screened_flags = flags;
  screened_step = update->ntimestep + 1;
}

/* ---------------------------------------------------------------------- */

double FixHardSphere::compute_vector(int n)
{
  if (n >= local_vec_offset) {
    // the step engine's counters (zero while the global engine runs)
    const int k = n - local_vec_offset;
    if (k == 4) return nfallback;
    if (!local_engine) return 0.0;
    const HardSphere::ClusterCounters &c = local_engine->counters();
    switch (k) {
      case 0:
        return c.clusters;
      case 1:
        return c.mean_members();
      case 2:
        return c.max_members;
      case 3:
        return local_engine->nrounds;
      case 5:
        return local_engine->ncompute;
    }
    return 0.0;
  }
  switch (n) {
    case 0:
      return ncoll_pair + ncoll_wall;
    case 1:
      return ncoll_pair;
    case 2:
      return ncoll_wall;
    case 3:
      return ncoll_steps;
    case 4:
      return force_evals();
  }
  return 0.0;
}

/* ---------------------------------------------------------------------- */

void FixHardSphere::write_restart(FILE *fp)
{
  if (comm->me == 0) {
    std::vector<double> list_ = {ncoll_pair, ncoll_wall, ncoll_steps, force_evals()};
    for (double *c : extra_counters()) list_.push_back(*c);
    int size = list_.size() * sizeof(double);
    fwrite(&size, sizeof(int), 1, fp);
    fwrite(list_.data(), sizeof(double), list_.size(), fp);
  }
}

void FixHardSphere::restart(char *buf)
{
  const double *list_ = (const double *) buf;
  ncoll_pair = list_[0];
  ncoll_wall = list_[1];
  ncoll_steps = list_[2];
  nforce_evals = list_[3] - pot->nevals();
  int k = 4;
  for (double *c : extra_counters()) *c = list_[k++];
}

/* ---------------------------------------------------------------------- */

double FixHardSphere::memory_usage()
{
  return (double) nmax_hs * 8 * sizeof(double) + (double) cand.capacity() * sizeof(int);
}
