#!/bin/bash
# bench/scaling/ranks.sh: the local engine on 1 and 2 MPI ranks (issue 20).
# On the hard-core LJ fluid at SIZES atoms: fix nve, hardsphere/cva and
# hardsphere/pcva (their default, the local engine) on 1 and 2 ranks,
# repeats alternating the six runs; then 4 ranks (oversubscribed on a
# 2-core machine: correctness only, its collisions must equal 1 rank's).
# ranks_parse.py writes the table (ranks.md): per method and repeat the
# ratios m(1)/m(2) (speed-up), m/nve on 1 and on 2 ranks, medians and
# spreads, collisions per step on 1, 2, 4 ranks.
# Each timed run follows WARMUP untimed steps in the same process (default
# 5; WARMUP=0: none, the figures of before 2026-11-27 21:00): a run's first
# steps touch every per-copy array for the first time, ~80000 page faults
# at 256000 atoms, ~0.5 s of kernel time on one rank, as long as several
# steps, and on each of 2 ranks ~0.35 s, so that a short cold run
# understates the steady 2-rank speed-up.
# Timed steps: STEPS, default max(100, 4e6/N) (100 at 256000 atoms, 16 list
# rebuilds; 20 before 2026-11-29): the host's other jobs only add time, more
# of it to a 2-rank run, and a disturbance of a given length is a larger part
# of a short run (scaling README "How long, how many repeats").
#   bash bench/scaling/ranks.sh                       # SIZES="32000 256000" REPEATS=3
#   SIZES=32000 REPEATS=5 bash bench/scaling/ranks.sh
# A second run can add its repeats to the first's (ranks.md then pools both):
#   SIZES=256000 REPEATS=4 bash bench/scaling/ranks.sh
#   SIZES=256000 REPEATS=4 FIRST_REPEAT=5 KEEP_LOGS=1 bash bench/scaling/ranks.sh
# NEWTON=off: every run with LAMMPS' newton off (the local engine on several
# ranks since 30 Nov 2026); RESULTS=<file>: the table there instead of ranks.md
#   NEWTON=off SIZES=32000 RESULTS=/tmp/ranks-newtoff.md bash bench/scaling/ranks.sh
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
LMP=${LMP:-$ROOT/build/lmp}
SIZES=${SIZES:-"32000 256000"}
REPEATS=${REPEATS:-3}
WARMUP=${WARMUP:-5}
NEWTON=${NEWTON:-on}
RESULTS=${RESULTS:-$HERE/ranks.md}
SCR=$HERE/scratch
LOGS=$SCR/ranks-logs
mkdir -p "$SCR" "$LOGS"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
[ -x "$LMP" ] || (cd "$ROOT" && cmake -S . -B build >/dev/null && cmake --build build -j2)
FIRST_REPEAT=${FIRST_REPEAT:-1}
[ "${KEEP_LOGS:-0}" = 1 ] || rm -f "$LOGS"/log.*
cd "$SCR"
run() {    # run <np> <log> <N> <steps> <fix command>
  local np=$1 log=$2 N=$3 n=$4 fixcmd=$5 counts=no
  [[ "$fixcmd" == *hardsphere* ]] && counts=yes
  local engine=0    # the engine's first output entry (its balance entry: 10 after it)
  [[ "$fixcmd" == *hardsphere/cva* ]] && engine=6
  [[ "$fixcmd" == *hardsphere/pcva* ]] && engine=9
  mpirun -np "$np" --oversubscribe "$LMP" -screen none -in "$HERE/in.run" -var system fluid \
    -var data "$SCR/fluid.$N.data" -var steps "$n" -var counts $counts -var fixcmd "$fixcmd" \
    -var engine $engine \
    -var warmup "$WARMUP" -var newton "$NEWTON" -log "$log"
  grep -E "^Loop time|^BENCH" "$log" | tr '\n' ' '; echo
}
for N in $SIZES; do
  cells=$(/usr/bin/python3 -c "n=round(($N/4)**(1/3)); assert 4*n**3==$N, 'N must be 4 cells^3'; print(n)")
  if [ ! -f "$SCR/fluid.$N.data" ]; then
    echo "[$(date +%T)] equilibrating fluid N=$N (300 psa steps)"
    "$LMP" -screen none -in "$HERE/in.make-fluid" -var cells "$cells" -var out "$SCR/fluid.$N.data" \
      -log "$SCR/log.make-fluid.$N"
  fi
  steps=${STEPS:-$(/usr/bin/python3 -c "print(max(100, round(4e6/$N)))")}
  for k in $(seq "$FIRST_REPEAT" $((FIRST_REPEAT + REPEATS - 1))); do
    for np in 1 2; do
      for c in nve cva pcva; do
        if [ $c = nve ]; then f="fix hs all nve"; else f="fix hs all hardsphere/$c diameter 1.0"; fi
        echo "[$(date +%T)] N=$N repeat $k: $c on $np ranks ($steps steps)"
        run $np "$LOGS/log.$N.$k.$c.$np" "$N" "$steps" "$f"
      done
    done
  done
  for c in cva pcva; do
    echo "[$(date +%T)] N=$N: $c on 4 ranks (oversubscribed: collisions only)"
    run 4 "$LOGS/log.$N.1.$c.4" "$N" "$steps" "fix hs all hardsphere/$c diameter 1.0"
  done
done
/usr/bin/python3 "$HERE/ranks_parse.py" "$RESULTS" "$LOGS"
