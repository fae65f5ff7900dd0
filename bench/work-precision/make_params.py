#!/usr/bin/python3
"""Barker-Henderson diameters of the continuous repulsions used in place of
the hard cores (bench/work-precision): d = int_0^rc (1 - exp(-u(r)/kT)) dr.
sigma is chosen so that d equals the hard-sphere diameter at the energy scale
kT of the system (the fluid: kT = 1, d = 1; the chain: the same ratios
eps/kT, d = 0.9 between spheres and 0.45 from the wall). Prints the numbers
written into pair.fluid and in.chain; exits 1 if they differ by more than
1e-7 from those files' values.

    /usr/bin/python3 make_params.py
"""
import sys
import numpy as np
from scipy.integrate import quad
from scipy.optimize import brentq

C_MIE = 50.0 * (50.0 / 49.0) ** 49   # Mie(50,49) prefactor (n/(n-m)) (n/m)^(m/(n-m))


def wca(s, eps):
    return (lambda r: 4 * eps * ((s / r) ** 12 - (s / r) ** 6) + eps), 2 ** (1 / 6) * s


def mie(s, eps):
    return (lambda r: C_MIE * eps * ((s / r) ** 50 - (s / r) ** 49) + eps), 50 / 49 * s


def d_bh(model, s, eps, kT=1.0):
    u, rc = model(s, eps)
    f = lambda r: 1.0 if r < 0.5 * s else 1.0 - np.exp(-u(r) / kT)
    return quad(f, 0, rc, limit=400, points=[0.5 * s, 0.9 * s, s])[0]


def sigma_for(model, eps, d=1.0):
    return brentq(lambda s: d_bh(model, s, eps) - d, 0.8 * d, 1.2 * d, xtol=1e-14)


s_wca = sigma_for(wca, 1.0)   # eps/kT = 1
s_mie = sigma_for(mie, 1.5)   # eps/kT = 1.5 (Jover et al. 2012)
vals = {
    "fluid wca sigma": s_wca, "fluid wca cut": 2 ** (1 / 6) * s_wca,
    "fluid mie sigma": s_mie, "fluid mie cut": 50 / 49 * s_mie,
    "chain wca sigma": 0.9 * s_wca, "chain wca cut": 0.9 * 2 ** (1 / 6) * s_wca,
    "chain mie sigma": 0.9 * s_mie, "chain mie cut": 0.9 * 50 / 49 * s_mie,
    "chain wall sigma": 0.45 * s_wca, "chain wall cut": 0.45 * 2 ** (1 / 6) * s_wca,
}
used = {
    "fluid wca sigma": 0.984634367, "fluid wca cut": 1.105214708,
    "fluid mie sigma": 0.99493969, "fluid mie cut": 1.015244582,
    "chain wca sigma": 0.8861709303, "chain wca cut": 0.9946932,
    "chain mie sigma": 0.8954457, "chain mie cut": 0.9137201,
    "chain wall sigma": 0.4430855, "chain wall cut": 0.4973466,
}
bad = 0
for k, v in vals.items():
    ok = abs(v - used[k]) < 1e-7
    bad += not ok
    print(f"{k:18s} {v:.10f}  used {used[k]:.10f}  {'ok' if ok else 'DIFFERS'}")
print(f"d_BH(sigma=1): wca {d_bh(wca, 1.0, 1.0):.6f}, mie {d_bh(mie, 1.0, 1.5):.6f}")
sys.exit(1 if bad else 0)
