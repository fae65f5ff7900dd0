#!/bin/bash
# bench/scaling/hybrid.sh: pair hybrid in the local engine. The fluid at SIZE
# atoms (in.make-fluid's data, two types) with lj/cut written as one style,
# pair hybrid, hybrid/overlay and hybrid/scaled (in.hybrid: the same forces),
# fix nve and hardsphere/cva and /pcva (their default engine), repeats
# alternating every run; per style the median ms/step of each fix and of
# method/nve over the repeats (spread min..max), collisions per step (equal
# for the four styles where the run is the same to round-off).
#   SIZE=32000 REPEATS=3 bash bench/scaling/hybrid.sh
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
LMP=${LMP:-$ROOT/build/lmp}
SIZE=${SIZE:-32000}
REPEATS=${REPEATS:-3}
STEPS=${STEPS:-$(( 4000000 / SIZE > 100 ? 4000000 / SIZE : 100 ))}
STYLES=${STYLES:-"plain hybrid overlay scaled"}
FIXES=${FIXES:-"nve cva pcva"}
SCR=$HERE/scratch
OUT=$SCR/hybrid-logs
mkdir -p "$OUT"
rm -f "$OUT"/log.*
[ -x "$LMP" ] || (cd "$ROOT" && cmake -S . -B build >/dev/null && cmake --build build -j2)
if [ ! -f "$SCR/fluid.$SIZE.data" ]; then
  cells=$(awk -v n="$SIZE" 'BEGIN { printf "%d", (n / 4) ^ (1 / 3) + 0.5 }')
  "$LMP" -screen none -in "$HERE/in.make-fluid" -var cells "$cells" -var out "$SCR/fluid.$SIZE.data" \
    -log "$SCR/log.make-fluid.$SIZE"
fi
for k in $(seq 1 "$REPEATS"); do
  for st in $STYLES; do
    for f in $FIXES; do
      "$LMP" -screen none -in "$HERE/in.hybrid" -var data "$SCR/fluid.$SIZE.data" -var style "$st" \
        -var fix "$f" -var steps "$STEPS" -log "$OUT/log.$st.$f.$k" > /dev/null
    done
  done
done
/usr/bin/python3 - "$OUT" "$SIZE" "$STEPS" "$STYLES" "$FIXES" <<'PY'
import glob, re, statistics, sys
out, size, steps, styles, fixes = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4].split(), sys.argv[5].split()
def read(path):
    t = re.findall(r"^Loop time of ([0-9.e+-]+)", open(path).read(), re.M)[-1]
    b = re.search(r"^BENCH collisions ([0-9.e+-]+) etotal ([-0-9.e+]+)", open(path).read(), re.M)
    return 1e3 * float(t) / steps, float(b.group(1)) / steps, b.group(2)
def med(v):
    return f"{statistics.median(v):.3g} ({min(v):.3g}..{max(v):.3g})"
print(f"## pair hybrid in the local engine: {size} atoms, {steps} timed steps\n")
head = "| style | " + " | ".join(f"{f} ms/step" for f in fixes) + " | " + \
    " | ".join(f"{f}/nve" for f in fixes if f != "nve") + " | collisions/step | etotal at the end |"
print(head)
print("|" + "---|" * (head.count("|") - 1))
for st in styles:
    runs = {f: [read(p) for p in sorted(glob.glob(f"{out}/log.{st}.{f}.*"))] for f in fixes}
    ms = {f: [r[0] for r in runs[f]] for f in fixes}
    row = [st] + [med(ms[f]) for f in fixes]
    for f in fixes:
        if f == "nve": continue
        row.append(med([a / b for a, b in zip(ms[f], ms["nve"])]))
    m = [f for f in fixes if f != "nve"]
    row.append(" / ".join(f"{runs[f][0][1]:.2f}" for f in m))
    row.append(" / ".join(runs[f][0][2] for f in m))
    print("| " + " | ".join(row) + " |")
PY
