/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: the system layer shared by the fix family, the step
   engines and the methods (doc/fix_hardsphere.rst, "How the code is
   organised"). It holds what every step needs whichever engine takes it:
   the group's geometry (radii, masses, walls), the contact candidates of
   the current neighbor list and each sphere's free gap, screening, the
   velocity-Verlet pieces of fix nve, impulses on every copy of an atom,
   the collision ledger (counts, virial) and the family's errors.

   It calls nothing above it: no engine, no method, no fix of the family.
   The fix that owns it (the host) only passes its communication buffers
   through (pack/unpack_*_comm) and receives list-build requests.
------------------------------------------------------------------------- */

#ifndef LMP_HS_SYSTEM_H
#define LMP_HS_SYSTEM_H

#include "atom.h"
#include "hs_screen.h"
#include "hs_types.h"
#include "pointers.h"

#include <cstdint>
#include <string>
#include <vector>

namespace LAMMPS_NS {

class Fix;
class HSPotential;

class HSSystem : protected Pointers, public HSTypes {
  double **cols_ = nullptr;    // forward_columns()/reverse_columns() in progress
  double **extra_ = nullptr;    // forward_vel_acc()'s extra columns
  int nextra_ = 0;
  int ncols_ = 0, ncmp_ = 0;
  std::vector<int> *changed_ = nullptr;
  // sparse messages: {count, (position in the swap's list, row)...}, always
  // for reverse_columns, for forward_columns when given the rows to send
  bool sparse_ = false;
  // rows marked for the sparse exchange in progress: forward, the rows to
  // send (owned, and ghosts received); reverse, the ghost rows that may be
  // nonzero (listed by the caller, and ghosts received)
  std::vector<char> sendmark_;
  std::vector<int> marked_;
  std::vector<int> packsel_;    // pack_reverse_comm(): the listed rows of one swap
  bool revlisted_ = false;

 public:
  HSSystem(class LAMMPS *, Fix *host, const std::string &style_name);
  ~HSSystem() override;

  Fix *host;                 // the fix: its comm buffers, virial and reneighbor request
  const int groupbit;
  const std::string style_name;    // e.g. "hardsphere/cva", for messages
  const char *fix_id() const;

  // force evaluations, and derivatives of V for the methods that need them
  HSPotential *pot;
  // all full force evaluations so far (output vector [4]; restart offset
  // in nforce_evals)
  double force_evals() const;

  // geometry (keywords)
  double diameter = 0.0;
  int diameter_flag = 0;
  std::vector<Wall> walls;
  // inline: called per candidate pair in the list-build and prediction loops
  double radius_of(int i) const { return diameter_flag ? 0.5 * diameter : atom->radius[i]; }
  double mass_of(int i) const { return atom->rmass ? atom->rmass[i] : atom->mass[atom->type[i]]; }
  // acc[i] = f[i] / m in velocity units (ftm2v = force->ftm2v): set_acc()'s
  // row, also for the local engine's fused first-guess pass
  void set_acc_row(int i, double ftm2v) { acc_of(i, ftm2v, acc[i]); }
  // owned atom i's acceleration as acc holds it, into a[0..2]
  void acc_of(int i, double ftm2v, double *a) const
  {
    const double im = ftm2v / mass_of(i);
    const double *fi = atom->f[i];
    a[0] = fi[0] * im;
    a[1] = fi[1] * im;
    a[2] = fi[2] * im;
  }
  // moved more than half the skin since the list build (LAMMPS' rebuild
  // trigger): moved_half_skin()'s test, also made in the local engine's
  // closing-velocities pass
  bool moved_half(int i) const
  {
    const double dx = atom->x[i][0] - xref[i][0], dy = atom->x[i][1] - xref[i][1],
                 dz = atom->x[i][2] - xref[i][2];
    return dx * dx + dy * dy + dz * dz > 0.25 * skin * skin;
  }
  double wall_gap(const Wall &, const double *x, double r) const;
  void wall_name(const Wall &, std::string &) const;
  void update_walls();
  // whether an atom of this group is also in the group of other_groupbit,
  // on any rank (a collective: at set-up)
  bool shares_atoms(int other_groupbit) const;
  // group igroup can never hold an atom of this group during the run: it
  // shares none now and is not dynamic (a dynamic group may come to)
  bool group_apart(int igroup) const;

  // cached per run
  bigint max_substeps = MAX_SUBSTEPS_BASE;
  double dtv = 0.0, dtf = 0.0, dtf_last = 0.0;
  double skin = 0.0, rmax = 0.0, list_cutoff = 0.0;
  int forces_present = 0;
  class NeighList *list = nullptr;
  std::vector<int> cand;        // candidate pairs (i owned, j owned or ghost), flat
  std::vector<double> cand_r;   // their distances at the build (xref)
  bigint cand_version = 0;      // bumped at every candidate list build
  std::vector<double> ftm2v_mass;    // ftm2v / mass[type], when there is no rmass

  // per-atom state, sized atom->nmax
  double **xref = nullptr;    // positions at the last neighbor list build (owned and ghosts)
  double *gap = nullptr;      // a sphere that moved less than gap since xref can touch nothing
  double *active = nullptr;   // 1 if it may touch something within the rest of the step
  double **acc = nullptr;     // accelerations, forwarded to ghosts with v and active
  void grow_peratom();

  // global counters, identical on every rank
  double ncoll_pair = 0.0, ncoll_wall = 0.0, ncoll_steps = 0.0, nforce_evals = 0.0;
  double nfallback = 0.0;       // collisional steps run globally instead of locally
  // keyword overflow: a cluster beyond the ghost atoms is an error, makes
  // the step global, or has the local engine widen the ghost cutoff and
  // take the step again
  enum { OVERFLOW_ERROR, OVERFLOW_GLOBAL, OVERFLOW_WIDEN };
  int overflow = OVERFLOW_ERROR;
  // keyword ghost (local engine, several ranks): lazy N, LAMMPS' own ghost
  // cutoff until a contact is predicted, the engine's until N steps pass
  // without one (ghost_lazy = N); wide, the engine's always (ghost_lazy = 0)
  bigint ghost_lazy = 500;
  int fallback_counting = 0;    // 1: local was the default but is unavailable
  // flags of the current step: an impulse was applied / the loop sub-stepped
  int step_collided = 0, step_substeps = 0;

  // held (thermostat) forces, doc "Fixes beside the integrator"
  int nheld = 0;              // 1 if some fix's forces are held
  int step_split = 0;         // 1 while the current step is split so
  bigint held_step = -1;      // the step whose start x fcons/fheld belong to
  double **ftot = nullptr, **fcons = nullptr, **fheld = nullptr;    // [nmax_held][3]
  // at the current x with atom->f = f_c + f_h: ftot = that, fcons = f_c
  // (left in atom->f), fheld = f_h
  void split_held_forces(bool at_start);
  // LAMMPS' conservative forces of a step, f before the held fixes' post_force
  // adds theirs: copied by the fix's own post_force() when it comes after
  // every force fix and before every held one (FixHardSphere::
  // capture_rule()). The local engine's held force is then f - fcap, with
  // no evaluation of the members' terms (doc/fix_hardsphere.rst "Fixes
  // beside the integrator")
  int cap_on = 0;
  void capture_forces();
  // fcap of the step's start (the last step's end: at_start) or end, if it
  // holds this step's forces under the current local indices; else null
  double **captured(bool at_start) const;
  void uncapture() { cap_step = -1; }
  // a list build that kept every owned atom's index (ghosts rebuilt only,
  // HSLocalEngine::reborder()): a copy valid before it stays valid
  void capture_kept(bigint ncalls_before);
  Fix *other_integrator = nullptr;    // a fix that integrates atoms outside the group

  // screening (screened ahead by the closing kick, see closing_kick())
  bigint screened_step = -1;
  int screened_flags = 0;
  int screen(double tleft);
  // LIST: also the NEAR bit for near_atoms (closing_kick())
  template <bool LIST = false> int screen_atom(int i, double t2, double h4, double ftm2v_over_m);
  template <bool LIST = false> int screen_terms(int i, double d2, double v2, double a2);
  // the closing kick's list of the owned atoms that the local engine's
  // quick first guess may find flagged at step near_step: every atom the
  // screen does not clear with its free gap less near_margin (set by the
  // engine; < 0: no list). Ascending local index.
  double near_margin = -1.0, near_used_margin = -1.0;
  bigint near_step = -1;
  std::vector<int> near_atoms;

  // at each list build: reference positions, candidates, gaps; overlaps
  // are errors (at_setup: the input's, else a missed collision)
  void reset_reference(int at_setup);
  // this rank's owned and ghost atoms at the last list build: a step's
  // references (xref, the candidates, gaps) are by local index, valid only
  // for those atoms (atom->natoms would not do: with thermo_modify lost
  // ignore, LAMMPS counts atoms lost at a reneighboring only at the next
  // thermo output, after the lists were rebuilt without them)
  int nlocal_ref = -1, nghost_ref = -1;
  // the atoms present on every rank, as their number and the sum of their
  // IDs, renewed at each list build if track_atoms (hardsphere/pcva): within
  // a step atoms are created or deleted only at a reneighboring (fixes'
  // pre_exchange: deposit, pour, evaporate, gcmc; atoms lost at the
  // exchange), whose list build comes before the step's end. One reduction
  // per list build
  bool track_atoms = false;
  bigint atoms_count = -1;
  unsigned long long atoms_idsum = 0;
  // at a step's start: an error if atoms were created or deleted since the
  // last list build (between runs, with "run ... pre no", which skips the
  // set-up that would rebuild them: else every reference is another atom's).
  // Deferred (defer_error()): FOUND_ERROR if this rank found it, else 0
  int check_atoms_unchanged();

  // errors that some ranks find at a point every rank reaches. error->one()
  // prints on the finding rank's screen only: with -screen none, or a
  // screen per rank, the log ended with no message. So the message is kept
  // (this rank's first) and raise_deferred(), which every rank calls,
  // stops all of them with the lowest finding rank's message through
  // error->all() (rank 0 writes it to the screen and the log). On one rank
  // defer_error() is error->one() at once
  void defer_error(const std::string &msg);
  void drop_deferred() { deferred_msg.clear(); }
  void raise_deferred();
  // (collective) every rank stops with the message of the lowest rank whose
  // msg is not empty; returns if every msg is empty
  void error_from_lowest(const std::string &msg);
  // the step's screening flags OR-ed over the ranks (one MPI_Allreduce); a
  // FOUND_ERROR among them raises the deferred errors
  int reduce_step_flags(int flags);
  // a step's start (every style's initial_integrate()): the atoms checked
  // against the last list build, the per-atom arrays and walls brought up
  // to date, and the step's screening flags over the ranks: those of the
  // previous step's closing kick if it screened for this step (no
  // end_of_step fix, the same run), else screen() now. A deferred error
  // (atoms changed, an atom beyond the skin) stops every rank here
  int screen_step();
  // what the last step, its list build and its forces depend on besides
  // velocities, as one number the same on every rank and for every
  // distribution of the atoms over the ranks: the box, the per-type
  // masses and every owned atom's ID, position, radius and per-atom mass
  // (an exact sum of hashed bits: no round-off, no order). Taken when a
  // run ends and compared when the next skips its set-up (run ... pre no)
  uint64_t state_fingerprint() const;
  // accelerations of owned atoms, then v, a and active to the ghosts
  void comm_vel_acc();
  // its two parts: the owned atoms' accelerations; v, a and active to the
  // ghosts, with up to COMM_EXTRA columns of an engine in the same
  // messages (the local engine's first guess: one exchange, not two)
  void set_acc();
  static constexpr int COMM_EXTRA = 2;
  void forward_vel_acc(double **extra = nullptr, int nextra = 0);
  int pack_forward_comm(int n, int *list, double *buf);
  void unpack_forward_comm(int n, int first, double *buf);
  int pack_reverse_comm(int n, int first, double *buf);
  void unpack_reverse_comm(int n, int *list, double *buf);
  // an engine's own per-atom columns a[i][0..ncol) (ncol <= COMM_COLUMNS),
  // through the host's buffers: forward copies the owners' rows to their
  // ghosts, reverse adds the ghosts' rows to their owners' (and leaves the
  // ghosts' as they were)
  // changed (optional): forward lists the ghosts whose first ncmp columns
  // changed, reverse the owners that received a nonzero row
  // send (forward, optional): only the owned rows listed go to their ghosts (the others' ghosts keep their rows: the caller
  // knows they did not change since the last forward of the same array);
  // reverse sends only the ghost rows with a nonzero entry. Both then
  // travel as sparse messages (a position and a row each), which LAMMPS'
  // buffers hold for ncol <= COMM_COLUMNS (comm_forward, comm_reverse are
  // sized for it)
  static constexpr int COMM_COLUMNS = 7;
  void forward_columns(double **a, int ncol, std::vector<int> *changed = nullptr, int ncmp = 0,
                       const std::vector<int> *send = nullptr);
  // reverse with changed: on entry it lists every row that may be nonzero
  // (the callers' invariant), so the ghosts not in it are not looked at
  void reverse_columns(double **a, int ncol, std::vector<int> *changed = nullptr);

  // earliest approaching contact within tleft of this rank's candidates
  double predict(double tleft, Event &);
  // a touching contact that a method found separating on its own flow:
  // predict() passes over it while it touches, until a sub-step moves on
  struct {
    int type = -1;
    tagint itag = 0, jtag = 0;
    int wall = -1;
  } released;
  void release_contact(const Impulse &);
  bool is_released(int type, tagint itag, tagint jtag, int wall) const;

  // velocity Verlet pieces: fix nve's arithmetic, to the bit
  void nve_initial();
  void kick(double tau);
  void kick_dtf(double dtfk, double **force = nullptr);
  void kick_drift(double tau);
  void recompute_forces();
  // the closing half kick of a step without sub-steps, screening the next
  // step in the same pass unless end_of_step fixes may change v before it
  void closing_kick();
  template <bool LIST> int kick_and_screen(double t2, double h4);
  bool fast_screen(HardSphere::KickScreen &k, double t2, double h4, bool list, bool kick);
  // kick_and_screen(), screen(): the spheres the fast path did not clear
  std::vector<HardSphere::Unscreened> unscreened;
  int moved_half_skin();
  // moved: this rank's moved_half_skin() if the caller has it (else computed)
  void request_rebuild(int moved = -1);

  // an impulse on every copy of its atoms on this rank
  void apply_impulse(const Impulse &);
  void add_impulse_virial(const Impulse &);
  // the contact's relative normal acceleration, positive if it pulls the
  // two spheres together (or the sphere onto the wall): ai, aj the
  // accelerations of imp's spheres (aj unused for a wall)
  double approach_accel(const Impulse &imp, const double *ai, const double *aj) const;

  // errors
  std::string contact_name(const Impulse &) const;
  void resting_contact_error(const Impulse &, bool every_rank);
  void pair_overlap_error(int i, int j, double r, double sigma);
  void check_runaway(bigint ncollisions, bool every_rank);

  double memory_usage() const;

 private:
  int nmax_hs = 0;
  int nmax_held = 0;
  double **fcap = nullptr;    // [nmax_cap][3], owned atoms
  int nmax_cap = 0, cap_nlocal = -1;
  bigint cap_step = -1, cap_ncalls = -1;
  std::vector<int> near;    // scratch: one list row's pairs within reach
  std::string deferred_msg;
  // the screen's "beyond the skin" error is deferred (the callers reduce
  // its flags: screen_step(), the closing kick's) or at once
  bool defer_skin = false;
};

}    // namespace LAMMPS_NS

#endif
