#!/bin/bash
# bench/work-precision-large: CPU time against error at N = 32000 on the
# hard-core fluid with the smooth Gaussian attraction of bench/work-precision
# (its pair.fluid and in.make-fluid are used in place, by relative path:
# every LAMMPS run starts in bench/work-precision). Every method of the
# package with its default engine (local for cva, pcva, vci) against fix nve
# with WCA and with Mie(50,49) cores (Barker-Henderson diameter 1), over
# several dt each; mcva (global engine only) is timed on one step.
# Writes results[-short].md and work-precision[-short].png (parse.py).
#
#   bash bench/work-precision-large/run.sh               # full run
#   MODE=short bash bench/work-precision-large/run.sh    # ~20 min on one core
#   PARSE_ONLY=1 [MODE=short] bash bench/work-precision-large/run.sh
#   STABILITY=1 bash bench/work-precision-large/run.sh   # + the 10^6-step 500-atom runs
#
# Resumable: a run whose log has a BENCH line is not redone (delete the log to
# redo it); start states are kept in scratch/ (git-ignored).
# Every LAMMPS run is serial, under `nice -n 19`, one at a time (the machine
# is shared); the cost is CPU time = Loop time x "CPU use" / 100.
set -uo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
WP=$ROOT/bench/work-precision
LMP=${LMP:-$ROOT/.lmp-frozen}
[ -x "$LMP" ] || LMP=$ROOT/build/lmp
MODE=${MODE:-full}
SCR=$HERE/scratch
LOGS=$SCR/logs-$MODE
PARSE_ONLY=${PARSE_ONLY:-0}
CELLS=${CELLS:-20}                       # N = 4 cells^3 = 32000
NICE=${NICE:-19}

if [ "$MODE" = short ]; then
  STATES="A"; T_E=0.4; TW=0.4; T_LONG=0; LONG_STATES=""
  G_PSA="0.005 0.0025"; G_CVA="0.01 0.005"; G_PCVA="0.01 0.005"; G_VCI="0.01 0.005"
  G_WCA="0.0025 0.001"; G_MIE="0.001 0.0005"
  R_HS=0.001; R_PSA=""; R_WCA=0.0002; R_MIE=0.0002; MCVA=0
  SUFFIX=-short
else
  STATES=${STATES:-"A B"}; T_E=${T_E:-0.8}; TW=0.4; T_LONG=${T_LONG:-5}; LONG_STATES=${LONG_STATES:-"A B"}
  G_PSA="0.01 0.005 0.0025 0.001"; G_CVA="0.02 0.01 0.005 0.0025"
  G_PCVA="0.02 0.01 0.005 0.0025"; G_VCI="0.01 0.005 0.0025"
  G_WCA="0.005 0.0025 0.001 0.0005"; G_MIE="0.0025 0.001 0.0005 0.00025"
  R_HS=0.0005; R_PSA=${R_PSA:-}; R_WCA=0.0002; R_MIE=0.0001; MCVA=${MCVA:-1}
  SUFFIX=
fi

mkdir -p "$LOGS" "$SCR/logs"
cd "$WP"     # pair.fluid is included by its relative path

lmp() { nice -n "$NICE" "$LMP" -screen none "$@"; }
source "$HERE/wpl-machine.sh"

if [ "$PARSE_ONLY" != 1 ]; then
  wpl_machine "$LOGS" "$ROOT" "$LMP" "mode $MODE T_E $T_E Tw $TW T_long $T_LONG states $STATES"

  # one <state> <method> <dt> <T> <tag> [extra lmp args]
  one() {
    local S=$1 m=$2 dt=$3 T=$4 tag=$5; shift 5
    local name="$S.$m.$dt.$tag"
    local log="$LOGS/log.$name"
    if grep -q '^BENCH' "$log" 2>/dev/null; then return; fi
    local d=hs; case $m in wca|mie) d=$m ;; esac
    local data=$SCR/fluid32k.$S.$d.data
    case $tag in short*) data=$SCR/fluid2916.hs.data ;; esac
    echo "[$(date -u +%T)] $name T $T"
    # extra arguments first: the first definition of an index variable wins
    lmp -in "$HERE/in.fluid-large" "$@" -var method "$m" -var dt "$dt" -var T "$T" -var Tw "$TW" \
      -var data "$data" -var efile "$LOGS/e.$name" -var pfile "$LOGS/p.$name" -var xfile "$LOGS/x.$name" \
      -log "$log"
    grep -E '^BENCH|^ERROR|^Loop' "$log" | tail -2 | cut -c1-160
  }
  nth() { echo $1 | cut -d' ' -f$2; }

  # ---- start states (not timed): per state S, hard spheres from fcc with
  # seed of S (psa, kT = 1 by rescaling every 0.5 for 10 time units), then
  # each soft core re-equilibrated from it (fix nve dt 0.001, rescaled, 2 units)
  seed_of() { case $1 in A) echo 4928 ;; B) echo 7213 ;; *) echo 1000 ;; esac; }
  make_state() {
    local S=$1 d m
    d=$SCR/fluid32k.$S
    if [ ! -s "$d.hs.data" ]; then
      echo "[$(date -u +%T)] start state $S: hs"
      lmp -in in.make-fluid -var method hs -var cells "$CELLS" -var warm 10 -var seed "$(seed_of $S)" \
        -var out "$d.hs.data" -log "$SCR/logs/make.32k.$S.hs"
    fi
    for m in wca mie; do
      if [ ! -s "$d.$m.data" ]; then
        echo "[$(date -u +%T)] start state $S: $m"
        lmp -in in.make-fluid -var method $m -var warm 2 -var in "$d.hs.data" -var out "$d.$m.data" \
          -log "$SCR/logs/make.32k.$S.$m"
      fi
    done
  }

  # ---- contenders over dt, alternated (one dt level of each at a time), per state
  for S in $STATES; do
    make_state $S
    for i in 1 2 3 4; do
      for pair in "psa:$G_PSA" "cva:$G_CVA" "pcva:$G_PCVA" "vci:$G_VCI" "wca:$G_WCA" "mie:$G_MIE"; do
        m=${pair%%:*}; dt=$(nth "${pair#*:}" $i)
        [ -n "$dt" ] && one $S $m $dt $T_E run
      done
    done
    # references: each model's dt -> 0 limit over the pressure window (same start state)
    one $S cva $R_HS $TW ref
    one $S wca $R_WCA $TW ref
    one $S mie $R_MIE $TW ref
    [ -n "$R_PSA" ] && [ "$S" = A ] && one $S psa $R_PSA $TW ref
  done

  # ---- model error: long runs at kT = 1 (fix langevin beside each integrator)
  if [ "$T_LONG" != 0 ]; then
    for S in $LONG_STATES; do
      one $S cva 0.01 $T_LONG long -var nvt yes -var Tw 0.5
      one $S wca 0.001 $T_LONG long -var nvt yes -var Tw 0.5
      one $S mie 0.001 $T_LONG long -var nvt yes -var Tw 0.5
    done
  fi

  # ---- mcva (global engine, O(N) per collision): one step at N = 2916
  if [ "$MCVA" = 1 ]; then
    if [ ! -s "$SCR/fluid2916.hs.data" ]; then
      lmp -in in.make-fluid -var method hs -var cells 9 -var warm 10 -var out "$SCR/fluid2916.hs.data" \
        -log "$SCR/logs/make.2916.hs"
    fi
    one A mcva 0.005 0.01 short -var every 1 -var engine global
    one A cva 0.005 0.5 short2916     # cva (local) on the same data, for comparison
    one A cva 0.005 0.5 short2916g -var engine global   # and the global engine (energy error)
  fi
  [ -n "${STABILITY:-}" ] && bash "$HERE/stability.sh"

  echo "load_end $(cut -d' ' -f1-3 /proc/loadavg)" >> "$LOGS/machine.txt"
  echo "end $(date -u '+%Y-%m-%d %H:%M UTC')" >> "$LOGS/machine.txt"
fi
/usr/bin/python3 "$HERE/parse.py" "$LOGS" "$HERE/results$SUFFIX.md" "$HERE/work-precision$SUFFIX.png"
