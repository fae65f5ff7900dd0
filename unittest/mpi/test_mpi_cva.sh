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
# global); test_mpi_local.sh compares the local engine (the default).

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

echo "the default engine on 2 ranks is the local one (test_mpi_local.sh compares it):"
lj_fluid_input cva | sed 's/ substep global//; s/^atom_style  atomic/atom_style  atomic\natom_modify map array/' > in.cva_default
mpirun -np 2 --oversubscribe "$LMP" -in in.cva_default -var nsteps 20 -log none -echo none > out.cva_default 2>&1
if [ $? -eq 0 ] && grep -q "substep local (collisions sub-stepped per cluster)" out.cva_default && ! grep -q "falls back" out.cva_default; then
  echo "  default: local, no fall-back: ok"
else
  echo "  FAIL: default cva on 2 ranks did not take the local engine"; tail -5 out.cva_default; fail=1
fi
echo "pcva's default on 2 ranks is the local engine too (test_mpi_local.sh compares it):"
sed 's/hardsphere\/cva/hardsphere\/pcva/' in.cva_default > in.pcva_default
mpirun -np 2 --oversubscribe "$LMP" -in in.pcva_default -var nsteps 20 -log none -echo none > out.pcva_default 2>&1
if [ $? -eq 0 ] && grep -q "substep local (collisions sub-stepped per cluster)" out.pcva_default && ! grep -q "falls back" out.pcva_default; then
  echo "  pcva default: local, no fall-back: ok"
else
  echo "  FAIL: default pcva on 2 ranks did not take the local engine"; tail -5 out.pcva_default; fail=1
fi

mpi_finish
