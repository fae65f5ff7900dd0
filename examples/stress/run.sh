#!/bin/bash
# Stability stress runs of the HARDSPHERE fixes (issue 4); the fast cases are
# ctest tests (unittest/lammps/test_stress_*.cpp, unittest/mpi/test_mpi_stress.sh).
#   bash examples/stress/run.sh              # all parts, 2 jobs at a time
#   PARTS="long scan" NP=1 bash examples/stress/run.sh
# Parts: long  (pendulum chain, 10^6 steps of dt 0.02, each method; cva and
#               psa also on 2 MPI ranks)
#        scan  (pendulum chain, T 1000, dt 0.05 ... 1.0, seeds 1-3: stability limit,
#               with the default skin 0.3 and with skin 2.0)
#        dimer (stiff bond near Verlet's limit dt = 2/omega, with and without contacts)
#        rest  (sphere pressed against a wall: resting contact)
# Each run writes scratch/out/<name>.txt (its STRESS or ERROR line); runs
# whose output exists are skipped (delete scratch/ to redo).  Then
# parse.py writes results.md.
set -uo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
LMP=$ROOT/build/lmp
NP=${NP:-2}
TIMEOUT=${TIMEOUT:-3000}            # seconds per run (long part)
TIMEOUT_SCAN=${TIMEOUT_SCAN:-60}    # per run of the other parts: a run stuck in a
                                    # runaway collision loop is recorded as "timeout"
PARTS=${PARTS:-"long scan dimer rest"}
METHODS=${METHODS:-"psa cva pcva mcva vci"}
SCR=$HERE/scratch
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1

if [ ! -x "$LMP" ]; then
  (cd "$ROOT" && cmake -S . -B build >/dev/null && cmake --build build -j2)
fi
mkdir -p "$SCR/out"
jobs=$SCR/jobs.txt
: > "$jobs"
# job <name> <ranks> <input> <vars...>
job() {
  local name=$1 np=$2 input=$3
  shift 3
  [ -s "$SCR/out/$name.txt" ] && return
  echo "$name $np $input $*" >> "$jobs"
}
for part in $PARTS; do
  case $part in
    long)
      for m in $METHODS; do
        job long.$m.np1 1 in.chain-long -var method $m -var dt 0.02 -var T 20000 -var seed 1
      done
      for m in cva psa; do
        job long.$m.np2 2 in.chain-long -var method $m -var dt 0.02 -var T 20000 -var seed 1
      done ;;
    scan)
      for m in $METHODS; do
        for dt in 0.05 0.1 0.15 0.2 0.25 0.3 0.4 0.5 0.6 0.7 0.8 0.9 1.0; do
          for s in 1 2 3; do
            job scan.$m.$dt.$s 1 in.chain-long -var method $m -var dt $dt -var T 1000 -var seed $s
            # skin 2: the method's own limit, not the neighbour list's
            job scanskin.$m.$dt.$s 1 in.chain-long -var method $m -var dt $dt -var T 1000 -var seed $s -var skin 2.0
          done
        done
      done ;;
    dimer)
      for m in $METHODS; do
        for amp in 0.05 0.2; do
          for hw in 0.1 0.5 1.0 1.5 1.9 1.99 2.01 2.1; do
            job dimer.$m.$amp.$hw 1 in.dimer -var method $m -var amp $amp -var hw $hw
          done
        done
      done ;;
    rest)
      for dt in 0.01 0.005 0.0025; do
        job rest.psa.$dt 1 in.resting -var method psa -var dt $dt -var T 1000
      done
      for m in $METHODS; do
        [ "$m" = psa ] && continue
        job rest.$m.0.01 1 in.resting -var method $m -var dt 0.01 -var T 10
      done ;;
  esac
done

runone() {
  local name=$1 np=$2 input=$3
  shift 3
  local log=$SCR/out/$name.log
  local tmo=$TIMEOUT_SCAN
  case $name in long.*) tmo=$TIMEOUT ;; esac
  if [ "$np" -gt 1 ]; then
    (cd "$HERE" && timeout "$tmo" mpirun -np "$np" --oversubscribe "$LMP" -in "$input" -log none -echo none "$@" > "$log" 2>&1)
  else
    (cd "$HERE" && timeout "$tmo" "$LMP" -in "$input" -log none -echo none "$@" > "$log" 2>&1)
  fi
  local rc=$?
  local res
  res=$(grep -m1 -E '^STRESS' "$log")
  if [ -z "$res" ]; then
    if [ $rc -eq 124 ]; then
      res="ERROR rc=124 timeout after ${tmo} s"
    else
      res="ERROR rc=$rc $(grep -m1 -E 'ERROR' "$log" | cut -c1-300)"
    fi
  fi
  echo "$name $res" > "$SCR/out/$name.txt"
  echo "[$(date +%T)] $name: $res"
}
export -f runone
export HERE LMP SCR TIMEOUT TIMEOUT_SCAN
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2), load $(cut -d' ' -f1-3 /proc/loadavg)" | tee "$SCR/machine.txt"
echo "$(wc -l < "$jobs") runs to do, $NP at a time"
# long runs first (they take longest)
xargs -P "$NP" -L 1 bash -c 'runone "$@"' _ < "$jobs"
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)" | tee -a "$SCR/machine.txt"
/usr/bin/python3 "$HERE/parse.py" "$SCR" "$HERE/results.md"
