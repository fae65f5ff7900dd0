#!/usr/bin/python3
"""Summarise examples/hard-spheres runs: analyze.py SCRATCHDIR OUT.md

Theory (independent of the simulation):
  Carnahan-Starling  Z = (1 + eta + eta^2 - eta^3) / (1 - eta)^3
  contact value      g(sigma) = (1 - eta/2) / (1 - eta)^3   (CS)
  Enskog rate        Gamma = 4 sigma^2 n g(sigma) sqrt(pi kT / m)  (per particle)
Error bars: block averages of the per-block means (each block averages every
step), coarsened by pairs while at least 16 blocks are left; the largest
standard error over the levels is quoted (Flyvbjerg-Petersen blocking).
"""
import glob, math, os, re, statistics, sys
import numpy as np
from scipy.integrate import quad
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
from blocking import blocking_se    # ../common/blocking.py

scr, out = sys.argv[1], sys.argv[2]
PI = math.pi


def z_cs(eta):
    return (1 + eta + eta**2 - eta**3) / (1 - eta)**3


def g_cs(eta):
    return (1 - eta / 2) / (1 - eta)**3


# Kolafa's correction of CS (Boublik & Nezbeda 1986): virial coefficients B4, B5 = 18.33, 28.33
# against the exact 18.365, 28.224 (CS: 18, 28); g(sigma) = (Z - 1) / (4 eta)
def z_csk(eta):
    return (1 + eta + eta**2 - 2 / 3 * (eta**3 + eta**4)) / (1 - eta)**3


def parse(path):
    txt = open(path).read()
    run = dict(zip(*[iter(re.search(r"^RUN (.*)$", txt, re.M).group(1).split())] * 2))
    # fix print also prints at step 0, before any block average exists
    blk = np.array([[float(v) for v in l.split()[1:]] for l in re.findall(r"^BLK \d.*$", txt, re.M)])
    blk = blk[blk[:, 0] > 0]
    c0 = float(re.search(r"^BLK0 (\S+)", txt, re.M).group(1))
    loop = re.findall(r"Loop time of (\S+) on \d+ procs for (\d+) steps", txt)[-1]
    cpu = float(re.findall(r"([\d.]+)% CPU use", txt)[-1])
    builds = int(re.findall(r"Neighbor list builds = (\d+)", txt)[-1])
    natoms, vol, dt = int(run["atoms"]), float(run["vol"]), float(run["dt"])
    steps, bsteps = int(run["steps"]), int(run["blocksteps"])
    n = natoms / vol
    P, T, C = blk[:, 1], blk[:, 2], blk[:, 3]
    Z = P / (n * T)
    tb = bsteps * dt
    rate = 2 * np.diff(np.concatenate([[c0], C])) / (natoms * tb)
    half = len(Z) // 2
    drift = (Z[half:].mean() - Z[:half].mean()) / math.hypot(blocking_se(Z[:half], 8),
                                                             blocking_se(Z[half:], 8))
    wall, cpu_s = float(loop[0]), float(loop[0]) * cpu / 100
    Zh = (Z[:half].mean(), blocking_se(Z[:half], 8), Z[half:].mean(), blocking_se(Z[half:], 8))
    return dict(Zh=Zh, N=natoms, n=n, dt=dt, steps=steps, time=steps * dt, T=T.mean(), Tse=blocking_se(T),
                Z=Z.mean(), Zse=blocking_se(Z), G=rate.mean(), Gse=blocking_se(rate), drift=drift,
                coll=C[-1] - c0, wall=wall, cpu=cpu, cpu_s=cpu_s, builds=builds,
                thr=natoms * steps * dt / cpu_s)


def order(path):
    try:
        return float(re.search(r"^ORDER Q6 (\S+)", open(path).read(), re.M).group(1))
    except (OSError, AttributeError):
        return float("nan")


# Barker-Henderson diameter of the pseudo-hard-sphere potential at kT/eps = 1.5
def u_mie(r, eps=1 / 1.5):
    return 50 * (50 / 49)**49 * eps * (r**-50 - r**-49) + eps


rc = 50 / 49
d_bh = quad(lambda r: 1 - math.exp(-u_mie(r)), 0.5, rc, points=[1.0])[0] + 0.5

rows = []
for d in sorted(glob.glob(f"{scr}/eta*"), key=lambda p: float(p.split("eta")[-1])):
    eta = float(d.split("eta")[-1])
    r = {"eta": eta}
    for m in ("psa", "cva", "mie"):
        p = f"{d}/log.{m}"
        if os.path.exists(p) and "RUN model" in open(p).read():
            r[m] = parse(p)
    r["q6start"], r["q6equil"] = order(f"{d}/log.order.start"), order(f"{d}/log.order.equil")
    r["q6end"] = order(f"{d}/log.order.psa")
    rows.append(r)

mach = open(f"{scr}/machine.txt").read().strip().splitlines()
L = ["# Pure hard spheres: measured results", "",
     "Command: `bash examples/hard-spheres/run.sh` (inputs `in.prepare`, `in.hs`, `in.order`, analysis "
     "`analyze.py`, all in `examples/hard-spheres/`).", ""]
L += [f"- {l}" for l in mach] + [""]
L += ["## Pressure against Carnahan-Starling, collision rate against Enskog", "",
      "Z = P / (n kT) with P the pressure averaged over every step (kinetic part plus the impulse virial) "
      "and kT the measured temperature; Gamma = 2 x (sphere-sphere collisions) / (N x time). "
      "Theory: Z_CS = (1+eta+eta^2-eta^3)/(1-eta)^3; Gamma_E = 4 sigma^2 n g(sigma) sqrt(pi kT/m), "
      "g(sigma) = (1-eta/2)/(1-eta)^3. Uncertainties are one standard error (blocking analysis). "
      "dev = (simulation - theory) / theory.", "",
      "| eta | n | Z_CS | Z psa | dev | Z cva | dev | psa - cva (sigma) | Gamma_E | Gamma psa | dev | "
      "Gamma cva | dev | psa - cva (sigma) | Gamma / Gamma(Z) psa | collisions psa / cva |",
      "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]


def pm(v, e, f=4):
    return f"{v:.{f}f} ± {e:.{f}f}"


def dev(v, th):
    return f"{100 * (v - th) / th:+.2f} %"


summary = {}
for r in rows:
    eta = r["eta"]
    a, c = r.get("psa"), r.get("cva")
    if not a:
        continue
    n = a["n"]
    zc = z_cs(eta)
    ge = 4 * n * g_cs(eta) * math.sqrt(PI * 1.0)    # sigma = m = 1, kT from the run below
    ge_a = ge * math.sqrt(a["T"])
    cells = [f"{eta:.2f}", f"{n:.5f}", f"{zc:.4f}", pm(a["Z"], a["Zse"]), dev(a["Z"], zc)]
    if c:
        cells += [pm(c["Z"], c["Zse"]), dev(c["Z"], zc),
                  f"{(a['Z'] - c['Z']) / math.hypot(a['Zse'], c['Zse']):+.1f}"]
    else:
        cells += ["", "", ""]
    cells += [f"{ge_a:.4f}", pm(a["G"], a["Gse"]), dev(a["G"], ge_a)]
    # exact in equilibrium, free of CS: Z - 1 = (2 pi / 3) n sigma^3 g(sigma) and the Enskog rate
    # give Gamma = 6 (Z - 1) sqrt(kT/m) / (sqrt(pi) sigma): pressure (impulse virial) and
    # collision counter of the same run must agree
    gz = 6 * (a["Z"] - 1) * math.sqrt(a["T"]) / math.sqrt(PI)
    cons = f"{a['G'] / gz:.4f} ± {math.hypot(a['Gse'] / a['G'], a['Zse'] / (a['Z'] - 1)) * a['G'] / gz:.4f}"
    if c:
        ge_c = ge * math.sqrt(c["T"])
        cells += [pm(c["G"], c["Gse"]), dev(c["G"], ge_c),
                  f"{(a['G'] - c['G']) / math.hypot(a['Gse'], c['Gse']):+.1f}", cons,
                  f"{a['coll']:.0f} / {c['coll']:.0f}"]
    else:
        cells += ["", "", "", cons, f"{a['coll']:.0f}"]
    L.append("| " + " | ".join(cells) + " |")

L += ["", "The same psa results against Kolafa's more accurate correction of CS (Boublik & Nezbeda 1986), "
      "Z_CSK = (1+eta+eta^2-(2/3)(eta^3+eta^4))/(1-eta)^3 (virial coefficients B4, B5 = 18.33, 28.33; "
      "exact 18.365, 28.224; CS gives 18, 28), with the Enskog rate from its contact value "
      "g_CSK = (Z_CSK - 1)/(4 eta):", "",
      "| eta | Z_CSK | Z_CSK / Z_CS - 1 | Z psa | dev vs CSK (sigma) | Gamma_E(CSK) | Gamma psa | dev vs CSK (sigma) |",
      "|---|---|---|---|---|---|---|---|"]
for r in rows:
    a = r.get("psa")
    if not a:
        continue
    eta, zk = r["eta"], z_csk(r["eta"])
    gk = 4 * a["n"] * (zk - 1) / (4 * eta) * math.sqrt(PI * a["T"])
    L.append(f"| {eta:.2f} | {zk:.4f} | {100 * (zk / z_cs(eta) - 1):+.2f} % | {pm(a['Z'], a['Zse'])} | "
             f"{dev(a['Z'], zk)} ({(a['Z'] - zk) / a['Zse']:+.1f}) | {gk:.4f} | {pm(a['G'], a['Gse'])} | "
             f"{dev(a['G'], gk)} ({(a['G'] - gk) / a['Gse']:+.1f}) |")

L += ["", "## Did the fluid stay a fluid?", "",
      "Start: random insertion of N spheres at the final density, overlaps removed by minimizing a soft "
      "repulsion of range 1.001 (`in.prepare`; no lattice is ever made), then a psa equilibration run. "
      f"Q6 = mean Steinhardt bond order (12 nearest neighbours, `in.order`): {order(f'{scr}/log.order.fcc'):.3f} "
      "for a perfect fcc crystal (`in.order -var fcc 1`), about 0.3 in a disordered state. Drift = (mean Z of the second half of the production run - mean of the "
      "first half) / its standard error: |drift| < 3 means no detectable trend.", "",
      "| eta | Q6 start | Q6 after equilibration | Q6 after production | Z psa 1st half | Z psa 2nd half | "
      "drift psa | drift cva | drift mie | <T> psa | <T> mie |",
      "|---|---|---|---|---|---|---|---|---|---|---|"]
for r in rows:
    a, c, m = r.get("psa"), r.get("cva"), r.get("mie")
    f = lambda x, k: f"{x[k]:+.1f}" if x else ""
    L.append(f"| {r['eta']:.2f} | {r['q6start']:.3f} | {r['q6equil']:.3f} | {r['q6end']:.3f} | "
             f"{pm(a['Zh'][0], a['Zh'][1])} | {pm(a['Zh'][2], a['Zh'][3])} | {f(a, 'drift')} | {f(c, 'drift')} | "
             f"{f(m, 'drift')} | {a['T']:.6f} | " + (f"{m['T']:.4f} ± {m['Tse']:.4f}" if m else "") + " |")

L += ["", "## Pseudo hard spheres (pair mie/cut 50 49, fix nve, dt 0.001) against Carnahan-Starling", "",
      f"Jover et al. 2012: u(r) = 50 (50/49)^49 eps [(sigma/r)^50 - (sigma/r)^49] + eps for "
      f"r < (50/49) sigma, at kT/eps = 1.5 (here kT = 1, eps = 2/3, so the thermal speeds and time units "
      f"are those of the hard-sphere runs). Its Barker-Henderson diameter d_BH = int_0^rc "
      f"[1 - exp(-u/kT)] dr = {d_bh:.4f} sigma (computed in `analyze.py`); eta_BH = eta d_BH^3. "
      "Z = P / (n <T>) with sigma = 1 in n.", "",
      "| eta | Z_CS(eta) | Z mie | dev vs Z_CS(eta) | Z_CS(eta_BH) | dev vs Z_CS(eta_BH) | Z psa | mie - psa |",
      "|---|---|---|---|---|---|---|---|"]
for r in rows:
    m, a = r.get("mie"), r.get("psa")
    if not m:
        continue
    eta = r["eta"]
    zb = z_cs(eta * d_bh**3) * d_bh**0    # Z depends on eta only
    L.append(f"| {eta:.2f} | {z_cs(eta):.4f} | {pm(m['Z'], m['Zse'])} | {dev(m['Z'], z_cs(eta))} | {zb:.4f} | "
             f"{dev(m['Z'], zb)} | {pm(a['Z'], a['Zse'])} | {dev(m['Z'], a['Z'])} |")

L += ["", "## Throughput (particle-time-units per CPU second)", "",
      "Throughput = N x (simulated time of the production run) / (CPU seconds of that run = LAMMPS "
      "'Loop time' x '% CPU use'). All three runs of a row are consecutive in the same run of run.sh "
      "(psa, mie, cva), on the same N and density. Hard spheres: dt 0.02, neighbor skin 0.5 (psa is exact "
      "for any dt, the skin bounds it); mie: dt 0.001, skin 0.3 (LAMMPS' default for lj units).", "",
      "| eta | N | psa | mie/cut 50 49 + nve | cva | psa / mie | mie / cva | psa collisions per CPU s | "
      "cva collisions per CPU s | % CPU use psa / mie / cva |",
      "|---|---|---|---|---|---|---|---|---|---|"]
ratios = []
for r in rows:
    a, c, m = r.get("psa"), r.get("cva"), r.get("mie")
    if not (a and m):
        continue
    ratios.append(a["thr"] / m["thr"])
    L.append(f"| {r['eta']:.2f} | {a['N']} | {a['thr']:,.0f} | {m['thr']:,.0f} | "
             + (f"{c['thr']:,.0f}" if c else "") + f" | {a['thr'] / m['thr']:.2f} | "
             + (f"{m['thr'] / c['thr']:.0f}" if c else "") + f" | {a['coll'] / a['cpu_s']:,.0f} | "
             + (f"{c['coll'] / c['cpu_s']:,.0f}" if c else "") + f" | {a['cpu']:.0f} / {m['cpu']:.0f} / "
             + (f"{c['cpu']:.0f}" if c else "") + " |")
if ratios:
    L += ["", f"psa / mie throughput: median {statistics.median(ratios):.2f} over the packing fractions "
          f"(from {min(ratios):.2f} to {max(ratios):.2f})."]
open(out, "w").write("\n".join(L) + "\n")
print("\n".join(L))
