#!/usr/bin/env bash
# Build (via setup.sh) and run the pendulum-chain example with the CVA method.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$ROOT/scripts/setup.sh"
cd "$ROOT/examples/pendulum-chain"
"$ROOT/build/lmp" -in in.pendulum-chain -var method cva "$@"
