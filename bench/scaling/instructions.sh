#!/bin/bash
# bench/scaling/instructions.sh: instructions of LAMMPS' run loop (callgrind,
# collection limited to Verlet::run) for fix nve, cva-local and pcva-local on
# the fluid of run.sh: a deterministic before/after figure where the shared
# host's wall times cannot resolve a few per cent. Slow (valgrind, ~1 min per
# contender at 32000 atoms and 10 steps).
#
#   bash bench/scaling/instructions.sh                       # build/lmp, N=32000, STEPS=10
#   LMP=/path/to/old/lmp bash bench/scaling/instructions.sh  # another build
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
LMP=${LMP:-$ROOT/build/lmp}
N=${N:-32000}
STEPS=${STEPS:-10}
DATA=$HERE/scratch/fluid.$N.data
[ -f "$DATA" ] || { echo "no $DATA: run SIZES=$N REPEATS=1 bash bench/scaling/run.sh first"; exit 1; }
OUT=$HERE/scratch/callgrind
mkdir -p "$OUT"
for c in "nve:fix hs all nve" "cva-local:fix hs all hardsphere/cva diameter 1.0" \
         "pcva-local:fix hs all hardsphere/pcva diameter 1.0"; do
  name=${c%%:*}; fix=${c#*:}
  valgrind --tool=callgrind --callgrind-out-file="$OUT/cg.$name.out" --collect-atstart=no \
    --toggle-collect='LAMMPS_NS::Verlet::run(int)' "$LMP" -screen none -log "$OUT/log.$name" \
    -in "$HERE/in.run" -var data "$DATA" -var fixcmd "$fix" -var steps "$STEPS" \
    -var counts "$([[ $name == nve ]] && echo no || echo yes)" > "$OUT/valgrind.$name.txt" 2>&1
  echo "$name $(grep -m1 'Collected' "$OUT/valgrind.$name.txt" | awk '{print $4}') instructions ($STEPS steps, N $N)"
done
