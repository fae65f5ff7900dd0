#!/usr/bin/python3
"""The reduced second virial coefficient B2* = B2 / B2_HS (B2_HS = 2 pi
sigma^3 / 3) of the AO pair potential (virial.py's formula, hard core
included), against the polymer reservoir packing fraction eta_p^r, and
the eta_p^r at which B2* reaches a given value (default -1.5, the
Vliegenthart-Lekkerkerker / Noro-Frenkel estimate of the gas-liquid
critical point of short-ranged attractions; README.md, "Where the
criterion puts the critical point").

  critical_b2.py [B2STAR] [Q ...]          default -1.5, q = 0.1 0.2

B2 by Gauss-Legendre quadrature (64 nodes on [0, sigma] and on
[sigma, sigma (1+q)]), the same as virial.coefficients; eta_p^r by
bisection. Self-check: at depth 0 B2* = 1; at the committed tables'
contact value -3 kT it repeats virial.py's B2.
"""
import math, os, sys
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import virial

PI = math.pi
XG, WG = np.polynomial.legendre.leggauss(64)


def b2star(q, depth):
    tot = 0.0
    for a, b in ((0.0, 1.0), (1.0, 1.0 + q)):
        s, w = 0.5 * (b - a) * XG + 0.5 * (a + b), 0.5 * (b - a) * WG
        with np.errstate(over="ignore"):    # f's exp(-u) where u is not used (r < sigma)
            tot += np.sum(w * virial.f(s, q, depth) * s * s)
    return -2 * PI * tot / (2 * PI / 3)


def depth_at(q, target, lo=0.0, hi=20.0):
    """contact value |U(sigma)|/kT at which B2* = target (B2* falls with depth)"""
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if b2star(q, mid) > target:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


if __name__ == "__main__":
    target = float(sys.argv[1]) if len(sys.argv) > 1 else -1.5
    qs = [float(x) for x in sys.argv[2:]] or [0.1, 0.2]
    print(f"check: B2*(depth 0) = {b2star(0.2, 0.0):.12f} (1)")
    for q in qs:
        b2, _, _ = virial.coefficients(q) if q in (0.1, 0.2) else (None, None, None)
        d3 = b2star(q, 3.0)
        chk = f" (virial.py: {b2 / (2 * PI / 3):.6f})" if b2 is not None else ""
        d = depth_at(q, target)
        print(f"q {q}: table (contact -3 kT, eta_p^r {virial.eta_p(q):.6f}): B2* = {d3:.6f}{chk}")
        print(f"q {q}: B2* = {target} at contact value -{d:.4f} kT, eta_p^r = {virial.eta_p(q, d):.5f}")
        for dd in (1.0, 2.0, 3.0, d, 4.0, 5.0):
            print(f"    contact -{dd:.4f} kT  eta_p^r {virial.eta_p(q, dd):.5f}  B2* {b2star(q, dd):+.4f}")
