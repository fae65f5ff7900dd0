#!/bin/bash
# The accuracy table of doc/fix_hardsphere.rst ("Step engines"): max energy
# error per atom over TSPAN time units of the hard-core LJ fluid (in.accuracy:
# lj/smooth/linear 2.5, packing fraction 0.3, T = 1), mean over the starting
# velocities SEEDS (the max of one trajectory is set by a few events), for
# each method in METHODS with the local and the global engine, and for fix
# nve on the same forces (no hard cores: Verlet's own error).
#   bash bench/scaling/accuracy.sh                       # 500 spheres, 5 time units
#   CELLS=10 SEEDS=111 ENGINES=local bash bench/scaling/accuracy.sh   # 4000 spheres
# Variables: CELLS (4 x CELLS^3 spheres; 5), TSPAN (5), SEEDS ("111 222 333
# 444"), DTS ("0.005 0.0025 0.00125"), METHODS ("cva pcva"), ENGINES ("local
# global"), LMP (build/lmp), NP (MPI ranks; 1: no mpirun), HTILDE (yes: the
# modified Hamiltonian H~ of compute hamiltonian/modified instead of the energy,
# for mcva; fix nve's column is then left out).
#   NP=2 CELLS=10 SEEDS="111 222" ENGINES=local bash bench/scaling/accuracy.sh   # on 2 ranks
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
LMP=${LMP:-$HERE/../../build/lmp}
SEEDS=${SEEDS:-"111 222 333 444"}
CELLS=${CELLS:-5}
TSPAN=${TSPAN:-5}
METHODS=${METHODS:-"cva pcva"}
ENGINES=${ENGINES:-"local global"}
PY=/usr/bin/python3
NP=${NP:-1}
LAUNCH=()
if [ "$NP" -gt 1 ]; then
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
  LAUNCH=(mpirun -np "$NP" --oversubscribe)
fi

cols=("nve")
cmds=("fix hs all nve")
for m in $METHODS; do
  for e in $ENGINES; do
    cols+=("$m-$e")
    cmds+=("fix hs all hardsphere/$m diameter 1.0 substep $e")
  done
done
q=E; [ "${HTILDE:-no}" = yes ] && q="H~"
echo "max |$q(t) - $q(0)| per atom over $TSPAN time units, $((4 * CELLS ** 3)) spheres, mean over seeds $SEEDS, $NP MPI rank(s)"
printf "%-8s" dt; for c in "${cols[@]}"; do printf " %-12s" "$c"; done; printf " %-12s\n" "coll/step"
for dt in ${DTS:-0.005 0.0025 0.00125}; do
  printf "%-8s" "$dt"
  coll=""
  for k in "${!cols[@]}"; do
    if [ "${HTILDE:-no}" = yes ] && [ "$k" = 0 ]; then printf " %-12s" "-"; continue; fi
    sum=0; n=0
    for seed in $SEEDS; do
      out=$("${LAUNCH[@]}" "$LMP" -in "$HERE/in.accuracy" -var seed "$seed" -var dt "$dt" -var cells "$CELLS" \
            -var tspan "$TSPAN" -var htilde "${HTILDE:-no}" -var counts "$([ "$k" = 0 ] && echo no || echo yes)" -var fixcmd "${cmds[$k]}" -log none -echo none | grep '^ACC')
      e=$(awk '{print $3}' <<<"$out")
      [ "$k" = 1 ] && coll=$(awk -v s="$TSPAN" -v d="$dt" '{print $5 * d / s}' <<<"$out")
      sum=$($PY -c "print($sum + $e)"); n=$((n + 1))
    done
    printf " %-12s" "$($PY -c "print('%.2e' % ($sum / $n))")"
  done
  printf " %-12s\n" "${coll:--}"
done
