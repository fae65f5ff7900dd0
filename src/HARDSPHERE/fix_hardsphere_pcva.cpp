/* ----------------------------------------------------------------------
   HARDSPHERE package: fix hardsphere/pcva (Bond & Leimkuhler 2007,
   section 3.2). See fix_hardsphere_pcva.h and doc/fix_hardsphere_pcva.rst.
------------------------------------------------------------------------- */

#include "fix_hardsphere_pcva.h"

#include "hs_potential.h"
#include "hs_projection.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "force.h"
#include "hs_compat.h"
#include "neigh_request.h"
#include "neighbor.h"
#include "update.h"

#include <cmath>
#include <cstring>
#include <mpi.h>

using namespace LAMMPS_NS;


/* ---------------------------------------------------------------------- */

FixHardSpherePCVA::FixHardSpherePCVA(LAMMPS *lmp, int narg, char **arg) :
    FixHardSphere(lmp, narg, arg), Ht0(0.0), nproj(0.0), nskip(0.0), maxdev(0.0),
    warned(0)
{
  size_vector = 8;
  derivs_needed = 1;
}

/* ---------------------------------------------------------------------- */

/* ----------------------------------------------------------------------
   H_[2,VV] = K~ + U at the current state (section 3; hs_projection.h),
   with grad V = -f (valid: forces are current whenever this is called),
   V and v^T V'' v from the derivative layer. LAMMPS units:
   1/2 p M^-1 p = 1/2 m v^2 mvv2e, grad V M^-1 grad V = f^2 ftm2v / m
   (times dt^2: energy), v^T V'' v in energy / time^2. Collective.
------------------------------------------------------------------------- */

double FixHardSpherePCVA::modified_energy(double &U, double &Kt)
{
  double **v = atom->v;
  double **f = atom->f;
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  double loc[2] = {0.0, 0.0}, all[2];
  for (int i = 0; i < nlocal; i++)
    if (mask[i] & groupbit) {
      const double m = mass_of(i);
      loc[0] += m * (v[i][0] * v[i][0] + v[i][1] * v[i][1] + v[i][2] * v[i][2]);
      loc[1] += (f[i][0] * f[i][0] + f[i][1] * f[i][1] + f[i][2] * f[i][2]) / m;
    }
  MPI_Allreduce(loc, all, 2, MPI_DOUBLE, MPI_SUM, world);

  HardSphere::ModifiedEnergyParts e;
  e.kin = 0.5 * force->mvv2e * all[0];
  e.g2 = force->ftm2v * all[1];
  e.pot = pot->energy();
  e.vhv = pot->d2(v);

  U = HardSphere::modified_potential(e, dtv);
  Kt = HardSphere::modified_kinetic(e, dtv);
  return Kt + U;
}

/* ----------------------------------------------------------------------
   the projection of section 3.2: p -> alpha p with H_[2,VV](q, alpha p)
   = H_[2,VV] before the sub-step, which every earlier projection of the
   step has kept at its value at the step's start (Ht0)
------------------------------------------------------------------------- */

void FixHardSpherePCVA::project(const char *where)
{
  double U, Kt;
  modified_energy(U, Kt);
  double alpha;
  const HardSphere::ScaleStatus st = HardSphere::pcva_scale(Ht0, U, Kt, alpha);
  if (st != HardSphere::SCALE_OK) {
    // no real alpha > 0: leave this sub-step unprojected (counted, f_ID[7])
    nskip += 1.0;
    if (!warned && comm->me == 0)
      error->warning(FLERR,
                     "Fix {}: no momentum scaling restores H_[2,VV] {} on step {} ({}: "
                     "target {}, U {}, K~ {}); the sub-step is left unprojected. Such "
                     "sub-steps are counted in f_{}[7]; this warning is printed once",
                     style_name, where, update->ntimestep,
                     st == HardSphere::SCALE_NO_ROOT ? "target - U <= 0 or not a number"
                                                     : "K~ <= 0 or not a number",
                     Ht0, U, Kt,
                     id);
    warned = 1;
    return;
  }

  // owned atoms only: ghosts get v with the loop's next comm_vel_acc(), or
  // in the next step's communication
  double **v = atom->v;
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  for (int i = 0; i < nlocal; i++)
    if (mask[i] & groupbit) {
      v[i][0] *= alpha;
      v[i][1] *= alpha;
      v[i][2] *= alpha;
    }
  nproj += 1.0;
  maxdev = MAX(maxdev, fabs(alpha - 1.0));
}

/* ---------------------------------------------------------------------- */

void FixHardSpherePCVA::begin_collisional_step()
{
  double U, Kt;
  Ht0 = modified_energy(U, Kt);
}

void FixHardSpherePCVA::end_substep(double)
{
  project("after a collision");
}

void FixHardSpherePCVA::end_collisional_step()
{
  project("at the end of a step with collisions");
}

/* ---------------------------------------------------------------------- */

double FixHardSpherePCVA::compute_vector(int n)
{
  switch (n) {
    case 5:
      return nproj;
    case 6:
      return nskip;
    case 7:
      return maxdev;
  }
  return FixHardSphere::compute_vector(n);
}

/* ---------------------------------------------------------------------- */

// the counters after the base's in restart files
std::vector<double *> FixHardSpherePCVA::extra_counters()
{
  return {&nproj, &nskip, &maxdev};
}
