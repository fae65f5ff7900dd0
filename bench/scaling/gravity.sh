#!/bin/bash
# bench/scaling/gravity.sh: fix gravity in the local engine (in.gravity). The largest
# energy error per atom (etotal with fix gravity's energy, every 20 steps) over T time
# units of a fluid of about 4 CELLS^3 spheres settling onto a wall, hardsphere/cva (its default engine)
# and fix nve + fix wall/reflect on the same forces, per seed and dt, and cva's observed
# order log2(err(dt) / err(dt/2)).
#   SEEDS="111 222" DTS="0.005 0.0025" T=5 CELLS=10 bash bench/scaling/gravity.sh
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
LMP=${LMP:-$ROOT/build/lmp}
SEEDS=${SEEDS:-"111 222"}
DTS=${DTS:-"0.005 0.0025"}
T=${T:-5}
CELLS=${CELLS:-10}
for s in $SEEDS; do
  prev=""
  for m in cva nve; do
    for dt in $DTS; do
      steps=$(/usr/bin/python3 -c "print(round($T / $dt))")
      err=$("$LMP" -in "$HERE/in.gravity" -var cells "$CELLS" -var method "$m" -var seed "$s" \
              -var dt "$dt" -var steps "$steps" -log none 2>&1 |
            awk 'NF == 4 && $1 ~ /^[0-9]+$/' |
            awk 'NR == 1 { e0 = $4 } { d = $4 - e0; if (d < 0) d = -d; if (d > m) m = d } END { printf "%.3g", m }')
      line="$m seed $s dt $dt: max |dE| per atom $err"
      if [ "$m" = cva ] && [ -n "$prev" ]; then
        line+=" (order $(/usr/bin/python3 -c "import math; print(round(math.log2($prev / $err), 2))"))"
      fi
      echo "$line"
      [ "$m" = cva ] && prev=$err
    done
    prev=""
  done
done
