#!/usr/bin/python3
"""Summarise examples/depletion: analyze.py SCRATCHDIR OUT.md "q:rho ..."

Against the exact low-density expansion of virial.py (quadrature):
  g(r)  = exp(-u/kT) [1 + rho y1(r)]                 + O(rho^2)
  Z     = 1 + B2 rho + B3 rho^2                      + O(rho^3)
  U/N   = (rho/2) int 4 pi r^2 u exp(-u/kT) [1 + rho y1(r)] dr + O(rho^3)
MD: Z = 1 + P_vir/(rho kT) from blocks averaging every step; g(r) from
compute rdf (bins of 0.005 sigma), the theory averaged over each bin with
weight r^2. Error bars: blocking of 100 block means; for g(r) the scatter
of the theory/MD ratio over the bins is shown, not a per-bin error.
"""
import math, os, re, sys
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import virial
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
from blocking import blocking_se    # ../common/blocking.py

scr, out, states = sys.argv[1], sys.argv[2], sys.argv[3].split()
PI = math.pi


coef = {}
res = []
for s in states:
    qs, rs, *extra = s.split(":")    # optional third field: tag suffix of a variant run
    q, rho = float(qs), float(rs)
    if q not in coef:
        coef[q] = virial.coefficients(q)
    B2, B3, y1 = coef[q]
    tag = f"q{qs}_rho{rs}" + (extra[0] if extra else "")
    log = open(os.path.join(scr, "log." + tag)).read()
    run = dict(zip(*[iter(re.search(r"^RESULT (.*)$", log, re.M).group(1).split())] * 2))
    n = float(run["atoms"]) / float(run["vol"])
    b = np.loadtxt(os.path.join(scr, "blocks." + tag + ".txt"))
    T, U, pv, pf = b[:, 1], b[:, 2], b[:, 3], b[:, 4]
    Z = 1 + pv / n
    half = len(Z) // 2
    # theory
    R = 1.0 + q
    rr = np.linspace(1.0, R, 2001)
    y1r = np.array([y1(x) for x in rr[::20]])
    y1i = np.interp(rr, rr[::20], y1r)
    ur = virial.u(rr, q)
    Ut = 0.5 * n * np.trapz(4 * PI * rr**2 * ur * np.exp(-ur) * (1 + n * y1i), rr)
    Zt = 1 + B2 * n + B3 * n * n
    # g(r): last (running) block of the rdf file
    txt = open(os.path.join(scr, "gr." + tag + ".txt")).read().strip().split("\n")
    nrow = int(txt[3].split()[1])
    g = np.array([[float(x) for x in l.split()] for l in txt[-nrow:]])
    rc, gm = g[:, 1], g[:, 2]
    h = rc[1] - rc[0]
    sel = (rc - h / 2 >= 1.0 - 1e-9) & (rc + h / 2 <= R + 1e-9)
    gth = []
    for c in rc[sel]:
        x = np.linspace(c - h / 2, c + h / 2, 41)
        yy = np.interp(x, rr, y1i)
        w = x * x
        gth.append(np.sum(w * np.exp(-virial.u(x, q)) * (1 + n * yy)) / np.sum(w))
    gth = np.array(gth)
    ratio = gm[sel] / gth
    dt = float(run["dt"])
    res.append(dict(q=q, rho=n, dt=dt, N=int(run["atoms"]), steps=int(run["steps"]), T=(T.mean(), blocking_se(T)),
                    U=(U.mean(), blocking_se(U)), Ut=Ut, Z=(Z.mean(), blocking_se(Z)), Zt=Zt,
                    Zh=(Z[:half].mean(), Z[half:].mean()), B2=B2, B3=B3,
                    ratio=(ratio.mean(), ratio.std(ddof=1) / math.sqrt(len(ratio)), ratio.min(), ratio.max()),
                    gr=(rc, gm), grt=(rc[sel], gth),
                    Bfit=((Z.mean() - 1 - B3 * n * n) / n, blocking_se(Z) / n)))

L = ["# Depletion (Asakura-Oosawa) colloids: MD against the exact low-density expansion\n",
     "Written by `analyze.py` from the runs of `run.sh`. Theory from `virial.py` (quadrature). "
     "Uncertainties: one standard error (blocking of 100 block means).\n"]
L.append("| q | B2 / sigma^3 | B2 / B2_HS | B3 / sigma^6 |")
L.append("|---|---|---|---|")
for q, (B2, B3, _) in coef.items():
    L.append(f"| {q} | {B2:.5f} | {B2 / (2 * PI / 3):.5f} | {B3:.5f} |")
L.append("\n| q | rho sigma^3 | N | steps (dt) | <T> | MD Z | 1 + B2 rho + B3 rho^2 | dev | (Z - 1 - B3 rho^2)/rho | B2 | "
         "MD U/N | theory U/N | g_MD / g_theory on [sigma, sigma(1+q)]: mean, min, max |")
L.append("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
for r in res:
    L.append(f"| {r['q']} | {r['rho']:.4f} | {r['N']} | {r['steps']} ({r['dt']}) | {r['T'][0]:.4f} ± {r['T'][1]:.4f} | "
             f"{r['Z'][0]:.5f} ± {r['Z'][1]:.5f} | {r['Zt']:.5f} | {(r['Z'][0] - r['Zt']) / r['Z'][1]:+.1f} | "
             f"{r['Bfit'][0]:.3f} ± {r['Bfit'][1]:.3f} | {r['B2']:.3f} | {r['U'][0]:.4f} ± {r['U'][1]:.4f} | "
             f"{r['Ut']:.4f} | {r['ratio'][0]:.4f} ± {r['ratio'][1]:.4f}, {r['ratio'][2]:.3f}, {r['ratio'][3]:.3f} |")
L.append("\nFirst and second half of each run, mean Z: " +
         "; ".join(f"q {r['q']} rho {r['rho']:.3f}: {r['Zh'][0]:.5f} / {r['Zh'][1]:.5f}" for r in res))
open(out, "w").write("\n".join(L) + "\n")
print("\n".join(L))

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    sys.exit(0)
fig, ax = plt.subplots(1, len(res), figsize=(3.6 * len(res), 3.2))
ax = np.atleast_1d(ax)
for k, r in enumerate(res):
    ax[k].semilogy(*r["gr"], "r.", ms=3, label="MD (cva)")
    ax[k].semilogy(*r["grt"], "k-", lw=1, label="exp(-u/kT)(1 + rho y1)")
    ax[k].set_xlim(0.98, 1.0 + r["q"] + 0.1)
    ax[k].set_ylim(0.5, 40)
    ax[k].set_title(f"q = {r['q']}, rho = {r['rho']:.3f}, dt {r['dt']}", fontsize=9)
    ax[k].set_xlabel("r / sigma")
ax[0].set_ylabel("g(r)")
ax[0].legend(fontsize=8)
fig.tight_layout()
fig.savefig(os.path.join(os.path.dirname(os.path.abspath(out)), "gr.png"), dpi=80)
