#!/bin/bash
# Hard-core Yukawa fluid in NPT: in.hcy.npt (fix hardsphere/press beside
# cva + langevin) at the pressure P = Z rho T that the NVT MD of results.md
# measured at each state point; does the mean density come back to rho?
# Writes results_npt.md (analyze_npt.py).
#
#   bash examples/hard-core-yukawa/run_npt.sh
#   STATES="1.5:0.6:1.2042:0.0099" NRUN=20000 bash examples/hard-core-yukawa/run_npt.sh
#
# STATES: "T:rho:P:dP" (dP: the NVT pressure's standard error, from Z's).
# PAR=1 runs the states at the same time (one process each), else one after
# the other. Resumable: a finished run (RESULT line) is not repeated.
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
LMP=$ROOT/build/lmp
# P = Z rho T and dP = dZ rho T from the NVT MD of results.md
STATES=${STATES:-"1.5:0.3:0.30825:0.0018 1.5:0.6:1.2042:0.0099 2.0:0.7:4.2252:0.0294"}
EQUIL=${EQUIL:-5000}; NRUN=${NRUN:-30000}; EVERY=${EVERY:-2}
SCR=${SCR:-$HERE/scratch/npt}; OUT=${OUT:-$HERE/results_npt.md}
if [ ! -x "$LMP" ]; then
  (cd "$ROOT" && cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null && cmake --build build -j1)
fi
mkdir -p "$SCR"; cd "$SCR"
one() {
  IFS=: read -r T rho P dP <<< "$1"; tag=rho${rho}_T$T
  if [ "${FORCE:-0}" != 1 ] && [ -f log.npt.$tag ] && grep -q "^RESULT" log.npt.$tag; then return; fi
  echo "[$(date +%T)] NPT $tag P $P"
  nice -n 19 "$LMP" -in "$HERE/in.hcy.npt" -var rho "$rho" -var T "$T" -var P "$P" -var every "$EVERY" \
    -var equil "$EQUIL" -var nrun "$NRUN" -log log.npt.$tag -screen none
}
pids=""
for s in $STATES; do
  if [ "${PAR:-0}" = 1 ]; then one "$s" & pids="$pids $!"; else one "$s"; fi
done
for p in $pids; do wait $p; done
/usr/bin/python3 "$HERE/analyze_npt.py" "$SCR" "$OUT" "$STATES"
