#!/bin/bash
# Held forces (doc/fix_hardsphere.rst, "Fixes beside the integrator") on 1,
# 2 and 4 MPI ranks: fix viscous is a velocity-dependent force, so it is held
# through collisional steps (two half kicks around the method's conservative
# step, separated from LAMMPS' total force by one conservative evaluation, or
# by the copy of f the integrator takes before a viscous fix defined after it);
# unlike langevin it is deterministic, so the trajectory must not depend on
# the rank count: collision counts identical, energies equal to round-off.
#   bash test_mpi_held.sh <lmp> <source dir>
# System: the periodic 3-D fluid of hard spheres (diameter 1) with LJ
# attraction of the other multi-rank tests, 500 atoms, plus fix viscous 0.2.

source "$(dirname "${BASH_SOURCE[0]}")/lib/lib_mpi.sh"
mpi_init test_mpi_held "$@"
# pcva and vci sum globally (projection, discrete energy): 1 ulp differences
# grow in a chaotic fluid; 100 steps keep them at round-off level
RTOL=1e-9
LABELS=("etotal" "ke" "collisions" "pair" "wall" "coll.steps")

for method in cva pcva vci; do
  lj_fluid_input "$method" | sed 's/^fix         hs all hardsphere/fix         vi all viscous 0.2\nfix         hs all hardsphere/' > in.held_$method
  # the log line that names the held fix
  echo "fluid + fix viscous, $method, 100 steps, on 1, 2, 4 ranks:"
  check_system "held_$method" in.held_$method "2 4" -var nsteps 100
  if ! grep -q "forces of fix vi viscous held" out.held_$method.1; then
    echo "FAIL: $method did not report fix vi viscous as held"
    fail=1
  fi
  # the local engine with fix viscous after the integrator: its post_force()
  # copies LAMMPS' f before the viscous force is added, and the held force is
  # f less that copy (no evaluation of the members' terms); the same on
  # every rank count
  lj_fluid_input "$method" | sed -e 's/ substep global//' \
    -e 's/^\(fix         hs all hardsphere.*\)$/\1\nfix         vi all viscous 0.2/' > in.held_after_$method
  echo "fluid + fix viscous after the integrator, $method, substep local, 100 steps, on 1, 2, 4 ranks:"
  check_system "held_after_$method" in.held_after_$method "2 4" -var nsteps 100
  if grep -q "a second evaluation of the conservative forces" out.held_after_$method.1 ||
     ! grep -q "forces of fix vi viscous held" out.held_after_$method.1; then
    echo "FAIL: $method with fix viscous after it did not take LAMMPS' conservative forces"
    fail=1
  fi
done

mpi_finish
