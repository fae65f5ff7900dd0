#!/usr/bin/python3
"""Bead-spring melt for the overhead benchmark: straight chains of NB beads
laid along x on a simple cubic lattice at number density RHO, written as a
LAMMPS data file (atom_style bond). Chains relax during the warm-up.

usage: make_data.py OUT [NX NY NZ] [RHO] [NB]
  NX (a multiple of NB) x NY x NZ lattice sites = atoms; default 40 40 20 = 32000
"""
import sys

out = sys.argv[1]
nx, ny, nz = (int(a) for a in sys.argv[2:5]) if len(sys.argv) >= 5 else (40, 40, 20)
rho = float(sys.argv[5]) if len(sys.argv) >= 6 else 0.85
nb = int(sys.argv[6]) if len(sys.argv) >= 7 else 10
if nx % nb:
    sys.exit(f"NX={nx} must be a multiple of the chain length {nb}")

a = (1.0 / rho) ** (1.0 / 3.0)
natoms = nx * ny * nz
nchains = natoms // nb
nbonds = nchains * (nb - 1)

with open(out, "w") as f:
    f.write(f"bead-spring melt: {nchains} chains x {nb} beads, rho {rho}\n\n")
    f.write(f"{natoms} atoms\n{nbonds} bonds\n1 atom types\n1 bond types\n\n")
    f.write(f"0 {nx * a:.10f} xlo xhi\n0 {ny * a:.10f} ylo yhi\n0 {nz * a:.10f} zlo zhi\n\n")
    f.write("Masses\n\n1 1.0\n\nAtoms # bond\n\n")
    tag = 0
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                tag += 1
                mol = (tag - 1) // nb + 1
                f.write(f"{tag} {mol} 1 {(i + 0.5) * a:.10f} {(j + 0.5) * a:.10f} {(k + 0.5) * a:.10f}\n")
    f.write("\nBonds\n\n")
    b = 0
    for c in range(nchains):
        for m in range(nb - 1):
            b += 1
            t = c * nb + m + 1
            f.write(f"{b} 1 {t} {t + 1}\n")
print(f"wrote {out}: {natoms} atoms, {nbonds} bonds, box {nx * a:.4f} x {ny * a:.4f} x {nz * a:.4f}")
