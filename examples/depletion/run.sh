#!/bin/bash
# Depletion example: hard colloids with the AO tables of potentials/ (q 0.1
# and 0.2, contact value -3 kT) at low density, MD (in.ao) against the exact
# low-density expansion (virial.py). Writes results.md and gr.png.
#
#   bash examples/depletion/run.sh
#   STATES="0.2:0.02 0.2:0.05" NRUN=100000 bash examples/depletion/run.sh
#
# One run at a time (nice), resumable (a run with a RESULT line is kept).
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
LMP=$ROOT/build/lmp
STATES=${STATES:-"0.1:0.02 0.1:0.05 0.2:0.02 0.2:0.05"}
NRUN=${NRUN:-200000}; EQUIL=${EQUIL:-10000}
SCR=${SCR:-$HERE/scratch/full}; OUT=${OUT:-$HERE/results.md}
if [ ! -x "$LMP" ]; then
  (cd "$ROOT" && cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null && cmake --build build -j2)
fi
mkdir -p "$SCR"; cd "$SCR"
for s in $STATES; do
  q=${s%%:*}; rho=${s##*:}; tag=q${q}_rho$rho
  if [ "${FORCE:-0}" != 1 ] && [ -f log.$tag ] && grep -q "^RESULT" log.$tag; then continue; fi
  echo "[$(date +%T)] $tag"
  nice -n 10 "$LMP" -in "$HERE/in.ao" -var q "$q" -var rho "$rho" -var root "$ROOT" \
    -var equil "$EQUIL" -var nrun "$NRUN" -log log.$tag -screen none
done
/usr/bin/python3 "$HERE/analyze.py" "$SCR" "$OUT" "$STATES"
