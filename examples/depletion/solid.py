#!/usr/bin/python3
"""Crystal-like colloids in a position dump of in.ao (-var dump N), by the
ten Wolde-Ruiz-Montero-Frenkel criterion: neighbours within RC = 1.4 sigma
(between the AO fluid's first and second shells), q6m(i) normalised, a
bond i-j "solid" when Re sum_m q6m(i) q6m(j)* > 0.7, a colloid solid-like
with >= 7 solid bonds. Also the mean number of neighbours within RC.

  solid.py pos.<tag>.txt [...]      (the first and the last frame of each)

Check: an fcc lattice gives 100 % solid-like, an ideal gas at rho 0.4
about 0 %."""
import math, os, sys
import numpy as np
from scipy.special import sph_harm

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sk import frames

RC = 1.4


def solid_fraction(L, x):
    n = len(x)
    d = x[:, None, :] - x[None, :, :]
    d -= L * np.round(d / L)
    r = np.sqrt((d * d).sum(-1))
    nb = (r < RC) & (r > 0)
    i, j = np.nonzero(nb)
    v = d[i, j]
    rr = r[i, j]
    theta = np.arccos(np.clip(v[:, 2] / rr, -1, 1))
    phi = np.arctan2(v[:, 1], v[:, 0])
    q = np.zeros((n, 13), complex)
    for k, m in enumerate(range(-6, 7)):
        np.add.at(q[:, k], i, sph_harm(m, 6, phi, theta))
    cnt = nb.sum(1)
    q /= np.maximum(cnt, 1)[:, None]
    q /= np.maximum(np.linalg.norm(q, axis=1), 1e-30)[:, None]
    dots = np.real((q[i] * np.conj(q[j])).sum(1))
    nsolid = np.bincount(i, weights=(dots > 0.7), minlength=n)
    return (nsolid >= 7).mean(), cnt.mean()


if __name__ == "__main__":
    if len(sys.argv) == 1:    # self-check
        a = np.array([[0, 0, 0], [0.5, 0.5, 0], [0.5, 0, 0.5], [0, 0.5, 0.5]])
        c = 4
        x = np.array([a + [i, j, k] for i in range(c) for j in range(c) for k in range(c)]).reshape(-1, 3) * 1.2
        print("fcc:", solid_fraction(np.array([c * 1.2] * 3), x))
        rng = np.random.default_rng(1)
        L = (864 / 0.4) ** (1 / 3)
        print("ideal gas:", solid_fraction(np.array([L] * 3), rng.random((864, 3)) * L))
        sys.exit()
    for path in sys.argv[1:]:
        fr = list(frames(path))
        for name, (L, x) in (("first", fr[0]), ("last", fr[-1])):
            f, c = solid_fraction(L, x)
            print(f"{os.path.basename(path)} {name} frame: solid-like {100 * f:.1f} %, neighbours within {RC}: {c:.2f}")
