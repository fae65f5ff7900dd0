#!/usr/bin/env bash
# Reproduce Figures 4.2-4.5 of Bond & Leimkuhler (2007), section 4, on the
# impact pendulum chain, with every HARDSPHERE method, two runs at a time:
#
#   bash examples/pendulum-chain/run_figures.sh
#
# Runs go to scratch/ (git-ignored); a run whose scratch/runs/NAME.done exists
# is skipped, so an interrupted run_figures.sh resumes where it stopped.
# Then figures.py writes results/ (CSV, PNG, report.md).
# Environment: NPROC (parallel runs, default 2), LMP (default ../../build/lmp,
# built if missing), SCRATCH, SKIP_RUNS=1 (only re-make results/ from scratch/).
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
export LMP="${LMP:-$ROOT/build/lmp}"
export SCRATCH="${SCRATCH:-$HERE/scratch}"
NPROC="${NPROC:-2}"
S="$SCRATCH"
if [ ! -x "$LMP" ]; then
  cmake -S "$ROOT" -B "$ROOT/build" -DCMAKE_BUILD_TYPE=Release > /dev/null
  cmake --build "$ROOT/build" -j"$NPROC" --target lmp
fi
mkdir -p "$S/runs" "$S/series" "$S/vel" "$S/inputs" "$HERE/results"

METHODS="psa cva pcva mcva vci"
# Fig. 4.2/4.3: dt from 0.3 down to 0.001 (the paper's range), T = 5000
DTS="0.3 0.2 0.15 0.1 0.07 0.05 0.035 0.025 0.02 0.015 0.01 0.007 0.005 0.0035 0.0025 0.002 0.0015 0.001"
# two more initial conditions on a coarser grid (spread of the error curves)
DTS_EXTRA="0.1 0.05 0.02 0.01"
SEEDS_EXTRA="2 3"
# collision counts: CVA at dt 0.02 over six seeds for each input variant
COUNT_SEEDS="1 2 3 4 5 6"
VARIANTS="base wallc H2 k2 d095 n4"

# Input variants for the collision-count hypotheses (see report.md):
#  base  the example as it is, plus the distance of spheres 1 and 2 from the
#        anchor every step (how often they come within 0.9 of it)
#  wallc wall contact at the sphere centre (wall plane at x = -0.45)
#  H2    both initial speeds sqrt(2) (H(0) = 2 instead of 1)
#  k2    spring constant 2 (V = k (r - r0)^2 with k = 1, LAMMPS' convention)
#  d095  diameter 0.95
#  n4    "five spheres" counting the anchor: four moving spheres, the second
#        and fourth of the five (atoms 3 and 5 -> at x = 1 and 3: atoms 2, 4)
IN="$HERE/in.pendulum-chain"
sed 's#^run         $(round(v_T/v_dt))#variable r1 equal sqrt(x[2]^2+y[2]^2)\nvariable r2 equal sqrt(x[3]^2+y[3]^2)\nfix ro all ave/time 1 1 1 v_r1 v_r2 file ${rout}\n&#' "$IN" > "$S/inputs/in.base"
sed 's/wall xlo 0.0/wall xlo -0.45/' "$IN" > "$S/inputs/in.wallc"
sed 's/set $(cos(v_a2)) $(sin(v_a2)) 0/set $(sqrt(2)*cos(v_a2)) $(sqrt(2)*sin(v_a2)) 0/; s/set $(cos(v_a4)) $(sin(v_a4)) 0/set $(sqrt(2)*cos(v_a4)) $(sqrt(2)*sin(v_a4)) 0/' "$IN" > "$S/inputs/in.H2"
sed 's/^bond_coeff  1 0.5 1.0/bond_coeff  1 1.0 1.0/' "$IN" > "$S/inputs/in.k2"
sed 's/diameter 0.9 wall/diameter 0.95 wall/' "$IN" > "$S/inputs/in.d095"
sed '/^create_atoms 2 single 5 0 0/d; /^create_bonds single\/bond 1 5 6/d; s/^group       s2 id 3/group       s2 id 2/; s/^group       s4 id 5/group       s4 id 4/' "$IN" > "$S/inputs/in.n4"
for v in $VARIANTS; do
  if [ "$v" != base ] && cmp -s "$IN" "$S/inputs/in.$v"; then echo "variant $v: sed changed nothing" >&2; exit 1; fi
done

if [ "${SKIP_RUNS:-0}" != 1 ]; then {
  echo "nproc $(nproc)"
  grep -m1 "model name" /proc/cpuinfo
  echo "load before: $(cut -d' ' -f1-3 /proc/loadavg)"
  echo "start: $(date -u +%FT%TZ)"
  echo "lmp: $LMP"
  echo "commit: $(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo unknown)"
} > "$S/machine.txt"; fi

jobs="$S/jobs.txt"
{
  # seed 1 sweep first (Figures 4.2-4.4), then 4.5 (longest run first),
  # counts (all variants seed by seed, so a cut-short run has every variant),
  # extra seeds
  for m in $METHODS; do for dt in $DTS; do echo "sweep $m $dt 1"; done; done
  echo "vacf cva 0.01 1"
  for m in $METHODS; do echo "vacf $m 0.02 1"; done
  for s in $COUNT_SEEDS; do for v in $VARIANTS; do echo "count cva 0.02 $s $v"; done; done
  for s in $SEEDS_EXTRA; do for m in $METHODS; do for dt in $DTS_EXTRA; do echo "sweep $m $dt $s"; done; done; done
} > "$jobs"

if [ "${SKIP_RUNS:-0}" != 1 ]; then
  xargs -P "$NPROC" -L 1 bash "$HERE/run_one.sh" < "$jobs"
  echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)" >> "$S/machine.txt"
  echo "end: $(date -u +%FT%TZ)" >> "$S/machine.txt"
fi
/usr/bin/python3 "$HERE/figures.py" "$S" "$HERE/results"
