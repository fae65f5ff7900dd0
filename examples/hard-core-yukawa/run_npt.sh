#!/bin/bash
# Hard-core Yukawa fluid in NPT: in.hcy.npt (fix hardsphere/press beside
# cva + langevin) at the pressure P = Z rho T that the NVT MD of results.md
# measured at each state point; does the mean density come back to rho?
# Writes results_npt.md (analyze_npt.py).
#
#   bash examples/hard-core-yukawa/run_npt.sh
#   STATES="1.5:0.6:1.2042:0.0099" NRUN=20000 bash examples/hard-core-yukawa/run_npt.sh
#
#   PARTS=20 NRUN=30000 bash examples/hard-core-yukawa/run_npt.sh   # 20 x 30000 steps per state, in parts
#
# STATES: "T:rho:P:dP[:ref]" (dP: the NVT pressure's standard error, from
# Z's; rho: the fcc start's density and the tag; ref: the NVT density that
# P belongs to, when the run starts elsewhere, default rho).
# PAR=1 runs the states at the same time (one process each), else one after
# the other. Resumable: a finished run (RESULT line) is not repeated.
# PARTS=n: each state as part 0 (set-up, EQUIL steps, restart file) and
# parts 1..n of NRUN steps, each a LAMMPS process that continues from the
# restart file of the one before (in.hcy.npt -var part k): stop any time,
# run again to go on, raise PARTS to lengthen; the analysis takes the
# finished parts. Without PARTS: one run of EQUIL + NRUN steps, as before.
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
LMP=${LMP:-$ROOT/build/lmp}    # LMP=path: another LAMMPS binary
# P = Z rho T and dP = dZ rho T from the NVT MD of results.md
STATES=${STATES:-"1.5:0.3:0.30825:0.0018 1.5:0.6:1.2042:0.0099 2.0:0.7:4.2252:0.0294"}
EQUIL=${EQUIL:-5000}; NRUN=${NRUN:-30000}; EVERY=${EVERY:-2}
SCR=${SCR:-$HERE/scratch/npt}; OUT=${OUT:-$HERE/results_npt.md}
if [ ! -x "$LMP" ]; then
  (cd "$ROOT" && cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null && cmake --build build -j1)
fi
mkdir -p "$SCR"; cd "$SCR"
done_() { [ "${FORCE:-0}" != 1 ] && [ -f "$1" ] && grep -q "^RESULT" "$1"; }
one() {
  IFS=: read -r T rho P dP ref <<< "$1"; tag=rho${rho}_T$T
  if [ -z "${PARTS:-}" ]; then
    done_ log.npt.$tag && return
    echo "[$(date +%T)] NPT $tag P $P"
    nice -n 19 "$LMP" -in "$HERE/in.hcy.npt" -var rho "$rho" -var T "$T" -var P "$P" -var every "$EVERY" \
      -var equil "$EQUIL" -var nrun "$NRUN" -log log.npt.$tag -screen none
    return
  fi
  for k in $(seq 0 "$PARTS"); do
    done_ log.npt.$tag.$k && continue
    echo "[$(date +%T)] NPT $tag P $P part $k"
    nice -n 19 "$LMP" -in "$HERE/in.hcy.npt" -var rho "$rho" -var T "$T" -var P "$P" -var every "$EVERY" \
      -var equil "$EQUIL" -var nrun "$NRUN" -var part $k -log log.npt.$tag.$k -screen none
  done
}
pids=""
for s in $STATES; do
  if [ "${PAR:-0}" = 1 ]; then one "$s" & pids="$pids $!"; else one "$s"; fi
done
for p in $pids; do wait $p; done
/usr/bin/python3 "$HERE/analyze_npt.py" "$SCR" "$OUT" "$STATES"
