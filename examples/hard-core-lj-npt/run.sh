#!/bin/bash
# Hard-core LJ fluid: fix hardsphere/press at each pressure (in.npt), then an
# NVT run at the mean density it sampled (in.nvt), whose pressure must give
# back the target. 1 rank, nice; logs and samples in scratch/; results.md.
#   bash examples/hard-core-lj-npt/run.sh
# Environment: PRESSURES (default "0.5 1.5 3"), T (2.0), CELLS (fcc cells
# per side, 4 = 256 atoms), NEQ, NPROD (NPT steps), NVTPROD, LMP (build/lmp).
set -euo pipefail
HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
LMP=${LMP:-$ROOT/build/lmp}
PRESSURES=${PRESSURES:-"0.5 1.5 3"}
T=${T:-2.0}
CELLS=${CELLS:-4}
NEQ=${NEQ:-20000}
NPROD=${NPROD:-400000}
NVTPROD=${NVTPROD:-200000}
cd "$HERE"
mkdir -p scratch
seed=4711
for p in $PRESSURES; do
  seed=$((seed + 101))
  nice -n 10 "$LMP" -in in.npt -log "scratch/log.npt.$p" -screen none -var T "$T" -var P "$p" \
    -var cells "$CELLS" -var seed "$seed" -var every 5 -var neq "$NEQ" -var nprod "$NPROD" \
    -var out "scratch/dens.$p.txt"
  grep '^NPT' "scratch/log.npt.$p"
  rho=$(/usr/bin/python3 analyze.py density "scratch/dens.$p.txt")
  nice -n 10 "$LMP" -in in.nvt -log "scratch/log.nvt.$p" -screen none -var T "$T" -var rho "$rho" \
    -var cells "$CELLS" -var seed "$((seed + 1))" -var neq 10000 -var nprod "$NVTPROD" \
    -var out "scratch/press.$p.txt"
  grep '^NVT' "scratch/log.nvt.$p"
done
/usr/bin/python3 analyze.py report scratch $((4 * CELLS * CELLS * CELLS)) "$T" $PRESSURES
