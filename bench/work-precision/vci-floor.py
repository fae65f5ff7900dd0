#!/usr/bin/python3
"""Tables for vci-floor.sh (issue 21): energy and pressure errors per form and
dt, fitted orders, and the shape of the energy error in the per-step traces.

    /usr/bin/python3 vci-floor.py <OUT dir>      # writes <OUT>/tables.md

Measures (as in results.md): max |E(t) - E(0)| per atom with E sampled every
0.01 time units (results.md's sampling; `dE(0.01)`) and every step (`dE(step)`);
the pressure: mean of thermo_press (impulse virial included) over steps 1..N,
corrected to a trapezoid mean with the kinetic + pair pressure at steps 0 and N;
its error relative to a reference over the same window from the same start.
"""
import glob
import math
import os
import re
import sys

import numpy as np

OUT = sys.argv[1]
runs = {}
for p in sorted(glob.glob(os.path.join(OUT, "logs", "log.*"))):
    txt = open(p, errors="replace").read()
    m = re.search(r"^FLOOR (.*)$", txt, re.M)
    if not m:
        continue
    f = m.group(1).split()
    d = dict(zip(f[0::2], f[1::2]))
    tag = os.path.basename(p)[4:]
    cells, method, sub = tag.split(".")[:3]
    dt_s = tag[len(cells) + len(method) + len(sub) + 3:]
    loop = re.findall(r"^Loop time of (\S+)", txt, re.M)
    tr = np.loadtxt(os.path.join(OUT, "traces", "tr." + tag), comments="#")
    step, E, P, Psm, coll, nr, nz = tr.T
    N = int(d["steps"])
    assert len(step) == N + 1 and step[0] == 0, tag
    every = math.ceil(0.01 / float(dt_s) - 1e-9)
    r = dict(cells=int(cells), method=method, sub="local" if sub == "default" else sub,
             dt=float(dt_s), dt_s=dt_s, N=N, atoms=int(d["atoms"]), loop=float(loop[-1]),
             coll=int(float(d["collisions"])), noroot=int(float(d["elastic_noroot_held"])),
             tau0=int(float(d["elastic_tau0"])), Ed_evals=float(d["Ed_evals"]),
             maxdEd=float(d["max_dEd"]), E=E - E[0], coll_t=coll)
    r["dE_step"] = np.abs(r["E"]).max()
    r["dE_001"] = np.abs(r["E"][::every]).max()
    r["drift"] = r["E"][-1]
    r["press"] = P[1:].mean() + (Psm[0] - Psm[-1]) / (2 * N)
    # the same over the first 0.1 time units (before the runs' trajectories part)
    n1 = int(round(0.1 / r["dt"]))
    r["press01"] = P[1:n1 + 1].mean() + (Psm[0] - Psm[n1]) / (2 * n1)
    # shape of the error: per-step increments, contacts per step
    dE = np.diff(r["E"])
    nc = np.diff(coll)
    r["rough"] = np.abs(dE).sum() / max(abs(dE.sum()), 1e-300)   # 1: monotone drift
    r["jump"] = np.abs(dE).max() / r["dE_step"]                  # largest one-step share
    r["per_contact"] = r["drift"] * r["atoms"] / max(r["coll"], 1)  # total energy per contact
    # steps without contacts (plain Verlet steps) against steps with them
    quiet = nc == 0
    r["frac_quiet"] = quiet.mean()
    r["dE_quiet"] = dE[quiet].sum()
    r["dE_busy"] = dE[~quiet].sum()
    runs[(r["cells"], method, r["sub"], dt_s)] = r


def get(c, m, s, dt_s):
    return runs.get((c, m, s, dt_s))


def order(xs, ys):
    xs, ys = np.array(xs), np.array(ys)
    ok = ys > 0
    if ok.sum() < 2:
        return float("nan")
    return np.polyfit(np.log(xs[ok]), np.log(ys[ok]), 1)[0]


md = []
FORMS = [("vci", "global"), ("vci", "local"), ("cva", "local"), ("cva", "global")]
for c in sorted({k[0] for k in runs}, reverse=True):
    atoms = next(r["atoms"] for k, r in runs.items() if k[0] == c)
    ref_g = get(c, "cva", "global", "0.0001")
    ref_l = get(c, "cva", "local", "0.0001")
    ref_v = get(c, "vci", "local", "0.00015625")
    md.append(f"### {atoms} spheres (T = 0.4 from the same start)\n")
    refs = []
    for name, rr in (("cva global dt 0.0001", ref_g), ("cva local dt 0.0001", ref_l),
                     ("vci local dt 0.00015625", ref_v)):
        if rr:
            refs.append(f"{name}: {rr['press']:.9f}")
    md.append("Reference pressures: " + "; ".join(refs) + ".\n")
    md.append("| form | dt | steps | contacts | contacts per step | elastic: no root/held, tau2=0 | "
              "dE(0.01) | dE(step) | E(T)-E(0) | rough | press | err vs cva-global ref | "
              "err vs own-engine ref | signed err vs cva-global ref, t in [0, 0.1] | Loop s |")
    md.append("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for m, s in FORMS:
        rs = sorted([r for k, r in runs.items() if k[0] == c and k[1] == m and k[2] == s],
                    key=lambda r: -r["dt"])
        own = ref_v if (m, s) == ("vci", "local") else (ref_l if s == "local" else ref_g)
        for r in rs:
            eg = abs(r["press"] - ref_g["press"]) / ref_g["press"] if ref_g and r is not ref_g else float("nan")
            eo = abs(r["press"] - own["press"]) / own["press"] if own and r is not own else float("nan")
            r["err_g"], r["err_o"] = eg, eo
            e01 = (r["press01"] - ref_g["press01"]) / ref_g["press01"] if ref_g and r is not ref_g else float("nan")
            md.append(f"| {m} {s} | {r['dt_s']} | {r['N']} | {r['coll']} | {r['coll'] / r['N']:.1f} | "
                      f"{r['noroot']}, {r['tau0']} | {r['dE_001']:.2e} | {r['dE_step']:.2e} | "
                      f"{r['drift']:+.2e} | {r['rough']:.2f} | {r['press']:.7f} | {eg:.1e} | {eo:.1e} | {e01:+.1e} | "
                      f"{r['loop']:.3g} |")
    md.append("")
    md.append("Fitted orders (least squares of log error on log dt over the main dts 0.005 ... 0.000625):\n")
    md.append("| form | dE(0.01) | dE(step) | pressure vs cva-global ref | pressure vs own-engine ref |")
    md.append("|---|---|---|---|---|")
    for m, s in FORMS:
        rs = [r for k, r in runs.items() if k[0] == c and k[1] == m and k[2] == s
              and 0.0006 < r["dt"] <= 0.005]
        if len(rs) < 2:
            continue
        xs = [r["dt"] for r in rs]
        md.append(f"| {m} {s} | {order(xs, [r['dE_001'] for r in rs]):.2f} | "
                  f"{order(xs, [r['dE_step'] for r in rs]):.2f} | "
                  f"{order(xs, [r['err_g'] for r in rs]):.2f} | {order(xs, [r['err_o'] for r in rs]):.2f} |")
    md.append("")
    md.append("Shape of the energy error: E(T)-E(0) per contact (total energy, not per atom), the "
              "largest one-step change as a share of max|E-E0|, the share of steps without a "
              "contact and the energy change summed over those steps and over the steps with "
              "contacts (per atom):\n")
    md.append("| form | dt | drift per contact | largest step share | steps w/o contact | "
              "sum dE quiet steps | sum dE contact steps |")
    md.append("|---|---|---|---|---|---|---|")
    for m, s in FORMS:
        for r in sorted([r for k, r in runs.items() if k[0] == c and k[1] == m and k[2] == s],
                        key=lambda r: -r["dt"]):
            md.append(f"| {m} {s} | {r['dt_s']} | {r['per_contact']:+.2e} | {r['jump']:.2f} | "
                      f"{r['frac_quiet']:.2f} | {r['dE_quiet']:+.2e} | {r['dE_busy']:+.2e} |")
    md.append("")


def w_of(data):
    """W = sum_pairs v_ij^T V'' v_ij - 1/2 sum_i |grad_i V|^2 (unit masses) of pair.fluid's
    Gaussian well at a start state: E_d - H of a Verlet sub-step of length tau is
    tau^2 W / 4 + O(tau^3) (doc/fix_hardsphere_vci.rst, Accuracy)."""
    A, r0, sg, rc = -0.501325654926, 1.0, 0.2, 2.4
    lines = open(data).read().splitlines()
    L = np.array([float(l.split()[1]) - float(l.split()[0]) for l in lines
                  if l.endswith(("xlo xhi", "ylo yhi", "zlo zhi"))])

    def section(name):
        i = next(k for k, l in enumerate(lines) if l.startswith(name))
        rows = []
        for l in lines[i + 2:]:
            if not l.strip():
                break
            rows.append(l.split())
        return rows
    at, ve = section("Atoms"), section("Velocities")
    ids = [int(r[0]) for r in at]
    x = np.array([[float(v) for v in r[2:5]] for r in at])
    vd = {int(r[0]): [float(v) for v in r[1:4]] for r in ve}
    v = np.array([vd[i] for i in ids])
    n = len(x)
    w1, g = 0.0, np.zeros_like(x)
    for i in range(n - 1):
        d = x[i] - x[i + 1:]
        d -= L * np.round(d / L)
        r = np.sqrt((d * d).sum(1))
        m = r < rc
        d, r, j = d[m], r[m], np.arange(i + 1, n)[m]
        e = A * np.exp(-(r - r0) ** 2 / (2 * sg * sg))
        d1 = -e * (r - r0) / sg ** 2
        d2 = e * ((r - r0) ** 2 / sg ** 4 - 1 / sg ** 2)
        u = d / r[:, None]
        vr = v[i] - v[j]
        vn = (vr * u).sum(1)
        w1 += (d2 * vn ** 2 + d1 / r * ((vr * vr).sum(1) - vn ** 2)).sum()
        f = d1[:, None] * u
        g[i] += f.sum(0)
        np.add.at(g, j, -f)
    return w1 - 0.5 * (g * g).sum()


md.append("### The global form's per-step energy kicks\n")
md.append("Within a step the global form carries E_d of the whole system from sub-step to "
          "sub-step across every contact, so the step's change of H from the matches telescopes "
          "to (tau_first^2 - tau_last^2) W / 4, tau_first the gap from the step's start to the "
          "first contact anywhere in the box and tau_last from the last contact to the step's "
          "end; W (below) from the start state. Predicted rms per step: with many contacts per "
          "step (exponential gaps of mean 1/R, R the box's collision rate) sqrt(40) W / (4 R^2), "
          "independent of dt; with at most one contact per step (gap uniform in [0, dt]) "
          "dt^2 W / (4 sqrt(3)) per step with a contact. Measured: the rms of E(t+dt) - E(t) (total "
          "energy) over all steps and over the steps with a contact.\n")
md.append("| spheres | W | form | dt | contacts per step | rms dE per step | rms dE per step with contact | "
          "predicted (many per step) | predicted (one per step) |")
md.append("|---|---|---|---|---|---|---|---|---|")
for c in sorted({k[0] for k in runs}, reverse=True):
    data = os.path.join(OUT, "fluid.%d.data" % c)
    if not os.path.exists(data):
        continue
    W = w_of(data)
    for m, s in (("vci", "global"), ("cva", "global"), ("vci", "local")):
        for r in sorted([r for k, r in runs.items() if k[0] == c and k[1] == m and k[2] == s],
                        key=lambda r: -r["dt"]):
            dE = np.diff(r["E"]) * r["atoms"]
            busy = np.diff(r["coll_t"]) > 0
            R = r["coll"] / (r["N"] * r["dt"])
            many = math.sqrt(40) * W / (4 * R * R) if m == "vci" and s == "global" else float("nan")
            one = r["dt"] ** 2 * W / (4 * math.sqrt(3)) if m == "vci" and s == "global" else float("nan")
            md.append(f"| {r['atoms']} | {W:.3g} | {m} {s} | {r['dt_s']} | {r['coll'] / r['N']:.2f} | "
                      f"{np.sqrt((dE ** 2).mean()):.2e} | {np.sqrt((dE[busy] ** 2).mean()):.2e} | "
                      f"{many:.1e} | {one:.1e} |")
md.append("")
open(os.path.join(OUT, "tables.md"), "w").write("\n".join(md) + "\n")
print("\n".join(md))
