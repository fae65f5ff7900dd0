#!/bin/bash
# fix hardsphere/psa gives the same trajectory on 1, 2 and 4 MPI ranks:
# identical collision counts and energies equal to round-off. Each rank keeps
# its own event queue; the globally earliest event is found by an Allreduce
# and its impulse (with the contact time and positions) broadcast.
#   bash test_mpi_psa.sh <lmp> <source dir>
# Systems: the 5-sphere pendulum chain (examples/pendulum-chain, walls,
# bonds, sphere-sphere and wall collisions), a periodic 3-D fluid of pure hard
# spheres (diameter 1, packing fraction 0.3: psa's own use case, event-driven
# with many collisions per step) and the hard-sphere + LJ fluid at density 0.6.
# Velocities use "loop geom" so the initial state does not depend on the rank
# count (with the default "loop all" the 1- and 2-rank runs of fix nve already
# differ by 1e-7 after one step).

source "$(dirname "${BASH_SOURCE[0]}")/lib/lib_mpi.sh"
mpi_init test_mpi_psa "$@"

chain_input > in.psa_chain
lj_fluid_input psa > in.psa_fluid

cat > in.psa_hs <<'EOF2'
units       lj
atom_style  atomic
boundary    p p p
lattice     fcc 0.572958
region      box block 0 5 0 5 0 5
create_box  1 box
create_atoms 1 box
mass        1 1.0
velocity    all create 1.0 4928 mom yes rot no dist gaussian loop geom
neighbor    0.3 bin
neigh_modify every 1 delay 0 check yes
comm_modify cutoff 1.7
fix         hs all hardsphere/psa diameter 1.0
timestep    0.01
thermo_style custom step ke press f_hs[1]
thermo_modify norm no
thermo      50
run         ${nsteps}
print "RESULT $(ke:%.17g) $(press:%.17g) $(f_hs[1]) $(f_hs[2]) $(f_hs[3]) $(f_hs[4])"
EOF2

# the RESULT fields: the first two to RTOL relative, the counters exactly
LABELS=("etotal|ke" "ke|press" "collisions" "pair" "wall" "coll.steps")

echo "pendulum chain (dt 0.02, T 100) on 1, 2, 4 ranks:"
check_system chain in.psa_chain "2 4" -var method psa -var dt 0.02 -var T 100 -var seed 1 -var every 1000
echo "periodic pure hard-sphere fluid (500 atoms, 100 steps) on 1, 2, 4 ranks:"
check_system hs in.psa_hs "2 4" -var nsteps 100
echo "periodic hard-sphere + LJ fluid (500 atoms, 200 steps) on 1, 2, 4 ranks:"
check_system fluid in.psa_fluid "2 4" -var nsteps 200

mpi_finish
