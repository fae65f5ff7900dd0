#!/bin/bash
# bench/vci-local/agree.sh: vci local and global on the 4000-sphere fluid,
# NBLOCKS blocks of 50 steps from the same start; collisions per step and
# pressure, block means with standard errors (issue 21).
#   NBLOCKS=8 bash bench/vci-local/agree.sh        # ~7 min (global: ~0.65 s per step)
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
LMP=${LMP:-$HERE/../../build/lmp}
NBLOCKS=${NBLOCKS:-8}
cd "$HERE"
for s in local global; do
  "$LMP" -in in.agree -screen none -log log.agree.$s -var substep $s -var nblocks "$NBLOCKS" -var seed 4242 > /dev/null
  grep '^BLOCK' log.agree.$s | awk -v s=$s '{n++; c+=$2/50; c2+=($2/50)^2; p+=$3; p2+=$3^2}
    END {mc=c/n; mp=p/n; sc=sqrt((c2/n-mc^2)/(n-1)); sp=sqrt((p2/n-mp^2)/(n-1));
         printf "%-6s collisions/step %.3f +- %.3f  pressure %.4f +- %.4f  (%d blocks)\n", s, mc, sc, mp, sp, n}'
done | tee agree.txt
rm -f log.agree.local log.agree.global
