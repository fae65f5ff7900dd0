#!/bin/bash
# Depletion example, part 3: the mechanism of the thermostat bias (README.md,
# "The thermostat bias: mechanism"). q = 0.2 AO colloids at rho sigma^3 =
# 0.05 (864, in.ao; and 0.3) under fix langevin at gamma dt = 0.025 and 0.05 (gamma =
# 1/damp) and under fix temp/berendsen; hard spheres alone (-var pair hs) at
# rho 0.05 and 0.5; a Lennard-Jones fluid under fix nve + fix langevin
# (in.halfstep, no package). One run at a time, nice 19, resumable (FORCE=1
# redoes a run); about 40 min on one core. Table: bias.py -> results_bias.md.
#
#   bash examples/depletion/run_bias.sh
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
LMP=$ROOT/build/lmp
SCR=${SCR:-$HERE/scratch/bias}; OUT=${OUT:-$HERE/results_bias.md}
mkdir -p "$SCR"
cd "$SCR"
fin() { [ "${FORCE:-0}" != 1 ] && [ -f "log.$1" ] && grep -q "^RESULT" "log.$1"; }
# in.ao: "tag|-var arguments" (the first -var of a name wins: these come before the defaults)
AO=(
  "lv_d0.1_dt0.005|-var damp 0.1 -var nrun 200000 -var seed 103"
  "lv_d0.2_dt0.005|-var damp 0.2 -var nrun 200000 -var seed 104"
  "lv_d0.1_dt0.0025|-var damp 0.1 -var dt 0.0025 -var nrun 400000 -var seed 105"
  "ber_d0.1_dt0.005|-var thermostat berendsen -var damp 0.1 -var nrun 200000 -var seed 102"
  "hs_rho0.05_lv_d0.1|-var pair hs -var damp 0.1 -var nrun 50000 -var seed 106"
  "hs_rho0.05_lv_d2.0|-var pair hs -var damp 2.0 -var nrun 50000 -var seed 108"
  "hs_rho0.05_ber_d0.1|-var pair hs -var thermostat berendsen -var damp 0.1 -var nrun 50000 -var seed 107"
  "hs_rho0.05_nve|-var pair hs -var damp 0.1 -var nve yes -var nrun 50000 -var seed 109"
  "hs_rho0.5_lv_d0.1|-var pair hs -var rho 0.5 -var damp 0.1 -var nrun 50000 -var seed 106"
  "hs_rho0.5_ber_d0.1|-var pair hs -var rho 0.5 -var thermostat berendsen -var damp 0.1 -var nrun 50000 -var seed 107"
  # rho 0.3, against the MC of results_mc.md (no series)
  "lv_d0.1_rho0.3|-var damp 0.1 -var rho 0.3 -var equil 10000 -var nrun 60000 -var seed 2026"
  "ber_rho0.3|-var thermostat berendsen -var damp 0.1 -var rho 0.3 -var equil 10000 -var nrun 60000 -var seed 2025"
  "ber_d2.0_rho0.3|-var thermostat berendsen -var damp 2.0 -var rho 0.3 -var equil 10000 -var nrun 60000 -var seed 2027"
  "nve_rho0.3|-var nve yes -var damp 2.0 -var rho 0.3 -var equil 10000 -var nrun 60000 -var seed 2028"
)
tags=()
for s in "${AO[@]}"; do
  tag=${s%%|*}; args=${s#*|}; tags+=("$tag")
  # shellcheck disable=SC2086
  fin "$tag" || nice -n 19 "$LMP" -in "$HERE/in.ao" $args -var q 0.2 -var rho 0.05 -var root "$ROOT" \
    -var equil 5000 -var tag "$tag" -log "log.$tag" -screen none > /dev/null
done
for d in 0.1 2.0; do
  tag=lj_damp${d}_dt0.005; tags+=("$tag")
  fin "$tag" || nice -n 19 "$LMP" -in "$HERE/in.halfstep" -var damp $d -var tag "$tag" -log "log.$tag" -screen none > /dev/null
done
{
  echo "# Depletion example: the thermostat bias (README.md, \"The thermostat bias: mechanism\")"
  echo
  echo "Written by \`run_bias.sh\` (\`bias.py\`). One standard error (blocking); in brackets (Z - series) / error."
  echo
  /usr/bin/python3 "$HERE/bias.py" "$SCR" "${tags[@]}"
} > "$OUT"
cat "$OUT"
