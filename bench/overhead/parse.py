#!/usr/bin/python3
"""Summarise the overhead runs: parse.py OUT.md LABEL:NP:LOGDIR ...
Each LOGDIR holds log.<k>.nve / log.<k>.cva for pairs k = 1, 2, ...
Reads the timed (last) run of each log: Loop time, step count, the MPI task
timing breakdown (avg column), neighbor list builds, and the BENCH lines."""
import glob, os, re, statistics, subprocess, sys, datetime

def parse(path):
    txt = open(path).read()
    loops = re.findall(r"Loop time of (\S+) on (\d+) procs for (\d+) steps with (\d+) atoms", txt)
    t, np_, n, nat = loops[-1]
    last = txt[txt.rfind("Loop time of"):]
    sec = {}
    for m in re.finditer(r"^(\w+)\s*\|\s*(\S+)\s*\|\s*(\S+)\s*\|", last, re.M):
        if m.group(1) != "Section":
            sec[m.group(1)] = float(m.group(3))    # avg over ranks
    m = re.search(r"^Other\s*\|\s*\|\s*(\S+)", last, re.M)
    if m: sec["Other"] = float(m.group(1))
    builds = int(re.findall(r"Neighbor list builds = (\d+)", txt)[-1])
    dang = int(re.findall(r"Dangerous builds = (\d+)", txt)[-1])
    m = re.search(r"^BENCH collisions (\S+)", txt, re.M)
    coll = float(m.group(1)) if m else float("nan")
    cpu = float(re.findall(r"([\d.]+)% CPU use", txt)[-1])
    return dict(cpu=cpu, t=float(t), n=int(n), np=int(np_), natoms=int(nat), sec=sec,
                builds=builds, dang=dang, coll=coll, tps=float(t) / int(n))

def machine():
    model = "?"
    try:
        for line in subprocess.run(["lscpu"], capture_output=True, text=True).stdout.splitlines():
            if line.startswith("Model name"):
                model = line.split(":", 1)[1].strip()
    except OSError:
        pass
    return model, os.cpu_count(), datetime.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z")

out = sys.argv[1]
model, ncpu, date = machine()
lines = ["## Overhead of fix hardsphere/cva over fix nve (collision-free bead-spring melt)", "",
         f"Machine: {model}, nproc {ncpu}, {date}. Command: `bash bench/overhead/run.sh`", ""]
for spec in sys.argv[2:]:
    label, np_, d = spec.split(":", 2)
    k = 1
    rows, ratios = [], []
    while os.path.exists(f"{d}/log.{k}.nve") and os.path.exists(f"{d}/log.{k}.cva"):
        a, b = parse(f"{d}/log.{k}.nve"), parse(f"{d}/log.{k}.cva")
        rows.append((k, a, b))
        ratios.append(b["tps"] / a["tps"])
        k += 1
    if not rows:
        continue
    a0 = rows[0][1]
    lines.append(f"### {label}: {a0['natoms']} atoms, {a0['np']} MPI rank(s), {a0['n']} timed steps per run")
    lines.append("")
    lines.append("| pair | nve ms/step | cva ms/step | cva/nve | nve Neigh s | cva Neigh s | nve Modify s | cva Modify s | builds nve / cva | collisions cva | CPU use nve / cva |")
    lines.append("|---|---|---|---|---|---|---|---|---|---|---|")
    for k, a, b in rows:
        lines.append(f"| {k} | {1e3*a['tps']:.3f} | {1e3*b['tps']:.3f} | {b['tps']/a['tps']:.3f} | "
                     f"{a['sec'].get('Neigh', 0):.3f} | {b['sec'].get('Neigh', 0):.3f} | "
                     f"{a['sec'].get('Modify', 0):.3f} | {b['sec'].get('Modify', 0):.3f} | "
                     f"{a['builds']} / {b['builds']} | {b['coll']:g} | {a['cpu']:.0f}% / {b['cpu']:.0f}% |")
    med = statistics.median(ratios)
    mn = statistics.median(r[1]["tps"] for r in rows) * 1e3
    mc = statistics.median(r[2]["tps"] for r in rows) * 1e3
    lines.append("")
    # the fix's own time: Modify (cva less nve), per step, against nve's step
    dmod = statistics.median((b['sec'].get('Modify', 0) - a['sec'].get('Modify', 0)) /
                             a['t'] for _, a, b in rows)
    lines.append(f"Median time per step: nve {mn:.3f} ms, cva {mc:.3f} ms. "
                 f"**Median ratio cva/nve = {med:.3f}** (target <= 1.02, issue 22: "
                 f"{'met' if med <= 1.02 else 'NOT met'}); pair ratios "
                 + ", ".join(f"{r:.3f}" for r in ratios) + ". "
                 f"The fix's own time (Modify, cva less nve) is {100 * dmod:.1f} % of fix nve's step "
                 "(median over pairs; less exposed to the host's noise than the whole step).")
    colls = {r[2]["coll"] for r in rows}
    lines.append(f"Collisions counted by cva (f_1[1]): {', '.join(f'{c:g}' for c in sorted(colls))} (must be 0). "
                 f"Dangerous builds: nve {sum(r[1]['dang'] for r in rows)}, cva {sum(r[2]['dang'] for r in rows)}.")
    lines.append("Neigh and Modify are LAMMPS' timer sections (avg over ranks, whole timed run). "
                 "CPU use well below 100% means the shared machine took cycles from that run.")
    lines.append("")
text = "\n".join(lines)
open(out, "w").write(text + "\n")
print(text)
