"""What parse.py (the fluid) and parse-melt.py (the melt) share: reading the
logs of run.sh / run-melt.sh, combining the start states per (contender, dt),
the noise fit of the observable's differences, the table of the cheapest
contender at each accuracy and the figure's panels. The systems differ only
in their observable (pressure, Rg^2), its reference runs and the text.

Cost: CPU seconds per unit of simulated time = Loop time x CPU use / 100 / T.
Uncertainties: over the start states (mean and standard error of the mean);
drift: standard error of the slope of a line fitted to NBLK_E block means of
E(t).
"""
import math
import os
import re

import numpy as np

NBLK_E = 10


def rows(path):
    """The numeric rows of a LAMMPS fix ave/time file (no rows: a 0 x 0 array)."""
    if not os.path.exists(path):
        return np.zeros((0, 0))
    r = [l.split() for l in open(path) if l.strip() and not l.startswith("#")]
    return np.array([[float(x) for x in l] for l in r]) if r else np.zeros((0, 0))


def read_log(path, logs):
    """One run: log.<state>.<method>.<dt>.<tag> and its energy file e.<...>.
    ok is False without a BENCH line or with a non-finite energy; r["bench"]
    holds the BENCH line's key-value pairs for the system's own fields."""
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
    r["bench"] = d
    r.update(ok=True, T=float(d["T"]), steps=int(d["steps"]), atoms=int(d["atoms"]),
             dE_lmp=float(d["dEmax"]), coll=float(d["collisions"]), fe=float(d["force_evals"]))
    r["cost"] = r["ctime"] / r["T"]                  # CPU s per unit time
    E = rows(os.path.join(logs, "e." + name))
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
    return r


def read_machine(logs):
    """machine.txt: the first value of each key, the last of load_end and end."""
    mach = {}
    if os.path.exists(os.path.join(logs, "machine.txt")):
        for line in open(os.path.join(logs, "machine.txt")):
            k, _, v = line.strip().partition(" ")
            mach.setdefault(k, v)
            if k in ("load_end", "end"):
                mach[k] = v
    return mach


def finder(runs):
    """get(state, method, tag, dt=None): the first successful run that matches."""
    def get(S, m, tag, dt=None):
        for r in runs:
            if r["ok"] and r["state"] == S and r["method"] == m and r["tag"] == tag and \
                    (dt is None or abs(r["dt"] - dt) < 1e-12):
                return r
        return None
    return get


def mean_se(vals):
    v = [x for x in vals if x is not None and np.isfinite(x)]
    if not v:
        return float("nan"), float("nan"), 0
    if len(v) == 1:
        return v[0], float("nan"), 1
    return float(np.mean(v)), float(np.std(v, ddof=1) / math.sqrt(len(v))), len(v)


def combine(runs, order, observable):
    """Per (method, dt) of the runs tagged "run": cost, CPU use, collisions
    per unit time, max energy error and drift (inverse-variance mean over the
    states), then observable(p, ok) for the system's own fields; sorted by
    contender (order) and decreasing dt."""
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
        p["coll"] = float(np.mean([r["coll"] / r["T"] for r in ok]))      # per unit time
        p["dE"], p["dE_se"], _ = mean_se([r["dE"] for r in ok])
        sl = [(r["slope"], r["slope_se"]) for r in ok if "slope" in r]
        if sl:
            w = np.array([1 / s[1] ** 2 if s[1] > 0 else 1.0 for s in sl])
            v = np.array([s[0] for s in sl])
            p["slope"] = float((w * v).sum() / w.sum())
            p["slope_se"] = float(1 / math.sqrt(w.sum()))
        observable(p, ok)
        table.append(p)
    table.sort(key=lambda p: (order.index(p["method"]) if p["method"] in order else 99, -p["dt"]))
    return table


def noise_fit(table, order, diffs_key):
    """The noise of the observable's differences against the own reference.
    The run and its reference start from the same state but their
    trajectories drift apart over the window, so a difference has a random
    part besides the dt error, and it grows with dt. The difference of two
    states' values, dA - dB, is free of the dt error (the same for both):
    |dA - dB|/sqrt(2) estimates the per-state noise at that dt with one degree
    of freedom. Per contender, a power law sigma = c dt^b is fitted to
    ln(|dA - dB|/sqrt(2)) over its dt values (+0.635 = -E ln|Z| for a normal
    Z, so that the fit estimates sigma, not the mean log). Returns
    {method: (ln c, b, number of dt)}."""
    sigma_fit = {}
    for m in order:
        pts = [(p["dt"], list(p[diffs_key].values())) for p in table
               if p["method"] == m and len(p.get(diffs_key, {})) >= 2]
        pts = [(dt, abs(v[0] - v[1]) / math.sqrt(2)) for dt, v in pts]
        pts = [(dt, x) for dt, x in pts if x > 0]
        if len(pts) >= 3:
            X = np.log([q[0] for q in pts])
            Y = np.log([q[1] for q in pts]) + 0.635
            b, a = np.polyfit(X, Y, 1)
            sigma_fit[m] = (a, b, len(pts))
        elif pts:
            sigma_fit[m] = (math.log(math.sqrt(np.mean([q[1] ** 2 for q in pts]))), 0.0, len(pts))
    return sigma_fit


def noise_se(sigma_fit, m, dt, n):
    """The standard error of a mean over n states: sigma(dt)/sqrt(n)."""
    if m not in sigma_fit:
        return float("nan")
    return math.exp(sigma_fit[m][0] + sigma_fit[m][1] * math.log(dt)) / math.sqrt(n)


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


def cheapest(table, k, tgt, order):
    """Per contender of order, its cheapest point whose bound(k) <= tgt; sorted by cost."""
    best = {}
    for p in table:
        if p["n"] == 0 or p["method"] not in order:
            continue
        bb = bound(p, k)
        if np.isfinite(bb) and bb <= tgt:
            if p["method"] not in best or p["cost"] < best[p["method"]]["cost"]:
                best[p["method"]] = p
    return sorted(best.values(), key=lambda p: p["cost"])


def cost_ratio(num, den, states, digits):
    """num's cost over den's, with its range over the states' own costs."""
    f = num["cost"] / den["cost"]
    per = [num["cost_by_state"][S] / den["cost_by_state"][S] for S in states
           if S in num["cost_by_state"] and S in den["cost_by_state"]]
    rng = f" ({min(per):.{digits}g}..{max(per):.{digits}g})" if len(per) > 1 else ""
    return f"{f:.{digits}g}{rng}"


def plot_panels(axs, table, kinds, order, color, label):
    """One panel per error kind: |error| against cost, one curve per
    contender, labelled by dt; a value within 2 s.e. of zero is plotted at
    its bound, hollow."""
    for ax, (k, desc) in zip(axs, kinds):
        for m in order:
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
            ax.plot(x, yp, "-", color=color[m], alpha=0.6)
            ax.errorbar(x[~hollow], y[~hollow], yerr=[(y - lo)[~hollow], (2 * se)[~hollow]],
                        xerr=xe[~hollow], fmt="o", color=color[m], ms=5, capsize=2, label=label[m])
            if hollow.any():
                ax.plot(x[hollow], yp[hollow], "v", mfc="none", color=color[m], ms=7,
                        label=None if (~hollow).any() else label[m])
            for xi, yi, p in zip(x, yp, ps):
                ax.annotate(p["dt_s"], (xi, yi), fontsize=6, color=color[m], xytext=(3, 2),
                            textcoords="offset points")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("cost: CPU s per unit of simulated time (N = 32000)")
        ax.set_ylabel(desc, fontsize=8)
        ax.grid(True, which="both", alpha=0.3)


def preamble(title, mach, out_md, discussion):
    """The results page's title, the machine and load line, and the
    discussion file (<discussion>[-short].md beside out_md) if it exists."""
    md = [title + "\n"]
    md.append(f"Machine: {mach.get('cpu', '?')}, nproc {mach.get('nproc', '?')} (shared; every run serial, "
              f"`nice -n 19`, one at a time); load average (1, 5, 15 min) {mach.get('load_start', '?')} at "
              f"the start, {mach.get('load_end', '?')} at the end; {mach.get('start', '?')} to "
              f"{mach.get('end', '?')}; commit {mach.get('commit', '?')}; binary {mach.get('binary', '?')}; "
              f"{mach.get('mode', '')}. **Cost = CPU seconds per unit of simulated time**: LAMMPS' Loop "
              f"time x its \"CPU use\" / 100, divided by the run's length T.\n")
    disc = os.path.join(os.path.dirname(os.path.abspath(out_md)),
                        discussion + ("-short" if "short" in os.path.basename(out_md) else "") + ".md")
    if os.path.exists(disc):
        md.append(open(disc).read().rstrip() + "\n")
    return md
