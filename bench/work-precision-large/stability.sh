#!/bin/bash
# bench/work-precision-large/stability.sh: long-run stability of the
# collisional methods. NVE runs of STEPS (default 10^6) steps at dt 0.005 on
# the 500-atom hard-core fluid with the Gaussian attraction (the model of
# ../work-precision/pair.fluid; start state by ../work-precision/in.make-fluid,
# cells 5 = 500 atoms), E(t) per atom every 1000 steps to scratch/stab/e.*;
# stability.py writes stability.md and stability.png. Resumable (a run with a
# BENCH line is not redone). Serial, nice -n 19, one run at a time.
#
#   bash bench/work-precision-large/stability.sh                # cva pcva vci psa, 10^6 steps
#   METHODS="cva" STEPS=10000 bash bench/work-precision-large/stability.sh
#   CELLS=10 STEPS=100000 TAG=4000 bash ...                      # the 4000-atom runs
set -uo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
LMP=${LMP:-$ROOT/.lmp-frozen}
[ -x "$LMP" ] || LMP=$ROOT/build/lmp
METHODS=${METHODS:-"cva pcva vci psa"}
STEPS=${STEPS:-1000000}
CELLS=${CELLS:-5}
TAG=${TAG:-$((4 * CELLS * CELLS * CELLS))}
DT=${DT:-0.005}
SCR=$HERE/scratch/stab
mkdir -p "$SCR"
cd "$ROOT/bench/work-precision"
lmp() { nice -n 19 "$LMP" -screen none "$@"; }
data=$SCR/fluid$TAG.hs.data
if [ ! -s "$data" ]; then
  lmp -in in.make-fluid -var method hs -var cells "$CELLS" -var warm 10 -var out "$data" -log "$SCR/make.$TAG"
fi
echo "load $(date -u '+%Y-%m-%d %H:%M UTC') $(cut -d' ' -f1-3 /proc/loadavg)" >> "$SCR/machine.txt"
T=$(/usr/bin/python3 -c "print($STEPS*$DT)")
for m in $METHODS; do
  name=$TAG.$m.$DT.$STEPS
  log=$SCR/log.$name
  grep -q '^BENCH' "$log" 2>/dev/null && continue
  echo "[$(date -u +%T)] stability $name"
  lmp -in "$HERE/in.fluid-large" -var every 1000 -var Tw 50 -var method "$m" -var dt "$DT" -var T "$T" \
    -var data "$data" -var efile "$SCR/e.$name" -log "$log"
  grep -E '^BENCH|^ERROR|^Loop|CPU use' "$log" | cut -c1-170
done
echo "load_end $(date -u '+%Y-%m-%d %H:%M UTC') $(cut -d' ' -f1-3 /proc/loadavg)" >> "$SCR/machine.txt"
/usr/bin/python3 "$HERE/stability.py" "$SCR" "$HERE/stability.md" "$HERE/stability.png"
