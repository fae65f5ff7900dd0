/* ----------------------------------------------------------------------
   HARDSPHERE package: the global step engine. See hs_global_engine.h.
------------------------------------------------------------------------- */

#include "hs_global_engine.h"

#include "hs_method.h"
#include "hs_system.h"

#include "atom.h"
#include "comm.h"
#include "update.h"

#include <cstring>
#include <mpi.h>

using namespace LAMMPS_NS;

HSGlobalEngine::HSGlobalEngine(LAMMPS *lmp, HSSystem &sys, HSMethod &method) :
    HSStepEngine(lmp), S(sys), M(method)
{
}

/* ----------------------------------------------------------------------
   one step of the collision Verlet algorithm (section 2.2) with the
   method's pieces (hs_method.h): while time is left, sub-step to the
   earliest contact, apply the impulse there, repeat. The method's hooks
   are called on every rank together, with the contact's tags known.
------------------------------------------------------------------------- */

bool HSGlobalEngine::step()
{
  double tleft = S.dtv;
  // the sub-steps evaluate forces of all atoms: keep those of atoms that
  // another integrator moves
  save_other_forces();
  if (S.nheld) {
    begin_held_split();    // K_held(dt/2); atom->f is conservative from here
    S.screen(tleft);         // velocities changed: which spheres may touch
  }

  int stuck = 0;
  bigint nsub = 0;
  bool contact_seen = false;

  while (true) {
    S.comm_vel_acc();    // ghosts' v, a and active flags for the prediction
    Event ev{PAIR_EVENT, -1, -1, -1};
    struct {
      double t;
      int rank;
    } mine{S.predict(tleft, ev), comm->me}, first;
    MPI_Allreduce(&mine, &first, 1, MPI_DOUBLE_INT, MPI_MINLOC, world);

    if (first.t >= tleft) {    // no contact in the rest of the step
      M.finish_step(tleft);      // hook
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
      M.begin_collisional_step();    // hook: state at the step's start
      contact_seen = true;
    }

    double tau = first.t;
    if (!M.advance_to_contact(tau, tleft, imp)) break;    // hook: the step ended without it
    if (tau > 0.0) S.released.type = -1;    // the sub-step moved the released pair apart

    // the rank that found the contact builds the impulse from the state at
    // contact and sends it to all; each applies it to its copies of the atoms

    if (comm->me == first.rank) {
      if (imp.type == PAIR_EVENT) M.collide_pair(ev.i, ev.j, imp);
      else M.collide_wall(ev.i, S.walls[ev.wall], imp);
    }
    MPI_Bcast(&imp, sizeof(Impulse), MPI_BYTE, first.rank, world);
    if (imp.apply) M.modify_impulse(imp);    // hook: another collision operator
    if (imp.apply && comm->me == first.rank) S.add_impulse_virial(imp);
    S.apply_impulse(imp);
    if (imp.apply) {
      if (imp.type == PAIR_EVENT) S.ncoll_pair += 1.0;
      else S.ncoll_wall += 1.0;
      S.step_collided = 1;
    } else if (tau == 0.0 && ++stuck > MAX_STUCK) {
      S.resting_contact_error(imp, true);
    }
    if (tau > 0.0) stuck = 0;
    M.end_substep(tau);    // hook: after each collisional sub-step

    tleft -= tau;
    S.screen(tleft);
    S.check_runaway(++nsub, true);
  }
  if (S.step_collided) S.ncoll_steps += 1.0;
  if (contact_seen && S.fallback_counting) S.nfallback += 1.0;
  S.step_substeps = contact_seen;
  restore_other_forces();
  S.request_rebuild();
  return true;
}


/* ----------------------------------------------------------------------
   final_integrate of a step this engine sub-stepped
------------------------------------------------------------------------- */

bool HSGlobalEngine::finish()
{
  if (S.step_split) {    // closing half kicks of a split step (doc: the rule)
    end_held_split();
    return true;
  }
  if (!S.step_substeps) return false;
  // a method may change v after the kick: the next step screens afresh
  S.kick_dtf(S.dtf_last);
  M.end_collisional_step();
  S.screened_step = -1;
  return true;
}

// every force in LAMMPS' f but the held ones is in the evaluation the copy
// replaces (HSPotential::evaluate(): the styles, kspace, the conservative fixes)
bool HSGlobalEngine::takes_captured_forces() const
{
  return S.nheld != 0;
}

// only the count of steps that fell back to this engine from the local one
double HSGlobalEngine::counter(int k)
{
  return (k == 4) ? S.nfallback : 0.0;
}

/* ----------------------------------------------------------------------
   held (thermostat) forces, doc "Fixes beside the integrator": a step with
   collisions is K_held(dt/2) . Phi(dt) . K_held(dt/2), Phi the method's
   map with conservative forces only. Held forces f_h are LAMMPS' own,
   evaluated once per step at its end as beside fix nve: each random force
   acts for dt in all, and the drag sees the velocities fix nve's would.
   A step without collisions stays fix nve's step with f = f_c + f_h.
------------------------------------------------------------------------- */

void HSGlobalEngine::begin_held_split()
{
  if (S.held_step == update->ntimestep) {
    // split at these positions at the end of the last step
    double **f = atom->f;
    for (int i = 0; i < atom->nlocal; i++)
      for (int k = 0; k < 3; k++) f[i][k] = S.fcons[i][k];
  } else
    S.split_held_forces(true);
  S.kick_dtf(S.dtf, S.fheld);    // K_held(dt/2)
  S.step_split = 1;
}

void HSGlobalEngine::end_held_split()
{
  S.split_held_forces(false);    // at the step's end
  S.kick_dtf(S.dtf_last);     // the method's closing kick, conservative forces
  if (S.step_substeps) M.end_collisional_step();
  S.kick_dtf(S.dtf, S.fheld);    // K_held(dt/2)
  // LAMMPS' forces again, for output and the next step
  double **f = atom->f;
  for (int i = 0; i < atom->nlocal; i++)
    for (int k = 0; k < 3; k++) f[i][k] = S.ftot[i][k];
  S.held_step = update->ntimestep + 1;
  S.step_split = 0;
  S.screened_step = -1;
}

// forces of owned atoms outside the group, while another fix integrates
// some: the sub-step evaluations overwrite them
void HSGlobalEngine::save_other_forces()
{
  fother.clear();
  if (!S.other_integrator) return;
  double **f = atom->f;
  const int *mask = atom->mask;
  for (int i = 0; i < atom->nlocal; i++)
    if (!(mask[i] & S.groupbit)) fother.insert(fother.end(), f[i], f[i] + 3);
}

void HSGlobalEngine::restore_other_forces()
{
  if (!S.other_integrator) return;
  double **f = atom->f;
  const int *mask = atom->mask;
  size_t m = 0;
  for (int i = 0; i < atom->nlocal; i++)
    if (!(mask[i] & S.groupbit))
      for (int k = 0; k < 3; k++) f[i][k] = fother[m++];
}
