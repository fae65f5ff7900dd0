#!/bin/bash
# bench/scaling/contention.sh: how much does a second busy core slow a
# serial run? On a machine whose cores share caches and memory, two ranks
# of one run can be no faster than two independent serial runs side by side;
# so 2 / (the slowdown of a run beside its twin) bounds the 2-rank speed-up
# the machine allows, whatever the code's parallel overhead (issue 20). For
# fix nve and hardsphere/cva (local engine) on the fluid of ranks.sh: one run
# alone, then two identical runs at once, REPEATS times alternating; prints
# per contender the median slowdown (loop time beside the twin / alone, both
# twins) with its spread, and the speed-up bound 2 / slowdown.
#   bash bench/scaling/contention.sh                 # N=256000 REPEATS=3 STEPS=30
#   N=32000 STEPS=100 bash bench/scaling/contention.sh
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
LMP=${LMP:-$ROOT/build/lmp}
N=${N:-256000}
REPEATS=${REPEATS:-3}
STEPS=${STEPS:-30}
SCR=$HERE/scratch
LOGS=$SCR/contention-logs
mkdir -p "$LOGS"
DATA=$SCR/fluid.$N.data
[ -f "$DATA" ] || { echo "no $DATA: run SIZES=$N REPEATS=1 bash bench/scaling/ranks.sh first"; exit 2; }
[ -x "$LMP" ] || (cd "$ROOT" && cmake -S . -B build >/dev/null && cmake --build build -j2)
run() {    # run <log> <fix command>
  "$LMP" -screen none -in "$HERE/in.run" -var system fluid -var data "$DATA" -var steps "$STEPS" \
    -var counts no -var fixcmd "$2" -log "$1" >/dev/null
  awk '/^Loop time/ {print $4}' "$1"
}
declare -A RATIOS
for k in $(seq 1 "$REPEATS"); do
  for c in nve cva; do
    if [ $c = nve ]; then f="fix hs all nve"; else f="fix hs all hardsphere/cva diameter 1.0"; fi
    alone=$(run "$LOGS/log.$c.$k.alone" "$f")
    run "$LOGS/log.$c.$k.twin1" "$f" > "$LOGS/t1" &
    run "$LOGS/log.$c.$k.twin2" "$f" > "$LOGS/t2"
    wait
    t1=$(cat "$LOGS/t1") t2=$(cat "$LOGS/t2")
    echo "[$(date +%T)] repeat $k $c: alone $alone s, beside its twin $t1 / $t2 s"
    RATIOS[$c]+="$(/usr/bin/python3 -c "print($t1/$alone, $t2/$alone)") "
  done
done
for c in nve cva; do
  /usr/bin/python3 - "$c" ${RATIOS[$c]} <<'EOF'
import statistics, sys
c, r = sys.argv[1], [float(v) for v in sys.argv[2:]]
m = statistics.median(r)
print(f"{c}: slowdown beside its twin {m:.3f} ({min(r):.3f}..{max(r):.3f}), "
      f"2-rank speed-up bound 2 / slowdown = {2 / m:.2f}")
EOF
done
