#!/bin/bash
# Pure hard spheres against independent theory: pressure against
# Carnahan-Starling, collision rate against Enskog, at packing fractions
# 0.2 ... 0.45, with fix hardsphere/psa and fix hardsphere/cva, and LAMMPS'
# pseudo-hard-sphere model (pair mie/cut 50 49, fix nve, dt 0.001) at the
# same N and density; throughput of each in the same run. Writes
# examples/hard-spheres/results.md (logs in scratch/, git-ignored).
#
#   bash examples/hard-spheres/run.sh             # full run (~13 min on 2 busy cores)
#   QUICK=1 bash examples/hard-spheres/run.sh     # short smoke test
#   FORCE=1 ...                                   # redo finished runs too
#
# Resumable: a run whose log is complete is not repeated. Per packing
# fraction: in.prepare (random insertion + soft overlap removal), then
# psa (equilibration + production, writes its final state), then from that
# state mie (2 time units at kT = 1 by velocity rescaling, then plain NVE)
# and cva; in.order measures the mean Q6 of the start, after psa's
# equilibration and at its end.
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
LMP=$ROOT/build/lmp
N=${N:-2000}
ETAS=${ETAS:-"0.2 0.25 0.3 0.35 0.4 0.45"}
if [ "${QUICK:-0}" = 1 ]; then
  SCR=$HERE/scratch/quick; PSA_EQ=2; PSA_T=5; CVA_T=0.1; MIE_EQ=0.5; MIE_T=1; NB=20
else
  SCR=$HERE/scratch/full; PSA_EQ=${PSA_EQ:-50}; PSA_T=${PSA_T:-200}; CVA_T=${CVA_T:-5}
  MIE_EQ=${MIE_EQ:-2}; MIE_T=${MIE_T:-100}; NB=${NB:-100}
fi
OUT=${OUT:-$HERE/results.md}
[ "${QUICK:-0}" = 1 ] && OUT=${OUT_QUICK:-$SCR/results.md}

if [ ! -x "$LMP" ]; then
  (cd "$ROOT" && cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null && cmake --build build -j2)
fi
mkdir -p "$SCR"
cd "$SCR"
machine() {
  echo "nproc $(nproc); CPU $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//');" \
       "load average $(cut -d' ' -f1-3 /proc/loadavg); $(date -u '+%Y-%m-%d %H:%M UTC')"
}
echo "before: $(machine)" > machine.txt
echo "settings: N $N, psa: equilibration $PSA_EQ + production $PSA_T, cva: $CVA_T," \
     "mie: $MIE_EQ + $MIE_T (time units), $NB blocks" >> machine.txt

# reference: mean Q6 of a perfect fcc crystal at eta 0.45
[ -f "$SCR/log.order.fcc" ] || "$LMP" -in "$HERE/in.order" -var fcc 1 -log "$SCR/log.order.fcc" -screen none

done_log() { [ "${FORCE:-0}" != 1 ] && [ -f "$1" ] && grep -q "^RUN model" "$1"; }

for eta in $ETAS; do
  d=$SCR/eta$eta; mkdir -p "$d"
  if [ ! -f "$d/start.data" ] || [ "${FORCE:-0}" = 1 ]; then
    echo "[$(date +%T)] eta $eta: prepare"
    "$LMP" -in "$HERE/in.prepare" -var eta "$eta" -var N "$N" -var out "$d/start.data" \
      -log "$d/log.prepare" -screen none
    "$LMP" -in "$HERE/in.order" -var data "$d/start.data" -log "$d/log.order.start" -screen none
  fi
  if ! done_log "$d/log.psa"; then
    echo "[$(date +%T)] eta $eta: psa"
    "$LMP" -in "$HERE/in.hs" -var model psa -var data "$d/start.data" -var equil "$PSA_EQ" \
      -var prod "$PSA_T" -var nblocks "$NB" -var write 1 -var out "$d/psa.data" -log "$d/log.psa" -screen none
    "$LMP" -in "$HERE/in.order" -var data "$d/psa.data.equil" -log "$d/log.order.equil" -screen none
    "$LMP" -in "$HERE/in.order" -var data "$d/psa.data" -log "$d/log.order.psa" -screen none
  fi
  if ! done_log "$d/log.mie"; then
    echo "[$(date +%T)] eta $eta: mie"
    "$LMP" -in "$HERE/in.hs" -var model mie -var data "$d/psa.data" -var equil "$MIE_EQ" \
      -var prod "$MIE_T" -var nblocks "$NB" -log "$d/log.mie" -screen none
  fi
  if ! done_log "$d/log.cva"; then
    echo "[$(date +%T)] eta $eta: cva"
    "$LMP" -in "$HERE/in.hs" -var model cva -var data "$d/psa.data" -var equil 0.1 \
      -var prod "$CVA_T" -var nblocks "$NB" -log "$d/log.cva" -screen none
  fi
done
echo "after: $(machine)" >> machine.txt
/usr/bin/python3 "$HERE/analyze.py" "$SCR" "$OUT"
echo "wrote $OUT"
