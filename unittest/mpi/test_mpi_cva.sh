#!/bin/bash
# fix hardsphere/cva gives the same trajectory on 1, 2 and 4 MPI ranks:
# identical collision counts and energies equal to round-off.
#   bash test_mpi_cva.sh <lmp> <source dir>
# Systems: the 5-sphere pendulum chain (examples/pendulum-chain, walls,
# bonds, sphere-sphere and wall collisions), and a periodic 3-D fluid of hard
# spheres (diameter 1) with LJ attraction (lj/cut 2.5) at density 0.6.
# Velocities use "loop geom" so the initial state does not depend on the rank
# count (with the default "loop all" the 1- and 2-rank runs of fix nve already
# differ by 1e-7 after one step).

source "$(dirname "${BASH_SOURCE[0]}")/lib/lib_mpi.sh"
mpi_init test_mpi_cva "$@"

cat > in.cva_chain <<EOF
include ${SRC}/examples/pendulum-chain/in.pendulum-chain
print "RESULT \$(etotal:%.17g) \$(ke:%.17g) \$(f_hs[1]) \$(f_hs[2]) \$(f_hs[3]) \$(f_hs[4])"
EOF

cat > in.cva_fluid <<'EOF'
units       lj
atom_style  atomic
lattice     fcc 0.6
region      box block 0 5 0 5 0 5
create_box  1 box
create_atoms 1 box
mass        1 1.0
velocity    all create 1.5 87287 mom yes rot yes dist gaussian loop geom
pair_style  lj/cut 2.5
pair_coeff  1 1 1.0 1.0 2.5
neighbor    0.3 bin
neigh_modify every 1 delay 0 check yes
fix         hs all hardsphere/cva diameter 1.0
timestep    0.005
thermo_style custom step pe ke etotal press f_hs[1]
thermo_modify norm no
thermo      50
run         ${nsteps}
print "RESULT $(etotal:%.17g) $(ke:%.17g) $(f_hs[1]) $(f_hs[2]) $(f_hs[3]) $(f_hs[4])"
EOF

# the RESULT fields: the first two to RTOL relative, the counters exactly
LABELS=("etotal" "ke" "collisions" "pair" "wall" "coll.steps")

echo "pendulum chain (dt 0.02, T 100) on 1, 2, 4 ranks:"
check_system chain in.cva_chain "2 4" -var method cva -var dt 0.02 -var T 100 -var seed 1 -var every 1000
echo "periodic hard-sphere + LJ fluid (500 atoms, 200 steps) on 1, 2, 4 ranks:"
check_system fluid in.cva_fluid "2 4" -var nsteps 200

mpi_finish
