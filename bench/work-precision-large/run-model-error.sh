#!/bin/bash
# bench/work-precision-large: the equilibrium model error of the bead-spring
# melt of run-melt.sh (pair.melt: chains of 10, rho 0.85, FENE bonds). Rg^2,
# <R_ee^2> and the mean bond length of the soft-core models (kg: fix nve +
# WCA, the Kremer-Grest melt; mie: fix nve + Mie(50,49)) against the hard-core
# model (fix hardsphere/psa, cores of d_BH), all at kT = 1 with fix langevin
# 1 1 1 beside the integrator, at N = 4000 (400 chains; the observables are
# intensive). Each model runs from two start states:
#   K: the Kremer-Grest melt after W_KG time units from straight chains (for
#      the hard cores pushed apart + 5 time units of psa, for Mie + 1 of Mie:
#      in.make-melt-large, as run-melt.sh makes its states);
#   R: the straight chains themselves (the lattice, no distance below the
#      Mie cut-off), far above every model's equilibrium Rg^2.
# Runs are in segments of T_SEG time units (in.model-error, each starts from
# the last one's end state); parse-model-error.py drops the first T_EQ of
# each run and writes results-model-error.md. Also: psa at dt/2 continued from
# the end of psa's K run (the dt check), and the Kremer-Grest melt at
# N = 32000 (the size check).
#
#   bash bench/work-precision-large/run-model-error.sh               # ~55 CPU min
#   PARSE_ONLY=1 bash bench/work-precision-large/run-model-error.sh
#   LMP=/path/to/lmp ...        # binary (default .lmp-frozen, else build/lmp)
#   NSEG_KG=24 NSEG_MIE=20 NSEG_HS=20 ...   # run lengths in segments (more: longer runs, resumed)
#
# Resumable: a segment whose log has a SEGMENT line is not redone (delete the
# log to redo it); start states, logs and series are kept in scratch/
# (git-ignored). Every LAMMPS run is serial, under `nice -n 19`, one at a time
# (the machine is shared); the cost is CPU time = Loop time x "CPU use" / 100.
set -uo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
LMP=${LMP:-$ROOT/.lmp-frozen}
[ -x "$LMP" ] || LMP=$ROOT/build/lmp
SCR=$HERE/scratch
LOGS=${LOGS:-$SCR/model-error-logs}
PARSE_ONLY=${PARSE_ONLY:-0}
NICE=${NICE:-19}
NXYZ=${NXYZ:-"20 20 10"}           # lattice sites: N = 4000 beads, 400 chains
W_KG=${W_KG:-100}                  # time units of Kremer-Grest making state K
T_SEG=${T_SEG:-50}; T_EQ=${T_EQ:-300}
NSEG_KG=${NSEG_KG:-20}; NSEG_MIE=${NSEG_MIE:-16}; NSEG_HS=${NSEG_HS:-16}
DT_KG=0.005; DT_MIE=0.001; DT_HS=0.001; DT_HS2=0.0005
SIZE_CHECK=${SIZE_CHECK:-1}; NSEG_32K=${NSEG_32K:-7}

mkdir -p "$LOGS" "$SCR/logs"
cd "$HERE"     # pair.melt is included by its relative path

lmp() { nice -n "$NICE" "$LMP" -screen none "$@"; }
source "$HERE/wpl-machine.sh"

# state <prefix> "<nx ny nz>" <models>: the lattice (start R) and the K states
# of in.make-melt-large (kg, then hs from kg, then mie from hs)
state() {
  local p=$1 nxyz=$2 models=$3
  [ -s "$p.lattice.data" ] || /usr/bin/python3 "$ROOT/bench/overhead/make_data.py" "$p.lattice.data" $nxyz 0.85 10
  local prev=$p.lattice.data m w
  for m in $models; do
    case $m in kg) w=$W_KG ;; hs) w=5 ;; mie) w=1 ;; esac
    if [ ! -s "$p.K.$m.data" ]; then
      echo "[$(date -u +%T)] $(basename "$p") start state K: $m ($w time units)"
      lmp -in in.make-melt-large -var method $m -var in "$prev" -var warm $w -var seed 4928 \
        -var out "$p.K.$m.data" -log "$SCR/logs/make.$(basename "$p").K.$m"
    fi
    prev=$p.K.$m.data
  done
}

# chain <system> <model> <start> <dt> <nseg> <first data> [vel]: segments 1..nseg
# of run <system>.<model>.<start>.<dt>; segment k reads segment k-1's end state.
# The langevin seed differs for every segment of every run.
chain() {
  local sys=$1 m=$2 S=$3 dt=$4 nseg=$5 data=$6 vel=${7:-keep} k
  local run=$sys.$m.$S.$dt seed
  case $m.$S in kg.K) seed=100 ;; kg.R) seed=200 ;; mie.K) seed=300 ;; mie.R) seed=400 ;;
    psa.K) seed=500 ;; psa.R) seed=600 ;; *) seed=700 ;; esac
  [ "$sys" = me4k ] || seed=$((seed + 1000))
  for k in $(seq 1 "$nseg"); do
    local log=$LOGS/log.$run.$k
    if ! grep -q '^SEGMENT' "$log" 2>/dev/null; then
      echo "[$(date -u +%T)] $run segment $k/$nseg"
      lmp -in in.model-error -var method $m -var dt $dt -var T $T_SEG -var data "$data" -var vel $vel \
        -var seed $((seed + k)) \
        -var out "$LOGS/d.$run.$k.data" -var sfile "$LOGS/s.$run.$k" -log "$log"
      grep -E '^SEGMENT|^ERROR' "$log" | tail -1
      grep -q '^SEGMENT' "$log" || return 1
    fi
    data=$LOGS/d.$run.$k.data; vel=keep
  done
}

if [ "$PARSE_ONLY" != 1 ]; then
  wpl_machine "$LOGS" "$ROOT" "$LMP" "mode model-error N $NXYZ T_SEG $T_SEG T_EQ $T_EQ segments kg $NSEG_KG mie $NSEG_MIE psa $NSEG_HS"
  P=$SCR/me4k
  state "$P" "$NXYZ" "kg hs mie"
  # the two start states of each model, alternated (one run after another)
  for S in K R; do
    if [ $S = K ]; then dk=$P.K.kg.data; dm=$P.K.mie.data; dh=$P.K.hs.data; v=keep
    else dk=$P.lattice.data; dm=$dk; dh=$dk; v=create; fi
    chain me4k kg  $S $DT_KG  $NSEG_KG  "$dk" $v
    chain me4k mie $S $DT_MIE $NSEG_MIE "$dm" $v
    chain me4k psa $S $DT_HS  $NSEG_HS  "$dh" $v
  done
  # the dt check: psa at dt/2 from the end of psa's K run (one segment)
  chain me4k psa Kc $DT_HS2 1 "$LOGS/d.me4k.psa.K.$DT_HS.$NSEG_HS.data"
  # the size check: the Kremer-Grest melt at N = 32000 (3200 chains), start state K
  if [ "$SIZE_CHECK" = 1 ]; then
    state "$SCR/me32k" "40 40 20" kg
    chain me32k kg K $DT_KG $NSEG_32K "$SCR/me32k.K.kg.data"
  fi
  echo "load_end $(cut -d' ' -f1-3 /proc/loadavg)" >> "$LOGS/machine.txt"
  echo "end $(date -u '+%Y-%m-%d %H:%M UTC')" >> "$LOGS/machine.txt"
fi
/usr/bin/python3 "$HERE/parse-model-error.py" "$LOGS" "$HERE/results-model-error.md" "$T_SEG" "$T_EQ"
