#!/bin/bash
# bench/scaling/held.sh: forces the local engine holds (kspace, fix efield) on charged hard
# spheres (in.held). Two parts:
#  cost:     seconds per step of fix nve (on a soft core, the same coul/long and kspace),
#            hardsphere/cva with substep local and (at sizes in GLOBAL_SIZES) substep global,
#            hardsphere/pcva with substep local (CONTENDERS: the list, default "nve local pcva"),
#            alternated, REPEATS times; ratios to fix nve from the same repeat
#  accuracy: the largest energy error per ion over T time units, cva local and pcva local
#            at each dt of DTS (and cva substep global at the dts of GLOBAL_DTS; ACC_METHODS), ACC_CELLS^3 ions, kspace ewald
#            (its forces are its energy's gradient; pppm's are not: an energy floor)
#   bash bench/scaling/held.sh                        # both parts
#   PART=cost SIZES="16 32" REPEATS=3 bash bench/scaling/held.sh
#   PART=cost THERMO=langevin CONTENDERS="nve local pcva pcva_global" SIZES=16 GLOBAL_SIZES="" \
#     REPEATS=2 bash bench/scaling/held.sh        # beside fix langevin (after the integrator)
#   PART=accuracy ACC_CELLS=10 DTS="0.01 0.005 0.0025" GLOBAL_DTS="0.01" bash bench/scaling/held.sh
#   PART=accuracy ACC_CELLS=16 RC=6.0 DTS="0.01 0.005" GLOBAL_DTS="" bash bench/scaling/held.sh
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
LMP=${LMP:-$ROOT/build/lmp}
PART=${PART:-all}
SIZES=${SIZES:-"16 32"}              # lattice cells per edge: 4096 and 32768 ions
GLOBAL_SIZES=${GLOBAL_SIZES:-"16"}
REPEATS=${REPEATS:-3}
CONTENDERS=${CONTENDERS:-"nve local pcva"}
ACC_METHODS=${ACC_METHODS:-"local pcva global"}    # local, global: cva; pcva: pcva local
STEPS=${STEPS:-100}
ACC_CELLS=${ACC_CELLS:-10}
DTS=${DTS:-"0.01 0.005 0.0025"}
GLOBAL_DTS=${GLOBAL_DTS:-"0.01"}
T=${T:-5}
RC=${RC:-4.0}                        # the coul/long cutoff (its kspace part the smoother, the larger)
THERMO=${THERMO:-none}               # langevin: fix langevin after the integrator (cost part)
OUT=$HERE/scratch/held
mkdir -p "$OUT"

# run <log> <vars...>: one run; prints "<s per step> <collisions> <fell back> <max dE>"
run() {
  local log=$1
  shift
  "$LMP" -in "$HERE/in.held" -log "$log" -screen none "$@" > /dev/null
  /usr/bin/python3 - "$log" <<'PY'
import re, sys
txt = open(sys.argv[1]).read()
loop = re.findall(r'Loop time of ([\d.e+-]+) on \d+ procs for (\d+) steps', txt)[-1]
held = re.search(r'HELD steps (\d+) collisions ([\d.e+]+) fellback ([\d.e+]+)', txt)
e = [float(l.split()[3]) for l in txt.splitlines()
     if re.match(r'^\s*\d+\s+\S+\s+\S+\s+\S+\s*$', l)]
de = max(abs(x - e[0]) for x in e) if e else float('nan')
print(f"{float(loop[0]) / int(loop[1]):.6g} {held.group(2)} {held.group(3)} {de:.3g}")
PY
}

if [ "$PART" = all ] || [ "$PART" = cost ]; then
  echo "## cost: seconds per step ($STEPS steps, dt 0.005, pppm 1e-4, E 0.2, thermostat $THERMO), $REPEATS alternated repeats"
  for n in $SIZES; do
    ions=$((n * n * n))
    contenders=$CONTENDERS
    for g in $GLOBAL_SIZES; do [ "$g" = "$n" ] && contenders="$contenders global"; done
    for r in $(seq 1 "$REPEATS"); do
      line="ions $ions repeat $r:"
      tnve=""
      for m in $contenders; do
        res=$(run "$OUT/log.cost.$n.$m.$r" -var n "$n" -var method "$m" -var dt 0.005 \
                -var T "$(/usr/bin/python3 -c "print($STEPS * 0.005)")" -var thermo "$THERMO")
        read -r t c fb _ <<< "$res"
        [ "$m" = nve ] && tnve=$t
        ratio=$(/usr/bin/python3 -c "print(f'{$t / $tnve:.2f}')")
        line+=" $m $t s (x$ratio nve, collisions $c, fell back $fb);"
      done
      echo "$line"
    done
  done
fi

if [ "$PART" = all ] || [ "$PART" = accuracy ]; then
  ions=$((ACC_CELLS * ACC_CELLS * ACC_CELLS))
  echo "## accuracy: largest |E(t) - E(0)| per ion over $T time units, $ions ions, ewald 1e-5, coul/long $RC"
  for m in $ACC_METHODS; do
    dts=$DTS
    [ "$m" = global ] && dts=$GLOBAL_DTS
    prev=""
    for dt in $dts; do
      res=$(run "$OUT/log.acc.$m.$dt" -var n "$ACC_CELLS" -var method "$m" -var dt "$dt" \
              -var T "$T" -var kspace "ewald 1e-5" -var rc "$RC")
      read -r t c fb de <<< "$res"
      line="$m dt $dt: max |dE| $de, collisions $c, fell back $fb, $t s per step"
      [ -n "$prev" ] && line+=" (order $(/usr/bin/python3 -c "import math; print(round(math.log2($prev / $de), 2))"))"
      echo "$line"
      prev=$de
    done
  done
fi
