#!/bin/bash
# compute hamiltonian/modified gives the same H, H_[2,VV], H_[4,VV] (and the
# corrections [4], [5]) on 1, 2 and 4 MPI ranks, on every path (auto =
# single for pair/bond + fdiff for angles; fdiff), with newton on and off,
# for the whole system and a group; the auto and fdiff paths agree.
#   bash test_mpi_hamiltonian.sh <lmp> <source dir>
# System: 16 four-atom chains (harmonic bonds and angles) in a periodic 8^3
# box with lj/cut or a Gaussian pair repulsion; chains and pairs cross the
# periodic faces and the rank boundaries. comm_modify cutoff 7 gives every
# rank all atoms of the angles it stores with newton off.

source "$(dirname "${BASH_SOURCE[0]}")/lib/lib_mpi.sh"
mpi_init test_mpi_hamiltonian "$@"

# data file: chain c (0..15) at grid point (y, z) = (c % 4, c / 4) * 2 + 1,
# atoms at x = 0.5, 1.5, 2.5, 3.5, deterministically perturbed
awk 'BEGIN {
  print "chains for test_mpi_hamiltonian\n"
  print "64 atoms\n48 bonds\n32 angles\n1 atom types\n1 bond types\n1 angle types\n"
  print "0 8 xlo xhi\n0 8 ylo yhi\n0 8 zlo zhi\n"
  print "Masses\n\n1 1.0\n\nAtoms # molecular\n"
  for (c = 0; c < 16; c++)
    for (a = 0; a < 4; a++) {
      id = 4 * c + a + 1
      x = 0.5 + a + 0.15 * sin(1.3 * id)
      y = 2 * (c % 4) + 1 + 0.3 * sin(2.1 * id + 1)
      z = 2 * int(c / 4) + 1 + 0.3 * sin(0.7 * id + 2)
      printf "%d %d 1 %.10f %.10f %.10f\n", id, c + 1, x, y, z
    }
  print "\nBonds\n"
  n = 0
  for (c = 0; c < 16; c++)
    for (a = 0; a < 3; a++) printf "%d 1 %d %d\n", ++n, 4 * c + a + 1, 4 * c + a + 2
  print "\nAngles\n"
  n = 0
  for (c = 0; c < 16; c++)
    for (a = 0; a < 2; a++) printf "%d 1 %d %d %d\n", ++n, 4 * c + a + 1, 4 * c + a + 2, 4 * c + a + 3
}' > data.chains

# in.<sys>: common part + pair style. lj: lj/cut 2.5 (special 0 1 1), whose
# force jumps at the cutoff: path auto only (path fdiff reports NaN when a
# pair is within the difference steps of the cutoff). gauss: a Gaussian
# repulsion 2 exp(-r^2) cut at 6.5 (smooth to 1e-18), special 1 1 1: all paths.
common() {
  cat <<'EOF'
units       lj
atom_style  molecular
newton      ${newton}
read_data   data.chains
bond_style  harmonic
bond_coeff  1 5.0 1.0
angle_style harmonic
angle_coeff 1 2.0 180.0
EOF
}
tail_part() {
  cat <<'EOF'
group       half molecule <> 1 8
velocity    all create 1.0 4928459 loop geom
neighbor    0.3 bin
comm_modify cutoff 7.0
fix         nve all nve
timestep    0.005
compute     hm ${grp} hamiltonian/modified path ${path}
thermo_style custom step pe c_hm[1] c_hm[2] c_hm[3] c_hm
thermo      10
run         20
print "RESULT $(c_hm[1]:%.17g) $(c_hm[2]:%.17g) $(c_hm[3]:%.17g) $(c_hm[4]:%.17g) $(c_hm[5]:%.17g) $(c_hm:%.17g)"
EOF
}
{
  common
  printf 'pair_style  lj/cut 2.5\npair_coeff  1 1 1.0 1.0\nspecial_bonds lj 0.0 1.0 1.0\n'
  tail_part
} > in.lj
{
  common
  printf 'pair_style  gauss 6.5\npair_coeff  1 1 -2.0 1.0\nspecial_bonds lj 1.0 1.0 1.0\n'
  tail_part
} > in.gauss

# compare_h <label> <ref fields> <fields> <rtol> [<rtol of [4]> <rtol of [5]>]
compare_h() {
  python3 - "$@" <<'PY'
import sys, math
name, ref, got, rtol = sys.argv[1], sys.argv[2].split(), sys.argv[3].split(), float(sys.argv[4])
tols = [rtol, rtol, rtol, float(sys.argv[5]) if len(sys.argv) > 5 else rtol,
        float(sys.argv[6]) if len(sys.argv) > 6 else rtol, rtol]
labels = ["H", "H_[2,VV]", "H_[4,VV]", "dt2/24 H2", "dt4/720 H4", "scalar"]
ok = len(ref) == len(got) == 6
if not ok:
    print(f"FAIL {name}: malformed results {ref} / {got}"); sys.exit(1)
for lab, a, b, tol in zip(labels, ref, got, tols):
    a, b = float(a), float(b)
    rel = abs(a - b) / max(abs(a), 1e-300)
    good = math.isfinite(a) and math.isfinite(b) and rel <= tol
    print(f"  {name:36s} {lab:10s} {a:.17g} vs {b:.17g}  rel.diff {rel:.2e} {'ok' if good else 'FAIL'}")
    ok = ok and good
# the corrections must be there
if not abs(float(ref[3])) > 1e-8 * abs(float(ref[0])) or not abs(float(ref[4])) > 0:
    print(f"FAIL {name}: no correction terms"); ok = False
sys.exit(0 if ok else 1)
PY
}

# check <sys> <path> <newton> <grp>: 1 rank against $NPS ranks. The H4
# correction [5] contains differences of force evaluations (angles on every
# path), whose round-off (about eps/s^3, 1e-9 of V'''') differs with the
# order of the force sums: 1e-7 relative for [5]
check() {
  local sys=$1 path=$2 newton=$3 grp=$4
  local vars=(-var newton $newton -var grp $grp -var path $path)
  local ref got
  ref=$(run "$sys.$path.$newton.$grp" 1 in.$sys "${vars[@]}") || { fail=1; return; }
  for np in $NPS; do
    got=$(run "$sys.$path.$newton.$grp" $np in.$sys "${vars[@]}") || { fail=1; continue; }
    compare_h "$sys $path newton $newton $grp np=$np" "$ref" "$got" "$RTOL" "$RTOL" 1e-7 || fail=1
  done
  echo "$ref" > res.$sys.$path.$newton.$grp
}

for newton in on off; do
  for grp in all half; do
    # 4 ranks once (ghost cutoff 7 reaches beyond the neighbouring subdomains)
    if [ $newton = on ] && [ $grp = all ]; then NPS="2 4"; else NPS="2"; fi
    check lj auto $newton $grp
    check gauss auto $newton $grp
    check gauss fdiff $newton $grp
    # the paths agree (single: r-differences of the pair's single(); fdiff:
    # force differences): H2 to ~1e-10, H4 to ~1e-5 relative
    if [ -f res.gauss.auto.$newton.$grp ] && [ -f res.gauss.fdiff.$newton.$grp ]; then
      compare_h "gauss auto vs fdiff newton $newton $grp" "$(cat res.gauss.auto.$newton.$grp)" \
        "$(cat res.gauss.fdiff.$newton.$grp)" 1e-13 1e-8 1e-4 || fail=1
    fi
  done
done

mpi_finish
