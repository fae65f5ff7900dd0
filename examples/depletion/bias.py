#!/usr/bin/python3
"""The thermostat bias of the depletion example (README.md, "The thermostat
bias"): MD runs of in.ao (or in.bias) against the exact low-density series.

  bias.py DIR TAG [TAG ...]

(tags of in.halfstep runs, lj_*, go to a second table: <T>, <T_half>, Z)

DIR holds log.<TAG>, blocks.<TAG>.txt, gr.<TAG>.txt. Per run: thermostat,
damp, dt, gamma dt (gamma = 1/damp for fix langevin), <T>, Z = 1 +
P_vir/(rho kT) (kT = 1; the measured <T> for an NVE run), Z - series,
Z_smooth (the pair forces' part of Z - 1),
U/N and its series, the mechanism's prediction of Z - series (README:
Z_coll gamma dt / (2 - gamma dt), Z_coll the exact collisional part, (2 pi
rho / 3) exp(-u(sigma)/kT) (1 + rho y1(sigma)), or Z_hs - 1), g(sigma+)
from the impulses, Z_coll / (2 pi rho / 3), and from the configurations (a
straight-line fit of g exp(u/kT) on [sigma, 1.04 sigma], per block), and n_well: the
number of neighbours in the well [sigma, sigma (1+q)] from g(r), over its
value from exp(-u/kT) (1 + rho y1). Series: 1 + B2 rho + B3 rho^2 + B4 rho^3
(virial.py; B4 = 2.35 +- 0.34 from mayer_b4.cpp, README); for hard spheres
(log says pair_style zero) Kolafa's equation of state,
Z = (1 + e + e^2 - (2/3) e^3 (1 + e)) / (1 - e)^3, e = pi rho / 6. Error bars: one standard
error, blocking (../common/blocking.py). At rho > 0.1 (AO) no series:
those runs are compared with the MC of results_mc.md in README.md.
"""
import math, os, re, sys
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "common"))
import virial
from blocking import blocking_se

PI = math.pi
B4_AO = 2.35    # q = 0.2, mayer_b4.cpp (README)
_coef = {}


def series(q, n, kT):
    if q is None:    # hard spheres: Kolafa's correction of Carnahan-Starling
        e = PI / 6 * n
        return (1 + e + e * e - 2.0 / 3.0 * e**3 * (1 + e)) / (1 - e)**3, 0.0, None
    key = (q, kT)
    if key not in _coef:
        _coef[key] = virial.coefficients(q, depth=3.0 / kT)
    B2, B3, y1 = _coef[key]
    R = 1.0 + q
    rr = np.linspace(1.0, R, 401)
    y1i = np.interp(rr, rr[::20], np.array([y1(x) for x in rr[::20]]))
    ur = virial.u(rr, q)
    w = 4 * PI * rr**2 * np.exp(-ur / kT) * (1 + n * y1i)
    Ut = 0.5 * n * np.trapz(ur * w, rr)
    nwell = n * np.trapz(w, rr)
    return 1 + B2 * n + B3 * n * n + B4_AO * n**3, Ut, nwell


def contact(path, q, width=0.04):
    """g(sigma+) from the configurations: per block of g(r), the cavity
    function y = g exp(u/kT) (u at the bin centres; for hard spheres y = g)
    on the bins in [sigma, sigma + width], fitted by a straight line in r and
    taken at sigma, times exp(-u(sigma)/kT). Mean and blocking error."""
    vals, rows = [], []
    for line in open(path):
        if line.startswith("#"):
            continue
        w = line.split()
        if len(w) == 2:
            if rows:
                vals.append(rows)
            rows = []
        else:
            rows.append([float(x) for x in w[1:3]])
    if rows:
        vals.append(rows)
    out = []
    for blk in vals:
        a = np.array(blk)
        sel = (a[:, 0] > 1.0) & (a[:, 0] < 1.0 + width)
        rr, g = a[sel, 0], a[sel, 1]
        u0, ur = (0.0, 0.0 * rr) if q is None else (float(virial.u(1.0, q)), virial.u(rr, q))
        c = np.polyfit(rr - 1.0, g * np.exp(ur), 1)
        out.append(c[1] * math.exp(-u0))
    out = np.array(out)
    return out.mean(), blocking_se(out)


def run(d, tag):
    log = open(os.path.join(d, "log." + tag)).read()
    res = dict(zip(*[iter(re.search(r"^RESULT (.*)$", log, re.M).group(1).split())] * 2))
    n = float(res["atoms"]) / float(res["vol"])
    hs = re.search(r"^\s*pair_style\s+zero", log, re.M) is not None
    q = None if hs else float(res["q"])
    m = [x for x in re.finditer(r"^\s*fix\s+th\s+all\s+(\S+)\s+\S+\s+\S+\s+([0-9.eE+-]+)\s", log, re.M)][-1]
    style, damp = m.group(1), float(m.group(2))
    nve = re.search(r"^\s*unfix th\s*$", log, re.M) is not None
    b = np.loadtxt(os.path.join(d, "blocks." + tag + ".txt"))
    T, U, pv, pf = b[:, 1], b[:, 2], b[:, 3], b[:, 4]
    kT = T.mean() if nve else 1.0
    dt = float(res["dt"])
    r = dict(tag=tag, style=("nve" if nve else style), damp=damp, dt=dt, rho=n, q=q,
             gdt=(dt / damp if style == "langevin" and not nve else 0.0),
             coll=float(res["collisions"]) / float(res["steps"]) / float(res["atoms"]))
    for k, v in (("T", T), ("U", U), ("Z", 1 + pv / (n * kT)), ("Zs", (pv - pf) / (n * kT)),
                 ("gc", pf / (n * kT) / (2 * PI / 3 * n))):
        r[k] = (v.mean(), blocking_se(v))
    zs, ut, nw = series(q, n, kT)
    r["series"], r["Ut"] = zs, ut
    # the exact collisional part of Z: (2 pi rho / 3) g(sigma+), g(sigma+) =
    # exp(-u(sigma)/kT) (1 + rho y1(sigma)) to O(rho) (AO), Z - 1 (hard spheres)
    if q is None:
        zc = zs - 1.0
    else:
        y1 = _coef[(q, kT)][2]
        zc = 2 * PI / 3 * n * math.exp(-float(virial.u(1.0, q)) / kT) * (1 + n * y1(1.0))
    # mechanism (README): impulses at T_half = T / (1 - gamma dt / 2)
    r["pred"] = zc * r["gdt"] / (2 - r["gdt"])
    if b.shape[1] > 5:
        r["Th"] = (b[:, 5].mean(), blocking_se(b[:, 5]))
    gb = os.path.join(d, "grblocks." + tag + ".txt")
    if os.path.exists(gb):
        r["gconf"] = contact(gb, q)
    txt = open(os.path.join(d, "gr." + tag + ".txt")).read().strip().split("\n")
    nrow = int(txt[3].split()[1])
    g = np.array([[float(x) for x in l.split()] for l in txt[-nrow:]])
    if q is not None:
        dr = g[1, 1] - g[0, 1]
        sel = (g[:, 1] > 1.0) & (g[:, 1] < 1.0 + q)
        r["nwell"] = n * np.sum(4 * PI * g[sel, 1]**2 * g[sel, 2]) * dr / nw
    return r


def smooth(d, tag):
    """an in.halfstep run (Lennard-Jones, fix nve + fix langevin, no hard cores)"""
    log = open(os.path.join(d, "log." + tag)).read()
    res = dict(zip(*[iter(re.search(r"^RESULT (.*)$", log, re.M).group(1).split())] * 2))
    b = np.loadtxt(os.path.join(d, "blocks." + tag + ".txt"))
    T0, dt, damp = float(res["T"]), float(res["dt"]), float(res["damp"])
    gdt = dt / damp
    out = [(b[:, k].mean(), blocking_se(b[:, k])) for k in (1, 2, 3)]
    return (f"| {tag} | {damp} | {dt} | {gdt:.4g} | {out[0][0] / T0:.4f} ± {out[0][1] / T0:.4f} | "
            f"{out[1][0] / T0:.4f} ± {out[1][1] / T0:.4f} | {1 / (1 - gdt / 2):.4f} | {out[2][0]:.4f} ± {out[2][1]:.4f} |")


if __name__ == "__main__":
    d = sys.argv[1]
    lj = [t for t in sys.argv[2:] if open(os.path.join(d, "log." + t)).read().find("in.halfstep") >= 0
          or t.startswith("lj_")]
    print("| run | thermostat | damp | dt | gamma dt | coll./sphere/step | <T> | <T_half> | Z | Z - series | Z_coll gamma dt / (2 - gamma dt) | U/N (series) "
          "| Z_smooth | g(sigma+) impulses | g(sigma+) configurations | n_well / exact |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for tag in [t for t in sys.argv[2:] if t not in lj]:
        r = run(d, tag)
        dz = r["Z"][0] - r["series"]
        dense = r["q"] is not None and r["rho"] > 0.1    # the series does not hold: compare with the MC
        if dense:
            dz = float("nan")
        ut = f"{r['U'][0]:.4f} ± {r['U'][1]:.4f} ({r['Ut']:.4f})" if r["q"] is not None else "-"
        if dense:
            ut = f"{r['U'][0]:.4f} ± {r['U'][1]:.4f}"
        nw = f"{r['nwell']:.4f}" if "nwell" in r else "-"
        print(f"| {tag} | {r['style']} | {r['damp']} | {r['dt']} | {r['gdt']:.4g} | {r['coll']:.4f} | "
              f"{r['T'][0]:.4f} ± {r['T'][1]:.4f} | " +
              (f"{r['Th'][0]:.4f} ± {r['Th'][1]:.4f}" if "Th" in r else "-") +
              f" | {r['Z'][0]:.5f} ± {r['Z'][1]:.5f} | " +
              (f"{dz:+.5f} ± {r['Z'][1]:.5f} ({dz / r['Z'][1]:+.1f}) | {r['pred']:+.5f}" if not dense else "- | -") +
              f" | {ut} | " +
              (f"{r['Zs'][0]:.4f} ± {r['Zs'][1]:.4f}" if r["q"] is not None else "-") +
              f" | {r['gc'][0]:.3f} ± {r['gc'][1]:.3f} | " +
              (f"{r['gconf'][0]:.3f} ± {r['gconf'][1]:.3f}" if "gconf" in r else "-") + f" | {nw} |")
    if lj:
        print("\nLennard-Jones fluid, fix nve + fix langevin (in.halfstep; T* 1.5, rho 0.5, 500 atoms):\n")
        print("| run | damp | dt | gamma dt | <T>/T* | <T_half>/T* | 1/(1 - gamma dt/2) | Z |")
        print("|---|---|---|---|---|---|---|---|")
        for tag in lj:
            print(smooth(d, tag))
