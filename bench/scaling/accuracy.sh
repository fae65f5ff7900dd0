#!/bin/bash
# The accuracy table of doc/fix_hardsphere.rst ("Step engines"): max energy
# error per atom over 0.5 time units, local and global cva, and Verlet alone
# (diameter 0.5: no sphere touches, fix nve's arithmetic), at three timesteps.
#   bash bench/scaling/accuracy.sh
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
LMP=${LMP:-$HERE/../../build/lmp}
printf "%-8s %-12s %-12s %-12s\n" dt local global "verlet(d=0.5)"
for dt in 0.01 0.005 0.0025; do
  row="$dt"
  for f in "diameter 1.0 substep local" "diameter 1.0 substep global" "diameter 0.5"; do
    e=$("$LMP" -in "$HERE/in.accuracy" -var dt $dt -var fixcmd "fix hs all hardsphere/cva $f" \
        -log none -echo none | awk '/^ACC/{print $3}')
    row="$row $e"
  done
  printf "%-8s %-12s %-12s %-12s\n" $row
done
