#!/bin/bash
# Collisions per second of fix hardsphere/psa on pure hard spheres (no smooth
# forces: psa is then exact event-driven hard-sphere dynamics), against
# fix hardsphere/cva and fix nve (ideal gas: spheres pass through each
# other) on the same system, bench/psa/in.hs-fluid (packing fraction 0.3).
# Writes bench/psa/results.md.
#
#   bash bench/psa/run.sh          # REPS=3 NP2=1 (also psa on 2 ranks)
#
# Cases (name: spheres, skin, dt, timed T):
#   small:  500 spheres, skin 0.3, dt 0.01, T 10   (the setting of bench/collision-cost)
#   large: 4000 spheres, skin 0.3, dt 0.01, T 5    (cva: T 0.5, it is O(N) per collision)
#   tuned: 4000 spheres, skin 0.5, dt 0.04, T 5    (psa only: the flight is exact for any
#          dt, so dt is only bounded by the skin; fewer steps, fewer list builds)
#   tuned on 2 MPI ranks (psa only) when NP2=1
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
LMP=$ROOT/build/lmp
REPS=${REPS:-3}
NP2=${NP2:-1}
SCR=$HERE/scratch
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1

if [ ! -x "$LMP" ]; then
  (cd "$ROOT" && cmake -S . -B build >/dev/null && cmake --build build -j2)
fi
rm -rf "$SCR/logs"; mkdir -p "$SCR/logs"
cd "$SCR"

one() {    # one <label> <np> <integrator> <cells> <skin> <dt> <T>
  local label=$1 np=$2 I=$3 cells=$4 skin=$5 dt=$6 T=$7
  local log="$SCR/logs/log.$label.$I.$k"
  echo "[$(date +%T)] $label $I (np $np, run $k)"
  if [ "$np" -eq 1 ]; then
    "$LMP" -in "$HERE/in.hs-fluid" -var integrator $I -var cells $cells -var skin $skin \
      -var dt $dt -var T $T -var warm 1 -log "$log" -screen none
  else
    mpirun -np "$np" --oversubscribe "$LMP" -in "$HERE/in.hs-fluid" -var integrator $I \
      -var cells $cells -var skin $skin -var dt $dt -var T $T -var warm 1 -log "$log" -screen none
  fi
  grep -E "^Loop time|^BENCH" "$log" | tail -2
}

for k in $(seq 1 "$REPS"); do
  for I in nve cva psa; do one small 1 $I 5 0.3 0.01 10; done
  one large 1 nve 10 0.3 0.01 5
  one large 1 cva 10 0.3 0.01 0.5
  one large 1 psa 10 0.3 0.01 5
  one tuned 1 nve 10 0.5 0.04 5
  one tuned 1 psa 10 0.5 0.04 5
  if [ "$NP2" = 1 ]; then one tuned2 2 psa 10 0.5 0.04 5; fi
done
/usr/bin/python3 "$HERE/parse.py" "$HERE/results.md" "$SCR/logs"
