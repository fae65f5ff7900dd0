#!/usr/bin/python3
"""Summarise bench/collision-cost runs: parse.py OUT.md SCRATCHDIR
pendulum: log.pend.<k>.{nve,cva}; hard-sphere fluid: log.fluid.<k>.{nve,cva}"""
import os, re, statistics, subprocess, sys, datetime

def parse(path):
    txt = open(path).read()
    t, n, nat = re.findall(r"Loop time of (\S+) on \d+ procs for (\d+) steps with (\d+) atoms", txt)[-1]
    cpu = re.findall(r"([\d.]+)% CPU use", txt)[-1]
    m = re.search(r"^BENCH collisions (\S+)(.*)$", txt, re.M)
    extra = dict(zip(m.group(2).split()[0::2], (float(x) for x in m.group(2).split()[1::2])))
    builds = int(re.findall(r"Neighbor list builds = (\d+)", txt)[-1])
    return dict(t=float(t), n=int(n), natoms=int(nat), cpu=float(cpu), coll=float(m.group(1)),
                builds=builds, **extra)

def pairs(d, name):
    k, out = 1, []
    while os.path.exists(f"{d}/log.{name}.{k}.nve") and os.path.exists(f"{d}/log.{name}.{k}.cva"):
        out.append((k, parse(f"{d}/log.{name}.{k}.nve"), parse(f"{d}/log.{name}.{k}.cva")))
        k += 1
    return out

model = "?"
for line in subprocess.run(["lscpu"], capture_output=True, text=True).stdout.splitlines():
    if line.startswith("Model name"):
        model = line.split(":", 1)[1].strip()
date = datetime.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z")
out, d = sys.argv[1], sys.argv[2]
L = ["## Cost per collision of fix hardsphere/cva", "",
     f"Machine: {model}, nproc {os.cpu_count()}, {date}. Command: `bash bench/collision-cost/run.sh` (serial).", ""]

P = pairs(d, "pend")
if P:
    a0, b0 = P[0][1], P[0][2]
    L += [f"### Pendulum chain (5 spheres + anchor, 2d, dt 0.01, {b0['n']} steps per run)", "",
          "cva = `fix hs chain hardsphere/cva diameter 0.9 wall xlo 0.0`; nve = `fix hs chain nve` "
          "(same springs, spheres pass through each other and the wall).", "",
          "| pair | nve us/step | cva us/step | collisions (pair+wall) | collisions/step | extra force evals | force evals/collision | (t_cva - t_nve)/collision us | nbr builds nve / cva |",
          "|---|---|---|---|---|---|---|---|---|"]
    per = []
    for k, a, b in P:
        c = b["coll"]
        pc = (b["t"] - a["t"]) / c * 1e6
        per.append(pc)
        L.append(f"| {k} | {1e6*a['t']/a['n']:.3f} | {1e6*b['t']/b['n']:.3f} | {c:g} ({b['pair']:g}+{b['wall']:g}) | "
                 f"{c/b['n']:.4f} | {b['force_evals']:g} | {b['force_evals']/c:.3f} | {pc:.2f} | {a['builds']} / {b['builds']} |")
    L += ["", f"**Median cost per collision: {statistics.median(per):.2f} us** "
          f"(pairs: {', '.join(f'{x:.2f}' for x in per)}); median time per step nve "
          f"{1e6*statistics.median(a['t']/a['n'] for _, a, _ in P):.3f} us, cva "
          f"{1e6*statistics.median(b['t']/b['n'] for _, _, b in P):.3f} us.", ""]

F = pairs(d, "fluid")
if F:
    b0 = F[0][2]
    L += [f"### Pure hard spheres, packing fraction 0.3 ({b0['natoms']} spheres, fcc start, dt 0.01, {b0['n']} timed steps)", "",
          "No smooth forces; nve = ideal gas (spheres pass through each other) as the baseline.", "",
          "| run | nve ms/step | cva ms/step | collisions | collisions/step | collisions per s of loop time | us per collision (cva - nve) | CPU use cva | nbr builds nve / cva |",
          "|---|---|---|---|---|---|---|---|---|"]
    rates, per = [], []
    for k, a, b in F:
        c = b["coll"]
        rate = c / b["t"]
        rates.append(rate)
        per.append((b["t"] - a["t"]) / c * 1e6)
        L.append(f"| {k} | {1e3*a['t']/a['n']:.4f} | {1e3*b['t']/b['n']:.3f} | {c:g} | {c/b['n']:.2f} | {rate:,.0f} | "
                 f"{per[-1]:.1f} | {b['cpu']:.1f}% | {a['builds']} / {b['builds']} |")
    L += ["", f"**Median: {statistics.median(rates):,.0f} collisions per second** "
          f"({statistics.median(per):.1f} us per collision, {statistics.median(b['coll']/b['n'] for _, _, b in F):.2f} collisions per step).", ""]
text = "\n".join(L)
open(out, "w").write(text + "\n")
print(text)
