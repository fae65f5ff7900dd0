#!/bin/bash
# fix hardsphere/pcva gives the same trajectory on 1, 2 and 4 MPI ranks:
# identical collision and projection counts, energies equal to round-off
# (the projection's sums and the derivative layer are global reductions).
# Unlike cva's, the trajectories are not bitwise the same on 1 and 2 ranks:
# the global sums of the projection round differently (1 ulp in alpha), and
# the chain is chaotic (such a difference grows ~e-fold per 3 time units:
# 5e-3 in ke by T = 100), so the chain is compared at T = 20.
#   bash test_mpi_pcva.sh <lmp> <source dir>
# Systems: the 5-sphere pendulum chain (examples/pendulum-chain, walls,
# bonds, sphere-sphere and wall collisions), and a periodic 3-D fluid of hard
# spheres (diameter 1) with LJ attraction (lj/cut 2.5) at density 0.6.
# Velocities use "loop geom" so the initial state does not depend on the rank
# count (with the default "loop all" the 1- and 2-rank runs of fix nve already
# differ by 1e-7 after one step).

source "$(dirname "${BASH_SOURCE[0]}")/lib/lib_mpi.sh"
mpi_init test_mpi_pcva "$@"

chain_input 6 7 > in.pcva_chain
lj_fluid_input pcva 6 7 > in.pcva_fluid

# the RESULT fields: the first two to RTOL relative, the counters exactly
LABELS=("etotal" "ke" "collisions" "pair" "wall" "coll.steps" "projections" "skipped")

echo "pendulum chain (dt 0.02, T 20) on 1, 2, 4 ranks:"
check_system chain in.pcva_chain "2 4" -var method pcva -var dt 0.02 -var T 20 -var seed 1 -var every 1000
echo "periodic hard-sphere + LJ fluid (500 atoms, 100 steps) on 1, 2, 4 ranks:"
check_system fluid in.pcva_fluid "2 4" -var nsteps 100

mpi_finish
