/* ----------------------------------------------------------------------
   HARDSPHERE package: compute hamiltonian/modified.
   See compute_hamiltonian_modified.h and doc/compute_hamiltonian_modified.rst.
------------------------------------------------------------------------- */

#include "compute_hamiltonian_modified.h"

#include "hs_potential.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "fix.h"
#include "force.h"
#include "group.h"
#include "memory.h"
#include "modify.h"
#include "update.h"

#include <cmath>
#include <cstring>
#include <limits>
#include <mpi.h>

using namespace LAMMPS_NS;

// H2 (H4) is NaN when the FDIFF error estimate of V''v (V'''[v,v], V'''') exceeds this
static constexpr double FD_TOL = 1.0e-3;

/* ---------------------------------------------------------------------- */

ComputeHamiltonianModified::ComputeHamiltonianModified(LAMMPS *lmp, int narg, char **arg) :
    Compute(lmp, narg, arg), pot(nullptr), mode(HSPotential::AUTO), h2_(0.0), h4_(0.0),
    nmax(0), g(nullptr), hv(nullptr), tv(nullptr), logged(0)
{
  scalar_flag = 1;
  vector_flag = 1;
  size_vector = 5;
  extscalar = 1;    // energies, normalized like compute pe by thermo_modify norm
  extvector = 1;
  peflag = 1;       // LAMMPS tallies the energy on the steps we are invoked
  timeflag = 1;
  vector = vec;
  for (double &x : vec) x = 0.0;

  int iarg = 3;
  while (iarg < narg) {
    if (strcmp(arg[iarg], "path") == 0) {
      if (iarg + 2 > narg)
        error->all(FLERR, "Illegal compute hamiltonian/modified command: path needs a value");
      if (strcmp(arg[iarg + 1], "auto") == 0)
        mode = HSPotential::AUTO;
      else if (strcmp(arg[iarg + 1], "single") == 0)
        mode = HSPotential::SINGLE;
      else if (strcmp(arg[iarg + 1], "fdiff") == 0)
        mode = HSPotential::FDIFF;
      else
        error->all(FLERR, "Compute hamiltonian/modified path must be auto, single or fdiff, got {}",
                   arg[iarg + 1]);
      iarg += 2;
    } else
      error->all(FLERR, "Unknown compute hamiltonian/modified keyword: {}", arg[iarg]);
  }

  pot = new HSPotential(lmp, groupbit, "compute hamiltonian/modified");
}

ComputeHamiltonianModified::~ComputeHamiltonianModified()
{
  delete pot;
  memory->destroy(g);
  memory->destroy(hv);
  memory->destroy(tv);
  memory->destroy(fc);
}

/* ---------------------------------------------------------------------- */

void ComputeHamiltonianModified::init()
{
  pot->init((HSPotential::Mode) mode);
  pot->request_list(this, instance_me);
  if (!logged && comm->me == 0)
    utils::logmesg(lmp, "compute {} hamiltonian/modified: {}\n", id, pot->describe());
  logged = 1;
  check_group_integrated();
}

/* ----------------------------------------------------------------------
   H_[2,VV] is the modified Hamiltonian of the integrator's flow: of the
   atoms it moves. An atom of the group that no integrator moves (e.g. the
   anchor of the pendulum chain) still adds its |grad V|^2 term, so the
   sum is conserved only to second order: warn once.
------------------------------------------------------------------------- */

void ComputeHamiltonianModified::check_group_integrated()
{
  if (warned_group) return;
  const int nlocal = atom->nlocal;
  const int *mask = atom->mask;
  int integmask = 0;
  for (int k = 0; k < modify->nfix; k++)
    if (modify->fix[k]->time_integrate) integmask |= modify->fix[k]->groupbit;
  bigint one = 0, all = 0;
  for (int i = 0; i < nlocal; i++)
    if ((mask[i] & groupbit) && !(mask[i] & integmask)) one++;
  MPI_Allreduce(&one, &all, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  if (all > 0 && comm->me == 0)
    error->warning(FLERR,
                   "Compute hamiltonian/modified {}: {} atoms of group {} are moved by no "
                   "time integrator; their force terms make H_[2,VV] and H_[4,VV] conserved "
                   "only to second order. Use the integrator's group",
                   id, all, group->names[igroup]);
  if (all > 0) warned_group = 1;
}

void ComputeHamiltonianModified::init_list(int, NeighList *ptr)
{
  pot->init_list(ptr);
}

/* ---------------------------------------------------------------------- */

double ComputeHamiltonianModified::mass_of(int i) const
{
  return atom->rmass ? atom->rmass[i] : atom->mass[atom->type[i]];
}

// V is read from LAMMPS' tallies (as compute pe does): they hold the
// energy of the current step only if LAMMPS was asked to tally it
void ComputeHamiltonianModified::check_energy_tallied()
{
  if (update->eflag_global != update->ntimestep)
    error->all(FLERR,
               "Compute hamiltonian/modified {}: energy was not tallied on step {} (use it "
               "in thermo output or a fix that invokes it on the steps it is needed)",
               id, update->ntimestep);
}

/* ----------------------------------------------------------------------
   section 3 of the paper, in LAMMPS units: v in velocity units, f in
   force units, M_c = m / ftm2v the mass in energy time^2 / distance^2
   (ftm2v = 1 / mvv2e), g = M_c^-1 grad V = -ftm2v f / m (an acceleration):
     H2 = 2 v.V''v - grad V . M_c^-1 grad V                  (energy/time^2)
     H4 = -V''''[v,v,v,v] - 3 g.V''g + 12 (V''v).M_c^-1 (V''v)
          + 6 V'''[g,v,v]                                    (energy/time^4)
------------------------------------------------------------------------- */

void ComputeHamiltonianModified::eval(int want_h4)
{
  check_energy_tallied();
  if (atom->nmax > nmax) {
    memory->destroy(g);
    memory->destroy(hv);
    memory->destroy(tv);
    memory->destroy(fc);
    nmax = atom->nmax;
    memory->create(fc, nmax, 3, "hamiltonian/modified:fc");
    memory->create(g, nmax, 3, "hamiltonian/modified:g");
    memory->create(hv, nmax, 3, "hamiltonian/modified:hv");
    memory->create(tv, nmax, 3, "hamiltonian/modified:tv");
  }

  double **v = atom->v;
  double **f = atom->f;
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  const double ftm2v = force->ftm2v, mvv2e = force->mvv2e;

  // grad V = -f, unless thermostat forces are in f (doc: the rule)
  if (pot->held_any()) {
    pot->conservative_forces(fc);
    f = fc;
  }

  // hv = V''v (and tv = V'''[v,v,.])
  pot->reset_fd_error();
  pot->hess_third(v, hv, want_h4 ? tv : nullptr);

  // local sums: K, grad V.M^-1 grad V, v.V''v, (V''v).M^-1(V''v), g.V'''[v,v]
  double loc[5] = {0, 0, 0, 0, 0}, all[5];
  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) {
      g[i][0] = g[i][1] = g[i][2] = 0.0;
      continue;
    }
    const double m = mass_of(i);
    for (int k = 0; k < 3; k++) g[i][k] = -ftm2v * f[i][k] / m;
    loc[0] += 0.5 * mvv2e * m * (v[i][0] * v[i][0] + v[i][1] * v[i][1] + v[i][2] * v[i][2]);
    loc[1] += ftm2v * (f[i][0] * f[i][0] + f[i][1] * f[i][1] + f[i][2] * f[i][2]) / m;
    loc[2] += v[i][0] * hv[i][0] + v[i][1] * hv[i][1] + v[i][2] * hv[i][2];
    if (want_h4) {
      loc[3] += ftm2v * (hv[i][0] * hv[i][0] + hv[i][1] * hv[i][1] + hv[i][2] * hv[i][2]) / m;
      loc[4] += g[i][0] * tv[i][0] + g[i][1] * tv[i][1] + g[i][2] * tv[i][2];
    }
  }
  MPI_Allreduce(loc, all, 5, MPI_DOUBLE, MPI_SUM, world);

  const double dt = update->dt;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  h2_ = 2.0 * all[2] - all[1];
  // differences across a discontinuity of the forces are meaningless
  if (pot->fd_error_hess() > FD_TOL) h2_ = nan;
  const double H = all[0] + pot->tallied_energy();
  vec[0] = H;
  vec[3] = dt * dt / 24.0 * h2_;
  vec[1] = H + vec[3];
  if (want_h4) {
    const double gHg = pot->d2(g);
    const double d4 = pot->d4(v);    // NaN if the differences show V not smooth enough
    h4_ = -d4 - 3.0 * gHg + 12.0 * all[3] + 6.0 * all[4];
    if (pot->fd_error_hess() > FD_TOL || pot->fd_error_third() > FD_TOL) h4_ = nan;
    vec[4] = dt * dt * dt * dt / 720.0 * h4_;
    vec[2] = vec[1] + vec[4];
  }
}

/* ---------------------------------------------------------------------- */

double ComputeHamiltonianModified::compute_scalar()
{
  invoked_scalar = update->ntimestep;
  eval(0);
  scalar = vec[1];
  return scalar;
}

void ComputeHamiltonianModified::compute_vector()
{
  invoked_vector = update->ntimestep;
  eval(1);
}

double ComputeHamiltonianModified::memory_usage()
{
  return 4.0 * nmax * 3 * sizeof(double);
}
