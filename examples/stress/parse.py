#!/usr/bin/python3
"""Tables of examples/stress/run.sh: reads scratch/out/*.txt, writes results.md.
   /usr/bin/python3 parse.py <scratch dir> <results.md>"""
import glob
import os
import sys

scr, outp = sys.argv[1], sys.argv[2]
rows = {}
for f in glob.glob(os.path.join(scr, "out", "*.txt")):
    line = open(f).read().strip()
    name, _, rest = line.partition(" ")
    rows[name] = rest.split()
METHODS = ["psa", "cva", "pcva", "mcva", "vci"]
out = []
machine = open(os.path.join(scr, "machine.txt")).read().strip() if os.path.exists(
    os.path.join(scr, "machine.txt")) else "?"
out.append("# examples/stress: results of `bash examples/stress/run.sh`\n")
out.append("Machine: " + machine.replace("\n", "; ") + "\n")


def err(r):
    return " ".join(r[2:])[:160] if r and r[0] == "ERROR" else None


# ---- long runs
out.append("## Pendulum chain, dt 0.02, 10^6 steps (T = 20000), seed 1 (`in.chain-long`)\n")
out.append("H(0) = 1. max|dH| over the first 10 % of the run and over all of it; the same for "
           "H_[2,VV] (compute hamiltonian/modified, sampled every 10 steps); smallest bond length "
           "and smallest sphere x seen (contact with the wall: 0.45; bonded spheres touch at 0.9).\n")
out.append("| method | ranks | collisions | max dH first 10 % | max dH all | max dH2 first 10 % "
           "| max dH2 all | H(end) | min bond | min x | status |")
out.append("|---|---|---|---|---|---|---|---|---|---|---|")
for m in METHODS:
    for np in (1, 2):
        r = rows.get(f"long.{m}.np{np}")
        if r is None:
            continue
        if err(r):
            out.append(f"| {m} | {np} | | | | | | | | | {err(r)} |")
            continue
        # STRESS method dt T steps coll mdE mdE1 mdH2 mdH21 Hend minsep minwall
        c, mdE, mdE1, mdH2, mdH21, Hend, ms, mw = r[5], float(r[6]), float(r[7]), float(
            r[8]), float(r[9]), r[10], r[11], r[12]
        out.append(f"| {m} | {np} | {c} | {mdE1:.2e} | {mdE:.2e} | {mdH21:.2e} | {mdH2:.2e} "
                   f"| {Hend} | {ms} | {mw} | ok |")
out.append("")

# ---- timestep scan
DTS = ["0.05", "0.1", "0.15", "0.2", "0.25", "0.3", "0.4", "0.5", "0.6", "0.7", "0.8", "0.9", "1.0"]
for prefix, skin in (("scan", "0.3 (default)"), ("scanskin", "2.0")):
    out.append(f"## Stability limit on the pendulum chain, neighbour skin {skin} (T = 1000, seeds 1, 2, 3)\n")
    out.append("Each cell: max over the 3 seeds of max_t |H(t) - H(0)| (H(0) = 1), and in brackets "
               "the errors that stopped runs (skin: a sphere moved farther than the neighbour skin "
               "in a step; Gauss: mcva's stage iteration did not converge; lost atom: a sphere left "
               "the box; runaway: more than 10^8 collisions in one step; timeout: stopped after "
               "60 s, stuck in such a loop). A run is *stable* when it completes with max|dH| < 1 (100 %, the paper's "
               "mark for an unstable run). Limit = largest dt up to which every run (all smaller "
               "dt, all seeds) is stable.\n")
    out.append("| method | " + " | ".join(DTS) + " | limit |")
    out.append("|---|" + "---|" * (len(DTS) + 1))
    for m in METHODS:
        cells, limit, broken = [], None, False
        for dt in DTS:
            vals, bad, msgs = [], False, []
            for s in (1, 2, 3):
                r = rows.get(f"{prefix}.{m}.{dt}.{s}")
                if r is None:
                    msgs.append("not run")
                    bad = True
                    continue
                if err(r):
                    bad = True
                    e = err(r)
                    msgs.append("skin" if "skin" in e else ("lost atom" if ("missing" in e or "Lost" in e)
                                else ("overlap" if "overlap" in e else ("Gauss" if "Gauss" in e
                                      else ("runaway" if "collisions in step" in e
                                            else ("timeout" if "timeout" in e else e[:60]))))))
                    continue
                v = float(r[6])
                vals.append(v)
                if not (v < 1.0):
                    bad = True
            cell = f"{max(vals):.1e}" if vals else ""
            if msgs:
                cell += " (" + ", ".join(f"{x} x{msgs.count(x)}" for x in sorted(set(msgs))) + ")"
            if bad:
                broken = True
            elif not broken:
                limit = dt
            cells.append(cell + (" **U**" if bad else ""))
        out.append(f"| {m} | " + " | ".join(cells) + f" | {limit} |")
    out.append("\n**U**: unstable (max|dH| >= 1 or stopped) for at least one seed.\n")

# ---- dimer
HWS = ["0.1", "0.5", "1.0", "1.5", "1.9", "1.99", "2.01", "2.1"]
for amp, title in (("0.05", "no contacts (amp 0.05)"), ("0.2", "hard-core contacts every period (amp 0.2)")):
    out.append(f"## Stiff bond, omega = 100, {title} (`in.dimer`, 20000 steps)\n")
    out.append("Cell: max H/H0 / min H/H0 (collisions), or the error. Verlet theory without "
               "contacts: H in [1 - (hw/2)^2, 1] for hw < 2, exponential growth above.\n")
    out.append("| method | " + " | ".join("hw " + h for h in HWS) + " |")
    out.append("|---|" + "---|" * len(HWS))
    for m in METHODS:
        cells = []
        for hw in HWS:
            r = rows.get(f"dimer.{m}.{amp}.{hw}")
            if r is None:
                cells.append("-")
            elif err(r):
                e = err(r)
                cells.append("stop: skin" if "skin" in e else ("stop: Gauss" if "Gauss" in e
                             else "stop: " + e[:50]))
            else:
                # STRESS method K amp hw N coll Emax Emin
                cells.append(f"{float(r[7]):.4g} / {float(r[8]):.4g} ({r[6]})")
        out.append(f"| {m} | " + " | ".join(cells) + " |")
    out.append("")

# ---- resting contact
out.append("## Sphere pressed against a wall at rest (`in.resting`)\n")
out.append("| run | result |")
out.append("|---|---|")
for name in sorted(k for k in rows if k.startswith("rest.")):
    r = rows[name]
    if err(r):
        out.append(f"| {name} | {err(r)} |")
    else:
        # STRESS method dt T coll mdE E0 maxx
        out.append(f"| {name} | T {r[3]}: {r[4]} wall collisions, max abs(H - H0) = {r[5]} "
                   f"(H0 = {float(r[6]):.4g}), largest x {r[7]} (contact at 0.5) |")
out.append("")
open(outp, "w").write("\n".join(out) + "\n")
print("wrote", outp)
