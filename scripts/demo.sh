#!/usr/bin/env bash
# Set up and build (via setup.sh), then run the impact pendulum chain of
# Bond & Leimkuhler (2007), section 4, over the paper's horizon T = 5000 at
# dt = 0.02 with each method of the package (psa, cva, pcva, mcva, vci);
# prints each run's collision counts and its maximal energy error.
# Extra arguments go to lmp (e.g. -var dt 0.01 -var seed 3);
# METHODS="cva pcva" restricts the methods.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
HS_LAMMPS_VERSIONS="${HS_LAMMPS_VERSIONS:-2021}" bash "$ROOT/scripts/setup.sh"
cd "$ROOT/examples/pendulum-chain"
series="$(mktemp)"
trap 'rm -f "$series" "$series.screen"' EXIT
for method in ${METHODS:-psa cva pcva mcva vci}; do
  "$ROOT/build/lmp" -in in.pendulum-chain -log none -echo none \
    -var method "$method" -var T 5000 -var every 25000 -var out "$series" "$@" \
    > "$series.screen" || {
      echo "demo: the $method run failed; rerun it with:" >&2
      echo "  build/lmp -in examples/pendulum-chain/in.pendulum-chain -var method $method -var T 5000" >&2
      exit 1; }
  grep '^pendulum chain:' "$series.screen"
  awk -v m="$method" '!/^#/ { if ($2 > x) x = $2 } END { printf "  %-5s max |H(t) - H(0)| over the run = %.3e\n", m, x }' "$series"
done
