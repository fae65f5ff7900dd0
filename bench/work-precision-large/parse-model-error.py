#!/usr/bin/python3
"""Parse the runs of bench/work-precision-large/run-model-error.sh (the
equilibrium model error of the bead-spring melt) into results-model-error.md.

    /usr/bin/python3 parse-model-error.py <log dir> <results-model-error.md> <T_SEG> <T_EQ>

A run is <system>.<model>.<start>.<dt>, in segments 1, 2, ... of T_SEG time
units (log.<run>.<k>, series s.<run>.<k>: one line per time unit with the
means over it of Rg^2, <R_ee^2>, the bond length and the temperature). The
first T_EQ time units of a run are dropped (T_EQ_CHECK for the dt check,
which continues an equilibrated run; T_EQ_BIG for the N = 32000 check). Uncertainties: standard errors of the
mean of blocks of B_LEN time units (block means of the 1-time-unit means),
B_LEN being several integrated autocorrelation times (the block-size table
shows the plateau). Starts K and R of a model are combined by their
inverse-variance mean; their difference is the equilibration check.
Cost: CPU seconds = LAMMPS' Loop time x its "CPU use" / 100, summed over the
segments.
"""
import glob
import json
import math
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import wplcommon as W

LOGS, OUT_MD = sys.argv[1], sys.argv[2]
T_SEG, T_EQ = int(sys.argv[3]), int(sys.argv[4])
T_EQ_CHECK = 5                       # the dt check starts from an equilibrated state
T_EQ_BIG = 150                       # the size check (N = 32000, Kremer-Grest from state K)
B_LEN = 100                          # block length (time units) of the error bars
BLOCKS = [1, 2, 5, 10, 25, 50, 100]  # block lengths of the plateau table
OBS = ["rg2", "ree2", "bond", "temp"]
MODEL = {"psa": "hard cores (psa)", "kg": "WCA (Kremer-Grest, nve)", "mie": "Mie(50,49) (nve)"}
START = {"K": "K (Kremer-Grest state)", "R": "R (straight chains)",
         "Kc": "end of psa's K run"}


def blocks(x, b):
    """The means of the blocks of b samples of x, the last block ending at the run's end."""
    n = len(x) // b
    return x[len(x) - n * b:].reshape(n, b).mean(1)


def block_se(x, b):
    """Standard error of the mean of x from blocks of b samples (NaN if < 4 blocks)."""
    m = blocks(x, b)
    return float(m.std(ddof=1) / math.sqrt(len(m))) if len(m) >= 4 else float("nan")


def tau_acf(x):
    """Integrated autocorrelation time (in samples) of x, Sokal's window: the
    smallest W with W >= 5 tau(W), tau(W) = 1/2 + sum_{t=1}^{W} rho(t)."""
    y = x - x.mean()
    n = len(y)
    v = y @ y / n
    tau = 0.5
    for t in range(1, n // 4):
        tau += (y[:n - t] @ y[t:]) / (n - t) / v
        if t >= 5 * tau:
            return tau
    return float("nan")


def read_run(run, files):
    segs = sorted(files, key=lambda p: int(p.rsplit(".", 1)[1]))
    sysname, model, start, dt = run.split(".", 3)
    r = dict(run=run, system=sysname, model=model, start=start, dt=dt, nseg=0, ctime=0.0, steps=0)
    parts = []
    for p in segs:
        txt = open(p, errors="replace").read()
        if not re.search(r"^SEGMENT", txt, re.M):
            break                                    # a segment still running or failed: stop there
        loop = re.findall(r"^Loop time of (\S+) on \d+ procs for (\d+) steps with (\d+) atoms", txt, re.M)
        cpu = re.findall(r"^(\S+)% CPU use", txt, re.M)
        r["ctime"] += float(loop[-1][0]) * (float(cpu[-1]) if cpu else 100.0) / 100.0
        r["atoms"] = int(loop[-1][2])
        c = re.search(r"^SEGMENT .* collisions (\S+)", txt, re.M)
        r["coll"] = r.get("coll", 0.0) + float(c.group(1))
        S = W.rows(os.path.join(LOGS, "s." + os.path.basename(p)[4:]))
        if len(S) != T_SEG:
            sys.exit(f"{p}: {len(S)} rows in its series, expected T_SEG = {T_SEG}")
        parts.append(S[:, 1:5])
        r["nseg"] += 1
    if not parts:
        return None
    X = np.vstack(parts)
    r["T"] = len(X)
    r["series"] = {k: X[:, i] for i, k in enumerate(OBS)}
    r["teq"] = T_EQ_CHECK if start == "Kc" else T_EQ if sysname == "me4k" else T_EQ_BIG
    r["tprod"] = r["T"] - r["teq"]
    if r["tprod"] < 4:
        return r
    # blocks of B_LEN, or of the longest length in BLOCKS that gives 4 blocks (short runs)
    r["blen"] = B_LEN if r["tprod"] >= 4 * B_LEN else max(b for b in BLOCKS if 4 * b <= r["tprod"])
    for k in OBS:
        x = r["series"][k][r["teq"]:]
        r[k + "_x"] = x
        r[k] = float(x.mean())
        r[k + "_se"] = block_se(x, r["blen"])
        r[k + "_se_blocks"] = {b: block_se(x, b) for b in BLOCKS}
        r[k + "_se1"] = r[k + "_se_blocks"][1]
        # integrated autocorrelation time from the block error: tau = (se_B / se_1)^2 / 2 time units,
        # and from the autocorrelation function of the 1-time-unit means
        r[k + "_tau"] = 0.5 * (r[k + "_se"] / r[k + "_se1"]) ** 2 if r["blen"] == B_LEN else float("nan")
        r[k + "_tau_acf"] = tau_acf(x)
        h = len(x) // 2                              # drift: second half minus first half
        a, b = x[:h], x[h:2 * h]
        bh = max(1, min(r["blen"], h // 4))
        r[k + "_drift"] = float(b.mean() - a.mean())
        r[k + "_drift_se"] = math.hypot(block_se(a, bh), block_se(b, bh))
    return r


files = {}
for p in glob.glob(os.path.join(LOGS, "log.*")):
    files.setdefault(os.path.basename(p)[4:].rsplit(".", 1)[0], []).append(p)
runs = [x for x in (read_run(run, fs) for run, fs in sorted(files.items())) if x]
runs = [r for r in runs if r["tprod"] >= 4]
mach = W.read_machine(LOGS)

# Short runs (the dt and size checks: fewer than 4 blocks of B_LEN) have too few
# long blocks for their own error: theirs is the larger of the block error and
# se_1 sqrt(2 tau_int), tau_int that of the same model and observable in the
# N = 4000 runs (the chains' dynamics is intensive too).
tau_pool = {}
for r in runs:
    if r["blen"] == B_LEN:
        for k in OBS:
            tau_pool.setdefault((r["model"], k), []).append(r[k + "_tau"])
for r in runs:
    if r["blen"] < B_LEN:
        r["tau_used"] = {}
        for k in OBS:
            t = float(np.mean(tau_pool.get((r["model"], k), [float("nan")])))
            r["tau_used"][k] = t
            if np.isfinite(t):
                r[k + "_se"] = max(np.nan_to_num(r[k + "_se"]), r[k + "_se1"] * math.sqrt(2 * t))


def get(system, model, start):
    for r in runs:
        if (r["system"], r["model"], r["start"]) == (system, model, start):
            return r
    return None


def f(x, se, d=4):
    """x ± se with d decimals, more if se would show as 0 (two significant digits of se)."""
    if not np.isfinite(x):
        return "-"
    if not np.isfinite(se):
        return f"{x:.{d}f}"
    if 0 < se < 0.5 * 10 ** -d:
        d = int(math.ceil(-math.log10(se))) + 1
    return f"{x:.{d}f} ± {se:.{d}f}"


def pct(x, se, d=2):
    if not np.isfinite(x):
        return "-"
    return f"{100 * x:+.{d}f} ± {100 * se:.{d}f} %"


# ---- per model: starts K and R pooled. The blocks of B_LEN of both runs (equal
# production lengths) give the mean and its standard error; a run's own standard
# error for the K - R check uses the pooled block variance.
comb = {}
for m in ("psa", "kg", "mie"):
    rs = [r for r in (get("me4k", m, "K"), get("me4k", m, "R")) if r]
    if not rs:
        continue
    c = dict(runs=rs)
    for k in OBS:
        bl = [blocks(r[k + "_x"], B_LEN) for r in rs]
        allb = np.concatenate(bl)
        if len(rs) == 2 and min(len(b) for b in bl) >= 2:
            # pooled within-run variance of the block means (a K - R offset is not noise)
            s2 = sum(((b - b.mean()) ** 2).sum() for b in bl) / (len(allb) - 2)
            c[k] = float(allb.mean())
            c[k + "_se"] = math.sqrt(s2 / len(allb))
            c[k + "_nblk"] = len(allb)
            d = bl[0].mean() - bl[1].mean()
            c[k + "_KR"] = (float(d), math.sqrt(s2 * (1 / len(bl[0]) + 1 / len(bl[1]))))
        else:
            c[k], c[k + "_se"] = rs[0][k], rs[0][k + "_se"]
            c[k + "_nblk"] = len(bl[0])
    comb[m] = c
hs = comb.get("psa")


def rel(m, k):
    """(model - hard cores) / hard cores, its se (independent runs)."""
    if not hs or m not in comb:
        return float("nan"), float("nan")
    a, sa, b, sb = comb[m][k], comb[m][k + "_se"], hs[k], hs[k + "_se"]
    return a / b - 1, (a / b) * math.hypot(sa / a, sb / b)


md = ["# Bead-spring melt: the equilibrium model error (run-model-error.sh)\n"]
md.append(f"Machine: {mach.get('cpu', '?')}, nproc {mach.get('nproc', '?')} (shared; every run serial, "
          f"`nice -n 19`, one at a time); load average (1, 5, 15 min) {mach.get('load_start', '?')} at the "
          f"start, {mach.get('load_end', '?')} at the end; {mach.get('start', '?')} to {mach.get('end', '?')}; "
          f"commit {mach.get('commit', '?')}; binary {mach.get('binary', '?')}; {mach.get('mode', '')}. "
          f"CPU s = LAMMPS' Loop time x its \"CPU use\" / 100, summed over a run's segments of {T_SEG} "
          f"time units (equilibration included).\n")
md.append(f"Model: pair.melt (chains of 10, rho 0.85, FENE K 30 R0 1.5 in every model); N = 4000 beads "
          f"(400 chains, box 21.1 x 21.1 x 10.6) unless marked 32000; kT = 1 with `fix langevin 1.0 1.0 "
          f"1.0` beside the integrator. The first {T_EQ} time units of every run are dropped (equilibration; "
          f"{T_EQ_BIG} for the N = 32000 check, {T_EQ_CHECK} for the dt check), the rest is production. Observables: Rg^2 = mean over the chains of the squared radius of "
          f"gyration; <R_ee^2> = mean squared end-to-end distance; b = mean bond length; T = kinetic "
          f"temperature. ± = one standard error from blocks of {B_LEN} time units.\n")

md.append("What it means for the melt benchmark: discussion-melt.md, \"Rg^2 against the hard-core model "
          "(model error)\"; how it was run: README.md, \"The model error at equilibrium\".\n")
md.append("## Runs\n")
md.append("| model | N | start state | dt | equilibration + production | blocks | Rg^2 | <R_ee^2> | b | T | "
          "Rg^2 2nd - 1st half of production | collisions per bead per time unit | CPU s |")
md.append("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
for r in runs:
    coll = r["coll"] / r["atoms"] / (r["nseg"] * T_SEG) if r["model"] == "psa" else float("nan")
    tau_note = f" (tau {r['tau_used']['rg2']:.0f})" if "tau_used" in r else ""
    md.append(f"| {MODEL[r['model']]} | {r['atoms']} | {START.get(r['start'], r['start'])} | {r['dt']} | "
              f"{r['teq']} + {r['tprod']} | {r['tprod'] // r['blen']} x {r['blen']}{tau_note} | {f(r['rg2'], r['rg2_se'])} | {f(r['ree2'], r['ree2_se'], 3)} | "
              f"{f(r['bond'], r['bond_se'], 5)} | {f(r['temp'], r['temp_se'], 4)} | "
              f"{f(r['rg2_drift'], r['rg2_drift_se'])} | {'-' if not np.isfinite(coll) else f'{coll:.1f}'} | "
              f"{r['ctime']:.0f} |")
md.append("")
md.append(f"blocks: number x length (time units) of the blocks of the error bars; (tau t): a short run, whose "
          f"error is the larger of its block error and se_1 sqrt(2 tau_int), tau_int = t time units (Rg^2; "
          f"each observable its own) from the same model's N = 4000 runs. Rg^2 2nd - 1st half: the drift check "
          f"(blocks of up to {B_LEN} within each half).\n")

md.append("## Each model (starts K and R combined) against the hard cores\n")
md.append("| model | Rg^2 | <R_ee^2> | b | T | K - R: Rg^2 (in s.e.) | Rg^2 vs hard cores | "
          "<R_ee^2> vs hard cores | b vs hard cores | CPU s |")
md.append("|---|---|---|---|---|---|---|---|---|---|")
for m, c in comb.items():
    kr = c.get("rg2_KR")
    krs = f"{kr[0]:+.4f} ± {kr[1]:.4f} ({kr[0] / kr[1]:+.1f})" if kr else "-"
    md.append(f"| {MODEL[m]} | {f(c['rg2'], c['rg2_se'])} | {f(c['ree2'], c['ree2_se'], 3)} | "
              f"{f(c['bond'], c['bond_se'], 5)} | {f(c['temp'], c['temp_se'])} | {krs} | "
              f"{pct(*rel(m, 'rg2')) if m != 'psa' else '-'} | {pct(*rel(m, 'ree2')) if m != 'psa' else '-'} | "
              f"{pct(*rel(m, 'bond'), 3) if m != 'psa' else '-'} | {sum(r['ctime'] for r in c['runs']):.0f} |")
md.append("")
krz = [(m, c["rg2_KR"]) for m, c in comb.items() if "rg2_KR" in c]
if krz:
    md.append("Equilibration check: the two starts of a model agree within "
              + ", ".join(f"{abs(d / s):.1f}" for _, (d, s) in krz)
              + " standard errors in Rg^2 (" + ", ".join(m for m, _ in krz) + ").\n")

md.append("## Block-size plateau of the Rg^2 error\n")
md.append("Standard error of the production mean of Rg^2 from blocks of b time units (the error bar "
          f"uses b = {B_LEN}); tau_int = (se_{B_LEN} / se_1)^2 / 2 time units, the integrated autocorrelation "
          "time of the 1-time-unit means.\n")
md.append("| run | " + " | ".join(f"b = {b}" for b in BLOCKS) + " | tau_int Rg^2: blocks, ACF | "
          "tau_int <R_ee^2>: blocks, ACF |")
md.append("|---|" + "---|" * (len(BLOCKS) + 2))
for r in runs:
    row = " | ".join("-" if not np.isfinite(r["rg2_se_blocks"][b]) else f"{r['rg2_se_blocks'][b]:.4f}"
                     for b in BLOCKS)
    md.append(f"| {r['model']} {r['start']} dt {r['dt']} N {r['atoms']} | {row} | {r['rg2_tau']:.0f}, "
              f"{r['rg2_tau_acf']:.0f} | {r['ree2_tau']:.0f}, {r['ree2_tau_acf']:.0f} |")
md.append("")

md.append(f"## Running Rg^2: means over each segment of {T_SEG} time units (equilibration included)\n")
long = [r for r in runs if r["start"] != "Kc"]
nmax = max(r["nseg"] for r in long)
md.append("| time | " + " | ".join(f"{r['model']} {r['start']}" + (" 32k" if r["atoms"] > 4000 else "")
                                  for r in long) + " |")
md.append("|---|" + "---|" * len(long))
for k in range(nmax):
    cells = []
    for r in long:
        x = r["series"]["rg2"][k * T_SEG:(k + 1) * T_SEG]
        cells.append(f"{x.mean():.4f}" if len(x) == T_SEG else "")
    md.append(f"| {k * T_SEG}-{(k + 1) * T_SEG} | " + " | ".join(cells) + " |")
md.append("")

md.append("## Checks\n")
ck = get("me4k", "psa", "Kc")
pk = get("me4k", "psa", "K")
if ck and pk:
    md.append(f"* **psa's dt** ({ck['tprod']} time units at dt {ck['dt']} from the end of psa's K run at dt "
              f"{pk['dt']}): T {f(ck['temp'], ck['temp_se'])} against {f(pk['temp'], pk['temp_se'])}, "
              f"b {f(ck['bond'], ck['bond_se'], 5)} against {f(pk['bond'], pk['bond_se'], 5)} "
              f"(relative {pct(ck['bond'] / pk['bond'] - 1, math.hypot(ck['bond_se'], pk['bond_se']) / pk['bond'], 3)}), "
              f"Rg^2 {f(ck['rg2'], ck['rg2_se'])} (short run).")
big = get("me32k", "kg", "K")
if big and "kg" in comb:
    c = comb["kg"]
    md.append(f"* **System size** (WCA, N = {big['atoms']}, start K, {big['teq']} + {big['tprod']} time units): "
              f"Rg^2 {f(big['rg2'], big['rg2_se'])}, <R_ee^2> {f(big['ree2'], big['ree2_se'], 3)}, b "
              f"{f(big['bond'], big['bond_se'], 5)}; against N = 4000: Rg^2 "
              f"{pct(big['rg2'] / c['rg2'] - 1, math.hypot(big['rg2_se'], c['rg2_se']) / c['rg2'])}, "
              f"<R_ee^2> {pct(big['ree2'] / c['ree2'] - 1, math.hypot(big['ree2_se'], c['ree2_se']) / c['ree2'])}.")
md.append(f"\nTotal: {sum(r['ctime'] for r in runs) / 60:.1f} CPU min in the runs above (start states not "
          "included).\n")
open(OUT_MD, "w").write("\n".join(md) + "\n")
# the pooled values per model, for parse-melt.py's offsets against the hard cores
out_json = os.path.splitext(OUT_MD)[0] + ".json"
json.dump({m: {k: c[k] for k in ("rg2", "rg2_se", "bond", "bond_se", "temp", "temp_se")}
           for m, c in comb.items()}, open(out_json, "w"), indent=1)
print(f"wrote {OUT_MD} and {out_json}: {len(runs)} runs")
