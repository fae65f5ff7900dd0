#!/usr/bin/python3
"""Parse the logs of bench/work-precision/run.sh: one table and one figure
(two panels per system: Loop time against (a) the max energy error and (b)
the error of an observable) plus the winner at each accuracy.

    /usr/bin/python3 parse.py <scratch dir> <results.md> <plot.png>
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

SCR, OUT_MD, OUT_PNG = sys.argv[1], sys.argv[2], sys.argv[3]
LOGS = os.path.join(SCR, "logs")
HS = ["psa", "cva", "pcva", "mcva", "vci"]
ORDER = HS + ["wca", "mie"]
COLOR = {"psa": "tab:orange", "cva": "tab:blue", "pcva": "tab:green", "mcva": "tab:purple",
         "vci": "tab:brown", "wca": "tab:red", "mie": "black"}
LABEL = {m: m for m in HS}
LABEL.update({"wca": "nve + WCA", "mie": "nve + Mie(50,49)"})


def read_machine():
    info = {}
    p = os.path.join(SCR, "machine.txt")
    if os.path.exists(p):
        for line in open(p):
            k, _, v = line.strip().partition(" ")
            info[k] = v
    return info


def read_log(path):
    txt = open(path, errors="replace").read()
    name = os.path.basename(path)[4:]            # system.method.dt.tag
    sysname, method = name.split(".")[:2]
    tag = name.split(".")[-1]
    dt = name[len(sysname) + len(method) + 2:-len(tag) - 1]
    r = {"system": sysname, "method": method, "dt": float(dt), "dt_s": dt, "tag": tag,
         "ok": False}
    loops = re.findall(r"^Loop time of (\S+) on (\d+) procs for (\d+) steps", txt, re.M)
    cpu = re.findall(r"^(\S+)% CPU use", txt, re.M)
    if loops:
        r["loop"] = float(loops[-1][0])
        r["steps_done"] = int(loops[-1][2])
    if cpu:
        r["cpu"] = float(cpu[-1])
    if loops:
        # CPU seconds of the run: Loop time (wall) x LAMMPS' "CPU use" (cpu / wall);
        # less sensitive than the wall time to other jobs on the shared machine
        r["ctime"] = r["loop"] * r.get("cpu", 100.0) / 100.0
    m = re.search(r"^BENCH (.*)$", txt, re.M)
    if m:
        f = m.group(1).split()
        d = dict(zip(f[0::2], f[1::2]))
        r.update(ok=True, T=float(d["T"]), steps=int(d["steps"]), dE=float(d["dEmax"]),
                 coll=float(d["collisions"]), fe=float(d["force_evals"]))
        if sysname == "fluid":
            # mean over steps 1..N -> trapezoid mean for the kinetic + pair part
            # (the fixes' impulse virial is already a per-step integral)
            e = ends(r)
            r["obs_R"] = float(d["press"])
            r["obs"] = r["obs_R"] + (e[0] - e[-1]) / (2 * r["steps"])
            r["temp"] = float(d["temp"])
        else:
            r["ke_all"] = float(d["ke"])
            # first block: mean over steps 1..n -> trapezoid mean over [0, 10]
            n = round(10.0 / r["dt"])
            e = ends(r)
            r["obs_R"] = first_block(r)
            r["obs"] = r["obs_R"] + (e[0] - e[1]) / (2 * n)
        if not np.isfinite(r["dE"]):
            r["ok"] = False
    else:
        e = re.findall(r"^ERROR.*$", txt, re.M)
        r["error"] = e[-1] if e else "no BENCH line (killed or still running)"
    return r


def blocks(r):
    p = os.path.join(SCR, "blk.%s.%s.%s.%s" % (r["system"], r["method"], r["dt_s"], r["tag"]))
    rows = [l.split() for l in open(p) if l.strip() and not l.startswith("#")]
    return np.array([float(x[1]) for x in rows])


def ends(r):
    p = os.path.join(SCR, "blk.%s.%s.%s.%s.ends" % (r["system"], r["method"], r["dt_s"], r["tag"]))
    rows = [l.split() for l in open(p) if l.strip() and not l.startswith("#")]
    return [float(x[1]) for x in rows]


def first_block(r):
    b = blocks(r)
    return float(b[0]) if len(b) else float("nan")


runs = [read_log(p) for p in sorted(glob.glob(os.path.join(LOGS, "log.*")))]
mach = read_machine()


def find(system, method, tag, dt=None):
    for r in runs:
        if r["system"] == system and r["method"] == method and r["tag"] == tag and r["ok"] \
                and (dt is None or abs(r["dt"] - dt) < 1e-12):
            return r
    return None


def fmt(x, p=3):
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return ""
    return f"{x:.{p}e}"


md = []
md.append("## Run time against error: hard-sphere methods vs fix nve with steep repulsion\n")
md.append(f"Machine: {mach.get('cpu', '?')}, nproc {mach.get('nproc', '?')}; load average "
          f"(1, 5, 15 min) {mach.get('load_start', '?')} at the start, {mach.get('load_end', '?')} "
          f"at the end; {mach.get('start', '?')} to {mach.get('end', '?')}; commit "
          f"{mach.get('commit', '?')} plus the bench files. Command: `bash bench/work-precision/run.sh` "
          f"(serial runs, one at a time; every number below is from that one run). "
          f"Time = LAMMPS' Loop time (wall clock) of each run and its CPU time = Loop time x LAMMPS' "
          f"\"CPU use\" (below 100 % means the shared machine took cycles from that run); the "
          f"figure and the winners use the CPU time.\n")

# the reading of the numbers, written by hand from this run's tables (kept when re-parsing)
DISC = os.path.join(os.path.dirname(os.path.abspath(OUT_MD)), "discussion.md")
if os.path.exists(DISC):
    md.append(open(DISC).read().rstrip() + "\n")

summary = {}
for system in ("chain", "fluid"):
    hsref = find(system, "cva", "ref")
    psaref = find(system, "psa", "ref")
    ownref = {m: hsref for m in HS}
    ownref["wca"] = find(system, "wca", "ref")
    ownref["mie"] = find(system, "mie", "ref")
    offset = {m: 0.0 if m in HS else float("nan") for m in ORDER}
    offset_se = {m: 0.0 if m in HS else float("nan") for m in ORDER}
    longs = {}
    if system == "fluid":
        for m in ("psa", "wca", "mie"):
            lr = find("fluid", m, "long")
            if lr:
                b = blocks(lr)
                longs[m] = (lr["obs"], b.std(ddof=1) / math.sqrt(len(b)), len(b), lr)
        for m in ("wca", "mie"):
            if m in longs and "psa" in longs:
                offset[m] = longs[m][0] - longs["psa"][0]
                offset_se[m] = math.hypot(longs[m][1], longs["psa"][1])
    else:
        for m in ("wca", "mie"):
            if ownref[m] and hsref:
                offset[m] = ownref[m]["obs"] - hsref["obs"]
                offset_se[m] = 0.0     # same initial state, deterministic
    ref_hs_value = longs["psa"][0] if system == "fluid" and "psa" in longs else \
        (hsref["obs"] if hsref else float("nan"))
    for r in runs:
        if r["system"] != system or not r["ok"]:
            continue
        o = ownref.get(r["method"])
        r["err_own"] = abs(r["obs"] - o["obs"]) / abs(o["obs"]) if o else float("nan")
        d_own = r["obs"] - o["obs"] if o else float("nan")
        r["err_hs"] = abs(d_own + offset[r["method"]]) / abs(ref_hs_value)
        # 2 standard errors of the model offset (T = 20 runs; 0 where it is deterministic)
        r["err_hs_2se"] = 2 * offset_se[r["method"]] / abs(ref_hs_value)
        r["err_hs_hi"] = r["err_hs"] + r["err_hs_2se"]
        if system == "fluid":
            r["dE_rel"] = r["dE"]             # per atom, kT = 1
        else:
            r["dE_rel"] = r["dE"]             # H(0) = 1
    summary[system] = dict(ref_value=hsref["obs"] if hsref else None, hsref=hsref, psaref=psaref, ownref=ownref, offset=offset,
                           offset_se=offset_se, longs=longs, ref_hs_value=ref_hs_value)

# ---------------- tables
for system in ("chain", "fluid"):
    S = summary[system]
    if system == "chain":
        md.append("### 1. Impact pendulum chain (5 spheres, 2d, H(0) = 1, seed 1, T = 5000)\n")
        md.append("Energy error: max over the run of |H(t) - H(0)| (H sampled every step for "
                  "dt >= 0.01, every 0.01 time units below). Observable: the mean kinetic "
                  "energy over the first 10 time units, from the same initial state in every run "
                  "(the chain is chaotic: over the whole run the trajectories of different dt "
                  "decorrelate and the mean would measure sampling noise, not dt error). "
                  "Error vs own reference: against the same model at a tiny dt over the same "
                  "window (hard spheres: cva at dt 0.00005; wca 0.00002; mie 0.00001). Error vs "
                  "the hard-sphere reference: against cva at dt 0.00005; for wca and mie this "
                  "includes their model error (soft cores penetrate). The mean is a trapezoid sum "
                  "over the steps (block mean of fix ave/time corrected with the KE at t = 0 and "
                  "t = 10; the plain mean over steps 1..n has an O(dt) bias of (KE(0) - KE(10)) "
                  "dt / 20, larger than cva's own error). fix ave/time writes 6 significant digits, "
                  "so relative errors below about 1e-6 are not resolved (dotted line in the plot).\n")
    else:
        md.append("### 2. Fluid: 2916 hard spheres + Gaussian attraction (periodic, packing "
                  "fraction 0.3, kT = 1, T = 0.4 per run)\n")
        md.append("Energy error: max over the run of |E(t) - E(0)| per atom in units of kT "
                  "(E sampled every step for dt >= 0.01, every 0.01 time units below). "
                  "Observable: the mean pressure over the run (every step; for the hard-sphere "
                  "methods including the impulse virial), all runs of a model from the same "
                  "start state (each model from its own equilibrated state, in.make-fluid), so "
                  "the runs of one model at different dt stay correlated over the short window "
                  "and their difference measures dt error rather than sampling noise. Error vs "
                  "own reference: against the same model at a tiny dt over the same window "
                  "(hard spheres: cva at dt 0.0005; wca and mie at 0.0001). Error vs the "
                  "hard-sphere reference: the same, plus the model's pressure offset from the "
                  "hard-sphere model measured by T = 20 runs (below); the relative errors are "
                  "divided by the hard-sphere pressure of the T = 20 psa run. As for the chain, the "
                  "mean over steps 1..N is corrected to a trapezoid mean (for the kinetic and pair "
                  "part; the impulse virial is already a per-step integral).\n")
    md.append("| method | dt | steps | Loop time s | CPU use | collisions | extra force evals | "
              "max energy error | observable | rel. error vs own ref | rel. error vs hard-sphere ref | CPU time s |")
    md.append("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for m in ORDER:
        for r in sorted([r for r in runs if r["system"] == system and r["method"] == m],
                        key=lambda r: (r["tag"] != "run", -r["dt"])):
            tag = "" if r["tag"] == "run" else f" ({r['tag']})"
            if not r["ok"]:
                md.append(f"| {LABEL[m]}{tag} | {r['dt_s']} | {r.get('steps_done', '')} | "
                          f"{('%.3g' % r['loop']) if 'loop' in r else ''} | {r.get('cpu', '')} | | | "
                          f"FAILED: {r.get('error', '')[:90]} | | | | |")
                continue
            unstable = " (unstable)" if r["dE_rel"] > (1.0 if system == "chain" else 1.0) else ""
            md.append(f"| {LABEL[m]}{tag} | {r['dt_s']} | {r['steps']} | {r['loop']:.3g} | "
                      f"{r.get('cpu', 0):.0f}% | {r['coll']:.0f} | {r['fe']:.0f} | "
                      f"{fmt(r['dE_rel'])}{unstable} | {r['obs']:.6g} | {fmt(r['err_own'], 2)} | "
                      f"{fmt(r['err_hs'], 2)} | {r['ctime']:.3g} |")
    md.append("")
    if S["hsref"] and S["psaref"]:
        d = abs(S["hsref"]["obs"] - S["psaref"]["obs"]) / abs(S["hsref"]["obs"])
        md.append(f"Cross-check of the hard-sphere reference: psa at dt {S['psaref']['dt_s']} differs "
                  f"from the reference (cva at dt {S['hsref']['dt_s']}) by {d:.2e} (relative) in the "
                  f"observable. Compare with the psa rows: where this is as large as psa's own "
                  f"errors at larger dt, it is psa converging slowly, not an uncertain reference "
                  f"(cva and pcva converge to the reference far below it).\n")
        S["ref_floor"] = d
    if system == "chain" and S["hsref"]:
        for m in ("wca", "mie"):
            if S["ownref"][m]:
                md.append(f"Model error of {LABEL[m]} (its dt -> 0 limit against the hard-sphere "
                          f"one, 10-unit window): {S['offset'][m] / S['hsref']['obs']:+.2e} relative.\n")
        ke = [r["ke_all"] for r in runs if r["system"] == "chain" and r["ok"] and r["tag"] == "run"
              and r["method"] in HS]
        if ke:
            md.append(f"Mean kinetic energy over T = 5000 (hard-sphere runs): {np.median(ke):.3f} "
                      f"(median), so kT = 2<KE>/10 = {np.median(ke) / 5:.3f}; the chain's wca/mie "
                      f"use eps = 0.1 and 0.15 (eps/kT about {0.1 / (np.median(ke) / 5):.2f} and "
                      f"{0.15 / (np.median(ke) / 5):.2f}).\n")
    if system == "fluid" and S["longs"]:
        md.append("Pressure of each model from a T = 20 run (mean over every step; standard "
                  "error from blocks of 0.5 time units):\n")
        md.append("| model | dt | Loop time s | pressure | std. error | blocks | mean temperature |")
        md.append("|---|---|---|---|---|---|---|")
        for m, (p, se, nb, lr) in S["longs"].items():
            md.append(f"| {LABEL[m]} | {lr['dt_s']} | {lr['loop']:.3g} | {p:.4f} | {se:.4f} | {nb} | "
                      f"{lr['temp']:.4f} |")
        md.append("")
        for m in ("wca", "mie"):
            if m in S["longs"] and "psa" in S["longs"]:
                md.append(f"Model error of {LABEL[m]}: pressure {S['offset'][m]:+.4f} +- "
                          f"{S['offset_se'][m]:.4f} against hard spheres "
                          f"({S['offset'][m] / S['ref_hs_value']:+.2%}).\n")
        mr = [r for r in runs if r["system"] == "fluid" and r["method"] == "mcva"]
        for r in mr:
            if r["ok"]:
                per = r["loop"] / r["steps"]
                md.append(f"**mcva on the fluid** (`{r['tag']}` run, dt {r['dt_s']}, {r['steps']} steps): "
                          f"{per:.1f} s per step (CPU use {r.get('cpu', 0):.0f}%), {r['coll'] / r['steps']:.0f} "
                          f"collisions and {r['fe'] / r['steps']:.0f} extra force evaluations per step, "
                          f"{r['loop'] / max(r['coll'], 1):.2f} s per collision; one T = 0.4 window at this dt "
                          f"({round(0.4 / r['dt'])} steps) would take about {per * 0.4 / r['dt'] / 3600:.1f} h, "
                          f"so it is not in the figure.\n")
            else:
                md.append(f"**mcva on the fluid**: FAILED: {r.get('error', '')}\n")

# ---------------- winners
def pareto_time(system, method, key, eps):
    ts = [r["ctime"] for r in runs if r["system"] == system and r["method"] == method and r["ok"]
          and r["tag"] == "run" and r.get(key, float("nan")) <= eps]
    return min(ts) if ts else None


md.append("### Who wins at which accuracy\n")
md.append("For each target accuracy, the fastest run of each contender whose error is at most "
          "the target (no interpolation between timesteps); the winner and its factor over the "
          "runner-up (and over the faster of the two continuous models). Times are CPU seconds "
          "(Loop time x CPU use). Against the hard-sphere reference, a continuous model counts "
          "only if its error plus twice the standard error of its model offset is below the "
          "target (fluid: the offset comes from T = 20 runs with a standard error of about "
          "0.9 %).\n")
md.append("| system | error measure | target | winner (s) | runner-up (s) | factor | best continuous (s) | factor |")
md.append("|---|---|---|---|---|---|---|---|")
for system in ("chain", "fluid"):
    for key, name, targets in (("dE_rel", "max energy error", [1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7]),
                               ("err_own", "observable vs own ref", [1e-1, 1e-2, 1e-3, 1e-4]),
                               ("err_hs_hi", "observable vs hard-sphere ref (+2 s.e.)", [1e-1, 3e-2, 1e-2, 1e-3])):
        for eps in targets:
            t = {m: pareto_time(system, m, key, eps) for m in ORDER}
            t = {m: v for m, v in t.items() if v is not None}
            if not t:
                continue
            s = sorted(t.items(), key=lambda kv: kv[1])
            win = s[0]
            ru = s[1] if len(s) > 1 else None
            cont = [kv for kv in s if kv[0] in ("wca", "mie")]
            bc = cont[0] if cont else None
            md.append(f"| {system} | {name} | {eps:g} | {LABEL[win[0]]} ({win[1]:.3g}) | "
                      + (f"{LABEL[ru[0]]} ({ru[1]:.3g}) | {ru[1] / win[1]:.1f} | " if ru else "none | | ")
                      + (f"{LABEL[bc[0]]} ({bc[1]:.3g}) | {bc[1] / win[1]:.1f} |" if bc and bc != win
                         else ("(winner) | |" if bc else "none reaches it | |")))
md.append("")

# ---------------- figure
fig, axes = plt.subplots(2, 2, figsize=(12, 10))
for row, system in enumerate(("chain", "fluid")):
    for col, (key, xl) in enumerate((("dE_rel", "max |H(t)-H(0)|" if system == "chain"
                                      else "max |E(t)-E(0)| per atom / kT"),
                                     ("err_own", "relative error of " +
                                      ("<KE> (first 10 time units)" if system == "chain"
                                       else "<P> (T = 0.4)")))):
        ax = axes[row, col]
        for m in ORDER:
            rs = sorted([r for r in runs if r["system"] == system and r["method"] == m and r["ok"]
                         and r["tag"] == "run" and r.get(key, 0) > 0], key=lambda r: -r["dt"])
            if not rs:
                continue
            x = [max(r[key], 1e-17) for r in rs]
            y = [r["ctime"] for r in rs]
            ax.plot(x, y, "o-", color=COLOR[m], label=LABEL[m])
            for r in rs:
                ax.annotate(r["dt_s"], (max(r[key], 1e-17), r["ctime"]), fontsize=6,
                            xytext=(3, 3), textcoords="offset points", color=COLOR[m])
            if key == "err_own" and m in ("wca", "mie"):
                xs = [r["err_hs"] for r in rs]
                xe = [r["err_hs_2se"] for r in rs]
                ax.plot(xs, y, "s:", mfc="none", color=COLOR[m], label=LABEL[m] + " vs hard-sphere ref")
                if max(xe) > 0:
                    lo = [min(e, x * 0.999) for x, e in zip(xs, xe)]
                    ax.errorbar(xs, y, xerr=[lo, xe], fmt="none", ecolor=COLOR[m], lw=0.6, capsize=2)
        if key == "err_own" and summary[system].get("ref_value"):
            # fix ave/time writes 6 significant digits: relative resolution of the observable
            ax.axvline(1e-6 * 10 ** math.floor(math.log10(abs(summary[system]["ref_value"])) + 1)
                       / abs(summary[system]["ref_value"]) / 2, color="gray", lw=0.8, ls=":",
                       label="6-digit output (half ulp)")
        if key == "err_own" and summary[system].get("ref_floor"):
            ax.axvline(summary[system]["ref_floor"], color="gray", lw=0.8, ls="--",
                       label="psa at tiny dt vs reference")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(xl)
        ax.set_ylabel("CPU time (s) = Loop time x CPU use")
        ax.set_title(f"({'ab'[col]}) {'pendulum chain, T = 5000' if system == 'chain' else 'fluid, 2916 spheres, T = 0.4'}")
        ax.grid(True, which="both", lw=0.3)
        ax.legend(fontsize=7)
fig.suptitle("Run time against error (bench/work-precision); dt next to each point", fontsize=11)
fig.tight_layout()
fig.savefig(OUT_PNG, dpi=110)

md.append(f"Figure: `{os.path.basename(OUT_PNG)}` (rows: chain, fluid; columns: (a) max energy "
          "error, (b) observable error; for wca and mie the dotted hollow squares are the error "
          "against the hard-sphere reference, model error included).\n")
open(OUT_MD, "w").write("\n".join(md) + "\n")
print("wrote", OUT_MD, OUT_PNG)
