#!/bin/bash
# The hard-sphere equation of state at five pressures from fix hardsphere/press
# against Carnahan-Starling: runs in.hs-eos per pressure (1 rank, nice), then
# analyze.py writes results.md and eos.png. Logs and samples go to scratch/.
#   bash examples/hard-sphere-eos/run.sh
# Environment: PSTARS (default "1 2 5 8 10"), CELLS (fcc cells per side,
# default 5 = 500 spheres), NEQ, NPROD (steps), LMP (default build/lmp).
set -euo pipefail
HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
LMP=${LMP:-$ROOT/build/lmp}
PSTARS=${PSTARS:-"1 2 5 8 10"}
CELLS=${CELLS:-4}
NEQ=${NEQ:-30000}
NPROD=${NPROD:-200000}
cd "$HERE"
mkdir -p scratch
seed=4711
for p in $PSTARS; do
  seed=$((seed + 101))
  echo "P* = $p"
  nice -n 10 "$LMP" -in in.hs-eos -log "scratch/log.$p" -screen none -var pstar "$p" \
    -var seed "$seed" -var cells "$CELLS" -var neq "$NEQ" -var nprod "$NPROD" \
    -var out "scratch/vol.$p.txt"
  grep '^EOS' "scratch/log.$p"
done
/usr/bin/python3 analyze.py scratch $((4 * CELLS * CELLS * CELLS)) $PSTARS
