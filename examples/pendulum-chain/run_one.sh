#!/usr/bin/env bash
# One run of the figure set (called by run_figures.sh through xargs -P).
#   run_one.sh KIND METHOD DT SEED [VARIANT]
# KIND: sweep (T = 5000, H and H_[2,VV] maxima, halt at 100 % energy error),
#       vacf  (T = 50000, velocity of the first sphere, no halt),
#       count (T = 5000, collision counts of an input VARIANT, see run_figures.sh).
# Skips the run if scratch/runs/NAME.done exists (resumable); writes the log
# to scratch/runs/NAME.log and "rc wall_seconds" to NAME.done.
set -uo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
S="${SCRATCH:-$HERE/scratch}"
LMP="${LMP:-$HERE/../../build/lmp}"
kind=$1 method=$2 dt=$3 seed=$4 variant=${5:-base}
name="${kind}_${method}_${dt}_${seed}"
[ "$kind" = count ] && name="${kind}_${variant}_${method}_${dt}_${seed}"
[ -e "$S/runs/$name.done" ] && exit 0
# another run_figures.sh may be running this very run
if [ -e "$S/runs/$name.running" ] && kill -0 "$(cat "$S/runs/$name.running")" 2> /dev/null; then exit 0; fi
echo $$ > "$S/runs/$name.running"
# neighbor skin: a sphere may move skin/2 per step at speed <= 2 (H <= 2)
skin=$(awk -v d="$dt" 'BEGIN { s = 6 * d; if (s < 0.3) s = 0.3; print s }')
input="$HERE/in.pendulum-chain"
args=(-var method "$method" -var dt "$dt" -var seed "$seed" -var box 30 -var skin "$skin")
case $kind in
  sweep)
    T=5000
    args+=(-var T $T -var hmod 1 -var halt 1)
    # the per-step series of Fig. 4.4 (dt 0.02, seed 1)
    if [ "$dt" = 0.02 ] && [ "$seed" = 1 ]; then args+=(-var out "$S/series/dE_${method}.txt"); fi ;;
  vacf)
    T=50000
    # velocity every 0.02 time units whatever dt is
    ve=$(awk -v d="$dt" 'BEGIN { printf "%d", 0.02 / d + 0.5 }')
    args+=(-var T $T -var vevery "$ve" -var vout "$S/vel/v_${method}_${dt}.txt" -var box 60) ;;
  count)
    T=5000
    input="$S/inputs/in.$variant"
    args+=(-var T $T -var rout "$S/series/r_${variant}_${seed}.txt") ;;
  *) echo "unknown kind $kind" >&2; exit 2 ;;
esac
every=$(awk -v T=$T -v d="$dt" 'BEGIN { n = int(T / d / 50 + 0.5); if (n < 1) n = 1; print n }')
t0=$(date +%s.%N)
"$LMP" -in "$input" -log none -echo none "${args[@]}" -var every "$every" > "$S/runs/$name.log" 2>&1
rc=$?
t1=$(date +%s.%N)
echo "$rc $(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.2f", b - a }')" > "$S/runs/$name.done"
rm -f "$S/runs/$name.running"
echo "$name rc $rc $(cut -d' ' -f2 "$S/runs/$name.done") s"
