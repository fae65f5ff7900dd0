#!/usr/bin/python3
"""Bead-spring chains with angles and dihedrals (bench/scaling/angles.sh,
unittest/mpi/test_mpi_local.sh): N x N chains of 10 beads along x, B apart,
on a C-spaced square lattice in y, z (default B 1.1, C 1.25: number density
0.58), with a small helical offset (no straight angle or dihedral to start
from). atom_style molecular; one type each.

usage: make_angle_melt.py OUT N [B C]
"""
import math
import sys

out, n = sys.argv[1], int(sys.argv[2])
b, c = (float(a) for a in sys.argv[3:5]) if len(sys.argv) >= 5 else (1.1, 1.25)
nb = 10
atoms, bonds, angles, dihedrals = [], [], [], []
tag = 0
for k in range(n):
    for j in range(n):
        for i in range(nb):
            tag += 1
            y = (j + 0.5) * c + 0.1 * math.cos(0.5 * math.pi * i)
            z = (k + 0.5) * c + 0.1 * math.sin(0.5 * math.pi * i)
            atoms.append(f"{tag} {(tag - 1) // nb + 1} 1 {(i + 0.5) * b:.10f} {y:.10f} {z:.10f}")
            if i >= 1:
                bonds.append((tag - 1, tag))
            if i >= 2:
                angles.append((tag - 2, tag - 1, tag))
            if i >= 3:
                dihedrals.append((tag - 3, tag - 2, tag - 1, tag))
with open(out, "w") as f:
    f.write(f"bead-spring chains with angles and dihedrals\n\n{len(atoms)} atoms\n"
            f"{len(bonds)} bonds\n{len(angles)} angles\n{len(dihedrals)} dihedrals\n"
            "1 atom types\n1 bond types\n1 angle types\n1 dihedral types\n\n")
    f.write(f"0 {nb * b:.10f} xlo xhi\n0 {n * c:.10f} ylo yhi\n0 {n * c:.10f} zlo zhi\n")
    f.write("\nMasses\n\n1 1.0\n\nAtoms # molecular\n\n" + "\n".join(atoms) + "\n")
    for name, terms in (("Bonds", bonds), ("Angles", angles), ("Dihedrals", dihedrals)):
        f.write(f"\n{name}\n\n")
        for m, t in enumerate(terms):
            f.write(f"{m + 1} 1 " + " ".join(map(str, t)) + "\n")
