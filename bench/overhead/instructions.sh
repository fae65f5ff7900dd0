#!/bin/bash
# bench/overhead/instructions.sh: instructions of LAMMPS' run loop (callgrind,
# collection limited to Verlet::run) for fix nve and hardsphere/cva on the
# collision-free melt of run.sh: a deterministic before/after figure for the
# overhead where the shared host's wall times scatter by more than the changes
# move them. Serial, WARM warm-up steps (fix langevin) and N timed steps, both
# counted; the functions of the fix (and LAMMPS' own that differ) listed.
#   bash bench/overhead/instructions.sh                      # build/lmp, N=100 WARM=30
#   LMP=/path/to/old/lmp bash bench/overhead/instructions.sh # another build
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
LMP=${LMP:-$ROOT/build/lmp}
N=${N:-100}
WARM=${WARM:-30}
SCR=${SCR:-$HERE/scratch}
OUT=$SCR/callgrind
mkdir -p "$OUT"
[ -f "$SCR/chains.data" ] || /usr/bin/python3 "$HERE/make_data.py" "$SCR/chains.data"
for I in nve cva; do
  rm -f "$OUT/cg.$I"
  (cd "$SCR" && valgrind --tool=callgrind --callgrind-out-file="$OUT/cg.$I" --collect-atstart=no \
    --toggle-collect='LAMMPS_NS::Verlet::run(int)' "$LMP" -screen none -log "$OUT/log.$I" \
    -in "$HERE/in.lj-bonds" -var integrator $I -var data "$SCR/chains.data" -var N "$N" \
    -var warm "$WARM" > "$OUT/valgrind.$I.txt" 2>&1)
  callgrind_annotate --auto=no --threshold=100 --inclusive=no --show=Ir "$OUT/cg.$I" > "$OUT/self.$I.txt"
done
/usr/bin/python3 - "$OUT" <<'EOF'
import re, sys
out = sys.argv[1]
def load(f):
    d, total = {}, 0
    for line in open(f):
        m = re.match(r'\s*([\d,]+) \([^)]*\)\s+PROGRAM TOTALS', line)
        if m:
            total = int(m.group(1).replace(',', ''))
            continue
        m = re.match(r'\s*([\d,]+) \([^)]*\)\s+\S+:(.*)', line)
        if m:
            k = re.sub(r'\s*\[.*\]$', '', m.group(2).strip())
            d[k] = d.get(k, 0) + int(m.group(1).replace(',', ''))
    return d, total
a, ta = load(f'{out}/self.nve.txt')
b, tb = load(f'{out}/self.cva.txt')
print(f"instructions in Verlet::run: nve {ta/1e9:.3f}e9, cva {tb/1e9:.3f}e9, "
      f"cva / nve = {tb/ta:.4f} (+{(tb-ta)/1e6:.0f}e6)")
rows = sorted(set(a) | set(b), key=lambda k: -abs(b.get(k, 0) - a.get(k, 0)))
print("largest differences (1e6 instructions): nve, cva, function")
for k in rows[:15]:
    print(f"  {a.get(k, 0)/1e6:9.1f} {b.get(k, 0)/1e6:9.1f}  {k[:100]}")
EOF
