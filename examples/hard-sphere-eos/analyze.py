#!/usr/bin/python3
"""Mean packing fraction and volume variance of the hard-sphere-eos runs
against Carnahan-Starling; writes results.md and eos.png.
    /usr/bin/python3 analyze.py <scratch dir> <N> <P*> ...
Each <scratch dir>/vol.<P*>.txt holds "step volume" after every attempt (production)."""
import math
import sys

NB = 20  # blocks


def cs_pstar(eta):
    z = (1 + eta + eta**2 - eta**3) / (1 - eta)**3
    return 6 * eta * z / math.pi


def cs_eta(p):
    lo, hi = 0.0, 0.7
    for _ in range(200):
        m = 0.5 * (lo + hi)
        lo, hi = (m, hi) if cs_pstar(m) < p else (lo, m)
    return 0.5 * (lo + hi)


def cs_dbetap_drho(eta):
    return (1 + 4 * eta + 4 * eta**2 - 4 * eta**3 + eta**4) / (1 - eta)**4


def blocks(x):
    n = len(x) // NB
    x = x[:n * NB]
    mean = sum(x) / len(x)
    bm = [sum(x[j * n:(j + 1) * n]) / n for j in range(NB)]
    bv = [sum((v - mean)**2 for v in x[j * n:(j + 1) * n]) / n for j in range(NB)]

    def sem(a):
        m = sum(a) / NB
        return m, math.sqrt(sum((v - m)**2 for v in a) / (NB - 1) / NB)

    return mean, sem(bm)[1], sem(bv)[0], sem(bv)[1]


def main():
    scratch, natoms = sys.argv[1], int(sys.argv[2])
    rows = []
    for p in sys.argv[3:]:
        # fix ave/time file: "step volume" per line, comments start with #
        vol = [float(l.split()[-1]) for l in open(f"{scratch}/vol.{p}.txt")
               if l.strip() and l[0] != '#']
        eta = [natoms * math.pi / 6 / v for v in vol]
        m, e, _, _ = blocks(eta)
        vm, _, vv, vve = blocks(vol)
        ecs = cs_eta(float(p))
        rv, rve = vv / vm**2, vve / vm**2
        rvcs = 1 / (natoms * cs_dbetap_drho(ecs))
        rows.append((float(p), m, e, ecs, rv, rve, rvcs, len(vol)))
    out = ["| P* | <eta> | error | eta CS | deviation | (eta-CS)/error | <dV^2>/<V>^2 | error | CS: 1/(N d(betaP)/drho) | deviation | samples |",
           "|---|---|---|---|---|---|---|---|---|---|---|"]
    for p, m, e, ecs, rv, rve, rvcs, n in rows:
        out.append(f"| {p:g} | {m:.5f} | {e:.5f} | {ecs:.5f} | {100 * (m / ecs - 1):+.3f} % | "
                   f"{(m - ecs) / e:+.1f} | {rv:.4e} | {rve:.1e} | {rvcs:.4e} | "
                   f"{100 * (rv / rvcs - 1):+.1f} % | {n} |")
    text = "\n".join(out) + "\n"
    open("results.md", "w").write(
        f"# Hard-sphere equation of state from fix hardsphere/press (N = {natoms})\n\n"
        "Mean packing fraction and relative volume variance against Carnahan-Starling;\n"
        f"errors from {NB} block averages (one standard error). Written by analyze.py.\n\n" + text)
    print(text)
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("no matplotlib: eos.png not written")
        return
    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    etas = [0.005 * k for k in range(1, 105)]
    ax[0].plot(etas, [cs_pstar(x) for x in etas], "k-", label="Carnahan-Starling")
    ax[0].errorbar([r[1] for r in rows], [r[0] for r in rows], xerr=[r[2] for r in rows],
                   fmt="o", color="C3", label="hardsphere/press + psa")
    ax[0].set_xlabel("packing fraction $\\eta$")
    ax[0].set_ylabel("$P\\sigma^3/kT$")
    ax[0].legend()
    ax[1].errorbar([r[0] for r in rows], [100 * (r[1] / r[3] - 1) for r in rows],
                   yerr=[100 * r[2] / r[3] for r in rows], fmt="o", color="C3",
                   label="$\\langle\\eta\\rangle$ / CS - 1")
    ax[1].errorbar([r[0] + 0.15 for r in rows], [10 * (r[4] / r[6] - 1) for r in rows],
                   yerr=[10 * r[5] / r[6] for r in rows], fmt="s", color="C0",
                   label="($\\langle\\delta V^2\\rangle$ / CS - 1) / 10")
    ax[1].axhline(0, color="k", lw=0.8)
    ax[1].set_xlabel("$P\\sigma^3/kT$")
    ax[1].set_ylabel("deviation from Carnahan-Starling (%)")
    ax[1].legend()
    fig.tight_layout()
    fig.savefig("eos.png", dpi=110)
    print("wrote eos.png")


main()
