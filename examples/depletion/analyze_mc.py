#!/usr/bin/python3
"""MD against the NVT Monte Carlo of mc_ao.cpp, and both against the virial
series with B4 from mayer_b4.cpp:  analyze_mc.py SCRATCHDIR OUT.md "q:rho[:seedtag] ..."

SCRATCHDIR/md: in.ao runs (log.<tag>, blocks.<tag>.txt, gr.<tag>.txt; tag
q<q>_rho<rho>[_s<seed>]); SCRATCHDIR/mc: mc.q<q>_rho<rho>.txt (+ gr file);
SCRATCHDIR/b4: b4_q<q>.txt. MD Z = 1 + P_vir/(rho kT), its collisional
part from the fix's virial, g(sigma+) = Z_coll / (2 pi rho / 3); MC Z =
1 + Z_smooth + (2 pi rho / 3) g(sigma+) (contact extrapolation). Error bars:
one standard error, blocking (as analyze.py). dev = difference / combined
standard error. Also writes gr_mc.png (g(r), MD against MC).
"""
import math, os, re, sys
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import virial
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
from blocking import blocking_se    # ../common/blocking.py

scr, out, states = sys.argv[1], sys.argv[2], sys.argv[3].split()
PI = math.pi


def md(tag):
    """kT: the target (1) with the thermostat; for a run with fix langevin only
    in equilibration (log says nve yes) the measured mean temperature."""
    d = os.path.join(scr, "md")
    log = open(os.path.join(d, "log." + tag)).read()
    run = dict(zip(*[iter(re.search(r"^RESULT (.*)$", log, re.M).group(1).split())] * 2))
    n = float(run["atoms"]) / float(run["vol"])
    b = np.loadtxt(os.path.join(d, "blocks." + tag + ".txt"))
    T, U, pv, pf = b[:, 1], b[:, 2], b[:, 3], b[:, 4]
    nve = re.search(r"^\s*unfix th\s*$", log, re.M)    # in.ao with -var nve yes
    kT = T.mean() if nve else 1.0
    r = dict(rho=n, N=int(run["atoms"]), steps=int(run["steps"]), dt=float(run["dt"]), kT=kT, nve=bool(nve),
             coll=float(run["collisions"]) / int(run["steps"]))
    for k, v in (("T", T), ("U", U), ("Z", 1 + pv / (n * kT)), ("Zs", (pv - pf) / (n * kT)),
                 ("gc", pf / (n * kT) / (2 * PI / 3 * n))):
        r[k] = (v.mean(), blocking_se(v))
    txt = open(os.path.join(d, "gr." + tag + ".txt")).read().strip().split("\n")
    nrow = int(txt[3].split()[1])
    g = np.array([[float(x) for x in l.split()] for l in txt[-nrow:]])
    r["gr"] = (g[:, 1], g[:, 2])
    return r


def mc(tag):
    d = os.path.join(scr, "mc")
    txt = open(os.path.join(d, "mc." + tag + ".txt")).read()
    if not re.search(r"^RESULT", txt, re.M):
        return None    # still running
    head = re.search(r"^# mc_ao (.*)$", txt, re.M).group(1).split()
    h = dict(zip(head[0::2], head[1::2]))
    v = re.search(r"^RESULT (.*)$", txt, re.M).group(1).split()
    res = {v[i]: (float(v[i + 1]), float(v[i + 2])) for i in range(0, len(v), 3)}
    r = dict(U=res["U/N"], Zs=res["Z_smooth"], gc=res["g_contact"], Z=res["Z"], sweeps=int(h["sweeps"]),
             acc=float(h["acceptance"]), N=int(h["N"]))
    gf = os.path.join(d, "gr." + tag + ".txt")
    if os.path.exists(gf):
        g = np.loadtxt(gf)
        r["gr"] = (g[:, 0], g[:, 1])
    return r


def b4(q):
    f = os.path.join(scr, "b4", f"b4_q{q}.txt")
    m = re.search(r"^RESULT (.*)$", open(f).read(), re.M) if os.path.exists(f) else None
    if not m:
        return None
    v = m.group(1).split()
    return float(v[v.index("B4") + 1]), float(v[v.index("B4") + 2]), float(v[v.index("B3") + 1]), float(v[v.index("B3") + 2])


def theory(q, n, kT):
    """1 + B2 rho + B3 rho^2 and U/N to O(rho^2) (as analyze.py) at kT (u = depth 3 kT at kT = 1)."""
    B2, B3, y1 = virial.coefficients(q, depth=3.0 / kT)
    R = 1.0 + q
    rr = np.linspace(1.0, R, 2001)
    y1i = np.interp(rr, rr[::40], np.array([y1(x) for x in rr[::40]]))
    ur = virial.u(rr, q)    # in units of the kT = 1 energy
    Ut = 0.5 * n * np.trapz(4 * PI * rr**2 * ur * np.exp(-ur / kT) * (1 + n * y1i), rr)
    return 1 + B2 * n + B3 * n * n, Ut


def dev(a, b):
    return (a[0] - b[0]) / math.hypot(a[1], b[1])


L = ["# Depletion colloids: MD against Monte Carlo (mc_ao.cpp) and the virial series with B4\n",
     "Written by `analyze_mc.py` (README.md, \"Monte Carlo reference\"). Uncertainties: one standard error "
     "(blocking). dev = (MD - MC) / combined standard error.\n"]
coef, rows = {}, []
for s in states:
    qs, rs, *extra = s.split(":")
    q, rho = float(qs), float(rs)
    if q not in coef:
        coef[q] = virial.coefficients(q)[:2] + (b4(qs),)
    mdtag = f"q{qs}_rho{rs}" + (extra[0] if extra else "")
    rows.append((q, rho, mdtag, md(mdtag) if os.path.exists(os.path.join(scr, "md", "log." + mdtag)) else None,
                 mc(f"q{qs}_rho{rs}") if os.path.exists(os.path.join(scr, "mc", f"mc.q{qs}_rho{rs}.txt")) else None))

L.append("## Virial coefficients\n")
L.append("B2, B3 by quadrature (virial.py); B3 and B4 by Mayer-sampling Monte Carlo (mayer_b4.cpp).\n")
L.append("| q | B2 | B3 (quadrature) | B3 (mayer_b4) | B4 (mayer_b4) |")
L.append("|---|---|---|---|---|")
for q, (B2, B3, m) in coef.items():
    L.append(f"| {q} | {B2:.5f} | {B3:.5f} | " + (f"{m[2]:.4f} ± {m[3]:.4f} | {m[0]:.3f} ± {m[1]:.3f} |" if m else "- | - |"))

L.append("\n## Compressibility factor and energy\n")
L.append("Z = P/(rho kT) with kT the target (1) for the thermostatted runs and the measured <T> for the "
         "NVE run (`-var nve yes`: fix langevin in equilibration only); the series and U/N to O(rho^2) "
         "are taken at that kT (B4 at kT = 1). Series columns only at rho <= 0.1.\n")
L.append("| q | rho | run | N | length | <T> | kT used | Z | Z_smooth | g(sigma+) | U/N | series U/N | 1 + B2 rho + B3 rho^2 | + B4 rho^3 |")
L.append("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
mc_done = set()
for q, rho, tag, a, c in rows:
    m = coef[q][2]
    for who, r in (("MD " + tag, a), ("MC", c)):
        if not r or (who == "MC" and (q, rho) in mc_done):
            continue
        if who == "MC":
            mc_done.add((q, rho))
        kT = r.get("kT", 1.0)
        if rho <= 0.1:
            z3, Ut = theory(q, rho, kT)
            ser = f"{Ut:.4f} | {z3:.5f} | " + (f"{z3 + m[0] * rho**3:.5f} ± {m[1] * rho**3:.5f} |" if m else "- |")
        else:
            ser = "- | - | - |"
        if who == "MC":
            length, Ts = f"{r['sweeps']} sweeps (acc. {r['acc']:.2f})", "-"
        else:
            length, Ts = f"{r['steps']} steps, dt {r['dt']}", f"{r['T'][0]:.4f} ± {r['T'][1]:.4f}"
        L.append(f"| {q} | {rho} | {who} | {r['N']} | {length} | {Ts} | {kT:.4f} | {r['Z'][0]:.5f} ± {r['Z'][1]:.5f} | "
                 f"{r['Zs'][0]:.4f} ± {r['Zs'][1]:.4f} | {r['gc'][0]:.4f} ± {r['gc'][1]:.4f} | "
                 f"{r['U'][0]:.4f} ± {r['U'][1]:.4f} | " + ser)
L.append("\nMD against MC (both at kT = 1; the NVE run is at another temperature and left out):\n")
L.append("| q | rho | MD run | dev Z | dev Z_smooth | dev g(sigma+) | dev U/N |")
L.append("|---|---|---|---|---|---|---|")
for q, rho, tag, a, c in rows:
    if a and c and not a["nve"]:
        L.append(f"| {q} | {rho} | {tag} | {dev(a['Z'], c['Z']):+.1f} | {dev(a['Zs'], c['Zs']):+.1f} | "
                 f"{dev(a['gc'], c['gc']):+.1f} | {dev(a['U'], c['U']):+.1f} |")
open(out, "w").write("\n".join(L) + "\n")
print("\n".join(L))

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    sys.exit(0)
pl = [(q, rho, a, c) for q, rho, tag, a, c in rows if a and c and "gr" in c]
if pl:
    fig, ax = plt.subplots(1, len(pl), figsize=(4.2 * len(pl), 3.2))
    ax = np.atleast_1d(ax)
    for k, (q, rho, a, c) in enumerate(pl):
        ax[k].plot(*a["gr"], "r-", lw=1, label="MD (cva + langevin)")
        ax[k].plot(*c["gr"], "k.", ms=2, label="MC (mc_ao)")
        ax[k].set_xlim(0.95, 1.5)
        ax[k].set_title(f"q = {q}, rho sigma^3 = {rho}", fontsize=9)
        ax[k].set_xlabel("r / sigma")
    ax[0].set_ylabel("g(r)")
    ax[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(os.path.dirname(os.path.abspath(out)), "gr_mc.png"), dpi=80)
