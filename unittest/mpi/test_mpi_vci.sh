#!/bin/bash
# fix hardsphere/vci gives the same trajectory on 1, 2 and 4 MPI ranks:
# identical collision counts and counts of solved contacts, energies equal
# to round-off (the discrete energies are global sums, the impulse strength
# comes from a root solve on them). The global sums round differently on 1
# and 2 ranks, and the chain is chaotic, so it is compared at T = 20 (see
# test_mpi_pcva.sh).
#   bash test_mpi_vci.sh <lmp> <source dir>
# Systems: the 5-sphere pendulum chain (examples/pendulum-chain, walls,
# bonds, sphere-sphere and wall collisions), and a periodic 3-D fluid of hard
# spheres (diameter 1) with LJ attraction (lj/cut 2.5) at density 0.6.
# Velocities use "loop geom" so the initial state does not depend on the rank
# count (with the default "loop all" the 1- and 2-rank runs of fix nve already
# differ by 1e-7 after one step).

source "$(dirname "${BASH_SOURCE[0]}")/lib/lib_mpi.sh"
mpi_init test_mpi_vci "$@"

chain_input 6 7 8 > in.vci_chain
lj_fluid_input vci 6 7 8 > in.vci_fluid

# the RESULT fields: the first two to RTOL relative, the counters exactly
LABELS=("etotal" "ke" "collisions" "pair" "wall" "coll.steps" "solved" "fallback" "tau2=0")

echo "pendulum chain (dt 0.02, T 20) on 1, 2, 4 ranks:"
check_system chain in.vci_chain "2 4" -var method vci -var dt 0.02 -var T 20 -var seed 1 -var every 1000
echo "periodic hard-sphere + LJ fluid (500 atoms, 100 steps) on 1, 2, 4 ranks:"
check_system fluid in.vci_fluid "2 4" -var nsteps 100

mpi_finish
