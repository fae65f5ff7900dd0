#!/bin/bash
# bench/scaling/bitwise.sh: do two builds of lmp take the same trajectories? A change
# that only reorders memory accesses or fuses passes must leave every result bit for
# bit as it was; this compares the thermo output (%.15g every 5 steps) and the
# collision counts of 30 steps on the cases the engine's changes are checked on:
# the 32000-atom hard-core fluid with cva and pcva, the 4000-bead melt with pcva, and
# the melt with fix langevin for cva and pcva (held forces), and vci (the flows'
# energies) on the fluid and the melt, and mcva (its own cluster flows) on the fluid
# and on the melt with fix langevin, each on NPS ranks.
#   bash bench/scaling/bitwise.sh /path/to/old/lmp              # against build/lmp
#   NPS="1 2" bash bench/scaling/bitwise.sh OLD_LMP NEW_LMP
# Prints one line per case and rank count (same / DIFFERS) and exits 1 if any differs.
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
OLD=${1:?usage: bitwise.sh OLD_LMP [NEW_LMP]}
NEW=${2:-$ROOT/build/lmp}
NPS=${NPS:-"1 2 4"}
SCR=$HERE/scratch
OUT=$SCR/bitwise
mkdir -p "$OUT"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
# the systems of run.sh
for f in fluid.32000 melt.4000; do
  [ -f "$SCR/$f.data" ] || { echo "no $SCR/$f.data: run SIZES=32000 MELT=4000 REPEATS=1 bash bench/scaling/run.sh first"; exit 2; }
done
run() {    # run <lmp> <tag> <np> <system> <data> <fixcmd> [extra]
  local log=$OUT/log.$2.$3
  mpirun -np "$3" --oversubscribe "$1" -screen none -in "$HERE/in.run" -var system "$4" \
    -var data "$5" -var steps 30 -var counts yes -var thermo_every 5 -var fixcmd "$6" \
    -var extra "${7:-variable no_extra equal 0}" -log "$log" >/dev/null 2>&1 || true
  grep -E "^\s+[0-9]+ |^BENCH|ERROR" "$log" || true
}
lt="fix lg all langevin 1.0 1.0 1.0 48279"
cases=("cvaF|fluid|$SCR/fluid.32000.data|fix hs all hardsphere/cva diameter 1.0|"
       "pcvaF|fluid|$SCR/fluid.32000.data|fix hs all hardsphere/pcva diameter 1.0|"
       "pcvaM|melt|$SCR/melt.4000.data|fix hs all hardsphere/pcva diameter 0.9|"
       "cvaL|melt|$SCR/melt.4000.data|fix hs all hardsphere/cva diameter 0.9|$lt"
       "pcvaL|melt|$SCR/melt.4000.data|fix hs all hardsphere/pcva diameter 0.9|$lt"
       "vciF|fluid|$SCR/fluid.32000.data|fix hs all hardsphere/vci diameter 1.0|"
       "vciM|melt|$SCR/melt.4000.data|fix hs all hardsphere/vci diameter 0.9|"
       "mcvaF|fluid|$SCR/fluid.32000.data|fix hs all hardsphere/mcva diameter 1.0|"
       "mcvaL|melt|$SCR/melt.4000.data|fix hs all hardsphere/mcva diameter 0.9|$lt")
fail=0
for np in $NPS; do
  for c in "${cases[@]}"; do
    IFS='|' read -r name sys data fix extra <<<"$c"
    a=$(run "$OLD" "old.$name" "$np" "$sys" "$data" "$fix" "$extra")
    b=$(run "$NEW" "new.$name" "$np" "$sys" "$data" "$fix" "$extra")
    # a run that stopped has no BENCH line: not a comparison
    if ! grep -q BENCH <<<"$a" || ! grep -q BENCH <<<"$b"; then
      echo "$name on $np rank(s): a run did not finish (logs in $OUT)"; fail=1
    elif [ "$a" == "$b" ]; then
      echo "$name on $np rank(s): same ($(grep BENCH <<<"$b"))"
    else
      echo "$name on $np rank(s): DIFFERS (logs in $OUT)"; fail=1
    fi
  done
done
exit $fail
