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
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import wplcommon as W
from wplcommon import NBLK_E, fmt, mean_se, rows

LOGS, OUT_MD, OUT_PNG = sys.argv[1], sys.argv[2], sys.argv[3]
HS = ["psa", "cva", "pcva", "vci"]
ORDER = HS + ["wca", "mie"]
SOFT = ["wca", "mie"]
COLOR = {"psa": "tab:orange", "cva": "tab:blue", "pcva": "tab:green", "vci": "tab:brown",
         "wca": "tab:red", "mie": "black", "mcva": "tab:purple"}
LABEL = {m: m for m in HS + ["mcva"]}
LABEL.update({"wca": "nve + WCA", "mie": "nve + Mie(50,49)"})


def read_log(path):
    r = W.read_log(path, LOGS)
    if "bench" not in r:
        return r
    r.update(press_all=float(r["bench"]["press"]), temp=float(r["bench"]["temp"]))
    P = rows(os.path.join(LOGS, "p." + r["name"]))
    X = rows(os.path.join(LOGS, "x." + r["name"]))
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
mach = W.read_machine(LOGS)
get = W.finder(runs)

states = sorted({r["state"] for r in runs if r["tag"] == "run"})



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
def pressure_errors(p, ok):
    m = p["method"]
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


table = W.combine(runs, ORDER, pressure_errors)

# the noise of the pressure differences (wplcommon.noise_fit)
sigma_fit = W.noise_fit(table, ORDER, "dP_diffs")
for p in table:
    if "dP_own" not in p:
        continue
    m = p["method"]
    se = W.noise_se(sigma_fit, m, p["dt"], p["dP_own_n"])
    p["dP_own_se"] = se
    o, ose = offset[m]
    p["dP_hs"] = p["dP_own"] + o / P_HS
    p["dP_hs_se"] = math.hypot(se if np.isfinite(se) else 0.0, ose / P_HS)



KINDS = [("dE", "max |E(t) - E(0)| per atom [kT] over T_E"),
         ("slope", "energy drift |dE/dt| per atom [kT per time unit]"),
         ("dP_own", "pressure error vs own dt -> 0 limit (relative)"),
         ("dP_hs", "pressure error vs the hard-sphere model (relative)")]

md = W.preamble("## Run time against error at N = 32000: hard-core fluid with a Gaussian attraction",
                mach, OUT_MD, "discussion")

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
        rank = W.cheapest(table, k, tgt, ORDER)
        if not rank:
            md.append(f"| {k} | {tgt:g} | none reaches it | | | |")
            continue
        w = rank[0]
        ru = rank[1] if len(rank) > 1 else None
        soft = [p for p in rank if p["method"] in SOFT]
        sc = soft[0] if soft else None
        fac = ""
        if sc and w["method"] not in SOFT:
            fac = W.cost_ratio(sc, w, states, 2)
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
W.plot_panels(axs.flat, table, KINDS, ORDER, COLOR, LABEL)
axs.flat[0].legend(fontsize=8)
fig.suptitle("Hard-core fluid + Gaussian attraction, N = 32000, packing fraction 0.3, kT = 1: "
             "error against CPU time\n(hollow triangles: error within 2 s.e. of zero, plotted at "
             "|error| + 2 s.e.; labels: dt)", fontsize=10)
fig.tight_layout()
fig.savefig(OUT_PNG, dpi=110)
print(f"wrote {OUT_MD} and {OUT_PNG}: {sum(r['ok'] for r in runs)} runs ok, "
      f"{sum(not r['ok'] for r in runs)} not")
