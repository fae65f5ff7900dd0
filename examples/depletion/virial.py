#!/usr/bin/python3
"""Exact low-density results for hard colloids with the AO depletion pair
potential of potentials/ (written out again here from its formula):

  u(r)/kT = -eta_p ((1+q)/q)^3 [1 - 3x/2 + x^3/2],  x = r / (sigma (1+q)),
            sigma <= r <= sigma (1+q); hard core below sigma, 0 beyond,
  eta_p = 3 / (1 + 3/(2q))  (contact value -3 kT, as the committed tables).

Mayer function f = exp(-u/kT) - 1 (f = -1 in the core). By quadrature:
  B2 = -2 pi int f r^2 dr
  y1(r) = int f(|r1 - r3|) f(|r2 - r3|) dr3
        = (2 pi / r) int ds s f(s) int_{|r-s|}^{s+r} dt t f(t)
  B3 = -(4 pi / 3) int r^2 f(r) y1(r) dr
so that g(r) = exp(-u/kT) [1 + rho y1(r) + O(rho^2)] and
Z = 1 + B2 rho + B3 rho^2 + O(rho^3). Checked on hard spheres (eps = 0):
B2 = 2 pi/3, y1(sigma) = 5 pi/12, B3 = 5 pi^2/18.

  virial.py Q           prints B2, B3 and y1 on [1, 1+q]
  (import: functions u, f, coefficients)
"""
import math, sys
import numpy as np

PI = math.pi


def eta_p(q, depth=3.0):
    return depth / (1.0 + 1.5 / q)


def u(r, q, depth=3.0):
    """AO potential in kT for sigma <= r (0 beyond sigma (1+q))."""
    r = np.asarray(r, float)
    x = r / (1.0 + q)
    v = -eta_p(q, depth) * ((1 + q) / q) ** 3 * (1 - 1.5 * x + 0.5 * x ** 3)
    return np.where(r < 1.0 + q, v, 0.0)


def f(r, q, depth=3.0):
    r = np.asarray(r, float)
    return np.where(r < 1.0, -1.0, np.exp(-u(r, q, depth)) - 1.0)


def coefficients(q, depth=3.0, n=4000):
    """B2, B3 and y1 on a grid of r (Gauss-Legendre on each smooth piece)."""
    R = 1.0 + q
    # pieces where f is smooth: [0, 1] and [1, R]
    xg, wg = np.polynomial.legendre.leggauss(64)
    def nodes(a, b):
        return 0.5 * (b - a) * xg + 0.5 * (a + b), 0.5 * (b - a) * wg
    pieces = [nodes(0.0, 1.0), nodes(1.0, R)]
    B2 = -2 * PI * sum(np.sum(w * f(s, q, depth) * s * s) for s, w in pieces)

    def inner(lo, hi):
        # int_lo^hi t f(t) dt, split at the core edge 1 and at R
        tot = 0.0
        for a, b in ((0.0, 1.0), (1.0, R)):
            a2, b2 = max(a, lo), min(b, hi)
            if b2 > a2:
                t, w = nodes(a2, b2)
                tot += np.sum(w * t * f(t, q, depth))
        return tot

    def y1(r):
        tot = 0.0
        # s pieces split where |r - s| or s + r crosses 1 or R: split finely
        brk = sorted({0.0, 1.0, R} | {b for b in (r - 1, r - R, 1 - r, R - r, r + 1, r + R) if 0 < b < R})
        for a, b in zip(brk[:-1], brk[1:]):
            s, w = nodes(a, b)
            tot += sum(wi * si * f(si, q, depth) * inner(abs(r - si), si + r) for si, wi in zip(s, w))
        return 2 * PI / r * tot

    # B3 on the same pieces of r
    B3 = 0.0
    for s, w in pieces:
        B3 += -(4 * PI / 3) * sum(wi * ri * ri * float(f(ri, q, depth)) * y1(ri) for ri, wi in zip(s, w))
    return B2, B3, y1


if __name__ == "__main__":
    # hard spheres first: the quadrature against the known values
    b2, b3, y1 = coefficients(0.1, depth=0.0)
    print(f"hard spheres: B2 {b2:.10f} (2pi/3 = {2*PI/3:.10f})  B3 {b3:.10f} (5pi^2/18 = {5*PI*PI/18:.10f})"
          f"  y1(1) {y1(1.0):.10f} (5pi/12 = {5*PI/12:.10f})")
    q = float(sys.argv[1]) if len(sys.argv) > 1 else 0.1
    b2, b3, y1 = coefficients(q)
    print(f"AO q {q}: eta_p {eta_p(q):.6f}  B2 {b2:.8f}  B2/B2_HS {b2/(2*PI/3):.6f}  B3 {b3:.8f}")
    for r in np.linspace(1.0, 1.0 + q, 6):
        print(f"  r {r:.3f}  u {float(u(r, q)):+.5f}  y1 {y1(r):.6f}")
