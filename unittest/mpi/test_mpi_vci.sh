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
# spheres (diameter 1) with LJ attraction (lj/cut 2.5) at density 0.6; and
# the local form's "no root" warning on a dense fluid, once, in the log.
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

# the "no root" warning of the local form (printed once): a flow runs on one
# rank, so the warning used to come from the rank that ran it, once per
# rank, and never reached the log from any rank but 0. Now rank 0 prints
# the step's first (lowest contact ID) once: the same warning in the log on
# 1, 2 and 4 ranks. A dense hot fluid (fcc 0.859, T 2, 4000 atoms) has one
# on step 33 (atom IDs are not compared: create_atoms numbers the atoms
# rank by rank)
cat > in.vci_warn <<EOF
units lj
atom_style atomic
atom_modify map array
lattice fcc 0.859
region box block 0 10 0 10 0 10
create_box 1 box
create_atoms 1 box
mass 1 1
pair_style lj/cut 2.5
pair_coeff 1 1 1 1
pair_modify shift yes
neighbor 0.3 bin
velocity all create 2.0 4711 mom yes loop geom
fix hs all hardsphere/vci diameter 1.0
thermo 10
timestep 0.005
run 40
EOF
echo "the no-root warning of a dense fluid (4000 atoms, 40 steps) in the log, once, on 1, 2, 4 ranks:"
warn_ref=""
for np in 1 2 4; do
  mpirun -np "$np" --oversubscribe "$LMP" -in in.vci_warn -log log.vci_warn.$np -screen none > /dev/null 2>&1
  n=$(grep -c "^WARNING: .*no impulse strength" log.vci_warn.$np)
  # the step and the kind exactly, E_d- (a global sum) to RTOL
  w=$(grep "^WARNING: .*no impulse strength" log.vci_warn.$np | grep -o "on step [0-9]* ([a-z ]*, E_d- [-0-9.e]*")
  same=0
  if [ -n "$w" ] && [ -n "$warn_ref" ]; then
    same=$(awk -v a="$w" -v b="$warn_ref" -v tol="$RTOL" 'BEGIN {
      na = split(a, x, " "); split(b, y, " "); e = x[na] + 0; f = y[na] + 0
      sub(/E_d- .*/, "", a); sub(/E_d- .*/, "", b)
      d = e - f; if (d < 0) d = -d; s = f < 0 ? -f : f
      print (a == b && d <= tol * s) ? 1 : 0 }')
  fi
  if [ "$n" = 1 ] && [ -n "$w" ] && { [ -z "$warn_ref" ] || [ "$same" = 1 ]; }; then
    echo "  np=$np: one warning, $w: ok"
  else
    echo "  FAIL: np=$np: $n warnings in the log, '$w' (1 rank: '$warn_ref')"; fail=1
  fi
  [ "$np" = 1 ] && warn_ref=$w
done

mpi_finish

