/* ----------------------------------------------------------------------
   HARDSPHERE package: fix hardsphere/press. See fix_hardsphere_press.h and
   doc/fix_hardsphere_press.rst (the derivation of the acceptance rule).
------------------------------------------------------------------------- */

#include "fix_hardsphere_press.h"

#include "fix_hardsphere.h"
#include "hs_compat.h"
#include "hs_fix_rule.h"
#include "hs_potential.h"

#include "angle.h"
#include "atom.h"
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
#include "random_park.h"
#include "update.h"

#include <cmath>
#include <cstring>
#include <mpi.h>

using namespace LAMMPS_NS;
using namespace FixConst;

namespace {
constexpr double PI = 3.14159265358979323846;
// reduced pressure P sigma^3 / kT of the hard-sphere fluid at freezing
// (coexistence with the fcc solid, packing fractions 0.494 / 0.545)
constexpr double P_FREEZE = 11.57;
// close packing of equal spheres (fcc)
constexpr double ETA_CP = 0.74048;
constexpr double TARGET_ACCEPTANCE = 0.4;
constexpr int ADAPT_BLOCK = 20;    // attempts per adaptation of delta
enum { NRESTART = 7 };
// number of dimensions in a set (bit mask of x, y, z)
inline int nbits(int set)
{
  return (set & 1) + ((set >> 1) & 1) + ((set >> 2) & 1);
}
}    // namespace

/* ---------------------------------------------------------------------- */

FixHardSpherePress::FixHardSpherePress(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
{
  if (narg < 7)
    error->all(FLERR,
               "Illegal fix hardsphere/press command: expected fix ID group hardsphere/press "
               "iso|aniso Pstart Pstop Pdamp temp T seed S [keyword value ...]");
  if (strcmp(arg[3], "iso") == 0) couple = "xyz";
  else if (strcmp(arg[3], "aniso") == 0) couple = "none";
  else
    error->all(FLERR,
               "Fix hardsphere/press: expected iso (one volume, all dimensions scaled alike) or "
               "aniso (each dimension, or each coupled set, scaled by its own moves), got {}",
               arg[3]);
  p_start = utils::numeric(FLERR, arg[4], false, lmp);
  p_stop = utils::numeric(FLERR, arg[5], false, lmp);
  p_period = utils::numeric(FLERR, arg[6], false, lmp);
  if (!std::isfinite(p_start) || !std::isfinite(p_stop))
    error->all(FLERR, "Fix hardsphere/press: Pstart and Pstop must be finite, got {} {}",
               arg[4], arg[5]);
  if (!(p_period > 0.0))
    error->all(FLERR, "Fix hardsphere/press Pdamp must be > 0 (the time between volume moves), "
               "got {}", arg[6]);

  int iarg = 7;
  while (iarg < narg) {
    const std::string key = arg[iarg];
    if (iarg + 2 > narg)
      error->all(FLERR, "Illegal fix hardsphere/press command: {} needs a value", key);
    if (key == "temp") {
      t_target = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
      if (!(t_target > 0.0))
        error->all(FLERR, "Fix hardsphere/press temp must be > 0, got {}", arg[iarg + 1]);
    } else if (key == "seed") {
      seed = utils::inumeric(FLERR, arg[iarg + 1], false, lmp);
      if (seed <= 0)
        error->all(FLERR, "Fix hardsphere/press seed must be > 0, got {}", arg[iarg + 1]);
    } else if (key == "every") {
      nevery = utils::inumeric(FLERR, arg[iarg + 1], false, lmp);
      if (nevery <= 0)
        error->all(FLERR, "Fix hardsphere/press every must be > 0, got {}", arg[iarg + 1]);
      every_flag = 1;
    } else if (key == "delta") {
      delta = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
      if (!(delta > 0.0))
        error->all(FLERR, "Fix hardsphere/press delta must be > 0, got {}", arg[iarg + 1]);
    } else if (key == "couple") {
      couple = arg[iarg + 1];
      if (couple != "none" && couple != "xyz" && couple != "xy" && couple != "yz" &&
          couple != "xz")
        error->all(FLERR, "Fix hardsphere/press couple must be none, xyz, xy, yz or xz, got {}",
                   couple);
      if (strcmp(arg[3], "iso") == 0 && couple != "xyz")
        error->all(FLERR,
                   "Fix hardsphere/press iso scales x, y and z together (couple xyz); couple "
                   "{} needs aniso",
                   couple);
    } else if (key == "adapt") {
      adapt_attempts = utils::bnumeric(FLERR, arg[iarg + 1], false, lmp);
      if (adapt_attempts < 0)
        error->all(FLERR, "Fix hardsphere/press adapt must be >= 0, got {}", arg[iarg + 1]);
    } else
      error->all(FLERR, "Unknown fix hardsphere/press keyword: {}", key);
    iarg += 2;
  }
  if (!(t_target > 0.0))
    error->all(FLERR,
               "Fix hardsphere/press needs the temp keyword: the Monte Carlo acceptance "
               "exp(-(dU + P dV)/kT) needs the temperature the thermostat or the initial "
               "velocities give the system");
  if (seed <= 0)
    error->all(FLERR, "Fix hardsphere/press needs the seed keyword (a positive integer)");

  dimension = domain->dimension;
  for (int d = 0; d < dimension; d++)
    if (!domain->periodicity[d])
      error->all(FLERR,
                 "Fix hardsphere/press {} scales the {} dimension, which is not periodic: "
                 "use boundary p p p (p p in 2d); a wall or shrink-wrapped boundary does not "
                 "move with the volume",
                 arg[3], "xyz"[d]);
  if (domain->triclinic)
    error->all(FLERR, "Fix hardsphere/press does not support triclinic boxes");

  // the sets of dimensions a move scales together (one set per move, drawn
  // uniformly): iso one set of all; aniso one per dimension or coupled set
  int coupled = 0;
  if (couple != "none")
    for (char c : couple) coupled |= 1 << (c - 'x');
  if (dimension == 2) coupled &= 3;    // z is not a dimension in 2d
  if (coupled == 1 || coupled == 2 || coupled == 4) coupled = 0;
  if (coupled) move_sets.push_back(coupled);
  for (int d = 0; d < dimension; d++)
    if (!(coupled & (1 << d))) move_sets.push_back(1 << d);

  // a fix defined before that changes the box too (one defined later: the
  // check in init(), or LAMMPS' own "multiple fixes change box parameter")
  for (int k = 0; k < modify->nfix; k++)
    if (modify->fix[k]->box_change & (BOX_CHANGE_SIZE | BOX_CHANGE_SHAPE)) box_fix_error(modify->fix[k]);

  // the same sequence on every rank: every move is decided alike everywhere
  random = new RanPark(lmp, seed);

  box_change |= BOX_CHANGE_X | BOX_CHANGE_Y;
  if (dimension == 3) box_change |= BOX_CHANGE_Z;
  no_change_box = 1;
  force_reneighbor = 1;    // the lists are built on the step of each move
  next_reneighbor = -1;
  vector_flag = 1;
  size_vector = 8;
  global_freq = 1;
  extvector = 0;
  restart_global = 1;
  pot = new HSPotential(lmp, groupbit, "fix hardsphere/press");
  grow_arrays(atom->nmax);
  atom->add_callback(Atom::GROW);
}

FixHardSpherePress::~FixHardSpherePress()
{
  atom->delete_callback(id, Atom::GROW);
  memory->destroy(fheld);
  delete random;
  delete pot;
}

int FixHardSpherePress::setmask()
{
  return END_OF_STEP;
}

/* ---------------------------------------------------------------------- */

void FixHardSpherePress::init()
{
  if (domain->triclinic)
    error->all(FLERR, "Fix hardsphere/press does not support triclinic boxes");

  // one fix changes the box; the hardsphere fixes supply the spheres
  hs.clear();
  for (int k = 0; k < modify->nfix; k++) {
    Fix *other = modify->fix[k];
    if (other == this) continue;
    if (other->box_change & (BOX_CHANGE_SIZE | BOX_CHANGE_SHAPE)) box_fix_error(other);
    if (utils::strmatch(HardSphere::base_style(other->style), "^hardsphere/"))
      hs.push_back(dynamic_cast<FixHardSphere *>(other));
  }
  for (auto *f : hs)
    if (!f) error->all(FLERR, "Fix hardsphere/press: a hardsphere fix of an unknown kind");
  if (hs.empty())
    error->all(FLERR,
               "Fix hardsphere/press needs a fix of the hardsphere family (psa, cva, pcva, "
               "mcva, vci): it takes the spheres' diameters and the overlap test from it");

  // attempt period: every keyword, else Pdamp in steps
  if (!every_flag) nevery = MAX(1, (int) lround(p_period / update->dt));

  // the largest contact distance of any two spheres (a pair counts if both
  // are in one hardsphere fix's group)
  double rloc = 0.0;
  const int nlocal = atom->nlocal;
  for (int i = 0; i < nlocal; i++)
    for (auto *f : hs)
      if (atom->mask[i] & f->groupbit) rloc = MAX(rloc, f->sphere_radius(i));
  double rmax = 0.0;
  MPI_Allreduce(&rloc, &rmax, 1, MPI_DOUBLE, MPI_MAX, world);
  contact_max = 2.0 * rmax;
  ngroup = group->count(igroup);
  if (ngroup == 0) error->all(FLERR, "Fix hardsphere/press group {} has no atoms", group->names[igroup]);

  // the smooth potential energy, if any (pure hard spheres: none)
  smooth = 0;
  cut_max = 0.0;
  if (force->pair && force->pair->compute_flag && strcmp(force->pair_style, "zero") != 0) {
    smooth = 1;
    cut_max = force->pair->cutforce;
  }
  if (atom->molecular != Atom::ATOMIC &&
      (force->bond || force->angle || force->dihedral || force->improper))
    smooth = 1;
  if (force->kspace) smooth = 1;
  for (int k = 0; k < modify->nfix; k++)
    if (modify->fix[k]->energy_global_flag && modify->fix[k]->thermo_energy) smooth = 1;
  // thermostat forces (hs_fix_rule.h: held) are kept through a move
  pot->init_fixes();
  held = pot->held_any() ? 1 : 0;
  if (smooth || held) pot->init(HSPotential::AUTO);

  // moves stay within what the lists hold: a pair closer than c after
  // scaling by s was closer than c/s before, which is in a list of cutoff
  // c + skin built at the current positions if s >= c / (c + skin). The
  // pair list of the energy is such a list on the move's step, whose build
  // is forced; the contact list of the overlap test has a skin more
  const double skin = neighbor->skin;
  if (!(skin > 0.0))
    error->all(FLERR,
               "Fix hardsphere/press needs a neighbor skin > 0: a volume move is limited to "
               "what the neighbor lists built with that skin can hold");
  double smin = contact_max / (contact_max + skin);
  if (smooth && cut_max > 0.0) smin = MAX(smin, cut_max / (cut_max + skin));
  // a move of ln V by x scales each of its k dimensions by exp(x/k)
  int kmin = dimension;
  for (int set : move_sets) kmin = MIN(kmin, nbits(set));
  delta_max = 2.0 * kmin * log(1.0 / smin);
  if (delta > delta_max) {
    if (comm->me == 0)
      error->warning(FLERR,
                     "Fix hardsphere/press delta {} is wider than the neighbor skin {} allows; "
                     "using {}",
                     delta, skin, delta_max);
    delta = delta_max;
  }

  // a box length below twice the largest cutoff (minimum image) or two
  // contact distances is an error, not a rejection: rejecting would bias
  // the volume distribution
  length_min = 2.0 * MAX(contact_max, cut_max);
  double vol = volume();
  check_box(domain->prd, vol);
  check_target(p_start);
  check_target(p_stop);

  // the contact list of the overlap test, cutoff contact distance + 2 skin
  // as the hardsphere fixes' own (LAMMPS may share it): between builds no
  // sphere moves more than skin/2 (the hardsphere fixes rebuild then), so a
  // pair closer than c/s now was closer than c/s + skin <= c + 2 skin at
  // the build for s >= c / (c + skin)
  // (under neighbor multi, the pairs of one hardsphere fix's types are
  // listed to the contact list's cutoff or that fix's init() stopped)
  HSCompat::request_half_list(lmp, this, instance_me, contact_max + 2.0 * skin, 0);
}

void FixHardSpherePress::box_fix_error(Fix *other)
{
  error->all(FLERR,
             "Fix hardsphere/press cannot run beside fix {} {}: it changes the box too, and "
             "two fixes changing the box undo each other's moves (and the other one's ignore "
             "the spheres' contacts)",
             other->id, other->style);
}

void FixHardSpherePress::init_list(int, NeighList *ptr)
{
  list = ptr;
}

// the targets: a pure hard-sphere system has no equilibrium volume at P <= 0
// and none beyond close packing; its packing fraction at P (Carnahan-Starling
// in the fluid, the free-volume law of the solid) must fit in a box the
// cutoffs allow
void FixHardSpherePress::check_target(double pressure)
{
  if (smooth) return;
  if (!(pressure > 0.0))
    error->all(FLERR,
               "Fix hardsphere/press target pressure {} <= 0 with pure hard spheres (no "
               "smooth potential): no finite volume has P <= 0, the box would grow without "
               "bound",
               pressure);
  if (dimension != 3) return;
  const double kt = force->boltz * t_target;
  const double sigma = contact_max;
  const double pstar = pressure * sigma * sigma * sigma / (kt * force->nktv2p);
  double eta;
  if (pstar <= P_FREEZE) {
    // Carnahan-Starling, P* = 6 eta Z / pi, increasing in eta: bisection
    double lo = 0.0, hi = 0.6;
    for (int it = 0; it < 100; it++) {
      const double m = 0.5 * (lo + hi);
      const double z = (1 + m + m * m - m * m * m) / ((1 - m) * (1 - m) * (1 - m));
      if (6.0 * m * z / PI < pstar) lo = m;
      else hi = m;
    }
    eta = lo;
  } else {
    // solid (free volume): P* = (6 eta / pi) 3 / (1 - eta / eta_cp)
    const double a = 18.0 / PI;
    eta = pstar / (a + pstar / ETA_CP);
    if (comm->me == 0)
      error->warning(FLERR,
                     "Fix hardsphere/press target P sigma^3/kT = {:.4g} is above the hard-sphere "
                     "fluid's freezing pressure {}: the equilibrium state is the fcc solid "
                     "(packing fraction about {:.3f}), which a fluid start reaches only by "
                     "crystallising, if at all, within a run",
                     pstar, P_FREEZE, eta);
  }
  const double vsphere = PI * sigma * sigma * sigma / 6.0;
  const double vtarget = ngroup * vsphere / eta;
  const double s = cbrt(vtarget / volume());
  double lmin = 1.0e300;
  for (int d = 0; d < 3; d++) lmin = MIN(lmin, s * domain->prd[d]);
  if (lmin < length_min)
    error->all(FLERR,
               "Fix hardsphere/press target pressure {} (P sigma^3/kT = {:.4g}) needs "
               "packing fraction {:.3f} (close packing: {}), a box of shortest length {:.4g} "
               "below the {} the cutoffs allow (twice the largest cutoff or contact "
               "distance): no way to reach it; use more atoms or a lower pressure",
               pressure, pstar, eta, ETA_CP, lmin, length_min);
}

void FixHardSpherePress::check_box(const double *prd_new, double vnew)
{
  for (int d = 0; d < dimension; d++)
    if (prd_new[d] < length_min)
      error->all(FLERR,
                 "Fix hardsphere/press: the box length in {} would be {:.6g} (volume {:.6g}) on "
                 "step {}, below {:.6g}, twice the largest cutoff or contact distance: the "
                 "system is too small for its cutoffs at this pressure; use more atoms or a "
                 "lower pressure",
                 "xyz"[d], prd_new[d], vnew, update->ntimestep, length_min);
}

void FixHardSpherePress::setup(int)
{
  // the first attempt: the next multiple of every. With smooth forces its
  // step rebuilds the lists (the energy's pair list must be built at the
  // current positions); pure hard spheres need no build
  next_reneighbor = smooth ? (update->ntimestep / nevery) * nevery + nevery : -1;
  p_current = target_pressure();
}

double FixHardSpherePress::volume() const
{
  return (dimension == 3) ? domain->xprd * domain->yprd * domain->zprd
                          : domain->xprd * domain->yprd;
}

// Pstart -> Pstop over the run, as fix press/berendsen
double FixHardSpherePress::target_pressure() const
{
  double f = update->ntimestep - update->beginstep;
  if (f != 0.0) f /= update->endstep - update->beginstep;
  return p_start + f * (p_stop - p_start);
}

/* ----------------------------------------------------------------------
   one volume move (doc: derivation). Collective; the random numbers are
   the same on every rank, so every rank takes the same decision
------------------------------------------------------------------------- */

void FixHardSpherePress::end_of_step()
{
  const bigint ntimestep = update->ntimestep;
  p_current = target_pressure();

  // with smooth forces the pair list must be built at the current x: on
  // this step (forced), unless something prevented it
  if (smooth) {
    next_reneighbor = ntimestep + nevery;
    if (neighbor->lastcall != ntimestep) rebuild();
  }

  const double kt = force->boltz * t_target;
  const double v_old = volume();
  // which dimensions (one random number more only if there is a choice)
  int set = move_sets[0];
  if (move_sets.size() > 1)
    set = move_sets[MIN((int) (random->uniform() * move_sets.size()), (int) move_sets.size() - 1)];
  const double dlnv = delta * (random->uniform() - 0.5);
  const double v_new = v_old * exp(dlnv);
  const double s1 = exp(dlnv / nbits(set));
  double s[3] = {1.0, 1.0, 1.0};
  for (int d = 0; d < dimension; d++)
    if (set & (1 << d)) s[d] = s1;
  nattempt += 1.0;
  block_attempt += 1.0;

  double prd_new[3];
  for (int d = 0; d < 3; d++) prd_new[d] = domain->prd[d] * s[d];
  check_box(prd_new, v_new);

  const double u_old = smooth ? pot->energy() : 0.0;
  if (held) save_held_forces();

  // save positions (owned and ghost) and the box, to restore bit for bit
  const int nall = atom->nlocal + atom->nghost;
  xsave.resize(3 * (size_t) nall);
  if (nall) memcpy(xsave.data(), &atom->x[0][0], 3 * sizeof(double) * nall);
  double lo_save[3], hi_save[3];
  for (int d = 0; d < 3; d++) {
    lo_save[d] = domain->boxlo[d];
    hi_save[d] = domain->boxhi[d];
  }

  scale_box_and_atoms(s, set);
  comm->forward_comm();    // ghosts at the new box's images

  bool accept = false;
  if (overlap_anywhere()) {
    noverlap += 1.0;
  } else {
    const double u_new = smooth ? pot->energy() : 0.0;
    du_last = u_new - u_old;
    // beta (dU + P dV) - (N + 1) ln(V'/V); PV / nktv2p is an energy
    const double w = (u_new - u_old + p_current * (v_new - v_old) / force->nktv2p) / kt -
        (ngroup + 1.0) * dlnv;
    const double u = random->uniform();
    accept = (w <= 0.0) || (u < exp(-w));
  }

  if (accept) {
    naccept += 1.0;
    block_accept += 1.0;
    rebuild();
    forces_after_move();
    for (auto *f : hs) f->box_changed();
  } else {
    for (int d = 0; d < 3; d++) {
      domain->boxlo[d] = lo_save[d];
      domain->boxhi[d] = hi_save[d];
    }
    domain->set_global_box();
    domain->set_local_box();
    if (force->kspace) force->kspace->setup();
    if (nall) memcpy(&atom->x[0][0], xsave.data(), 3 * sizeof(double) * nall);
  }

  // delta tuned towards the target acceptance during the first attempts
  // only (afterwards the chain is a fixed Metropolis chain)
  if (nattempt <= (double) adapt_attempts && block_attempt >= ADAPT_BLOCK) {
    const double r = block_accept / block_attempt;
    double f = (r + 0.05) / (TARGET_ACCEPTANCE + 0.05);
    f = MAX(0.7, MIN(1.4, f));
    delta = MIN(delta * f, delta_max);
    block_attempt = block_accept = 0.0;
  }
}

// box and the group's positions scaled by s[d] about the box centre in the
// dimensions d of set
// (wrapped coordinates: with fixed image flags this scales the unwrapped
// ones alike)
void FixHardSpherePress::scale_box_and_atoms(const double *s, int set)
{
  double c[3];
  for (int d = 0; d < dimension; d++) {
    if (!(set & (1 << d))) continue;    // left to the bit
    c[d] = 0.5 * (domain->boxlo[d] + domain->boxhi[d]);
    const double half = 0.5 * s[d] * domain->prd[d];
    domain->boxlo[d] = c[d] - half;
    domain->boxhi[d] = c[d] + half;
  }
  domain->set_global_box();
  domain->set_local_box();
  double **x = atom->x;
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  for (int i = 0; i < nlocal; i++)
    if (mask[i] & groupbit)
      for (int d = 0; d < dimension; d++)
        if (set & (1 << d)) x[i][d] = c[d] + s[d] * (x[i][d] - c[d]);
  if (force->kspace) force->kspace->setup();
}

// any two spheres of one hardsphere fix closer than their contact distance?
int FixHardSpherePress::overlap_anywhere()
{
  double **x = atom->x;
  const int *mask = atom->mask;
  const int inum = list->inum;
  const int *ilist = list->ilist;
  const int *numneigh = list->numneigh;
  int **firstneigh = list->firstneigh;
  int found = 0;
  for (int ii = 0; ii < inum && !found; ii++) {
    const int i = ilist[ii];
    const int *jlist = firstneigh[i];
    for (int jj = 0; jj < numneigh[i] && !found; jj++) {
      const int j = jlist[jj] & NEIGHMASK;
      const double dx = x[i][0] - x[j][0], dy = x[i][1] - x[j][1], dz = x[i][2] - x[j][2];
      const double r2 = dx * dx + dy * dy + dz * dz;
      if (r2 >= contact_max * contact_max) continue;
      for (auto *f : hs) {
        if (!(mask[i] & f->groupbit) || !(mask[j] & f->groupbit)) continue;
        const double sigma = f->sphere_radius(i) + f->sphere_radius(j);
        if (r2 < sigma * sigma) found = 1;
      }
    }
  }
  // bonded partners the lists leave out (special_bonds weight 0)
  if (!found && atom->molecular != Atom::ATOMIC && atom->special) {
    int **nspecial = atom->nspecial;
    tagint **special = atom->special;
    for (int i = 0; i < atom->nlocal && !found; i++)
      for (int m = 0; m < nspecial[i][2] && !found; m++) {
        const int level = (m < nspecial[i][0]) ? 1 : (m < nspecial[i][1]) ? 2 : 3;
        if (neighbor->special_flag[level] != 0) continue;
        int j = atom->map(special[i][m]);
        if (j < 0) continue;
        j = domain->closest_image(i, j);
        const double dx = x[i][0] - x[j][0], dy = x[i][1] - x[j][1], dz = x[i][2] - x[j][2];
        const double r2 = dx * dx + dy * dy + dz * dz;
        for (auto *f : hs) {
          if (!(mask[i] & f->groupbit) || !(mask[j] & f->groupbit)) continue;
          const double sigma = f->sphere_radius(i) + f->sphere_radius(j);
          if (r2 < sigma * sigma) found = 1;
        }
      }
  }
  int any = 0;
  MPI_Allreduce(&found, &any, 1, MPI_INT, MPI_MAX, world);
  return any;
}

// what Verlet does on a reneighboring step, after a move changed the box
void FixHardSpherePress::rebuild()
{
  domain->pbc();
  domain->reset_box();
  comm->setup();
  if (neighbor->style) neighbor->setup_bins();
  comm->exchange();
  comm->borders();
  if (modify->n_pre_neighbor) modify->pre_neighbor();
  neighbor->build(1);
  if (modify->n_post_neighbor) modify->post_neighbor();
}

// the forces at the new positions, as Verlet computes them, with the
// energy and virial tallies this step had asked for (thermo output follows);
// the thermostats' forces of the step's end are added back, not drawn again
void FixHardSpherePress::forces_after_move()
{
  const bigint n = update->ntimestep;
  int eflag = 0, vflag = 0;
  if (update->eflag_global == n) eflag |= ENERGY_GLOBAL;
  if (update->eflag_atom == n) eflag |= ENERGY_ATOM;
  if (update->vflag_global == n) vflag |= force->newton_pair ? VIRIAL_FDOTR : VIRIAL_PAIR;
  if (update->vflag_atom == n) vflag |= VIRIAL_ATOM;
  pot->evaluate_flags(eflag, vflag);
  if (held) {
    double **f = atom->f;
    for (int i = 0; i < atom->nlocal; i++)
      for (int d = 0; d < 3; d++) f[i][d] += fheld[i][d];
  }
}

// f - its conservative part at the current x: the thermostats' forces. The
// conservative part is LAMMPS' own if an integrator copied it before the
// held fixes' post_force on this step, with no list build since (FixHardSphere::
// captured_forces(): the same on every rank); else one evaluation
void FixHardSpherePress::save_held_forces()
{
  const int nlocal = atom->nlocal;
  double **f = atom->f;
  for (auto *h : hs)
    if (double **fc = h->captured_forces()) {
      for (int i = 0; i < nlocal; i++)
        for (int d = 0; d < 3; d++) fheld[i][d] = f[i][d] - fc[i][d];
      return;
    }
  fcons.resize(3 * (size_t) MAX(nlocal, 1));
  std::vector<double *> rows(MAX(nlocal, 1));
  for (int i = 0; i < nlocal; i++) rows[i] = &fcons[3 * (size_t) i];
  pot->conservative_forces(rows.data());
  for (int i = 0; i < nlocal; i++)
    for (int d = 0; d < 3; d++) fheld[i][d] = f[i][d] - rows[i][d];
}

/* ----------------------------------------------------------------------
   per-atom held forces: migrate with their atoms
------------------------------------------------------------------------- */

void FixHardSpherePress::grow_arrays(int nmax)
{
  memory->grow(fheld, nmax, 3, "hardsphere/press:fheld");
}

void FixHardSpherePress::copy_arrays(int i, int j, int)
{
  for (int d = 0; d < 3; d++) fheld[j][d] = fheld[i][d];
}

int FixHardSpherePress::pack_exchange(int i, double *buf)
{
  for (int d = 0; d < 3; d++) buf[d] = fheld[i][d];
  return 3;
}

int FixHardSpherePress::unpack_exchange(int nlocal, double *buf)
{
  for (int d = 0; d < 3; d++) fheld[nlocal][d] = buf[d];
  return 3;
}

double FixHardSpherePress::memory_usage()
{
  return (double) atom->nmax * 3 * sizeof(double) + xsave.capacity() * sizeof(double);
}

/* ---------------------------------------------------------------------- */

// volume, attempts, accepted, rejected by overlap, target pressure,
// acceptance ratio, delta, dU of the last move that passed the overlap test
double FixHardSpherePress::compute_vector(int n)
{
  switch (n) {
    case 0:
      return volume();
    case 1:
      return nattempt;
    case 2:
      return naccept;
    case 3:
      return noverlap;
    case 4:
      return p_current;
    case 5:
      return nattempt > 0.0 ? naccept / nattempt : 0.0;
    case 6:
      return delta;
    case 7:
      return du_last;
  }
  return 0.0;
}

void FixHardSpherePress::write_restart(FILE *fp)
{
  if (comm->me == 0) {
    double list_[NRESTART] = {nattempt,      naccept,      noverlap, delta,
                              block_attempt, block_accept, (double) random->state()};
    int size = NRESTART * sizeof(double);
    fwrite(&size, sizeof(int), 1, fp);
    fwrite(list_, sizeof(double), NRESTART, fp);
  }
}

void FixHardSpherePress::restart(char *buf)
{
  const double *list_ = (const double *) buf;
  nattempt = list_[0];
  naccept = list_[1];
  noverlap = list_[2];
  delta = list_[3];
  block_attempt = list_[4];
  block_accept = list_[5];
  random->reset((int) list_[6]);
}
