/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: what a method may read (and the few things it may
   change) of a step that an engine took cluster by cluster (the local
   engine, hs_local_engine.h): the step's clusters, the start state, the
   partners' kicks, the restricted force evaluations. A method that keeps
   a modified energy per step (pcva's local projection, hs_local_modified.h)
   sees the step through this view and never the engine itself.
   Valid from HSMethod::cluster_step_begun() to the end of
   HSMethod::cluster_step_done().
------------------------------------------------------------------------- */

#ifndef LMP_HS_STEP_VIEW_H
#define LMP_HS_STEP_VIEW_H

#include "lmptype.h"

#include <vector>

namespace LAMMPS_NS {

class HSLocalForces;

class HSStepView {
 public:
  // the step's clusters and their members (local indices at the step's start)
  virtual int nclusters() const = 0;
  virtual const std::vector<int> &members(int c) const = 0;
  // the state at the step's start of local index i
  virtual const double *start_x(int i) const = 0;
  virtual const double *start_v(int i) const = 0;
  // the same as arrays of rows (start_x(i) == start_x_rows()[i]), for loops
  // over many atoms (a call per atom was ~1 % of pcva's step)
  virtual const double *const *start_x_rows() const = 0;
  virtual const double *const *start_v_rows() const = 0;
  // the V_C kicks non-member i took in the first, resp. second Phi_H1
  virtual void partner_kicks(int i, double *first, double *second) const = 0;
  // restricted force evaluations on the step's lists
  virtual HSLocalForces &local_forces() = 0;
  // the constant one-atom force on copy i (fix gravity's m g; zero without
  // one): part of V_C for a member, not in the restricted evaluations
  virtual void const_force(int i, double *out) const = 0;
  // the owned index of atom ID t of the step's clusters at the step's end
  // (a rebuild may have sorted the atoms); an error if it is not owned
  virtual int owned(tagint t) const = 0;
  // change an atom's velocity or position, on all its copies the step uses
  virtual void put_v(int i, const double *vn) = 0;
  virtual void put_x(int i, const double *xn) = 0;

 protected:
  // not deleted through the view: no virtual destructor to clash with
  // Pointers' in the engine that implements it
  ~HSStepView() = default;
};

}    // namespace LAMMPS_NS

#endif
