#!/usr/bin/python3
"""Parse the logs of bench/work-precision-large/run.sh into a table, the
cheapest contender at each accuracy, and a figure (four panels: max energy
error, energy drift rate, pressure error against the model's own dt -> 0
limit, pressure error against the hard-sphere model).

    /usr/bin/python3 parse.py <log dir> <results.md> <plot.png>

Cost: CPU seconds per unit of simulated time = Loop time x CPU use / 100 / T.
Uncertainties: over the start states A and B (mean and half their
difference, i.e. the standard error of a mean of two) where both exist;
drift: standard error of the slope of a line fitted to 10 block means of
E(t); model error: block standard errors of long runs at kT = 1.
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

LOGS, OUT_MD, OUT_PNG = sys.argv[1], sys.argv[2], sys.argv[3]
HS = ["psa", "cva", "pcva", "vci"]
ORDER = HS + ["wca", "mie"]
SOFT = ["wca", "mie"]
COLOR = {"psa": "tab:orange", "cva": "tab:blue", "pcva": "tab:green", "vci": "tab:brown",
         "wca": "tab:red", "mie": "black", "mcva": "tab:purple"}
LABEL = {m: m for m in HS + ["mcva"]}
LABEL.update({"wca": "nve + WCA", "mie": "nve + Mie(50,49)"})
NBLK_E = 10


def rows(path):
    if not os.path.exists(path):
        return np.zeros((0, 0))
    r = [l.split() for l in open(path) if l.strip() and not l.startswith("#")]
    return np.array([[float(x) for x in l] for l in r]) if r else np.zeros((0, 0))


def read_log(path):
    txt = open(path, errors="replace").read()
    name = os.path.basename(path)[4:]                # state.method.dt.tag
    f = name.split(".")
    S, m, tag = f[0], f[1], f[-1]
    dt_s = ".".join(f[2:-1])
    r = dict(state=S, method=m, tag=tag, dt=float(dt_s), dt_s=dt_s, name=name, ok=False)
    loops = re.findall(r"^Loop time of (\S+) on (\d+) procs for (\d+) steps", txt, re.M)
    cpu = re.findall(r"^(\S+)% CPU use", txt, re.M)
    if loops:
        r["loop"] = float(loops[-1][0])
        r["cpu"] = float(cpu[-1]) if cpu else 100.0
        r["ctime"] = r["loop"] * r["cpu"] / 100.0
    b = re.search(r"^BENCH (.*)$", txt, re.M)
    if not b:
        e = re.findall(r"^ERROR.*$", txt, re.M)
        r["error"] = e[-1] if e else "no BENCH line (killed or still running)"
        return r
    d = dict(zip(b.group(1).split()[0::2], b.group(1).split()[1::2]))
    r.update(ok=True, T=float(d["T"]), steps=int(d["steps"]), atoms=int(d["atoms"]),
             dE_lmp=float(d["dEmax"]), press_all=float(d["press"]), temp=float(d["temp"]),
             coll=float(d["collisions"]), fe=float(d["force_evals"]))
    r["cost"] = r["ctime"] / r["T"]                  # CPU s per unit time
    E = rows(os.path.join(LOGS, "e." + name))
    if E.size:
        t = E[:, 0] * r["dt"]
        e = E[:, 1]
        r["dE"] = float(np.max(np.abs(e - e[0])))
        r["Et"] = (t, e)
        if len(e) >= 2 * NBLK_E:
            n = len(e) // NBLK_E
            tb = t[:n * NBLK_E].reshape(NBLK_E, n).mean(1)
            eb = e[:n * NBLK_E].reshape(NBLK_E, n).mean(1)
            A = np.vstack([tb, np.ones_like(tb)]).T
            coef, res, *_ = np.linalg.lstsq(A, eb, rcond=None)
            resid = eb - A @ coef
            s2 = resid @ resid / (NBLK_E - 2)
            r["slope"] = float(coef[0])
            r["slope_se"] = float(math.sqrt(s2 / np.sum((tb - tb.mean()) ** 2)))
    else:
        r["dE"] = r["dE_lmp"]
    if not np.isfinite(r["dE"]):
        r["ok"] = False
        r["error"] = "energy not finite"
    P = rows(os.path.join(LOGS, "p." + name))
    X = rows(os.path.join(LOGS, "x." + name))
    if P.size:
        nw = round(P[0, 0] / r["dt"]) if P[0, 0] > 0 else None
        r["pblk"] = P[:, 1]
        r["tblk"] = P[:, 2]
        if X.size >= 2 and X.shape[0] >= 2 and nw:
            # window 1: mean over steps 1..nw -> trapezoid mean over [0, Tw]
            r["P1"] = float(P[0, 1] + (X[0, 1] - X[1, 1]) / (2 * nw))
        else:
            r["P1"] = float(P[0, 1])
    return r


runs = [read_log(p) for p in sorted(glob.glob(os.path.join(LOGS, "log.*")))]
mach = {}
if os.path.exists(os.path.join(LOGS, "machine.txt")):
    for line in open(os.path.join(LOGS, "machine.txt")):
        k, _, v = line.strip().partition(" ")
        mach.setdefault(k, v)
        if k in ("load_end", "end"):
            mach[k] = v


def get(S, m, tag, dt=None):
    for r in runs:
        if r["ok"] and r["state"] == S and r["method"] == m and r["tag"] == tag and \
                (dt is None or abs(r["dt"] - dt) < 1e-12):
            return r
    return None


states = sorted({r["state"] for r in runs if r["tag"] == "run"})


def mean_se(vals):
    v = [x for x in vals if x is not None and np.isfinite(x)]
    if not v:
        return float("nan"), float("nan"), 0
    if len(v) == 1:
        return v[0], float("nan"), 1
    return float(np.mean(v)), float(np.std(v, ddof=1) / math.sqrt(len(v))), len(v)


# ---- model error (long runs at kT = 1)
longs = {}
for m in ("cva", "wca", "mie", "psa"):
    lrs = [r for r in runs if r["ok"] and r["method"] == m and r["tag"] == "long" and "pblk" in r]
    if lrs:
        # the blocks of every state's long run together (independent runs)
        b = np.concatenate([r["pblk"] for r in lrs])
        longs[m] = dict(P=float(b.mean()), se=float(b.std(ddof=1) / math.sqrt(len(b))), n=len(b),
                        T=float(np.concatenate([r["tblk"] for r in lrs]).mean()), r=lrs[0],
                        states="+".join(r["state"] for r in lrs), Ttot=sum(r["T"] for r in lrs),
                        ctime=sum(r["ctime"] for r in lrs),
                        per_state={r["state"]: float(r["pblk"].mean()) for r in lrs})
hs_long = longs.get("cva")
P_HS = hs_long["P"] if hs_long else None
offset = {m: (0.0, 0.0) for m in HS}
for m in SOFT:
    if m in longs and hs_long:
        offset[m] = (longs[m]["P"] - hs_long["P"], math.hypot(longs[m]["se"], hs_long["se"]))
    else:
        offset[m] = (float("nan"), float("nan"))
if P_HS is None:      # no long run: normalise by the hard-sphere reference window
    refs = [get(S, "cva", "ref") for S in states]
    refs = [x["P1"] for x in refs if x]
    P_HS = float(np.mean(refs)) if refs else 1.0

ownref_m = {m: "cva" for m in HS}
ownref_m.update({"wca": "wca", "mie": "mie"})

# ---- per (method, dt): combine the states
points = {}
for r in runs:
    if r["tag"] != "run":
        continue
    key = (r["method"], r["dt_s"])
    points.setdefault(key, []).append(r)

table = []
for (m, dt_s), rs in points.items():
    ok = [r for r in rs if r["ok"]]
    p = dict(method=m, dt=float(dt_s), dt_s=dt_s, n=len(ok), failed=[r for r in rs if not r["ok"]])
    if not ok:
        table.append(p)
        continue
    p["cost"], p["cost_se"], _ = mean_se([r["cost"] for r in ok])
    p["cost_by_state"] = {r["state"]: r["cost"] for r in ok}
    p["cpu"] = min(r["cpu"] for r in ok)
    p["coll"] = float(np.mean([r["coll"] / r["T"] for r in ok]))      # per unit time
    p["dE"], p["dE_se"], _ = mean_se([r["dE"] for r in ok])
    sl = [(r["slope"], r["slope_se"]) for r in ok if "slope" in r]
    if sl:
        w = np.array([1 / s[1] ** 2 if s[1] > 0 else 1.0 for s in sl])
        v = np.array([s[0] for s in sl])
        p["slope"] = float((w * v).sum() / w.sum())
        p["slope_se"] = float(1 / math.sqrt(w.sum()))
    diffs = []
    for r in ok:
        ref = get(r["state"], ownref_m[m], "ref")
        if ref and "P1" in r and "P1" in ref:
            diffs.append((r["P1"] - ref["P1"]) / P_HS)
    if diffs:
        d, dse, nd = mean_se(diffs)
        p["dP_own"] = d
        p["dP_own_se2"] = dse          # from this point's states alone (1 dof with two)
        p["dP_own_n"] = nd
        p["dP_diffs"] = {r["state"]: x for r, x in zip(ok, diffs)} if len(diffs) == len(ok) else {}
    p["P1"] = float(np.mean([r["P1"] for r in ok if "P1" in r]))
    table.append(p)
table.sort(key=lambda p: (ORDER.index(p["method"]) if p["method"] in ORDER else 99, -p["dt"]))

# Noise of the pressure differences: the run and its reference start from the same
# state but their trajectories drift apart over the window, so the difference has a
# random part besides the dt error, and it grows with dt. The difference of the two
# states' values, dA - dB, is free of the dt error (the same for both): |dA - dB|/sqrt(2)
# estimates the per-state noise at that dt with one degree of freedom. Per contender,
# a power law sigma = c dt^b is fitted to ln(|dA - dB|/sqrt(2)) over its dt values
# (+0.635 = -E ln|Z| for a normal Z, so that the fit estimates sigma, not the mean
# log); the standard error of the mean over n states is sigma(dt)/sqrt(n).
sigma_fit = {}
for m in ORDER:
    pts = [(p["dt"], list(p["dP_diffs"].values())) for p in table
           if p["method"] == m and len(p.get("dP_diffs", {})) >= 2]
    pts = [(dt, abs(v[0] - v[1]) / math.sqrt(2)) for dt, v in pts]
    pts = [(dt, x) for dt, x in pts if x > 0]
    if len(pts) >= 3:
        X = np.log([q[0] for q in pts])
        Y = np.log([q[1] for q in pts]) + 0.635
        b, a = np.polyfit(X, Y, 1)
        sigma_fit[m] = (a, b, len(pts))
    elif pts:
        sigma_fit[m] = (math.log(math.sqrt(np.mean([q[1] ** 2 for q in pts]))), 0.0, len(pts))
for p in table:
    if "dP_own" not in p:
        continue
    m = p["method"]
    se = math.exp(sigma_fit[m][0] + sigma_fit[m][1] * math.log(p["dt"])) / math.sqrt(p["dP_own_n"]) \
        if m in sigma_fit else float("nan")
    p["dP_own_se"] = se
    o, ose = offset[m]
    p["dP_hs"] = p["dP_own"] + o / P_HS
    p["dP_hs_se"] = math.hypot(se if np.isfinite(se) else 0.0, ose / P_HS)


def fmt(x, se=None, d=2):
    if x is None or not np.isfinite(x):
        return "-"
    s = f"{x:.{d}e}"
    if se is not None and np.isfinite(se):
        s += f" ± {se:.1e}"
    return s


def bound(p, k):
    """|error| + 2 standard errors (the error known to be below it): the
    figure of merit the winners use. NaN standard errors count as 0."""
    x = p.get(k)
    if x is None or not np.isfinite(x):
        return float("nan")
    se = p.get(k + "_se", float("nan"))
    return abs(x) + (2 * se if np.isfinite(se) else 0.0)


KINDS = [("dE", "max |E(t) - E(0)| per atom [kT] over T_E"),
         ("slope", "energy drift |dE/dt| per atom [kT per time unit]"),
         ("dP_own", "pressure error vs own dt -> 0 limit (relative)"),
         ("dP_hs", "pressure error vs the hard-sphere model (relative)")]

md = []
md.append("## Run time against error at N = 32000: hard-core fluid with a Gaussian attraction\n")
md.append(f"Machine: {mach.get('cpu', '?')}, nproc {mach.get('nproc', '?')} (shared; every run serial, "
          f"`nice -n 19`, one at a time); load average (1, 5, 15 min) {mach.get('load_start', '?')} at "
          f"the start, {mach.get('load_end', '?')} at the end; {mach.get('start', '?')} to "
          f"{mach.get('end', '?')}; commit {mach.get('commit', '?')}; binary {mach.get('binary', '?')}; "
          f"{mach.get('mode', '')}. **Cost = CPU seconds per unit of simulated time**: LAMMPS' Loop "
          f"time x its \"CPU use\" / 100, divided by the run's length T.\n")
DISC = os.path.join(os.path.dirname(os.path.abspath(OUT_MD)),
                    "discussion" + ("-short" if "short" in os.path.basename(OUT_MD) else "") + ".md")
if os.path.exists(DISC):
    md.append(open(DISC).read().rstrip() + "\n")

md.append("### Table\n")
md.append(f"Start states: {', '.join(states)} (each value is the mean over them; ± is the standard "
          f"error of that mean, i.e. half the difference for two states; no ± with one state). "
          f"Pressure errors are relative to the hard-sphere pressure P_hs = {P_HS:.5f}. "
          f"dE/dt: slope of a line through {NBLK_E} block means of E(t), ± its standard error "
          f"(inverse-variance mean over the states). Collisions per unit time.\n")
if sigma_fit:
    md.append("Noise of the pressure differences: the run and its reference drift apart over the window, "
              "so a difference has a random part besides the dt error. The difference between the two "
              "states' values, which the dt error cancels from, measures it: per contender a power law "
              "sigma = c dt^b per state is fitted to |dA - dB|/sqrt(2) over its dt values (in logs, "
              "corrected by +0.635 for the mean log of a normal's modulus); the ± of the pressure errors "
              "is sigma(dt)/sqrt(number of states). Fitted exponents b: " +
              ", ".join(f"{LABEL[m]} {v[1]:.2f} ({v[2]} dt)" for m, v in sigma_fit.items()) +
              ". The values of each state are in the last column.\n")
md.append("| contender | dt | cost CPU s / time unit | min CPU use | collisions / time unit | "
          "max abs(E-E0) per atom | dE/dt per atom | P error vs own limit | P error vs hard spheres | "
          "P error per state |")
md.append("|---|---|---|---|---|---|---|---|---|---|")
for p in table:
    if p["n"] == 0:
        md.append(f"| {LABEL.get(p['method'], p['method'])} | {p['dt_s']} | FAILED: "
                  f"{p['failed'][0].get('error', '')[:100]} | | | | | | | |")
        continue
    fail = f" ({len(p['failed'])} failed)" if p["failed"] else ""
    md.append(f"| {LABEL.get(p['method'], p['method'])}{fail} | {p['dt_s']} | {fmt(p['cost'], p['cost_se'])} | "
              f"{p['cpu']:.0f}% | {p['coll']:.3g} | {fmt(p['dE'], p['dE_se'])} | "
              f"{fmt(p.get('slope'), p.get('slope_se'))} | {fmt(p.get('dP_own'), p.get('dP_own_se'))} | "
              f"{fmt(p.get('dP_hs'), p.get('dP_hs_se'))} | "
              f"{', '.join(f'{S} {v:+.1e}' for S, v in sorted(p.get('dP_diffs', {}).items()))} |")
md.append("")

# references
md.append("References (each model's dt -> 0 limit over the first pressure window, same start state):\n")
md.append("| state | model | dt | window T | pressure (trapezoid mean) | CPU s |")
md.append("|---|---|---|---|---|---|")
for S in states:
    for m in ("cva", "psa", "wca", "mie"):
        r = get(S, m, "ref")
        if r:
            md.append(f"| {S} | {LABEL[m]} | {r['dt_s']} | {r['T']} | {r['P1']:.6f} | {r['ctime']:.3g} |")
for S in states:
    a, b = get(S, "cva", "ref"), get(S, "psa", "ref")
    if a and b:
        md.append(f"\nCross-check in state {S}: psa at dt {b['dt_s']} differs from the cva reference by "
                  f"{(b['P1'] - a['P1']) / P_HS:+.2e} (relative).")
md.append("")
if longs:
    md.append("Model error: long runs with `fix langevin 1 1 1` beside the integrator (all models at "
              "kT = 1), from each state listed; pressure mean over blocks of 0.5 time units, standard error from "
              "the block means:\n")
    md.append("| model | dt | states | T total | pressure | std. error | blocks | mean per state | mean temperature | CPU s |")
    md.append("|---|---|---|---|---|---|---|---|---|---|")
    for m, L in longs.items():
        md.append(f"| {LABEL[m]} | {L['r']['dt_s']} | {L['states']} | {L['Ttot']:g} | {L['P']:.5f} | {L['se']:.5f} | "
                  f"{L['n']} | {', '.join(f'{k} {v:.4f}' for k, v in L['per_state'].items())} | "
                  f"{L['T']:.4f} | {L['ctime']:.3g} |")
    md.append("")
    for m in SOFT:
        o, ose = offset[m]
        if np.isfinite(o):
            md.append(f"Model error of {LABEL[m]}: pressure {o:+.5f} ± {ose:.5f} against hard spheres "
                      f"({o / P_HS:+.3%} ± {ose / P_HS:.3%}).\n")

# mcva
mc = get("A", "mcva", "short")
cs = get("A", "cva", "short2916")
cg = get("A", "cva", "short2916g")
if mc:
    per = mc["ctime"] / mc["steps"]
    txt = (f"**mcva** (global engine only): {mc['steps']} steps at dt {mc['dt_s']} on {mc['atoms']} atoms "
           f"took {per:.1f} CPU s per step ({mc['coll'] / mc['steps']:.0f} collisions and "
           f"{mc['fe'] / mc['steps']:.0f} extra force evaluations per step, CPU use {mc['cpu']:.0f}%)")
    if cs:
        pc = cs["ctime"] / cs["steps"]
        txt += (f"; cva (local) on the same data: {pc * 1000:.1f} CPU ms per step ({cs['coll'] / cs['steps']:.1f} "
                f"collisions per step), so mcva costs {per / pc:.0f}x cva there")
    if cs and cg:
        txt += (f". Energy on those 2916 atoms, dt {cs['dt_s']}, T {cs['T']}: max abs(E - E0) per atom "
                f"{cs['dE']:.2e} with cva's local engine, {cg['dE']:.2e} with its global engine "
                f"({cg['ctime'] / cg['steps'] * 1000:.0f} CPU ms per step)")
    txt += (f". Its cost per collision is O(N) and collisions per step grow as N, so at N = 32000 a step "
            f"would cost about (32000/{mc['atoms']})^2 = {(32000 / mc['atoms']) ** 2:.0f}x more, "
            f"~{per * (32000 / mc['atoms']) ** 2 / 60:.0f} CPU min per step: it is left out of the curves.\n")
    md.append(txt)
elif get("A", "mcva", "short") is None and any(r["method"] == "mcva" for r in runs):
    md.append("**mcva**: " + [r for r in runs if r["method"] == "mcva"][0].get("error", "") + "\n")

# ---- winners
TARGETS = {"dE": [1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7],
           "slope": [1e-3, 1e-4, 1e-5, 1e-6, 1e-7],
           "dP_own": [1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5, 1e-5],
           "dP_hs": [3e-2, 1e-2, 3e-3, 1e-3]}
md.append("### Cheapest contender at each accuracy\n")
md.append("For each target, the cheapest run (mean cost over the states) of each contender whose error "
          "bound |error| + 2 standard errors is at most the target (no interpolation between dt); the "
          "winner, the runner-up, and the best soft core (fix nve with WCA or Mie). The factor is the "
          "best soft core's cost over the winner's, with its range over the start states (each state's "
          "own costs: the runs alternate, so both costs of a state come from the same hour).\n")
md.append("| error | target | winner (CPU s / time unit) | runner-up | best soft core | soft / winner (range) |")
md.append("|---|---|---|---|---|---|")
winners = []
for k, desc in KINDS:
    for tgt in TARGETS[k]:
        best = {}
        for p in table:
            if p["n"] == 0 or p["method"] not in ORDER:
                continue
            bb = bound(p, k)
            if np.isfinite(bb) and bb <= tgt:
                if p["method"] not in best or p["cost"] < best[p["method"]]["cost"]:
                    best[p["method"]] = p
        if not best:
            md.append(f"| {k} | {tgt:g} | none reaches it | | | |")
            continue
        rank = sorted(best.values(), key=lambda p: p["cost"])
        w = rank[0]
        ru = rank[1] if len(rank) > 1 else None
        soft = [p for p in rank if p["method"] in SOFT]
        sc = soft[0] if soft else None
        fac = ""
        if sc and w["method"] not in SOFT:
            f = sc["cost"] / w["cost"]
            per = [sc["cost_by_state"][S] / w["cost_by_state"][S] for S in states
                   if S in sc["cost_by_state"] and S in w["cost_by_state"]]
            rng = f" ({min(per):.2g}..{max(per):.2g})" if len(per) > 1 else ""
            fac = f"{f:.2g}{rng}"
        elif sc is None:
            fac = "no soft core reaches it"
        else:
            hs = [p for p in rank if p["method"] in HS]
            if hs:
                f = hs[0]["cost"] / w["cost"]
                fac = f"soft core wins; best hard sphere ({LABEL[hs[0]['method']]} dt {hs[0]['dt_s']}) costs {f:.2g}x"
            else:
                fac = "soft core wins; no hard-sphere run reaches it"
        lab = lambda p: f"{LABEL[p['method']]} dt {p['dt_s']} ({p['cost']:.3g})" if p else "-"
        md.append(f"| {k} | {tgt:g} | {lab(w)} | {lab(ru)} | {lab(sc)} | {fac} |")
        winners.append((k, tgt, w, sc))
md.append("")
md.append("Error kinds: dE = max |E(t) - E(0)| per atom over the run (T_E); slope = |dE/dt| per atom; "
          "dP_own = mean pressure over the first window against the same model at a tiny dt from the same "
          "start state; dP_hs = the same plus the model's offset from hard spheres (long runs).\n")
md.append("Figure: `" + os.path.basename(OUT_PNG) + "` (error bound against cost, log-log; error bars: "
          "± 2 standard errors where known).\n")
open(OUT_MD, "w").write("\n".join(md) + "\n")

# ---- figure
fig, axs = plt.subplots(2, 2, figsize=(12, 9.5))
for ax, (k, desc) in zip(axs.flat, KINDS):
    for m in ORDER:
        ps = [p for p in table if p["method"] == m and p["n"] > 0 and np.isfinite(p.get(k, float("nan")))]
        if not ps:
            continue
        ps.sort(key=lambda p: -p["dt"])
        x = np.array([p["cost"] for p in ps])
        y = np.array([abs(p[k]) for p in ps])
        se = np.array([p.get(k + "_se", float("nan")) for p in ps])
        se = np.where(np.isfinite(se), se, 0.0)
        # a value within 2 s.e. of zero is plotted at its bound, hollow
        lo = np.maximum(y - 2 * se, y * 1e-3)
        hollow = y < 2 * se
        yp = np.where(hollow, y + 2 * se, y)
        xe = np.array([p.get("cost_se", 0.0) for p in ps])
        xe = np.where(np.isfinite(xe), xe, 0.0)
        ax.plot(x, yp, "-", color=COLOR[m], alpha=0.6)
        ax.errorbar(x[~hollow], y[~hollow], yerr=[(y - lo)[~hollow], (2 * se)[~hollow]],
                    xerr=xe[~hollow], fmt="o", color=COLOR[m], ms=5, capsize=2, label=LABEL[m])
        if hollow.any():
            ax.plot(x[hollow], yp[hollow], "v", mfc="none", color=COLOR[m], ms=7,
                    label=None if (~hollow).any() else LABEL[m])
        for xi, yi, p in zip(x, yp, ps):
            ax.annotate(p["dt_s"], (xi, yi), fontsize=6, color=COLOR[m], xytext=(3, 2),
                        textcoords="offset points")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("cost: CPU s per unit of simulated time (N = 32000)")
    ax.set_ylabel(desc, fontsize=8)
    ax.grid(True, which="both", alpha=0.3)
axs.flat[0].legend(fontsize=8)
fig.suptitle("Hard-core fluid + Gaussian attraction, N = 32000, packing fraction 0.3, kT = 1: "
             "error against CPU time\n(hollow triangles: error within 2 s.e. of zero, plotted at "
             "|error| + 2 s.e.; labels: dt)", fontsize=10)
fig.tight_layout()
fig.savefig(OUT_PNG, dpi=110)
print(f"wrote {OUT_MD} and {OUT_PNG}: {sum(r['ok'] for r in runs)} runs ok, "
      f"{sum(not r['ok'] for r in runs)} not")
