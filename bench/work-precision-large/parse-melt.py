#!/usr/bin/python3
"""Parse the logs of bench/work-precision-large/run-melt.sh (system (b), the
bead-spring melt) into a table, the cheapest contender at each accuracy, and
a figure (panels: max energy error, energy drift rate, Rg^2 error against
the model's own dt -> 0 limit, and, if the model-error runs exist, Rg^2
error against the hard-core model).

    /usr/bin/python3 parse-melt.py <log dir> <results-melt.md> <plot.png>

Cost: CPU seconds per unit of simulated time = Loop time x CPU use / 100 / T.
Uncertainties: over the start states A and B (mean and half their
difference, i.e. the standard error of a mean of two) where both exist;
drift: standard error of the slope of a line fitted to 10 block means of
E(t); Rg^2 against the own limit: the A - B difference of the errors (free
of the dt error) fitted as a power of dt, as parse.py does for the pressure;
model error: the equilibrium offsets of results-model-error.json (written by
parse-model-error.py) if it exists, else block standard errors of the
2-time-unit langevin runs (LONG=1, not equilibrium).
"""
import glob
import json
import math
import os
import re
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
SOFT = ["kg", "mie"]
ORDER = HS + SOFT
COLOR = {"psa": "tab:orange", "cva": "tab:blue", "pcva": "tab:green", "vci": "tab:brown",
         "kg": "tab:red", "mie": "black"}
LABEL = {m: m for m in HS}
LABEL.update({"kg": "nve + WCA (Kremer-Grest)", "mie": "nve + Mie(50,49)"})


def read_log(path):
    r = W.read_log(path, LOGS)
    if "bench" not in r:
        return r
    R = rows(os.path.join(LOGS, "r." + r["name"]))
    if R.size:
        r["R1"] = float(R[0, 1])          # Rg^2, mean over the first window
        r["rblk"] = R[:, 1]
        r["bblk"] = R[:, 2]
        r["tblk"] = R[:, 3]
    return r


runs = [read_log(p) for p in sorted(glob.glob(os.path.join(LOGS, "log.*")))]
mach = W.read_machine(LOGS)
get = W.finder(runs)

states = sorted({r["state"] for r in runs if r["tag"] == "run"})



# ---- model error (langevin runs at kT = 1): Rg^2 over blocks of 0.5, the first block dropped
longs = {}
for m in ("cva", "kg", "mie"):
    lrs = [r for r in runs if r["ok"] and r["method"] == m and r["tag"] == "long" and "rblk" in r]
    if lrs:
        b = np.concatenate([r["rblk"][1:] for r in lrs])
        bl = np.concatenate([r["bblk"][1:] for r in lrs])
        slopes = []
        for r in lrs:     # trend of Rg^2 over the run (is it still relaxing?)
            y = r["rblk"]
            x = 0.5 * (np.arange(len(y)) + 0.5)
            slopes.append(np.polyfit(x, y, 1)[0] if len(y) >= 3 else float("nan"))
        longs[m] = dict(R=float(b.mean()), se=float(b.std(ddof=1) / math.sqrt(len(b))) if len(b) > 1 else float("nan"),
                        n=len(b), bond=float(bl.mean()),
                        T=float(np.concatenate([r["tblk"][1:] for r in lrs]).mean()), r=lrs[0],
                        states="+".join(r["state"] for r in lrs), Ttot=sum(r["T"] for r in lrs),
                        ctime=sum(r["ctime"] for r in lrs), slope=float(np.nanmean(slopes)),
                        first={r["state"]: float(r["rblk"][0]) for r in lrs},
                        per_state={r["state"]: float(r["rblk"][1:].mean()) for r in lrs})
hs_long = longs.get("cva")
offset = {m: (0.0, 0.0) for m in HS}
for m in SOFT:
    if m in longs and hs_long:
        offset[m] = (longs[m]["R"] - hs_long["R"], math.hypot(longs[m]["se"], hs_long["se"]))
    else:
        offset[m] = (float("nan"), float("nan"))

ownref_m = {m: "cva" for m in HS}
ownref_m.update({"kg": "kg", "mie": "mie"})
R_REF = {}
for S in states:
    for m in ("cva", "kg", "mie"):
        x = get(S, m, "ref")
        if x and "R1" in x:
            R_REF[(S, m)] = x["R1"]
R_HS = hs_long["R"] if hs_long else (np.mean([v for (S, m), v in R_REF.items() if m == "cva"])
                                    if any(m == "cva" for S, m in R_REF) else float("nan"))
# the equilibrium model error (run-model-error.sh: N = 4000, kT = 1, the hard cores by psa),
# if made, gives the offsets instead of the 2-time-unit langevin runs above
EQ_JSON = os.path.join(os.path.dirname(os.path.abspath(__file__)), "results-model-error.json")
eq = json.load(open(EQ_JSON)) if os.path.exists(EQ_JSON) else {}
eq_used = "psa" in eq and all(m in eq for m in SOFT)
if eq_used:
    R_HS = eq["psa"]["rg2"]
    for m in SOFT:
        offset[m] = (eq[m]["rg2"] - R_HS, math.hypot(eq[m]["rg2_se"], eq["psa"]["rg2_se"]))
have_hs = bool(longs) or eq_used

# ---- per (method, dt): combine the states
def rg_errors(p, ok):
    m = p["method"]
    diffs = {}
    for r in ok:
        ref = R_REF.get((r["state"], ownref_m[m]))
        if ref is not None and "R1" in r:
            diffs[r["state"]] = (r["R1"] - ref) / ref
    if diffs:
        d, dse, nd = mean_se(list(diffs.values()))
        p["dR_own"] = d
        p["dR_own_n"] = nd
        p["dR_diffs"] = diffs
    p["R1"] = float(np.mean([r["R1"] for r in ok if "R1" in r]))


table = W.combine(runs, ORDER, rg_errors)

# the noise of the Rg^2 differences (wplcommon.noise_fit)
sigma_fit = W.noise_fit(table, ORDER, "dR_diffs")
for p in table:
    if "dR_own" not in p:
        continue
    m = p["method"]
    se = W.noise_se(sigma_fit, m, p["dt"], p["dR_own_n"])
    p["dR_own_se"] = se
    o, ose = offset[m]
    if np.isfinite(o) and np.isfinite(R_HS):
        p["dR_hs"] = p["dR_own"] + o / R_HS
        p["dR_hs_se"] = math.hypot(se if np.isfinite(se) else 0.0, ose / R_HS)



KINDS = [("dE", "max |E(t) - E(0)| per atom [kT] over T_E"),
         ("slope", "energy drift |dE/dt| per atom [kT per time unit]"),
         ("dR_own", "Rg^2 error vs own dt -> 0 limit (relative)")]
if eq_used:
    KINDS.append(("dR_hs", "Rg^2 error vs the hard-core model (relative;\nequilibrium offsets, results-model-error.md)"))
elif longs:
    KINDS.append(("dR_hs", "Rg^2 error vs the hard-core model (relative;\n2-time-unit runs from shared conformations, not equilibrium)"))

md = W.preamble("## Run time against error at N = 32000: bead-spring melt (chains of 10, rho 0.85, FENE)",
                mach, OUT_MD, "discussion-melt")

md.append("### Table\n")
md.append(f"Start states: {', '.join(states)} (each value is the mean over them; ± is the standard "
          f"error of that mean, i.e. half the difference for two states; no ± with one state). "
          f"Rg^2 = mean over the 3200 chains of the squared radius of gyration, averaged over the first "
          f"window (samples every 0.05 time units); its error is relative to the same model's reference run. "
          f"dE/dt: slope of a line through {NBLK_E} block means of E(t), ± its standard error "
          f"(inverse-variance mean over the states). Collisions per unit time.\n")
if sigma_fit:
    md.append("Noise of the Rg^2 differences: per contender a power law sigma = c dt^b per state is fitted "
              "to |dA - dB|/sqrt(2) over its dt values (the dt error cancels from dA - dB; logs corrected by "
              "+0.635); the ± is sigma(dt)/sqrt(number of states). Fitted exponents b: " +
              ", ".join(f"{LABEL[m]} {v[1]:.2f} ({v[2]} dt)" for m, v in sigma_fit.items()) + ".\n")
elif len(states) == 1:
    md.append("One start state: the Rg^2 errors have no uncertainty estimate (the run and its reference "
              "decorrelate over the window; the full mode measures this noise from two states).\n")
hdr = ("| contender | dt | cost CPU s / time unit | min CPU use | collisions / time unit | "
       "max abs(E-E0) per atom | dE/dt per atom | Rg^2 error vs own limit | Rg^2 error per state |")
if have_hs:
    hdr += " Rg^2 error vs hard cores |"
md.append(hdr)
md.append("|---" * (hdr.count("|") - 1) + "|")
for p in table:
    if p["n"] == 0:
        md.append(f"| {LABEL.get(p['method'], p['method'])} | {p['dt_s']} | FAILED: "
                  f"{p['failed'][0].get('error', '')[:100]} |" + " |" * (hdr.count("|") - 4))
        continue
    fail = f" ({len(p['failed'])} failed)" if p["failed"] else ""
    line = (f"| {LABEL.get(p['method'], p['method'])}{fail} | {p['dt_s']} | {fmt(p['cost'], p['cost_se'])} | "
            f"{p['cpu']:.0f}% | {p['coll']:.3g} | {fmt(p['dE'], p['dE_se'])} | "
            f"{fmt(p.get('slope'), p.get('slope_se'))} | {fmt(p.get('dR_own'), p.get('dR_own_se'))} | "
            f"{', '.join(f'{S} {v:+.1e}' for S, v in sorted(p.get('dR_diffs', {}).items()))} |")
    if have_hs:
        line += f" {fmt(p.get('dR_hs'), p.get('dR_hs_se'))} |"
    md.append(line)
md.append("")

md.append("References (each model's dt -> 0 limit over the first window, same start state):\n")
md.append("| state | model | dt | window T | Rg^2 (window mean) | CPU s |")
md.append("|---|---|---|---|---|---|")
for S in states:
    for m in ("cva", "kg", "mie"):
        r = get(S, m, "ref")
        if r and "R1" in r:
            md.append(f"| {S} | {LABEL[m]} | {r['dt_s']} | {r['T']} | {r['R1']:.6f} | {r['ctime']:.3g} |")
md.append("")
if longs:
    md.append("Model error: runs with `fix langevin 1 1 1` beside the integrator (all models at kT = 1); "
              "Rg^2 and mean bond length over blocks of 0.5 time units, the first block dropped; standard "
              "error from the block means (the chains of 10 relax over tens of time units, so these runs "
              "see the fast part of the relaxation only: the trend column says whether Rg^2 still moves):\n")
    md.append("| model | dt | states | T total | Rg^2 | std. error | blocks | first block per state | "
              "trend dRg^2/dt | mean bond length | mean temperature | CPU s |")
    md.append("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for m, L in longs.items():
        md.append(f"| {LABEL[m]} | {L['r']['dt_s']} | {L['states']} | {L['Ttot']:g} | {L['R']:.4f} | "
                  f"{L['se']:.4f} | {L['n']} | {', '.join(f'{k} {v:.4f}' for k, v in L['first'].items())} | "
                  f"{L['slope']:+.2e} | {L['bond']:.4f} | {L['T']:.4f} | {L['ctime']:.3g} |")
    md.append("")
    if not eq_used:
        for m in SOFT:
            o, ose = offset[m]
            if np.isfinite(o):
                md.append(f"Model error of {LABEL[m]}: Rg^2 {o:+.4f} ± {ose:.4f} against the hard-core model "
                          f"({o / R_HS:+.2%} ± {ose / R_HS:.2%}).\n")
        md.append("These 2-time-unit offsets are not equilibrium values (they enter the column \"Rg^2 error vs "
                  "hard cores\" and the dR_hs rows); the equilibrium model error is in results-model-error.md "
                  "(run-model-error.sh).\n")
    else:
        md.append("These 2-time-unit runs are not at equilibrium and are not used; the offsets below are.\n")
if eq_used:
    md.append("Model error (the column \"Rg^2 error vs hard cores\" and the dR_hs rows add it to each run's "
              "error against its own limit): the equilibrium offsets of results-model-error.md "
              "(run-model-error.sh; N = 4000, kT = 1, fix langevin 1 1 1, the hard cores by psa): " +
              "; ".join(f"{LABEL[m]} Rg^2 {offset[m][0]:+.4f} ± {offset[m][1]:.4f} "
                        f"({offset[m][0] / R_HS:+.2%} ± {offset[m][1] / R_HS:.2%})" for m in SOFT) + ".\n")

# ---- the local engine's clusters (in.melt-clusters)
clu = []
for path in sorted(glob.glob(os.path.join(LOGS, "clu.*")), key=lambda q: -float(q.split(".", 3)[3])):
    txt = open(path, errors="replace").read()
    c = re.search(r"^CLUSTERS (.*)$", txt, re.M)
    lp = re.findall(r"^Loop time of (\S+) on", txt, re.M)
    cu = re.findall(r"^(\S+)% CPU use", txt, re.M)
    if c:
        d = dict(zip(c.group(1).split()[0::2], c.group(1).split()[1::2]))
        d["ctime"] = float(lp[-1]) * float(cu[-1]) / 100 if lp and cu else float("nan")
        clu.append(d)
if clu:
    md.append("The local engine's clusters (cva, state A, 0.05 time units per dt, `in.melt-clusters`; "
              "entries 6-9 of the fix's vector): the same collisions are split into more and smaller "
              "clusters at smaller dt.\n")
    md.append("| dt | steps | collisions | clusters | mean members per cluster | largest cluster | growth rounds | "
              "CPU us per collision (whole run) |")
    md.append("|---|---|---|---|---|---|---|---|")
    for d in clu:
        md.append(f"| {d['dt']} | {d['steps']} | {float(d['collisions']):.0f} | {float(d['clusters']):.0f} | "
                  f"{d['mean_members']} | {float(d['largest']):.0f} | {float(d['growth_rounds']):.0f} | "
                  f"{d['ctime'] / float(d['collisions']) * 1e6:.0f} |")
    md.append("")

# ---- winners
TARGETS = {"dE": [1e-2, 1e-3, 1e-4, 1e-5, 1e-6],
           "slope": [1e-2, 1e-3, 1e-4, 1e-5, 1e-6],
           "dR_own": [1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5, 1e-5],
           "dR_hs": [1e-1, 3e-2, 1e-2, 3e-3]}
md.append("### Cheapest contender at each accuracy\n")
md.append("For each target, the cheapest run (mean cost over the states) of each contender whose error "
          "bound |error| + 2 standard errors is at most the target (no interpolation between dt; with one "
          "state there is no standard error and the bound is |error|); the winner, the runner-up, the best "
          "soft core (fix nve with WCA or Mie) and the best hard-sphere method. The factor is the best "
          "hard-sphere run's cost over the best soft core's (> 1: the soft core is cheaper), with its "
          "range over the start states.\n")
md.append("| error | target | winner (CPU s / time unit) | runner-up | best soft core | best hard spheres | "
          "hard / soft (range) |")
md.append("|---|---|---|---|---|---|---|")
for k, desc in KINDS:
    for tgt in TARGETS[k]:
        rank = W.cheapest(table, k, tgt, ORDER)
        if not rank:
            md.append(f"| {k} | {tgt:g} | none reaches it | | | | |")
            continue
        w = rank[0]
        ru = rank[1] if len(rank) > 1 else None
        soft = [p for p in rank if p["method"] in SOFT]
        hard = [p for p in rank if p["method"] in HS]
        sc = soft[0] if soft else None
        hc = hard[0] if hard else None
        fac = "-"
        if sc and hc:
            fac = W.cost_ratio(hc, sc, states, 3)
        elif sc:
            fac = "no hard-sphere run reaches it"
        elif hc:
            fac = "no soft core reaches it"
        lab = lambda p: f"{LABEL[p['method']]} dt {p['dt_s']} ({p['cost']:.3g})" if p else "-"
        md.append(f"| {k} | {tgt:g} | {lab(w)} | {lab(ru)} | {lab(sc)} | {lab(hc)} | {fac} |")
md.append("")
md.append("Error kinds: dE = max |E(t) - E(0)| per atom over the run (T_E); slope = |dE/dt| per atom; "
          "dR_own = Rg^2 over the first window against the same model at a tiny dt from the same start "
          "state" + ("; dR_hs = the same plus the model's Rg^2 offset from the hard-core model ("
                     + ("equilibrium, results-model-error.md" if eq_used else "2-time-unit langevin runs") + ")"
                     if have_hs else "") + ".\n")
md.append("Figure: `" + os.path.basename(OUT_PNG) + "` (error against cost, log-log; error bars: "
          "± 2 standard errors where known).\n")
open(OUT_MD, "w").write("\n".join(md) + "\n")

# ---- figure
nk = len(KINDS)
fig, axs = plt.subplots(2, 2, figsize=(12, 9.5))
W.plot_panels(axs.flat, table, KINDS, ORDER, COLOR, LABEL)
for ax in list(axs.flat)[nk:]:
    ax.axis("off")
axs.flat[0].legend(fontsize=8)
fig.suptitle("Bead-spring melt (chains of 10, rho 0.85, FENE), N = 32000, kT = 1: error against CPU time\n"
             "(hollow triangles: error within 2 s.e. of zero, plotted at |error| + 2 s.e.; labels: dt)",
             fontsize=10)
fig.tight_layout()
fig.savefig(OUT_PNG, dpi=110)
print(f"wrote {OUT_MD} and {OUT_PNG}: {sum(r['ok'] for r in runs)} runs ok, "
      f"{sum(not r['ok'] for r in runs)} not")
