#!/usr/bin/python3
"""The lammps Python module of the stock LAMMPS build loads the HARDSPHERE
plugin and runs the pendulum chain; its trajectory must equal our lmp
driver's (same LAMMPS) to round-off.

    test_python_plugin.py <dir with lammps/> <hardsphereplugin.so> <lmp driver> <source dir>

Exits 77 (ctest: skipped), saying why, when that LAMMPS build has no
Python module (Debian bookworm's liblammps is used without one here).
"""
import os
import subprocess
import sys
import tempfile

pydir, plugin, driver, src = sys.argv[1:5]
if not os.path.isfile(os.path.join(pydir, "lammps", "__init__.py")):
    print(f"SKIPPED: no lammps Python module of a LAMMPS build with PLUGIN at {pydir} "
          "(build-2025/lammps/python is the one of LAMMPS 4Feb2025)")
    sys.exit(77)
sys.path.insert(0, pydir)
from lammps import lammps  # noqa: E402

example = os.path.join(src, "examples", "pendulum-chain", "in.pendulum-chain")
work = tempfile.mkdtemp(prefix="hs_python_", dir=".")
failed = []


def numbers(path):
    with open(path) as f:
        return [float(x) for line in f if not line.startswith(("#", "ITEM"))
                for x in line.split()]


for method in ("cva", "mcva"):
    tag = os.path.join(work, method)
    args = ["-var", "method", method, "-var", "T", "40", "-var", "vevery", "1"]
    dump = "write_dump all custom {} id x y z vx vy vz modify sort id format float %.17g"

    lmp = lammps(cmdargs=["-log", "none", "-screen", "none", "-nocite"] + args
                 + ["-var", "vout", tag + ".py.v"])
    assert lmp.has_package("PLUGIN"), "this LAMMPS has no PLUGIN package"
    lmp.command(f"plugin load {plugin}")
    assert lmp.has_style("fix", "hardsphere/" + method), "plugin load did not add the fix style"
    lmp.file(example)
    lmp.command(dump.format(tag + ".py.dump"))
    collisions = lmp.extract_fix("hs", 0, 1, 0)
    lmp.close()

    with open(tag + ".in", "w") as f:
        f.write(f"include {example}\n" + dump.format(tag + ".lmp.dump") + "\n")
    res = subprocess.run([driver, "-in", tag + ".in", "-log", "none", "-screen", "none"] + args
                         + ["-var", "vout", tag + ".lmp.v"], stdin=subprocess.DEVNULL)
    if res.returncode != 0:
        failed.append(f"{method}: {driver} exited with {res.returncode}")
        continue
    if not collisions > 0:
        failed.append(f"{method}: no collisions in the Python run ({collisions})")
    for ext in (".dump", ".v"):
        a, b = numbers(tag + ".py" + ext), numbers(tag + ".lmp" + ext)
        if len(a) != len(b) or len(a) < 10:
            failed.append(f"{method}{ext}: {len(a)} numbers from Python, {len(b)} from lmp")
            continue
        worst = max(abs(x - y) / (1 + abs(x)) for x, y in zip(a, b))
        print(f"{method}{ext}: {len(a)} numbers, {collisions:.0f} collisions, "
              f"max relative difference Python vs lmp {worst:.2e}")
        if worst > 1e-12:
            failed.append(f"{method}{ext}: Python and lmp differ by {worst:.2e}")

if failed:
    print("FAILED:\n  " + "\n  ".join(failed))
    sys.exit(1)
print("OK: the lammps Python module with plugin load reproduces the lmp driver")
