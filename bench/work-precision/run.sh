#!/bin/bash
# Run time against error: every HARDSPHERE method (hard cores) and stock
# fix nve with steep continuous repulsion (WCA; Mie(50,49) of Jover et al.
# 2012) on (1) the impact pendulum chain (in.chain) and (2) a periodic fluid
# of 2916 hard spheres with a smooth attraction (in.fluid, pair.fluid), over
# several timesteps each; LAMMPS' Loop time against (a) the max energy error
# and (b) the error of an observable. Writes bench/work-precision/results.md
# and work-precision.png (parse.py). Serial runs, one after another, the
# contenders alternated. About 30-40 minutes on a shared 2-core machine.
#
#   bash bench/work-precision/run.sh            # the full run
#   RESUME=1 bash bench/work-precision/run.sh   # keep logs that already have a BENCH line
#   KEEP_DATA=1 bash ...: keep the fluid start states of an earlier run
#   PARSE_ONLY=1 bash bench/work-precision/run.sh
#
# Observables (see results.md for why):
#   chain: mean kinetic energy over the first 10 time units (first block of
#          the KE block file), from the same initial state for every run;
#   fluid: mean pressure over the T = 0.4 window from each model's own
#          equilibrated start state; model error from T = 20 runs.
set -uo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
LMP=$ROOT/build/lmp
SCR=$HERE/scratch
LOGS=$SCR/logs
RESUME=${RESUME:-0}
PARSE_ONLY=${PARSE_ONLY:-0}
T_CHAIN=${T_CHAIN:-5000}
T_FLUID=${T_FLUID:-0.4}
T_LONG=${T_LONG:-20}

if [ ! -x "$LMP" ]; then
  (cd "$ROOT" && cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null && cmake --build build -j2 --target lmp)
fi
mkdir -p "$LOGS"
cd "$HERE"   # the inputs include pair.fluid by a relative path

if [ "$PARSE_ONLY" != 1 ]; then
  [ "$RESUME" = 1 ] || rm -f "$LOGS"/* "$SCR"/blk.*
  [ "$RESUME" = 1 ] || [ "${KEEP_DATA:-0}" = 1 ] || rm -f "$SCR"/*.data
  {
    echo "start $(date -u '+%Y-%m-%d %H:%M UTC')"
    echo "nproc $(nproc)"
    echo "cpu $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//')"
    echo "load_start $(cut -d' ' -f1-3 /proc/loadavg)"
    echo "commit $(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null)"
  } > "$SCR/machine.txt"

  # one <system> <method> <dt> <T> <tag> [extra lmp args...]
  one() {
    local sys=$1 m=$2 dt=$3 T=$4 tag=$5; shift 5
    local log="$LOGS/log.$sys.$m.$dt.$tag"
    if [ "$RESUME" = 1 ] && grep -q '^BENCH' "$log" 2>/dev/null; then return; fi
    echo "[$(date -u +%T)] $sys $m dt $dt T $T ($tag)"
    local bfile="$SCR/blk.$sys.$m.$dt.$tag"
    # mcva: the global form, of which results.md is (its default is the
    # local form since 2 Dec 2026: ENGINE_MCVA=default)
    local eng=()
    [ "$m" = mcva ] && eng=(-var engine "${ENGINE_MCVA:-global}")
    if [ "$sys" = chain ]; then
      "$LMP" -in in.chain -var method "$m" -var dt "$dt" -var T "$T" -var kfile "$bfile" -var efile "$bfile.ends" \
        "${eng[@]}" "$@" -log "$log" -screen none
    else
      local d=hs; case $m in wca|mie) d=$m ;; esac
      "$LMP" -in in.fluid -var method "$m" -var dt "$dt" -var T "$T" \
        -var data "$SCR/fluid.$d.data" -var pfile "$bfile" -var efile "$bfile.ends" "${eng[@]}" "$@" -log "$log" -screen none
    fi
    grep -E '^BENCH|^ERROR' "$log" | tail -1 | cut -c1-200
  }

  # ---- start states of the fluid (not timed)
  if [ ! -s "$SCR/fluid.hs.data" ]; then
    echo "[$(date -u +%T)] fluid start states"
    "$LMP" -in in.make-fluid -var method hs -var warm 10 -var out "$SCR/fluid.hs.data" \
      -log "$LOGS/make.hs" -screen none
  fi
  for m in wca mie; do
    [ -s "$SCR/fluid.$m.data" ] || "$LMP" -in in.make-fluid -var method $m -var warm 5 \
      -var in "$SCR/fluid.hs.data" -var out "$SCR/fluid.$m.data" -log "$LOGS/make.$m" -screen none
  done

  # ---- pendulum chain: T_CHAIN for every point, references over the 10-unit window
  CH_HS="0.1 0.05 0.02 0.01 0.005 0.002"
  CH_WCA="0.02 0.01 0.005 0.002 0.001 0.0005"
  CH_MIE="0.01 0.005 0.002 0.001 0.0005"
  for i in 1 2 3 4 5 6; do     # alternate the contenders, one dt level at a time
    for m in psa cva pcva mcva vci; do
      dt=$(echo $CH_HS | cut -d' ' -f$i); one chain $m $dt $T_CHAIN run
    done
    dt=$(echo $CH_WCA | cut -d' ' -f$i); [ -n "$dt" ] && one chain wca $dt $T_CHAIN run
    dt=$(echo $CH_MIE | cut -d' ' -f$i); [ -n "$dt" ] && one chain mie $dt $T_CHAIN run
  done
  one chain cva 0.00005 10 ref
  one chain psa 0.0001 10 ref
  one chain wca 0.00002 10 ref
  one chain mie 0.00001 10 ref

  # ---- fluid: T_FLUID windows from the same start state per model
  FL_PSA="0.02 0.01 0.005 0.0025 0.001"
  FL_CVA="0.02 0.01 0.005 0.0025"
  FL_PCVA="0.01 0.005 0.0025"
  FL_VCI="0.01 0.005 0.0025"
  FL_WCA="0.01 0.005 0.0025 0.001 0.0005"
  FL_MIE="0.005 0.0025 0.001 0.0005 0.00025"
  for i in 1 2 3 4 5; do
    for pair in "psa:$FL_PSA" "cva:$FL_CVA" "pcva:$FL_PCVA" "vci:$FL_VCI" "wca:$FL_WCA" "mie:$FL_MIE"; do
      m=${pair%%:*}; dt=$(echo ${pair#*:} | cut -d' ' -f$i)
      [ -n "$dt" ] && one fluid $m $dt $T_FLUID run
    done
  done
  # references: the same window at a tiny dt (hard spheres: cva; psa as a cross-check)
  one fluid cva 0.0005 $T_FLUID ref
  one fluid psa 0.0002 $T_FLUID ref
  one fluid wca 0.0001 $T_FLUID ref
  one fluid mie 0.0001 $T_FLUID ref
  # model error: long runs (pressure mean and its block standard error)
  one fluid psa 0.0025 $T_LONG long -var blk 0.5
  one fluid wca 0.001 $T_LONG long -var blk 0.5
  one fluid mie 0.001 $T_LONG long -var blk 0.5
  # mcva on the fluid: cost per step from a 2-step run (a T_FLUID run would take hours)
  [ "${MCVA_FLUID:-1}" = 1 ] && one fluid mcva 0.005 0.01 short -var every 1

  echo "load_end $(cut -d' ' -f1-3 /proc/loadavg)" >> "$SCR/machine.txt"
  echo "end $(date -u '+%Y-%m-%d %H:%M UTC')" >> "$SCR/machine.txt"
fi
/usr/bin/python3 "$HERE/parse.py" "$SCR" "$HERE/results.md" "$HERE/work-precision.png"
