#!/bin/bash
# bench/scaling/poly.sh: polydisperse spheres with per-atom radii (atom style
# sphere, in.poly) on 1 and 2 MPI ranks, fix nve (no hard cores) and
# hardsphere/cva and /pcva (their default engine), repeats alternating; then
# 4 ranks (oversubscribed: collisions only). Prints per run the loop time and
# the BENCH line (collisions, clusters, fall-backs to substep global).
#   CELLS=40 STEPS=100 REPEATS=3 bash bench/scaling/poly.sh
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
LMP=${LMP:-$ROOT/build/lmp}
CELLS=${CELLS:-40}
STEPS=${STEPS:-100}
REPEATS=${REPEATS:-3}
OUT=$HERE/scratch/poly-logs
mkdir -p "$OUT"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
run() {    # run <np> <method> <tag>
  local log=$OUT/log.$3
  if [ "$2" = nve ]; then
    sed 's/^fix            hs all hardsphere.*$/fix            hs all nve/; s/ f_hs\[1\]$//; /^if .*variable e equal/,$d' \
      "$HERE/in.poly" > "$OUT/in.poly.nve"
    mpirun -np "$1" --oversubscribe "$LMP" -screen none -in "$OUT/in.poly.nve" -var cells "$CELLS" \
      -var steps "$STEPS" -log "$log" > /dev/null
  else
    mpirun -np "$1" --oversubscribe "$LMP" -screen none -in "$HERE/in.poly" -var cells "$CELLS" \
      -var steps "$STEPS" -var method "$2" -log "$log" > /dev/null
  fi
  printf '%-5s %d rank(s): %s %s\n' "$2" "$1" "$(grep -h '^Loop time' "$log" | awk '{print $4 " s"}')" \
    "$(grep -h '^BENCH' "$log" || true)"
}
echo "$((CELLS ** 3)) spheres, $STEPS steps"
for k in $(seq 1 "$REPEATS"); do
  for np in 1 2; do
    for m in nve cva pcva; do run "$np" "$m" "$m.$np.$k"; done
  done
done
for m in cva pcva; do run 4 "$m" "$m.4"; done
