#!/usr/bin/python3
"""Summarise bench/psa runs: parse.py OUT.md LOGDIR (logs log.<case>.<integrator>.<k>)"""
import datetime, glob, os, re, statistics, subprocess, sys

def parse(path):
    txt = open(path).read()
    t, n, nat = re.findall(r"Loop time of (\S+) on \d+ procs for (\d+) steps with (\d+) atoms", txt)[-1]
    procs = int(re.findall(r"Loop time of \S+ on (\d+) procs", txt)[-1])
    cpu = re.findall(r"([\d.]+)% CPU use", txt)[-1]
    m = re.search(r"^BENCH (.*)$", txt, re.M)
    f = m.group(1).split()
    extra = dict(zip(f[0::2], f[1::2]))
    builds = int(re.findall(r"Neighbor list builds = (\d+)", txt)[-1])
    return dict(t=float(t), n=int(n), natoms=int(nat), procs=procs, cpu=float(cpu), builds=builds,
                coll=float(extra.get("collisions", 0)), kerel=extra.get("ke_rel_change", "-"))

out, d = sys.argv[1], sys.argv[2]
runs = {}
for p in sorted(glob.glob(f"{d}/log.*")):
    _, case, integ, k = os.path.basename(p).split(".")
    runs.setdefault((case, integ), []).append(parse(p))

model = "?"
for line in subprocess.run(["lscpu"], capture_output=True, text=True).stdout.splitlines():
    if line.startswith("Model name"):
        model = line.split(":", 1)[1].strip()
date = datetime.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z")
L = ["## Collisions per second of fix hardsphere/psa (pure hard spheres)", "",
     f"Machine: {model}, nproc {os.cpu_count()}, {date}. Command: `bash bench/psa/run.sh` "
     f"(input `bench/psa/in.hs-fluid`: packing fraction 0.3, fcc start, temperature 1, 1 time unit of warm-up, "
     "no smooth forces). Medians over the repetitions; nve (ideal gas, no collisions) is the baseline "
     "for the cost of the steps themselves.", "",
     "| case | integrator | spheres | ranks | skin | dt | timed steps | collisions | collisions/step | "
     "collisions per s of loop time | us per collision (t - t_nve) | ms/step | nbr builds | |dKE|/KE | CPU use |",
     "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
setting = {"small": ("0.3", "0.01"), "large": ("0.3", "0.01"), "tuned": ("0.5", "0.04"),
           "tuned2": ("0.5", "0.04")}
summary = {}
for case in ["small", "large", "tuned", "tuned2"]:
    base = runs.get((case, "nve"))    # tuned2 (2 ranks) has no nve run of its own
    tnve_step = statistics.median(r["t"] / r["n"] for r in base) if base else None
    for integ in ["nve", "cva", "psa"]:
        R = runs.get((case, integ))
        if not R:
            continue
        t = statistics.median(r["t"] for r in R)
        r0 = R[0]
        coll = statistics.median(r["coll"] for r in R)
        rate = statistics.median(r["coll"] / r["t"] for r in R) if coll else 0.0
        per = ""
        if coll and tnve_step is not None:
            per = f"{statistics.median((r['t'] - tnve_step * r['n']) / r['coll'] for r in R) * 1e6:.2f}"
        if integ != "nve":
            summary[(case, integ)] = rate
        skin, dt = setting[case]
        L.append(f"| {case} | {integ} | {r0['natoms']} | {r0['procs']} | {skin} | {dt} | {r0['n']} | {coll:g} | "
                 f"{coll / r0['n']:.2f} | {rate:,.0f} | {per} | {1e3 * t / r0['n']:.4f} | "
                 f"{r0['builds']} | {r0['kerel'].lstrip('-')} | {statistics.median(r['cpu'] for r in R):.0f}% |")
L += [""]
if ("small", "psa") in summary and ("small", "cva") in summary:
    L.append(f"**500 spheres, dt 0.01: psa {summary[('small','psa')]:,.0f} collisions/s, cva "
             f"{summary[('small','cva')]:,.0f} collisions/s ({summary[('small','psa')] / summary[('small','cva')]:.1f}x).**")
if ("large", "psa") in summary and ("large", "cva") in summary:
    L.append(f"**4000 spheres, dt 0.01: psa {summary[('large','psa')]:,.0f} collisions/s, cva "
             f"{summary[('large','cva')]:,.0f} collisions/s ({summary[('large','psa')] / summary[('large','cva')]:.1f}x).**")
if ("tuned", "psa") in summary:
    L.append(f"**4000 spheres, skin 0.5, dt 0.04: psa {summary[('tuned','psa')]:,.0f} collisions/s serial"
             + (f", {summary[('tuned2','psa')]:,.0f} on 2 ranks" if ("tuned2", "psa") in summary else "") + ".**")
L += ["", "Collision counts of repeated runs are identical (same input, same seed); different cases and "
      "integrators follow different trajectories (round-off is amplified by every collision), so their "
      "counts differ slightly. CPU use well below 100% means the shared machine took cycles from that run.", ""]
open(out, "w").write("\n".join(L))
print("\n".join(L))
