/* ----------------------------------------------------------------------
   HARDSPHERE package: the system layer shared by the fix family, the step
   engines and the methods. See hs_system.h.
------------------------------------------------------------------------- */

#include "hs_system.h"

#include "hs_compat.h"
#include "hs_contact.h"
#include "hs_mix.h"
#include "hs_near.h"
#include "hs_potential.h"
#include "hs_screen.h"
#include "hs_stamp.h"

#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix.h"
#include "force.h"
#include "group.h"
#include "memory.h"
#include "modify.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "update.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <mpi.h>

using namespace LAMMPS_NS;
using HardSphere::Contact;

/* ---------------------------------------------------------------------- */

HSSystem::HSSystem(LAMMPS *lmp, Fix *host_, const std::string &name) :
    Pointers(lmp), host(host_), groupbit(host_->groupbit), style_name(name)
{
  pot = new HSPotential(lmp, groupbit, "fix " + style_name);
}

HSSystem::~HSSystem()
{
  delete pot;
  memory->destroy(xref);
  memory->destroy(gap);
  memory->destroy(active);
  memory->destroy(acc);
  memory->destroy(ftot);
  memory->destroy(fcons);
  memory->destroy(fheld);
  memory->destroy(fcap);
}

const char *HSSystem::fix_id() const
{
  return host->id;
}

// "atoms I and J" or "atom I and wall F", for messages
std::string HSSystem::contact_name(const Impulse &imp) const
{
  if (imp.type == WALL_EVENT) {
    std::string name;
    wall_name(walls[imp.wall], name);
    return fmt::format("atom {} and wall {}", imp.itag, name);
  }
  return fmt::format("atoms {} and {}", imp.itag, imp.jtag);
}

double HSSystem::approach_accel(const Impulse &imp, const double *ai, const double *aj) const
{
  if (imp.type == WALL_EVENT) {
    const Wall &W = walls[imp.wall];
    return (W.side < 0) ? -ai[W.dim] : ai[W.dim];
  }
  const double *dq = imp.dq;
  const double r = sqrt(dq[0] * dq[0] + dq[1] * dq[1] + dq[2] * dq[2]);
  return -((ai[0] - aj[0]) * dq[0] + (ai[1] - aj[1]) * dq[1] + (ai[2] - aj[2]) * dq[2]) / r;
}

// impulse virial, averaged over the step: r (x) J / (dt ftm2v); tallied by
// the one rank that built the impulse
void HSSystem::add_impulse_virial(const Impulse &imp)
{
  const double s = 1.0 / (dtv * force->ftm2v);
  host->virial[0] += s * imp.dq[0] * imp.J[0];
  host->virial[1] += s * imp.dq[1] * imp.J[1];
  host->virial[2] += s * imp.dq[2] * imp.J[2];
  host->virial[3] += s * imp.dq[0] * imp.J[1];
  host->virial[4] += s * imp.dq[0] * imp.J[2];
  host->virial[5] += s * imp.dq[1] * imp.J[2];
}

void HSSystem::pair_overlap_error(int i, int j, double r, double sigma)
{
  error->one(FLERR,
             "Fix {}: atoms {} and {} overlap by {} (distance {} < contact distance {}) "
             "on step {}: a collision was missed",
             style_name, atom->tag[i], atom->tag[j], sigma - r, r, sigma, update->ntimestep);
}

// every_rank: the caller's step is collective (global engine, psa), so
// every rank stops here alike; else (the local engine's cluster, run by one
// rank) error->one, which ends every rank without waiting for them
void HSSystem::check_runaway(bigint ncollisions, bool every_rank)
{
  if (ncollisions <= max_substeps) return;
  const std::string msg = fmt::format(
               "Fix {}: more than {} collisions in step {}: a sequence of contacts that does "
               "not end (e.g. a sphere pressed against a wall or a neighbour with almost no "
               "normal velocity) or a timestep far too large for this system",
               style_name, max_substeps, update->ntimestep);
  if (every_rank) error->all(FLERR, msg);
  error->one(FLERR, msg);
}

void HSSystem::resting_contact_error(const Impulse &imp, bool every_rank)
{
  const std::string msg =
      fmt::format("Fix {}: {} stay in contact with no normal velocity on step {} "
                  "(a resting contact), which impulsive hard spheres cannot resolve",
                  style_name, contact_name(imp), update->ntimestep);
  if (every_rank) error->all(FLERR, msg);
  error->one(FLERR, msg);
}

// a touching contact that a method found separating on its own flow:
// predict() passes over it while it touches, until a sub-step moves on
void HSSystem::release_contact(const Impulse &imp)
{
  released.type = imp.type;
  released.itag = imp.itag;
  released.jtag = imp.jtag;
  released.wall = imp.wall;
}

bool HSSystem::is_released(int type, tagint itag, tagint jtag, int wall) const
{
  if (released.type != type) return false;
  if (type == WALL_EVENT) return released.itag == itag && released.wall == wall;
  return (released.itag == itag && released.jtag == jtag) ||
         (released.itag == jtag && released.jtag == itag);
}

double HSSystem::force_evals() const
{
  return nforce_evals + pot->nevals();
}

void HSSystem::grow_peratom()
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

bool HSSystem::shares_atoms(int other_groupbit) const
{
  const int nlocal = atom->nlocal;
  const int *mask = atom->mask;
  int shared = 0;
  for (int i = 0; i < nlocal && !shared; i++)
    if ((mask[i] & groupbit) && (mask[i] & other_groupbit)) shared = 1;
  int any;
  MPI_Allreduce(&shared, &any, 1, MPI_INT, MPI_MAX, world);
  return any != 0;
}

bool HSSystem::group_apart(int igroup) const
{
  return !group->dynamic[igroup] && !shares_atoms(group->bitmask[igroup]);
}

void HSSystem::update_walls()
{
  for (Wall &w : walls)
    if (w.edge) w.coord = (w.side < 0) ? domain->boxlo[w.dim] : domain->boxhi[w.dim];
}

// distance of a sphere's surface from the wall plane, >= 0 where allowed
double HSSystem::wall_gap(const Wall &w, const double *x, double r) const
{
  return (w.side < 0) ? (x[w.dim] - w.coord) - r : (w.coord - x[w.dim]) - r;
}

void HSSystem::wall_name(const Wall &w, std::string &name) const
{
  name = std::string(1, "xyz"[w.dim]) + (w.side < 0 ? "lo" : "hi");
}

int HSSystem::check_atoms_unchanged()
{
  if (nlocal_ref < 0 || (atom->nlocal == nlocal_ref && atom->nghost == nghost_ref)) return 0;
  defer_error(fmt::format(
      "Fix {}: {} owned and {} ghost atoms on rank {} at step {}, {} and {} when the neighbor "
      "lists were last built: atoms were created or deleted (delete_atoms, create_atoms, "
      "read_data add, ...) or given to other ranks with their ghost copies built again "
      "(displace_atoms, change_box, balance, write_restart, write_data, ...) and the run "
      "skipped its set-up (run ... pre no): use pre yes after such a change",
      style_name, atom->nlocal, atom->nghost, comm->me, update->ntimestep, nlocal_ref,
      nghost_ref));
  return FOUND_ERROR;
}

void HSSystem::defer_error(const std::string &msg)
{
  if (comm->nprocs == 1) error->one(FLERR, msg);
  if (deferred_msg.empty()) deferred_msg = msg;
}

void HSSystem::raise_deferred()
{
  if (comm->nprocs == 1) return;    // (defer_error() stopped at once)
  std::string msg;
  msg.swap(deferred_msg);
  error_from_lowest(msg);
}

void HSSystem::error_from_lowest(const std::string &msg)
{
  const int nprocs = comm->nprocs;
  int mine = msg.empty() ? nprocs : comm->me, from = nprocs;
  MPI_Allreduce(&mine, &from, 1, MPI_INT, MPI_MIN, world);
  if (from == nprocs) return;
  std::string all = msg;
  int len = (int) all.size();
  MPI_Bcast(&len, 1, MPI_INT, from, world);
  all.resize(len);
  MPI_Bcast(&all[0], len, MPI_CHAR, from, world);
  error->all(FLERR, all);
}

int HSSystem::reduce_step_flags(int flags)
{
  int all = flags;
  MPI_Allreduce(&flags, &all, 1, MPI_INT, MPI_BOR, world);
  if (all & FOUND_ERROR) {
    raise_deferred();
    error->all(FLERR, "Fix {}: internal error: a rank flagged an error on step {} and kept no "
               "message", style_name, update->ntimestep);
  }
  return all;
}

int HSSystem::screen_step()
{
  // (the closing kick's flags, and any error it deferred, hold only for
  // the step it screened: a new run, even with pre no, screens afresh)
  const bool ahead = screened_step == update->ntimestep && update->ntimestep > update->firststep + 1;
  if (!ahead) drop_deferred();
  const int changed = check_atoms_unchanged();
  grow_peratom();
  update_walls();
  int flags = changed;
  if (!changed && ahead) flags = screened_flags;
  if (!changed && !ahead) {
    defer_skin = true;
    flags = screen(dtv);
    defer_skin = false;
  }
  return reduce_step_flags(flags);
}

using HardSphere::mix64;

static inline uint64_t bits_of(double v)
{
  uint64_t b;
  memcpy(&b, &v, sizeof(b));
  return b;
}

uint64_t HSSystem::state_fingerprint() const
{
  const int nlocal = atom->nlocal;
  const tagint *tag = atom->tag;
  double **x = atom->x;
  const double *radius = atom->radius_flag ? atom->radius : nullptr;
  const double *rmass = atom->rmass;
  uint64_t mine = 0;
  for (int i = 0; i < nlocal; i++) {
    uint64_t h = mix64((uint64_t) tag[i]);
    for (int d = 0; d < 3; d++) h = mix64(h ^ bits_of(x[i][d]));
    if (radius) h = mix64(h ^ bits_of(radius[i]));
    if (rmass) h = mix64(h ^ bits_of(rmass[i]));
    mine += h;    // (modulo 2^64: the same for any order and any ranks)
  }
  uint64_t all = 0;
  MPI_Allreduce(&mine, &all, 1, MPI_UINT64_T, MPI_SUM, world);
  uint64_t g = 0x9e3779b97f4a7c15ULL;
  for (int d = 0; d < 3; d++)
    g = mix64(g ^ bits_of(domain->boxlo[d]) ^ mix64(bits_of(domain->boxhi[d])));
  for (double t : {domain->xy, domain->xz, domain->yz}) g = mix64(g ^ bits_of(t));
  if (atom->mass)
    for (int t = 1; t <= atom->ntypes; t++) g = mix64(g ^ bits_of(atom->mass[t]));
  return all ^ g;
}

void HSSystem::reset_reference(int at_setup)
{
  grow_peratom();
  update_walls();
  nlocal_ref = atom->nlocal;
  nghost_ref = atom->nghost;
  if (track_atoms) {
    unsigned long long mine[2] = {(unsigned long long) atom->nlocal, 0ULL}, all[2];
    for (int i = 0; i < atom->nlocal; i++) mine[1] += (unsigned long long) atom->tag[i];
    MPI_Allreduce(mine, all, 2, MPI_UNSIGNED_LONG_LONG, MPI_SUM, world);
    atoms_count = (bigint) all[0];
    atoms_idsum = all[1];
  }

  double **x = atom->x;
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  const int nall = nlocal + atom->nghost;
  const tagint *tag = atom->tag;
  // at set-up the likely cause is the input, not a missed collision
  const char *when = at_setup
      ? "at set-up (the initial configuration, or a change_box, displace_atoms, set, "
        "create_atoms, read_data or minimize since the last run, or atoms outside this fix's "
        "group in an earlier run, placed them closer than their contact distance)"
      : "after a step (a collision was missed)";
  const double cut2 = list_cutoff * list_cutoff;

  // ghosts too: the local engine's interaction rows are taken at the list
  // build's positions, as LAMMPS' own (HSLocalForces::set_reference)
  for (int i = 0; i < nall; i++) {
    xref[i][0] = x[i][0];
    xref[i][1] = x[i][1];
    xref[i][2] = x[i][2];
  }
  for (int i = 0; i < nall; i++) gap[i] = skin;
  ++cand_version;
  const size_t ncand_before = cand.size();
  cand.clear();
  cand.reserve(ncand_before + ncand_before / 4);
  cand_r.clear();
  cand_r.reserve(cand.capacity() / 2);

  auto candidate = [&](int i, int j) {
    if (!(mask[j] & groupbit)) return;
    const double dx = x[i][0] - x[j][0], dy = x[i][1] - x[j][1], dz = x[i][2] - x[j][2];
    const double r2 = dx * dx + dy * dy + dz * dz;
    if (r2 > cut2) return;    // cannot touch before the next build
    const double sigma = radius_of(i) + radius_of(j);
    const double r = sqrt(r2);
    // (every rank builds its lists here: deferred, raised at the end)
    if (r < sigma * (1.0 - TOUCH_TOL))
      defer_error(fmt::format("Fix {}: atoms {} and {} overlap by {} (distance {} < contact "
                              "distance {}) on step {} {}",
                              style_name, tag[i], tag[j], sigma - r, r, sigma,
                              update->ntimestep, when));
    const double g = 0.5 * (r - sigma);
    gap[i] = MIN(gap[i], g);
    gap[j] = MIN(gap[j], g);
    cand.push_back(i);
    cand.push_back(j);
    cand_r.push_back(r);
  };

  // the list may be the pair style's, with a longer cutoff: the distance
  // test comes first, as most of its pairs are out of reach

  const int inum = list->inum;
  // x's rows are one block (Memory::create): row j at xa + 3 j
  const double *xa = nall ? x[0] : nullptr;
  const int *ilist = list->ilist;
  const int *numneigh = list->numneigh;
  int **firstneigh = list->firstneigh;
  for (int ii = 0; ii < inum; ii++) {
    const int i = ilist[ii];
    if (!(mask[i] & groupbit)) continue;
    const double xi = x[i][0], yi = x[i][1], zi = x[i][2];
    const int *jlist = firstneigh[i];
    const int jnum = numneigh[i];
    // the few pairs within reach, compacted branch-free (a branch taken at
    // random for ~10 % of the pairs costs more than the arithmetic), four
    // at a time where the processor has AVX2 (hs_near.h: the same list)
    if ((int) near.size() < jnum + 4) near.resize(jnum + 4);
    const int nnear = HardSphere::near(jlist, jnum, NEIGHMASK, xa, xi, yi, zi, cut2, near.data());
    for (int k = 0; k < nnear; k++) candidate(i, near[k]);
  }

  // bonded partners the neighbor lists leave out (special_bonds weight 0),
  // each pair once: from its lower atom ID. A partner that is not even a
  // ghost is farther than the ghost cutoff >= list cutoff: it cannot touch.

  if (atom->molecular != Atom::ATOMIC && atom->special) {
    int **nspecial = atom->nspecial;
    tagint **special = atom->special;
    // map()'s copy is the closest image when it lies within half the
    // shortest periodic length of i (another image is a lattice vector
    // away, and every lattice vector, tilted or not, is at least the
    // shortest periodic length long: h is upper triangular), so
    // Domain::closest_image()'s walk over every copy (random reads of x,
    // ~20 % of this filter on a bead-spring melt) is needed only otherwise
    double half = BIG;
    for (int d = 0; d < 3; d++)
      if (domain->periodicity[d]) half = MIN(half, 0.5 * domain->prd[d]);
    const double half2 = half * half;
    // only the levels (1-2, 1-3, 1-4: nspecial's cumulative ranges) the
    // lists leave out are read (a melt's special_bonds lj 0 1 1: the 1-2
    // range alone, not every 1-3 and 1-4 entry of every atom)
    bool out[3];
    for (int lev = 0; lev < 3; lev++) out[lev] = neighbor->special_flag[lev + 1] == 0;
    for (int i = 0; i < nlocal; i++) {
      if (!(mask[i] & groupbit)) continue;
      for (int lev = 0; lev < 3; lev++) {
        if (!out[lev]) continue;
        const int m1 = nspecial[i][lev];
        for (int m = lev ? nspecial[i][lev - 1] : 0; m < m1; m++) {
          if (special[i][m] < tag[i]) continue;
          int j = atom->map(special[i][m]);
          if (j < 0) continue;
          const double dx = x[i][0] - x[j][0], dy = x[i][1] - x[j][1], dz = x[i][2] - x[j][2];
          if (!(dx * dx + dy * dy + dz * dz < half2)) j = domain->closest_image(i, j);
          candidate(i, j);
        }
      }
    }
  }

  // a ghost's gaps belong to its owner
  HSCompat::reverse_comm_fix(comm, host);

  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    for (const Wall &w : walls) {
      const double g = wall_gap(w, x[i], radius_of(i));
      if (g < -TOUCH_TOL * 2.0 * radius_of(i)) {
        std::string name;
        wall_name(w, name);
        defer_error(fmt::format("Fix {}: atom {} is {} through wall {} at {} on step {} {}",
                                style_name, tag[i], -g, name, w.coord, update->ntimestep,
                                when));
      }
      gap[i] = MIN(gap[i], g);
    }
  }
  raise_deferred();
}

int HSSystem::pack_reverse_comm(int n, int first, double *buf)
{
  if (cols_) {    // (always sparse: reverse_columns)
    if (n == 0) return 0;    // (nothing is sent or received)
    int m = 1, cnt = 0;
    auto pack = [&](int k) {
      const double *row = cols_[first + k];
      bool nz = false;
      for (int c = 0; c < ncols_ && !nz; c++) nz = row[c] != 0.0;
      if (!nz) return;
      buf[m++] = k;
      for (int c = 0; c < ncols_; c++) buf[m++] = row[c];
      cnt++;
    };
    if (revlisted_) {
      // only the listed ghosts of this swap, in index order as the scan
      // takes them: O(listed), not O(ghosts) per swap (the ghost shell of
      // the local engine on several ranks is ~40 % of a rank's copies)
      packsel_.clear();
      for (int j : marked_)
        if (j >= first && j < first + n) packsel_.push_back(j - first);
      std::sort(packsel_.begin(), packsel_.end());
      for (int k : packsel_) pack(k);
    } else
      for (int k = 0; k < n; k++) pack(k);
    buf[0] = cnt;
    return m;
  }
  for (int k = 0; k < n; k++) buf[k] = gap[first + k];
  return n;
}

void HSSystem::unpack_reverse_comm(int n, int *list_, double *buf)
{
  if (cols_) {    // (always sparse: reverse_columns)
    if (n == 0) return;
    const int cnt = (int) buf[0];
    int m = 1;
    for (int k = 0; k < cnt; k++) {
      const int j = list_[(int) buf[m++]];
      bool nz = false;
      for (int c = 0; c < ncols_; c++) {
        nz = nz || buf[m] != 0.0;
        cols_[j][c] += buf[m++];
      }
      if (nz && changed_) changed_->push_back(j);
      // a ghost that received (corners, several hops) sends on in an
      // earlier swap: it may be nonzero now
      if (nz && revlisted_ && j >= atom->nlocal && !sendmark_[j]) {
        sendmark_[j] = 1;
        marked_.push_back(j);
      }
    }
    return;
  }
  for (int k = 0; k < n; k++) gap[list_[k]] = MIN(gap[list_[k]], buf[k]);
}

void HSSystem::forward_columns(double **a, int ncol, std::vector<int> *changed, int ncmp,
                               const std::vector<int> *send)
{
  if (ncol < 1 || ncol > COMM_COLUMNS || ncmp > ncol)
    error->one(FLERR, "Fix {}: internal error: {} columns to forward", style_name, ncol);
  cols_ = a;
  ncols_ = ncol;
  changed_ = changed;
  ncmp_ = changed ? ncmp : 0;
  sparse_ = send != nullptr;
  if (sparse_) {
    if ((int) sendmark_.size() < atom->nmax) sendmark_.resize(atom->nmax, 0);
    for (int i : *send) {
      if (!sendmark_[i]) marked_.push_back(i);
      sendmark_[i] = 1;
    }
  }
  HSCompat::forward_comm_fix(comm, host);
  for (int i : marked_) sendmark_[i] = 0;
  marked_.clear();
  cols_ = nullptr;
  changed_ = nullptr;
  sparse_ = false;
}

void HSSystem::reverse_columns(double **a, int ncol, std::vector<int> *changed)
{
  if (ncol < 1 || ncol > COMM_COLUMNS)
    error->one(FLERR, "Fix {}: internal error: {} columns to reverse", style_name, ncol);
  cols_ = a;
  ncols_ = ncol;
  changed_ = changed;
  revlisted_ = changed != nullptr;
  if (revlisted_) {
    const int nlocal = atom->nlocal;
    if ((int) sendmark_.size() < atom->nmax) sendmark_.resize(atom->nmax, 0);
    for (int i : *changed)
      if (i >= nlocal && !sendmark_[i]) {
        sendmark_[i] = 1;
        marked_.push_back(i);
      }
  }
  HSCompat::reverse_comm_fix(comm, host);
  for (int i : marked_) sendmark_[i] = 0;
  marked_.clear();
  revlisted_ = false;
  cols_ = nullptr;
  changed_ = nullptr;
}

template <bool LIST> inline int HSSystem::screen_atom(int i, double t2, double h4, double im)
{
  double **x = atom->x;
  double **v = atom->v;
  double **f = atom->f;
  const double dx = x[i][0] - xref[i][0], dy = x[i][1] - xref[i][1], dz = x[i][2] - xref[i][2];
  const double d2 = dx * dx + dy * dy + dz * dz;
  const double v2 = t2 * (v[i][0] * v[i][0] + v[i][1] * v[i][1] + v[i][2] * v[i][2]);
  const double a2 = h4 * im * im * (f[i][0] * f[i][0] + f[i][1] * f[i][1] + f[i][2] * f[i][2]);
  return screen_terms<LIST>(i, d2, v2, a2);
}

// screen_atom() from its three squared terms (hs_screen.h's kernel has them)
template <bool LIST> inline int HSSystem::screen_terms(int i, double d2, double v2, double a2)
{
  // most spheres are cleared without a sqrt (hs_screen.h)
  const int fast =
      HardSphere::screen_fast_test(d2, v2, a2, gap[i], 0.5 * skin, LIST, near_margin);
  if (fast != HardSphere::OPEN) return fast == HardSphere::CLEARED ? 0 : NEAR;
  const int listed = LIST ? NEAR : 0;
  const double w = sqrt(d2) + sqrt(v2) + sqrt(a2);
  int flags = ((w > 0.5 * skin) ? FAR : 0) | listed;
  if (w <= gap[i]) return flags;
  if (w > skin) {
    const std::string msg = fmt::format(
        "Fix {}: atom {} may be {} away from where the neighbor list was built, more than the "
        "skin {} (the fix rebuilds lists at skin/2): use a smaller timestep or a larger "
        "neighbor skin",
        style_name, atom->tag[i], w, skin);
    if (!defer_skin) error->one(FLERR, msg);
    defer_error(msg);
    flags |= FOUND_ERROR;
  }
  active[i] = 1.0;
  return flags | ACTIVE;
}

// hs_screen.h's kernel over the owned atoms, if it applies (per-type
// masses, rows contiguous as Memory::create() makes them)
bool HSSystem::fast_screen(HardSphere::KickScreen &k, double t2, double h4, bool list, bool kick)
{
  const int nlocal = atom->nlocal;
  double **x = atom->x, **v = atom->v, **f = atom->f;
  auto contiguous = [nlocal](double **a) {
    return a[nlocal - 1] == a[0] + 3 * (size_t) (nlocal - 1);
  };
  if (atom->rmass || nlocal == 0 || !contiguous(x) || !contiguous(v) || !contiguous(f) ||
      !contiguous(xref))
    return false;
  k.v = v[0];
  k.active = active;
  k.f = f[0];
  k.x = x[0];
  k.xref = xref[0];
  k.gap = gap;
  k.type = atom->type;
  k.mask = atom->mask;
  k.mass = atom->mass;
  k.im = ftm2v_mass.data();
  k.groupbit = groupbit;
  k.dtf = dtf_last;
  k.t2 = t2;
  k.h4 = h4;
  k.half_skin = 0.5 * skin;
  k.list = list;
  k.margin = near_margin;
  k.kick = kick;
  return true;
}

int HSSystem::screen(double tleft)
{
  const double *rmass = atom->rmass;
  const int *type = atom->type;
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  const double ftm2v = force->ftm2v;
  const double t2 = tleft * tleft;
  const double h4 = 0.25 * t2 * t2;
  int flags = 0;
  // four spheres at a time where it applies (hs_screen.h; the same decisions)
  HardSphere::KickScreen k;
  if (fast_screen(k, t2, h4, false, false)) {
    HardSphere::kick_clear_chunked(k, nlocal, unscreened, [&](const HardSphere::Unscreened &u) {
      flags |= screen_terms(u.i, u.d2, u.v2, u.a2);
    });
    return flags;
  }

  for (int i = 0; i < nlocal; i++) {
    active[i] = 0.0;
    if (!(mask[i] & groupbit)) continue;
    flags |= screen_atom(i, t2, h4, rmass ? ftm2v / rmass[i] : ftm2v_mass[type[i]]);
  }
  return flags;
}

void HSSystem::comm_vel_acc()
{
  set_acc();
  forward_vel_acc();
}

void HSSystem::set_acc()
{
  const int nlocal = atom->nlocal;
  const double ftm2v = force->ftm2v;
  for (int i = 0; i < nlocal; i++) set_acc_row(i, ftm2v);
}

void HSSystem::forward_vel_acc(double **extra, int nextra)
{
  if (nextra < 0 || nextra > COMM_EXTRA || (nextra && !extra))
    error->one(FLERR, "Fix {}: internal error: {} extra columns to forward", style_name, nextra);
  extra_ = extra;
  nextra_ = nextra;
  HSCompat::forward_comm_fix(comm, host);
  extra_ = nullptr;
  nextra_ = 0;
}

int HSSystem::pack_forward_comm(int n, int *list_, double *buf)
{
  double **v = atom->v;
  int m = 0;
  if (cols_ && sparse_) {
    if (n == 0) return 0;
    int cnt = 0;
    m = 1;
    // (a swap's list holds owned atoms, or ghosts received in an earlier
    // swap: their rows are current, sent if their owner's was)
    for (int k = 0; k < n; k++) {
      const int j = list_[k];
      if (!sendmark_[j]) continue;
      buf[m++] = k;
      for (int c = 0; c < ncols_; c++) buf[m++] = cols_[j][c];
      cnt++;
    }
    buf[0] = cnt;
    return m;
  }
  if (cols_) {
    if (ncols_ == 4) {    // (Phi_H2's velocities: a fixed width the compiler unrolls)
      for (int k = 0; k < n; k++, m += 4) {
        const double *row = cols_[list_[k]];
        buf[m] = row[0];
        buf[m + 1] = row[1];
        buf[m + 2] = row[2];
        buf[m + 3] = row[3];
      }
      return m;
    }
    for (int k = 0; k < n; k++)
      for (int c = 0; c < ncols_; c++) buf[m++] = cols_[list_[k]][c];
    return m;
  }
  for (int k = 0; k < n; k++) {
    const int j = list_[k];
    buf[m++] = v[j][0];
    buf[m++] = v[j][1];
    buf[m++] = v[j][2];
    buf[m++] = acc[j][0];
    buf[m++] = acc[j][1];
    buf[m++] = acc[j][2];
    buf[m++] = active[j];
    if (nextra_ == 2) {    // (the local engine's first guess)
      buf[m++] = extra_[j][0];
      buf[m++] = extra_[j][1];
    } else
      for (int c = 0; c < nextra_; c++) buf[m++] = extra_[j][c];
  }
  return m;
}

void HSSystem::unpack_forward_comm(int n, int first, double *buf)
{
  double **v = atom->v;
  int m = 0;
  const int last = first + n;
  if (cols_ && sparse_) {
    if (n == 0) return;
    const int cnt = (int) buf[0];
    m = 1;
    for (int k = 0; k < cnt; k++) {
      const int i = first + (int) buf[m++];
      double *row = cols_[i];
      bool ch = false;
      for (int c = 0; c < ncmp_; c++) ch = ch || row[c] != buf[m + c];
      if (ch && changed_) changed_->push_back(i);
      for (int c = 0; c < ncols_; c++) row[c] = buf[m++];
      // a ghost received here is sent on by later swaps (corners, or
      // ghost cutoffs beyond the neighbour sub-domain)
      if (!sendmark_[i]) marked_.push_back(i);
      sendmark_[i] = 1;
    }
    return;
  }
  if (cols_) {
    if (ncols_ == 4 && (!changed_ || ncmp_ == 3)) {    // (Phi_H2's velocities, unrolled)
      for (int i = first; i < last; i++, m += 4) {
        double *row = cols_[i];
        const double *b = buf + m;
        if (changed_ && ((row[0] != b[0]) | (row[1] != b[1]) | (row[2] != b[2])))
          changed_->push_back(i);
        row[0] = b[0];
        row[1] = b[1];
        row[2] = b[2];
        row[3] = b[3];
      }
      return;
    }
    for (int i = first; i < last; i++) {
      double *row = cols_[i];
      bool ch = false;
      for (int c = 0; c < ncmp_; c++) ch = ch || row[c] != buf[m + c];
      if (ch) changed_->push_back(i);
      for (int c = 0; c < ncols_; c++) row[c] = buf[m++];
    }
    return;
  }
  for (int i = first; i < last; i++) {
    v[i][0] = buf[m++];
    v[i][1] = buf[m++];
    v[i][2] = buf[m++];
    acc[i][0] = buf[m++];
    acc[i][1] = buf[m++];
    acc[i][2] = buf[m++];
    active[i] = buf[m++];
    if (nextra_ == 2) {
      extra_[i][0] = buf[m++];
      extra_[i][1] = buf[m++];
    } else
      for (int c = 0; c < nextra_; c++) extra_[i][c] = buf[m++];
  }
}

double HSSystem::predict(double tleft, Event &ev)
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

void HSSystem::nve_initial()
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

int HSSystem::moved_half_skin()
{
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  for (int i = 0; i < nlocal; i++)
    if ((mask[i] & groupbit) && moved_half(i)) return 1;
  return 0;
}

void HSSystem::request_rebuild(int moved)
{
  if (moved < 0) moved = moved_half_skin();
  int any;
  MPI_Allreduce(&moved, &any, 1, MPI_INT, MPI_MAX, world);
  if (any) host->next_reneighbor = update->ntimestep;
}

void HSSystem::kick(double tau)
{
  kick_dtf((tau == dtv) ? dtf : 0.5 * tau * force->ftm2v);
}

// v += dtfk f / m, in the form of fix nve's kicks (dtf / m first), so a
// kick with dtfk = dtf is bit for bit fix nve's; force: atom->f unless given
// (the held thermostat forces)
void HSSystem::kick_dtf(double dtfk, double **force)
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

void HSSystem::kick_drift(double tau)
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

void HSSystem::recompute_forces()
{
  if (forces_present) pot->evaluate(0);    // forwards ghost positions first
  else comm->forward_comm();               // ghost positions, for the prediction
}

void HSSystem::apply_impulse(const Impulse &imp)
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

// at the current x with atom->f = f_c + f_h (LAMMPS' forces): ftot = that,
// fcons = f_c (left in atom->f), fheld = f_h. f_c is LAMMPS' own force
// before the held fixes' post_force if the fix copied it (captured(): the
// step's start, at_start, or end), else one conservative evaluation
void HSSystem::split_held_forces(bool at_start)
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
  if (double **fc = captured(at_start)) {
    for (int i = 0; i < nlocal; i++)
      for (int k = 0; k < 3; k++) {
        fcons[i][k] = f[i][k] = fc[i][k];
        fheld[i][k] = ftot[i][k] - fc[i][k];
      }
    return;
  }
  pot->evaluate(0);
  for (int i = 0; i < nlocal; i++)
    for (int k = 0; k < 3; k++) {
      fcons[i][k] = f[i][k];
      fheld[i][k] = ftot[i][k] - f[i][k];
    }
}

// f of the owned atoms as it is now (called between the force fixes'
// post_force and the held fixes'): one copy, no evaluation
void HSSystem::capture_forces()
{
  const int nlocal = atom->nlocal;
  if (atom->nmax > nmax_cap) {
    nmax_cap = atom->nmax;
    memory->destroy(fcap);
    memory->create(fcap, nmax_cap, 3, "hardsphere:fcap");
  }
  if (nlocal > 0) memcpy(&fcap[0][0], &atom->f[0][0], 3 * sizeof(double) * (size_t) nlocal);
  cap_step = update->ntimestep;
  cap_ncalls = neighbor->ncalls;
  cap_nlocal = nlocal;
}

void HSSystem::capture_kept(bigint ncalls_before)
{
  if (cap_ncalls == ncalls_before) cap_ncalls = neighbor->ncalls;
}

// the start's forces are the last step's end (captured before this step's
// integrate: no list build since, which would sort or move atoms), the
// end's this step's post_force (after any build of the step). The same
// answer on every rank (callers choose collective evaluations by it)
double **HSSystem::captured(bool at_start) const
{
  if (!cap_on) return nullptr;
  const bigint want = update->ntimestep - (at_start ? 1 : 0);
  if (cap_step != want || cap_ncalls != neighbor->ncalls) return nullptr;
  if (cap_nlocal != atom->nlocal)
    error->one(FLERR,
               "Fix {}: the atoms changed between the force evaluation of step {} and step "
               "{} without a neighbor list build ({} atoms on this rank, {} then); after "
               "adding or deleting atoms, run with pre yes",
               style_name, cap_step, update->ntimestep, atom->nlocal, cap_nlocal);
  return fcap;
}

/* ----------------------------------------------------------------------
   the closing half kick of a step without sub-steps (fix nve's, with the
   step's last dtf). With no end_of_step fix, nothing can change velocities
   before the next step: screen for it now, in the same pass as the kick,
   while v and f are in cache
------------------------------------------------------------------------- */

void HSSystem::closing_kick()
{
  if (modify->n_end_of_step) {
    kick_dtf(dtf_last);
    return;
  }
  const double t2 = dtv * dtv, h4 = 0.25 * t2 * t2;
  // with the local engine, the atoms its quick first guess must look at
  // (near_atoms: it then makes no pass of its own over every atom)
  const bool listing = near_margin >= 0.0;
  near_atoms.clear();
  // (its flags are reduced at the next step's start: reduce_step_flags())
  defer_skin = true;
  const int flags = listing ? kick_and_screen<true>(t2, h4) : kick_and_screen<false>(t2, h4);
  defer_skin = false;
  screened_flags = flags;
  screened_step = update->ntimestep + 1;
  near_used_margin = near_margin;
  near_step = listing ? update->ntimestep + 1 : -1;
}

// the kick is kick_dtf()'s (fix nve's) arithmetic
template <bool LIST> int HSSystem::kick_and_screen(double t2, double h4)
{
  double **v = atom->v;
  double **f = atom->f;
  const double *rmass = atom->rmass;
  const double *mass = atom->mass;
  const int *type = atom->type;
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  int flags = 0;
  // per-type masses and contiguous rows: the kick and the fast path four
  // spheres at a time (hs_screen.h, bit for bit this loop's), the full test
  // only for the spheres it does not clear
  HardSphere::KickScreen k;
  if (fast_screen(k, t2, h4, LIST, true)) {
    HardSphere::kick_clear_chunked(k, nlocal, unscreened, [&](const HardSphere::Unscreened &u) {
      const int fl = screen_terms<LIST>(u.i, u.d2, u.v2, u.a2);
      if (LIST && (fl & NEAR)) near_atoms.push_back(u.i);
      flags |= fl & ~NEAR;
    });
    return flags;
  }
  for (int i = 0; i < nlocal; i++) {
    active[i] = 0.0;
    if (!(mask[i] & groupbit)) continue;
    const double dtfm = rmass ? dtf_last / rmass[i] : dtf_last / mass[type[i]];
    v[i][0] += dtfm * f[i][0];
    v[i][1] += dtfm * f[i][1];
    v[i][2] += dtfm * f[i][2];
    const int fl =
        screen_atom<LIST>(i, t2, h4, rmass ? force->ftm2v / rmass[i] : ftm2v_mass[type[i]]);
    if (LIST && (fl & NEAR)) near_atoms.push_back(i);
    flags |= fl & ~NEAR;
  }
  return flags;
}

double HSSystem::memory_usage() const
{
  return (double) nmax_hs * 8 * sizeof(double) + (double) nmax_cap * 3 * sizeof(double) +
      HardSphere::capacity_bytes(cand) +
      HardSphere::capacity_bytes(cand_r) + HardSphere::capacity_bytes(near_atoms) +
      HardSphere::capacity_bytes(unscreened);
}
