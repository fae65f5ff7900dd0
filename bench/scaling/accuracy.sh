#!/bin/bash
# The accuracy table of doc/fix_hardsphere.rst ("Step engines"): max energy
# error per atom over 0.5 time units, mean over 4 starting velocities (the max
# of one trajectory is set by a few events), for local and global cva and for
# Verlet alone (diameter 0.5: no sphere touches, fix nve's arithmetic).
#   bash bench/scaling/accuracy.sh
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
LMP=${LMP:-$HERE/../../build/lmp}
SEEDS=${SEEDS:-"111 222 333 444"}
printf "%-8s %-12s %-12s %-12s\n" dt local global "verlet(d=0.5)"
for dt in ${DTS:-0.01 0.005 0.0025 0.00125}; do
  row="$dt"
  for f in "diameter 1.0 substep local" "diameter 1.0 substep global" "diameter 0.5"; do
    sum=0; n=0
    for seed in $SEEDS; do
      e=$("$LMP" -in "$HERE/in.accuracy" -var seed $seed -var dt $dt \
          -var fixcmd "fix hs all hardsphere/cva $f" -log none -echo none | awk '/^ACC/{print $3}')
      sum=$(/usr/bin/python3 -c "print($sum + $e)"); n=$((n + 1))
    done
    row="$row $(/usr/bin/python3 -c "print('%.2e' % ($sum / $n))")"
  done
  printf "%-8s %-12s %-12s %-12s\n" $row
done
