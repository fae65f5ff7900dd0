/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: fix hardsphere/press, a barostat for hard spheres
   that samples the isothermal-isobaric ensemble by Monte Carlo volume
   moves (doc/fix_hardsphere_press.rst).

   Every N steps, at the end of a step: ln V' = ln V + delta (u - 1/2),
   all dimensions (iso) or one set of them (aniso, couple) and the
   positions of the group scaled about the box centre, momenta unchanged;
   a move that makes two spheres of a hardsphere fix overlap is rejected at
   once, else it is accepted with probability
     min(1, exp(-beta (dU + P dV) + (N + 1) ln(V'/V)))
   (dU the change of the smooth potential energy). A rejected move leaves
   box and positions as they were, to the bit; an accepted one rebuilds
   the neighbor lists and forces at once, so the next step starts from a
   state as consistent as after a LAMMPS step.
------------------------------------------------------------------------- */

#ifdef FIX_CLASS
// clang-format off
FixStyle(hardsphere/press,FixHardSpherePress);
// clang-format on
#else

#ifndef LMP_FIX_HARDSPHERE_PRESS_H
#define LMP_FIX_HARDSPHERE_PRESS_H

#include "fix.h"

#include <string>
#include <vector>

namespace LAMMPS_NS {

class FixHardSphere;
class HSPotential;
class RanPark;

class FixHardSpherePress : public Fix {
 public:
  FixHardSpherePress(class LAMMPS *, int, char **);
  ~FixHardSpherePress() override;
  int setmask() override;
  void init() override;
  void init_list(int, class NeighList *) override;
  void setup(int) override;
  void end_of_step() override;
  double compute_vector(int) override;
  void write_restart(FILE *) override;
  void restart(char *) override;
  void grow_arrays(int) override;
  void copy_arrays(int, int, int) override;
  int pack_exchange(int, double *) override;
  int unpack_exchange(int, double *) override;
  double memory_usage() override;

 private:
  double p_start, p_stop, p_period;
  double t_target = 0.0;      // temp keyword (temperature units)
  int seed = 0;
  int every_flag = 0;         // the every keyword was given
  double delta = 0.01;        // largest |ln V' - ln V| / 2 ... the move width
  double delta_max = 0.0;     // the widest move the neighbor lists allow
  bigint adapt_attempts = 0;  // the first this many attempts tune delta
  int dimension = 3;
  std::string couple;             // iso: xyz; aniso: none (default), xy, yz, xz, xyz
  std::vector<int> move_sets;     // bit masks of the dimensions a move scales together

  // state (restart): counters and the random generator, identical on all ranks
  double nattempt = 0.0, naccept = 0.0, noverlap = 0.0;
  double block_attempt = 0.0, block_accept = 0.0;    // adaptation block
  RanPark *random = nullptr;
  double p_current = 0.0;
  double du_last = 0.0;    // U' - U of the last move tested for energy (output)

  std::vector<FixHardSphere *> hs;    // fixes whose spheres must not overlap
  HSPotential *pot = nullptr;         // the smooth energy (none: pure hard spheres)
  int smooth = 0;                     // 1 if there is a smooth potential energy
  class NeighList *list = nullptr;    // pairs within contact distance + skin
  double contact_max = 0.0;           // largest contact distance r_i + r_j
  double cut_max = 0.0;               // largest pair cutoff
  double length_min = 0.0;            // the shortest box length allowed
  bigint ngroup = 0;

  std::vector<double> xsave;          // x of owned + ghost atoms before a move

  // thermostat (held) forces at the step's end, kept through an accepted
  // move (drawing them again would halve the random kicks of that step);
  // per atom, migrating with the atoms at the rebuild
  int held = 0;
  double **fheld = nullptr;
  std::vector<double> fcons;    // scratch: conservative forces, owned atoms
  void save_held_forces();

  double volume() const;
  double target_pressure() const;
  void box_fix_error(Fix *other);
  void check_box(const double *prd_new, double vnew);
  void check_target(double pressure);
  int overlap_anywhere();
  void scale_box_and_atoms(const double *s, int set);
  void rebuild();
  void forces_after_move();
};

}    // namespace LAMMPS_NS

#endif
#endif
