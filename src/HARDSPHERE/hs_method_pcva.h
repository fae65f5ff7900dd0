/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: the method of fix hardsphere/pcva, the projected
   collision Verlet algorithm (Bond & Leimkuhler 2007, section 3.2): CVA,
   and after every sub-step of a step with a collision the group's momenta
   are scaled so that the modified Hamiltonian H_[2,VV] keeps the value it
   had at the step's start. Collision-free steps are fix nve's. A step
   taken by clusters (substep local) gets one projection of the colliding
   spheres' velocities that keeps H_[2,VV] to fourth order
   (hs_local_modified.h). See doc/fix_hardsphere_pcva.rst.
------------------------------------------------------------------------- */

#ifndef LMP_HS_METHOD_PCVA_H
#define LMP_HS_METHOD_PCVA_H

#include "hs_method.h"

#include <string>
#include <vector>

namespace LAMMPS_NS {

class HSLocalModified;

class HSMethodPCVA : public HSMethod {
 public:
  HSMethodPCVA(class LAMMPS *, HSSystem &);
  ~HSMethodPCVA() override;

  int needs_derivatives() const override { return 1; }
  void init() override;
  std::string local_limits() override;

  void begin_collisional_step() override;
  void end_substep(double tau) override;
  void end_collisional_step() override;
  void cluster_step_begun(HSStepView &) override;
  void cluster_step_done(HSStepView &) override;

  int nvector() const override { return 3; }
  double vector(int) override;
  double memory_usage() override;
  std::vector<double *> counters() override;

 private:
  double Ht0 = 0.0;      // H_[2,VV] at the start of the current collisional step
  // the atoms present at its start (HSSystem::atoms_count, atoms_idsum)
  bigint count0 = -1;
  unsigned long long idsum0 = 0;
  void note_atoms();
  bool atoms_changed();
  double nproj = 0.0;    // projections done
  double nskip = 0.0;    // sub-steps left unprojected (no real positive alpha)
  double maxdev = 0.0;   // max |alpha - 1| of the projections done
  int warned = 0;

  double modified_energy(double &U, double &Kt);
  void project_momenta(const char *where);
  void skipped(const std::string &what);
  HSLocalModified *lmod = nullptr;
  std::string held_work;    // local_limits(): kspace, energy fixes ("" if none)
};

}    // namespace LAMMPS_NS

#endif
