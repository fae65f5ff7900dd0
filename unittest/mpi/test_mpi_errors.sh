#!/bin/bash
# Errors that only some ranks find reach the log (doc/fix_hardsphere.rst,
# "Restrictions"): an overlap at set-up, a sphere through a wall at set-up,
# an atom that may leave its neighbor list's skin, and atoms created after a run that the next run (pre no)
# would not know. Each case is built so that only rank 1 of 2 finds it, and
# runs with -screen none: with error->one() the message went to rank 1's
# screen only and the log ended without it.
#   bash test_mpi_errors.sh <lmp> <source dir>

source "$(dirname "${BASH_SOURCE[0]}")/lib/lib_mpi.sh"
mpi_init test_mpi_errors "$@"

# a 20 x 10 x 10 box cut at x = 10 on 2 ranks (processors * 1 1): rank 1
# owns x >= 10. Every atom is at x = 14-16, more than the ghost cutoff 2.8
# from both faces of rank 1: rank 0 has no atom and no ghost, before and
# after create_atoms, and finds nothing
header() {
  cat <<EOF
units       lj
atom_style  atomic
atom_modify map array
boundary    p p p
processors  * 1 1
region      box block 0 20 0 10 0 10
create_box  1 box
mass        1 1.0
pair_style  lj/cut 2.5
pair_coeff  1 1 1.0 1.0 2.5
neighbor    0.3 bin
timestep    0.005
EOF
}

# expect <name> <input> <pattern>: on 2 ranks the run fails and the log
# (rank 0's) has an ERROR line matching the pattern, on 1 rank the same
# message
expect() {
  local name=$1 input=$2 pattern=$3 np
  for np in 1 2; do
    rm -f log.$name.$np
    if [ "$np" -eq 1 ]; then
      "$LMP" -in "$input" -log log.$name.$np -screen none > out.$name.$np 2>&1
    else
      mpirun -np 2 --oversubscribe "$LMP" -in "$input" -log log.$name.$np -screen none \
        > out.$name.$np 2>&1
    fi
    local rc=$?
    if [ $rc -ne 0 ] && grep -q "^ERROR.*$pattern" log.$name.$np; then
      echo "  $name on $np ranks: the log names it: $(grep -m1 '^ERROR' log.$name.$np | cut -c1-110)..."
    else
      echo "FAIL: $name on $np ranks (exit $rc): no ERROR line matching '$pattern' in the log:"
      tail -5 log.$name.$np
      fail=1
    fi
  done
}

for method in cva pcva psa; do
  # two spheres closer than their diameter, on rank 1
  { header
    echo "create_atoms 1 single 15 2 2"
    echo "create_atoms 1 single 15.9 2 2"
    echo "fix hs all hardsphere/$method diameter 1.0"
    echo "run 10"; } > in.overlap_$method
  expect overlap_$method in.overlap_$method "atoms 1 and 2 overlap by .* at set-up"

  # a sphere through one of the fix's walls at set-up, on rank 1
  { header | sed 's/^boundary    p p p/boundary    p p f/'
    echo "create_atoms 1 single 15 5 9.8"
    echo "fix hs all hardsphere/$method diameter 1.0 wall zhi 9.5"
    echo "run 10"; } > in.wall_$method
  expect wall_$method in.wall_$method "atom 1 is .* through wall zhi at 9.5 on step 0 at set-up"

  # an atom on rank 1 whose step may take it farther than the skin
  # (dt |v| = 0.15 > 0.1)
  { header | sed 's/^neighbor .*/neighbor    0.1 bin/'
    echo "create_atoms 1 single 14 2 2"
    echo "create_atoms 1 single 15 5 5"
    echo "velocity all set 0 0 0"
    echo "group fast id 2"
    echo "velocity fast set 30 0 0"
    echo "fix hs all hardsphere/$method diameter 1.0"
    echo "run 10"; } > in.skin_$method
  expect skin_$method in.skin_$method "atom 2 may be 0.15.* more than the skin 0.1"

  # an atom created on rank 1 between runs, and a run that skips its set-up
  { header
    echo "create_atoms 1 single 14 5 5"
    echo "create_atoms 1 single 15.5 5 5"
    echo "velocity all set 0.1 0 0"
    echo "fix hs all hardsphere/$method diameter 1.0"
    echo "run 10"
    echo "create_atoms 1 single 15 2 2"
    echo "run 10 pre no"; } > in.prenoatoms_$method
  expect prenoatoms_$method in.prenoatoms_$method "owned and [0-9]* ghost atoms on rank [01] at step 11, .* when the neighbor lists were last built"
done

mpi_finish
