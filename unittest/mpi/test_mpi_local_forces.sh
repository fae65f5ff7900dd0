#!/bin/bash
# HSLocalForces (src/HARDSPHERE/hs_local_forces.h) on 2, 3 and 4 MPI ranks:
# runs the in-process test executable lammps_test_local_forces under mpirun.
# Every rank passes its own part of C; the forces on C must equal the full
# forces, LAMMPS' f and tallies must be unchanged, and V_C's total force
# (summed over ranks) must vanish (the fluid with newton on/off, the melt
# with bonds, angles and dihedrals, and after reneighboring). Rank-local rows
# (compute_rows(), issue 20): every rank passes random local copies, ghosts
# included; members get their full force, partners V_C's part (by tag).
# Their contact neighbours (set_near()) against a brute-force search.
#   bash test_mpi_local_forces.sh <lmp> <source dir>
LMP=${1:?usage: test_mpi_local_forces.sh <lmp> <source dir>}
EXE="$(dirname "$LMP")/unittest/lammps_test_local_forces"
if [ ! -x "$EXE" ]; then
  echo "FAIL: $EXE not built"
  exit 1
fi
fail=0
for np in 2 3 4; do
  out=$(mpirun -np "$np" --oversubscribe "$EXE" \
        --gtest_filter='*LocalForcesFluid*:*LocalForcesMelt*:LocalForces.AfterReneighboring:LocalForcesRows.GhostCopiesOnAnyRankCount:LocalForcesRows.NearRowsAreTheContactNeighbours:LocalForcesHybrid.*' 2>&1)
  npass=$(printf '%s\n' "$out" | grep -c 'PASSED.*8 tests')
  if [ "$npass" -eq "$np" ]; then
    echo "ok: $np ranks, 8 tests passed on every rank"
  else
    echo "FAIL: $np ranks"
    printf '%s\n' "$out" | grep -E 'Failure|Expected|actual|FAILED' | head -20
    fail=1
  fi
done
exit $fail
