/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: compute hamiltonian/modified, the modified
   Hamiltonians of velocity Verlet (Bond & Leimkuhler 2007, section 3):
   [1] H, [2] H_[2,VV] = H + dt^2/24 H2, [3] H_[4,VV] = H_[2,VV] + dt^4/720 H4,
   [4] dt^2/24 H2, [5] dt^4/720 H4 (the corrections alone).
   See doc/compute_hamiltonian_modified.rst.
------------------------------------------------------------------------- */

#ifdef COMPUTE_CLASS
// clang-format off
ComputeStyle(hamiltonian/modified,ComputeHamiltonianModified);
// clang-format on
#else

#ifndef LMP_COMPUTE_HAMILTONIAN_MODIFIED_H
#define LMP_COMPUTE_HAMILTONIAN_MODIFIED_H

#include "compute.h"

namespace LAMMPS_NS {

class ComputeHamiltonianModified : public Compute {
 public:
  ComputeHamiltonianModified(class LAMMPS *, int, char **);
  ~ComputeHamiltonianModified() override;
  void init() override;
  void init_list(int, class NeighList *) override;
  double compute_scalar() override;
  void compute_vector() override;
  double memory_usage() override;

  // the derivative layer this compute uses (tests, diagnostics)
  class HSPotential *potential() { return pot; }
  // H2 and H4 of the last evaluation (energy/time^2, energy/time^4)
  double h2() const { return h2_; }
  double h4() const { return h4_; }

 protected:
  class HSPotential *pot;
  int mode;
  double vec[5];
  double h2_, h4_;
  bigint step_h2, step_h4;    // steps at which H2 / H4 were last evaluated
  int nmax;
  double **g, **hv, **tv;
  double **fc = nullptr;    // conservative forces, when thermostat forces are in atom->f
  int warned_group = 0;
  void check_group_integrated();
  int logged;    // the paths were written to the log

  void check_energy_tallied();
  double mass_of(int i) const;
  void eval(int want_h4);
};

}    // namespace LAMMPS_NS

#endif
#endif
