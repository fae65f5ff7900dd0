#!/bin/bash
# bench/scaling/instructions.sh: instructions of LAMMPS' run loop (callgrind,
# collection limited to Verlet::run) for fix nve, cva-local and pcva-local on
# the fluid of run.sh: a deterministic before/after figure where the shared
# host's wall times cannot resolve a few per cent. Slow (valgrind, ~1 min per
# contender at 32000 atoms and 10 steps; ~2 min at 256000).
# NP > 1 runs each contender on NP MPI ranks and sums the ranks' counts; the
# "outside MPI" figure leaves out MPI's own functions (Open MPI's progress
# loops spin while a rank waits, so their count depends on the host's timing)
# and is the one to compare with 1 rank.
#
#   bash bench/scaling/instructions.sh                       # build/lmp, N=32000, STEPS=10
#   LMP=/path/to/old/lmp bash bench/scaling/instructions.sh  # another build
#   N=256000 NP=2 bash bench/scaling/instructions.sh         # 2 ranks (issue 20)
#   N=256000 CACHE=1 bash bench/scaling/instructions.sh      # + last-level cache misses
#   N=4000 STEPS=40 CONTENDERS=mcva-local bash bench/scaling/instructions.sh
#                        # others (issue 21): nve cva-local pcva-local mcva-local vci-local
# CACHE=1 adds callgrind's cache simulation with a 16 MB, 16-way last-level
# cache (this VM reports a 256 MB L3, in which every array fits) and reports
# its read and write misses: the memory traffic of the passes over all atoms,
# which instruction counts do not see (about 2x slower).
# OUT=DIR puts callgrind's files there (default scratch/callgrind): two builds
# measured at once, each with its own OUT, do not overwrite each other's.
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
LMP=${LMP:-$ROOT/build/lmp}
N=${N:-32000}
STEPS=${STEPS:-10}
NP=${NP:-1}
CACHE=${CACHE:-0}
CONTENDERS=${CONTENDERS:-"nve cva-local pcva-local"}
CACHEOPTS=()
[ "$CACHE" = 1 ] && CACHEOPTS=(--cache-sim=yes --LL=16777216,16,64)
DATA=$HERE/scratch/fluid.$N.data
[ -f "$DATA" ] || { echo "no $DATA: run SIZES=$N REPEATS=1 bash bench/scaling/run.sh first"; exit 1; }
OUT=${OUT:-$HERE/scratch/callgrind}
mkdir -p "$OUT"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
for name in $CONTENDERS; do
  case $name in
    nve) fix="fix hs all nve" ;;
    cva-local|pcva-local|mcva-local|vci-local) fix="fix hs all hardsphere/${name%-local} diameter 1.0" ;;
    *) echo "instructions.sh: unknown contender $name (nve, cva-local, pcva-local, mcva-local, vci-local)"; exit 1 ;;
  esac
  rm -f "$OUT/cg.$name".*
  mpirun -np "$NP" --oversubscribe valgrind --tool=callgrind "${CACHEOPTS[@]}" \
    --callgrind-out-file="$OUT/cg.$name.np$NP.%q{OMPI_COMM_WORLD_RANK}" --collect-atstart=no \
    --toggle-collect='LAMMPS_NS::Verlet::run(int)' "$LMP" -screen none -log "$OUT/log.$name" \
    -in "$HERE/in.run" -var data "$DATA" -var fixcmd "$fix" -var steps "$STEPS" \
    -var counts "$([[ $name == nve ]] && echo no || echo yes)" > "$OUT/valgrind.$name.txt" 2>&1
  # self counts of every function, summed over the ranks; MPI's own apart
  /usr/bin/python3 - "$name" "$N" "$STEPS" "$NP" "$OUT"/cg."$name".np"$NP".* <<'EOF'
import re, subprocess, sys
name, n, steps, np_ = sys.argv[1:5]
total = mpi = 0
llr = llw = 0
for f in sys.argv[5:]:
    # last-level misses, if the run simulated the cache
    tot = subprocess.run(['callgrind_annotate', '--auto=no', '--threshold=100', '--show=DLmr,DLmw', f],
                         capture_output=True, text=True).stdout
    m = re.search(r'^\s*([\d,]+) \([^)]*\)\s+([\d,]+) \([^)]*\)\s+PROGRAM TOTALS', tot, re.M)
    if m:
        llr += int(m.group(1).replace(',', ''))
        llw += int(m.group(2).replace(',', ''))
    out = subprocess.run(['callgrind_annotate', '--auto=no', '--threshold=100', '--inclusive=no', '--show=Ir', f],
                         capture_output=True, text=True, check=True).stdout
    for line in out.splitlines():
        m = re.match(r'\s*([\d,]+) \(\s*[\d.]+%\)\s+(\S.*)', line)
        if not m or 'PROGRAM TOTALS' in m.group(2):
            continue
        k = int(m.group(1).replace(',', ''))
        total += k
        # Open MPI / PMIx libraries (a function's signature may name ompi_*
        # types: match the library, not the name)
        if re.search(r'\[[^\]]*(libmpi|libopen-pal|libopen-rte|mca_|libpmix|libevent)[^\]]*\]$',
                     m.group(2)):
            mpi += k
print(f"{name} {total} instructions ({steps} steps, N {n}, {np_} rank(s); "
      f"outside MPI {total - mpi}, MPI {mpi})"
      + (f"; last-level misses read {llr}, write {llw}" if llr + llw else ""))
EOF
done
