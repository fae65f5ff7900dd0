#!/bin/bash
# bench/scaling/large.sh: the local engine beyond 256000 atoms, with a thermostat.
# The 256000-atom fluid of run.sh and the same replicated 2 x 2 x 2 (2048000 atoms),
# fix nve and the METHODS (default cva; their default engine), each beside fix langevin (EXTRA,
# defined after the integrator: the held forces are f less LAMMPS' own conservative force,
# copied before the thermostat's; doc/fix_hardsphere.rst "Held forces"), on NP ranks,
# repeats alternating the runs. Prints per run the time per step,
# collisions and clusters per step, restricted evaluations per cluster and LAMMPS'
# memory per rank; then per size the medians and the cost per collision
# ((cva - nve) / collisions per step), which should not grow with N (issue 22).
#   bash bench/scaling/large.sh                      # NP=2 REPEATS=2 STEPS=10
#   EXTRA="variable none equal 0" bash bench/scaling/large.sh    # without the thermostat
#   LMP=/path/to/lmp REPS="1 2" METHODS="cva pcva vci" bash bench/scaling/large.sh
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
LMP=${LMP:-$ROOT/build/lmp}
NP=${NP:-2}
REPEATS=${REPEATS:-2}
STEPS=${STEPS:-10}
WARMUP=${WARMUP:-5}
REPS=${REPS:-"1 2"}
METHODS=${METHODS:-cva}
EXTRA=${EXTRA:-"fix lg all langevin 1.0 1.0 1.0 4321"}
SCR=$HERE/scratch
LOGS=$SCR/large-logs
mkdir -p "$LOGS"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
[ -x "$LMP" ] || (cd "$ROOT" && cmake -S . -B build >/dev/null && cmake --build build -j2)
[ -f "$SCR/fluid.256000.data" ] || { echo "no $SCR/fluid.256000.data: run SIZES=256000 REPEATS=1 bash bench/scaling/run.sh first"; exit 2; }
rm -f "$LOGS"/log.*
echo "$(date -u '+%F %H:%M UTC'), $NP ranks, $STEPS steps after $WARMUP, extra: $EXTRA, $LMP"
for k in $(seq 1 "$REPEATS"); do
  for rep in $REPS; do
    for c in nve $METHODS; do
      # (the engine's first output entry follows the method's own ones)
      case $c in
        nve) f="fix hs all nve"; counts=no; eng=0 ;;
        cva) eng=6 ;;
        pcva) eng=9 ;;
        vci) eng=12 ;;
        *) echo "large.sh: no engine entry known for method $c"; exit 2 ;;
      esac
      [ $c = nve ] || { f="fix hs all hardsphere/$c diameter 1.0"; counts=yes; }
      log=$LOGS/log.$c.$rep.$k
      mpirun -np "$NP" --oversubscribe "$LMP" -screen none -in "$HERE/in.run" -var system fluid \
        -var data "$SCR/fluid.256000.data" -var rep "$rep" -var steps "$STEPS" -var counts $counts \
        -var engine $eng -var fixcmd "$f" -var extra "$EXTRA" -var warmup "$WARMUP" -log "$log" \
        >/dev/null
    done
  done
done
/usr/bin/python3 - "$LOGS" "$STEPS" "$REPEATS" "$REPS" "$METHODS" <<'EOF'
import glob, re, statistics, sys
logs, steps, repeats, reps = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4].split()
methods = sys.argv[5].split()
def read(path):
    t = open(path).read()
    loop = re.findall(r'^Loop time of ([\d.eE+-]+) on \d+ procs for (\d+) steps with (\d+) atoms', t, re.M)[-1]
    mem = re.findall(r'Per MPI rank memory allocation \(min/avg/max\) = [\d.]+ \| ([\d.]+) \|', t)[-1]
    b = re.search(r'^BENCH collisions ([\d.eE+-]+)', t, re.M)
    e = re.search(r'^BENCH_ENGINE clusters ([\d.eE+-]+) evaluations ([\d.eE+-]+)', t, re.M)
    return dict(ms=1e3 * float(loop[0]) / int(loop[1]), n=int(loop[2]), mem=float(mem),
                coll=float(b.group(1)) / steps if b else 0.0,
                clus=float(e.group(1)) / steps if e else 0.0,
                ev=float(e.group(2)) / float(e.group(1)) if e and float(e.group(1)) else 0.0)
print("| N | run | repeat | ms/step | collisions/step | clusters/step | evaluations/cluster | MB/rank |")
print("|---|---|---|---|---|---|---|---|")
med = {}
for rep in reps:
    for c in ["nve"] + methods:
        rows = [read(f"{logs}/log.{c}.{rep}.{k}") for k in range(1, repeats + 1)]
        for k, r in enumerate(rows, 1):
            print(f"| {r['n']} | {c} | {k} | {r['ms']:.1f} | {r['coll']:.0f} | {r['clus']:.0f} | "
                  f"{r['ev']:.2f} | {r['mem']:.0f} |")
        med[rep, c] = (statistics.median(r['ms'] for r in rows), rows[0]['n'], rows[0]['coll'])
print()
print("| N | method | nve ms/step | method ms/step | method / nve | cost per collision (us) |")
print("|---|---|---|---|---|---|")
for m in methods:
    for rep in reps:
        (tn, n, _), (tc, _, coll) = med[rep, "nve"], med[rep, m]
        print(f"| {n} | {m} | {tn:.1f} | {tc:.1f} | {tc / tn:.2f} | {1e3 * (tc - tn) / coll:.1f} |")
EOF
