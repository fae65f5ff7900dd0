#!/bin/bash
# bench/scaling: time per step of the hard-sphere integrators against fix nve
# on the hard-core LJ fluid at several N and on a bead-spring melt with hard
# cores (serial). Contenders are the lines of contenders.txt; repeats alternate
# the contenders, parse.py takes medians and spreads and writes results.md.
#
#   bash bench/scaling/run.sh                        # SIZES="4000 32000 256000" MELT=4000 REPEATS=3
#   SIZES=4000 MELT=4000 REPEATS=3 bash bench/scaling/run.sh
#   PARSE_ONLY=1 bash bench/scaling/run.sh           # re-make results.md from the logs
#
# Variables: SIZES (fluid atom counts, 4 x cells^3), MELT (melt atom count, a
# multiple of 2000; 0 = no melt), REPEATS, STEPS (timed steps of a baseline run;
# default 2e6/N, at least 20), WARMUP (untimed steps before each timed run, in
# the same process, default 10: a run's first steps fault in and grow the
# engine's arrays and caches, ~1 s at 256000 atoms, which a 20-step timed run
# carried as ~15 % of cva's time there and a 500-step run at 4000 atoms as ~2 %;
# WARMUP=0: the figures of before 2026-12-03 17:30 UTC), NICE (nice level, 10), CONTENDERS (file),
# RESULTS (the table, default results.md), LOGS (default scratch/logs), BINARIES: other builds of lmp to
# compare in the same run, "KEY=PATH ..."; a contender named NAME@KEY runs
# with that binary (before/after a change, ratios within one repeat):
#   BINARIES="old=/tmp/lmp-old" CONTENDERS=my-contenders.txt bash bench/scaling/run.sh
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
LMP=${LMP:-$ROOT/build/lmp}
SIZES=${SIZES:-"4000 32000 256000"}
MELT=${MELT:-4000}
REPEATS=${REPEATS:-3}
WARMUP=${WARMUP:-10}
NICE=${NICE:-10}
CONTENDERS=$(realpath "${CONTENDERS:-$HERE/contenders.txt}")
RESULTS=$(realpath -m "${RESULTS:-$HERE/results.md}")
declare -A BIN=()
for kv in ${BINARIES:-}; do BIN[${kv%%=*}]=${kv#*=}; done
SCR=$HERE/scratch
LOGS=$(realpath -m "${LOGS:-$SCR/logs}")
mkdir -p "$SCR" "$LOGS"

if [ "${PARSE_ONLY:-0}" != 1 ]; then
  if [ ! -x "$LMP" ]; then
    (cd "$ROOT" && cmake -S . -B build >/dev/null && cmake --build build -j2)
  fi
  rm -f "$LOGS"/log.*
  cd "$SCR"
  run_lmp() { nice -n "$NICE" "$LMP" -screen none "$@"; }
  # the binary of a contender: NAME@KEY -> BINARIES' KEY, else $LMP
  lmp_of() {
    if [[ "$1" == *@* ]]; then
      local key=${1##*@}
      [ -n "${BIN[$key]:-}" ] || { echo "contender $1: no binary $key in BINARIES" >&2; exit 1; }
      echo "${BIN[$key]}"
    else echo "$LMP"; fi
  }

  # systems: "name natoms diameter datafile"
  systems=()
  for N in $SIZES; do
    cells=$(/usr/bin/python3 -c "n=round(($N/4)**(1/3)); assert 4*n**3==$N, 'N must be 4 cells^3'; print(n)")
    data=$SCR/fluid.$N.data
    if [ ! -f "$data" ]; then
      echo "[$(date +%T)] equilibrating fluid N=$N (300 psa steps)"
      run_lmp -in "$HERE/in.make-fluid" -var cells "$cells" -var out "$data" -log "$SCR/log.make-fluid.$N"
    fi
    systems+=("fluid $N 1.0 $data")
  done
  if [ "$MELT" -gt 0 ]; then
    data=$SCR/melt.$MELT.data
    if [ ! -f "$data" ]; then
      nz=$((MELT / 400))
      [ $((nz * 400)) -eq "$MELT" ] || { echo "MELT must be a multiple of 400 (20 x 20 x NZ)"; exit 1; }
      /usr/bin/python3 "$ROOT/bench/overhead/make_data.py" "$SCR/melt.$MELT.lattice" 20 20 "$nz" 0.85 10
      echo "[$(date +%T)] equilibrating melt N=$MELT (300 psa + langevin steps)"
      run_lmp -in "$HERE/in.make-melt" -var data "$SCR/melt.$MELT.lattice" -var out "$data" \
        -log "$SCR/log.make-melt.$MELT"
    fi
    systems+=("melt $MELT 0.9 $data")
  fi

  for sys in "${systems[@]}"; do
    read -r sname N diam data <<<"$sys"
    steps=${STEPS:-$(/usr/bin/python3 -c "print(max(20, round(2e6/$N)))")}
    for k in $(seq 1 "$REPEATS"); do
      while read -r name maxn factor fixcmd; do
        [[ -z "$name" || "$name" == \#* ]] && continue
        if [ "$maxn" != 0 ] && [ "$N" -gt "$maxn" ]; then continue; fi
        n=$(/usr/bin/python3 -c "print(max(5, round($steps*$factor)))")
        fixcmd=${fixcmd//DIAM/$diam}
        counts=no; [[ "$fixcmd" == *hardsphere* ]] && counts=yes
        log=$LOGS/log.$sname.$N.$k.$name
        echo "[$(date +%T)] $sname N=$N repeat $k: $name ($n steps)"
        nice -n "$NICE" "$(lmp_of "$name")" -screen none -in "$HERE/in.run" -var system "$sname" -var data "$data" -var steps "$n" \
          -var warmup "$WARMUP" -var counts $counts -var fixcmd "$fixcmd" -log "$log"
        grep -E "^Loop time|^BENCH" "$log" | tr '\n' ' '; echo
      done < "$CONTENDERS"
    done
  done
fi
/usr/bin/python3 "$HERE/parse.py" "$RESULTS" "$LOGS" "$CONTENDERS"
