#!/usr/bin/python3
"""Summarise examples/hard-core-yukawa: analyze.py SCRATCHDIR OUT.md "T:rho ..."

MD (in.hcy): per block (each averages every step) T, U/N and the virial
pressure: pair (smooth forces) and fix (impulses of fix hardsphere/cva).
Z = 1 + P_vir / (rho kT) with the target kT (configurational averages;
the measured <T> is reported beside it). MC (mc_hcy.cpp): block means of
U/N, Z_smooth, g(sigma+) and Z. Error bars: one standard error by blocking
(block means coarsened by pairs while >= 16 remain, largest SE kept).
Also writes gr.png (g(r), MD against MC) and eos.png (Z and U/N).
"""
import math, os, re, sys
import numpy as np
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
from blocking import blocking_se    # ../common/blocking.py

scr, out, states = sys.argv[1], sys.argv[2], sys.argv[3].split()
PI = math.pi


def md(tag, T):
    log = open(os.path.join(scr, "log.md." + tag)).read()
    run = dict(zip(*[iter(re.search(r"^RESULT (.*)$", log, re.M).group(1).split())] * 2))
    n = float(run["atoms"]) / float(run["vol"])
    b = np.loadtxt(os.path.join(scr, "blocks." + tag + ".txt"))
    Tb, U, pv, pp, pf = b[:, 1], b[:, 2], b[:, 3], b[:, 4], b[:, 5]
    loop = re.findall(r"Loop time of (\S+) on \d+ procs for (\d+) steps", log)[-1]
    r = dict(N=int(run["atoms"]), rho=n, steps=int(run["steps"]), dt=float(run["dt"]),
             damp=run["damp"], coll=float(run["collisions"]) / int(run["steps"]),
             loop=float(loop[0]), nb=len(Tb))
    for k, v in (("T", Tb), ("U", U), ("Z", 1 + pv / (n * T)), ("Zs", pp / (n * T)),
                 ("Zc", pf / (n * T)), ("gc", pf / (n * T) / (2 * PI / 3 * n))):
        r[k] = (v.mean(), blocking_se(v))
    # g(r): the last (running-average) block of the fix ave/time file
    txt = open(os.path.join(scr, "gr." + tag + ".txt")).read().strip().split("\n")
    nrow = int(txt[3].split()[1])
    g = np.array([[float(x) for x in l.split()] for l in txt[-nrow:]])
    r["gr"] = (g[:, 1], g[:, 2])
    return r


def mc(tag):
    txt = open(os.path.join(scr, "mc." + tag + ".txt")).read()
    head = re.search(r"^# mc_hcy (.*)$", txt, re.M).group(1).split()
    h = dict(zip(head[0::2], head[1::2]))
    v = re.search(r"^RESULT (.*)$", txt, re.M).group(1).split()
    res = {v[i]: (float(v[i + 1]), float(v[i + 2])) for i in range(0, len(v), 3)}
    gr = np.loadtxt(os.path.join(scr, "mcgr." + tag + ".txt"))
    return dict(U=res["U/N"], Zs=res["Z_smooth"], gc=res["g_contact"], Zc=res["Z_contact"],
                Z=res["Z"], sweeps=int(h["sweeps"]), acc=float(h["acceptance"]), gr=(gr[:, 0], gr[:, 1]))


def pm(x, f=4):
    return f"{x[0]:.{f}f} ± {x[1]:.{f}f}"


def dev(a, b):
    return (a[0] - b[0]) / math.hypot(a[1], b[1])


rows, res = [], []
for s in states:
    T, rho = (float(x) for x in s.split(":")[:2])
    tag = f"rho{s.split(':')[1]}_T{s.split(':')[0]}"
    a, m = md(tag, T), mc(tag)
    res.append((T, rho, tag, a, m))

L = []
L.append("# Hard-core Yukawa fluid: MD (fix hardsphere/cva + fix langevin) against NVT Monte Carlo\n")
L.append("Written by `analyze.py` from the runs of `run.sh` (see README.md for the model and methods). "
         "Uncertainties: one standard error (blocking). dev = (MD - MC) / combined standard error.\n")
m0 = open(os.path.join(scr, "machine.txt")).read().strip().replace("\n", "; ")
L.append(f"Machine / settings: {m0}\n")
L.append("## Energy and compressibility factor\n")
L.append("| T* | rho* | MD <T>/T* - 1 | MD U/N | MC U/N | dev | MD Z | MC Z | dev |")
L.append("|---|---|---|---|---|---|---|---|---|")
for T, rho, tag, a, m in res:
    tb = (a["T"][0] / T - 1, a["T"][1] / T)
    L.append(f"| {T} | {rho} | {tb[0]*100:+.2f} ± {tb[1]*100:.2f} % | {pm(a['U'])} | {pm(m['U'])} | "
             f"{dev(a['U'], m['U']):+.1f} | {pm(a['Z'], 3)} | {pm(m['Z'], 3)} | {dev(a['Z'], m['Z']):+.1f} |")
L.append("\n## The two parts of Z, and the contact value\n")
L.append("MD: smooth part from the pair virial, collisional part from the impulse virial of the fix, "
         "g(sigma+) = Z_coll / (2 pi rho sigma^3 / 3). MC: smooth part from the virial of the forces, "
         "g(sigma+) by extrapolating the cavity function to contact (mc_hcy.cpp, contact_value).\n")
L.append("| T* | rho* | MD Z_smooth | MC Z_smooth | dev | MD g(sigma+) | MC g(sigma+) | dev |")
L.append("|---|---|---|---|---|---|---|---|")
for T, rho, tag, a, m in res:
    L.append(f"| {T} | {rho} | {pm(a['Zs'])} | {pm(m['Zs'])} | {dev(a['Zs'], m['Zs']):+.1f} | "
             f"{pm(a['gc'])} | {pm(m['gc'])} | {dev(a['gc'], m['gc']):+.1f} |")
# g = 1 beyond rc: what the full-range potential adds (for literature
# values of the untruncated model), and the delta term at rc that the
# truncated *discontinuous* model's virial pressure would carry (y(rc) = 1)
r = np.linspace(4.0, 60.0, 200001)
uu = -np.exp(-1.8 * (r - 1)) / r
du = np.exp(-1.8 * (r - 1)) * (1.8 * r + 1) / r**2
L.append("\n## Cutoff: tail corrections (g = 1 beyond rc = 4)\n")
L.append("The runs use u truncated at rc = 4 sigma (table above: no tail correction). For the "
         "untruncated model add U_tail/N = 2 pi rho int_rc^inf u r^2 dr and Z_tail = -(2 pi rho / 3kT) "
         "int_rc^inf u'(r) r^3 dr; a truncated, unshifted model sampled with the discontinuous weight "
         "exp(-U_trunc/kT) (not what MD samples, see README) would add the delta term at rc, "
         "Z_rc = (2 pi rho rc^3 / 3) y(rc) [1 - exp(-u(rc)/kT)] with y(rc) = 1.\n")
L.append("| T* | rho* | U_tail/N | Z_tail | Z_rc |")
L.append("|---|---|---|---|---|")
for T, rho, tag, a, m in res:
    ut = 2 * PI * rho * np.trapz(uu * r**2, r)
    zt = -2 * PI * rho / (3 * T) * np.trapz(du * r**3, r)
    zrc = 2 * PI * rho * 4.0**3 / 3 * (1 - math.exp(-uu[0] / T))
    L.append(f"| {T} | {rho} | {ut:.4f} | {zt:.4f} | {zrc:.4f} |")
L.append("\n## Run lengths\n")
L.append("| T* | rho* | N | MD steps (dt) | collisions / step | MD loop time (s) | MC sweeps | MC acceptance |")
L.append("|---|---|---|---|---|---|---|---|")
for T, rho, tag, a, m in res:
    L.append(f"| {T} | {rho} | {a['N']} | {a['steps']} ({a['dt']}) | {a['coll']:.1f} | {a['loop']:.0f} | "
             f"{m['sweeps']} | {m['acc']:.2f} |")
open(out, "w").write("\n".join(L) + "\n")
print("\n".join(L))

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    sys.exit(0)
outdir = os.path.dirname(os.path.abspath(out))
fig, ax = plt.subplots(1, len(res), figsize=(4 * len(res), 3.2), sharey=True, squeeze=False)
ax = ax[0]
for k, (T, rho, tag, a, m) in enumerate(res):
    ax[k].plot(*m["gr"], "k-", lw=1.2, label="MC")
    ax[k].plot(*a["gr"], "r--", lw=1, label="MD (cva)")
    ax[k].set_xlim(0.8, 4)
    ax[k].set_title(f"T* = {T}, rho* = {rho}")
    ax[k].set_xlabel("r / sigma")
ax[0].set_ylabel("g(r)")
ax[0].legend()
fig.tight_layout()
fig.savefig(os.path.join(outdir, "gr.png"), dpi=80)

fig, ax = plt.subplots(1, 2, figsize=(8, 3.2))
for key, k, lab in (("Z", 0, "Z = P / (rho kT)"), ("U", 1, "U / (N eps)")):
    for T, rho, tag, a, m in res:
        c = "C0" if T == 1.5 else "C3"
        ax[k].errorbar(rho - 0.005, a[key][0], yerr=a[key][1], fmt="o", color=c, mfc="none")
        ax[k].errorbar(rho + 0.005, m[key][0], yerr=m[key][1], fmt="s", color=c)
    ax[k].set_xlabel("rho sigma^3")
    ax[k].set_ylabel(lab)
ax[0].plot([], [], "ko", mfc="none", label="MD")
ax[0].plot([], [], "ks", label="MC")
ax[0].plot([], [], "C0-", label="T* = 1.5")
ax[0].plot([], [], "C3-", label="T* = 2.0")
ax[0].legend(fontsize=8)
fig.tight_layout()
fig.savefig(os.path.join(outdir, "eos.png"), dpi=80)
