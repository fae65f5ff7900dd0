/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: fix hardsphere/pcva, the projected collision Verlet
   algorithm (Bond & Leimkuhler 2007, section 3.2): CVA, and after every
   sub-step of a step with a collision the group's momenta are scaled so
   that the modified Hamiltonian H_[2,VV] keeps the value it had at the
   step's start. Collision-free steps are fix nve's. With substep local
   (the local engine) one projection per step of the colliding spheres'
   velocities keeps H_[2,VV] to fourth order (hs_local_modified.h).
   See doc/fix_hardsphere_pcva.rst.
------------------------------------------------------------------------- */

#ifdef FIX_CLASS
// clang-format off
FixStyle(hardsphere/pcva,FixHardSpherePCVA);
// clang-format on
#else

#ifndef LMP_FIX_HARDSPHERE_PCVA_H
#define LMP_FIX_HARDSPHERE_PCVA_H

#include "fix_hardsphere.h"

#include <string>
#include <vector>

namespace LAMMPS_NS {

class FixHardSpherePCVA : public FixHardSphere {
 public:
  FixHardSpherePCVA(class LAMMPS *, int, char **);
  ~FixHardSpherePCVA() override;
  double compute_vector(int) override;

 protected:
  std::vector<double *> extra_counters() override;
  double Ht0;            // H_[2,VV] at the start of the current collisional step
  double nproj;          // projections done
  double nskip;          // sub-steps left unprojected (no real positive alpha)
  double maxdev;         // max |alpha - 1| of the projections done
  int warned;

  void begin_collisional_step() override;
  void end_substep(double tau) override;
  void end_collisional_step() override;

  double modified_energy(double &U, double &Kt);
  void project(const char *where);
  void skipped(const std::string &what);

  // substep local: one projection per step with clusters, of the members'
  // velocities relative to their cluster's centre of mass, that undoes the
  // step's change of H_[2,VV] (hs_local_modified.h)
  int engines_supported() const override { return ENGINE_BOTH; }
  std::string local_limits() override;
  void local_step_begun() override;
  void local_step_done() override;
  class HSLocalModified *lmod = nullptr;
};

}    // namespace LAMMPS_NS

#endif
#endif
