#!/usr/bin/python3
"""Parse bench/work-precision-large/stability.sh: E(t) - E(0) per atom of each
long NVE run, plotted, with max |E - E(0)|, the value at the end, the slope of
a line through 20 block means (± its standard error) and the RMS of E - E(0)
over the first and the last fifth of the run (a random walk grows as sqrt(t),
a drift as t, a bounded error not at all).

    /usr/bin/python3 stability.py <scratch/stab> <stability.md> <stability.png>
"""
import glob
import math
import os
import re
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

D, OUT_MD, OUT_PNG = sys.argv[1:4]
COLOR = {"psa": "tab:orange", "cva": "tab:blue", "pcva": "tab:green", "vci": "tab:brown"}
NB = 20
res = []
for log in sorted(glob.glob(os.path.join(D, "log.*"))):
    name = os.path.basename(log)[4:]
    txt = open(log, errors="replace").read()
    tag, m = name.split(".")[:2]
    steps = name.split(".")[-1]
    dt = float(".".join(name.split(".")[2:-1]))
    r = dict(name=name, atoms=tag, method=m, dt=dt, steps_req=int(steps))
    lp = re.findall(r"^Loop time of (\S+) on \d+ procs for (\d+) steps", txt, re.M)
    cpu = re.findall(r"^(\S+)% CPU use", txt, re.M)
    b = re.search(r"^BENCH (.*)$", txt, re.M)
    if lp:
        r["ctime"] = float(lp[-1][0]) * float(cpu[-1]) / 100
        r["cpu"] = float(cpu[-1])
    if b:
        d = dict(zip(b.group(1).split()[0::2], b.group(1).split()[1::2]))
        r["coll"] = float(d["collisions"])
    else:
        e = re.findall(r"^ERROR.*$", txt, re.M)
        r["error"] = e[-1] if e else "no BENCH line (killed or still running)"
    ef = os.path.join(D, "e." + name)
    if os.path.exists(ef):
        a = np.array([[float(x) for x in l.split()] for l in open(ef) if l.strip() and l[0] != "#"])
        if len(a) > 2:
            t = a[:, 0] * dt
            e = a[:, 1] - a[0, 1]
            r.update(t=t, e=e, maxabs=float(np.abs(e).max()), end=float(e[-1]), tend=float(t[-1]))
            n = len(e) // NB
            if n >= 2:
                tb = t[:n * NB].reshape(NB, n).mean(1)
                eb = e[:n * NB].reshape(NB, n).mean(1)
                A = np.vstack([tb, np.ones_like(tb)]).T
                c, *_ = np.linalg.lstsq(A, eb, rcond=None)
                rs = eb - A @ c
                r["slope"] = float(c[0])
                r["slope_se"] = float(math.sqrt(rs @ rs / (NB - 2) / np.sum((tb - tb.mean()) ** 2)))
                k = len(e) // 5
                r["rms_first"] = float(np.sqrt(np.mean(e[1:k] ** 2)))
                r["rms_last"] = float(np.sqrt(np.mean(e[-k:] ** 2)))
    res.append(r)

md = ["## Long-run stability: NVE on the hard-core fluid with the Gaussian attraction\n",
      "Command: `bash bench/work-precision-large/stability.sh` (or `STABILITY=1` with run.sh). "
      "Packing fraction 0.3, kT = 1 at the start, E sampled every 1000 steps; energies per atom in "
      "units of kT. Slope: a line through 20 block means of E(t) - E(0), ± its standard error "
      "(blocks are correlated over a random walk, so read it with the RMS columns). RMS: "
      "root-mean-square of E - E(0) over the first and the last fifth of the run. Cost: CPU s = Loop "
      "time x CPU use.\n"]
if os.path.exists(os.path.join(D, "machine.txt")):
    md.append("Load (date, 1/5/15-min load average): " +
              "; ".join(l.strip() for l in open(os.path.join(D, "machine.txt"))) + "\n")
md.append("| atoms | method | dt | steps done / asked | T | collisions | CPU s | max abs(E-E0) | E-E0 at end | "
          "slope per time unit | RMS first fifth | RMS last fifth |")
md.append("|---|---|---|---|---|---|---|---|---|---|---|---|")
for r in res:
    if "e" not in r:
        md.append(f"| {r['atoms']} | {r['method']} | {r['dt']} | 0 / {r['steps_req']} | | | | "
                  f"{r.get('error', '')[:80]} | | | | |")
        continue
    done = round(r["tend"] / r["dt"])
    sl = f"{r['slope']:+.2e} ± {r['slope_se']:.1e}" if "slope" in r else "-"
    md.append(f"| {r['atoms']} | {r['method']} | {r['dt']} | {done} / {r['steps_req']} | {r['tend']:g} | "
              f"{r.get('coll', float('nan')):.4g} | {r.get('ctime', float('nan')):.4g} | {r['maxabs']:.2e} | "
              f"{r['end']:+.2e} | {sl} | {r.get('rms_first', float('nan')):.2e} | "
              f"{r.get('rms_last', float('nan')):.2e} |" + ("" if "coll" in r else " (unfinished)"))
md.append("")
DISC = os.path.join(os.path.dirname(os.path.abspath(OUT_MD)), "stability-discussion.md")
if os.path.exists(DISC):
    md.append(open(DISC).read().rstrip() + "\n")
md.append("Figure: `" + os.path.basename(OUT_PNG) + "`.\n")
open(OUT_MD, "w").write("\n".join(md) + "\n")

groups = sorted({r["atoms"] for r in res if "e" in r})
if groups:
    fig, axs = plt.subplots(len(groups), 2, figsize=(12, 4 * len(groups)), squeeze=False)
    for row, g in zip(axs, groups):
        for r in res:
            if r["atoms"] != g or "e" not in r:
                continue
            for ax in row:
                ax.plot(r["t"], r["e"], lw=0.8, color=COLOR.get(r["method"]),
                        label=f"{r['method']} dt {r['dt']}, {r['steps_req']:.0e} steps")
        row[0].set_title(f"{g} atoms: E(t) - E(0) per atom [kT]")
        row[1].set_yscale("symlog", linthresh=1e-6)
        row[1].set_title("same, symlog scale")
        for ax in row:
            ax.set_xlabel("time (LJ units)")
            ax.grid(alpha=0.3)
            ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(OUT_PNG, dpi=110)
print(f"wrote {OUT_MD}, {OUT_PNG}")
