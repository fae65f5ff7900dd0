"""Table of results.md from the outputs of run.sh: mean T over the run and
its standard error from 20 block means (tblocks.<method>.<thermo>.txt),
the expected value from statistical mechanics, collisions per step."""
import glob
import os
import re
import sys

import numpy as np

out = sys.argv[1]
N = 500
T0 = 1.5
def expected(th, n, damp):
    dof = 3 * n / (3 * n - 3)    # langevin (zero no) thermalizes 3N components
    return {
        "langevin": T0 * dof,
        "langevin_spring": T0 * dof,    # (the tether changes no kinetic average)
        "langevin_zero": T0,
        # drag adds up, noise is langevin's only: gamma_L = 1/damp, viscous 1.0
        "langevin_viscous": T0 * dof * (1.0 / damp) / (1.0 / damp + 1.0),
        "berendsen": T0,
        "rescale": T0,
    }[th]


rows = []
for f in sorted(glob.glob(os.path.join(out, "*.out"))):
    txt = open(f).read()
    r = re.search(r"RESULT method (\S+) thermo (\S+) T_mean (\S+) collisions_per_step (\S+) atoms (\d+)"
                  r"(?: damp (\S+))?", txt)
    if not r:
        m, th = os.path.basename(f)[:-4].split(".")
        rows.append((th, m, None))
        continue
    m, th, n = r.group(1), r.group(2), int(r.group(5))
    damp = float(r.group(6)) if r.group(6) else 0.5
    # a run of another size is kept under its own name (e.g. mcva108.langevin.out)
    tag = os.path.basename(f)[:-4].split(".")[0]
    blk = os.path.join(out, f"tblocks.{tag}.{th}.txt")
    if not os.path.exists(blk):
        blk = os.path.join(out, f"tblocks.{m}.{th}.txt")
    d = np.loadtxt(blk, comments="#")
    T = d[:, 1]
    se = T.std(ddof=1) / np.sqrt(len(T))
    sec = re.search(r"SECONDS (\d+)", txt)
    label = m if n == N else f"{m} ({n} atoms)"
    if damp != 0.5:
        label = label[:-1] + f", damp {damp:g})" if label.endswith(")") else f"{m} (damp {damp:g})"
    rows.append((th, label, (T.mean(), se, float(r.group(4)), len(T), sec.group(1) if sec else "?",
                             expected(th, n, damp))))

order = ["langevin", "langevin_zero", "langevin_viscous", "berendsen", "rescale",
         "langevin_spring"]
mord = ["nve", "psa", "cva", "pcva", "vci", "mcva", "mcva (108 atoms)",
        "mcva (108 atoms, damp 0.1)"]
print("# Thermostats beside the hard-sphere methods: measured\n")
print("`bash examples/thermostats/run.sh` (input `in.lj-thermostat`: 500 atoms, fcc 0.8,")
print("LJ 2.5 shifted, diameter 1.0, kT 1.5, dt 0.005, damp 0.5; `nve` is fix nve")
print("without hard cores). <T> is the mean of compute temp over the run after")
print("equilibration, +- the standard error of the block means (column blocks). Expected: statistical")
print("mechanics (langevin thermalizes all 3N components, compute temp counts 3N-3;")
print("zero yes removes the total momentum; viscous 1.0 beside langevin damp 0.5 gives")
print("gamma_L/(gamma_L+gamma_v) of it).\n")
print("| thermostat | method | <T> | expected | deviation | coll./step | blocks | s |")
print("|---|---|---|---|---|---|---|---|")
for th in order:
    for m in mord:
        for (t, mm, v) in rows:
            if t != th or mm != m:
                continue
            if v is None:
                print(f"| {th} | {m} | failed | | | | | |")
                continue
            Tm, se, cps, nb, sec, ex = v
            print(f"| {th} | {m} | {Tm:.4f} +- {se:.4f} | {ex:.4f} | {100*(Tm/ex-1):+.2f} % "
                  f"({(Tm-ex)/se:+.1f} se) | {cps:.1f} | {nb} | {sec} |")
