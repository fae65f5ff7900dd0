# Hard-sphere fluid (diameter 1, mass 1, kT = 1) from a data file written by
# in.prepare, with fix hardsphere/psa or hardsphere/cva (no smooth forces:
# exact event-driven dynamics), or LAMMPS' pseudo-hard-sphere model
# (pair mie/cut 50 49 of Jover et al. 2012, T* = kT/epsilon = 1.5, cut at
# its minimum (50/49) sigma and shifted, fix nve, dt 0.001).
#
#   ../../build/lmp -in in.hs -var model psa -var data start.data -var prod 20
#
# Equilibration run of length `equil`, then a production run of length
# `prod` (time units) split into `nblocks` blocks. At the end of each block
# a line "BLK step <P> <T> <sphere-sphere collisions so far>" is printed:
# <P>, <T> = pressure and temperature averaged over every step of the block
# (the impulse virial of a step holds that step's collisions only, see
# doc/fix_hardsphere.rst, Pressure). With -var write 1 the states after
# equilibration and production go to ${out}.equil and ${out}. The
# production run's "Loop time" and "% CPU use" give the CPU time.
#
# Several MPI ranks: psa is the method for pure hard spheres. cva's local
# engine takes a step's chain of contacts as one cluster; at packing 0.45
# and dt 0.02 those reach beyond the ghost atoms on 2 ranks (an error at
# step 2 that names the options): pass them with -var hsargs, e.g.
#   mpirun -np 2 ../../build/lmp -in in.hs -var model cva -var hsargs "overflow widen"
# or a smaller -var dthard.

variable model   index psa
variable hsargs  index ""
variable data    index start.data
variable out     index final.data
variable write   index 0
variable equil   index 5
variable prod    index 20
variable nblocks index 100
variable seed    index 8675309
variable skin    index 0.5
variable skinmie index 0.3
variable dthard  index 0.02
variable dtmie   index 0.001

units       lj
atom_style  atomic
atom_modify map array
boundary    p p p
read_data   ${data}
mass        1 1.0
velocity    all create 1.0 ${seed} mom yes rot no dist gaussian
if "${model} == mie" then "jump SELF mie"
neighbor    ${skin} bin
neigh_modify every 1 delay 0 check yes
# hard spheres: no pair style, the contact list (1 + 2 skin) needs the ghosts
comm_modify cutoff $(1.1+2*v_skin)
if "${model} == psa" then "fix hs all hardsphere/psa diameter 1.0 ${hsargs}" &
  elif "${model} == cva" "fix hs all hardsphere/cva diameter 1.0 ${hsargs}" &
  else "print 'model must be psa, cva or mie, got ${model}'" "quit 1"
variable    dt equal ${dthard}
variable    ncoll equal f_hs[2]
jump SELF run

label mie
# LAMMPS' defaults for lj units (skin 0.3, rebuild check every step)
neighbor    ${skinmie} bin
neigh_modify every 1 delay 0 check yes
# Jover et al. 2012: u = 50 (50/49)^49 eps [(s/r)^50 - (s/r)^49] + eps,
# r < (50/49) s, at kT/eps = 1.5 (kT = 1 here, as for the hard spheres)
pair_style  mie/cut $(50.0/49.0)
pair_coeff  1 1 $(1.0/1.5) 1.0 50.0 49.0
pair_modify shift yes
fix         nve all nve
variable    dt equal ${dtmie}
variable    ncoll equal 0
# equilibrate at kT = 1 (the hard-sphere contacts of the start are soft here)
fix         trs all temp/rescale 10 1.0 1.0 0.0 1.0

label run
timestep    ${dt}
thermo_style custom step temp press pe
thermo      $(round(v_equil/v_dt/5))
run         $(round(v_equil/v_dt))
if "${model} == mie" then "unfix trs"
if "${write} == 1" then "write_data ${out}.equil nocoeff"

variable    nb0 equal round(v_prod/v_dt/v_nblocks)
variable    nb equal v_nb0*(v_nb0>=1)+(v_nb0<1)
variable    nsteps equal v_nb*v_nblocks
reset_timestep 0
print       "BLK0 $(v_ncoll)"
fix         avg all ave/time 1 ${nb} ${nb} c_thermo_press c_thermo_temp
variable    P equal f_avg[1]
variable    T equal f_avg[2]
fix         blk all print ${nb} "BLK $(step) $(v_P:%.10g) $(v_T:%.10g) ${ncoll}"
thermo      ${nsteps}
run         ${nsteps}
if "${write} == 1" then "write_data ${out} nocoeff"
print       "RUN model ${model} atoms $(atoms) vol $(vol:%.10g) dt ${dt} steps ${nsteps} blocksteps ${nb}"
