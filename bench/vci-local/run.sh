#!/bin/bash
# bench/vci-local: the energy error of hardsphere/vci in its local form
# (the default) against the paper's global form, hardsphere/cva (local) and
# fix nve on the same forces, on the 500-sphere hard-core fluid of the
# local-engine tests over T time units, at several timesteps and seeds
# (issue 21: the energy "floor" of the global form). README.md has the table.
#   bash bench/vci-local/run.sh        # T=5, dt 0.005 0.0025 0.00125, 4 seeds, ~10 min
# results.txt: method dt seed max|E(t)-E(0)|/N collisions solved noroot zero seconds;
# parse.py prints the means per method and dt and the fitted orders.
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
LMP=${LMP:-$ROOT/build/lmp}
T=${T:-5}
DTS=${DTS:-"0.005 0.0025 0.00125"}
SEEDS=${SEEDS:-"111 222 333 444"}
METHODS=${METHODS:-"nve cva-local vci-local vci-global"}
OUT=${OUT:-$HERE/results.txt}
[ -x "$LMP" ] || (cd "$ROOT" && bash scripts/setup.sh)
cd "$HERE"
: > "$OUT"
for dt in $DTS; do
  for seed in $SEEDS; do
    for m in $METHODS; do
      counts=1
      case $m in
        nve) f="fix hs all nve"; counts=0 ;;
        cva-local) f="fix hs all hardsphere/cva diameter 1.0" ;;
        vci-local) f="fix hs all hardsphere/vci diameter 1.0" ;;
        vci-global) f="fix hs all hardsphere/vci diameter 1.0 substep global" ;;
        *) echo "unknown method $m"; exit 1 ;;
      esac
      t0=$(date +%s.%N)
      "$LMP" -in in.fluid -screen none -log log.run -var cells 5 -var seed "$seed" -var dt "$dt" \
        -var T "$T" -var counts $counts -var fixcmd "$f" > /dev/null
      t1=$(date +%s.%N)
      res=$(grep '^RESULT' log.run | tail -1)
      line="$m $dt $seed ${res#RESULT } $(echo "$t1 - $t0" | bc)"
      echo "$line" | tee -a "$OUT"
    done
  done
done
rm -f log.run
/usr/bin/python3 "$HERE/parse.py" "$OUT"
