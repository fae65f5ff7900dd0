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
model error: block standard errors of the langevin runs.
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
SOFT = ["kg", "mie"]
ORDER = HS + SOFT
COLOR = {"psa": "tab:orange", "cva": "tab:blue", "pcva": "tab:green", "vci": "tab:brown",
         "kg": "tab:red", "mie": "black"}
LABEL = {m: m for m in HS}
LABEL.update({"kg": "nve + WCA (Kremer-Grest)", "mie": "nve + Mie(50,49)"})
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
             dE_lmp=float(d["dEmax"]), coll=float(d["collisions"]), fe=float(d["force_evals"]))
    r["cost"] = r["ctime"] / r["T"]                  # CPU s per unit time
    E = rows(os.path.join(LOGS, "e." + name))
    if E.size:
        t = E[:, 0] * r["dt"]
        e = E[:, 1]
        r["dE"] = float(np.max(np.abs(e - e[0])))
        if len(e) >= 2 * NBLK_E:
            n = len(e) // NBLK_E
            tb = t[:n * NBLK_E].reshape(NBLK_E, n).mean(1)
            eb = e[:n * NBLK_E].reshape(NBLK_E, n).mean(1)
            A = np.vstack([tb, np.ones_like(tb)]).T
            coef, *_ = np.linalg.lstsq(A, eb, rcond=None)
            resid = eb - A @ coef
            s2 = resid @ resid / (NBLK_E - 2)
            r["slope"] = float(coef[0])
            r["slope_se"] = float(math.sqrt(s2 / np.sum((tb - tb.mean()) ** 2)))
    else:
        r["dE"] = r["dE_lmp"]
    if not np.isfinite(r["dE"]):
        r["ok"] = False
        r["error"] = "energy not finite"
    R = rows(os.path.join(LOGS, "r." + name))
    if R.size:
        r["R1"] = float(R[0, 1])          # Rg^2, mean over the first window
        r["rblk"] = R[:, 1]
        r["bblk"] = R[:, 2]
        r["tblk"] = R[:, 3]
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

# ---- per (method, dt): combine the states
points = {}
for r in runs:
    if r["tag"] != "run":
        continue
    points.setdefault((r["method"], r["dt_s"]), []).append(r)

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
    p["coll"] = float(np.mean([r["coll"] / r["T"] for r in ok]))
    p["dE"], p["dE_se"], _ = mean_se([r["dE"] for r in ok])
    sl = [(r["slope"], r["slope_se"]) for r in ok if "slope" in r]
    if sl:
        w = np.array([1 / s[1] ** 2 if s[1] > 0 else 1.0 for s in sl])
        v = np.array([s[0] for s in sl])
        p["slope"] = float((w * v).sum() / w.sum())
        p["slope_se"] = float(1 / math.sqrt(w.sum()))
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
    table.append(p)
table.sort(key=lambda p: (ORDER.index(p["method"]) if p["method"] in ORDER else 99, -p["dt"]))

# noise of the Rg^2 differences (see parse.py: the A - B difference is free of the dt error)
sigma_fit = {}
for m in ORDER:
    pts = [(p["dt"], list(p["dR_diffs"].values())) for p in table
           if p["method"] == m and len(p.get("dR_diffs", {})) >= 2]
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
    if "dR_own" not in p:
        continue
    m = p["method"]
    se = math.exp(sigma_fit[m][0] + sigma_fit[m][1] * math.log(p["dt"])) / math.sqrt(p["dR_own_n"]) \
        if m in sigma_fit else float("nan")
    p["dR_own_se"] = se
    o, ose = offset[m]
    if np.isfinite(o) and np.isfinite(R_HS):
        p["dR_hs"] = p["dR_own"] + o / R_HS
        p["dR_hs_se"] = math.hypot(se if np.isfinite(se) else 0.0, ose / R_HS)


def fmt(x, se=None, d=2):
    if x is None or not np.isfinite(x):
        return "-"
    s = f"{x:.{d}e}"
    if se is not None and np.isfinite(se):
        s += f" ± {se:.1e}"
    return s


def bound(p, k):
    """|error| + 2 standard errors; NaN standard errors count as 0."""
    x = p.get(k)
    if x is None or not np.isfinite(x):
        return float("nan")
    se = p.get(k + "_se", float("nan"))
    return abs(x) + (2 * se if np.isfinite(se) else 0.0)


KINDS = [("dE", "max |E(t) - E(0)| per atom [kT] over T_E"),
         ("slope", "energy drift |dE/dt| per atom [kT per time unit]"),
         ("dR_own", "Rg^2 error vs own dt -> 0 limit (relative)")]
if longs:
    KINDS.append(("dR_hs", "Rg^2 error vs the hard-core model (relative;\n2-time-unit runs from shared conformations, not equilibrium)"))

md = []
md.append("## Run time against error at N = 32000: bead-spring melt (chains of 10, rho 0.85, FENE)\n")
md.append(f"Machine: {mach.get('cpu', '?')}, nproc {mach.get('nproc', '?')} (shared; every run serial, "
          f"`nice -n 19`, one at a time); load average (1, 5, 15 min) {mach.get('load_start', '?')} at "
          f"the start, {mach.get('load_end', '?')} at the end; {mach.get('start', '?')} to "
          f"{mach.get('end', '?')}; commit {mach.get('commit', '?')}; binary {mach.get('binary', '?')}; "
          f"{mach.get('mode', '')}. **Cost = CPU seconds per unit of simulated time**: LAMMPS' Loop "
          f"time x its \"CPU use\" / 100, divided by the run's length T.\n")
DISC = os.path.join(os.path.dirname(os.path.abspath(OUT_MD)),
                    "discussion-melt" + ("-short" if "short" in os.path.basename(OUT_MD) else "") + ".md")
if os.path.exists(DISC):
    md.append(open(DISC).read().rstrip() + "\n")

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
if longs:
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
    if longs:
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
    for m in SOFT:
        o, ose = offset[m]
        if np.isfinite(o):
            md.append(f"Model error of {LABEL[m]}: Rg^2 {o:+.4f} ± {ose:.4f} against the hard-core model "
                      f"({o / R_HS:+.2%} ± {ose / R_HS:.2%}).\n")

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
        best = {}
        for p in table:
            if p["n"] == 0 or p["method"] not in ORDER:
                continue
            bb = bound(p, k)
            if np.isfinite(bb) and bb <= tgt:
                if p["method"] not in best or p["cost"] < best[p["method"]]["cost"]:
                    best[p["method"]] = p
        if not best:
            md.append(f"| {k} | {tgt:g} | none reaches it | | | | |")
            continue
        rank = sorted(best.values(), key=lambda p: p["cost"])
        w = rank[0]
        ru = rank[1] if len(rank) > 1 else None
        soft = [p for p in rank if p["method"] in SOFT]
        hard = [p for p in rank if p["method"] in HS]
        sc = soft[0] if soft else None
        hc = hard[0] if hard else None
        fac = "-"
        if sc and hc:
            f = hc["cost"] / sc["cost"]
            per = [hc["cost_by_state"][S] / sc["cost_by_state"][S] for S in states
                   if S in sc["cost_by_state"] and S in hc["cost_by_state"]]
            rng = f" ({min(per):.3g}..{max(per):.3g})" if len(per) > 1 else ""
            fac = f"{f:.3g}{rng}"
        elif sc:
            fac = "no hard-sphere run reaches it"
        elif hc:
            fac = "no soft core reaches it"
        lab = lambda p: f"{LABEL[p['method']]} dt {p['dt_s']} ({p['cost']:.3g})" if p else "-"
        md.append(f"| {k} | {tgt:g} | {lab(w)} | {lab(ru)} | {lab(sc)} | {lab(hc)} | {fac} |")
md.append("")
md.append("Error kinds: dE = max |E(t) - E(0)| per atom over the run (T_E); slope = |dE/dt| per atom; "
          "dR_own = Rg^2 over the first window against the same model at a tiny dt from the same start "
          "state" + ("; dR_hs = the same plus the model's Rg^2 offset from the hard-core model (langevin runs)"
                     if longs else "") + ".\n")
md.append("Figure: `" + os.path.basename(OUT_PNG) + "` (error against cost, log-log; error bars: "
          "± 2 standard errors where known).\n")
open(OUT_MD, "w").write("\n".join(md) + "\n")

# ---- figure
nk = len(KINDS)
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
