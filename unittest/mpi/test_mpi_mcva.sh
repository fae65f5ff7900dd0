#!/bin/bash
# fix hardsphere/mcva's global form (substep global, the paper's algorithm)
# gives the same trajectory on 1 and 2 MPI ranks (the pendulum chain also
# on 4): identical collision counts and energies equal to round-off. The
# Gauss solves, the contact-time root finder and the modified impulse are
# collective, with the contact's atoms on any rank. (Its local form, the
# default: test_mpi_local.sh, section "mcva".)
#   bash test_mpi_mcva.sh <lmp> <source dir>
# Systems: the 5-sphere pendulum chain (examples/pendulum-chain: walls,
# bonds, sphere-sphere and wall collisions), and a small periodic 3-D fluid
# of hard spheres (diameter 1) with a short smoothly cut LJ attraction
# (lj/gromacs 0.9 1.2: the Gauss stages want a smooth field; and so the
# contact list has its own cutoff and the derivative layer a second list) at
# density 0.6. Velocities use "loop geom" (rank-independent initial state).
# The number of Gauss stage iterations may differ between rank counts (the
# convergence test sees round-off-level differences), so it is not compared.
# Sums over ranks (stage convergence, alpha-hat) round differently on other
# rank counts, and the chain is chaotic (differences grow ~10x per 5 time
# units): at T = 100 the 1- and 2-rank runs differ by ~1e-8 in ke, so the
# chain is compared at T = 40 (bit-identical on 2 and 4 ranks when written).

source "$(dirname "${BASH_SOURCE[0]}")/lib/lib_mpi.sh"
mpi_init test_mpi_mcva "$@"

chain_input 7 > in.mcva_chain

cat > in.mcva_fluid <<'EOF'
units       lj
atom_style  atomic
lattice     fcc 0.6
region      box block 0 3 0 3 0 3
create_box  1 box
create_atoms 1 box
mass        1 1.0
velocity    all create 1.5 87287 mom yes rot yes dist gaussian loop geom
pair_style  lj/gromacs 0.9 1.2
pair_coeff  1 1 1.0 1.0
comm_modify cutoff 1.7
neighbor    0.3 bin
neigh_modify every 1 delay 0 check yes
fix         hs all hardsphere/mcva diameter 1.0 substep global
timestep    0.005
thermo_style custom step pe ke etotal press f_hs[1]
thermo_modify norm no
thermo      50
run         ${nsteps}
print "RESULT $(etotal:%.17g) $(ke:%.17g) $(f_hs[1]) $(f_hs[2]) $(f_hs[3]) $(f_hs[4]) $(f_hs[7])"
EOF

# the LJ fluid of examples/thermostats (lj/cut 2.5 shifted: the force jumps
# at the cutoff), 108 atoms: the Gauss sub-steps freeze the cutoff set at
# their start (doc/fix_hardsphere_mcva.rst), with the pairs' ghosts on any
# rank; about 14 pairs cross the cutoff per step inside Gauss sub-steps
cat > in.mcva_ljcut <<'EOF'
units       lj
atom_style  atomic
atom_modify map array
lattice     fcc 0.8
region      box block 0 3 0 3 0 3
create_box  1 box
create_atoms 1 box
mass        1 1.0
pair_style  lj/cut 2.5
pair_coeff  1 1 1.0 1.0 2.5
pair_modify shift yes
neighbor    0.3 bin
neigh_modify every 1 delay 0 check yes
comm_modify cutoff 3.0
velocity    all create 1.5 12345 dist gaussian loop geom
timestep    0.005
fix         hs all hardsphere/mcva diameter 1.0 substep global
thermo_style custom step pe ke etotal f_hs[1] f_hs[12]
thermo_modify norm no
thermo      20
run         ${nsteps}
print "RESULT $(etotal:%.17g) $(ke:%.17g) $(f_hs[1]) $(f_hs[2]) $(f_hs[12]) $(f_hs[4]) $(f_hs[7])"
EOF

# the RESULT fields: the first two to RTOL relative, the counters exactly
# (ljcut: the fifth is the cutoff crossings, entry 12, instead of the wall
# collisions)
LABELS=("etotal" "ke" "collisions" "pair" "wall" "coll.steps" "gauss.substeps")
# the system must collide, and sub-step with Gauss
REF_CHECK='$3 > 0 && $7 >= $3'
REF_CHECK_MSG='no collisions / Gauss sub-steps'

echo "pendulum chain (mcva, dt 0.02, T 40) on 1, 2, 4 ranks:"
check_system chain in.mcva_chain "2 4" -var method mcva -var dt 0.02 -var T 40 -var seed 1 -var every 1000
echo "periodic hard-sphere + LJ fluid (108 atoms, 40 steps) on 1, 2 ranks:"
check_system fluid in.mcva_fluid "2" -var nsteps 40
echo "LJ fluid with lj/cut (108 atoms, 40 steps) on 1, 2 ranks:"
check_system ljcut in.mcva_ljcut "2" -var nsteps 40

mpi_finish
