/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: fix hardsphere/psa, the primitive splitting
   algorithm (Bond & Leimkuhler 2007, section 2.1; Suh et al.): a half kick
   with the smooth forces, exact event-driven hard-sphere free flight over
   the whole step (straight lines, elastic collisions), a closing half kick.
   With no smooth forces it is the classic event-driven hard-sphere
   algorithm; with forces its energy error is first order through a
   collision (section 2.1's Delta H).

   Everything but the step itself (keywords, contact candidates, walls,
   screening, virial, counters, restart) is the fix family's shell and the
   system layer's (FixHardSphere, HSSystem); psa uses no step engine.
------------------------------------------------------------------------- */

#ifdef FIX_CLASS
// clang-format off
FixStyle(hardsphere/psa,FixHardSpherePSA);
// clang-format on
#else

#ifndef LMP_FIX_HARDSPHERE_PSA_H
#define LMP_FIX_HARDSPHERE_PSA_H

#include "fix_hardsphere.h"
#include "hs_eventq.h"

#include <utility>
#include <vector>

namespace LAMMPS_NS {

class FixHardSpherePSA : public FixHardSphere {
 public:
  FixHardSpherePSA(class LAMMPS *, int, char **);
  ~FixHardSpherePSA() override;
  void setup_post_neighbor() override;
  void post_neighbor() override;
  void initial_integrate(int) override;
  double memory_usage() override;

 protected:
  void apply_impulse(const Impulse &);    // every copy, by tag (no atom map needed)
  // no sub-steps with forces: local by construction, substep has no effect

 private:
  // a rank's earliest event, as reduced over all ranks (the earliest wins,
  // ties to the lower rank) in one collective per collision: the contact
  // time, the impulse, and both spheres' positions at contact (as the
  // predicting rank has its copies), so every copy, owned or ghost, is put
  // at the same place
  struct FlightImpulse {
    double t;
    int rank;
    Impulse imp;
    double xi[3], xj[3];
  };
  MPI_Datatype event_type;
  MPI_Op event_op;
  static void earliest_event(void *in, void *inout, int *len, MPI_Datatype *);

  // contact candidates per atom (owned and ghost), from the system layer's cand
  // list, rebuilt lazily after each neighbor list build
  std::vector<int> adj_start, adj;
  int adj_valid;
  // tag -> local indices, sorted, when LAMMPS keeps no atom map
  std::vector<std::pair<tagint, int>> tag_index;

  // event-driven state of one step, per local atom (owned and ghost):
  // atom->x[k] is the position at local time tloc[k] (x(t) = x + v (t - tloc))
  std::vector<double> tloc;
  std::vector<int> ncol;       // collisions of this copy in the step
  std::vector<int> partner;    // the scheduled event's partner: index, or -1 - wall
  std::vector<int> pcount;     // the partner's ncol when the event was predicted
  std::vector<double> tfirst;  // scratch of predict_all()
  HardSphere::EventHeap heap;  // one scheduled event (the earliest) per atom

  void build_adjacency();
  void build_event(int k, double te, FlightImpulse &fi);
  void predict_all();
  void predict_atom(int k);
  void place_copies(tagint tag, const double *xc, double t);
  void after_collision(tagint tag);
  template <class F> void for_copies(tagint tag, F fn);
};

}    // namespace LAMMPS_NS

#endif
#endif
