#!/bin/bash
# Cost per collision of fix hardsphere/cva (serial):
#  1. pendulum chain (bench/collision-cost/in.pendulum-chain), cva vs plain nve,
#     (t_cva - t_nve) / n_collisions
#  2. pure hard spheres at packing fraction 0.3 (in.hs-fluid): collisions per second
# Writes bench/collision-cost/results.md.
#
#   bash bench/collision-cost/run.sh          # PAIRS=3 T_PEND=20000 T_FLUID=50
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
LMP=$ROOT/build/lmp
PAIRS=${PAIRS:-3}
T_PEND=${T_PEND:-20000}     # time units; dt 0.01 -> 100 steps per unit
T_FLUID=${T_FLUID:-50}
SCR=$HERE/scratch

if [ ! -x "$LMP" ]; then
  (cd "$ROOT" && cmake -S . -B build >/dev/null && cmake --build build -j2)
fi
rm -rf "$SCR/logs"; mkdir -p "$SCR/logs"
cd "$SCR"
for k in $(seq 1 "$PAIRS"); do
  for I in nve cva; do
    echo "[$(date +%T)] pendulum pair $k: $I"
    "$LMP" -in "$HERE/in.pendulum-chain" -var integrator $I -var dt 0.01 -var T "$T_PEND" \
      -log "$SCR/logs/log.pend.$k.$I" -screen none
    grep -E "^Loop time|^BENCH" "$SCR/logs/log.pend.$k.$I"
  done
done
for k in $(seq 1 "$PAIRS"); do
  for I in nve cva; do
    echo "[$(date +%T)] hard-sphere fluid run $k: $I"
    "$LMP" -in "$HERE/in.hs-fluid" -var integrator $I -var T "$T_FLUID" \
      -log "$SCR/logs/log.fluid.$k.$I" -screen none
    grep -E "^Loop time|^BENCH" "$SCR/logs/log.fluid.$k.$I" | tail -2
  done
done
/usr/bin/python3 "$HERE/parse.py" "$HERE/results.md" "$SCR/logs"
