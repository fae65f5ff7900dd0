#!/bin/bash
# bench/scaling: hardsphere/pcva's local projection on a melt with angle and
# dihedral terms (their energies and V''v by the styles' compute() on each
# term: hs_local_modified.cpp), against fix nve, cva local and (small N
# only) pcva global, which this system took before the local projection
# covered such terms. Serial; repeats alternate the contenders; ratios to
# fix nve within each repeat, medians and spreads.
#
#   bash bench/scaling/angles.sh                 # CHAINS="20 57" (4000, 32490 beads) REPEATS=3
#   CHAINS=20 REPEATS=3 STEPS=200 bash bench/scaling/angles.sh
#   GLOBAL_MAX=0 ...: pcva global left out (default: up to 4000 beads)
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
LMP=${LMP:-$ROOT/build/lmp}
CHAINS=${CHAINS:-"20 57"}
GLOBAL_MAX=${GLOBAL_MAX:-4000}
REPEATS=${REPEATS:-3}
NICE=${NICE:-10}
SCR=$HERE/scratch/angles
mkdir -p "$SCR"
cd "$SCR"
rm -f log.*
for n in $CHAINS; do
  N=$((n * n * 10))
  data=$SCR/angle-melt.$N.data
  if [ ! -f "$data" ]; then
    /usr/bin/python3 "$HERE/make_angle_melt.py" "$SCR/angle-melt.$N.lattice" "$n"
    echo "[$(date +%T)] equilibrating the melt N=$N (1000 steps of cva + langevin)"
    nice -n "$NICE" "$LMP" -screen none -in "$HERE/in.angle-melt" -var mode make \
      -var data "$SCR/angle-melt.$N.lattice" -var out "$data" -log "$SCR/make.$N"
  fi
  steps=${STEPS:-$(/usr/bin/python3 -c "print(max(20, round(8e5/$N)))")}
  for k in $(seq 1 "$REPEATS"); do
    for c in nve cva-local pcva-local pcva-global; do
      case $c in
        nve) fix="fix hs all nve"; s=$steps ;;
        cva-local) fix="fix hs all hardsphere/cva diameter 1.0 substep local"; s=$steps ;;
        pcva-local) fix="fix hs all hardsphere/pcva diameter 1.0 substep local"; s=$steps ;;
        pcva-global)
          [ "$N" -le "$GLOBAL_MAX" ] || continue
          fix="fix hs all hardsphere/pcva diameter 1.0 substep global"; s=$((steps / 10)) ;;
      esac
      counts=yes; [ "$c" = nve ] && counts=no
      echo "[$(date +%T)] N=$N repeat $k: $c ($s steps)"
      nice -n "$NICE" "$LMP" -screen none -in "$HERE/in.angle-melt" -var data "$data" \
        -var steps "$s" -var counts $counts -var fixcmd "$fix" -log "log.$N.$k.$c"
      grep -E "^Loop time|^BENCH" "log.$N.$k.$c" | tail -2 | tr '\n' ' '; echo
    done
  done
done
/usr/bin/python3 - "$SCR" <<'PY'
import glob, re, statistics, sys, os
scr = sys.argv[1]
t = {}
for f in glob.glob(os.path.join(scr, "log.*")):
    _, N, k, c = os.path.basename(f).split(".", 3)
    txt = open(f).read()
    loops = re.findall(r"Loop time of ([0-9.eE+-]+) on \d+ procs for (\d+) steps", txt)
    coll = re.findall(r"BENCH collisions ([0-9.eE+-]+)", txt)
    if not loops or not coll:
        continue
    sec, n = float(loops[-1][0]), int(loops[-1][1])
    t[(int(N), int(k), c)] = (1e3 * sec / n, float(coll[-1]) / n)
print("| N | contender | ms/step median (min..max) | / fix nve median (min..max) | collisions/step |")
print("|---|---|---|---|---|")
for N in sorted({key[0] for key in t}):
    for c in ["nve", "cva-local", "pcva-local", "pcva-global"]:
        reps = sorted(k for (n, k, cc) in t if n == N and cc == c)
        if not reps:
            continue
        ms = [t[(N, k, c)][0] for k in reps]
        r = [t[(N, k, c)][0] / t[(N, k, "nve")][0] for k in reps if (N, k, "nve") in t]
        col = statistics.median(t[(N, k, c)][1] for k in reps)
        print(f"| {N} | {c} | {statistics.median(ms):.3f} ({min(ms):.3f}..{max(ms):.3f}) | "
              f"{statistics.median(r):.2f} ({min(r):.2f}..{max(r):.2f}) | {col:.1f} |")
PY
