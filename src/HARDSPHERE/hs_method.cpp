/* ----------------------------------------------------------------------
   HARDSPHERE package: the collision Verlet algorithm (Bond & Leimkuhler
   2007, section 2.2) as the family's default method. See hs_method.h.
------------------------------------------------------------------------- */

#include "hs_method.h"

#include "hs_contact.h"
#include "hs_potential.h"
#include "hs_system.h"

#include "atom.h"
#include "error.h"
#include "fix.h"
#include "force.h"

using namespace LAMMPS_NS;

HSMethod::HSMethod(LAMMPS *lmp, HSSystem &sys) : Pointers(lmp), S(sys) {}

// (measured: hardsphere/pcva, substep global, spheres falling under fix
// gravity without its energy: the projection took 0.3 % of their kinetic
// energy by t = 4.5, and the collisions came at other times)
void HSMethod::require_fix_energies(const char *what) const
{
  const std::string names = S.pot->energyless_names();
  if (names.empty()) return;
  error->all(FLERR,
             "Fix {}: {} adds forces whose energy is not in the potential energy: use "
             "fix_modify <fix-ID> energy yes for it (or hardsphere/cva, which keeps no "
             "energy). The method keeps {}, which must hold the energy of every "
             "conservative force, or it undoes the work of that force",
             S.style_name, names, what);
}

/* ----------------------------------------------------------------------
   the collision operator R of section 2 at contact
------------------------------------------------------------------------- */

void HSMethod::collide_pair(int i, int j, Impulse &imp)
{
  double **x = atom->x;
  double **v = atom->v;
  const double dv[3] = {v[i][0] - v[j][0], v[i][1] - v[j][1], v[i][2] - v[j][2]};
  for (int k = 0; k < 3; k++) imp.dq[k] = x[i][k] - x[j][k];
  const double un = imp.dq[0] * dv[0] + imp.dq[1] * dv[1] + imp.dq[2] * dv[2];
  imp.apply = un < 0.0;
  if (imp.apply) HardSphere::pair_impulse(imp.dq, dv, S.mass_of(i), S.mass_of(j), imp.J);
}

void HSMethod::collide_wall(int i, const Wall &w, Impulse &imp)
{
  double **v = atom->v;
  const double vn = (w.side < 0) ? v[i][w.dim] : -v[i][w.dim];
  imp.apply = vn < 0.0;
  imp.reflect = 1;
  imp.dq[w.dim] = atom->x[i][w.dim] - w.coord;
  if (imp.apply) imp.J[w.dim] = -2.0 * S.mass_of(i) * v[i][w.dim];
}

/* ----------------------------------------------------------------------
   CVA's smooth map between contacts: velocity Verlet sub-steps
------------------------------------------------------------------------- */

// no contact in the remaining tleft: plain Verlet to the step's end (its
// closing half kick in final_integrate)
void HSMethod::finish_step(double tleft)
{
  if (tleft == S.dtv) S.nve_initial();
  else S.kick_drift(tleft);
  S.dtf_last = (tleft == S.dtv) ? S.dtf : 0.5 * tleft * force->ftm2v;
}

// Verlet sub-step of length tau to the predicted contact; returns false if
// the method found no contact after all (it then finished the step)
bool HSMethod::advance_to_contact(double &tau, double, const Impulse &)
{
  if (tau > 0.0) {
    S.kick_drift(tau);
    S.recompute_forces();
    S.kick(tau);
    S.comm_vel_acc();    // ghosts' velocities at contact, for the impulse
  }
  return true;
}

/* ----------------------------------------------------------------------
   kspace and energy fixes: held smooth forces of the local engine, whose
   work on the members the local projection counts (HSLocalModified::
   set_held_work()). Beside a thermostat's held forces the fix's copy of
   LAMMPS' force between the two (FixHardSphere's capture rule) tells them
   apart: the thermostat's stay half kicks outside the conservative map.
   Without the copy both would ride inside the flows, where the
   thermostat's work cannot be told from theirs
------------------------------------------------------------------------- */

std::string HSMethod::projection_limits(std::string &held_work) const
{
  held_work = S.pot->held_energy_terms();
  const std::string order =
      (S.nheld && !held_work.empty()) ? S.pot->capture_order(S.host) : std::string();
  if (order.empty()) return "";
  return fmt::format("{} beside the held thermostat forces of {} when {} (the local "
                     "projection needs LAMMPS' force between the two, which fix {} copies in "
                     "its post_force stage: define the thermostat after fix {} and the force "
                     "fixes before it)",
                     held_work, S.pot->held_names(), order, S.host->id, S.host->id);
}
