#!/bin/bash
# Depletion example: hard colloids with the AO tables of potentials/ (q 0.1
# and 0.2, contact value -3 kT) at low density, MD (in.ao) against the exact
# low-density expansion (virial.py). Writes results.md and gr.png.
#
#   bash examples/depletion/run.sh
#   STATES="0.2:0.02 0.2:0.05:0.0025" TRUN=200 bash examples/depletion/run.sh
#
# STATES: "q:rho[:dt]" (dt default 0.005); each run has TEQ + TRUN time
# units (50 + 500). One run at a time (nice), resumable (a run with a
# RESULT line is kept; FORCE=1 redoes it).
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
LMP=$ROOT/build/lmp
STATES=${STATES:-"0.1:0.02 0.1:0.05 0.2:0.02 0.2:0.05 0.1:0.02:0.0025 0.1:0.05:0.0025 0.2:0.05:0.0025"}
TRUN=${TRUN:-500}; TEQ=${TEQ:-50}
SCR=${SCR:-$HERE/scratch/full}; OUT=${OUT:-$HERE/results.md}
if [ ! -x "$LMP" ]; then
  (cd "$ROOT" && cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null && cmake --build build -j2)
fi
mkdir -p "$SCR"; cd "$SCR"
AN=""
for s in $STATES; do
  IFS=: read -r q rho dt <<< "$s"
  if [ -n "$dt" ]; then tag=q${q}_rho${rho}_dt$dt; AN="$AN $q:$rho:_dt$dt"
  else dt=0.005; tag=q${q}_rho$rho; AN="$AN $q:$rho"; fi
  nrun=$(awk -v t=$TRUN -v d=$dt 'BEGIN{printf "%d", t/d + 0.5}')
  neq=$(awk -v t=$TEQ -v d=$dt 'BEGIN{printf "%d", t/d + 0.5}')
  if [ "${FORCE:-0}" != 1 ] && [ -f log.$tag ] && grep -q "^RESULT" log.$tag; then continue; fi
  echo "[$(date +%T)] $tag"
  nice -n 10 "$LMP" -in "$HERE/in.ao" -var q "$q" -var rho "$rho" -var dt "$dt" -var root "$ROOT" \
    -var equil "$neq" -var nrun "$nrun" -var tag "$tag" -log log.$tag -screen none
done
/usr/bin/python3 "$HERE/analyze.py" "$SCR" "$OUT" "$AN"
