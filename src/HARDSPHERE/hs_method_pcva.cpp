/* ----------------------------------------------------------------------
   HARDSPHERE package: the method of fix hardsphere/pcva (Bond & Leimkuhler
   2007, section 3.2). See hs_method_pcva.h and doc/fix_hardsphere_pcva.rst.
------------------------------------------------------------------------- */

#include "hs_method_pcva.h"

#include "hs_local_modified.h"
#include "hs_potential.h"
#include "hs_projection.h"
#include "hs_system.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "fix.h"
#include "group.h"
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

HSMethodPCVA::HSMethodPCVA(LAMMPS *lmp, HSSystem &sys) : HSMethod(lmp, sys) {}

HSMethodPCVA::~HSMethodPCVA()
{
  delete lmod;
}

/* ----------------------------------------------------------------------
   the projection keeps H_[2,VV] of the whole system (V: every term, of
   atoms inside and outside the group) by scaling the group's momenta
   (section 3.2): atoms that another fix moves change it in ways no scaling
   of the group's momenta undoes, so the scaling pumps their changes into
   the group (hard colloids beside a solvent under fix nve, substep global:
   +31 % total energy in 300 steps, where cva drifts by 0.3 %)
------------------------------------------------------------------------- */

void HSMethodPCVA::init()
{
  S.track_atoms = true;
  require_fix_energies("H_[2,VV] through collisional steps");
  // (the fix's init() found it: FixHardSphere::check_other_integrators())
  if (Fix *other = S.other_integrator)
    error->all(FLERR,
               "Fix {}: fix {} {} time-integrates atoms outside group {}: the projection "
               "keeps H_[2,VV] of a closed system, which their motion changes (it would feed "
               "their energy changes into the group); use hardsphere/cva, mcva or vci, or one "
               "hardsphere/pcva for every moving atom",
               S.style_name, other->id, other->style, group->names[S.host->igroup]);
}

/* ----------------------------------------------------------------------
   H_[2,VV] = K~ + U at the current state (section 3; hs_projection.h),
   with grad V = -f (valid: forces are current whenever this is called),
   V and v^T V'' v from the derivative layer. LAMMPS units:
   1/2 p M^-1 p = 1/2 m v^2 mvv2e, grad V M^-1 grad V = f^2 ftm2v / m
   (times dt^2: energy), v^T V'' v in energy / time^2. Collective.
------------------------------------------------------------------------- */

double HSMethodPCVA::modified_energy(double &U, double &Kt)
{
  double **v = atom->v;
  double **f = atom->f;
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  double loc[2] = {0.0, 0.0}, all[2];
  for (int i = 0; i < nlocal; i++)
    if (mask[i] & S.groupbit) {
      const double m = S.mass_of(i);
      loc[0] += m * (v[i][0] * v[i][0] + v[i][1] * v[i][1] + v[i][2] * v[i][2]);
      loc[1] += (f[i][0] * f[i][0] + f[i][1] * f[i][1] + f[i][2] * f[i][2]) / m;
    }
  MPI_Allreduce(loc, all, 2, MPI_DOUBLE, MPI_SUM, world);

  HardSphere::ModifiedEnergyParts e;
  e.kin = 0.5 * force->mvv2e * all[0];
  e.g2 = force->ftm2v * all[1];
  e.pot = S.pot->energy();
  e.vhv = S.pot->d2(v);

  U = HardSphere::modified_potential(e, S.dtv);
  Kt = HardSphere::modified_kinetic(e, S.dtv);
  return Kt + U;
}

/* ----------------------------------------------------------------------
   the projection of section 3.2: p -> alpha p with H_[2,VV](q, alpha p)
   = H_[2,VV] before the sub-step, which every earlier projection of the
   step has kept at its value at the step's start (Ht0)
------------------------------------------------------------------------- */

void HSMethodPCVA::project_momenta(const char *where)
{
  double U, Kt;
  modified_energy(U, Kt);
  double alpha;
  const HardSphere::ScaleStatus st = HardSphere::pcva_scale(Ht0, U, Kt, alpha);
  if (st != HardSphere::SCALE_OK) {
    skipped(fmt::format("{} ({}: target {}, U {}, K~ {})", where,
                        st == HardSphere::SCALE_NO_ROOT ? "target - U <= 0 or not a number"
                                                        : "K~ <= 0 or not a number",
                        Ht0, U, Kt));
    return;
  }

  // owned atoms only: ghosts get v with the loop's next comm_vel_acc(), or
  // in the next step's communication
  double **v = atom->v;
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  for (int i = 0; i < nlocal; i++)
    if (mask[i] & S.groupbit) {
      v[i][0] *= alpha;
      v[i][1] *= alpha;
      v[i][2] *= alpha;
    }
  nproj += 1.0;
  maxdev = MAX(maxdev, fabs(alpha - 1.0));
}

// no real scaling: the sub-step (step) is left unprojected, counted in f_ID[7]
void HSMethodPCVA::skipped(const std::string &what)
{
  nskip += 1.0;
  if (!warned && comm->me == 0)
    error->warning(FLERR,
                   "Fix {}: no momentum scaling restores H_[2,VV] {} on step {}; it is left "
                   "unprojected. Such sub-steps are counted in f_{}[7]; this warning is "
                   "printed once",
                   S.style_name, what, update->ntimestep, S.fix_id());
  warned = 1;
}

/* ----------------------------------------------------------------------
   substep local (doc "Local projection"): the set-ups it needs beyond the
   engine's; the projection once per step with clusters
------------------------------------------------------------------------- */

std::string HSMethodPCVA::local_limits()
{
  std::string why;
  auto add = [&why](const std::string &s) { why += (why.empty() ? "" : "; ") + s; };
  // (fix gravity's energy is the engine's: HSStepView::const_force())
  const std::string pair = S.pot->unsingled_pair();
  if (!pair.empty())
    add(fmt::format("{} (a pair style without single(): the local projection needs the "
                    "energy of each of the colliding spheres' pair terms)",
                    pair));
  const std::string proj = projection_limits(held_work);
  if (!proj.empty()) add(proj);
  return why;
}

void HSMethodPCVA::cluster_step_begun(HSStepView &view)
{
  if (!lmod) lmod = new HSLocalModified(lmp, &S, S.pot);
  lmod->set_held_work(!held_work.empty());
  lmod->begin(view);
  note_atoms();
}

void HSMethodPCVA::cluster_step_done(HSStepView &view)
{
  if (atoms_changed()) return;
  double A, B, C0, beta;
  lmod->end(view, A, B, C0);
  const HardSphere::ScaleStatus st = HardSphere::pcva_local_beta(A, B, C0, beta);
  if (st != HardSphere::SCALE_OK) {
    skipped(fmt::format("at the end of a step with collisions (substep local: change {}, {})", C0,
                        st == HardSphere::SCALE_NO_ROOT
                            ? "more than scaling the colliding spheres' motion can undo"
                            : "K~ <= 0 along the colliding spheres' velocities relative to "
                              "their clusters' centres of mass"));
    return;
  }
  lmod->scale(view, beta);
  nproj += 1.0;
  maxdev = MAX(maxdev, fabs(beta));
}

/* ---------------------------------------------------------------------- */

void HSMethodPCVA::begin_collisional_step()
{
  double U, Kt;
  Ht0 = modified_energy(U, Kt);
  note_atoms();
}

// atoms created or deleted between a step's start and its end (at the
// step's reneighboring, between initial_integrate and final_integrate):
// H_[2,VV] at the end is another system's than at the start, and a
// projection would put the energy of the atoms that came or went into the
// others' momenta (the local form: it cannot even find a deleted member).
// Such a step is left unprojected, counted and warned about as one that
// no scaling restores
void HSMethodPCVA::note_atoms()
{
  count0 = S.atoms_count;
  idsum0 = S.atoms_idsum;
}

bool HSMethodPCVA::atoms_changed()
{
  if (S.atoms_count == count0 && S.atoms_idsum == idsum0) return false;
  skipped(fmt::format("at the end of a step in which atoms were created or deleted ({} atoms "
                      "at its start, {} at its end: fix deposit, pour, evaporate, gcmc, or atoms "
                      "lost under thermo_modify lost ignore); H_[2,VV] then has no start value "
                      "for the system at its end",
                      count0, S.atoms_count));
  return true;
}

void HSMethodPCVA::end_substep(double)
{
  project_momenta("after a collision");
}

void HSMethodPCVA::end_collisional_step()
{
  if (atoms_changed()) return;
  project_momenta("at the end of a step with collisions");
}

/* ---------------------------------------------------------------------- */

// output entries 5-7
double HSMethodPCVA::vector(int k)
{
  switch (k) {
    case 0:
      return nproj;
    case 1:
      return nskip;
    case 2:
      return maxdev;
  }
  return 0.0;
}

/* ---------------------------------------------------------------------- */

// the counters after the fix's in restart files
std::vector<double *> HSMethodPCVA::counters()
{
  return {&nproj, &nskip, &maxdev};
}

// the local projection's columns and lists (HSLocalModified)
double HSMethodPCVA::memory_usage()
{
  return lmod ? lmod->memory_usage() : 0.0;
}
