#!/usr/bin/env bash
# Drop-in build: HARDSPHERE compiled INTO LAMMPS 4Feb2025, the way a user
# adds a package to a LAMMPS source tree, without any CMake of ours.
#
#   bash scripts/dropin-2025.sh                 build (or update) and run the
#                                               pendulum chain with that lmp
#   bash scripts/dropin-2025.sh --compare LMP   also run the chain with LMP
#                                               (e.g. build-2025/lmp) and
#                                               require the same trajectory
#
# Steps, as for any LAMMPS package:
#   1. a copy of the LAMMPS 4Feb2025 source tree (scripts/lammps-2025.sh
#      fetches and verifies it once per machine);
#   2. copy the package's style and helper sources into its src/:
#      fix_hardsphere*, compute_hamiltonian_modified.*, hs_potential.*,
#      hs_*.h -- not hardsphere_registry.* or hardsphere_plugin.cpp, which
#      belong to our driver and plugin;
#   3. LAMMPS' own CMake build (it compiles every src/*.cpp and finds the
#      FixStyle/ComputeStyle blocks), with MOLECULE for the chain's bonds;
#   4. run examples/pendulum-chain with the resulting lmp.
# The tree and build live in ~/.cache/hardsphere/dropin-<version>-<key>/ so
# that later runs only recompile the package files that changed.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
COMPARE=""
if [ "${1:-}" = "--compare" ]; then COMPARE="$2"; fi
log() { echo "dropin-2025: $*"; }

eval "$(bash "$ROOT/scripts/lammps-2025.sh" --source)"    # LAMMPS2025_SRC
CACHE="$(dirname "$LAMMPS2025_SRC")"
# the package's kernels use Eigen 3 (header only, Debian libeigen3-dev):
# LAMMPS' own build adds its include path only for the packages it knows
EIGEN_INC="$(pkg-config --cflags-only-I eigen3 2>/dev/null | sed 's/^-I//; s/ *$//')"
[ -n "$EIGEN_INC" ] || EIGEN_INC=/usr/include/eigen3
[ -f "$EIGEN_INC/Eigen/Dense" ] || { log "ERROR: no Eigen 3 headers in $EIGEN_INC (libeigen3-dev)"; exit 1; }
OPTS=(-D CMAKE_BUILD_TYPE=Release -D BUILD_MPI=on -D BUILD_OMP=off -D BUILD_SHARED_LIBS=off
      -D WITH_JPEG=off -D WITH_PNG=off -D WITH_FFMPEG=off -D DOWNLOAD_POTENTIALS=off
      -D PKG_MOLECULE=on -D "CMAKE_CXX_FLAGS=-isystem $EIGEN_INC")
KEY="$( { basename "$LAMMPS2025_SRC"; printf '%s\n' "${OPTS[@]}"; c++ --version | head -n1; } \
        | sha256sum | cut -c1-12)"
DROP="$CACHE/dropin-20250204-$KEY"
mkdir -p "$DROP"
exec 9>"$DROP/.lock"
flock 9

# 1. the source tree (copied once; kept, so that make sees what changed)
if [ ! -f "$DROP/lammps/.hs-copied" ]; then
  log "copying $LAMMPS2025_SRC -> $DROP/lammps"
  rm -rf "$DROP/lammps"
  cp -a "$LAMMPS2025_SRC" "$DROP/lammps"
  touch "$DROP/lammps/.hs-copied"
fi

# 2. the package files; unchanged files keep their time stamps, files that
# left the package since the last run are removed again
PKG="$ROOT/src/HARDSPHERE"
files=()
for f in "$PKG"/fix_hardsphere* "$PKG"/compute_hamiltonian_modified.* "$PKG"/hs_*.cpp \
         "$PKG"/hs_*.h; do
  files+=("$(basename "$f")")
done
if [ -f "$DROP/copied.txt" ]; then
  while read -r old; do
    if [[ ! " ${files[*]} " == *" $old "* ]]; then rm -f "$DROP/lammps/src/$old"; fi
  done < "$DROP/copied.txt"
fi
changed=0
for f in "${files[@]}"; do
  if ! cmp -s "$PKG/$f" "$DROP/lammps/src/$f"; then cp "$PKG/$f" "$DROP/lammps/src/$f"; changed=$((changed+1)); fi
done
printf '%s\n' "${files[@]}" > "$DROP/copied.txt"
log "${#files[@]} package files in $DROP/lammps/src ($changed changed)"

# 3. LAMMPS' own build
start=$(date +%s)
if [ ! -f "$DROP/build/CMakeCache.txt" ]; then
  cmake -S "$DROP/lammps/cmake" -B "$DROP/build" "${OPTS[@]}" > "$DROP/cmake.log"
fi
cmake --build "$DROP/build" -j"${HS_JOBS:-2}" > "$DROP/build.log" 2>&1 \
  || { tail -n 40 "$DROP/build.log"; log "ERROR: LAMMPS build with HARDSPHERE failed"; exit 1; }
if grep -i 'warning' "$DROP/build.log" | grep -E 'hardsphere|hs_|hamiltonian_modified' ; then
  log "ERROR: warnings in the package sources (above)"
  exit 1
fi
log "LAMMPS with HARDSPHERE built in $(( $(date +%s) - start )) s: $DROP/build/lmp"
LMP="$DROP/build/lmp"
"$LMP" -h | grep -q 'hardsphere/cva' \
  || { log "ERROR: $LMP does not list fix hardsphere/cva"; exit 1; }

# 4. the example
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
cd "$WORK"
for m in psa cva pcva mcva vci; do
  "$LMP" -in "$ROOT/examples/pendulum-chain/in.pendulum-chain" -log none -var method "$m" -var T 40 \
    -var vevery 1 -var vout "dropin.$m.v" < /dev/null > "dropin.$m.out" 2>&1 \
    || { tail -n 20 "dropin.$m.out"; log "ERROR: drop-in lmp failed on the chain ($m)"; exit 1; }
  grep '^pendulum chain: method' "dropin.$m.out"
  if [ -n "$COMPARE" ]; then
    "$COMPARE" -in "$ROOT/examples/pendulum-chain/in.pendulum-chain" -log none -var method "$m" \
      -var T 40 -var vevery 1 -var vout "ref.$m.v" < /dev/null > "ref.$m.out" 2>&1 \
      || { tail -n 20 "ref.$m.out"; log "ERROR: $COMPARE failed on the chain ($m)"; exit 1; }
    a="$(grep '^pendulum chain: method' "dropin.$m.out")"
    b="$(grep '^pendulum chain: method' "ref.$m.out")"
    if [ "$a" != "$b" ]; then log "ERROR ($m): drop-in '$a' but $COMPARE '$b'"; exit 1; fi
    # velocity of sphere 1 at every step (10 digits): the same to round-off
    /usr/bin/python3 - "dropin.$m.v" "ref.$m.v" "$m" <<'PY'
import sys
def nums(p):
    return [float(x) for l in open(p) if not l.startswith('#') for x in l.split()]
a, b = nums(sys.argv[1]), nums(sys.argv[2])
assert len(a) == len(b) and len(a) > 100, (len(a), len(b))
worst = max(abs(x - y) / (1 + abs(x)) for x, y in zip(a, b))
print(f"dropin-2025: {sys.argv[3]}: {len(a)} values, max relative difference {worst:.2e}")
sys.exit(0 if worst <= 1e-8 else 1)
PY
  fi
done
log "OK"
