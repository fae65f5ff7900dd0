# Shared functions of the multi-rank tests (unittest/mpi/test_mpi_*.sh):
# run an input on N ranks and pick its RESULT line, compare a RESULT line with
# the 1-rank reference, check one system on several rank counts. Sourced, not
# run: it lives outside the glob unittest/mpi/*.sh that CMake turns into tests.
#   source "$(dirname "${BASH_SOURCE[0]}")/lib/lib_mpi.sh"
#   mpi_init <test name> "$@"       (sets LMP, SRC, RTOL, fail)
#   ... write inputs, set LABELS, call check_system ...
#   mpi_finish

# mpi_init <test name> <lmp> <source dir>
mpi_init() {
  MPI_TEST=$1
  LMP=${2:?usage: $MPI_TEST.sh <lmp> <source dir>}
  SRC=${3:?usage: $MPI_TEST.sh <lmp> <source dir>}
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
  RTOL=${RTOL:-1e-10}
  fail=0
}

# result_line <k...>: the print command of the RESULT line: etotal, ke, the
# base counters f_hs[1..4] (collisions, pair, wall, steps with a collision),
# then f_hs[k] for each k given
result_line() {
  local s='print "RESULT $(etotal:%.17g) $(ke:%.17g) $(f_hs[1]) $(f_hs[2]) $(f_hs[3]) $(f_hs[4])'
  local k
  for k in "$@"; do s+=" \$(f_hs[$k])"; done
  echo "$s\""
}

# chain_input <k...>: the pendulum chain example (method, dt, T, seed given
# as -var) and the RESULT line with f_hs[k] for each k given
chain_input() {
  echo "include ${SRC}/examples/pendulum-chain/in.pendulum-chain"
  result_line "$@"
}

# global_substep <method>: " substep global" for cva, pcva and mcva, whose
# default is the local engine (its rank counts: test_mpi_local.sh): these
# tests compare rank counts of the global engine
global_substep() {
  case "$1" in cva | pcva | mcva) echo " substep global" ;; esac
  return 0
}

# lj_fluid_input <method> <k...>: a periodic 3-D fluid of hard spheres
# (diameter 1) with LJ attraction (lj/cut 2.5) at density 0.6, 500 atoms,
# ${nsteps} steps (-var nsteps), and the RESULT line. Velocities use "loop
# geom" so the initial state does not depend on the rank count.
lj_fluid_input() {
  local method=$1
  shift
  cat <<EOF
units       lj
atom_style  atomic
lattice     fcc 0.6
region      box block 0 5 0 5 0 5
create_box  1 box
create_atoms 1 box
mass        1 1.0
velocity    all create 1.5 87287 mom yes rot yes dist gaussian loop geom
pair_style  lj/cut 2.5
pair_coeff  1 1 1.0 1.0 2.5
neighbor    0.3 bin
neigh_modify every 1 delay 0 check yes
fix         hs all hardsphere/$method diameter 1.0$(global_substep "$method")
timestep    0.005
thermo_style custom step pe ke etotal press f_hs[1]
thermo_modify norm no
thermo      50
run         \${nsteps}
EOF
  result_line "$@"
}

# run <name> <np> <input> <vars...>: prints the RESULT line's fields (output
# in out.<name>.<np>); on a failed run or no RESULT line prints NORESULT and
# returns 1
run() {
  local name=$1 np=$2 input=$3
  shift 3
  local out=out.$name.$np
  if [ "$np" -eq 1 ]; then
    "$LMP" -in "$input" -log none -echo none "$@" > "$out" 2>&1
  else
    mpirun -np "$np" --oversubscribe "$LMP" -in "$input" -log none -echo none "$@" > "$out" 2>&1
  fi
  local rc=$?
  local res
  res=$(grep '^RESULT ' "$out" | tail -1)
  if [ $rc -ne 0 ] || [ -z "$res" ]; then
    echo "FAIL: $name on $np ranks exited with $rc / no RESULT line; output:" >&2
    tail -20 "$out" >&2
    echo "NORESULT"
    return 1
  fi
  echo "${res#RESULT }"
}

# compare <name> <ref fields> <fields> <np>: the RESULT fields named by the
# array LABELS (their number is checked); the first two (energies) and those
# whose label starts with "~" (e.g. a fingerprint of the positions) must
# agree to RTOL relative, all others (counters) exactly
compare() {
  local name=$1 ref=$2 got=$3 np=$4
  python3 - "$name" "$ref" "$got" "$np" "$RTOL" "${LABELS[@]}" <<'PY'
import sys
name, ref, got, np, rtol = sys.argv[1], sys.argv[2].split(), sys.argv[3].split(), sys.argv[4], float(sys.argv[5])
labels = sys.argv[6:]
width = max(10, max(len(l) for l in labels))
ok = len(ref) == len(got) == len(labels)
if not ok:
    print(f"FAIL {name}: malformed results {ref} / {got}"); sys.exit(1)
for i, (lab, a, b) in enumerate(zip(labels, ref, got)):
    a, b = float(a), float(b)
    if i < 2 or lab.startswith("~"):
        rel = abs(a - b) / max(abs(a), 1e-300)
        good = rel <= rtol
        print(f"  {name:6s} np={np} {lab:{width}s} 1 rank {a:.17g}  {np} ranks {b:.17g}  rel.diff {rel:.2e} {'ok' if good else 'FAIL'}")
    else:
        good = a == b
        print(f"  {name:6s} np={np} {lab:{width}s} 1 rank {a:g}  {np} ranks {b:g}  {'ok' if good else 'FAIL'}")
    ok = ok and good
sys.exit(0 if ok else 1)
PY
}

# check_system <name> <input> <rank counts> <vars...>: 1 rank is the
# reference, which must pass the awk condition REF_CHECK (default: field 3,
# the collision count, > 0: the system must actually collide); every rank
# count in <rank counts> is compared with it
REF_CHECK='$3 > 0'
REF_CHECK_MSG='no collisions'
check_system() {
  local name=$1 input=$2 nps=$3
  shift 3
  local ref
  ref=$(run "$name" 1 "$input" "$@") || { fail=1; return; }
  if ! echo "$ref" | awk "{exit !($REF_CHECK)}"; then
    echo "FAIL: $name has $REF_CHECK_MSG on 1 rank ($ref)"
    fail=1
  fi
  local np got
  for np in $nps; do
    got=$(run "$name" "$np" "$input" "$@") || { fail=1; continue; }
    compare "$name" "$ref" "$got" "$np" || fail=1
  done
}

# mpi_finish: the verdict and the exit status
mpi_finish() {
  if [ $fail -ne 0 ]; then
    echo "$MPI_TEST: FAILED"
    exit 1
  fi
  echo "$MPI_TEST: all comparisons passed (relative tolerance $RTOL)"
  exit 0
}
