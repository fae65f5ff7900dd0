#!/bin/bash
# The local engine (the default of hardsphere/cva) on 1, 2 and 4 MPI ranks
# (issue 20): the same collision counts (pair, wall, steps with a
# collision, clusters, growth rounds) exactly, and energies and (fluids,
# melt) a fingerprint of the positions equal to RTOL.
#   bash test_mpi_local.sh <lmp> <source dir>
# Systems: the hard-core LJ fluid (density 0.6) at 500 atoms over 200 steps
# (and as three runs of 100, 3 and 200 steps)
# and at 4000 atoms over 300 steps; the same 500 hot (T 3) with a small skin,
# so that atoms change rank between the two halves of a step; the 500 with
# fix viscous (held forces, deterministic); a bead-spring melt with bonds,
# angles, dihedrals and special weights (newton_bond on and off); fix
# langevin on 2 ranks (mean
# temperature within its error bar); half of the 500 as a solvent under fix
# nve defined before the spheres' fix (cva and vci), and the same with
# the solvent's pairs excluded (neigh_modify exclude; cva and pcva), and a
# melt half of whose chains are free with exclude molecule/intra; a chain
# of four hit at its end in a box with one short side; and exact
# boundary cases in a force-free box split into slabs (processors N 1 1):
# a head-on pair across a sub-domain face and across the periodic face
# (velocities exchanged exactly), a Newton's cradle of four spheres that
# spans two or three ranks and grows across them within a step (the last
# sphere leaves with the striker's velocity), a pair plus two wall
# contacts at a rank face, and 18 pairs across rank faces whose runners
# (who runs each cluster: output entry 16) split as the rule says. Then the error of a cluster that outgrows the
# ghost region, the counted fall-back to the global engine (overflow
# global) and the widened ghost cutoff (overflow widen); charged spheres
# with pppm and fix efield (held smooth forces, cva and vci), also between
# this fix's walls with pppm's slab correction; ghost lazy's
# shell (a collision-free run is fix nve's to the bit on 2 ranks, with its
# ghost atoms; a dilute fluid whose shell widens and narrows many times
# equals 1 rank); a triclinic box; newton off (fluids and melt); an error found by one rank inside a
# cluster ends every rank. hardsphere/pcva on the fluids, the hot and held
# fluid, the hot fluid tethered by fix spring/self (alone, and beside fix
# viscous: the thermostat's held force split from the spring's) and the
# melt (bonds only) as well, hardsphere/vci on the fluids,
# the hot and held fluid and the melt.

source "$(dirname "${BASH_SOURCE[0]}")/lib/lib_mpi.sh"
mpi_init test_mpi_local "$@"

no_fallback() {    # no_fallback <name> <rank counts>: no rank count took substep global
  local np
  for np in $2; do
    if grep -q "falls back to substep global" "out.$1.$np"; then
      echo "  FAIL: $1 on $np ranks fell back to substep global:"; grep "falls back" "out.$1.$np" | head -1
      fail=1
    fi
  done
}

# with_fingerprint: an input (stdin) with a fingerprint of the positions
# last on its RESULT line, the sum over atoms of xu^2 + 2 yu^2 + 3 zu^2
# (unwrapped; not weighted by ID: create_atoms numbers the lattice rank by
# rank), compared to RTOL ("~positions"); in the thermo output, so that it
# is current at the run's end. Energies alone would not see e.g. two equal
# spheres' velocities exchanged
with_fingerprint() {
  sed 's/^timestep/compute     pu all property\/atom xu yu zu\nvariable    fp atom c_pu[1]*c_pu[1]+2*c_pu[2]*c_pu[2]+3*c_pu[3]*c_pu[3]\ncompute     fp all reduce sum v_fp\ntimestep/; s/^thermo_style custom .*$/& c_fp/; /^print "RESULT/s/"$/ $(c_fp:%.17g)"/'
}

# fluid: lj_fluid_input without its " substep global"; clusters (f_hs[6])
# and growth rounds (f_hs[9]) added to the RESULT line, then the positions'
# fingerprint
fluid() {
  lj_fluid_input cva 6 9 | sed "s/ substep global//; s/region      box block 0 5 0 5 0 5/region      box block 0 $1 0 $1 0 $1/; s/^atom_style  atomic/atom_style  atomic\natom_modify map array/" | with_fingerprint
}
fluid 5 > in.local_fluid500
fluid 10 > in.local_fluid4000
fluid 5 | sed 's/create 1.5/create 3.0/; s/neighbor    0.3 bin/neighbor    0.2 bin/' > in.local_hot
# three runs (LAMMPS counts the list builds from 0 again at each run: a run
# with collisions and no rebuild after its set-up, the 3 steps, once left
# the next run with its rows, "a collision was missed" on every rank count)
fluid 5 | sed 's/^run \+\${nsteps}$/run         100\nrun         3\nrun         ${nsteps}/' > in.local_runs
grep -q "^run         3$" in.local_runs || { echo "FAIL: in.local_runs has no short run"; exit 1; }

LABELS=("etotal" "ke" "collisions" "pair" "wall" "coll.steps" "clusters" "rounds" "~positions")
echo "hard-core LJ fluid, 500 atoms, 200 steps, default engine, 1, 2, 4 ranks:"
check_system fluid500 in.local_fluid500 "2 4" -var nsteps 200
echo "the same as three runs, 100 steps, 3 and 200:"
check_system runs in.local_runs "2 4" -var nsteps 200
echo "the same at 4000 atoms, 300 steps:"
check_system fluid4000 in.local_fluid4000 "2 4" -var nsteps 300
echo "500 atoms at T 3 with skin 0.2 (atoms change rank within steps), 200 steps:"
check_system hot in.local_hot "2 4" -var nsteps 200
# held forces: fix viscous (deterministic, unlike langevin) taken as half
# kicks around the members' flows and in Phi_H2's kicks
sed 's/^fix         hs all hardsphere/fix         vi all viscous 0.2\nfix         hs all hardsphere/' in.local_fluid500 > in.local_held
echo "500 atoms with fix viscous 0.2 (held forces), 200 steps:"
check_system held in.local_held "2 4" -var nsteps 200

# a solvent under fix nve beside the spheres, its fix defined first: the
# atoms it moves before the engine's turn must be seen at their new
# positions by every copy (their ghosts had the old ones, and 1, 2 and 4
# ranks took different steps). The groups by region: create_atoms numbers
# the atoms rank by rank
sed 's/^fix         hs all hardsphere\/cva diameter 1.0$/region      low block INF INF INF INF INF 2.5\ngroup       solv region low\ngroup       hsg subtract all solv\nfix         nv solv nve\nfix         hs hsg hardsphere\/cva diameter 1.0/' \
  in.local_fluid500 > in.local_solvent
grep -q "^fix         nv solv nve$" in.local_solvent || { echo "FAIL: in.local_solvent has no solvent"; exit 1; }
echo "500 atoms, half of them a solvent under fix nve defined before the spheres' fix, 200 steps:"
check_system solvent in.local_solvent "2 4" -var nsteps 200
# an ideal solvent: neigh_modify exclude group solv solv takes the
# solvent's pairs off LAMMPS' lists; the engine's rows leave them out too,
# so it runs on every rank count (it fell back to the global engine on
# several ranks before 30 Nov 2026: other collisions than on 1 rank)
sed 's/^group       hsg subtract all solv$/&\nneigh_modify exclude group solv solv/' \
  in.local_solvent > in.local_exclude
grep -q "^neigh_modify exclude group solv solv$" in.local_exclude || { echo "FAIL: in.local_exclude has no exclusion"; exit 1; }
echo "the same with the solvent's pairs excluded (neigh_modify exclude group solv solv), 200 steps:"
check_system exclude in.local_exclude "2 4" -var nsteps 200
# (pcva keeps a closed system's H_[2,VV]: the solvent frozen, the idiom of
# a wall's atoms excluded from each other)
sed 's/hardsphere\/cva/hardsphere\/pcva/; s/f_hs\[6\]) $(f_hs\[9\])/f_hs[6]) $(f_hs[7]) $(f_hs[9]) $(f_hs[12])/; /^fix         nv solv nve$/d' \
  in.local_exclude > in.local_pcvaexclude
echo "the same with hardsphere/pcva, the solvent frozen:"
LABELS=("etotal" "ke" "collisions" "pair" "wall" "coll.steps" "projections" "skipped" "clusters" "rounds" "~positions")
check_system pcvaexclude in.local_pcvaexclude "2 4" -var nsteps 200
no_fallback exclude "2 4"
no_fallback pcvaexclude "2 4"
LABELS=("etotal" "ke" "collisions" "pair" "wall" "coll.steps" "clusters" "rounds" "~positions")

# the same with the lists built in every step (1 rank): the steps must not
# depend on when the lists were built. They did (1.4e-5 in etotal, a cluster
# more) while F_X(q0) took LAMMPS' start forces, at the solvent's old
# positions, against V_C at its new ones
sed 's/^neigh_modify every 1 delay 0 check yes$/neigh_modify every 1 delay 0 check no/' in.local_solvent > in.local_solvent_every
grep -q "check no" in.local_solvent_every || { echo "FAIL: in.local_solvent_every builds the lists as before"; exit 1; }
echo "the same with the lists built in every step, 1 rank:"
if ref=$(run solvent 1 in.local_solvent -var nsteps 200) && got=$(run solvent_every 1 in.local_solvent_every -var nsteps 200); then
  compare solvent_every "$ref" "$got" 1 || fail=1
else
  fail=1
fi
# (vci's counters as in method_cases below)
sed 's/hardsphere\/cva/hardsphere\/vci/; s/f_hs\[6\]) $(f_hs\[9\])/f_hs[6]) $(f_hs[7]) $(f_hs[8]) $(f_hs[12]) $(f_hs[15])/' \
  in.local_solvent > in.local_vcisolvent
echo "the same with hardsphere/vci:"
LABELS=("etotal" "ke" "collisions" "pair" "wall" "coll.steps" "solved" "noroot" "zero" "clusters" "rounds" "~positions")
check_system vcisolvent in.local_vcisolvent "2 4" -var nsteps 200
LABELS=("etotal" "ke" "collisions" "pair" "wall" "coll.steps" "clusters" "rounds" "~positions")

# bead-spring melt (molecular: the members' special lists and bonded terms
# come by atom ID, gathered when they join): 100 chains of 10 beads along
# x, 0.97 apart (FENE's minimum) on a 1.2-spaced square lattice in y, z
# (density 0.72), with a small helical offset (no straight angles or
# dihedrals); FENE bonds, angle cosine, dihedral harmonic, lj/cut 2.5 with
# special weights 0 (1-2), 0.5 (1-3, coded in the rows' special bits), 1
# (1-4); hard cores of 0.9 (bonded neighbours collide too). With
# newton_bond on and off (the engine's terms are listed once and evaluated
# with every copy taking its force).
/usr/bin/python3 "$SRC/bench/scaling/make_angle_melt.py" local_melt.data 10 0.97 1.2
melt_input() {
  cat <<EOF2
units       lj
atom_style  molecular
atom_modify map array
newton      on \${nb}
read_data   local_melt.data
velocity    all create 2.0 4928459 mom yes rot no dist gaussian loop geom
pair_style  lj/cut 2.5
pair_coeff  1 1 1.0 1.0 2.5
bond_style  fene
bond_coeff  1 30.0 1.5 1.0 1.0
angle_style cosine
angle_coeff 1 1.5
dihedral_style harmonic
dihedral_coeff 1 0.5 1 2
special_bonds lj 0.0 0.5 1.0
neighbor    0.3 bin
neigh_modify every 1 delay 0 check yes
fix         hs all hardsphere/cva diameter 0.9
timestep    0.005
thermo_style custom step pe ke etotal
thermo      50
run         \${nsteps}
EOF2
  result_line 6 9
}
melt_input | with_fingerprint > in.local_melt
echo "bead-spring melt (bonds, angles, dihedrals), 1000 beads at T 2, 200 steps, newton_bond on:"
check_system melt in.local_melt "2 4" -var nsteps 200 -var nb on
echo "the same with newton_bond off:"
check_system melt_nboff in.local_melt "2 4" -var nsteps 200 -var nb off
# half the chains free (fix nve), their beads' pairs within a chain taken
# off the lists (neigh_modify exclude molecule/intra: ghosts carry their
# molecule IDs); the other half hard spheres, on any rank count
sed 's/^fix         hs all hardsphere\/cva diameter 0.9$/group       free molecule > 50\ngroup       hard subtract all free\nneigh_modify exclude molecule\/intra free\nfix         nv free nve\nfix         hs hard hardsphere\/cva diameter 0.9/' \
  in.local_melt > in.local_meltexcl
grep -q "^neigh_modify exclude molecule/intra free$" in.local_meltexcl || { echo "FAIL: in.local_meltexcl has no exclusion"; exit 1; }
echo "the melt, half its chains free with their intra-chain pairs excluded (molecule/intra):"
check_system meltexcl in.local_meltexcl "2 4" -var nsteps 200 -var nb on
no_fallback meltexcl "2 4"

# a chain of four beads (bonds, angles, a dihedral) whose end is hit by a
# free bead, in a box with one short periodic side (z = 5). On 2 ranks the
# cluster's dihedral partner, 2.9 away, was refused as "no copy near it"
# (the bound was half the shortest period in every direction, 2.5), an
# error no comm_modify cutoff removed; on 4 ranks (2 x 2 x 1) the rank that
# runs the cluster lists no angle of its own, and the angle 2-3-4 of the
# member 4 was left out (the bonded styles' presence was taken from the
# rank's own LAMMPS list): another collision velocity than on 1 rank. Both
# before 30 Nov 2026
cat > local_chain5.data <<'EOF2'
a chain of four and a free bead

5 atoms
3 bonds
2 angles
1 dihedrals
1 atom types
1 bond types
1 angle types
1 dihedral types

0 20 xlo xhi
0 20 ylo yhi
0 5 zlo zhi

Masses

1 1.0

Atoms # molecular

1 1 1 8.00 10.00 2.5
2 1 1 8.97 10.30 2.5
3 1 1 9.94 10.00 2.5
4 1 1 10.91 10.30 2.5
5 2 1 12.30 10.30 2.5

Velocities

1 0 0 0
2 0 0 0
3 0 0 0
4 0 0 0
5 -1 0 0

Bonds

1 1 1 2
2 1 2 3
3 1 3 4

Angles

1 1 1 2 3
2 1 2 3 4

Dihedrals

1 1 1 2 3 4
EOF2
{ cat <<EOF2
units       lj
atom_style  molecular
atom_modify map array
read_data   local_chain5.data
pair_style  zero 2.0
pair_coeff  * *
bond_style  harmonic
bond_coeff  1 100.0 1.0
angle_style harmonic
angle_coeff 1 10.0 145.0
dihedral_style harmonic
dihedral_coeff 1 0.5 1 3
neighbor    0.3 bin
fix         hs all hardsphere/cva diameter 0.9
timestep    0.005
thermo_style custom step pe ke etotal
thermo      100
run         \${nsteps}
EOF2
  result_line 6 9; } | with_fingerprint > in.local_chain5
echo "a chain hit at its end in a box with a short side (z = 5), 200 steps:"
check_system chain5 in.local_chain5 "2 4" -var nsteps 200
no_fallback chain5 "2 4"

# method_cases <m> <sed filter> <melt filter> <melt text>: the fluids at 500
# and 4000 atoms, the hot and the held fluid and the melt with hardsphere/<m>
# and the RESULT fields the filter puts in, on 1, 2, 4 ranks
method_cases() {
  local m=$1 filter=$2 meltf=$3 melttext=$4
  local s
  for s in fluid500:500 fluid4000:4000 hot:hot held:held; do
    sed "$filter" < "in.local_${s%%:*}" > "in.local_$m${s##*:}"
  done
  sed "$meltf" in.local_melt | sed "$filter" > "in.local_${m}melt"
  echo "$m: fluid, 500 atoms, 200 steps:"
  check_system "${m}500" "in.local_${m}500" "2 4" -var nsteps 200
  echo "$m: fluid, 4000 atoms, 300 steps:"
  check_system "${m}4000" "in.local_${m}4000" "2 4" -var nsteps 300
  echo "$m: 500 atoms at T 3 with skin 0.2 (atoms change rank within steps), 200 steps:"
  check_system "${m}hot" "in.local_${m}hot" "2 4" -var nsteps 200
  echo "$m: 500 atoms with fix viscous 0.2 (held forces), 200 steps:"
  check_system "${m}held" "in.local_${m}held" "2 4" -var nsteps 200
  echo "$m: bead-spring melt ($melttext), 200 steps:"
  # (vci on the melt: the ranks' different summation orders grow like the
  # melt's chaos, ~10x per 25 steps: 1 and 4 ranks' kinetic energies differ
  # by 2e-13 after 100 steps, 3e-12 after 150 and 1.6e-10 after 200, with
  # every counter equal; cva's stay below 1e-10. pcva's, with its
  # projection's sums over the angle and dihedral terms in each rank's
  # order too: 7e-11 at step 200 on 2 ranks)
  local tol=$RTOL
  [ "$m" = vci ] || [ "$m" = pcva ] && RTOL=1e-9
  check_system "${m}melt" "in.local_${m}melt" "2 4" -var nsteps 200 -var nb on
  RTOL=$tol
}

# pcva's local projection (hs_local_modified.h) on the same systems: each
# rank evaluates its share of the members' terms, sums go to the owners by
# reverse communication, A, B, C0 and the clusters' centres of mass are
# reduced, members and partners found again by ID after a rebuild; the
# projections and skipped projections counted too (the melt with bonds,
# angles and dihedrals: the terms that are not radial through their styles'
# compute() on the rank that lists them)
LABELS=("etotal" "ke" "collisions" "pair" "wall" "coll.steps" "projections" "skipped" "clusters" "rounds" "~positions")
method_cases pcva 's/hardsphere\/cva/hardsphere\/pcva/; s/f_hs\[6\]) $(f_hs\[9\])/f_hs[6]) $(f_hs[7]) $(f_hs[9]) $(f_hs[12])/' \
  '' "bonds, angles, dihedrals"
no_fallback pcvamelt "1 2 4"
# the hot fluid tethered by fix spring/self (a held force with an energy:
# the members' start G and positions travel with them when they change rank
# within a step, HSLocalModified::remap())
sed 's/^fix         hs all hardsphere/fix         ss all spring\/self 0.5\nfix_modify  ss energy yes\nfix         hs all hardsphere/' \
  in.local_pcvahot > in.local_pcvahotspring
grep -q "^fix_modify  ss energy yes$" in.local_pcvahotspring || { echo "FAIL: in.local_pcvahotspring has no spring"; exit 1; }
echo "pcva: the hot fluid tethered by fix spring/self 0.5 (held, with energy), 200 steps:"
check_system pcvahotspring in.local_pcvahotspring "2 4" -var nsteps 200
no_fallback pcvahotspring "2 4"
# ... and beside a thermostat's held forces (fix viscous after the
# integrator): the fix's copy of LAMMPS' force before the thermostat's
# splits a member's held force, the thermostat's part forwarded to the
# member's ghost copies (HSLocalEngine::kick0); the copy survives the
# engine's own ghost rebuilds (reborder()), so 1 rank and several split alike
sed 's/^fix         hs all hardsphere.*$/&\nfix         vis all viscous 0.2/' \
  in.local_pcvahotspring > in.local_pcvahotspringvis
echo "pcva: the same with fix viscous 0.2 after the integrator (thermostat split from the spring), 200 steps:"
check_system pcvahotspringvis in.local_pcvahotspringvis "2 4" -var nsteps 200
no_fallback pcvahotspringvis "2 4"
for np in 1 2 4; do
  grep -q "fix vis viscous stay two half kicks" "out.pcvahotspringvis.$np" || {
    echo "  FAIL: pcvahotspringvis on $np ranks: the thermostat's forces are not split from the spring's"
    fail=1
  }
done

# vci's local form (the discrete energy matched inside each cluster's flow,
# its trial sub-steps on the runner's copies; its counters summed over the
# ranks from the step's final flows): solved, no root, zero-length contacts
# (f_hs[6..8]) and the engine's clusters and rounds (f_hs[12], f_hs[15])
# equal on 1, 2, 4 ranks; the melt with bonds, angles, dihedrals. Not the
# trial sub-steps (f_hs[9]): the secant's last step to round-off depends
# on the summation order of the copies (e.g. 7127 / 7113 / 7129 here)
LABELS=("etotal" "ke" "collisions" "pair" "wall" "coll.steps" "solved" "noroot" "zero" "clusters" "rounds" "~positions")
method_cases vci 's/hardsphere\/cva/hardsphere\/vci/; s/f_hs\[6\]) $(f_hs\[9\])/f_hs[6]) $(f_hs[7]) $(f_hs[8]) $(f_hs[12]) $(f_hs[15])/' \
  '' "bonds, angles, dihedrals"
LABELS=("etotal" "ke" "collisions" "pair" "wall" "coll.steps" "clusters" "rounds")

# polydisperse spheres with per-atom radii and masses (atom style sphere:
# diameters 1.0 and 1.5, a 70:30 mixture at T 2, lj/cut 2.5), the way
# colloid and polydisperse hard-sphere inputs give radii. Atom styles with
# torques fell back to the global engine on several ranks until the
# restricted evaluations kept LAMMPS' torques apart (hs_local_forces.cpp):
# the same collisions and clusters on 1, 2, 4 ranks, no fall-back warning;
# pcva also with fix viscous (held forces: the projection's conservative
# forces through the reverse communication, which carries the torques)
poly_input() {
  cat <<EOF2
units       lj
atom_style  sphere
atom_modify map array
lattice     sc 0.22
region      box block 0 10 0 10 0 10
create_box  2 box
create_atoms 1 box
set         group all type/fraction 2 0.3 4821
set         type 1 diameter 1.0
set         type 2 diameter 1.5
set         group all density 1.9099
velocity    all create 2.0 4928 mom yes rot no dist gaussian loop geom
pair_style  lj/cut 2.5
pair_coeff  * * 1.0 1.0 2.5
pair_modify shift yes
neighbor    0.3 bin
neigh_modify every 1 delay 0 check yes
fix         hs all hardsphere/cva
timestep    0.005
thermo      50
run         \${nsteps}
EOF2
  result_line 6 9
}
# cva_and_pcva <name> <what> <pcva's what> [sed for pcva's input]: in.local_<name>
# with cva, then with pcva (its projections and skipped ones on the RESULT
# line; in.local_pcva<name>), 200 steps on 1, 2, 4 ranks, neither falling
# back to substep global
cva_and_pcva() {
  local name=$1 what=$2 pwhat=$3 extra=${4:-}
  LABELS=("etotal" "ke" "collisions" "pair" "wall" "coll.steps" "clusters" "rounds")
  echo "$what, 200 steps:"
  check_system "$name" "in.local_$name" "2 4" -var nsteps 200
  no_fallback "$name" "2 4"
  pcva_too "$name" "$pwhat" "$extra"
}
# vci_too <name>: in.local_<name> with hardsphere/vci (its solved, no-root and
# zero-impulse counts on the RESULT line; in.local_vci<name>), 200 steps on
# 1, 2, 4 ranks, no fall-back to substep global
vci_too() {
  sed 's/hardsphere\/cva/hardsphere\/vci/; s/f_hs\[6\]) $(f_hs\[9\])/f_hs[6]) $(f_hs[7]) $(f_hs[8]) $(f_hs[12]) $(f_hs[15])/' \
    "in.local_$1" > "in.local_vci$1"
  LABELS=("etotal" "ke" "collisions" "pair" "wall" "coll.steps" "solved" "noroot" "zero" "clusters" "rounds")
  echo "vci: the same, 200 steps:"
  check_system "vci$1" "in.local_vci$1" "2 4" -var nsteps 200
  no_fallback "vci$1" "2 4"
  LABELS=("etotal" "ke" "collisions" "pair" "wall" "coll.steps" "clusters" "rounds")
}
# pcva_too <name> [what] [sed]: in.local_<name> with hardsphere/pcva (its
# projections and skipped ones on the RESULT line; in.local_pcva<name>,
# changed by the sed script if given), 200 steps on 1, 2, 4 ranks, no
# fall-back to substep global
pcva_too() {
  local name=$1 what=${2:-the same} extra=${3:-}
  sed 's/hardsphere\/cva/hardsphere\/pcva/; s/f_hs\[6\]) $(f_hs\[9\])/f_hs[6]) $(f_hs[7]) $(f_hs[9]) $(f_hs[12])/' \
    "in.local_$name" | sed "${extra:-}" > "in.local_pcva$name"
  LABELS=("etotal" "ke" "collisions" "pair" "wall" "coll.steps" "projections" "skipped" "clusters" "rounds")
  echo "pcva: $what, 200 steps:"
  check_system "pcva$name" "in.local_pcva$name" "2 4" -var nsteps 200
  no_fallback "pcva$name" "2 4"
  LABELS=("etotal" "ke" "collisions" "pair" "wall" "coll.steps" "clusters" "rounds")
}
poly_input > in.local_poly
cva_and_pcva poly "polydisperse spheres (atom style sphere), 1000 atoms" \
  "the same with fix viscous 0.2 (held forces)" 's/^fix         hs all hardsphere.*$/&\nfix         vis all viscous 0.2/'

# a triclinic box, tilted by whole lattice cells (the fcc crystal fits):
# ghost lazy's widening rebuilds the ghost atoms, in box fractions as
# Verlet does (with Cartesian positions every rank count but 1 missed
# collisions at step 8)
lj_fluid_input cva 6 9 | sed "s/ substep global//; s/^region      box block 0 5 0 5 0 5$/region      box prism 0 5 0 5 0 5 2 1 2/; s/^atom_style  atomic/atom_style  atomic\natom_modify map array/" > in.local_tri
grep -q "^region      box prism 0 5 0 5 0 5 2 1 2$" in.local_tri || { echo "FAIL: in.local_tri has no triclinic box"; exit 1; }
cva_and_pcva tri "a triclinic box (tilts xy 2, xz 1, yz 2 lattice cells), 500 atoms" \
  "the same triclinic box"
vci_too tri

# newton off (pair and bond): the interaction rows list each term once and
# evaluate it with newton_pair on, so ghost partners take their part too;
# before 30 Nov 2026 every rank count but 1 fell back to the global engine
# (4000 atoms, 200 steps: 9509 collisions on 2 ranks against 9544, 12x
# slower). cva, pcva, vci on the 500-atom fluid, cva on the 4000 and on the
# melt
lj_fluid_input cva 6 9 | sed "s/ substep global//; s/^atom_style  atomic/atom_style  atomic\natom_modify map array\nnewton      off/" > in.local_newtoff
grep -q "^newton      off$" in.local_newtoff || { echo "FAIL: in.local_newtoff has no newton off"; exit 1; }
cva_and_pcva newtoff "newton off, 500 atoms" "the same"
vci_too newtoff
sed 's/^atom_modify map array$/&\nnewton      off/' in.local_fluid4000 > in.local_newtoff4000
grep -q "^newton      off$" in.local_newtoff4000 || { echo "FAIL: in.local_newtoff4000 has no newton off"; exit 1; }
LABELS=("etotal" "ke" "collisions" "pair" "wall" "coll.steps" "clusters" "rounds" "~positions")
echo "newton off, 4000 atoms, 300 steps:"
check_system newtoff4000 in.local_newtoff4000 "2 4" -var nsteps 300
no_fallback newtoff4000 "2 4"
sed 's/^newton      on \${nb}$/newton      off ${nb}/' in.local_melt > in.local_meltnewtoff
grep -q "^newton      off" in.local_meltnewtoff || { echo "FAIL: in.local_meltnewtoff has no newton off"; exit 1; }
echo "the bead-spring melt with newton off off, 200 steps:"
check_system meltnewtoff in.local_meltnewtoff "2 4" -var nsteps 200 -var nb off
no_fallback meltnewtoff "2 4"
LABELS=("etotal" "ke" "collisions" "pair" "wall" "coll.steps" "clusters" "rounds")

# pair hybrid: the restricted rows split among the sub-styles' own lists by
# their type skips (hs_local_forces.cpp, "pair hybrid"): a 50:50 mixture
# with lj/cut between type 1 spheres, a soft repulsion between unlike ones
# and nothing (none) between type 2 ones; cva and pcva, no fall-back
hybrid_input() {
  cat <<EOF2
units       lj
atom_style  atomic
atom_modify map array
lattice     sc 0.4
region      box block 0 10 0 10 0 10
create_box  2 box
create_atoms 1 box
set         group all type/fraction 2 0.5 4821
mass        * 1.0
velocity    all create 1.5 4928 mom yes rot no dist gaussian loop geom
pair_style  hybrid lj/cut 2.5 soft 1.12
pair_coeff  1 1 lj/cut 1.0 1.0 2.5
pair_coeff  1 2 soft 5.0
pair_coeff  2 2 none
neighbor    0.3 bin
neigh_modify every 1 delay 0 check yes
fix         hs all hardsphere/cva diameter 1.0
timestep    0.005
thermo      50
run         \${nsteps}
EOF2
  result_line 6 9
}
hybrid_input > in.local_hybrid
cva_and_pcva hybrid "a mixture under pair hybrid (lj/cut, soft, none), 1000 atoms" "the same"

# held smooth forces: kspace and force fixes that only add to f ride inside
# the members' flows as the constant G(q0) = f - F_C (hs_local_engine.cpp,
# held_smooth); charged hard spheres (coul/long + pppm) in a field (fix
# efield), 1000 ions: cva, pcva (its ledger counts the held forces' work on
# the members) and vci, no fall-back
charged_input() {
  cat <<EOF2
units       lj
atom_style  charge
atom_modify map array
lattice     sc 0.2
region      box block 0 10 0 10 0 10
create_box  2 box
create_atoms 1 box
variable    odd atom id%2
group       anion variable odd
set         group anion type 2
set         type 1 charge 1.0
set         type 2 charge -1.0
mass        * 1.0
velocity    all create 1.0 4928 mom yes rot no dist gaussian loop geom
pair_style  coul/long 4.0
pair_coeff  * *
kspace_style pppm 1e-4
neighbor    0.3 bin
neigh_modify every 1 delay 0 check yes
fix         ef all efield 0.2 0.0 0.0
fix_modify  ef energy yes
fix         hs all hardsphere/cva diameter 1.0
timestep    0.005
thermo      50
run         \${nsteps}
EOF2
  result_line 6 9
}
charged_input > in.local_charged
LABELS=("etotal" "ke" "collisions" "pair" "wall" "coll.steps" "clusters" "rounds")
echo "charged hard spheres, coul/long + pppm, fix efield (held smooth forces), 1000 ions, 200 steps:"
check_system charged in.local_charged "2 4" -var nsteps 200
no_fallback charged "2 4"
pcva_too charged
vci_too charged

# the same ions between this fix's walls (boundary p p f, pppm with
# kspace_modify slab), the field across them: held kspace and field forces
# with wall contacts; cva, pcva and vci, no fall-back
charged_input | sed -e 's/^atom_style  charge/&\nboundary    p p f/' \
  -e 's/^region      box block 0 10 0 10 0 10/region      box block 0 10 0 10 -0.5 9.5/' \
  -e 's/^kspace_style pppm 1e-4/&\nkspace_modify slab 3.0/' \
  -e 's/^fix         ef all efield 0.2 0.0 0.0/fix         ef all efield 0.0 0.0 0.2/' \
  -e 's/^fix         hs all hardsphere\/cva diameter 1.0/& wall zlo EDGE wall zhi EDGE/' > in.local_slab
echo "the charged spheres between walls, pppm slab, the field across them, 200 steps:"
check_system slab in.local_slab "2 4" -var nsteps 200
no_fallback slab "2 4"
pcva_too slab
vci_too slab

# fix gravity: m g in the members' V_C (inside their flows, with the cross
# force; pcva's ledger holds their -m g.q, vci's flows -F.dq) and in V_R
# for everyone else; a fluid settling onto the fix's wall at zlo, with a
# wall at zhi: cva, pcva and vci, no fall-back
gravity_input() {
  cat <<EOF2
units       lj
atom_style  atomic
atom_modify map array
boundary    p p f
lattice     fcc 0.5729578
region      box block 0 6 0 6 -0.5 6
region      fill block 0 6 0 6 0.0 5.5
create_box  1 box
create_atoms 1 region fill
mass        1 1.0
velocity    all create 1.0 4928 mom yes rot no dist gaussian loop geom
pair_style  lj/cut 2.5
pair_coeff  1 1 1.0 1.0 2.5
pair_modify shift yes
neighbor    0.3 bin
neigh_modify every 1 delay 0 check yes
fix         g all gravity 0.5 vector 0 0 -1
fix_modify  g energy yes
fix         hs all hardsphere/cva diameter 1.0 wall zlo EDGE wall zhi EDGE
timestep    0.005
thermo      50
run         \${nsteps}
EOF2
  result_line 6 9
}
gravity_input > in.local_gravity
cva_and_pcva gravity "a fluid settling under fix gravity onto a wall" "the same"
vci_too gravity

# torques stay LAMMPS' own: dipolar spheres (lj/cut/dipole/cut writes
# torques) with fix langevin (held forces: conservative forces evaluated
# after LAMMPS' own at the step's end). The torques after a run must be
# those a fresh evaluation at the same positions gives (run 0); the
# restricted evaluations once added their terms' torques to them
if "$LMP" -h | grep -q "lj/cut/dipole/cut"; then
  cat > in.local_dipole <<'EOF2'
units       lj
atom_style  hybrid sphere dipole
atom_modify map array
lattice     sc 0.3
region      box block 0 8 0 8 0 8
create_box  1 box
create_atoms 1 box
set         type 1 diameter 1.0
set         type 1 density 1.9099
set         type 1 dipole/random 2917 1.0
velocity    all create 2.0 4928 mom yes rot no dist gaussian loop geom
pair_style  lj/cut/dipole/cut 2.5
pair_coeff  * * 1.0 1.0 2.5
neighbor    0.3 bin
neigh_modify every 1 delay 0 check yes
fix         hs all hardsphere/cva
fix         lg all langevin 1.5 1.5 0.5 4431
timestep    0.005
compute     tq all property/atom tqx tqy tqz
variable    t2 atom c_tq[1]^2+c_tq[2]^2+c_tq[3]^2
compute     st all reduce sum v_t2
thermo_style custom step temp etotal f_hs[1] c_st
thermo      50
run         200
variable    after equal c_st
variable    a equal ${after}
variable    nc equal f_hs[6]
variable    ncl equal ${nc}
run         0
print "RESULT ${a} $(c_st:%.17g) ${ncl}"
EOF2
  echo "torques of dipolar spheres (lj/cut/dipole/cut) after 200 steps with fix langevin, 1 and 2 ranks:"
  for np in 1 2; do
    got=$(run dipole "$np" in.local_dipole) || { fail=1; continue; }
    read -r ta tb ncl <<< "$got"
    if python3 -c "import sys; a, b, n = $ta, $tb, $ncl; sys.exit(0 if abs(a - b) <= 1e-12 * abs(b) and b > 0 and n > 0 else 1)"; then
      echo "  dipole np=$np torques^2 after the run $ta, recomputed $tb, clusters $ncl: ok"
    else
      echo "  FAIL: dipole np=$np torques^2 after the run $ta, recomputed $tb, clusters $ncl"; fail=1
    fi
  done
  no_fallback dipole 2
else
  echo "SKIPPED (torque case): this LAMMPS has no pair style lj/cut/dipole/cut (DIPOLE package)"
fi

# a thermostat on 2 ranks: fix langevin's random forces differ with the
# rank count, so the check is statistical: the mean temperature of the
# 500 atoms over 30 time units (after 5 of equilibration) in 20 blocks,
# within 3 standard errors (and 2 %) of the target 1.5
sed 's/^fix         hs all hardsphere/fix         lg all langevin 1.5 1.5 0.5 4242\nfix         hs all hardsphere/; s/^thermo      50/thermo      50\nvariable tt equal temp\nfix tav all ave\/time 10 1 10 v_tt file T.lang.dat/' in.local_fluid500 > in.local_lang
echo "fix langevin 1.5 on 2 ranks, 7000 steps:"
if run lang 2 in.local_lang -var nsteps 7000 > /dev/null; then
  python3 - <<'PY' || fail=1
import sys
T = [float(l.split()[1]) for l in open("T.lang.dat") if l.strip() and not l.startswith("#")]
T = T[100:]                       # 5 time units (1000 steps, a sample every 10)
nb = 20
m = len(T) // nb
blocks = [sum(T[k * m:(k + 1) * m]) / m for k in range(nb)]
mean = sum(blocks) / nb
se = (sum((b - mean) ** 2 for b in blocks) / (nb - 1) / nb) ** 0.5
ok = abs(mean - 1.5) <= max(3 * se, 0.02 * 1.5)
print(f"  lang   mean T {mean:.4f} +- {se:.4f} (target 1.5) {'ok' if ok else 'FAIL'}")
sys.exit(0 if ok else 1)
PY
else
  fail=1
fi

# a force-free periodic box 10^3 (y walls where asked), atoms given as
# "x y z vx vy vz" lines in ATOMS (IDs in order), slabs in x
box_input() {
  cat <<EOF2
units       lj
atom_style  atomic
atom_modify map array
boundary    p \${yb} p
processors  \${np} 1 1
region      box block 0 10 0 10 0 10
create_box  1 box
mass        1 1.0
pair_style  lj/cut 2.5
pair_coeff  1 1 0.0 1.0 2.5
neighbor    0.3 bin
neigh_modify every 1 delay 0 check yes
EOF2
  local n=0
  while read -r x y z vx vy vz; do
    [ -z "$x" ] && continue
    n=$((n + 1))
    echo "create_atoms 1 single $x $y $z units box"
    echo "set atom $n vx $vx vy $vy vz $vz"
  done <<< "$ATOMS"
  cat <<EOF2
fix         hs all hardsphere/cva diameter 1.0 \${walls}
timestep    0.005
run         \${nsteps}
EOF2
  local s='print "RESULT $(etotal:%.17g) $(ke:%.17g) $(f_hs[1]) $(f_hs[2]) $(f_hs[3]) $(f_hs[4]) $(f_hs[6]) $(f_hs[9])'
  for k in $(seq 1 "$n"); do s+=" \$(vx[$k]:%.17g) \$(vy[$k]:%.17g)"; done
  echo "$s\""
}

# boxcase <name> <rank counts> <expected "index=value" ...>: every rank
# count against 1 rank, and the 1-rank result against the analytic values
boxcase() {
  local name=$1 nps=$2 input=in.local_$1
  shift 2
  local ref np got
  ref=$(run "$name" 1 "$input" -var np 1 -var nsteps 200 -var yb "$YB" -var walls "$WALLS") || { fail=1; return; }
  python3 - "$name" "$ref" "$@" <<'PY' || fail=1
import sys
name, ref = sys.argv[1], [float(v) for v in sys.argv[2].split()]
ok = True
for spec in sys.argv[3:]:
    k, want = spec.split("=")
    got = ref[int(k)]
    good = abs(got - float(want)) <= 1e-12 * max(1.0, abs(float(want)))
    ok = ok and good
    print(f"  {name:8s} 1 rank field {k} = {got!r} (analytic {want}) {'ok' if good else 'FAIL'}")
sys.exit(0 if ok else 1)
PY
  for np in $nps; do
    got=$(run "$name" "$np" "$input" -var np "$np" -var nsteps 200 -var yb "$YB" -var walls "$WALLS") || { fail=1; continue; }
    compare "$name" "$ref" "$got" "$np" || fail=1
  done
}

LABELS=("etotal" "ke" "collisions" "pair" "wall" "coll.steps" "clusters" "rounds")
YB=p
WALLS=""
# head-on pair across the face x = 5 of 2 ranks: velocities exchanged
ATOMS="4.2 5 5 1 0 0
5.8 5 5 -1 0 0"
box_input > in.local_face
LABELS+=("vx1" "vy1" "vx2" "vy2")
echo "head-on pair across a sub-domain face (2 ranks) and the ranks' faces (4):"
boxcase face "2 4" 2=1 8=-1 10=1
# the same across the periodic face x = 0
ATOMS="0.8 5 5 -1 0 0
9.2 5 5 1 0 0"
box_input > in.local_periodic
echo "head-on pair across the periodic face:"
boxcase periodic "2 4" 2=1 8=1 10=-1
# Newton's cradle: a striker and three spheres in a row (gaps 1e-4) across
# x = 5 (2 ranks) and x = 2.5, 5 (4 ranks); the cluster grows along the row
# within one step, each contact passes the whole velocity on
LABELS=("etotal" "ke" "collisions" "pair" "wall" "coll.steps" "clusters" "rounds")
ATOMS="1.9 5 5 2 0 0
3.4 5 5 0 0 0
4.4001 5 5 0 0 0
5.4002 5 5 0 0 0"
box_input > in.local_cradle
for k in 1 2 3 4; do LABELS+=("vx$k" "vy$k"); done
echo "Newton's cradle across 2 and 3 ranks:"
boxcase cradle "2 4" 2=3 8=0 10=0 12=0 14=2
# a pair across x = 5 that collides and then hits the wall ylo with both
# spheres: contacts of one cluster on two ranks, at a wall
LABELS=("etotal" "ke" "collisions" "pair" "wall" "coll.steps" "clusters" "rounds")
YB=f
WALLS="wall ylo 0.0"
ATOMS="4.45 0.8 5 1 -2 0
5.55 0.8 5 -1 -2 0"
box_input > in.local_wall
LABELS+=("vx1" "vy1" "vx2" "vy2")
echo "a pair and two wall contacts at a rank face:"
boxcase wall "2 4" 2=3 3=1 4=2 8=-1 9=2 10=1 11=2

# who runs the clusters across rank faces: 9 head-on pairs across x = 5
# and 9 across the periodic face x = 0, all touching at the same time
# within step 60 (3 apart in y and z: no pair term between two pairs, so
# each pair's flows cost the same evaluations), IDs growing with
# x as create_atoms numbers a lattice. Run by the owner of their lowest ID,
# rank 0 would run all 18 on 2 ranks (and ranks 0 and 1 nine each on 4):
# the busiest rank's restricted evaluations over the mean (f_hs[16]) 2.0.
# runner_of() names the member with the least splitmix64 mix of its ID;
# the split that rule gives is worked out here from the IDs and the slabs,
# and f_hs[16] must be its busiest rank's share; every pair exchanges its
# velocities, 1, 2 and 4 ranks alike
YB=p
WALLS=""
ATOMS=""
for y in 2 5 8; do for z in 2 5 8; do ATOMS+="0.79625 $y $z -1 0 0
4.20375 $y $z 1 0 0
5.79625 $y $z -1 0 0
9.20375 $y $z 1 0 0
"; done; done
box_input | sed 's/^print "RESULT.*$/print "RESULT $(f_hs[1]) $(f_hs[2]) $(f_hs[6]) $(f_hs[16]:%.17g) $(vx[1]) $(vx[2]) $(vx[3]) $(vx[4])"/' > in.local_runner
echo "clusters across rank faces, IDs growing with x: who runs them (f_hs[16]):"
for np in 1 2 4; do
  got=$(run runner "$np" in.local_runner -var np "$np" -var nsteps 200 -var yb p -var walls "") || { fail=1; continue; }
  python3 - "$np" "$got" <<'PY' || fail=1
import sys
np_, got = int(sys.argv[1]), [float(v) for v in sys.argv[2].split()]
M = (1 << 64) - 1
def mix(i):    # splitmix64's finaliser, as runner_of() in hs_local_engine.cpp
    z = ((i ^ (i >> 30)) * 0xbf58476d1ce4e5b9) & M
    z = ((z ^ (z >> 27)) * 0x94d049bb133111eb) & M
    return z ^ (z >> 31)
xs = [0.79625, 4.20375, 5.79625, 9.20375] * 9            # ID k + 1 at xs[k]
pairs = [(4 * q + 2, 4 * q + 3) for q in range(9)] + [(4 * q + 1, 4 * q + 4) for q in range(9)]
runs = [0] * np_
for a, b in pairs:
    r = min((a, b), key=mix)
    runs[int(xs[r - 1] / (10.0 / np_))] += 1
want = max(runs) * np_ / len(pairs)
old = max([sum(1 for a, b in pairs if int(xs[min(a, b) - 1] / (10.0 / np_)) == k) for k in range(np_)]) * np_ / len(pairs)
ok = got[0] == 18 and got[1] == 18 and got[2] == 18 and abs(got[3] - want) < 1e-12 \
    and got[4:8] == [1, -1, 1, -1]
print(f"  {np_} ranks: 18 collisions, 18 clusters run {runs} by rank: busiest / mean {got[3]:.4f} "
      f"(expected {want:.4f}; by the lowest ID {old:.4f}), velocities exchanged: {'ok' if ok else 'FAIL'}")
sys.exit(0 if ok else 1)
PY
done

# a cluster that outgrows the ghost region: a cradle of nine spheres whose
# runner (the owner of the member runner_of() names: of IDs 1-9, ID 7) is
# at the far end from the striker (ID 9), on 2 ranks: the runner has no
# interaction rows for the striker's end. An error naming comm_modify
# cutoff; on 1 rank the same run is fine
YB=p
WALLS=""
ATOMS="2.5002 5 5 0 0 0
7.5007 5 5 0 0 0
6.5006 5 5 0 0 0
5.5005 5 5 0 0 0
4.5004 5 5 0 0 0
3.5003 5 5 0 0 0
8.5008 5 5 0 0 0
1.5001 5 5 0 0 0
0.4 5 5 2 0 0"
box_input > in.local_long
LABELS=("etotal" "ke" "collisions" "pair" "wall" "coll.steps" "clusters" "rounds")
for k in $(seq 1 9); do LABELS+=("vx$k" "vy$k"); done
echo "a cluster beyond the ghost region:"
if run long1 1 in.local_long -var np 1 -var nsteps 100 -var yb p -var walls "" > /dev/null; then
  echo "  1 rank: runs: ok"
else
  echo "  FAIL: the long cradle fails on 1 rank"; fail=1
fi
# (the error in the log file with the screen off: every rank raises it; it
# was error->one() on the rank that ran the cluster, in no log but rank 0's)
for np in 2 4; do
  rm -f log.long.$np
  mpirun -np $np --oversubscribe "$LMP" -in in.local_long -var np $np -var nsteps 100 -var yb p \
    -var walls "" -log log.long.$np -screen none -echo none > out.long.$np 2>&1
  if [ $? -ne 0 ] && grep -q "^ERROR: .*reaches beyond what the ghost cutoff.*comm_modify" log.long.$np; then
    echo "  $np ranks: error naming comm_modify cutoff, in the log: ok"
  else
    echo "  FAIL: $np ranks gave no error naming the ghost cutoff in the log"; tail -3 log.long.$np; tail -5 out.long.$np; fail=1
  fi
done
# the cutoff each error names for its cluster (it depends on the ranks'
# sub-domains) is enough: with it set from the start, 2 and 4 ranks end as
# 1 rank does
if ref=$(run long_ref 1 in.local_long -var np 1 -var nsteps 100 -var yb p -var walls ""); then
  for np in 2 4; do
    need=$(grep -o "this cluster needs comm_modify cutoff [0-9.]*" log.long.$np | awk '{print $NF}')
    if [ -z "$need" ]; then
      echo "  FAIL: the error on $np ranks names no comm_modify cutoff for the cluster"; fail=1
      continue
    fi
    sed "s/^neigh_modify every 1 delay 0 check yes/&\ncomm_modify cutoff $need/" in.local_long > in.local_long_cut
    got=$(run long_cut "$np" in.local_long_cut -var np "$np" -var nsteps 100 -var yb p -var walls "") || { fail=1; continue; }
    compare long_cut "$ref" "$got" "$np" && echo "  $np ranks with the named comm_modify cutoff $need: ok" || fail=1
  done
else
  fail=1
fi
# a missing bonded partner (member_copies(): a member's bonded atoms must
# have their bonded image on the rank that runs the cluster). Two chains of
# 4 beads 2.5 apart whose ends meet head-on across the face x = 15 of a
# 2-rank run: the other end's angle and dihedral partners lie up to 8.1
# beyond the running rank's sub-domain. The error names the cutoff that
# holds them all (their owners measure it, overflow_error()); with it, 2
# ranks end as 1 rank does. Until 2026-12-01 it named none
cat > in.local_partner <<'EOF2'
units       lj
atom_style  molecular
atom_modify map array
boundary    p p p
processors  * 1 1
region      box block 0 30 0 10 0 10
create_box  1 box bond/types 1 angle/types 1 dihedral/types 1 extra/bond/per/atom 2 extra/angle/per/atom 3 extra/dihedral/per/atom 4 extra/special/per/atom 8
create_atoms 1 single 14.4 5.0 5.0
create_atoms 1 single 11.9 5.4 5.0
create_atoms 1 single  9.4 5.0 5.3
create_atoms 1 single  6.9 5.4 5.3
create_atoms 1 single 15.6 5.0 5.0
create_atoms 1 single 18.1 5.4 5.0
create_atoms 1 single 20.6 5.0 5.3
create_atoms 1 single 23.1 5.4 5.3
mass        1 1.0
pair_style  lj/cut 0.9
pair_coeff  1 1 1.0 0.8
pair_modify shift yes
bond_style  harmonic
bond_coeff  1 10.0 2.5
angle_style cosine
angle_coeff 1 1.0
dihedral_style harmonic
dihedral_coeff 1 0.5 1 2
create_bonds single/bond 1 1 2
create_bonds single/bond 1 2 3
create_bonds single/bond 1 3 4
create_bonds single/bond 1 5 6
create_bonds single/bond 1 6 7
create_bonds single/bond 1 7 8
create_bonds single/angle 1 1 2 3
create_bonds single/angle 1 2 3 4
create_bonds single/angle 1 5 6 7
create_bonds single/angle 1 6 7 8
create_bonds single/dihedral 1 1 2 3 4
create_bonds single/dihedral 1 5 6 7 8
special_bonds lj 0.0 1.0 1.0
velocity    all set 0 0 0
group       ends id 1 5
velocity    ends set 1.0 0 0
set         atom 5 vx -1.0
neighbor    0.3 bin
neigh_modify every 1 delay 0 check yes
fix         hs all hardsphere/cva diameter 1.0
timestep    0.01
run         40
EOF2
result_line >> in.local_partner
labels_saved=("${LABELS[@]}")
LABELS=("etotal" "ke" "collisions" "pair" "wall" "coll.steps")
mpirun -np 2 --oversubscribe "$LMP" -in in.local_partner -log log.partner.2 -screen none -echo none > out.partner.2 2>&1
need=$(grep -o "comm_modify cutoff [0-9.]* would hold them" log.partner.2 | awk '{print $3}')
if grep -q "^ERROR: .*bonded to atom .* has no copy near it" log.partner.2 && [ -n "$need" ]; then
  echo "  missing bonded partners on 2 ranks: the error names comm_modify cutoff $need: ok"
  if ref=$(run partner 1 in.local_partner); then
    sed "s/^neigh_modify every 1 delay 0 check yes/&\ncomm_modify cutoff $need/" in.local_partner > in.local_partner_cut
    if got=$(run partner_cut 2 in.local_partner_cut); then
      compare partner_cut "$ref" "$got" 2 && echo "  2 ranks with the named comm_modify cutoff $need: ok" || fail=1
    else
      fail=1
    fi
    # (a hundredth less is not enough: the named value is the least one, rounded up)
    less=$(/usr/bin/python3 -c "print(round($need - 0.01, 2))")
    sed "s/^neigh_modify every 1 delay 0 check yes/&\ncomm_modify cutoff $less/" in.local_partner > in.local_partner_less
    if mpirun -np 2 --oversubscribe "$LMP" -in in.local_partner_less -log none -screen none -echo none > out.partner_less.2 2>&1; then
      echo "  FAIL: comm_modify cutoff $less (below the named $need) ran through"; fail=1
    else
      echo "  comm_modify cutoff $less stops with the same error: ok"
    fi
  else
    fail=1
  fi
else
  echo "  FAIL: missing bonded partners on 2 ranks: no error naming a cutoff"; tail -3 log.partner.2; fail=1
fi
LABELS=("${labels_saved[@]}")
# asked for: such a step is taken by the global engine and counted; the
# cradle's analytic end (the far sphere, ID 7, leaves with the striker's
# velocity 2) on 2 ranks
sed 's/diameter 1.0 ${walls}/diameter 1.0 ${walls} overflow global/; s/^print "RESULT/print "FALLBACK $(f_hs[10])"\nprint "RESULT/' in.local_long > in.local_long_fb
if got=$(run long_fb 2 in.local_long_fb -var np 2 -var nsteps 100 -var yb p -var walls ""); then
  fb=$(grep '^FALLBACK ' out.long_fb.2 | awk '{print $2}')
  read -r -a f <<< "$got"
  if [ "${fb:-0}" != 0 ] && [ "${f[2]}" = 8 ] && [ "${f[20]}" = 2 ] && [ "${f[24]}" = 0 ]; then
    echo "  2 ranks, overflow global: $fb step(s) taken globally, 8 collisions, ID 7 leaves at 2, the striker stops: ok"
  else
    echo "  FAIL: overflow global on 2 ranks: fallback '${fb}', result $got"; fail=1
  fi
else
  fail=1
fi
# overflow widen: the step is taken again with the ghost atoms one
# contact-list cutoff farther (6.0 -> 7.6 here), so 2 and 4 ranks end
# exactly as 1 rank does (the same collisions, rounds and velocities),
# with the widening counted (f_hs[14]) and named in the log
sed 's/diameter 1.0 ${walls}/diameter 1.0 ${walls} overflow widen/; s/^print "RESULT/print "WIDEN $(f_hs[14])"\nprint "RESULT/' in.local_long > in.local_long_wd
if ref=$(run long_wd 1 in.local_long_wd -var np 1 -var nsteps 100 -var yb p -var walls ""); then
  for np in 2 4; do
    got=$(run long_wd "$np" in.local_long_wd -var np "$np" -var nsteps 100 -var yb p -var walls "") || { fail=1; continue; }
    compare long_wd "$ref" "$got" "$np" || fail=1
    wd=$(grep '^WIDEN ' out.long_wd.$np | awk '{print $2}')
    if [ "${wd:-0}" = 1 ] && grep -q "overflow widen sets comm_modify cutoff 7.6 and takes the step again" out.long_wd.$np; then
      echo "  $np ranks, overflow widen: widened once to 7.6, counted and in the log: ok"
    else
      echo "  FAIL: overflow widen on $np ranks: count '${wd}'"; grep -i widen out.long_wd.$np; fail=1
    fi
  done
  [ "$(grep '^WIDEN ' out.long_wd.1 | awk '{print $2}')" = 0 ] || { echo "  FAIL: 1 rank widened"; fail=1; }
else
  fail=1
fi
# the engine raised the ghost cutoff itself (for the steps with contacts:
# ghost lazy), and said so
if grep -q "a step with one is taken with comm_modify cutoff 6 " log.long.2; then
  echo "  2 ranks: the engine's ghost cutoff is in the log: ok"
else
  echo "  FAIL: no log line about the ghost cutoff"; fail=1
fi

# a pair cutoff below the contact list's (WCA, 1.12 + skin 0.3 < 1.6): on 2
# ranks the engine raises the ghost cutoff before the contact list's check,
# which then passes (it used to stop the run asking for a smaller cutoff
# than the engine then set); the global engine, which raises nothing, is
# told to set comm_modify cutoff 1.6
sed 's/lj\/cut 2.5/lj\/cut 1.122462/; s/^pair_coeff  1 1 1.0 1.0 2.5/pair_coeff  1 1 1.0 1.0 1.122462/' \
  in.local_fluid500 > in.local_wca
grep -q "^pair_style  lj/cut 1.122462" in.local_wca || { echo "FAIL: in.local_wca is not WCA"; exit 1; }
# on 1 rank the engine raises the ghost cutoff to the contact list's 1.6
# (the periodic images; it used to stop with the contact list's error), and
# 1 and 2 ranks make the same collisions
echo "WCA (pair cutoff below the contact list's), substep local, 20 steps:"
LABELS=("etotal" "ke" "collisions" "pair" "wall" "coll.steps" "clusters" "rounds" "~positions")
check_system wca in.local_wca "2" -var nsteps 20
if grep -q "substep local sets comm_modify cutoff 1.6 (the ghost cutoff was 1.42" out.wca.1; then
  echo "  WCA on 1 rank, substep local: the engine sets the ghost cutoff 1.6, with a log line: ok"
else
  echo "  FAIL: WCA on 1 rank, substep local: no log line about the ghost cutoff"; tail -5 out.wca.1; fail=1
fi
if grep -q "a step with one is taken with comm_modify cutoff 4.8" out.wca.2; then
  echo "  WCA on 2 ranks, substep local: the engine sets the ghost cutoff 4.8 and runs: ok"
else
  echo "  FAIL: WCA on 2 ranks, substep local:"; tail -5 out.wca.2; fail=1
fi
sed 's/hardsphere\/cva diameter 1.0$/hardsphere\/cva diameter 1.0 substep global/' in.local_wca > in.local_wca_g
mpirun -np 2 --oversubscribe "$LMP" -in in.local_wca_g -log none -echo none -var nsteps 20 > out.wca_g.2 2>&1
if ! grep -q '^RESULT ' out.wca_g.2 && grep -q "ERROR.*needs ghost atoms out to 1.6.*comm_modify cutoff 1.6" out.wca_g.2; then
  echo "  WCA on 2 ranks, substep global: the error names comm_modify cutoff 1.6: ok"
else
  echo "  FAIL: WCA on 2 ranks, substep global:"; tail -5 out.wca_g.2; fail=1
fi

# ghost lazy (the default): on several ranks the ghost shell is LAMMPS' own
# until a contact is predicted. (a) Nothing collides (diameter 0.6 in the LJ
# fluid: r = 0.6 costs ~1750 epsilon): the run is fix nve's bit for bit on 2
# ranks, with fix nve's ghost atoms (LAMMPS' Nghost line: the mean per
# rank); ghost wide has more than 1.5 times as many (measured 2.7). (b) A
# dilute fluid whose collisions come every few steps, ghost lazy 5: the
# shell goes wide and narrow again many times (counted, f_hs[15]), and 1,
# 2 and 4 ranks still make the same collisions
echo "ghost lazy: a collision-free fluid (hard cores never reached) on 2 ranks, 300 steps:"
cat > in.local_quiet <<'EOF2'
units       lj
atom_style  atomic
atom_modify map array
lattice     fcc 0.6
region      box block 0 6 0 6 0 6
create_box  1 box
create_atoms 1 box
mass        1 1.0
velocity    all create 1.5 87287 mom yes rot yes dist gaussian loop geom
pair_style  lj/cut 2.5
pair_coeff  1 1 1.0 1.0 2.5
neighbor    0.3 bin
neigh_modify every 1 delay 0 check yes
if "${integ} == nve" then "fix hs all nve" else "fix hs all hardsphere/cva diameter 0.6 ${gh}"
timestep    0.005
thermo      100
run         300
if "${integ} == nve" then "print 'RESULT $(pe:%.17g) $(ke:%.17g) 0 0'" else "print 'RESULT $(pe:%.17g) $(ke:%.17g) $(f_hs[1]) $(f_hs[15])'"
EOF2
ghosts() { grep '^Nghost:' "$1" | tail -1 | awk '{print $2}'; }
if q_nve=$(run quiet_nve 2 in.local_quiet -var integ nve -var gh "") &&
   q_lazy=$(run quiet_lazy 2 in.local_quiet -var integ cva -var gh "") &&
   q_wide=$(run quiet_wide 2 in.local_quiet -var integ cva -var gh "ghost wide"); then
  read -r -a a <<< "$q_nve"; read -r -a b <<< "$q_lazy"; read -r -a c <<< "$q_wide"
  g_nve=$(ghosts out.quiet_nve.2); g_lazy=$(ghosts out.quiet_lazy.2); g_wide=$(ghosts out.quiet_wide.2)
  if [ "${a[0]}" = "${b[0]}" ] && [ "${a[1]}" = "${b[1]}" ] && [ "${b[2]}" = 0 ] && [ "${b[3]}" = 0 ] &&
     [ -n "$g_nve" ] && [ "$g_lazy" = "$g_nve" ]; then
    echo "  lazy: pe ${b[0]} ke ${b[1]} as fix nve's to the bit, 0 collisions, never widened, ghosts $g_lazy as fix nve's: ok"
  else
    echo "  FAIL: ghost lazy on a collision-free run: nve '$q_nve' ($g_nve ghosts), cva '$q_lazy' ($g_lazy ghosts)"; fail=1
  fi
  # the narrow shell is LAMMPS' own cutoff, not one below it that Comm
  # would adjust with a warning about a cutoff the input never set
  if grep -q "Communication cutoff adjusted" out.quiet_lazy.2; then
    echo "  FAIL: ghost lazy made LAMMPS warn: $(grep -m1 'Communication cutoff adjusted' out.quiet_lazy.2)"; fail=1
  else
    echo "  lazy: no 'Communication cutoff adjusted' warning: ok"
  fi
  if [ "${c[2]}" = 0 ] && [ "${c[3]}" = 0 ] && [ -n "$g_wide" ] && awk -v w="$g_wide" -v n="$g_nve" 'BEGIN {exit !(w > 1.5 * n)}'; then
    echo "  wide: 0 collisions, ghosts $g_wide against $g_nve: ok"
  else
    echo "  FAIL: ghost wide on a collision-free run: '$q_wide', $g_wide ghosts against $g_nve"; fail=1
  fi
else
  fail=1
fi
echo "ghost lazy 5: a dilute fluid (density 0.02) with collisions every few steps, 400 steps:"
fluid 5 | sed 's/^lattice     fcc 0.6$/lattice     fcc 0.02/; s/diameter 1.0$/diameter 1.0 ghost lazy 5/; s/^print "RESULT/print "WIDE $(f_hs[15])"\nprint "RESULT/' > in.local_lazy
grep -q "ghost lazy 5" in.local_lazy && grep -q "fcc 0.02" in.local_lazy || { echo "FAIL: in.local_lazy is not the dilute fluid"; exit 1; }
check_system lazy in.local_lazy "2 4" -var nsteps 400
widenings() { grep '^WIDE ' "$1" | awk '{print $2}'; }    # widenings <output>: f_hs[15]
w1=$(widenings out.lazy.1)
w2=$(widenings out.lazy.2)
if [ "$w1" = 0 ] && [ "${w2:-0}" -ge 3 ]; then
  echo "  the shell went wide $w2 times on 2 ranks (0 on 1 rank): ok"
else
  echo "  FAIL: ghost lazy 5 widened '$w2' times on 2 ranks, '$w1' on 1 (expected >= 3 and 0)"; fail=1
fi
# comm_style tiled keeps the wide shell (there the shell going wide and
# narrow lost pair terms in LAMMPS' forces): the same collisions and
# energies as 1 rank, never widened
sed 's/^mass        1 1.0$/mass        1 1.0\ncomm_style  tiled\nbalance     1.0 rcb/' in.local_lazy > in.local_lazy_tiled
grep -q "^comm_style  tiled" in.local_lazy_tiled || { echo "FAIL: in.local_lazy_tiled is not tiled"; exit 1; }
# stays_wide <name> <input> <ranks> <what>: the same collisions and energies
# as 1 rank, and on 2 ranks the shell never widened (it stays wide)
stays_wide() {
  check_system "$1" "$2" "$3" -var nsteps 400
  local w
  w=$(widenings "out.$1.2")
  [ "$w" = 0 ] && echo "  $4: the shell stays wide (never widened): ok" || { echo "  FAIL: $4 widened '$w' times"; fail=1; }
}
echo "the same with comm_style tiled (balance rcb):"
stays_wide lazy_tiled in.local_lazy_tiled "2 4" tiled
# two hardsphere fixes on two groups share the one ghost cutoff: both keep
# the wide shell (one's narrowing would leave the other's clusters short)
sed 's/^fix         hs all hardsphere\/cva diameter 1.0 ghost lazy 5$/region      low block INF INF INF INF INF 2.5\ngroup       g1 region low\ngroup       g2 subtract all g1\nfix         h2 g2 hardsphere\/cva diameter 1.0 ghost lazy 5\nfix         hs g1 hardsphere\/cva diameter 1.0 ghost lazy 5/' in.local_lazy > in.local_lazy_two
grep -q "^fix         h2 g2" in.local_lazy_two || { echo "FAIL: in.local_lazy_two has one fix"; exit 1; }
echo "the same with two hardsphere fixes on two groups:"
stays_wide lazy_two in.local_lazy_two "2" "two fixes"
# a run after reset_timestep to an earlier step: the last step with contacts
# (990 of the first run) is not a future step that keeps the shell wide.
# Two head-on pairs (no forces), one meeting at step ~990 of the first run,
# one at ~210 of the second: ghost lazy 20 narrows in between and widens
# again for the second contact (before the fix: still wide, 1 widening)
echo "ghost lazy after reset_timestep 0 (two pairs meeting 230 steps apart), 2 ranks:"
cat > in.local_reset <<'EOF2'
units       lj
atom_style  atomic
atom_modify map array
boundary    f f f
region      box block -20 20 -20 20 -20 20
create_box  1 box
create_atoms 1 single -0.995 0 0
create_atoms 1 single  0.995 0 0
create_atoms 1 single -1.1 10 0
create_atoms 1 single  1.1 10 0
mass        1 1.0
group       left id 1 3
group       right id 2 4
velocity    left set 0.05 0 0
velocity    right set -0.05 0 0
pair_style  zero 2.0
pair_coeff  * *
neighbor    0.3 bin
neigh_modify every 1 delay 0 check no
fix         hs all hardsphere/cva diameter 1.0 ghost lazy 20
timestep    0.01
run         1000
print       "FIRST $(f_hs[1]) $(f_hs[15])"
reset_timestep 0
run         400
print       "RESULT $(f_hs[1]) $(f_hs[15])"
EOF2
if r=$(run reset 2 in.local_reset); then
  f=$(grep '^FIRST ' out.reset.2 | awk '{print $2, $3}')
  if [ "$f" = "1 1" ] && [ "$r" = "2 2" ]; then
    echo "  collisions/widenings after the first run '$f', after the second '$r': ok"
  else
    echo "  FAIL: collisions/widenings '$f' then '$r' (expected '1 1' then '2 2')"; fail=1
  fi
else
  fail=1
fi

# and overflow widen, which rebuilds the ghosts the same way, is an error there
sed 's/ghost lazy 5/overflow widen/' in.local_lazy_tiled > in.local_widen_tiled
mpirun -np 2 --oversubscribe "$LMP" -in in.local_widen_tiled -var nsteps 10 -log none -echo none > out.widen_tiled.2 2>&1
if ! grep -q '^RESULT ' out.widen_tiled.2 && grep -q "overflow widen needs comm_style brick" out.widen_tiled.2; then
  echo "  tiled, overflow widen on 2 ranks: an error naming comm_style brick: ok"
else
  echo "  FAIL: overflow widen with comm_style tiled:"; tail -3 out.widen_tiled.2; fail=1
fi

# an error found by one rank inside a cluster's flow (the resting contact of
# examples/stress/in.resting, a sphere pressed onto a wall by a spring) ends
# every rank (error->one): with error->all the rank that ran the cluster
# waited in MPI_Barrier and the other in the step's packet gather, forever
for m in cva pcva vci; do
  timeout 120 mpirun -np 2 --oversubscribe "$LMP" -in "$SRC/examples/stress/in.resting" \
    -var method "$m" -var T 1 -log none -echo none > "out.resting.$m" 2>&1
  rc=$?
  if [ $rc -ne 0 ] && [ $rc -ne 124 ] && grep -q "(a resting contact)" "out.resting.$m"; then
    echo "  resting contact, $m on 2 ranks: the error, every rank ended: ok"
  else
    echo "  FAIL: resting contact, $m on 2 ranks: exit $rc (124: hung until the timeout)"
    tail -3 "out.resting.$m"
    fail=1
  fi
done

# mcva's local form (its default; here named, substep local; issue 21): each cluster's Gauss flow
# runs on the rank that runs the cluster, on its copies (periodic images
# of the members by their nearest copies), and the projection is pcva's:
# the same steps on 1, 2 and 4 ranks, the Gauss sub-steps counted alike
LABELS=("etotal" "ke" "collisions" "pair" "wall" "coll.steps" "sub-steps" "clusters" "rounds" "~positions")
for s in fluid500:500 hot:hot; do
  sed 's/hardsphere\/cva diameter 1.0/hardsphere\/mcva diameter 1.0 substep local/; s/f_hs\[6\]) $(f_hs\[9\])/f_hs[7]) $(f_hs[14]) $(f_hs[17])/' \
    "in.local_${s%%:*}" > "in.local_mcva${s##*:}"
  grep -q "hardsphere/mcva diameter 1.0 substep local" "in.local_mcva${s##*:}" \
    || { echo "FAIL: in.local_mcva${s##*:} has no mcva fix"; fail=1; }
done
echo "mcva local: fluid, 500 atoms, 100 steps:"
check_system mcva500 in.local_mcva500 "2 4" -var nsteps 100
echo "mcva local: 500 atoms at T 3 with skin 0.2 (atoms change rank within steps), 100 steps:"
check_system mcvahot in.local_mcvahot "2 4" -var nsteps 100

mpi_finish
