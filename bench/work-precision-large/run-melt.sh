#!/bin/bash
# bench/work-precision-large, system (b): CPU time against error at N = 32000
# on the bead-spring melt (chains of 10, rho 0.85, FENE bonds; pair.melt):
# fix nve with the Kremer-Grest WCA melt (kg) and with Mie(50,49) cores (mie)
# against the package's hard-sphere methods (default engines) with hard cores
# of the WCA bead's Barker-Henderson diameter, over several dt each.
# Writes results-melt[-short].md and work-precision-melt[-short].png (parse-melt.py).
#
#   bash bench/work-precision-large/run-melt.sh               # full run
#   MODE=short bash bench/work-precision-large/run-melt.sh    # ~10 CPU min
#   PARSE_ONLY=1 [MODE=short] bash bench/work-precision-large/run-melt.sh
#   LONG=1 bash bench/work-precision-large/run-melt.sh        # + the 2-time-unit model-error runs (state A; not
#                                                             #   equilibrium: run-model-error.sh measures that)
#   CLUSTERS=1 bash bench/work-precision-large/run-melt.sh    # + cva's cluster sizes per dt (in.melt-clusters)
#   LMP=/path/to/lmp ...                                      # binary (default .lmp-frozen, else build/lmp)
#
# Resumable: a run whose log has a BENCH line is not redone (delete the log to
# redo it); start states are kept in scratch/ (git-ignored).
# Every LAMMPS run is serial, under `nice -n 19`, one at a time (the machine
# is shared); the cost is CPU time = Loop time x "CPU use" / 100.
set -uo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
LMP=${LMP:-$ROOT/.lmp-frozen}
[ -x "$LMP" ] || LMP=$ROOT/build/lmp
MODE=${MODE:-full}
SCR=$HERE/scratch
LOGS=$SCR/melt-logs-$MODE
PARSE_ONLY=${PARSE_ONLY:-0}
NXYZ=${NXYZ:-"40 40 20"}                 # lattice sites: N = 32000 beads, 3200 chains
NICE=${NICE:-19}
W_KG=${W_KG:-100}; W_HS=${W_HS:-5}; W_MIE=${W_MIE:-1}   # warm-up times of the start states
LONG=${LONG:-0}; T_LONG=${T_LONG:-2}; LONG_STATES=${LONG_STATES:-A}
CLUSTERS=${CLUSTERS:-0}

if [ "$MODE" = short ]; then
  STATES="A"; T_E=0.2; TW=0.2
  G_PSA="0.0025 0.001"; G_CVA="0.01 0.005"; G_PCVA="0.01 0.005"; G_VCI="0.01 0.005"
  G_KG="0.01 0.005"; G_MIE="0.0025 0.001"
  R_HS=0.001; R_KG=0.0005; R_MIE=0.0002
  SUFFIX=-short
else
  STATES=${STATES:-"A B"}; T_E=${T_E:-0.5}; TW=0.4
  G_PSA="0.005 0.0025 0.001"; G_CVA="0.01 0.005 0.0025"; G_PCVA="0.01 0.005 0.0025"
  G_VCI="0.01 0.005 0.0025"; G_KG="0.01 0.005 0.0025 0.001 0.0005"; G_MIE="0.0025 0.001 0.0005"
  R_HS=0.0005; R_KG=0.0002; R_MIE=0.0001
  SUFFIX=
fi
METHODS=${METHODS:-"psa cva pcva vci kg mie"}

mkdir -p "$LOGS" "$SCR/logs"
cd "$HERE"     # pair.melt is included by its relative path

lmp() { nice -n "$NICE" "$LMP" -screen none "$@"; }
source "$HERE/wpl-machine.sh"

if [ "$PARSE_ONLY" != 1 ]; then
  wpl_machine "$LOGS" "$ROOT" "$LMP" "mode $MODE T_E $T_E Tw $TW states $STATES"

  # one <state> <method> <dt> <T> <tag> [extra lmp args]
  one() {
    local S=$1 m=$2 dt=$3 T=$4 tag=$5; shift 5
    local name="$S.$m.$dt.$tag"
    local log="$LOGS/log.$name"
    if grep -q '^BENCH' "$log" 2>/dev/null; then return; fi
    local d=hs; case $m in kg|mie) d=$m ;; esac
    echo "[$(date -u +%T)] $name T $T"
    lmp -in "$HERE/in.melt-large" "$@" -var method "$m" -var dt "$dt" -var T "$T" -var Tw "$TW" \
      -var data "$SCR/melt32k.$S.$d.data" -var efile "$LOGS/e.$name" -var rfile "$LOGS/r.$name" \
      -log "$log"
    grep -E '^BENCH|^ERROR|^Loop' "$log" | tail -2 | cut -c1-160
  }
  nth() { echo $1 | cut -d' ' -f$2; }
  has() { case " $METHODS " in *" $1 "*) return 0 ;; esac; return 1; }

  # ---- start states (not timed): per state S, straight chains on a lattice ->
  # Kremer-Grest (langevin, W_KG) -> pushed apart + hard spheres (psa + langevin,
  # W_HS) -> Mie (nve + langevin, W_MIE); each rescaled to T = 1 at the end.
  seed_of() { case $1 in A) echo 4928 ;; B) echo 7213 ;; *) echo 1000 ;; esac; }
  make_state() {
    local S=$1 d=$SCR/melt32k.$S
    [ -s "$SCR/melt32k.lattice.data" ] || /usr/bin/python3 "$ROOT/bench/overhead/make_data.py" \
      "$SCR/melt32k.lattice.data" $NXYZ 0.85 10
    if [ ! -s "$d.kg.data" ]; then
      echo "[$(date -u +%T)] start state $S: kg ($W_KG time units)"
      lmp -in in.make-melt-large -var method kg -var in "$SCR/melt32k.lattice.data" -var warm "$W_KG" \
        -var seed "$(seed_of $S)" -var out "$d.kg.data" -log "$SCR/logs/make.melt32k.$S.kg"
    fi
    if [ ! -s "$d.hs.data" ]; then
      echo "[$(date -u +%T)] start state $S: hs ($W_HS time units)"
      lmp -in in.make-melt-large -var method hs -var in "$d.kg.data" -var warm "$W_HS" \
        -var seed "$(seed_of $S)" -var out "$d.hs.data" -log "$SCR/logs/make.melt32k.$S.hs"
    fi
    if [ ! -s "$d.mie.data" ] && has mie; then
      echo "[$(date -u +%T)] start state $S: mie ($W_MIE time units)"
      lmp -in in.make-melt-large -var method mie -var in "$d.hs.data" -var warm "$W_MIE" \
        -var seed "$(seed_of $S)" -var out "$d.mie.data" -log "$SCR/logs/make.melt32k.$S.mie"
    fi
  }

  # ---- contenders over dt, alternated (one dt level of each at a time), per state
  for S in $STATES; do
    make_state $S
    for i in 1 2 3 4 5; do
      for pair in "kg:$G_KG" "psa:$G_PSA" "cva:$G_CVA" "pcva:$G_PCVA" "vci:$G_VCI" "mie:$G_MIE"; do
        m=${pair%%:*}; dt=$(nth "${pair#*:}" $i)
        has $m || continue
        [ -n "$dt" ] && one $S $m $dt $T_E run
      done
    done
    # references: each model's dt -> 0 limit over the window (same start state)
    one $S cva $R_HS $TW ref
    one $S kg $R_KG $TW ref
    has mie && one $S mie $R_MIE $TW ref
  done

  # ---- model error: runs at kT = 1 with fix langevin beside each integrator
  if [ "$LONG" = 1 ]; then
    for S in $LONG_STATES; do
      one $S kg 0.005 $T_LONG long -var nvt yes -var Tw 0.5
      one $S mie 0.001 $T_LONG long -var nvt yes -var Tw 0.5
      one $S cva 0.01 $T_LONG long -var nvt yes -var Tw 0.5
    done
  fi

  # ---- the local engine's clusters (cva, state A, 0.05 time units per dt)
  if [ "$CLUSTERS" = 1 ]; then
    for dt in 0.01 0.005 0.0025 0.001; do
      log=$LOGS/clu.A.cva.$dt
      grep -q '^CLUSTERS' "$log" 2>/dev/null && continue
      echo "[$(date -u +%T)] clusters cva $dt"
      lmp -in in.melt-clusters -var method cva -var dt $dt -var T 0.05 -var Tw 0.05 \
        -var data "$SCR/melt32k.A.hs.data" -log "$log"
      grep -E '^CLUSTERS|^ERROR' "$log"
    done
  fi

  echo "load_end $(cut -d' ' -f1-3 /proc/loadavg)" >> "$LOGS/machine.txt"
  echo "end $(date -u '+%Y-%m-%d %H:%M UTC')" >> "$LOGS/machine.txt"
fi
/usr/bin/python3 "$HERE/parse-melt.py" "$LOGS" "$HERE/results-melt$SUFFIX.md" "$HERE/work-precision-melt$SUFFIX.png"
