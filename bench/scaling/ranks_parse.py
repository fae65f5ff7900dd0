#!/usr/bin/python3
"""bench/scaling: ranks_parse.py OUT.md LOGDIR -- the table of ranks.sh.
Logs are LOGDIR/log.<N>.<repeat>.<nve|cva>.<ranks>. Ratios are taken within
one repeat (the four runs of a repeat are consecutive), then median and
spread (min..max) over the repeats. The "fastest repeats" columns divide the
fastest of each contender's repeats: on a shared host another job can only
add time to a run, and a 2-rank run, which needs both cores, takes more of
it than a 1-rank one, so the minimum is the estimate of the undisturbed time
(reported beside the medians, not instead of them)."""
import glob, os, re, sys, datetime
import numpy as np

out, logdir = sys.argv[1:3]
R = {}
WARM = set()    # untimed steps before the timed run (ranks.sh WARMUP), as the logs show
NEWTON = set()    # LAMMPS' newton setting of the runs (ranks.sh NEWTON)
for p in glob.glob(os.path.join(logdir, "log.*")):
    _, N, k, c, np_ = os.path.basename(p).split(".")
    txt = open(p).read()
    m = re.findall(r"Loop time of (\S+) on (\d+) procs for (\d+) steps", txt)
    if not m:
        continue
    t, _, n = m[-1]
    WARM.add(int(m[0][2]) if len(m) > 1 else 0)
    NEWTON.update(re.findall(r"^newton\s+(on|off)", txt, re.M) or ["on"])
    b = re.search(r"^BENCH collisions (\S+)", txt, re.M)
    # the slowest rank's time in the pair style (the same work in every run
    # of a contender at a rank count: LAMMPS' own lj/cut over the same atoms)
    pr = re.findall(r"^Pair\s+\|\s*\S+\s*\|\s*\S+\s*\|\s*(\S+)", txt, re.M)
    # the busiest rank's restricted evaluations over the ranks' mean (the
    # engine's balance entry, warm-up included; logs before 2026-11-30 lack it)
    e = re.search(r"^BENCH_ENGINE .* balance (\S+)", txt, re.M)
    R[(int(N), int(k), c, int(np_))] = dict(tps=float(t) / int(n), coll=float(b.group(1)) / int(n) if b else 0.0,
                                            pair=float(pr[-1]) / int(n) if pr else float("nan"),
                                            bal=float(e.group(1)) if e else float("nan"))

def stat(a):
    a = np.array(a)
    return f"{np.median(a):.3g} ({a.min():.3g}..{a.max():.3g})" if len(a) else "-"

def mean_se(a):
    """mean +- standard error of the mean (the repeats as independent samples)"""
    a = np.array(a)
    if len(a) < 2:
        return "-"
    return f"{a.mean():.3g} +- {a.std(ddof=1) / np.sqrt(len(a)):.2g}"

L = ["## bench/scaling: the local engine on 1 and 2 MPI ranks", "",
     f"{datetime.datetime.now().astimezone().strftime('%Y-%m-%d %H:%M %Z')}, `bash bench/scaling/ranks.sh` "
     "(hard-core LJ fluid of in.make-fluid, the methods' default engine; 2 cores, shared; "
     f"untimed warm-up steps before each timed run: {', '.join(map(str, sorted(WARM)))}"
     f"{'' if NEWTON <= {'on'} else '; newton ' + ', '.join(sorted(NEWTON))}).", "",
     "| N | method | repeats | nve ms/step 1 / 2 ranks | method ms/step 1 / 2 ranks | speed-up, 2 ranks over 1 | "
     "speed-up: mean +- s.e. | "
     "nve speed-up | method/nve 1 rank | method/nve 2 ranks | (m/nve 2) / (m/nve 1) | "
     "fastest repeats: speed-up, nve speed-up, (m/nve 2) / (m/nve 1) | "
     "quiet repeats: n, speed-up, nve speed-up | "
     "collisions/step 1 / 2 / 4 ranks | busiest rank / mean, 2 ranks |",
     "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
QUIET = 1.10
for N in sorted({k[0] for k in R}):
    for m in ("cva", "pcva"):
        ks = sorted({k[1] for k in R if k[0] == N and all((N, k[1], c, p) in R for c in ("nve", m) for p in (1, 2))})
        if not ks:
            continue
        g = lambda c, p: [R[(N, k, c, p)]["tps"] for k in ks]
        sp = [a / b for a, b in zip(g(m, 1), g(m, 2))]
        spn = [a / b for a, b in zip(g("nve", 1), g("nve", 2))]
        r1 = [a / b for a, b in zip(g(m, 1), g("nve", 1))]
        r2 = [a / b for a, b in zip(g(m, 2), g("nve", 2))]
        q = [b / a for a, b in zip(r1, r2)]
        coll = [R[(N, ks[0], m, p)]["coll"] for p in (1, 2)]
        c4 = R.get((N, 1, m, 4), {}).get("coll", float("nan"))
        b = {(c, p): min(g(c, p)) for c in ("nve", m) for p in (1, 2)}
        best = (f"{b[(m, 1)] / b[(m, 2)]:.3g}, {b[('nve', 1)] / b[('nve', 2)]:.3g}, "
                f"{(b[(m, 2)] / b[('nve', 2)]) / (b[(m, 1)] / b[('nve', 1)]):.3g}")
        # quiet repeats: each of the repeat's four runs spent at most QUIET
        # times the least pair-style time of its contender and rank count
        # (a slowed core shows there: the pair work is the same in each run)
        pmin = {(c, p): min(R[(N, k, c, p)]["pair"] for k in ks) for c in ("nve", m) for p in (1, 2)}
        qk = [i for i, k in enumerate(ks)
              if all(R[(N, k, c, p)]["pair"] <= QUIET * pmin[(c, p)] for c in ("nve", m) for p in (1, 2))]
        quiet = (f"{len(qk)}, {stat([sp[i] for i in qk])}, {stat([spn[i] for i in qk])}" if qk else "0")
        L.append(f"| {N} | {m} | {len(ks)} | {1e3*np.median(g('nve',1)):.1f} / {1e3*np.median(g('nve',2)):.1f} | "
                 f"{1e3*np.median(g(m,1)):.1f} / {1e3*np.median(g(m,2)):.1f} | {stat(sp)} | {mean_se(sp)} | {stat(spn)} | "
                 f"{stat(r1)} | {stat(r2)} | {stat(q)} | {best} | {quiet} | {coll[0]:.6g} / {coll[1]:.6g} / {c4:.6g} | "
                 f"{stat([R[(N, k, m, 2)]['bal'] for k in ks])} |")
L += ["", "Targets (issue 20): 2 ranks >= 1.8x faster than 1 at 256000 atoms; cva/nve on 2 ranks "
      "within 1.2x of its serial ratio (the (m/nve 2) / (m/nve 1) column). Medians with the "
      "spread (min..max) over the repeats; the mean's standard error treats the repeats as "
      "independent samples (a batch's repeats share the host's state of that hour: batches "
      "of the same code have differed by more). The fastest-repeats "
      "column divides the fastest run of each contender (the host's other jobs only add time, "
      "2-rank runs more of it). The quiet-repeats column keeps the repeats in which each of the "
      "four runs spent at most 1.10 times the least time in the pair style of its contender and "
      "rank count (the same lj/cut work in every such run: a core slowed by another job shows "
      "there; the slowest rank's time is taken). The last column is the engine's balance entry "
      "on 2 ranks (restricted evaluations of the busiest rank over the mean). 4 ranks run "
      "oversubscribed on 2 cores: their collisions are the check, not their time. nve's own "
      "speed-up bounds what the shared 2-core machine allows."]
text = "\n".join(L)
open(out, "w").write(text + "\n")
print(text)
