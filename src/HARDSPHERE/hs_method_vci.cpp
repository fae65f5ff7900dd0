/* ----------------------------------------------------------------------
   HARDSPHERE package: the method of fix hardsphere/vci (Bond & Leimkuhler
   2007, section 2.3; Fetecau, Marsden, Ortiz, West 2003). See
   hs_method_vci.h and doc/fix_hardsphere_vci.rst.

   One collisional sub-step q_k -> q_c of length tau1 (kick, drift, forces
   at q_c, kick) has the discrete energy of section 2.3
     E_d^- = 1/2 |v_h|^2_M + (V(q_k) + V(q_c))/2,  v_h = (q_c - q_k)/tau1,
   v_h being the velocity after the first half kick. The impulse s J
   (J the elastic one of section 2) is chosen so that the sub-step that
   follows, q_c -> q_next of length tau2 (the time to the next contact or
   the step's end, found as the sub-step loop finds it, so it depends on s),
   has the same discrete energy E_d^+(s). Each evaluation of E_d^+ is a
   trial sub-step: impulse, prediction of tau2, half kick and drift, V at
   q_next; x and v are restored afterwards (f is not changed by it).
------------------------------------------------------------------------- */

#include "hs_method_vci.h"

#include "hs_potential.h"
#include "hs_system.h"
#include "hs_flow_view.h"
#include "hs_vci.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "force.h"
#include "neigh_request.h"
#include "neighbor.h"
#include "update.h"

#include <cmath>
#include <cstring>
#include <limits>
#include <mpi.h>

using namespace LAMMPS_NS;

// the impulse strength is sought in [SMIN, SMAX] times the elastic one:
// below 1/2 the contact would not separate (1/2 stops the normal approach)
static constexpr double SMIN = 0.5, SMAX = 2.0;
// A contact is held if its spheres, leaving with the elastic normal speed
// v_n against a normal approach acceleration g > 0, would meet again
// within HELD steps (return time 2 v_n / g). Its sub-steps are then as
// long as its bounce, and E_d of a bounce's Verlet sub-step of length tau
// is H - mu g^2 tau^2 / 8 (exact for a constant g): the discrete energy's
// defect is of the order of the contact's normal kinetic energy mu v_n^2/2.
// Matching E_d there sets the restitution by the sub-steps' lengths, not
// by energy (the last bounce before a step's end leaves with e = tau2 /
// tau1 < 1), and a pair held by an attraction collapses onto a resting
// contact. The elastic impulse keeps the bounce exactly (constant g), and
// no match can take a pair below the threshold: no collapse. 1 step: every
// contact of the test fluids is above it; 2 steps would take many of the
// pendulum chain's contacts at dt 0.1, whose mixture of matched and
// elastic contacts doubles its energy error.
static constexpr double HELD = 1.0;
static constexpr int MAXIT = 100;

// the impulse s J (s = 1: J itself, a wall's exact reflection included)
static HSTypes::Impulse scaled(const HSTypes::Impulse &imp, double s)
{
  HSTypes::Impulse t = imp;
  if (s != 1.0) {
    for (int k = 0; k < 3; k++) t.J[k] = s * imp.J[k];
    t.reflect = 0;
  }
  return t;
}

/* ---------------------------------------------------------------------- */

HSMethodVCI::HSMethodVCI(LAMMPS *lmp, HSSystem &sys) : HSMethod(lmp, sys) {}

/* ----------------------------------------------------------------------
   1/2 p^T M^-1 p of the group (energy units), collective
------------------------------------------------------------------------- */

double HSMethodVCI::kinetic()
{
  double **v = atom->v;
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  double loc = 0.0, all;
  for (int i = 0; i < nlocal; i++)
    if (mask[i] & S.groupbit)
      loc += S.mass_of(i) * (v[i][0] * v[i][0] + v[i][1] * v[i][1] + v[i][2] * v[i][2]);
  MPI_Allreduce(&loc, &all, 1, MPI_DOUBLE, MPI_SUM, world);
  return 0.5 * force->mvv2e * all;
}

// V at the current x (ghosts are forwarded by the energy evaluation)
double HSMethodVCI::potential_at_new_x()
{
  return S.pot->energy();
}

void HSMethodVCI::check_pending(double Ed, Tally &t)
{
  if (!pending) return;
  t.mx[1] = MAX(t.mx[1], fabs(Ed - pending_target));
  pending = 0;
}

/* ---------------------------------------------------------------------- */

void HSMethodVCI::begin_collisional_step()
{
  Vk = potential_at_new_x();    // V(q^n)
  have_target = 0;
  pending = 0;
}

/* ----------------------------------------------------------------------
   CVA's Verlet sub-step to the contact, recording E_d of the sub-step (the
   force evaluation at q_c also gives V(q_c))
------------------------------------------------------------------------- */

bool HSMethodVCI::advance_to_contact(double &tau, double tleft, const Impulse &)
{
  if (tau > 0.0) {
    S.kick_drift(tau);
    const double Kh = kinetic();    // 1/2 |(q_c - q_k)/tau|^2_M
    double Vc = 0.0;
    if (S.forces_present) {
      Vc = S.pot->evaluate(1);
    } else
      comm->forward_comm();
    S.kick(tau);
    S.comm_vel_acc();
    const double Ed = Kh + 0.5 * (Vk + Vc);
    check_pending(Ed, all);
    Etarget = Ed;
    have_target = 1;
    Vk = Vc;
  } else {
    // a contact at the same instant as the last one (or at the step's
    // start): no sub-step in between. E_d^- stays the last sub-step's; at
    // the step's start it is the limit of E_d for tau -> 0, H(q, p).
    if (pending) check_pending(kinetic() + Vk, all);
    if (!have_target) {
      Etarget = kinetic() + Vk;
      have_target = 1;
    }
  }
  tleft_after = tleft - tau;
  return true;
}

/* ----------------------------------------------------------------------
   no contact in the rest of the step: CVA's last sub-step; after a solved
   contact, measure its E_d (V at the step's end: one more evaluation)
------------------------------------------------------------------------- */

void HSMethodVCI::finish_step(double tleft)
{
  HSMethod::finish_step(tleft);
  if (pending) {
    const double Kh = kinetic();
    const double Vn = potential_at_new_x();
    check_pending(Kh + 0.5 * (Vk + Vn), all);
  }
}

/* ----------------------------------------------------------------------
   E_d^+(s) - E_d^- by a trial sub-step with the impulse s J, exactly as
   the loop will do it: impulse, screen + predict the next contact in the
   time left (tau2), Verlet half kick + drift over tau2, V there.
   x and v (owned and ghost) are restored from xsave/vsave. Collective.
------------------------------------------------------------------------- */

double HSMethodVCI::trial(const Impulse &imp, double s, double &scale, double &tau2)
{
  S.apply_impulse(scaled(imp, s));

  S.screen(tleft_after);
  S.comm_vel_acc();
  Event ev{PAIR_EVENT, -1, -1, -1};
  struct {
    double t;
    int rank;
  } mine{S.predict(tleft_after, ev), comm->me}, first;
  MPI_Allreduce(&mine, &first, 1, MPI_DOUBLE_INT, MPI_MINLOC, world);
  tau2 = (first.t >= tleft_after) ? tleft_after : first.t;

  double Ed;
  if (tau2 > 0.0) {
    S.kick_drift(tau2);
    const double Kh = kinetic();
    const double Vn = potential_at_new_x();
    Ed = Kh + 0.5 * (Vk + Vn);
    scale = Kh + 0.5 * (fabs(Vk) + fabs(Vn)) + fabs(Etarget);
  } else {
    // zero length: E_d -> H(q_c, p+) (only used as a value; the caller
    // treats tau2 = 0 at s = 1 as the elastic case)
    const double K = kinetic();
    Ed = K + Vk;
    scale = K + fabs(Vk) + fabs(Etarget);
  }

  const int nall = atom->nlocal + atom->nghost;
  if (nall) {
    memcpy(&atom->x[0][0], xsave.data(), sizeof(double) * 3 * nall);
    memcpy(&atom->v[0][0], vsave.data(), sizeof(double) * 3 * nall);
  }
  return Ed - Etarget;
}

/* ----------------------------------------------------------------------
   the impulse strength of section 2.3: solve E_d^+(s) = E_d^- for the
   root near the elastic s = 1 (hs_vci.h)
------------------------------------------------------------------------- */

void HSMethodVCI::modify_impulse(Impulse &imp)
{
  const int nall = atom->nlocal + atom->nghost;
  xsave.resize(3 * (size_t) nall);
  vsave.resize(3 * (size_t) nall);
  if (nall) {
    memcpy(xsave.data(), &atom->x[0][0], sizeof(double) * 3 * nall);
    memcpy(vsave.data(), &atom->v[0][0], sizeof(double) * 3 * nall);
  }

  // slope of E_d^+ in s near 1 from the kinetic term alone: |J|^2_{M^-1}/2
  const double J2 = imp.J[0] * imp.J[0] + imp.J[1] * imp.J[1] + imp.J[2] * imp.J[2];
  double loc = 0.0, sum = 0.0;
  const tagint *tag = atom->tag;
  for (int i = 0; i < atom->nlocal; i++) {
    if (tag[i] == imp.itag) loc += J2 / S.mass_of(i);
    if (imp.type == PAIR_EVENT && tag[i] == imp.jtag) loc += J2 / S.mass_of(i);
  }
  MPI_Allreduce(&loc, &sum, 1, MPI_DOUBLE, MPI_SUM, world);
  const double slope = 0.5 * force->mvv2e * sum;

  // the contact's normal approach acceleration at q_c (the forces of the
  // sub-step to it, forwarded with v by advance_to_contact), from i's owner
  double gloc = 0.0, gn = 0.0;
  const int i = atom->map(imp.itag);
  if (i >= 0 && i < atom->nlocal) {
    // j: a ghost at least, being in contact
    const int j = (imp.type == WALL_EVENT) ? i : atom->map(imp.jtag);
    gloc = S.approach_accel(imp, S.acc[i], S.acc[j]);
  }
  MPI_Allreduce(&gloc, &gn, 1, MPI_DOUBLE, MPI_SUM, world);

  solve(
      imp, slope,
      [&](double s, double &scale, double &tau2, double &dF) {
        dF = std::numeric_limits<double>::quiet_NaN();
        return trial(imp, s, scale, tau2);
      },
      held(J2 > 0.0 ? sum * sum / J2 : 0.0, gn), all, true);
}

// is the contact held (HELD above)? J2im = |J|^2 (1/m_i + 1/m_j)^2 (pair)
// or |J|^2 / m_i^2 (wall) = (2 v_n)^2, v_n the normal approach speed; gn
// the normal approach acceleration: return time 2 v_n / gn <= HELD dt
bool HSMethodVCI::held(double J2im, double gn) const
{
  const double h = HELD * update->dt * gn;
  return gn > 0.0 && J2im <= h * h;
}

void HSMethodVCI::solve(Impulse &imp, double slope, const Eval &eval, bool is_held, Tally &t,
                        bool all_ranks)
{
  pending = 0;
  // a held contact (HELD above): elastic
  if (is_held) {
    if (wants_warning(WARN_HELD, all_ranks))
      warn(WARN_HELD, imp, all_ranks,
           fmt::format("Fix {}: the contact of {} on step {} is held (its spheres, pulled "
                       "together, would meet again within a step), where the discrete energy "
                       "cannot be matched; the elastic impulse is used. Such collisions are "
                       "counted in f_{}[7]; this warning is printed once",
                       S.style_name, S.contact_name(imp), update->ntimestep, S.fix_id()));
    t.n[1] += 1.0;
    return;
  }
  double scale1, tau2, df1;
  const double f1 = eval(1.0, scale1, tau2, df1);
  if (tau2 == 0.0) {
    // the next contact is at the same instant: no sub-step after this one
    // whose E_d could be matched; E_d^+ degenerates to H(q_c, p+), which
    // the elastic impulse conserves. E_d^- is carried to that next contact.
    t.n[2] += 1.0;
    t.n[3] += 1.0;
    t.mx[0] = MAX(t.mx[0], 1.0);
    return;
  }
  // a trial with no sub-step after the contact (the next contact at the
  // same instant: s = 1/2 under an attraction) has no E_d^+ to match: it
  // is not a root (it used to be taken as one when |F| was within the
  // tolerance, i.e. for v_n ~ 1e-7)
  auto F = [&](double s, double &scale, double &dF) {
    double t2;
    const double f = eval(s, scale, t2, dF);
    return t2 > 0.0 ? f : std::numeric_limits<double>::quiet_NaN();
  };
  const HardSphere::VciRoot r = HardSphere::vci_root(
      F, f1, scale1, slope, SMIN, SMAX, MAXIT, 64.0 * std::numeric_limits<double>::epsilon(), df1);
  t.n[3] += r.evals;
  t.mx[0] = MAX(t.mx[0], (double) r.evals);
  if (r.status == HardSphere::VCI_NOT_CONVERGED) {
    const std::string msg = fmt::format(
        "Fix {}: the discrete-energy equation E_d+(s) = E_d- of the collision of {} on "
        "step {} did not converge in {} evaluations (impulse strength in [{}, {}] "
        "times the elastic one, residual {})",
        S.style_name, S.contact_name(imp), update->ntimestep, r.evals, r.lo, r.hi, r.F);
    if (all_ranks) error->all(FLERR, msg);
    error->one(FLERR, msg);
  }
  if (r.status != HardSphere::VCI_CONVERGED) {
    if (wants_warning(WARN_NO_ROOT, all_ranks))
      warn(WARN_NO_ROOT, imp, all_ranks,
           fmt::format("Fix {}: no impulse strength between {} and {} times the elastic one "
                       "matches the discrete energy across the collision of {} on step {} ({}, "
                       "E_d- {}, E_d+ - E_d- {} for the elastic impulse); the elastic impulse "
                       "is used. Such collisions are counted in f_{}[7]; this warning is "
                       "printed once",
                       S.style_name, SMIN, SMAX, S.contact_name(imp), update->ntimestep,
                       r.status == HardSphere::VCI_JUMP ? "E_d+ jumps across E_d-" : "no root",
                       Etarget, f1, S.fix_id()));
    t.n[1] += 1.0;
    return;
  }
  imp = scaled(imp, r.s);
  t.n[0] += 1.0;
  pending = 1;
  pending_target = Etarget;
}

/* ----------------------------------------------------------------------
   local form (doc/fix_hardsphere_vci.rst, "Local form"): inside one
   cluster's flow, on the flow's energy. E_d^- of a contact is that of the
   flow's sub-step to it; at the flow's start (or after a contact at the
   start) H(q, p) of the flow, as at a step's start in the global form
------------------------------------------------------------------------- */

void HSMethodVCI::flow_begun(const HSFlowView &fv)
{
  const HSFlowView::Substep &s = fv.last_substep();
  Etarget = s.kh + s.v1;
  have_target = 1;
  pending = 0;
}

void HSMethodVCI::flow_substep(const HSFlowView &fv)
{
  const HSFlowView::Substep &s = fv.last_substep();
  if (s.tau > 0.0) {
    const double Ed = s.kh + 0.5 * (s.v0 + s.v1);
    check_pending(Ed, flow);
    Etarget = Ed;
    have_target = 1;
  } else if (pending)
    check_pending(s.kh + s.v1, flow);
}

void HSMethodVCI::modify_impulse_in_flow(Impulse &imp, HSFlowView &fv)
{
  // slope of E_d^+ in s near 1 from the kinetic term alone: |J|^2_{M^-1}/2
  // (the flow's runner holds a copy of both atoms)
  const double J2 = imp.J[0] * imp.J[0] + imp.J[1] * imp.J[1] + imp.J[2] * imp.J[2];
  double im = 1.0 / S.mass_of(atom->map(imp.itag));
  if (imp.type == PAIR_EVENT) im += 1.0 / S.mass_of(atom->map(imp.jtag));
  const double slope = 0.5 * force->mvv2e * J2 * im;
  const bool hd = held(J2 * im * im, fv.approach_accel());

  solve(
      imp, slope,
      [&](double s, double &scale, double &tau2, double &dF) {
        const HSFlowView::Substep n = fv.trial(scaled(imp, s));
        tau2 = n.tau;
        // (the trial's impulse is s J: d/ds = d/dlambda / s)
        dF = n.tau > 0.0 ? (n.dkh + 0.5 * n.dv1) / s : std::numeric_limits<double>::quiet_NaN();
        scale = n.kh + 0.5 * (fabs(n.v0) + fabs(n.v1)) + fabs(Etarget);
        return n.tau > 0.0 ? n.kh + 0.5 * (n.v0 + n.v1) - Etarget : n.kh + n.v1 - Etarget;
      },
      hd, flow, false);
}

// the flows' counts of every rank into the counters (collective)
// (no note: a key no contact has)
static constexpr double NO_NOTE = -1e300;

void HSMethodVCI::cluster_step_done(HSStepView &)
{
  Tally sum;
  MPI_Allreduce(rank.n, sum.n, 4, MPI_DOUBLE, MPI_SUM, world);
  // the maxima and, in the same reduction, each kind's lowest key of a
  // note (as -key)
  double mx[4] = {rank.mx[0], rank.mx[1], NO_NOTE, NO_NOTE}, mxall[4];
  for (int k = 0; k < 2; k++)
    if (!step_note[k].text.empty()) mx[2 + k] = -step_note[k].key;
  MPI_Allreduce(mx, mxall, 4, MPI_DOUBLE, MPI_MAX, world);
  for (int k = 0; k < 4; k++) all.n[k] += sum.n[k];
  for (int k = 0; k < 2; k++) all.mx[k] = MAX(all.mx[k], mxall[k]);
  rank = Tally();
  for (int k = 0; k < 2; k++) {
    if (warned[k] || mxall[2 + k] == NO_NOTE) continue;
    // (rare: the first such contact of the run) the note's rank to all
    const double key = -mxall[2 + k];
    int root = (!step_note[k].text.empty() && step_note[k].key == key) ? comm->me : -1, from;
    MPI_Allreduce(&root, &from, 1, MPI_INT, MPI_MAX, world);
    std::string text = step_note[k].text;
    int len = (int) text.size();
    MPI_Bcast(&len, 1, MPI_INT, from, world);
    text.resize(len);
    MPI_Bcast(&text[0], len, MPI_CHAR, from, world);
    if (comm->me == 0) error->warning(FLERR, text);
    warned[k] = 1;
  }
  notes.clear();
  step_note[0] = step_note[1] = Note();
}

// (a flow runs on one rank: its warning waits for the step's end)
void HSMethodVCI::warn(int kind, const Impulse &imp, bool all_ranks, const std::string &msg)
{
  if (!all_ranks) return note(kind, imp, msg);
  if (comm->me == 0) error->warning(FLERR, msg);
  warned[kind] = 1;
}

// a flow's first warning of each kind (WARN_NO_ROOT, WARN_HELD), kept with its counts
void HSMethodVCI::note(int kind, const Impulse &imp, const std::string &text)
{
  if (!flow_note[kind].text.empty()) return;
  flow_note[kind].text = text;
  flow_note[kind].key = (double) (imp.type == WALL_EVENT ? imp.itag : MIN(imp.itag, imp.jtag));
}

void HSMethodVCI::take_flow_counts(std::vector<double> &out)
{
  out.assign(flow.n, flow.n + 4);
  out.insert(out.end(), flow.mx, flow.mx + 2);
  flow = Tally();
  // its notes by index
  for (Note &n : flow_note) {
    if (n.text.empty()) {
      out.push_back(-1.0);
      continue;
    }
    out.push_back((double) notes.size());
    notes.push_back(n);
    n = Note();
  }
}

// a final flow's counts into this rank's sums of the step
void HSMethodVCI::add_flow_counts(const std::vector<double> &c)
{
  for (int k = 0; k < 4; k++) rank.n[k] += c[k];
  for (int k = 0; k < 2; k++) rank.mx[k] = MAX(rank.mx[k], c[4 + k]);
  for (int k = 0; k < 2; k++) {
    if (c[6 + k] < 0.0) continue;
    const Note &n = notes[(size_t) c[6 + k]];
    if (step_note[k].text.empty() || n.key < step_note[k].key) step_note[k] = n;
  }
}

/* ---------------------------------------------------------------------- */

double HSMethodVCI::vector(int k)
{
  if (k >= 0 && k < 4) return all.n[k];
  if (k >= 4 && k < 6) return all.mx[k - 4];
  return 0.0;
}

// the counters after the fix's in restart files
std::vector<double *> HSMethodVCI::counters()
{
  return {&all.n[0], &all.n[1], &all.n[2], &all.n[3], &all.mx[0], &all.mx[1]};
}
