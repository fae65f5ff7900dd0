#!/usr/bin/env bash
# Re-measures the table of issue 8: mean temperature of the 500-atom LJ
# fluid with hard cores (in.lj-thermostat) for every method and thermostat,
# with block-average error bars; writes results.md. Resumable: a finished
# run's output in out/ is kept.
#
#   bash examples/thermostats/run.sh            # all methods, all thermostats
#   METHODS="cva pcva" THERMOS="langevin" bash examples/thermostats/run.sh
#   THERMOS=langevin_spring NRUN=20000 OUT=/tmp/spring RESULTS=results-spring.md \
#     bash examples/thermostats/run.sh          # beside a held smooth force
#   NRUN_MCVA=2000 ...                          # mcva costs ~0.5 s per step here
#   METHODS=mcva ALL_MCVA=1 CELLS_MCVA=3 NRUN_MCVA=4000 bash examples/thermostats/run.sh
#                                               # mcva with 108 atoms (rows "mcva (108 atoms)")
#   METHODS=mcva ALL_MCVA=1 CELLS_MCVA=3 DAMP_MCVA=0.1 NRUN_MCVA=18000 \
#     THERMOS="langevin langevin_zero langevin_viscous" bash examples/thermostats/run.sh
#                                               # mcva's 1 % checks (damp 0.1: the temperature
#                                               # decorrelates 5x faster than at 0.5)
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
LMP="${LMP:-$ROOT/build/lmp}"
[ -x "$LMP" ] || bash "$ROOT/scripts/setup.sh"
METHODS="${METHODS:-nve psa cva pcva vci}"
THERMOS="${THERMOS:-langevin langevin_zero langevin_viscous berendsen rescale}"
NRUN="${NRUN:-6000}"
NRUN_MCVA="${NRUN_MCVA:-2000}"
OUT="${OUT:-$HERE/out}"
mkdir -p "$OUT"
cd "$OUT"
CELLS_MCVA="${CELLS_MCVA:-5}"
DAMP_MCVA="${DAMP_MCVA:-0.5}"
for th in $THERMOS; do
  for m in $METHODS; do
    # another size is kept under its own name: mcva108.<thermo>.out and
    # tblocks.mcva108.<thermo>.txt (parse.py labels it "mcva (108 atoms)")
    # (and another damping time as mcva108-damp0p1.<thermo>.out, ...)
    tag=$m; cells=5; damp=0.5
    if [ "$m" = mcva ] && [ "$CELLS_MCVA" != 5 ]; then
      cells=$CELLS_MCVA; tag="mcva$(( 4 * cells * cells * cells ))"
    fi
    # (no dot in a tag: parse.py splits the file names at dots)
    if [ "$m" = mcva ] && [ "$DAMP_MCVA" != 0.5 ]; then damp=$DAMP_MCVA; tag="${tag}-damp${damp//./p}"; fi
    f="$OUT/$tag.$th.out"
    if [ -f "$f" ] && grep -q '^RESULT' "$f"; then continue; fi
    n=$NRUN; eq=1000
    if [ "$m" = mcva ]; then n=$NRUN_MCVA; eq=500; fi
    # mcva only with langevin unless asked for: ~0.5 s per step
    if [ "$m" = mcva ] && [ "$th" != langevin ] && [ -z "${ALL_MCVA:-}" ]; then continue; fi
    echo "run: $tag $th ($n steps)"
    start=$(date +%s)
    # mcva: the global form, of which results.md's rows are (its default is
    # the local form since 2 Dec 2026: ENGINE_MCVA=default)
    eng=default
    [ "$m" = mcva ] && eng="${ENGINE_MCVA:-global}"
    "$LMP" -in "$HERE/in.lj-thermostat" -var method "$m" -var thermo "$th" -var nrun "$n" \
      -var equil "$eq" -var cells "$cells" -var damp "$damp" -var engine "$eng" -echo none -log none > "$f" 2>&1 \
      || { echo "FAILED: $tag $th"; tail -3 "$f"; }
    echo "SECONDS $(( $(date +%s) - start ))" >> "$f"
    if [ "$tag" != "$m" ] && [ -f "tblocks.$m.$th.txt" ]; then
      mv "tblocks.$m.$th.txt" "tblocks.$tag.$th.txt"
    fi
  done
done
RESULTS="${RESULTS:-results.md}"
/usr/bin/python3 "$HERE/parse.py" "$OUT" > "$HERE/$RESULTS"
cat "$HERE/$RESULTS"
