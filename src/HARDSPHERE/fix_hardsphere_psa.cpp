/* ----------------------------------------------------------------------
   HARDSPHERE package: fix hardsphere/psa, the primitive splitting
   algorithm. See fix_hardsphere_psa.h and doc/fix_hardsphere_psa.rst.
------------------------------------------------------------------------- */

#include "fix_hardsphere_psa.h"

#include "hs_contact.h"
#include "hs_eventq.h"
#include "hs_system.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "modify.h"
#include "update.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <mpi.h>

using namespace LAMMPS_NS;
using HardSphere::Contact;


/* ---------------------------------------------------------------------- */

FixHardSpherePSA::FixHardSpherePSA(LAMMPS *lmp, int narg, char **arg) :
    FixHardSphere(lmp, narg, arg), adj_valid(0)
{
  MPI_Type_contiguous((int) sizeof(FlightImpulse), MPI_BYTE, &event_type);
  MPI_Type_commit(&event_type);
  MPI_Op_create(&FixHardSpherePSA::earliest_event, 1, &event_op);
}

FixHardSpherePSA::~FixHardSpherePSA()
{
  MPI_Op_free(&event_op);
  MPI_Type_free(&event_type);
}

// reduction of the ranks' earliest events: the earliest, ties to the lower
// rank (commutative and associative, so every rank gets the same winner)
void FixHardSpherePSA::earliest_event(void *in, void *inout, int *len, MPI_Datatype *)
{
  const auto *a = (const FlightImpulse *) in;
  auto *b = (FlightImpulse *) inout;
  for (int k = 0; k < *len; k++)
    if (a[k].t < b[k].t || (a[k].t == b[k].t && a[k].rank < b[k].rank)) b[k] = a[k];
}

/* ----------------------------------------------------------------------
   the event scheduled for atom k at time te as a broadcastable collision:
   both spheres' positions at contact and the elastic impulse R of
   section 2 there (a wall reverses the normal velocity)
------------------------------------------------------------------------- */

void FixHardSpherePSA::build_event(int k, double te, FlightImpulse &fi)
{
  double **x = atom->x;
  double **v = atom->v;
  const tagint *tag = atom->tag;
  Impulse &imp = fi.imp;
  const int p = partner[k];
  fi.t = te;
  const double sk = te - tloc[k];
  for (int d = 0; d < 3; d++) fi.xi[d] = x[k][d] + sk * v[k][d];
  imp.itag = tag[k];
  if (p >= 0) {
    const double sp = te - tloc[p];
    for (int d = 0; d < 3; d++) {
      fi.xj[d] = x[p][d] + sp * v[p][d];
      imp.dq[d] = fi.xi[d] - fi.xj[d];
    }
    const double dv[3] = {v[k][0] - v[p][0], v[k][1] - v[p][1], v[k][2] - v[p][2]};
    imp.type = PAIR_EVENT;
    imp.wall = -1;
    imp.jtag = tag[p];
    imp.apply = imp.dq[0] * dv[0] + imp.dq[1] * dv[1] + imp.dq[2] * dv[2] < 0.0;
    if (imp.apply) HardSphere::pair_impulse(imp.dq, dv, S.mass_of(k), S.mass_of(p), imp.J);
  } else {
    const Wall &wl = S.walls[-1 - p];
    imp.type = WALL_EVENT;
    imp.wall = -1 - p;
    imp.dq[wl.dim] = fi.xi[wl.dim] - wl.coord;
    const double vn = (wl.side < 0) ? v[k][wl.dim] : -v[k][wl.dim];
    imp.apply = vn < 0.0;
    if (imp.apply) imp.J[wl.dim] = -2.0 * S.mass_of(k) * v[k][wl.dim];
  }
}

/* ----------------------------------------------------------------------
   the system layer collects the candidate pairs at each list build; our per-atom
   view of them is built on the first step that needs it
------------------------------------------------------------------------- */

void FixHardSpherePSA::setup_post_neighbor()
{
  FixHardSphere::setup_post_neighbor();
  adj_valid = 0;
}

void FixHardSpherePSA::post_neighbor()
{
  FixHardSphere::post_neighbor();
  adj_valid = 0;
}

void FixHardSpherePSA::build_adjacency()
{
  const int nall = atom->nlocal + atom->nghost;
  const int ncand = (int) S.cand.size();
  adj_start.assign(nall + 1, 0);
  for (int k = 0; k < ncand; k++) adj_start[S.cand[k] + 1]++;
  for (int i = 0; i < nall; i++) adj_start[i + 1] += adj_start[i];
  adj.resize(ncand);
  std::vector<int> fill(adj_start.begin(), adj_start.end() - 1);
  for (int k = 0; k < ncand; k += 2) {
    const int i = S.cand[k], j = S.cand[k + 1];
    adj[fill[i]++] = j;
    adj[fill[j]++] = i;
  }

  tag_index.clear();
  if (atom->map_style == Atom::MAP_NONE) {
    const tagint *tag = atom->tag;
    tag_index.reserve(nall);
    for (int i = 0; i < nall; i++) tag_index.emplace_back(tag[i], i);
    std::sort(tag_index.begin(), tag_index.end());
  }
  adj_valid = 1;
}

// fn(k) for every local copy k (owned or ghost) of the atom with this tag
template <class F> void FixHardSpherePSA::for_copies(tagint tag, F fn)
{
  if (atom->map_style != Atom::MAP_NONE) {
    for (int k = atom->map(tag); k >= 0; k = atom->sametag[k]) fn(k);
  } else {
    auto it = std::lower_bound(tag_index.begin(), tag_index.end(), std::make_pair(tag, -1));
    for (; it != tag_index.end() && it->first == tag; ++it) fn(it->second);
  }
}

/* ----------------------------------------------------------------------
   the step's first predictions, every atom at local time 0: one pass over
   the candidate pairs with an active atom (each pair once, its contact
   scheduled for each active atom of the two) and the walls of active atoms
------------------------------------------------------------------------- */

void FixHardSpherePSA::predict_all()
{
  double **x = atom->x;
  double **v = atom->v;
  const tagint *tag = atom->tag;
  const int nlocal = atom->nlocal;
  const int nall = nlocal + atom->nghost;
  tfirst.assign(nall, BIG);

  const int ncand = (int) S.cand.size();
  for (int m = 0; m < ncand; m += 2) {
    const int i = S.cand[m], j = S.cand[m + 1];
    const bool ai = S.active[i] != 0.0, aj = S.active[j] != 0.0;
    if (!ai && !aj) continue;
    const double dq[3] = {x[i][0] - x[j][0], x[i][1] - x[j][1], x[i][2] - x[j][2]};
    const double dv[3] = {v[i][0] - v[j][0], v[i][1] - v[j][1], v[i][2] - v[j][2]};
    const double sigma = S.radius_of(i) + S.radius_of(j);
    const Contact ct =
        HardSphere::free_flight_pair_contact(dq, dv, sigma, S.dtv, TOUCH_TOL * sigma * sigma);
    if (ct.status == HardSphere::NO_CONTACT) continue;
    if (ct.status == HardSphere::OVERLAP) {
      S.pair_overlap_error(i, j, sqrt(dq[0] * dq[0] + dq[1] * dq[1] + dq[2] * dq[2]), sigma);
    }
    if (ai && ct.t < tfirst[i]) {
      tfirst[i] = ct.t;
      partner[i] = j;
    }
    if (aj && ct.t < tfirst[j]) {
      tfirst[j] = ct.t;
      partner[j] = i;
    }
  }

  for (int i = 0; i < nlocal; i++) {
    if (S.active[i] == 0.0) continue;
    const double r = S.radius_of(i);
    for (int w = 0; w < (int) S.walls.size(); w++) {
      const Wall &wl = S.walls[w];
      const double g = S.wall_gap(wl, x[i], r);
      const double vn = (wl.side < 0) ? v[i][wl.dim] : -v[i][wl.dim];
      const Contact ct = HardSphere::free_flight_wall_contact(g, vn, S.dtv, TOUCH_TOL * 2.0 * r);
      if (ct.status == HardSphere::NO_CONTACT) continue;
      if (ct.status == HardSphere::OVERLAP) {
        std::string name;
        S.wall_name(wl, name);
        error->one(FLERR,
                   "Fix {}: atom {} is {} through wall {} on step {}: a collision was missed",
                   style_name, tag[i], -g, name, update->ntimestep);
      }
      if (ct.t < tfirst[i]) {
        tfirst[i] = ct.t;
        partner[i] = -1 - w;
      }
    }
  }

  for (int k = 0; k < nall; k++)
    if (tfirst[k] < S.dtv) {
      pcount[k] = 0;
      heap.set(k, tfirst[k]);
    }
}

/* ----------------------------------------------------------------------
   schedule atom k's earliest event in the rest of the step: a contact with
   a candidate partner (both on their straight lines, from the later of
   their two local times) or, for an owned atom, with a wall
------------------------------------------------------------------------- */

void FixHardSpherePSA::predict_atom(int k)
{
  double **x = atom->x;
  double **v = atom->v;
  const tagint *tag = atom->tag;
  double tbest = BIG;
  int pbest = -1;
  const double tk = tloc[k];
  const double rk = S.radius_of(k);

  for (int m = adj_start[k]; m < adj_start[k + 1]; m++) {
    const int p = adj[m];
    const double tp = tloc[p];
    const double t0 = (tk > tp) ? tk : tp;
    const double sk = t0 - tk, sp = t0 - tp;
    const double dq[3] = {(x[k][0] + sk * v[k][0]) - (x[p][0] + sp * v[p][0]),
                          (x[k][1] + sk * v[k][1]) - (x[p][1] + sp * v[p][1]),
                          (x[k][2] + sk * v[k][2]) - (x[p][2] + sp * v[p][2])};
    const double dv[3] = {v[k][0] - v[p][0], v[k][1] - v[p][1], v[k][2] - v[p][2]};
    const double sigma = rk + S.radius_of(p);
    const Contact ct =
        HardSphere::free_flight_pair_contact(dq, dv, sigma, S.dtv - t0, TOUCH_TOL * sigma * sigma);
    if (ct.status == HardSphere::NO_CONTACT) continue;
    if (ct.status == HardSphere::OVERLAP) {
      S.pair_overlap_error(k, p, sqrt(dq[0] * dq[0] + dq[1] * dq[1] + dq[2] * dq[2]), sigma);
    }
    const double te = t0 + ct.t;
    if (te < tbest) {
      tbest = te;
      pbest = p;
    }
  }

  if (k < atom->nlocal) {
    for (int w = 0; w < (int) S.walls.size(); w++) {
      const Wall &wl = S.walls[w];
      const double g = S.wall_gap(wl, x[k], rk);
      const double vn = (wl.side < 0) ? v[k][wl.dim] : -v[k][wl.dim];
      const Contact ct =
          HardSphere::free_flight_wall_contact(g, vn, S.dtv - tk, TOUCH_TOL * 2.0 * rk);
      if (ct.status == HardSphere::NO_CONTACT) continue;
      if (ct.status == HardSphere::OVERLAP) {
        std::string name;
        S.wall_name(wl, name);
        error->one(FLERR,
                   "Fix {}: atom {} is {} through wall {} on step {}: a collision was missed",
                   style_name, tag[k], -g, name, update->ntimestep);
      }
      const double te = tk + ct.t;
      if (te < tbest) {
        tbest = te;
        pbest = -1 - w;
      }
    }
  }

  if (tbest < S.dtv) {
    partner[k] = pbest;
    pcount[k] = (pbest >= 0) ? ncol[pbest] : 0;
    heap.set(k, tbest);
  } else
    heap.remove(k);
}

/* ----------------------------------------------------------------------
   every copy of an atom goes to the broadcast contact position (plus the
   periodic image offset of that copy) at the contact time
------------------------------------------------------------------------- */

void FixHardSpherePSA::place_copies(tagint tg, const double *xc, double t)
{
  double **x = atom->x;
  double **v = atom->v;
  const int *periodic = domain->periodicity;
  // h, h_inv: the box's lattice vectors, upper triangular in Voigt order
  // (xx yy zz yz xz xy), diagonal (the box lengths) in an orthogonal box
  const double *h = domain->h, *hi = domain->h_inv;
  for_copies(tg, [&](int c) {
    const double s = t - tloc[c];
    // the copy's image: the lattice vector h n nearest its own move, n
    // from that move in box fractions
    double dl[3];
    for (int d = 0; d < 3; d++) dl[d] = x[c][d] + s * v[c][d] - xc[d];
    const double f[3] = {hi[0] * dl[0] + hi[5] * dl[1] + hi[4] * dl[2],
                         hi[1] * dl[1] + hi[3] * dl[2], hi[2] * dl[2]};
    double n[3];
    for (int d = 0; d < 3; d++) n[d] = periodic[d] ? std::round(f[d]) : 0.0;
    x[c][0] = xc[0] + h[0] * n[0] + h[5] * n[1] + h[4] * n[2];
    x[c][1] = xc[1] + h[1] * n[1] + h[3] * n[2];
    x[c][2] = xc[2] + h[2] * n[2];
    tloc[c] = t;
  });
}

// velocities of every copy after an impulse (HSSystem::apply_impulse's arithmetic,
// with an O(log N) tag look-up when LAMMPS keeps no atom map)
void FixHardSpherePSA::apply_impulse(const Impulse &imp)
{
  if (!imp.apply) return;
  double **v = atom->v;
  if (imp.type == WALL_EVENT) {
    const int dim = S.walls[imp.wall].dim;
    for_copies(imp.itag, [&](int c) { v[c][dim] = -v[c][dim]; });
    return;
  }
  for_copies(imp.itag, [&](int c) {
    const double s = 1.0 / S.mass_of(c);
    v[c][0] += s * imp.J[0];
    v[c][1] += s * imp.J[1];
    v[c][2] += s * imp.J[2];
  });
  for_copies(imp.jtag, [&](int c) {
    const double s = -1.0 / S.mass_of(c);
    v[c][0] += s * imp.J[0];
    v[c][1] += s * imp.J[1];
    v[c][2] += s * imp.J[2];
  });
}

// after the impulse: invalidate events that involve the atom (counters),
// check the rest of its flight stays inside the neighbor list's reach, and
// schedule its next event
void FixHardSpherePSA::after_collision(tagint tg)
{
  double **x = atom->x;
  double **v = atom->v;
  const int nlocal = atom->nlocal;
  for_copies(tg, [&](int c) {
    ncol[c]++;
    if (c < nlocal) {
      const double dx = x[c][0] - S.xref[c][0], dy = x[c][1] - S.xref[c][1], dz = x[c][2] - S.xref[c][2];
      const double w = sqrt(dx * dx + dy * dy + dz * dz) +
          (S.dtv - tloc[c]) * sqrt(v[c][0] * v[c][0] + v[c][1] * v[c][1] + v[c][2] * v[c][2]);
      if (w > S.skin)
        error->one(FLERR,
                   "Fix {}: atom {} may be {} away from where the neighbor list was built "
                   "after a collision on step {}, more than the skin {}: use a smaller "
                   "timestep or a larger neighbor skin",
                   style_name, tg, w, update->ntimestep, S.skin);
    }
    predict_atom(c);
  });
}

/* ----------------------------------------------------------------------
   one step of the primitive splitting algorithm (section 2.1):
     p-  = p^n - dt/2 grad V(q^n)                  (here)
     (q^{n+1}, p+) = exact hard-sphere flow over dt  (here, event-driven)
     p^{n+1} = p+ - dt/2 grad V(q^{n+1})           (base final_integrate)
   A step in which screening finds no sphere that may touch anything is
   fix nve's step, to the bit.
------------------------------------------------------------------------- */

void FixHardSpherePSA::initial_integrate(int)
{
  begin_step_virial();
  check_state_kept();    // (a run without set-up: its first step)
  // the family's screening (HSSystem::screen_step()): the Verlet bound
  // |t v + t^2/2 a|, t <= dt, also bounds the free flight t (v + dt/2 a)
  const int allflags = S.screen_step();
  S.dtf_last = S.dtf;
  if (!(allflags & ACTIVE)) {
    S.nve_initial();
    if (allflags & FAR) S.request_rebuild();
    return;
  }

  // half kick, then ghosts' velocities and active flags
  S.kick_dtf(S.dtf);
  S.comm_vel_acc();
  if (!adj_valid) build_adjacency();

  double **x = atom->x;
  double **v = atom->v;
  const int nlocal = atom->nlocal;
  const int nall = nlocal + atom->nghost;
  const int *mask = atom->mask;
  const int nprocs = comm->nprocs, me = comm->me;

  tloc.assign(nall, 0.0);
  ncol.assign(nall, 0);
  partner.resize(nall);
  pcount.resize(nall);
  heap.reset(nall);
  predict_all();

  bool collided = false;
  int stuck = 0;
  bigint nevents = 0;
  double tlast = 0.0;

  while (true) {
    // this rank's earliest event whose partner has not collided since it
    // was predicted; stale ones are re-predicted (lazy invalidation)
    FlightImpulse mine, first;
    memset(&mine, 0, sizeof(mine));
    mine.t = BIG;
    mine.rank = me;
    while (!heap.empty()) {
      const int k = heap.top();
      const int p = partner[k];
      if (p >= 0 && ncol[p] != pcount[k]) {
        predict_atom(k);
        continue;
      }
      build_event(k, heap.top_key(), mine);
      break;
    }
    // the globally earliest one, with its impulse, in one collective
    if (nprocs > 1) MPI_Allreduce(&mine, &first, 1, event_type, event_op, world);
    else first = mine;
    if (first.t >= S.dtv) break;
    const double te = first.t;
    const FlightImpulse &fi = first;

    if (me == first.rank && fi.imp.apply) S.add_impulse_virial(fi.imp);

    // every rank: its copies of the atoms to the contact, the impulse, new
    // predictions for them (a grazing contact gets no impulse, but its
    // atoms still restart from the contact, so it is not found again)
    const Impulse &imp = fi.imp;
    place_copies(imp.itag, fi.xi, te);
    if (imp.type == PAIR_EVENT) place_copies(imp.jtag, fi.xj, te);
    apply_impulse(imp);
    after_collision(imp.itag);
    if (imp.type == PAIR_EVENT) after_collision(imp.jtag);

    if (te > tlast) stuck = 0;
    tlast = te;
    if (imp.apply) {
      if (imp.type == PAIR_EVENT) S.ncoll_pair += 1.0;
      else S.ncoll_wall += 1.0;
      collided = true;
    } else if (++stuck > MAX_STUCK) {
      S.resting_contact_error(imp, true);
    }
    S.check_runaway(++nevents, true);
  }

  // free flight of every sphere to the end of the step (fix nve's drift
  // for those that did not collide)
  for (int i = 0; i < nlocal; i++)
    if (mask[i] & groupbit) {
      const double s = S.dtv - tloc[i];    // dtv itself (bit for bit) if no collision
      x[i][0] += s * v[i][0];
      x[i][1] += s * v[i][1];
      x[i][2] += s * v[i][2];
    }

  if (collided) S.ncoll_steps += 1.0;
  S.request_rebuild();
}

/* ---------------------------------------------------------------------- */

double FixHardSpherePSA::memory_usage()
{
  double bytes = FixHardSphere::memory_usage();
  bytes += (double) tloc.capacity() * sizeof(double);
  bytes += (double) (ncol.capacity() + partner.capacity() + pcount.capacity()) * sizeof(int);
  bytes += (double) (adj.capacity() + adj_start.capacity()) * sizeof(int);
  bytes += (double) tag_index.capacity() * sizeof(std::pair<tagint, int>);
  bytes += (double) tloc.capacity() * (2 * sizeof(int) + sizeof(double));    // heap
  return bytes;
}
