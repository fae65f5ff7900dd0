#!/usr/bin/python3
"""Hard-core LJ: the NPT density of fix hardsphere/press against the NVT pressure.

  analyze.py density FILE          mean number density of an in.npt output (for in.nvt)
  analyze.py report DIR N T P...   results.md from DIR/dens.P.txt and DIR/press.P.txt

Errors: one standard error from 20 block means. The NVT pressure at the NPT
mean density must give back the target P; its error combines the NVT
pressure's own error and the density's, propagated with dP/drho from the
NPT volume fluctuation (<d rho^2>/rho^2 = 1/(N d(beta P)/d rho)).
"""
import sys
import numpy as np

NB = 20


def blocks(x, nb=NB):
    x = np.asarray(x)
    n = len(x) // nb
    b = x[: n * nb].reshape(nb, n).mean(axis=1)
    return x[: n * nb].mean(), b.std(ddof=1) / np.sqrt(nb)


def load(path, col=1):
    return np.loadtxt(path, comments="#")[:, col]


def main():
    if sys.argv[1] == "density":
        print("%.10f" % load(sys.argv[2]).mean())
        return
    d, n, t, ps = sys.argv[2], int(sys.argv[3]), float(sys.argv[4]), sys.argv[5:]
    rows = []
    for p in ps:
        rho = load("%s/dens.%s.txt" % (d, p))
        rm, re = blocks(rho)
        dbp = rm * rm / (n * rho.var())          # d(beta P)/d rho from the fluctuation
        press = load("%s/press.%s.txt" % (d, p))
        pm, pe = blocks(press)
        pe_rho = t * dbp * re
        err = np.hypot(pe, pe_rho)
        rows.append((float(p), rm, re, t * dbp, pm, pe, pe_rho, err, (pm - float(p)) / err,
                     len(rho), len(press) * 100))
    out = ["# Hard-core LJ at constant pressure: NPT density, NVT pressure (N = %d, kT = %g)" % (n, t), "",
           "fix hardsphere/press samples the density at P; an NVT run at that density",
           "must report P back. Errors: one standard error from %d blocks; the" % NB,
           "combined error adds the density's, propagated with dP/drho. Written by analyze.py.", "",
           "| P | <rho> NPT | error | dP/drho | <P> NVT | error | from rho | combined | (P_NVT - P)/error | NPT samples | NVT steps |",
           "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        out.append("| %g | %.5f | %.5f | %.3f | %.4f | %.4f | %.4f | %.4f | %+.2f | %d | %d |" % r)
    open("results.md", "w").write("\n".join(out) + "\n")
    print("\n".join(out))


if __name__ == "__main__":
    main()
