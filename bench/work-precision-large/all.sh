#!/bin/bash
# bench/work-precision-large/all.sh: issue 23's benchmark in one command.
# Runs, one after another (each script serial, nice -n 19, resumable: what
# has a finished log is not redone):
#   run.sh                 system (a), the hard-core fluid at N = 32000
#   run-melt.sh            system (b), the bead-spring melt at N = 32000
#                          (full mode: with CLUSTERS=1, cva's cluster sizes)
#   run-model-error.sh     the melt's equilibrium model error (full mode)
#   stability.sh           10^6-step NVE runs on 500 atoms (STABILITY=1)
# and leaves each one's results-*.md and figure beside it (README.md).
#
#   bash bench/work-precision-large/all.sh                 # full: ~2.6 CPU h (+ ~1.7 h with STABILITY=1)
#   MODE=short bash bench/work-precision-large/all.sh      # short: 9.4 min (2026-11-26, fresh worktree, start states included)
#   PARSE_ONLY=1 [MODE=short] bash bench/work-precision-large/all.sh
set -uo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
MODE=${MODE:-full}
export MODE
rc=0
step() {    # step <name> <command...>: run it, note a failure, go on
  local name=$1; shift
  echo "[$(date -u +%T)] all.sh: $name"
  "$@" || { echo "all.sh: $name failed (status $?)"; rc=1; }
}
step "fluid (run.sh)" env -u STABILITY bash "$HERE/run.sh"    # (stability below)
if [ "$MODE" = short ]; then
  step "melt (run-melt.sh)" bash "$HERE/run-melt.sh"
else
  step "melt (run-melt.sh, with cluster sizes)" env CLUSTERS=1 bash "$HERE/run-melt.sh"
  step "melt model error (run-model-error.sh)" bash "$HERE/run-model-error.sh"
fi
if [ "${STABILITY:-0}" = 1 ] && [ "${PARSE_ONLY:-0}" != 1 ]; then
  step "stability (stability.sh)" bash "$HERE/stability.sh"
fi
exit $rc
