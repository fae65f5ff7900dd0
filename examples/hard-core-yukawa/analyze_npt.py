#!/usr/bin/python3
"""Summarise the NPT runs of run_npt.sh: analyze_npt.py SCRATCHDIR OUT.md "T:rho:P:dP ..."
(environment NPT_SKIP=m: leave out the first m finished parts as equilibration)

Per block (each averages every step): T, shifted U/N, V, N/V. The mean
density with one standard error by blocking (as analyze.py). The NVT
pressure P carries its own error dP; it moves the density the NPT run
should find by dP / (dP/drho)_T, with (dP/drho)_T = kT <V> / (rho <dV^2>)
from this run's volume fluctuations (<dV^2> = kT V kappa_T). dev =
(<N/V> - rho) / sqrt(se^2 + (dP / (dP/drho))^2).
"""
import math, os, re, sys
import numpy as np
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
from blocking import blocking_se    # ../common/blocking.py

scr, out, states = sys.argv[1], sys.argv[2], sys.argv[3].split()


def tau_int(x):
    """Integrated autocorrelation time in samples (Sokal's window: the first
    W >= 5 tau(W)); None if the run is too short for the window to close."""
    x = np.asarray(x, float) - np.mean(x)
    n = len(x)
    f = np.fft.rfft(x, 2 * n)
    acf = np.fft.irfft(f * np.conj(f))[:n] / (x.var() * np.arange(n, 0, -1))
    tau = 0.5
    for w in range(1, n // 2):
        tau += acf[w]
        if w >= 5 * tau:
            return tau
    return None


rows = []
for s in states:
    f = s.split(":")    # T:rho:P:dP[:ref]: rho the start's density (tag), ref the NVT one (default rho)
    T, rho0, P, dP = (float(x) for x in f[:4])
    rho = float(f[4]) if len(f) > 4 else rho0
    tag = f"rho{f[1]}_T{f[0]}"
    parts = []    # run_npt.sh PARTS=n: the finished parts 1, 2, ... (in.hcy.npt -var part k)
    k = 1
    while os.path.exists(os.path.join(scr, f"log.npt.{tag}.{k}")):
        lg = open(os.path.join(scr, f"log.npt.{tag}.{k}")).read()
        mk = re.search(r"^RESULT (.*)$", lg, re.M)
        if not mk:
            break
        parts.append((k, dict(zip(*[iter(mk.group(1).split())] * 2))))
        k += 1
    # NPT_SKIP=m: the first m finished parts are more equilibration (the density
    # still drifting from the fcc start's), left out of every average below
    skip = int(os.environ.get("NPT_SKIP", "0"))
    nskip = len(parts[:skip])
    parts = parts[skip:]
    if parts:
        b = np.concatenate([np.loadtxt(os.path.join(scr, f"blocks.npt.{tag}.{k}.txt"), ndmin=2) for k, _ in parts])
        vs = np.concatenate([np.loadtxt(os.path.join(scr, f"vol.npt.{tag}.{k}.txt"))[:, 1] for k, _ in parts])
        run = dict(parts[-1][1])
        for key in ("steps", "attempts", "accepted"):
            run[key] = str(sum(int(float(p[key])) for _, p in parts))
        run["steps"] += f" ({len(parts)} parts" + (f", after {nskip} left out)" if nskip else ")")
    else:
        log = open(os.path.join(scr, "log.npt." + tag)).read()
        m = re.search(r"^RESULT (.*)$", log, re.M)
        b = np.loadtxt(os.path.join(scr, "blocks.npt." + tag + ".txt"))
        vs = np.loadtxt(os.path.join(scr, "vol.npt." + tag + ".txt"))[:, 1]
        if m:
            run = dict(zip(*[iter(m.group(1).split())] * 2))
        else:    # a run stopped early: its finished blocks are still samples; say so
            th = re.findall(r"^\s+\d+\s+\S+\s+\S+\s+\S+\s+\S+\s+(\d+)\s+(\S+)\s+(\S+)\s*$", log, re.M)
            run = dict(attempts="-", accepted="-", delta=th[-1][2] if th else "nan",
                       steps=f"{int(b[-1, 0]) - int(b[0, 0]) + int(b[1, 0] - b[0, 0])} (stopped)")
    Tb, U, V, n = b[:, 1], b[:, 2], b[:, 3], b[:, 4]
    # <dV^2> from the volume every 10 steps (block means would smooth it): vs above
    dPdrho = T * vs.mean() / (rho * vs.var())
    # the volume walks slowly: an error bar from the integrated
    # autocorrelation time of the volume series too, the larger one is used
    tv = tau_int(vs)
    se_tau = (vs.std() * math.sqrt(2 * tv / len(vs)) / vs.mean() * n.mean()) if tv else float("inf")
    se = max(blocking_se(n), se_tau)
    # the block averages' own statement of independence: blocks of L steps
    # (the coarsest blocking level that keeps >= 16 blocks) against tau_int
    bstep = int(round(b[1, 0] - b[0, 0])) if len(b) > 1 else 0
    nlev = len(n)
    while nlev // 2 >= 16:
        nlev //= 2
    blen = bstep * (len(n) // nlev)
    se_blk = blocking_se(n)
    shift = dP / dPdrho
    dev = (n.mean() - rho) / math.hypot(se, shift) if math.isfinite(se) else float("nan")
    rows.append((T, rho, P, dP, n.mean(), se, (10 * tv if tv else None), dPdrho, shift, dev, Tb.mean(), blocking_se(Tb),
                 run["attempts"], run["accepted"], float(run["delta"]), run["steps"], len(n),
                 blen, se_blk, se_tau, rho0))

L = ["# Hard-core Yukawa fluid in NPT (fix hardsphere/press) at the NVT pressures\n",
     "Written by `analyze_npt.py` from the runs of `run_npt.sh` (README.md, \"NPT\"). "
     "P = Z rho T with Z from the NVT MD of results.md; dP its standard error. "
     "Uncertainties: one standard error, the larger of blocking and of the volume's integrated "
     "autocorrelation time (Sokal window; 'None': the run is too short for the window to close, "
     "error bar infinite). (dP/drho)_T from the NPT run's volume "
     "fluctuations; rho shift = dP / (dP/drho), the density error that the NVT pressure's "
     "error carries; dev = (<N/V> - rho) / sqrt(se^2 + shift^2).\n",
     "| T* | rho* (NVT) | start | P | <N/V> (NPT) | <N/V>/rho - 1 | volume tau_int (steps) | (dP/drho)_T | rho shift from dP | dev | <T>/T* - 1 | volume moves (accepted) | d | steps (blocks) |",
     "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
for (T, rho, P, dP, nm, se, tv, dpr, sh, dev, Tm, Tse, att, acc, d, st, nb, *_, rho0) in rows:
    devs = "-" if dev != dev else f"{dev:+.1f}"
    L.append(f"| {T} | {rho} | fcc {rho0} | {P:.4f} ± {dP:.4f} | {nm:.4f} ± {se:.4f} | {100*(nm/rho-1):+.2f} ± {100*se/rho:.2f} % "
             f"| {tv if tv is None else round(tv)} | {dpr:.2f} | ± {sh:.4f} | {devs} | {100*(Tm/T-1):+.2f} ± {100*Tse/T:.2f} % | {att} ({acc}) | {d:.4g} | {st} ({nb}) |")
L += ["\n## Are the blocks independent?\n",
      "The error of <N/V> two ways: blocking of the block means (Flyvbjerg-Petersen, coarsened "
      "while >= 16 blocks remain; the largest standard error kept), and sigma sqrt(2 tau_int / n) "
      "from the volume series (every 10 steps). Blocks are independent when they are several "
      "tau_int long: the coarsest blocks below, in units of tau_int, say how far that holds; "
      "when both errors agree the plateau is reached.\n",
      "| T* | rho* | start | coarsest block (steps) | in tau_int | se (blocking) | se (tau_int) |",
      "|---|---|---|---|---|---|---|"]
for (T, rho, P, dP, nm, se, tv, dpr, sh, dev, Tm, Tse, att, acc, d, st, nb, blen, se_blk, se_tau, rho0) in rows:
    ratio = f"{blen / tv:.1f}" if tv else "-"
    L.append(f"| {T} | {rho} | fcc {rho0} | {blen} | {ratio} | {se_blk:.4f} | {se_tau:.4f} |")
# independent runs (other starts or seeds) of one state: their means' scatter
# is an error bar that does not depend on estimating tau_int within a run
groups = {}
for r in rows:
    groups.setdefault((r[0], r[1], r[2]), []).append(r)
if any(len(g) > 1 for g in groups.values()):
    L += ["\n## Independent runs of one state\n",
          "Runs from different starts are independent samples of <N/V>: their mean, and its standard "
          "error from the scatter of the run means (n - 1 degrees of freedom; no within-run "
          "correlation time needed). dev as above, with this error.\n",
          "| T* | rho* (NVT) | P | runs | run means | mean | <N/V>/rho - 1 | scatter of run means (sd) | dev |",
          "|---|---|---|---|---|---|---|---|---|"]
    for (T, rho, P), g in groups.items():
        if len(g) < 2:
            continue
        m = np.array([r[4] for r in g])
        se = m.std(ddof=1) / math.sqrt(len(m))
        sh = max(r[8] for r in g)
        L.append(f"| {T} | {rho} | {P:.4f} | {len(m)} | {', '.join(f'{x:.4f}' for x in m)} | {m.mean():.4f} ± {se:.4f} | "
                 f"{100*(m.mean()/rho-1):+.2f} ± {100*se/rho:.2f} % | {m.std(ddof=1):.4f} | {(m.mean()-rho)/math.hypot(se, sh):+.1f} |")
open(out, "w").write("\n".join(L) + "\n")
print("\n".join(L))
