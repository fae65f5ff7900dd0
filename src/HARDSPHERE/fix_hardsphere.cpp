/* ----------------------------------------------------------------------
   HARDSPHERE package: shared base of the hard-sphere integrator family.
   See fix_hardsphere.h and doc/fix_hardsphere.rst.
------------------------------------------------------------------------- */

#include "fix_hardsphere.h"

#include "hs_compat.h"
#include "hs_fix_rule.h"
#include "hs_global_engine.h"
#include "hs_local_engine.h"
#include "hs_method.h"
#include "hs_potential.h"
#include "hs_system.h"

#include "atom.h"
#include "compute.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "group.h"
#include "kspace.h"
#include "modify.h"
#include "neighbor.h"
#include "pair.h"
#include "update.h"

#include <cmath>
#include <cstring>
#include <mpi.h>
#include <vector>

using namespace LAMMPS_NS;
using namespace FixConst;

/* ---------------------------------------------------------------------- */

FixHardSphere::FixHardSphere(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), style_name(arg[2]), sys(new HSSystem(lmp, this, style_name)), S(*sys)
{
  time_integrate = 1;
  vector_flag = 1;
  size_vector = 5;
  global_freq = 1;
  extvector = 0;
  virial_global_flag = 1;
  thermo_virial = 1;
  // v, a, active and an engine's extra columns (HSSystem::forward_vel_acc);
  // or an engine's columns, sparse: a position per row and a count per
  // message (HSSystem::forward_columns)
  static_assert(7 + HSSystem::COMM_EXTRA >= HSSystem::COMM_COLUMNS + 1, "comm_forward");
  comm_forward = 7 + HSSystem::COMM_EXTRA;
  comm_reverse = HSSystem::COMM_COLUMNS + 2;    // the gap, or an engine's columns (sparse)
  restart_global = 1;
  force_reneighbor = 1;    // we ask for a list build when a sphere moved skin/2
  next_reneighbor = -1;

  int iarg = 3;
  while (iarg < narg) {
    if (strcmp(arg[iarg], "diameter") == 0) {
      if (iarg + 2 > narg)
        error->all(FLERR, "Illegal fix {} command: diameter needs a value", style_name);
      if (S.diameter_flag)
        error->all(FLERR, "Fix {} diameter given twice ({} and {})", style_name, S.diameter,
                   arg[iarg + 1]);
      S.diameter = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
      if (!(S.diameter > 0.0))
        error->all(FLERR, "Fix {} diameter must be > 0, got {}", style_name, arg[iarg + 1]);
      S.diameter_flag = 1;
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
      for (const Wall &o : S.walls)
        if (o.dim == w.dim && o.side == w.side)
          error->all(FLERR, "Fix {} wall {} given twice", style_name, face);
      if (strcmp(arg[iarg + 2], "EDGE") == 0) {
        w.edge = 1;
        w.coord = 0.0;
      } else {
        w.edge = 0;
        w.coord = utils::numeric(FLERR, arg[iarg + 2], false, lmp);
      }
      S.walls.push_back(w);
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
    } else if (strcmp(arg[iarg], "overflow") == 0) {
      if (iarg + 2 > narg)
        error->all(FLERR, "Illegal fix {} command: overflow needs error, global or widen",
                   style_name);
      if (strcmp(arg[iarg + 1], "error") == 0) S.overflow = HSSystem::OVERFLOW_ERROR;
      else if (strcmp(arg[iarg + 1], "global") == 0) S.overflow = HSSystem::OVERFLOW_GLOBAL;
      else if (strcmp(arg[iarg + 1], "widen") == 0) S.overflow = HSSystem::OVERFLOW_WIDEN;
      else
        error->all(FLERR, "Fix {} overflow must be error, global or widen, got {}", style_name,
                   arg[iarg + 1]);
      iarg += 2;
    } else if (strcmp(arg[iarg], "ghost") == 0) {
      if (iarg + 2 > narg)
        error->all(FLERR, "Illegal fix {} command: ghost needs lazy N or wide", style_name);
      if (strcmp(arg[iarg + 1], "wide") == 0) {
        S.ghost_lazy = 0;
        iarg += 2;
      } else if (strcmp(arg[iarg + 1], "lazy") == 0) {
        if (iarg + 3 > narg)
          error->all(FLERR, "Illegal fix {} command: ghost lazy needs a number of steps",
                     style_name);
        S.ghost_lazy = utils::bnumeric(FLERR, arg[iarg + 2], false, lmp);
        if (S.ghost_lazy < 1)
          error->all(FLERR,
                     "Fix {} ghost lazy {}: the number of steps without contacts before the "
                     "ghost shell narrows must be >= 1 (ghost wide: never)",
                     style_name, S.ghost_lazy);
        iarg += 3;
      } else
        error->all(FLERR, "Fix {} ghost must be lazy N or wide, got {}", style_name,
                   arg[iarg + 1]);
    } else
      error->all(FLERR, "Unknown fix {} keyword: {}", style_name, arg[iarg]);
  }

  if (!S.diameter_flag && !atom->radius_flag)
    error->all(FLERR,
               "Fix {} needs the diameter keyword, or an atom style with a per-atom "
               "radius (atom_style sphere)",
               style_name);
  for (const Wall &w : S.walls) {
    std::string name;
    S.wall_name(w, name);
    if (w.dim == 2 && domain->dimension == 2)
      error->all(FLERR, "Fix {} wall {} is not allowed in a 2d simulation", style_name, name);
    if (domain->periodicity[w.dim])
      error->all(FLERR, "Fix {} wall {} is on a periodic dimension", style_name, name);
  }
}

FixHardSphere::~FixHardSphere()
{
  delete global_engine;
  delete local_engine;
  delete method;
  delete sys;
}

int FixHardSphere::setmask()
{
  // (post_force: the conservative forces before a thermostat's, capture_rule())
  return INITIAL_INTEGRATE | POST_FORCE | FINAL_INTEGRATE | PRE_EXCHANGE | POST_NEIGHBOR;
}

void FixHardSphere::post_constructor()
{
  size_vector = 5 + (method ? method->nvector() : 0);
  local_vec_offset = size_vector;
  size_vector += HSStepEngine::NCOUNTERS;
}

void FixHardSphere::init()
{
  // a wall on a shrink-wrapped face at EDGE would follow the outermost
  // sphere centres (the box edge is where they are); a wall outside the
  // box on a fixed face is never reached: spheres leave the box first
  // (LAMMPS' "Lost atoms" some steps later). A wall is the plane x[dim] =
  // coord: in a triclinic box it is the box's face only where no tilt
  // factor leans that face (the x faces lean with xy and xz, the y faces
  // with yz; the z faces never do)
  for (const Wall &w : S.walls) {
    const int b = domain->boundary[w.dim][w.side < 0 ? 0 : 1];
    std::string name;
    S.wall_name(w, name);
    if (w.edge && b == 2)
      error->all(FLERR,
                 "Fix {} wall {} EDGE on a shrink-wrapped face (boundary s): the box edge "
                 "follows the outermost sphere centres, so the wall would pass through them: "
                 "use boundary f or m there, or give the wall a coordinate",
                 style_name, name);
    const double lo = domain->boxlo[w.dim], hi = domain->boxhi[w.dim];
    if (!w.edge && b == 1 && (w.side < 0 ? w.coord < lo : w.coord > hi))
      error->all(FLERR,
                 "Fix {} wall {} at {} lies outside the box ({} to {} on a fixed boundary): "
                 "spheres would leave the box, and be lost, before they reach it: put the "
                 "wall inside the box, use EDGE, or a shrink-wrapped boundary (s or m)",
                 style_name, name, w.coord, lo, hi);
    const double lean = !domain->triclinic ? 0.0
        : w.dim == 0                       ? fabs(domain->xy) + fabs(domain->xz)
        : w.dim == 1                       ? fabs(domain->yz)
                                           : 0.0;
    if (lean != 0.0)
      error->all(FLERR,
                 "Fix {} wall {}: in a triclinic box a wall must be a face of the box, and "
                 "the tilt factors (xy {}, xz {}, yz {}) lean the {} faces: use a wall on a "
                 "face no tilt factor leans, or an orthogonal box",
                 style_name, name, domain->xy, domain->xz, domain->yz,
                 std::string(1, "xyz"[w.dim]));
  }

  // rRESPA calls only the *_respa integrate stages, which a step with
  // collisions has no form for: the atoms would silently not move
  if (utils::strmatch(update->integrate_style, "^respa"))
    error->all(FLERR,
               "Fix {} does not support run_style {}: rRESPA would not call its steps "
               "(velocity-Verlet steps with collisions), so the atoms would not move; use "
               "run_style verlet",
               style_name, update->integrate_style);
  check_other_integrators();

  // the largest radius in the group sets the contact list cutoff

  double rloc = 0.0;
  const int nlocal = atom->nlocal;
  const int *mask = atom->mask;
  for (int i = 0; i < nlocal; i++)
    if (mask[i] & S.groupbit) {
      const double r = S.radius_of(i);
      if (!(r > 0.0))
        error->one(FLERR, "Fix {}: atom {} has radius {}, hard spheres need radius > 0",
                   style_name, atom->tag[i], r);
      rloc = MAX(rloc, r);
    }
  MPI_Allreduce(&rloc, &S.rmax, 1, MPI_DOUBLE, MPI_MAX, world);
  S.max_substeps = MAX_SUBSTEPS_BASE + MAX_SUBSTEPS_PER_SPHERE * group->count(igroup);
  if (S.rmax == 0.0) S.rmax = S.diameter_flag ? 0.5 * S.diameter : 0.0;

  // the list holds every pair within 2 rmax + 2 skin of each other when it
  // was built; with LAMMPS rebuilding once an atom moved skin/2, no sphere
  // moves more than skin before the next build, so pairs outside the list
  // cannot touch (checked in screen())

  S.skin = neighbor->skin;
  S.list_cutoff = 2.0 * S.rmax + 2.0 * S.skin;

  // contact candidates come from a half list. When the pair cutoffs of all
  // type pairs in the group reach the list cutoff, LAMMPS copies the pair
  // style's list for free; otherwise the list gets its own cutoff and build.

  const int ntypes = atom->ntypes;
  std::vector<int> tloc(ntypes + 1, 0), tall(ntypes + 1, 0);
  for (int i = 0; i < nlocal; i++)
    if (mask[i] & S.groupbit) tloc[atom->type[i]] = 1;
  MPI_Allreduce(tloc.data(), tall.data(), ntypes + 1, MPI_INT, MPI_MAX, world);
  int own_list = (force->pair == nullptr) ? 1 : 0;
  for (int a = 1; a <= ntypes && !own_list; a++)
    for (int b = 1; b <= ntypes && !own_list; b++)
      if (tall[a] && tall[b] && sqrt(force->pair->cutsq[a][b]) + S.skin < S.list_cutoff) own_list = 1;

  // neighbor multi builds each type pair's list to the pair cutoff + skin
  // (its collections'), not to a request's own cutoff: pure hard spheres
  // lost every pair and collided 15 % deep before an overlap error
  if (own_list && (neighbor->style == Neighbor::MULTI || neighbor->style == Neighbor::MULTI_OLD))
    error->all(FLERR,
               "Fix {} needs its contact list out to {} (contact distance {} + 2 x skin {}), "
               "which neighbor multi does not build ({}): use neighbor {} bin, or pair "
               "cutoffs of at least {} for the pairs of the group's types",
               style_name, S.list_cutoff, 2.0 * S.rmax, S.skin,
               force->pair ? "it lists each type pair to its pair cutoff + skin"
                           : "with no pair style it lists no pairs",
               S.skin, S.list_cutoff - S.skin);

  HSCompat::request_half_list(lmp, this, instance_me, own_list ? S.list_cutoff : 0.0,
                              CONTACT_LIST_ID);

  // the derivative layer decides its paths now, and asks for a second
  // list if its path needs one
  if (method && method->needs_derivatives()) {
    S.pot->init(HSPotential::AUTO);
    S.pot->request_list(this, instance_me, POT_LIST_ID);
    const std::string path = S.pot->describe();
    if (comm->me == 0 && path != path_told)
      utils::logmesg(lmp, "fix {}: derivatives of V: {}\n", style_name, path);
    path_told = path;
  }

  // with no smooth forces at all, sub-steps need no force re-evaluation

  S.forces_present = 0;
  if (force->pair && force->pair->compute_flag && strcmp(force->pair_style, "zero") != 0)
    S.forces_present = 1;
  if (atom->molecular != Atom::ATOMIC &&
      (force->bond || force->angle || force->dihedral || force->improper))
    S.forces_present = 1;
  if (force->kspace && force->kspace->compute_flag) S.forces_present = 1;
  for (int k = 0; k < modify->nfix; k++)
    if ((modify->fmask[k] & (FixConst::PRE_FORCE | FixConst::PRE_REVERSE | FixConst::POST_FORCE)) &&
        !HardSphere::package_fix(modify->fix[k]->style))
      S.forces_present = 1;

  check_fixes_beside();
  check_peratom_virial();
  choose_engine();
  if (method) method->engine_chosen(engine && engine == local_engine);
  // the global engine and mcva's stages evaluate every fix's forces at
  // sub-steps, a constraint fix's too
  if (!constraint_beside.empty() && engine && engine == local_engine &&
      S.overflow == HSSystem::OVERFLOW_GLOBAL)
    error->all(FLERR,
               "Fix {} cannot run beside {} with overflow global: its steps taken globally "
               "evaluate the forces of every fix at each contact, and that fix's constraint "
               "forces are computed for one velocity-Verlet step of dt (use overflow widen or "
               "a larger comm_modify cutoff)",
               style_name, constraint_beside);
  if (!constraint_beside.empty() && engine == global_engine && engine)
    error->all(FLERR,
               "Fix {} cannot run beside {} with substep global: the global engine evaluates "
               "the forces of every fix at each contact, and that fix's constraint forces "
               "are computed for one velocity-Verlet step of dt. Its group shares no atom "
               "with this fix's, so substep local (the default of cva, pcva, mcva and vci) or "
               "hardsphere/psa can run beside it",
               style_name, constraint_beside);
  capture_rule();

  // the contact list needs ghost atoms out to its cutoff: checked here,
  // before newer LAMMPS (4Feb2025) checks the request with a vaguer message,
  // and after the local engine on several ranks raised the ghost cutoff to
  // what it needs (more than this)
  // (comm_modify mode multi: per collection, checked at set-up)
  const double cutghost = HSCompat::ghost_cutoff_at_init(lmp);
  if (comm->mode == Comm::SINGLE && cutghost < S.list_cutoff)
    error->all(FLERR,
               "Fix {} needs ghost atoms out to {} (contact distance {} + 2 x skin {}), "
               "but the ghost cutoff is {}: use comm_modify cutoff {} or a pair style "
               "with a larger cutoff",
               style_name, S.list_cutoff, 2.0 * S.rmax, S.skin, cutghost, S.list_cutoff);
  reset_dt();
  if (method) method->init();
}

void FixHardSphere::choose_engine()
{
  engine = nullptr;
  S.fallback_counting = 0;
  if (!method) return;    // psa: it takes its steps itself
  const int support = method->engines_supported();
  if (support == HSMethod::ENGINE_NONE) return;
  if (!global_engine) global_engine = new HSGlobalEngine(lmp, S, *method);
  engine = global_engine;
  if (substep_mode == SUBSTEP_GLOBAL) return;
  if (support == HSMethod::ENGINE_GLOBAL_ONLY) {
    if (substep_mode == SUBSTEP_LOCAL)
      error->all(FLERR,
                 "Fix {} substep local is not available yet: only hardsphere/cva, /pcva, /mcva "
                 "and /vci (and psa, local by construction) have the local engine; use substep "
                 "global",
                 style_name);
    return;
  }
  if (!local_engine) local_engine = new HSLocalEngine(lmp, S, *method);
  std::string why = local_engine->limits();
  const std::string own = method->local_limits();
  if (!own.empty()) why += (why.empty() ? "" : "; ") + own;
  if (why.empty()) {
    engine = local_engine;
    local_engine->chosen();
    if (comm->me == 0 && local_why_told != "local")
      utils::logmesg(lmp, "fix {}: substep local (collisions sub-stepped per cluster)\n",
                     style_name);
    local_why_told = "local";
    return;
  }
  if (substep_mode == SUBSTEP_LOCAL)
    error->all(FLERR, "Fix {} substep local cannot run with {}: use substep global", style_name,
               why);
  S.fallback_counting = 1;
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
  constraint_beside.clear();
  bool press_beside = false;
  for (int k = 0; k < modify->nfix; k++)
    if (HardSphere::base_style(modify->fix[k]->style) == "hardsphere/press") press_beside = true;
  // (psa evaluates the forces once per step, as beside fix nve)
  if (method && force->pair)
    for (const auto &name : HardSphere::velocity_pair_names())
      if (force->pair_match(name, 1, 1))
        error->all(FLERR,
                   "Fix {} cannot run with pair style {}: its forces depend on the velocities "
                   "or are random, and a collisional step evaluates the pair forces again at "
                   "every contact as forces of the positions (a random force drawn anew at "
                   "each sub-step, a drag at mid-flight velocities). Use conservative pair "
                   "styles with a thermostat fix such as fix langevin (its forces are held "
                   "through collisional steps), or fix hardsphere/psa (one force evaluation "
                   "per step)",
                   style_name, name);
  for (int k = 0; k < modify->nfix; k++) {
    Fix *other = modify->fix[k];
    if (other == this) continue;
    // fix hardsphere/press changes the box only by moves that create no
    // overlap (Monte Carlo volume moves with the overlap test)
    if ((other->box_change & (Fix::BOX_CHANGE_SIZE | Fix::BOX_CHANGE_SHAPE)) &&
        HardSphere::base_style(other->style) != "hardsphere/press")
      error->all(FLERR,
                 "Fix {} cannot run beside fix {} {}: it changes the box during the run and "
                 "rescales positions without regard to the spheres' contacts, which makes "
                 "hard spheres overlap. Use fix hardsphere/press for a barostat, or run at "
                 "constant volume (a box changed between runs is checked for overlaps at "
                 "set-up)",
                 style_name, other->id, other->style);
    const std::string base = HardSphere::base_style(other->style);
    if (HardSphere::fix_force_kind(other->style) == HardSphere::FixForceKind::REFUSED) {
      if (!S.group_apart(other->igroup))
        error->all(FLERR,
                   "Fix {} cannot run beside fix {} {} on atoms of its group: its constraint "
                   "forces are computed for one velocity-Verlet step of dt, which the "
                   "collisional sub-steps break (on a group that shares no atom with this "
                   "fix's, e.g. a rigid solvent, it can)",
                   style_name, other->id, other->style);
      // (its molecules beside the spheres: untouched by a collisional step
      // unless the step evaluates every fix, below; a barostat rescales them)
      if (press_beside)
        error->all(FLERR,
                   "Fix {} cannot run beside fix {} {} and fix hardsphere/press: the "
                   "barostat's volume moves rescale the constrained molecules' atoms",
                   style_name, other->id, other->style);
      constraint_beside = fmt::format("fix {} {}", other->id, other->style);
    }
    // (reflected after this fix's step, a sphere may land inside another:
    // found as "a collision was missed" a few steps later)
    if ((base == "wall/reflect" || base == "wall/reflect/stochastic") &&
        S.shares_atoms(other->groupbit))
      error->all(FLERR,
                 "Fix {} cannot run beside fix {} {} on the same atoms: it reflects atoms "
                 "after this fix's step, without regard to the spheres' contacts (a sphere "
                 "reflected into another overlaps it). Use this fix's wall keyword (e.g. wall "
                 "zlo EDGE), whose wall contacts are elastic impulses at the contact time",
                 style_name, other->id, other->style);
    if (base == "langevin" &&
        (modify->fmask[k] & (FixConst::INITIAL_INTEGRATE | FixConst::POST_INTEGRATE)))
      error->all(FLERR,
                 "Fix {} cannot run beside fix {} langevin with the gjf keyword: GJF changes "
                 "positions and velocities as one velocity-Verlet step of dt, which the "
                 "collisional sub-steps break; use gjf no",
                 style_name, other->id);
  }

  S.pot->init_fixes();
  const std::string unknown = S.pot->unknown_names();
  if (!unknown.empty() && comm->me == 0 && unknown != unknown_told)
    error->warning(FLERR,
                   "Fix {}: the forces of {} are of a kind it does not know; they are "
                   "treated as conservative (a function of the positions) and evaluated again "
                   "at every collisional sub-step. If they are stochastic or depend on "
                   "velocities, statistics will be wrong",
                   style_name, unknown);
  unknown_told = unknown;
  S.nheld = S.pot->held_any() ? 1 : 0;
  const std::string held = S.pot->held_names();
  if (S.nheld && comm->me == 0 && held != held_told)
    utils::logmesg(lmp,
                   "fix {}: forces of {} held through collisional steps (two half kicks "
                   "around the method's conservative map)\n",
                   style_name, held);
  held_told = held;
}

/* ----------------------------------------------------------------------
   held forces without an evaluation: with held (thermostat) forces, the
   engines split f into its conservative and held parts (the local engine
   for the colliding spheres, the global one for all). LAMMPS' f holds the
   conservative force between the post_force() of the fixes whose forces
   are part of it (gravity, enforce2d; with the global engine any
   conservative fix) and those of the held fixes, which add theirs in the
   input's order: if this fix comes between them, its post_force() copies
   f there and the engine takes f - that copy; else the engine evaluates
   the conservative force again (the same forces, to round-off), or, with
   held smooth forces in the local engine, lets the thermostat's forces
   ride with them (HSStepEngine::uncaptured_cost() says which in the log).
   The engine says whether it can (HSStepEngine::takes_captured_forces())
------------------------------------------------------------------------- */

void FixHardSphere::capture_rule()
{
  S.cap_on = 0;
  S.uncapture();
  if (!engine || !engine->takes_captured_forces()) return;
  const std::string why = S.pot->capture_order(this);
  if (why.empty()) {
    S.cap_on = 1;
    capture_told.clear();
    return;
  }
  if (comm->me == 0 && why != capture_told)
    utils::logmesg(lmp,
                   "fix {}: {}, so the force it sees in its post_force stage is not the "
                   "conservative force alone: {}. Define thermostats after fix {} and force "
                   "fixes before it to save that\n",
                   style_name, why, engine->uncaptured_cost(), id);
  capture_told = why;
}

// f between the force fixes' post_force and the held fixes' (capture_rule())
void FixHardSphere::post_force(int)
{
  if (S.cap_on) S.capture_forces();
}

double **FixHardSphere::captured_forces() const
{
  return S.captured(false);
}

// the collisions' impulses enter the global virial only (add_impulse_virial):
// a compute of per-atom virials (stress/atom, centroid/stress/atom) would sum
// to the pressure without them, silently
void FixHardSphere::check_peratom_virial()
{
  std::string ids;
  for (int k = 0; k < modify->ncompute; k++)
    if (modify->compute[k]->pressatomflag)
      ids += fmt::format("{}{} {}", ids.empty() ? "" : ", ", modify->compute[k]->id,
                         modify->compute[k]->style);
  if (!ids.empty() && comm->me == 0 && ids != peratom_told)
    error->warning(FLERR,
                   "Fix {}: compute {} leaves out the collisions' virial: this fix gives "
                   "their impulses to the global virial (thermo press) only, so per-atom "
                   "stresses sum to the pressure without them",
                   style_name, ids);
  peratom_told = ids;
}

void FixHardSphere::check_other_integrators()
{
  S.other_integrator = nullptr;
  for (int k = 0; k < modify->nfix; k++) {
    Fix *other = modify->fix[k];
    if (other == this || !other->time_integrate) continue;
    if (!S.other_integrator) S.other_integrator = other;
    if (!S.shares_atoms(other->groupbit)) continue;
    // Nose-Hoover and Parrinello-Rahman styles are integrators too: say
    // what gives their ensembles beside this fix
    const std::string os = HardSphere::base_style(other->style);
    std::string hint;
    if (os.rfind("nvt", 0) == 0 || os == "temp/nosehoover")
      hint = " (constant temperature: a thermostat that adds forces or rescales velocities "
             "runs beside this fix, e.g. fix langevin, temp/berendsen or temp/rescale)";
    else if (os.rfind("npt", 0) == 0 || os.rfind("nph", 0) == 0)
      hint = " (constant pressure: fix hardsphere/press beside this fix, with a thermostat "
             "such as fix langevin)";
    error->all(FLERR,
               "Fix {} {} and fix {} {} both time-integrate the atoms common to group {} "
               "and group {}: use one integrator per atom{}",
               id, style_name, other->id, other->style, group->names[igroup],
               group->names[other->igroup], hint);
  }
}

void FixHardSphere::init_list(int id, NeighList *ptr)
{
  if (id == POT_LIST_ID) sys->pot->init_list(ptr);
  else sys->list = ptr;
}

/* ----------------------------------------------------------------------
   the first neigh_modify exclusion (as its arguments) that can remove a
   pair of two atoms of the group from the lists, "" if none: by the
   exclusion data Neighbor::init() sets (NPair::exclusion()'s tests);
   conservative for molecules (any atom of the group in the group named)
------------------------------------------------------------------------- */

std::string FixHardSphere::excluded_group_pairs() const
{
  if (!neighbor->exclude) return "";
  const int ntypes = atom->ntypes;
  const int ntests = neighbor->nex_group + neighbor->nex_mol;
  // per type: an atom of the group; per group (mol) test: an atom of the
  // group in its first group, in its second
  std::vector<int> mine(ntypes + 1 + 2 * ntests, 0), all(mine.size(), 0);
  const int *mask = atom->mask, *type = atom->type;
  for (int i = 0; i < atom->nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    mine[type[i]] = 1;
    int *g = &mine[ntypes + 1];
    for (int m = 0; m < neighbor->nex_group; m++) {
      if (mask[i] & neighbor->ex1_bit[m]) g[2 * m] = 1;
      if (mask[i] & neighbor->ex2_bit[m]) g[2 * m + 1] = 1;
    }
    for (int m = 0; m < neighbor->nex_mol; m++)
      if (mask[i] & neighbor->ex_mol_bit[m]) g[2 * (neighbor->nex_group + m)] = 1;
  }
  MPI_Allreduce(mine.data(), all.data(), (int) mine.size(), MPI_INT, MPI_MAX, world);
  if (neighbor->nex_type)    // (ex_type exists only then)
    for (int a = 1; a <= ntypes; a++)
      for (int b = a; b <= ntypes; b++)
        if (all[a] && all[b] && neighbor->ex_type[a][b]) return fmt::format("type {} {}", a, b);
  const int *g = &all[ntypes + 1];
  for (int m = 0; m < neighbor->nex_group; m++)
    if (g[2 * m] && g[2 * m + 1])
      return fmt::format("group {} {}", group->names[neighbor->ex1_group[m]],
                         group->names[neighbor->ex2_group[m]]);
  for (int m = 0; m < neighbor->nex_mol; m++)
    if (g[2 * (neighbor->nex_group + m)])
      return fmt::format("{} {}", neighbor->ex_mol_intra[m] ? "molecule/intra" : "molecule/inter",
                         group->names[neighbor->ex_mol_group[m]]);
  return "";
}

/* ----------------------------------------------------------------------
   comm_modify mode multi (multi/old): Comm takes each collection's (type's)
   ghost cutoff from cutoff/multi and the pair cutoffs, not from comm_modify
   cutoff, which init() and the local engine set; with too few ghosts the
   local engine's clusters lacked terms on several ranks (other collisions
   than on one rank, or an overlap error). After Neighbor::init() and
   Comm::init() (the collections, the user's cutoffs): the smallest
   collection's ghost cutoff (a lower bound of Comm::setup()'s: its own
   pairs' cutoff and the user's) must reach what the fix needs
------------------------------------------------------------------------- */

void FixHardSphere::check_multi_ghosts()
{
  const double need = MAX(S.list_cutoff, engine ? engine->ghost_needed() : 0.0);
  const bool old = comm->mode == Comm::MULTIOLD;
  const int n = old ? atom->ntypes : neighbor->ncollections;
  double least = -1.0;
  int which = 0;
  for (int k = 0; k < n; k++) {
    double cut;
    if (old)
      cut = MAX(neighbor->cuttype[k + 1],
                comm->cutusermultiold ? comm->cutusermultiold[k + 1] : 0.0);
    else
      cut = MAX(sqrt(neighbor->cutcollectionsq[k][k]),
                comm->cutusermulti ? comm->cutusermulti[k] : 0.0);
    if (least < 0.0 || cut < least) {
      least = cut;
      which = old ? k + 1 : k;
    }
  }
  if (n == 0 || least >= need) return;
  const char *mode = old ? "multi/old" : "multi";
  const std::string why = (engine && engine->ghost_needed() > S.list_cutoff)
      ? "substep local on several ranks: the neighbor cutoff plus two contact-list cutoffs"
      : "the contact list: contact distance + 2 x skin";
  error->all(FLERR,
             "Fix {} needs ghost atoms out to {} ({}), but comm_modify mode {} gives {} {} "
             "a ghost cutoff of {}: use comm_modify mode {} {} * {} (the fix sets the ghost "
             "cutoff itself in mode single only)",
             style_name, need, why, mode, old ? "type" : "collection", which, least, mode,
             old ? "cutoff/multi/old" : "cutoff/multi", need);
}

void FixHardSphere::reset_dt()
{
  // (contacts are predicted within [0, dt]: a negative step found none and
  // the spheres ran into each other; fix nve runs backwards, this does not)
  if (update->dt < 0.0)
    error->all(FLERR,
               "Fix {}: the timestep {} is negative; contacts are predicted forward in time "
               "only (to run backwards, negate the velocities, e.g. velocity all set v_mvx "
               "v_mvy v_mvz with atom variables mvx = -vx, ..., and run with a positive "
               "timestep)",
               style_name, update->dt);
  S.dtv = update->dt;
  S.dtf = 0.5 * update->dt * force->ftm2v;
}

void FixHardSphere::setup(int)
{
  // per-type ftm2v / m for the screening pass (mass may change between runs)

  if (!atom->rmass) {
    S.ftm2v_mass.assign(atom->ntypes + 1, 0.0);
    for (int t = 1; t <= atom->ntypes; t++) S.ftm2v_mass[t] = force->ftm2v / atom->mass[t];
  }

  if (comm->mode != Comm::SINGLE) check_multi_ghosts();

  // Neighbor::init() (after ours) sets neighbor->exclude: checked here.
  // Only an exclusion that can take a pair of the group's atoms off the
  // lists matters (those pass through each other); one among other atoms,
  // e.g. a frozen wall's with itself, does not
  const std::string excluded = excluded_group_pairs();
  if (!excluded.empty())
    error->all(FLERR,
               "Fix {} cannot be used with neigh_modify exclude {}: it takes pairs of "
               "the atoms of group {} off the neighbor lists, which would pass through "
               "each other",
               style_name, excluded, group->names[igroup]);

  // the impulse virial is that of the step taken last: a run that goes on
  // from that step reports the same pressure on its first thermo line as
  // the last run on its last (a set-up takes no step, so has no collisions
  // of its own); else none
  if (update->ntimestep != virial_step)
    for (int k = 0; k < 6; k++) virial[k] = 0.0;
  S.dtf_last = S.dtf;
  S.screened_step = -1;
  S.held_step = -1;
  S.step_split = 0;
  set_up = true;
  // the set-up's forces, for the first step (LAMMPS' set-up calls the fixes'
  // setup() in the input's order; a thermostat's calls its post_force())
  post_force(0);
}

// the state a run ends with: the next run, if it skips its set-up, must
// start from it (check_state_kept())
void FixHardSphere::post_run()
{
  S.drop_deferred();    // (the last closing kick's, for a step not taken)
  end_state = S.state_fingerprint();
  ended = true;
  set_up = false;
  // (a minimization calls post_run() too, its whichflag still set: its
  // list builds and forces are the minimizer's, not this fix's)
  minimized = update->whichflag == 2;
}

// at the first step of a run without set-up (run ... pre no): LAMMPS then
// builds no lists and computes no forces, and the ghost atoms keep what
// they were sent at the last reneighboring; a command between the runs
// that changed positions, radii, masses or the box (set, displace_atoms,
// change_box, mass, ...) would leave the contact candidates, their gaps,
// the ghosts' copies and the forces of the old state (fix nve, which reads
// only owned atoms' masses, is not affected; this fix would collide with
// stale radii and masses, differently on different numbers of ranks)
void FixHardSphere::check_state_kept()
{
  if (set_up) return;
  set_up = true;    // (checked once per run)
  if (!ended)
    error->all(FLERR,
               "Fix {} was defined after the last run, and this run skipped its set-up (run "
               "... pre no): a new fix needs the set-up (use pre yes)",
               style_name);
  if (minimized)
    error->all(FLERR,
               "Fix {}: a minimization ran since the last run, and this run skipped its "
               "set-up (run ... pre no): the neighbor lists, ghost atoms and forces are the "
               "minimizer's: use pre yes after minimize",
               style_name);
  S.check_atoms_unchanged();    // (per rank: names the rank and the counts)
  S.raise_deferred();
  if (S.state_fingerprint() != end_state)
    error->all(FLERR,
               "Fix {}: the atoms' positions, radii or masses, or the box, changed since the "
               "last run ended (set, displace_atoms, change_box, mass, write_restart, ...) and "
               "this run skipped its set-up (run ... pre no), which would leave the neighbor "
               "lists, ghost atoms, forces and contact candidates of the old state: use pre "
               "yes after such a change",
               style_name);
}

// (the local engine's ghost shell narrows when no contact came for a while)
void FixHardSphere::pre_exchange()
{
  if (engine) engine->pre_exchange();
}

void FixHardSphere::setup_post_neighbor()
{
  sys->reset_reference(1);
}

void FixHardSphere::post_neighbor()
{
  sys->reset_reference(0);
}


/* ----------------------------------------------------------------------
   a step: fix nve's arithmetic unless screening finds spheres that may
   touch within it; such a step goes to the engine
------------------------------------------------------------------------- */

// the impulse virial of the step that begins (setup() keeps it for a run
// that goes on from this step)
void FixHardSphere::begin_step_virial()
{
  for (int k = 0; k < 6; k++) virial[k] = 0.0;
  virial_step = update->ntimestep;
}

void FixHardSphere::initial_integrate(int)
{
  begin_step_virial();
  check_state_kept();    // (a run without set-up: its first step)
  const int allflags = S.screen_step();
  S.step_collided = 0;
  S.released.type = -1;
  if (!(allflags & ACTIVE)) {
    S.nve_initial();
    S.dtf_last = S.dtf;
    if (allflags & FAR) S.request_rebuild();
    return;
  }
  stepped = engine;
  if (!engine->step()) {
    // the local engine declined (overflow global): this step is global's
    stepped = global_engine;
    S.nfallback += 1.0;
    global_engine->step();
  }
}

void FixHardSphere::final_integrate()
{
  HSStepEngine *e = stepped ? stepped : engine;
  stepped = nullptr;
  if (e && e->finish()) return;
  sys->closing_kick();
}

/* ---------------------------------------------------------------------- */

double FixHardSphere::compute_vector(int n)
{
  if (n >= local_vec_offset) {
    // the step engines' counters (the local engine's, zero without one)
    const int k = n - local_vec_offset;
    if (k == 4) return S.nfallback;
    return local_engine ? local_engine->counter(k) : 0.0;
  }
  if (n >= 5) return method->vector(n - 5);
  switch (n) {
    case 0:
      return S.ncoll_pair + S.ncoll_wall;
    case 1:
      return S.ncoll_pair;
    case 2:
      return S.ncoll_wall;
    case 3:
      return S.ncoll_steps;
    case 4:
      return S.force_evals();
  }
  return 0.0;
}

/* ----------------------------------------------------------------------
   communication: the system layer's buffers (v, a, active forward; the
   free gap reverse)
------------------------------------------------------------------------- */

int FixHardSphere::pack_forward_comm(int n, int *list_, double *buf, int, int *)
{
  return sys->pack_forward_comm(n, list_, buf);
}

void FixHardSphere::unpack_forward_comm(int n, int first, double *buf)
{
  sys->unpack_forward_comm(n, first, buf);
}

int FixHardSphere::pack_reverse_comm(int n, int first, double *buf)
{
  return sys->pack_reverse_comm(n, first, buf);
}

void FixHardSphere::unpack_reverse_comm(int n, int *list_, double *buf)
{
  sys->unpack_reverse_comm(n, list_, buf);
}

/* ---------------------------------------------------------------------- */

void FixHardSphere::write_restart(FILE *fp)
{
  if (comm->me == 0) {
    std::vector<double> list_ = {S.ncoll_pair, S.ncoll_wall, S.ncoll_steps, S.force_evals()};
    if (method)
      for (double *c : method->counters()) list_.push_back(*c);
    int size = list_.size() * sizeof(double);
    fwrite(&size, sizeof(int), 1, fp);
    fwrite(list_.data(), sizeof(double), list_.size(), fp);
  }
}

void FixHardSphere::restart(char *buf)
{
  const double *list_ = (const double *) buf;
  S.ncoll_pair = list_[0];
  S.ncoll_wall = list_[1];
  S.ncoll_steps = list_[2];
  S.nforce_evals = list_[3] - S.pot->nevals();
  int k = 4;
  if (method)
    for (double *c : method->counters()) *c = list_[k++];
}

/* ---------------------------------------------------------------------- */

double FixHardSphere::sphere_radius(int i) const
{
  return S.radius_of(i);
}

void FixHardSphere::box_changed()
{
  S.held_step = -1;
  S.screened_step = -1;
  S.uncapture();    // (forces of the old box)
}

/* ---------------------------------------------------------------------- */

double FixHardSphere::memory_usage()
{
  return sys->memory_usage() + (method ? method->memory_usage() : 0.0) +
      (local_engine ? local_engine->memory_usage() : 0.0) +
      (global_engine ? global_engine->memory_usage() : 0.0);
}

// fix_modify keywords of the method (mcva: stages)
int FixHardSphere::modify_param(int narg, char **arg)
{
  return method ? method->modify_param(narg, arg) : 0;
}
