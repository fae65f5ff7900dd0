#!/bin/bash
# vci-floor.sh: issue 21's "vci floor" on the work-precision fluid (hard
# spheres + Gaussian attraction at contact, packing 0.3, kT 1): max
# |E(t)-E(0)| per atom and the pressure error over the T = 0.4 window of
# results.md, for hardsphere/vci substep global, vci substep local (its
# default), cva (default: local) and cva substep global, at several dt, on
# 2916 spheres (results.md's system) and 500 spheres; per-step traces for
# the jump/drift analysis (vci-floor.py). Serial runs, one at a time.
# Writes vci-floor.md's tables to $OUT/tables.md (not to the repo).
#
#   OUT=/tmp/vcifloor bash bench/work-precision/vci-floor.sh      # ~10 min
#   PARSE_ONLY=1 OUT=/tmp/vcifloor bash bench/work-precision/vci-floor.sh
#   LMP=/path/to/lmp ...     (default: build/lmp of this checkout)
set -uo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
LMP=${LMP:-$ROOT/build/lmp}
OUT=${OUT:-/tmp/vcifloor}
T=${T:-0.4}
DTS=${DTS:-"0.005 0.0025 0.00125 0.000625"}
mkdir -p "$OUT/logs" "$OUT/traces"
cd "$HERE"      # in.vci-floor includes pair.fluid by a relative path

one() {   # one <cells> <method> <substep> <dt>
  local c=$1 m=$2 s=$3 dt=$4 tag="$1.$2.$3.$4"
  [ -s "$OUT/logs/log.$tag" ] && grep -q '^FLOOR' "$OUT/logs/log.$tag" && return
  echo "[$(date -u +%T)] cells $c $m substep $s dt $dt"
  "$LMP" -in in.vci-floor -var method "$m" -var substep "$s" -var dt "$dt" -var T "$T" \
    -var data "$OUT/fluid.$c.data" -var tfile "$OUT/traces/tr.$tag" \
    -log "$OUT/logs/log.$tag" -screen none
  grep -E '^FLOOR|^ERROR' "$OUT/logs/log.$tag" | tail -1 | cut -c1-220
}

if [ "${PARSE_ONLY:-0}" != 1 ]; then
  { echo "start $(date -u '+%F %T UTC')"; echo "commit $(git -C "$ROOT" rev-parse --short HEAD)"
    echo "lmp $LMP $(md5sum < "$LMP" | cut -c1-12)"; } >> "$OUT/machine.txt"
  # start states: in.make-fluid (psa, kT 1, 10 time units) with 9^3 and 5^3 fcc cells
  for c in 9 5; do
    [ -s "$OUT/fluid.$c.data" ] || "$LMP" -in in.make-fluid -var method hs -var cells $c -var warm 10 \
      -var out "$OUT/fluid.$c.data" -log "$OUT/logs/make.$c" -screen none
  done
  for c in 9 5; do
    for dt in $DTS; do
      one $c vci global $dt
      one $c vci default $dt
      one $c cva default $dt
      one $c cva global $dt
    done
    # references over the same window: cva (both engines) and vci local at small dt
    one $c cva default 0.0001
    one $c cva global 0.0001
    one $c vci default 0.0003125
    one $c vci default 0.00015625
  done
  # 500 spheres: does the global form's error fall once dt is below the time
  # between contacts anywhere in the box (about 3e-4 here)?
  for dt in 0.0003125 0.00015625; do one 5 vci global $dt; one 5 cva global $dt; done
  # and on 2916 spheres (time between contacts in the box about 6e-5)
  for dt in 0.0003125 0.00015625 0.0000625 0.00003125; do one 9 vci global $dt; done
  for dt in 0.0000625 0.00003125; do one 9 cva global $dt; done
  echo "end $(date -u '+%F %T UTC')" >> "$OUT/machine.txt"
fi
/usr/bin/python3 "$HERE/vci-floor.py" "$OUT"
