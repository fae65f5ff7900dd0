#!/bin/bash
# fix hardsphere/cva gives the same trajectory on 1, 2 and 4 MPI ranks:
# identical collision counts and energies equal to round-off.
#   bash test_mpi_cva.sh <lmp> <source dir>
# Systems: the 5-sphere pendulum chain (examples/pendulum-chain, walls,
# bonds, sphere-sphere and wall collisions), and a periodic 3-D fluid of hard
# spheres (diameter 1) with LJ attraction (lj/cut 2.5) at density 0.6.
# Velocities use "loop geom" so the initial state does not depend on the rank
# count (with the default "loop all" the 1- and 2-rank runs of fix nve already
# differ by 1e-7 after one step). These compare the global engine (substep
# global); the local engine runs on one rank: on 2 ranks the default falls
# back to global with a warning and an explicit substep local is an error.

source "$(dirname "${BASH_SOURCE[0]}")/lib/lib_mpi.sh"
mpi_init test_mpi_cva "$@"

chain_input > in.cva_chain
lj_fluid_input cva > in.cva_fluid

# the RESULT fields: the first two to RTOL relative, the counters exactly
LABELS=("etotal" "ke" "collisions" "pair" "wall" "coll.steps")

echo "pendulum chain (dt 0.02, T 100) on 1, 2, 4 ranks:"
check_system chain in.cva_chain "2 4" -var method "cva substep global" -var dt 0.02 -var T 100 -var seed 1 -var every 1000
echo "periodic hard-sphere + LJ fluid (500 atoms, 200 steps) on 1, 2, 4 ranks:"
check_system fluid in.cva_fluid "2 4" -var nsteps 200

echo "substep local on 2 ranks:"
lj_fluid_input cva | sed 's/ substep global//' > in.cva_default
mpirun -np 2 --oversubscribe "$LMP" -in in.cva_default -var nsteps 20 -log none -echo none > out.cva_default 2>&1
if [ $? -eq 0 ] && grep -q "falls back to substep global" out.cva_default && grep -q "2 MPI ranks" out.cva_default; then
  echo "  default: falls back to global with a warning: ok"
else
  echo "  FAIL: default cva on 2 ranks did not fall back with a warning"; tail -5 out.cva_default; fail=1
fi
lj_fluid_input cva | sed 's/ substep global/ substep local/' > in.cva_local
mpirun -np 2 --oversubscribe "$LMP" -in in.cva_local -var nsteps 20 -log none -echo none > out.cva_local 2>&1
if [ $? -ne 0 ] && grep -q "substep local cannot run with 2 MPI ranks" out.cva_local; then
  echo "  explicit substep local: error naming the rank count: ok"
else
  echo "  FAIL: explicit substep local on 2 ranks gave no error naming the ranks"; tail -5 out.cva_local; fail=1
fi

mpi_finish
