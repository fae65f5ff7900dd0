/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: shared base of the hard-sphere integrator family
   (Bond & Leimkuhler, SIAM J. Sci. Comput. 30(1), 2007).

   The base does the plumbing every method shares: keywords, the contact
   neighbor list and bonded contact candidates, walls, screening and
   predicting the next collision, the sub-step loop of the collision Verlet
   algorithm (section 2.2), force re-evaluation, collision bookkeeping,
   virial, MPI ghost exchange and restart. A method class overrides only
   what differs (style name, smooth map, collision operator, projection).
------------------------------------------------------------------------- */

#ifndef LMP_FIX_HARDSPHERE_H
#define LMP_FIX_HARDSPHERE_H

#include "atom.h"
#include "fix.h"

#include <string>
#include <vector>

namespace LAMMPS_NS {

class FixHardSphere : public Fix {
  friend class HSLocalEngine;
  friend class HSLocalModified;

 public:
  FixHardSphere(class LAMMPS *, int, char **);
  ~FixHardSphere() override;
  void post_constructor() override;
  int setmask() override;
  void init() override;
  void init_list(int, class NeighList *) override;
  void setup(int) override;
  void setup_post_neighbor() override;
  void post_neighbor() override;
  void initial_integrate(int) override;
  void final_integrate() override;
  void reset_dt() override;
  double compute_vector(int) override;
  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;
  int pack_reverse_comm(int, int, double *) override;
  void unpack_reverse_comm(int, int *, double *) override;
  void write_restart(FILE *) override;
  void restart(char *) override;
  double memory_usage() override;

 protected:
  enum { PAIR_EVENT = 0, WALL_EVENT = 1 };

  // conventions shared by the family
  static constexpr double BIG = 1.0e300;
  // |g(0)| below this (relative to sigma^2, resp. the diameter) counts as
  // touching; below minus this it is an overlap (a missed collision). Far
  // above round-off in positions, far below any physical overlap.
  static constexpr double TOUCH_TOL = 1.0e-9;
  // consecutive zero-length sub-steps without an impulse before we call it
  // a resting contact, which the impulsive hard-sphere model cannot resolve
  static constexpr int MAX_STUCK = 100;
  // collisions in one step beyond which something is wrong (a sequence of
  // contacts that does not end): MAX_SUBSTEPS_BASE + MAX_SUBSTEPS_PER_SPHERE
  // x the group's size (a dense fluid at a large step has a few per sphere)
  static constexpr bigint MAX_SUBSTEPS_BASE = 1000000;
  static constexpr bigint MAX_SUBSTEPS_PER_SPHERE = 100;
  bigint max_substeps = MAX_SUBSTEPS_BASE;
  // screen() results
  static constexpr int ACTIVE = 1, FAR = 2;

  struct Wall {
    int dim;         // 0,1,2
    int side;        // -1 = lo face (allowed x >= coord + r), +1 = hi face
    int edge;        // 1 if coord follows the box boundary (EDGE)
    double coord;
  };

  // one collision as found by the rank that predicted it (local indices)
  struct Event {
    int type;
    int i, j;    // i owned; j owned or ghost (pair events)
    int wall;
  };

  // the collision as broadcast to every rank (tags, so any rank can apply it)
  struct Impulse {
    double J[3];      // momentum added to atom i (atom j receives -J)
    double dq[3];     // contact normal q_i - q_j (pair) or wall offset (wall)
    tagint itag, jtag;
    int type;
    int wall;
    int apply;        // 0 for a grazing contact (no normal approach velocity)
    int reflect;      // wall: 1 = exact v_n -> -v_n (elastic R); 0 = add J / m
  };

  std::string style_name;    // e.g. "hardsphere/cva", for messages

  // force evaluations, and derivatives of V for the methods that need them
  // (pcva, mcva, vci set derivs_needed in their constructors)
  class HSPotential *pot;
  int derivs_needed = 0;
  std::string path_told;    // the derivative paths last reported
  enum { CONTACT_LIST_ID = 0, POT_LIST_ID = 1 };
  // all full force evaluations so far (output vector [5]; restart offset
  // in nforce_evals)
  double force_evals() const;
  std::string contact_name(const Impulse &) const;
  void resting_contact_error(const Impulse &);
  void pair_overlap_error(int i, int j, double r, double sigma);
  void check_runaway(bigint ncollisions);
  void add_impulse_virial(const Impulse &);
  // a contact touching now that the method's own flow separates (mcva):
  // not predicted again until a sub-step of nonzero length
  struct {
    int type = -1;
    tagint itag = 0, jtag = 0;
    int wall = -1;
  } released;
  void release_contact(const Impulse &);
  bool is_released(int type, tagint itag, tagint jtag, int wall) const;
  // a method's own counters, written to restart files after the base's
  virtual std::vector<double *> extra_counters() { return {}; }

  // step engines (doc "Step engines"): how a step with contacts is
  // sub-stepped. GLOBAL: the paper's algorithm (every atom to every
  // contact); LOCAL: hs_local_engine.h. What a method supports:
  enum { SUBSTEP_DEFAULT = 0, SUBSTEP_LOCAL = 1, SUBSTEP_GLOBAL = 2 };
  enum { ENGINE_NONE = 0, ENGINE_GLOBAL_ONLY = 1, ENGINE_BOTH = 2 };
  virtual int engines_supported() const { return ENGINE_GLOBAL_ONLY; }
  int substep_mode = SUBSTEP_DEFAULT;    // the keyword
  int use_local = 0;                     // decided in init()
  int local_step = 0;                    // the current step ran locally
  class HSLocalEngine *local_engine = nullptr;
  bigint cand_version = 0;               // bumped at every candidate list build
  double nfallback = 0.0;                // collisional steps run globally instead of locally
  int fallback_counting = 0;             // 1: local was the default but is unavailable
  int local_vec_offset = 5;              // first output entry of the engine's counters
  std::string local_why_told;
  void choose_engine();
  // a method's own reasons it cannot run locally with this set-up ("" if none)
  virtual std::string local_limits() { return ""; }
  // a step the local engine took: after its step() (x, v as the engine left
  // them, f still the start forces), after its closing kick (all at the end)
  virtual void local_step_begun() {}
  virtual void local_step_done() {}

  // keywords
  double diameter;
  int diameter_flag;
  std::vector<Wall> walls;

  // cached per run
  double dtv, dtf, dtf_last;
  double skin, rmax, list_cutoff;
  int forces_present;
  int own_list;                 // 1 if our list has its own cutoff, 0 if the pair cutoffs
  class NeighList *list;
  std::vector<int> cand;        // candidate pairs (i owned, j owned or ghost), flat
  std::vector<int> near;        // scratch: one list row's pairs within reach
  std::vector<double> ftm2v_mass;    // ftm2v / mass[type], when there is no rmass

  // per-atom state, sized atom->nmax
  int nmax_hs;
  double **xref;      // positions at the last neighbor list build
  double *gap;        // a sphere that moved less than gap since xref can touch nothing
  double *active;     // 1 if it may touch something within the rest of the step
  double **acc;       // accelerations, forwarded to ghosts with v and active

  // global counters, identical on every rank
  double ncoll_pair, ncoll_wall, ncoll_steps, nforce_evals;

  // flags of the current step: an impulse was applied / the loop sub-stepped
  int step_collided = 0, step_substeps = 0;

  // thermostat (held) forces, doc "Fixes beside the integrator": a
  // collisional step is K_held(dt/2) . method's conservative map . K_held(dt/2)
  int nheld = 0;            // 1 if some fix's forces are held
  int step_split = 0;       // 1 while the current step is split so
  bigint held_step = -1;    // the step whose start x fcons/fheld belong to
  int nmax_held = 0;
  double **ftot = nullptr, **fcons = nullptr, **fheld = nullptr;    // [nmax_held][3]
  std::string unknown_told, held_told;    // fixes named in the log already
  void check_fixes_beside();
  void split_held_forces();
  void begin_held_split();
  void end_held_split();
  int others_integrate = 0;       // another fix integrates atoms outside the group
  std::vector<double> fother;     // their forces during a collisional step
  void save_other_forces();
  void restore_other_forces();

  // --- hooks of the sub-step loop; the defaults are CVA's. All are called
  // on every rank together (collective), with the contact's tags known ---
  // no contact in the remaining tleft: finish the step (set dtf_last)
  virtual void finish_step(double tleft);
  // move to the contact predicted at tau; may change tau; return false if
  // the method then finds no contact (it must have finished the step)
  virtual bool advance_to_contact(double &tau, double tleft, const Impulse &);
  // once per step, before its first sub-step, if the step has a contact
  virtual void begin_collisional_step();
  // change the elastic impulse (imp.J, imp.reflect) built by collide_*()
  virtual void modify_impulse(Impulse &);
  // after each contact's impulse (tau: the sub-step just taken)
  virtual void end_substep(double tau);
  // in final_integrate after the closing kick of a step that sub-stepped
  virtual void end_collisional_step();

  // --- pieces of the sub-step loop (CVA) ---
  virtual void kick(double tau);
  void kick_dtf(double dtfk, double **force = nullptr);
  virtual void kick_drift(double tau);
  virtual void collide_pair(int i, int j, Impulse &);    // operator R at contact
  virtual void collide_wall(int i, const Wall &, Impulse &);
  virtual void apply_impulse(const Impulse &);
  void nve_initial();
  int moved_half_skin();
  void request_rebuild();
  void recompute_forces();

  // screening, prediction, bookkeeping
  int screen(double tleft);
  int screen_atom(int i, double t2, double h4, double ftm2v_over_m);
  bigint screened_step;    // the step final_integrate screened ahead for
  int screened_flags;
  double predict(double tleft, Event &);
  void reset_reference(int at_setup);
  void comm_vel_acc();
  void grow_peratom();
  void update_walls();
  // inline: called per candidate pair in the list-build and prediction loops
  double radius_of(int i) const { return diameter_flag ? 0.5 * diameter : atom->radius[i]; }
  double mass_of(int i) const
  {
    return atom->rmass ? atom->rmass[i] : atom->mass[atom->type[i]];
  }
  double wall_gap(const Wall &, const double *x, double r) const;
  void wall_name(const Wall &, std::string &) const;
  void check_other_integrators();
};

}    // namespace LAMMPS_NS

#endif
