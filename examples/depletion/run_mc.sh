#!/bin/bash
# Depletion example, part 2: B4 by Mayer sampling (mayer_b4.cpp) and MD
# (in.ao) against the NVT Monte Carlo of mc_ao.cpp, at low density (does
# the virial series explain the MD's Z?) and at rho sigma^3 = 0.3. Writes
# results_mc.md and gr_mc.png (analyze_mc.py).
#
#   bash examples/depletion/run_mc.sh
#
# All lanes at once (nice 19), resumable (a finished run is kept; FORCE=1
# redoes it). MD: q 0.2, dt 0.005, damp 2.0, 864 colloids.
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
LMP=$ROOT/build/lmp
SCR=${SCR:-$HERE/scratch}; OUT=${OUT:-$HERE/results_mc.md}
if [ ! -x "$LMP" ]; then
  (cd "$ROOT" && cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null && cmake --build build -j1)
fi
mkdir -p "$SCR/md" "$SCR/mc" "$SCR/b4"
g++ -O2 -o "$SCR/mc_ao" "$HERE/mc_ao.cpp"
g++ -O2 -o "$SCR/b4/mayer_b4" "$HERE/mayer_b4.cpp"
fin() { [ "${FORCE:-0}" != 1 ] && [ -f "$1" ] && grep -q "^RESULT" "$1"; }
pids=""
run() { "$@" & pids="$pids $!"; }

fin "$SCR/b4/b4_q0.2.txt" || run sh -c "cd '$SCR/b4' && nice -n 19 ./mayer_b4 --q 0.2 --samples 3e8 --seed 7 > b4_q0.2.txt"
# MC: "rho:sweeps:seed"
for s in 0.05:600000:11 0.3:300000:12; do
  IFS=: read -r rho sw seed <<< "$s"; tag=q0.2_rho$rho
  fin "$SCR/mc/mc.$tag.txt" || run sh -c "cd '$SCR/mc' && nice -n 19 ../mc_ao --q 0.2 --rho $rho --sweeps $sw \
    --equil 10000 --every 5 --seed $seed --gr gr.$tag.txt > mc.$tag.txt"
done
# MD: "rho:equil:nrun:seed:tag:nve" (nve yes: fix langevin in equilibration only)
for s in 0.3:10000:60000:2024:q0.2_rho0.3:no 0.05:10000:200000:5077:q0.2_rho0.05_s5077:no \
         0.05:10000:200000:6151:q0.2_rho0.05_nve:yes; do
  # (and q0.2_rho0.05_damp0.5[_dt0.0025]: -var damp 0.5 [-var dt 0.0025], run by hand, see README)
  IFS=: read -r rho eq nrun seed tag nve <<< "$s"
  fin "$SCR/md/log.$tag" || run sh -c "cd '$SCR/md' && nice -n 19 '$LMP' -in '$HERE/in.ao' -var q 0.2 -var rho $rho \
    -var root '$ROOT' -var equil $eq -var nrun $nrun -var seed $seed -var nve $nve -var tag $tag -log log.$tag -screen none > /dev/null"
done
for p in $pids; do wait $p; done
/usr/bin/python3 "$HERE/analyze_mc.py" "$SCR" "$OUT" "0.2:0.05:_s5077 0.2:0.05:_damp0.5 0.2:0.05:_damp0.5_dt0.0025 0.2:0.05:_nve 0.2:0.3"
