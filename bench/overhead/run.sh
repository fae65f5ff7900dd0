#!/bin/bash
# Overhead of fix hardsphere/cva over fix nve on a collision-free bead-spring
# melt (32000 atoms). Runs nve and cva alternately (A B A B ...), serial and
# on 2 MPI ranks, and writes bench/overhead/results.md.
#
#   bash bench/overhead/run.sh            # PAIRS=3 N=1000 WARM=200 NP2=1
#   PAIRS=5 N=2000 bash bench/overhead/run.sh
#   LMP=/path/to/other/lmp RESULTS=/tmp/r.md bash bench/overhead/run.sh   # another build
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
LMP=${LMP:-$ROOT/build/lmp}
PY=/usr/bin/python3
PAIRS=${PAIRS:-3}
N=${N:-1000}
WARM=${WARM:-200}
NP2=${NP2:-1}          # 0: skip the 2-rank variant
NP1=${NP1:-1}          # 0: skip the serial runs (re-parse old logs if present)
SCR=${SCR:-$HERE/scratch}

if [ ! -x "$LMP" ]; then
  (cd "$ROOT" && cmake -S . -B build >/dev/null && cmake --build build -j2)
fi
mkdir -p "$SCR"
[ -f "$SCR/chains.data" ] || $PY "$HERE/make_data.py" "$SCR/chains.data"

run_set () {   # $1 = dir, rest = launcher prefix
  local d=$1; shift
  rm -rf "$d"; mkdir -p "$d"
  for k in $(seq 1 "$PAIRS"); do
    for I in nve cva; do
      echo "[$(date +%T)] $(basename "$d") pair $k: $I"
      (cd "$SCR" && "$@" "$LMP" -in "$HERE/in.lj-bonds" -var integrator $I \
        -var data "$SCR/chains.data" -var N "$N" -var warm "$WARM" \
        -log "$d/log.$k.$I" -screen none)
      grep -E "^Loop time" "$d/log.$k.$I" | tail -1
    done
  done
}

SPECS=()
[ "$NP1" = 1 ] && run_set "$SCR/np1"
SPECS+=("serial:1:$SCR/np1")
if [ "$NP2" = 1 ]; then
  run_set "$SCR/np2" env OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpirun -np 2
  SPECS+=("2 ranks (mpirun -np 2):2:$SCR/np2")
fi
$PY "$HERE/parse.py" "${RESULTS:-$HERE/results.md}" "${SPECS[@]}"
