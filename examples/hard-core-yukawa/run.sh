#!/bin/bash
# Hard-core Yukawa fluid (kappa sigma = 1.8, rc = 4 sigma): MD with
# fix hardsphere/cva + fix langevin (in.hcy) against the NVT Metropolis MC
# of mc_hcy.cpp (built here with g++ -O2), same N = 500, same model, at the
# state points of STATES ("T:rho[:sweeps] ...": MC sweeps per state, default
# SWEEPS; MC equilibration sweeps/10). Writes results.md and the plots.
#
#   bash examples/hard-core-yukawa/run.sh
#   STATES="1.5:0.6" NRUN=20000 SWEEPS=10000 bash examples/hard-core-yukawa/run.sh
#   FORCE=1 ...      redo finished runs; QUICK=1 a smoke test in scratch/quick
#   SERIAL=1 the two lanes one after the other; NICE (10); LMP (build/lmp)
#   SCR (scratch/full): where the runs and machine.txt go
#
# Two lanes at once (the MD states one after the other, the MC states one
# after the other), resumable: a finished run (RESULT line) is not repeated.
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
LMP=${LMP:-$ROOT/build/lmp}    # LMP=path: another LAMMPS binary
STATES=${STATES:-"1.5:0.3 1.5:0.6 2.0:0.7:20000"}
if [ "${QUICK:-0}" = 1 ]; then
  SCR=$HERE/scratch/quick; EQUIL=500; NRUN=2000; SWEEPS=1000; OUT=$SCR/results.md
  STATES=$(echo $STATES | sed 's/\([^: ]*:[^: ]*\):[0-9]*/\1/g')    # QUICK: SWEEPS for all
else
  SCR=${SCR:-$HERE/scratch/full}; EQUIL=${EQUIL:-5000}; NRUN=${NRUN:-40000}
  SWEEPS=${SWEEPS:-30000}; OUT=${OUT:-$HERE/results.md}
fi
DT=${DT:-0.005}; DAMP=${DAMP:-2.0}

if [ ! -x "$LMP" ]; then
  (cd "$ROOT" && cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null && cmake --build build -j2)
fi
mkdir -p "$SCR"
cd "$SCR"
g++ -O2 -o mc_hcy "$HERE/mc_hcy.cpp"
echo "before: nproc $(nproc); load $(cut -d' ' -f1-3 /proc/loadavg); $(date -u '+%F %H:%M UTC')" > machine.txt
echo "settings: MD dt $DT, langevin damp $DAMP, equil $EQUIL + $NRUN steps; MC sweeps $SWEEPS (or per state: $STATES)" >> machine.txt

done_run() { [ "${FORCE:-0}" != 1 ] && [ -f "$1" ] && grep -q "^RESULT" "$1"; }

md_lane() {
  for s in $STATES; do
    IFS=: read -r T rho sw <<< "$s"; tag=rho${rho}_T$T
    done_run log.md.$tag && continue
    echo "[$(date +%T)] MD $tag"
    nice -n ${NICE:-10} "$LMP" -in "$HERE/in.hcy" -var rho "$rho" -var T "$T" -var dt "$DT" \
      -var damp "$DAMP" -var equil "$EQUIL" -var nrun "$NRUN" -log log.md.$tag -screen none
  done
}
mc_lane() {
  for s in $STATES; do
    IFS=: read -r T rho sw <<< "$s"; tag=rho${rho}_T$T; sw=${sw:-$SWEEPS}
    done_run mc.$tag.txt && continue
    echo "[$(date +%T)] MC $tag"
    nice -n ${NICE:-10} ./mc_hcy --rho "$rho" --T "$T" --sweeps "$sw" --equil $((sw / 10)) --blocks 100 \
      --seed 12345 --gr mcgr.$tag.txt > mc.$tag.tmp && mv mc.$tag.tmp mc.$tag.txt
  done
}
if [ "${SERIAL:-0}" = 1 ]; then    # SERIAL=1: one process at a time (a shared machine)
  md_lane; mc_lane
else
  md_lane & mdpid=$!
  mc_lane & mcpid=$!
  wait $mdpid; wait $mcpid
fi
echo "after: load $(cut -d' ' -f1-3 /proc/loadavg); $(date -u '+%F %H:%M UTC')" >> machine.txt
/usr/bin/python3 "$HERE/analyze.py" "$SCR" "$OUT" "$STATES"
