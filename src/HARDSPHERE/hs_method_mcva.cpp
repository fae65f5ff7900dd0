/* ----------------------------------------------------------------------
   HARDSPHERE package: the method of fix hardsphere/mcva (Bond & Leimkuhler
   2007, section 3.1). See hs_method_mcva.h and doc/fix_hardsphere_mcva.rst.
------------------------------------------------------------------------- */

#include "hs_method_mcva.h"

#include "hs_cluster_flow.h"
#include "hs_flow_view.h"
#include "hs_gauss.h"
#include "hs_flatmap.h"
#include "hs_ljcut.h"
#include "hs_local_modified.h"
#include "hs_modified.h"
#include "hs_potential.h"
#include "hs_projection.h"
#include "hs_system.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix.h"
#include "force.h"
#include "memory.h"
#include "pair.h"
#include "update.h"
#include "utils.h"

#include <cmath>
#include <cstring>
#include <unordered_map>
#include <mpi.h>

using namespace LAMMPS_NS;

// relative change of the stage derivatives at which the fixed-point
// iteration stops, or at which it may stop once it no longer decreases
// (the noise floor of the derivatives: ~1e-11 for differences in r, more for
// differences of force evaluations); at most STAGE_MAXIT sweeps
static constexpr double STAGE_TOL = 1.0e-14;
static constexpr double STAGE_STAG = 1.0e-8;
static constexpr int STAGE_MAXIT = 100;
// the contact time on the Gauss flow is resolved to ROOT_TTOL * dt, with at
// most ROOT_MAXEVAL Gauss solves
static constexpr double ROOT_TTOL = 1.0e-13;
static constexpr int ROOT_MAXEVAL = 100;
// an overlap after a Gauss solve counts as a missed contact beyond this
// (relative to sigma^2, resp. the diameter): far above the round-off of
// gaps across periodic images, far below the family's touching tolerance
static constexpr double OVERLAP_TOL = 1.0e-12;

/* ---------------------------------------------------------------------- */

HSMethodMCVA::HSMethodMCVA(LAMMPS *lmp, HSSystem &sys) : HSMethod(lmp, sys) {}

HSMethodMCVA::~HSMethodMCVA()
{
  delete lmod;
  memory->destroy(fv);
  memory->destroy(fa);
  memory->destroy(fhv);
  memory->destroy(ftv);
  memory->destroy(fha);
}

/* ---------------------------------------------------------------------- */

// after the fix's init() (which set up the derivative layer)
void HSMethodMCVA::init()
{
  require_fix_energies("H_[2,VV] through collisional steps");
  // the stage equations continue a pair that leaves its cutoff in a
  // sub-step through single() past the cutoff (the frozen set): a table has
  // no values there (pair_table.cpp would stop the run mid-step)
  if (force->pair && utils::strmatch(force->pair_style, "^table"))
    error->all(FLERR,
               "Fix {} cannot use pair style {}: its Gauss stage equations evaluate a pair's "
               "potential past the cutoff (doc: the frozen cutoff set), where a table has no "
               "values; use hardsphere/pcva or /cva with tables",
               S.style_name, force->pair_style);
  gauss_step = 0;
  warned_drop = 0;
  if (comm->me == 0) {
    std::string how;
    if (local_form)
      how = "Newton per cluster (the start's Jacobian, Eigen LU; "
            "substep local)";
    else if (!newton)
      how = "fixed-point iteration (fix_modify stages fixed)";
    else if (comm->nprocs > 1)
      how = fmt::format("simplified Newton without V'' in the Jacobian on {} MPI ranks (no "
                        "distributed assembly): it converges as two fixed-point sweeps per "
                        "iteration",
                        comm->nprocs);
    else if (!S.pot->any_radial())
      how = "simplified Newton without V'' in the Jacobian (no pair or bond style on the "
            "single path): it converges as two fixed-point sweeps per iteration";
    else if (!S.pot->radial_only())
      how = "simplified Newton with V'' of the radial pair and bond styles in the Jacobian; "
            "the parts of V known only as force differences converge as two fixed-point "
            "sweeps per iteration";
    else
      how = "simplified Newton with V'' in the Jacobian";
    utils::logmesg(lmp, "Fix {}: Gauss stage equations by {}\n", S.style_name, how);
  }
}

// fix_modify ID stages newton|fixed
int HSMethodMCVA::modify_param(int narg, char **arg)
{
  if (strcmp(arg[0], "stages") != 0) return 0;
  if (narg < 2) error->all(FLERR, "Illegal fix_modify {} command: stages needs newton or fixed",
                           S.style_name);
  if (strcmp(arg[1], "newton") == 0) newton = 1;
  else if (strcmp(arg[1], "fixed") == 0) newton = 0;
  else
    error->all(FLERR, "Illegal fix_modify {} command: stages {} (use newton or fixed)",
               S.style_name, arg[1]);
  return 2;
}

/* ----------------------------------------------------------------------
   G = M^-1 V'' at the sub-step's start from the radial terms of the
   derivative layer (frozen cutoff set), rows of the group's owned atoms:
   the Jacobian of the Newton iteration (hs_newton.h). Serial only.
------------------------------------------------------------------------- */

void HSMethodMCVA::assemble_G()
{
  useG = 0;
  if (!newton || comm->nprocs > 1 || !S.pot->any_radial()) return;
  const int ng = (int) idx.size();
  std::unordered_map<tagint, int> row;
  row.reserve(2 * ng);
  for (int k = 0; k < ng; k++) row[atom->tag[idx[k]]] = k;
  const tagint *tag = atom->tag;
  auto row_of = [&](int i) {
    auto it = row.find(tag[i]);
    return it == row.end() ? -1 : it->second;
  };
  Gmat.clear(ng);
  const double ftm2v = force->ftm2v;
  for (int k = 0; k < ng; k++) Gmat.set_row_scale(k, ftm2v / S.mass_of(idx[k]));
  S.pot->use_frozen_set(true);
  S.pot->radial_terms([&](int i, int j, const double *del, double d1, double d2, bool ui, bool uj) {
    Gmat.add_radial(row_of(i), row_of(j), del, d1, d2, ui, uj);
  });
  S.pot->use_frozen_set(false);
  gx.resize(3 * ng);
  gy.resize(3 * ng);
  useG = 1;
}

void HSMethodMCVA::grow_fields()
{
  if (atom->nmax <= nmax_f) return;
  nmax_f = atom->nmax;
  memory->destroy(fv);
  memory->destroy(fa);
  memory->destroy(fhv);
  memory->destroy(ftv);
  memory->destroy(fha);
  memory->create(fv, nmax_f, 3, "hardsphere/mcva:fv");
  memory->create(fa, nmax_f, 3, "hardsphere/mcva:fa");
  memory->create(fhv, nmax_f, 3, "hardsphere/mcva:fhv");
  memory->create(ftv, nmax_f, 3, "hardsphere/mcva:ftv");
  memory->create(fha, nmax_f, 3, "hardsphere/mcva:fha");
}

/* ----------------------------------------------------------------------
   the state of the owned group atoms at a sub-step's start
------------------------------------------------------------------------- */

void HSMethodMCVA::save_start()
{
  grow_fields();
  idx.clear();
  const int *mask = atom->mask;
  for (int i = 0; i < atom->nlocal; i++)
    if (mask[i] & S.groupbit) idx.push_back(i);
  const int ng = (int) idx.size(), n = 6 * ng;
  y0.resize(n);
  double **x = atom->x, **v = atom->v;
  for (int k = 0; k < ng; k++)
    for (int d = 0; d < 3; d++) {
      y0[3 * k + d] = x[idx[k]][d];
      y0[3 * ng + 3 * k + d] = v[idx[k]][d];
    }
  f0.resize(n);
  K1.resize(n);
  K2.resize(n);
  K1p.resize(n);
  K2p.resize(n);
  y1.resize(n);
  work.resize(3 * n);
  hprev = 0.0;
  f0_valid = 0;
  // every solve from this start integrates the potential of the pairs
  // inside their cutoff here (see field())
  S.pot->freeze_cutoff_set();
  assemble_G();
}

void HSMethodMCVA::set_state(const std::vector<double> &y)
{
  const int ng = (int) idx.size();
  double **x = atom->x, **v = atom->v;
  for (int k = 0; k < ng; k++)
    for (int d = 0; d < 3; d++) {
      x[idx[k]][d] = y[3 * k + d];
      v[idx[k]][d] = y[3 * ng + 3 * k + d];
    }
}

/* ----------------------------------------------------------------------
   the vector field of H~ = H_[2,VV] (section 3, with v = M^-1 p):
     dq/dt = v + dt^2/6 M^-1 V'' v
     dv/dt = M^-1 (F - dt^2/12 V'''[v,v,.] - dt^2/12 V'' a),  a = M^-1 F, F = -grad V
   (M^-1 F in LAMMPS units is ftm2v F / m). Collective.
------------------------------------------------------------------------- */

void HSMethodMCVA::field(const double *y, double *kout)
{
  const int ng = (int) idx.size();
  const double dt = update->dt, ftm2v = force->ftm2v;
  const double c6 = dt * dt / 6.0, c12 = dt * dt / 12.0;
  double **x = atom->x, **f = atom->f;
  const int nlocal = atom->nlocal;

  for (int i = 0; i < nlocal; i++)
    for (int d = 0; d < 3; d++) fv[i][d] = fa[i][d] = 0.0;
  for (int k = 0; k < ng; k++)
    for (int d = 0; d < 3; d++) {
      x[idx[k]][d] = y[3 * k + d];
      fv[idx[k]][d] = y[3 * ng + 3 * k + d];
    }
  // the pairs inside their cutoff at the sub-step's start (doc, "Pair
  // styles cut off without smoothing"): the field is then smooth, and the
  // stage equations have a solution even where a pair crosses a cutoff at
  // which its force jumps
  S.pot->use_frozen_set(true);
  S.pot->evaluate(0);    // F at the stage positions (ghosts forwarded)
  for (int k = 0; k < ng; k++) {
    const int i = idx[k];
    const double im = ftm2v / S.mass_of(i);
    for (int d = 0; d < 3; d++) fa[i][d] = im * f[i][d];
  }
  S.pot->hess_third_vec(fv, fhv, ftv, fa, fha);    // V'' v, V'''[v,v,.]; V'' a
  S.pot->use_frozen_set(false);
  for (int k = 0; k < ng; k++) {
    const int i = idx[k];
    const double im = ftm2v / S.mass_of(i);
    for (int d = 0; d < 3; d++) {
      kout[3 * k + d] = fv[i][d] + c6 * im * fhv[i][d];
      kout[3 * ng + 3 * k + d] = im * (f[i][d] - c12 * ftv[i][d] - c12 * fha[i][d]);
    }
  }
}

/* ----------------------------------------------------------------------
   one Gauss-Legendre step of length h from the saved start y0 into out;
   stage guesses from the previous solve from y0 (if any)
------------------------------------------------------------------------- */

void HSMethodMCVA::gauss_solve(double h, std::vector<double> &out)
{
  const int n = (int) y0.size();
  if (!f0_valid) {
    field(y0.data(), f0.data());
    f0_valid = 1;
  }
  if (hprev > 0.0)
    HardSphere::gauss2_guess(f0.data(), K1p.data(), K2p.data(), hprev, h, n, K1.data(), K2.data());
  else {
    K1 = f0;
    K2 = f0;
  }
  auto fn = [this](const double *y, double *k) { field(y, k); };
  auto reduce = [this](double *buf, int m) {
    MPI_Allreduce(MPI_IN_PLACE, buf, m, MPI_DOUBLE, MPI_SUM, world);
  };
  HardSphere::GaussOptions opt;
  opt.tol = STAGE_TOL;
  opt.stag_tol = STAGE_STAG;
  opt.maxit = STAGE_MAXIT;
  HardSphere::GaussStatus st;
  if (newton) {
    HardSphere::NewtonOptions nopt;
    nopt.gauss = opt;
    auto applyG = [this](const double *x, double *out) { Gmat.apply(x, out); };
    const HardSphere::NewtonStatus ns = nsolver.solve(fn, reduce, applyG, useG != 0, y0.data(), n,
                                                      h, K1.data(), K2.data(), nopt);
    st = ns;
    nlin += ns.lin_iters;
    if (ns.lin_dropped && comm->me == 0 && !warned_drop) {
      warned_drop = 1;
      error->warning(FLERR,
                     "Fix {}: on step {} the Newton iteration's linear solve did not contract "
                     "(h^2 |V''|/m too large, beyond Verlet's stability); that solve went on "
                     "without V'' in the Jacobian (warned once)",
                     S.style_name, update->ntimestep);
    }
  } else
    st = HardSphere::gauss2_stages(fn, reduce, y0.data(), n, 2, h, K1.data(), K2.data(), opt,
                                   work.data());
  gauss_iters += st.iterations;
  gauss_solves += 1.0;
  gauss_maxit = MAX(gauss_maxit, (double) st.iterations);
  if (!st.converged && !std::isfinite(st.residual))
    error->all(FLERR,
               "Fix {}: the vector field of the modified Hamiltonian is not finite (NaN or inf "
               "in the forces or their derivatives) at a Gauss stage on step {} (sub-step tau "
               "{}, iteration {})",
               S.style_name, update->ntimestep, h, st.iterations);
  if (!st.converged)
    error->all(FLERR,
               "Fix {}: the Gauss stage equations did not converge in {} iterations on step {} "
               "(sub-step tau {}, relative change of the stage derivatives {}): use a smaller "
               "timestep (or smooth forces: a style on the path of force differences cut off "
               "without smoothing makes the field jump at its cutoff)",
               S.style_name, st.iterations, update->ntimestep, h, st.residual);
  K1p = K1;
  K2p = K2;
  hprev = h;
  HardSphere::gauss2_update(y0.data(), n, h, K1.data(), K2.data(), out.data());
}

// pairs whose cutoff status at the sub-step's end differs from its start:
// their force jump was integrated with the start's set (output entry 12)
void HSMethodMCVA::count_crossings()
{
  double jump = 0.0;
  ncross += S.pot->cutoff_crossings(jump);
}

/* ----------------------------------------------------------------------
   a Gauss sub-step of length h from the current state, no contact: x and v
   hold the result; forces are NOT re-evaluated (callers do when needed)
------------------------------------------------------------------------- */

void HSMethodMCVA::gauss_substep(double h)
{
  save_start();
  if (h > 0.0) {
    gauss_solve(h, y1);
    set_state(y1);
  }
  gauss_substeps += 1.0;
}

/* ----------------------------------------------------------------------
   local index of the owned atom with tag t, -1 if another rank owns it
   (a scan when the atom style keeps no map)
------------------------------------------------------------------------- */

static int owned_index(Atom *atom, tagint t)
{
  const int nlocal = atom->nlocal;
  if (atom->map_style != Atom::MAP_NONE) {
    const int k = atom->map(t);
    return (k >= 0 && k < nlocal) ? k : -1;
  }
  const tagint *tag = atom->tag;
  for (int i = 0; i < nlocal; i++)
    if (tag[i] == t) return i;
  return -1;
}

/* ----------------------------------------------------------------------
   gap of the contact imp (pair: |q_i - q_j|^2 - sigma^2; wall: distance of
   the surface from the plane) at the current x, and an estimate of its
   time derivative from the current v (the flow's dq/dt differs from v by
   O(dt^2), which only steers the root finder). Collective.
------------------------------------------------------------------------- */

double HSMethodMCVA::gap_of(const Impulse &imp, double &dg)
{
  double buf[14] = {0.0};
  double **x = atom->x, **v = atom->v;
  const int nlocal = atom->nlocal;
  auto put = [&](tagint t, double *b) {
    const int k = owned_index(atom, t);
    if (k >= 0) {
      for (int d = 0; d < 3; d++) {
        b[d] = x[k][d];
        b[3 + d] = v[k][d];
      }
      b[12] += S.radius_of(k);
    }
  };
  // buf: x_i v_i | x_j v_j | r_i + r_j
  {
    double bi[13] = {0.0}, bj[13] = {0.0};
    put(imp.itag, bi);
    if (imp.type == PAIR_EVENT) put(imp.jtag, bj);
    for (int d = 0; d < 6; d++) {
      buf[d] = bi[d];
      buf[6 + d] = bj[d];
    }
    buf[12] = bi[12] + bj[12];
  }
  MPI_Allreduce(MPI_IN_PLACE, buf, 13, MPI_DOUBLE, MPI_SUM, world);
  if (imp.type == PAIR_EVENT) {
    double dq[3] = {buf[0] - buf[6], buf[1] - buf[7], buf[2] - buf[8]};
    domain->minimum_image(dq);
    const double dv[3] = {buf[3] - buf[9], buf[4] - buf[10], buf[5] - buf[11]};
    const double sigma = buf[12];
    dg = 2.0 * (dq[0] * dv[0] + dq[1] * dv[1] + dq[2] * dv[2]);
    return dq[0] * dq[0] + dq[1] * dq[1] + dq[2] * dq[2] - sigma * sigma;
  }
  const Wall &w = S.walls[imp.wall];
  dg = (w.side < 0) ? buf[3 + w.dim] : -buf[3 + w.dim];
  return S.wall_gap(w, buf, buf[12]);
}

/* ----------------------------------------------------------------------
   the contact time of c on the Gauss flow from the saved start, within
   (0, tmax], from a guess. Returns 1 with tau and the state (x, v, ghosts'
   x) at the contact on the allowed side; 0 with the state at tmax if the
   flow has no contact there. Collective.
------------------------------------------------------------------------- */

int HSMethodMCVA::solve_contact(const Impulse &c, double guess, double tmax, double &tau)
{
  // phi(t): gap on the Gauss flow after t; the solution at the latest t
  // with a nonnegative gap is kept
  std::vector<double> ylo(y0.size());
  double tlo = -1.0;
  auto phi = [&](double t, double &g, double &dg) {
    gauss_solve(t, y1);
    set_state(y1);
    comm->forward_comm();
    g = gap_of(c, dg);
    if (g >= 0.0 && t > tlo) {
      tlo = t;
      ylo = y1;
    }
  };
  const HardSphere::RootResult r =
      HardSphere::contact_root(phi, guess, tmax, ROOT_TTOL * S.dtv, ROOT_MAXEVAL);

  if (r.status == HardSphere::ROOT_FAILED) {
    error->all(FLERR,
               "Fix {}: no contact time of {} found on the Gauss flow on step {} ({} Gauss "
               "solves, last tau {}, gap {})",
               S.style_name, S.contact_name(c), update->ntimestep, r.nevals, r.t, r.g);
  }
  if (r.status == HardSphere::ROOT_NONE) {
    if (r.t != tmax) gauss_solve(tmax, y1);    // else y1 holds the last solve, at tmax
    set_state(y1);
    comm->forward_comm();
    tau = tmax;
    return 0;
  }
  tau = r.t;
  if (tau == 0.0) set_state(y0);
  else {
    if (tlo != tau) {
      gauss_solve(tau, y1);
      ylo = y1;
    }
    set_state(ylo);
  }
  comm->forward_comm();
  return 1;
}

/* ----------------------------------------------------------------------
   the Verlet prescreen can miss a contact of the Gauss flow (their paths
   differ by O(tau dt^2)): the contact with the deepest overlap at the
   current x, if any (pair gap |q_i - q_j|^2 - sigma^2 relative to sigma^2,
   wall gap relative to the diameter). c gets its tags (all ranks), ev its
   local indices on 'rank'. Collective.
------------------------------------------------------------------------- */

bool HSMethodMCVA::find_overlap(Impulse &c, Event &ev, int &rank)
{
  double **x = atom->x;
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  double worst = -OVERLAP_TOL;
  Event mine{PAIR_EVENT, -1, -1, -1};
  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & S.groupbit)) continue;
    for (int w = 0; w < (int) S.walls.size(); w++) {
      const double r = S.radius_of(i);
      const double g = S.wall_gap(S.walls[w], x[i], r) / (2.0 * r);
      if (g < worst) {
        worst = g;
        mine = {WALL_EVENT, i, -1, w};
      }
    }
  }
  const int ncand = (int) S.cand.size();
  for (int k = 0; k < ncand; k += 2) {
    const int i = S.cand[k], j = S.cand[k + 1];
    const double sigma = S.radius_of(i) + S.radius_of(j);
    const double dx = x[i][0] - x[j][0], dy = x[i][1] - x[j][1], dz = x[i][2] - x[j][2];
    const double g = (dx * dx + dy * dy + dz * dz - sigma * sigma) / (sigma * sigma);
    if (g < worst) {
      worst = g;
      mine = {PAIR_EVENT, i, j, -1};
    }
  }
  struct {
    double g;
    int rank;
  } in{worst, comm->me}, out;
  MPI_Allreduce(&in, &out, 1, MPI_DOUBLE_INT, MPI_MINLOC, world);
  if (!(out.g < -OVERLAP_TOL)) return false;
  rank = out.rank;
  memset(&c, 0, sizeof(c));
  if (comm->me == rank) {
    ev = mine;
    c.type = mine.type;
    c.itag = atom->tag[mine.i];
    c.jtag = (mine.type == PAIR_EVENT) ? atom->tag[mine.j] : 0;
    c.wall = mine.wall;
  }
  MPI_Bcast(&c, sizeof(Impulse), MPI_BYTE, rank, world);
  return true;
}

/* ----------------------------------------------------------------------
   with the state at the Gauss solution at T from the saved start: if some
   contact overlaps there, its crossing is earlier: find it on the flow and
   move there (T shrinks), until no contact overlaps at T. Returns true if
   T moved (the contact in ev on rank). Collective.
------------------------------------------------------------------------- */

bool HSMethodMCVA::earliest_crossing(double &T, Event &ev, int &rank)
{
  bool moved = false;
  Impulse c;
  Event cev;
  int crank = 0;
  for (int it = 0; find_overlap(c, cev, crank); it++) {
    if (it > 100)
      error->all(FLERR, "Fix {}: no first contact found on the Gauss flow on step {}",
                 S.style_name, update->ntimestep);
    double dg;
    const double gT = gap_of(c, dg);
    if (!(gT < 0.0)) break;    // round-off across periodic images: no crossing
    set_state(y0);
    comm->forward_comm();
    const double g0 = gap_of(c, dg);
    double tau = 0.0;
    if (g0 > 0.0) {
      // guess by linear interpolation between 0 and T; the flow has a
      // contact in (0, T] (the gap is negative at T)
      const double guess = T * g0 / (g0 - gT);
      if (!solve_contact(c, guess, T, tau))
        error->all(FLERR,
                   "Fix {}: atoms {} and {} (or a wall) overlap after a Gauss sub-step on step {} "
                   "but no contact time was found",
                   S.style_name, c.itag, c.jtag, update->ntimestep);
    }
    // g0 <= 0: touching at the start already: a contact now (tau = 0, state y0)
    T = tau;
    moved = true;
    ev = cev;    // the contact at the (new) T
    rank = crank;
    if (tau == 0.0) break;
  }
  return moved;
}

/* ----------------------------------------------------------------------
   a contact found by earliest_crossing() inside finish_step(), where the
   engine's loop is over: the loop's collision, done here (rare)
------------------------------------------------------------------------- */

void HSMethodMCVA::collide_missed(const Event &ev, int rank)
{
  Impulse imp;
  memset(&imp, 0, sizeof(imp));
  if (comm->me == rank) {
    imp.type = ev.type;
    imp.itag = atom->tag[ev.i];
    imp.jtag = (ev.type == PAIR_EVENT) ? atom->tag[ev.j] : 0;
    imp.wall = ev.wall;
    if (ev.type == PAIR_EVENT) collide_pair(ev.i, ev.j, imp);
    else collide_wall(ev.i, S.walls[ev.wall], imp);
  }
  MPI_Bcast(&imp, sizeof(Impulse), MPI_BYTE, rank, world);
  if (!imp.apply)
    error->all(FLERR,
               "Fix {}: atoms {} and {} (or a wall) touch on the Gauss flow on step {} without "
               "approaching: cannot resolve the contact",
               S.style_name, imp.itag, imp.jtag, update->ntimestep);
  modify_impulse(imp);
  if (comm->me == rank) S.add_impulse_virial(imp);
  S.apply_impulse(imp);
  if (imp.type == PAIR_EVENT) S.ncoll_pair += 1.0;
  else S.ncoll_wall += 1.0;
  S.step_collided = 1;
  nmissed += 1.0;
}

/* ----------------------------------------------------------------------
   the hooks of the global engine's sub-step loop (hs_method.h)
------------------------------------------------------------------------- */

void HSMethodMCVA::begin_collisional_step()
{
  gauss_step = 1;
}

// no contact predicted in the rest of the step: plain Verlet if the step
// never had one (fix nve's step), else Gauss sub-steps to the
// step's end, stopping at contacts the Verlet prediction missed
void HSMethodMCVA::finish_step(double tleft)
{
  if (!gauss_step) {
    HSMethod::finish_step(tleft);
    return;
  }
  cancel = 0;
  for (int guard = 0;; guard++) {
    gauss_substep(tleft);
    comm->forward_comm();
    double T = tleft;
    Event ev;
    int rank = 0;
    const bool missed = earliest_crossing(T, ev, rank);
    count_crossings();
    if (!missed) break;
    if (guard > 1000)
      error->all(FLERR, "Fix {}: too many contacts missed by the prediction on step {}",
                 S.style_name, update->ntimestep);
    // at the missed contact: forces there, ghosts' v, the impulse
    S.pot->evaluate(0);
    S.comm_vel_acc();
    collide_missed(ev, rank);
    tleft -= T;
  }
  gauss_step = 0;
  S.dtf_last = 0.0;    // the sub-step is complete: final_integrate adds nothing
  // LAMMPS computes the forces at the step's end itself
}

// refine the contact time predicted by Verlet (tau) on the Gauss flow of H~
bool HSMethodMCVA::advance_to_contact(double &tau, double tleft, const Impulse &imp)
{
  cancel = 0;
  gauss_substeps += 1.0;
  if (tau == 0.0) return true;    // touching and approaching now: no sub-step

  save_start();
  double T;
  const int found = solve_contact(imp, tau, tleft, T);
  // a contact the prediction missed may come first on the Gauss flow
  Event ev;
  int rank;
  const bool missed = earliest_crossing(T, ev, rank);
  count_crossings();
  if (missed) {
    // stop there and drop the predicted contact: the next prediction finds
    // the earlier one touching and approaching (CONTACT_NOW) and collides it
    tau = T;
    cancel = 1;
    nmissed += 1.0;
  } else if (!found) {
    // the Gauss flow has no contact in the rest of the step: that was its
    // last sub-step
    gauss_step = 0;
    S.dtf_last = 0.0;
      return false;
  } else
    tau = T;
  S.pot->evaluate(0);    // forces at the contact: the next prediction needs them
  S.comm_vel_acc();      // ghosts' velocities at contact, for the impulse
  return true;
}

/* ----------------------------------------------------------------------
   the modified collision operator R_alpha-hat of section 3.1: p -> p +
   alpha-hat u with u the contact normal in configuration space (q_i - q_j
   on i, -(q_i - q_j) on j; the wall normal on one atom) and
   alpha-hat = -2 u^T A p / u^T A u, A = M^-1 + dt^2/6 M^-1 V'' M^-1,
   the matrix of H~'s quadratic form in p. With w = M^-1 u:
   u^T A p = u.v + dt^2/6 w^T V'' v,  u^T A u = u.w + dt^2/6 w^T V'' w.
   Collective; imp.J (momentum added to i, -J to j) replaces the elastic one.
------------------------------------------------------------------------- */

void HSMethodMCVA::modify_impulse(Impulse &imp)
{
  if (cancel) {    // the sub-step stopped at an earlier contact instead
    imp.apply = 0;
    cancel = 0;
    return;
  }
  grow_fields();
  const double ftm2v = force->ftm2v;
  const double dt = update->dt;
  double **v = atom->v;
  const int nlocal = atom->nlocal;
  for (int i = 0; i < nlocal; i++)
    for (int d = 0; d < 3; d++) fv[i][d] = 0.0;

  // u on the owned copies of the contact's atoms; w = M^-1 u in fv
  double u_i[3] = {0.0, 0.0, 0.0};
  const int dim = (imp.type == WALL_EVENT) ? S.walls[imp.wall].dim : -1;
  if (imp.type == PAIR_EVENT)
    for (int d = 0; d < 3; d++) u_i[d] = imp.dq[d];
  else
    u_i[dim] = imp.dq[dim];

  double loc[2] = {0.0, 0.0};    // u.v, u.w
  auto put = [&](tagint t, double sgn) {
    const int k = owned_index(atom, t);
    if (k < 0) return;
    const double im = ftm2v / S.mass_of(k);
    for (int d = 0; d < 3; d++) {
      const double u = sgn * u_i[d];
      fv[k][d] = im * u;
      loc[0] += u * v[k][d];
      loc[1] += u * fv[k][d];
    }
  };
  put(imp.itag, 1.0);
  if (imp.type == PAIR_EVENT) put(imp.jtag, -1.0);

  S.pot->hess_vec(fv, fhv);    // V'' w
  const int *mask = atom->mask;
  double sums[4] = {loc[0], loc[1], 0.0, 0.0};
  for (int i = 0; i < nlocal; i++)
    if (mask[i] & S.groupbit)
      for (int d = 0; d < 3; d++) {
        sums[2] += fhv[i][d] * v[i][d];     // w^T V'' v
        sums[3] += fhv[i][d] * fv[i][d];    // w^T V'' w
      }
  MPI_Allreduce(MPI_IN_PLACE, sums, 4, MPI_DOUBLE, MPI_SUM, world);

  // touching, approaching by the plain velocity (the prediction's test)
  // but separating on the Gauss flow of H~ (u^T A p = u.v + dt^2/6 w^T V''v
  // >= 0): no impulse, or alpha-hat would reverse it to approaching and the
  // next zero-length sub-step back again, without end
  if (sums[0] + dt * dt / 6.0 * sums[2] >= 0.0) {
    imp.apply = 0;
    S.release_contact(imp);
    nreleased += 1.0;
    return;
  }

  double alpha = 0.0;
  if (!HardSphere::modified_alpha(sums[0], sums[1], sums[2], sums[3], dt * dt / 6.0, alpha))
    error->all(FLERR,
               "Fix {}: on step {} the modified Hamiltonian is not convex in the momenta along "
               "the contact normal of atoms {} and {} (u^T A u = {} <= 0): the timestep {} is "
               "too large for the curvature of the potential",
               S.style_name, update->ntimestep, imp.itag, imp.jtag, sums[1] + dt * dt / 6.0 * sums[3],
               dt);

  // v_i += alpha w_i = alpha ftm2v u_i / m_i, i.e. J = alpha ftm2v u_i
  for (int d = 0; d < 3; d++) imp.J[d] = alpha * ftm2v * u_i[d];
  imp.reflect = 0;
}

/* ----------------------------------------------------------------------
   output entries after the fix's 5: total Gauss stage iterations, Gauss
   sub-steps, the most iterations in one solve, Gauss solves, contacts the
   Verlet prediction missed (found on the Gauss flow)
------------------------------------------------------------------------- */

double HSMethodMCVA::vector(int k)
{
  switch (k) {
    case 0:
      return gauss_iters;
    case 1:
      return gauss_substeps;
    case 2:
      return gauss_maxit;
    case 3:
      return gauss_solves;
    case 4:
      return nmissed;
    case 5:
      return nreleased;
    case 6:
      return ncross;
    case 7:
      return nlin;
  }
  return 0.0;
}

double HSMethodMCVA::memory_usage()
{
  return (double) nmax_f * 15 * sizeof(double) +
      (double) (y0.capacity() * 9 + work.capacity()) * sizeof(double);
}

// the counters after the fix's in restart files
std::vector<double *> HSMethodMCVA::counters()
{
  // entries 12 and 13 (ncross, nlin) are not stored: restart files keep the
  // layout of the fix before them (the fix reads as many as it expects)
  return {&gauss_iters, &gauss_substeps, &gauss_maxit, &gauss_solves, &nmissed, &nreleased};
}

/* ----------------------------------------------------------------------
   local form (substep local, issue 21; doc "Local form"): each cluster's
   flow is the Gauss flow of the cluster's modified Hamiltonian H~_1 (its
   members move; partners and other atoms are static), contact to contact
   with alpha-hat impulses (hs_cluster_flow.h); after the step the colliding
   spheres' velocities are projected so that the whole system's H~ keeps
   its value to fourth order (pcva's ledger, hs_local_modified.h)
------------------------------------------------------------------------- */

namespace {
// a cluster term's radial function: its atoms (local indices), special
// bits or bond type; lj: lj/cut's coefficients of its type pair
// (HSPotential::lj_cut_table(), checked against single() bit for bit) and
// fl its special factor, else nullptr
struct TermOf {
  int i, j, extra;
  bool pair;
  const double *lj;
  double fl;
};
// phi^(k)(r), k = 0..4, of the cluster's term `kind` (an index into its
// TermOf list): lj/cut's inline (the derivative layer's own arithmetic,
// without its call and lookups: 8 % of a collisional step), else LAMMPS'
// styles through the derivative layer
struct TermPhi {
  HSPotential *pot;
  const TermOf *of;
  void operator()(int k, double r, int order, double *d) const
  {
    const TermOf &t = of[k];
    if (t.lj) HardSphere::lj_cut_phi04(t.lj, t.fl, r * r, r, order, d);
    else if (t.pair) pot->pair_term4(t.i, t.j, t.extra, r, order, d);
    else pot->bond_term4(t.extra, t.i, t.j, r * r, order, d);
  }
  // (ClusterGauss' PhiNamesLJ: its lj/cut terms four at a time)
  const double *lj_coef(int k, double &fl) const
  {
    fl = of[k].fl;
    return of[k].lj;
  }
};
}    // namespace

// (the objects of cluster_flow(), reset for each cluster)
struct HSMethodMCVA::FlowKernel {
  std::vector<TermOf> term_of;
  std::vector<double> im, y, pmom;
  HardSphere::FlatMap<tagint, int> pslot;    // a partner's index by its ID
  HardSphere::ClusterGauss<TermPhi> G;
  HardSphere::ClusterFlow<TermPhi> flow{G, {}, {}, {}, 0, 0.0};
};

std::string HSMethodMCVA::local_limits()
{
  std::string why;
  auto add = [&why](const std::string &s) { why += (why.empty() ? "" : "; ") + s; };
  const std::string pair = S.pot->unsingled_pair();
  if (!pair.empty())
    add(fmt::format("{} (a pair style without single(): the local Gauss flow needs each of the "
                    "colliding spheres' pair terms and their derivatives)",
                    pair));
  for (const char *kind : {"angle", "dihedral", "improper"}) {
    const bool on = (kind[0] == 'a' && force->angle) || (kind[0] == 'd' && force->dihedral) ||
        (kind[0] == 'i' && force->improper);
    if (on) add(fmt::format("{} styles (the local Gauss flow takes radial terms only)", kind));
  }
  if (force->bond && !S.pot->bond_by_single())
    add(fmt::format("bond style {} (no single(): the local Gauss flow needs each bond's "
                    "derivatives)",
                    force->bond_style));
  if (!newton)
    add("fix_modify stages fixed (the local Gauss flow solves each cluster's stage equations "
        "by Newton only)");
  // the projection's needs (pcva's)
  const std::string proj = projection_limits(held_work);
  if (!proj.empty()) add(proj);
  return why;
}

void HSMethodMCVA::cluster_flow(HSClusterFlowJob &job)
{
  double **x = atom->x, **v = atom->v;
  const int nm = (int) job.members.size();
  const double ftm2v = force->ftm2v, dt = update->dt;
  const std::vector<int> &tl = *job.tloc, &to = *job.toff, &te = *job.textra;
  const int nterm = (int) to.size() - 1;
  double **cutsq = force->pair ? force->pair->cutsq : nullptr;
  const int *type = atom->type;
  if (!fk) fk.reset(new FlowKernel);
  HardSphere::ClusterGauss<TermPhi> &G = fk->G;
  HardSphere::ClusterFlow<TermPhi> &flow = fk->flow;
  std::vector<double> &im = fk->im, &rad = flow.radii();
  im.resize(nm);
  rad.resize(nm);
  for (int k = 0; k < nm; k++) {
    im[k] = ftm2v / S.mass_of(job.members[k]);
    rad[k] = S.radius_of(job.members[k]);
  }
  // a copy's member slot, by atom ID (a term or a contact may hold another
  // image of a member than its copy in job.members: periodic images)
  const tagint *tag = atom->tag;
  auto slot = [&](int c) {
    for (int k = 0; k < nm; k++)
      if (tag[job.members[k]] == tag[c]) return k;
    return -1;
  };
  // (by ID too: the engine's partners are the copies its sums fold the
  // terms' images into; a map, as a fluid's cluster has ~70 partners and a
  // search per term was a quarter of this function)
  HardSphere::FlatMap<tagint, int> &pslot = fk->pslot;
  pslot.clear();
  for (size_t p = 0; p < job.partners.size(); p++) pslot.insert(tag[job.partners[p]], (int) p);
  auto partner = [&](int c) {
    const int *p = pslot.find(tag[c]);
    return p ? *p : -1;
  };
  // the terms inside their cutoff at the flow's start, continued past it
  // through the flow (the frozen set of the global form, section
  // "Pair styles cut off without smoothing")
  std::vector<HardSphere::ClusterTerm> &terms = G.terms();
  std::vector<TermOf> &term_of = fk->term_of;
  terms.clear();
  term_of.clear();
  terms.reserve(nterm);
  term_of.reserve(nterm);
  // (lj_cut_table() also checks that epsilon and sigma still hold, as
  // begin_terms())
  const HardSphere::LJCutTable ljt = S.pot->lj_cut_table();
  for (int t = 0; t < nterm; t++) {
    if (to[t + 1] - to[t] != 2)
      error->one(FLERR, "Fix {} substep local: internal error: a term of {} atoms in a cluster",
                 S.style_name, to[t + 1] - to[t]);
    const int i = tl[to[t]], j = tl[to[t] + 1];
    if (t >= job.npair && te[t] <= 0) continue;    // a broken bond
    if (t < job.npair) {
      double rsq = 0.0;
      for (int d = 0; d < 3; d++) rsq += (x[i][d] - x[j][d]) * (x[i][d] - x[j][d]);
      if (rsq >= cutsq[type[i]][type[j]]) continue;
    }
    int si = slot(i), sj = slot(j), ci = i, cj = j;
    if (si < 0 && sj < 0) continue;
    // (both records written in place: built on the stack by parts and
    // copied whole, each copy waited on its parts' stores, a fifth of this
    // function's time)
    HardSphere::ClusterTerm &ct = terms.emplace_back();
    ct.kind = (int) term_of.size();
    {
      TermOf &of = term_of.emplace_back();
      of.i = i;
      of.j = j;
      of.extra = te[t];
      of.pair = t < job.npair;
      of.lj = nullptr;
      of.fl = 0.0;
      if (of.pair && ljt.coef) {
        of.lj = ljt.of(type[i], type[j]);
        of.fl = force->special_lj[te[t]];
      }
    }
    if (si < 0) {    // the member first (phi depends on |r| only)
      std::swap(si, sj);
      std::swap(ci, cj);
    }
    ct.a = si;
    ct.b = sj;
    // the copies' shifts from the members' copies in job.members
    double offi[3], offj[3] = {0.0, 0.0, 0.0};
    for (int d = 0; d < 3; d++) offi[d] = x[ci][d] - x[job.members[si]][d];
    if (sj >= 0) {
      for (int d = 0; d < 3; d++) {
        offj[d] = x[cj][d] - x[job.members[sj]][d];
        ct.off[d] = offi[d] - offj[d];
      }
    } else {
      for (int d = 0; d < 3; d++) ct.xb[d] = x[cj][d] - offi[d];
      ct.partner = partner(cj);
    }
  }
  G.reset(nm, im.data(), job.fc.data(), dt * dt / 12.0, TermPhi{S.pot, term_of.data()});
  std::vector<HardSphere::FlowStatic> &statics = flow.statics();
  statics.resize(job.statics.size());
  for (size_t s = 0; s < job.statics.size(); s++) {
    for (int d = 0; d < 3; d++) statics[s].x[d] = x[job.statics[s]][d];
    statics[s].radius = S.radius_of(job.statics[s]);
  }
  std::vector<HardSphere::FlowWall> &walls = flow.walls();
  walls.resize(S.walls.size());
  for (size_t w = 0; w < S.walls.size(); w++) {
    walls[w].dim = S.walls[w].dim;
    walls[w].coord = S.walls[w].coord;
    walls[w].sign = S.walls[w].side < 0 ? 1.0 : -1.0;
  }
  flow.reset((int) job.partners.size(), TOUCH_TOL);
  flow.max_stuck = MAX_STUCK;
  // the members' nearest images of each other at the flow's start
  for (int a = 0; a < nm; a++)
    for (int b = a + 1; b < nm; b++) {
      double d[3], dm[3], off[3];
      for (int dd = 0; dd < 3; dd++) d[dd] = dm[dd] = x[job.members[a]][dd] - x[job.members[b]][dd];
      domain->minimum_image(dm);
      for (int dd = 0; dd < 3; dd++) off[dd] = dm[dd] - d[dd];
      flow.set_pair_offset(a, b, off);
    }
  std::vector<double> &y = fk->y, &pmom = fk->pmom;
  y.resize(6 * nm);
  pmom.clear();
  for (int k = 0; k < nm; k++)
    for (int d = 0; d < 3; d++) {
      y[3 * k + d] = x[job.members[k]][d];
      y[3 * nm + 3 * k + d] = v[job.members[k]][d];
    }
  const auto end = flow.run(job.h, y, pmom);
  // the flow's counts (entries 1-4: Newton iterations, sub-steps, most
  // iterations of a solve, solves)
  flow_counts[0] += G.tally.iterations;
  flow_counts[1] += flow.stats.substeps;
  flow_counts[2] = MAX(flow_counts[2], G.tally.maxit);
  flow_counts[3] += G.tally.solves;
  using Flow = HardSphere::ClusterFlow<TermPhi>;
  if (end == Flow::STATIC_HIT) {
    job.result = HSClusterFlowJob::GROWS;
    job.hit_member = job.members[flow.hit_member];
    job.hit_static = job.statics[flow.hit_static];
    return;
  }
  if (end == Flow::FAILED)
    error->one(FLERR,
               "Fix {} substep local: on step {} the Gauss stage equations of the cluster of "
               "atom {} did not converge (or its contacts do not end): the timestep {} is too "
               "large for the curvature of the potential",
               S.style_name, update->ntimestep, tag[job.members[0]], dt);
  // the flow's contact (two members, or a member and wall -1 - hit_static)
  // for the errors
  auto contact = [&]() {
    Impulse imp{};
    imp.itag = tag[job.members[flow.hit_member]];
    if (flow.hit_static >= 0) {
      imp.type = PAIR_EVENT;
      imp.jtag = tag[job.members[flow.hit_static]];
    } else {
      imp.type = WALL_EVENT;
      imp.wall = -1 - flow.hit_static;
    }
    return imp;
  };
  if (end == Flow::NONCONVEX)
    error->one(FLERR,
               "Fix {} substep local: on step {} the modified Hamiltonian is not convex in the "
               "momenta along the contact normal of {}: the timestep {} is too large for the "
               "curvature of the potential",
               S.style_name, update->ntimestep, S.contact_name(contact()), dt);
  if (end == Flow::RESTING) S.resting_contact_error(contact(), false);
  if (end == Flow::OVERLAP)
    error->one(FLERR,
               "Fix {} substep local: on step {} a sphere of the cluster of atom {} overlaps "
               "another or a wall: a collision was missed",
               S.style_name, update->ntimestep, tag[job.members[0]]);
  job.result = HSClusterFlowJob::DONE;
  job.xend.assign(y.begin(), y.begin() + 3 * nm);
  job.vend.assign(y.begin() + 3 * nm, y.end());
  job.dvp.resize(3 * job.partners.size());
  for (size_t p = 0; p < job.partners.size(); p++) {
    const double s = ftm2v / S.mass_of(job.partners[p]);
    for (int d = 0; d < 3; d++) job.dvp[3 * p + d] = s * pmom[3 * p + d];
  }
  job.segs.assign(nm, {});
  for (int k = 0; k < nm; k++)
    for (const HardSphere::FlowSeg &fs : flow.segments()[k]) {
      HSClusterFlowJob::Seg js;
      js.t0 = fs.t0;
      js.t1 = fs.t1;
      for (int d = 0; d < 3; d++) {
        js.q[d] = fs.q[d];
        js.v[d] = fs.v[d];
        js.a[d] = fs.a[d];
      }
      job.segs[k].push_back(js);
    }
  job.kicks.clear();
  for (const HardSphere::FlowKick &fk : flow.kicks()) {
    HSClusterFlowJob::Kick kk;
    kk.i = job.members[fk.i];
    kk.j = fk.j >= 0 ? job.members[fk.j] : fk.j;
    // v += J / m: J = m im alpha u = ftm2v alpha u
    for (int d = 0; d < 3; d++) {
      kk.J[d] = ftm2v * fk.J[d];
      kk.dq[d] = fk.dq[d];
    }
    job.kicks.push_back(kk);
  }
}

void HSMethodMCVA::take_flow_counts(std::vector<double> &out)
{
  out.assign(flow_counts, flow_counts + 4);
  for (double &c : flow_counts) c = 0.0;
}

void HSMethodMCVA::add_flow_counts(const std::vector<double> &c)
{
  for (int k : {0, 1, 3}) rank_counts[k] += c[k];
  rank_counts[2] = MAX(rank_counts[2], c[2]);
}

void HSMethodMCVA::cluster_step_begun(HSStepView &view)
{
  if (!lmod) lmod = new HSLocalModified(lmp, &S, S.pot);
  lmod->set_held_work(!held_work.empty());
  lmod->begin(view);
  count0 = S.atoms_count;
  idsum0 = S.atoms_idsum;
}

void HSMethodMCVA::cluster_step_done(HSStepView &view)
{
  double sum[3], mx;
  const double mine[3] = {rank_counts[0], rank_counts[1], rank_counts[3]};
  MPI_Allreduce(mine, sum, 3, MPI_DOUBLE, MPI_SUM, world);
  MPI_Allreduce(&rank_counts[2], &mx, 1, MPI_DOUBLE, MPI_MAX, world);
  gauss_iters += sum[0];
  gauss_substeps += sum[1];
  gauss_solves += sum[2];
  gauss_maxit = MAX(gauss_maxit, mx);
  for (double &c : rank_counts) c = 0.0;
  // atoms created or deleted within the step: H~ is another system's
  if (S.atoms_count != count0 || S.atoms_idsum != idsum0) {
    nskip += 1.0;
    return;
  }
  double A, B, C0, beta;
  lmod->end(view, A, B, C0);
  const HardSphere::ScaleStatus st = HardSphere::pcva_local_beta(A, B, C0, beta);
  if (st != HardSphere::SCALE_OK) {
    nskip += 1.0;
    return;
  }
  lmod->scale(view, beta);
  nproj += 1.0;
}
