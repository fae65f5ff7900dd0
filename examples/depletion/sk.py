#!/usr/bin/python3
"""S(k) at the smallest wavevectors of the periodic box from in.ao's
position dumps (-var dump N):  sk.py pos.<tag>.txt [...]

S(k) = |sum_j exp(i k.r_j)|^2 / N for k = (2 pi / L) n, averaged over the
n of each shell |n|^2 = 1, 2, 3 and over the frames; error bar: blocking
of the per-frame shell means (../common/blocking.py); and S(k_min) over
the first and the second half of the frames (a drift: not stationary)."""
import math, os, sys
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
from blocking import blocking_se


def frames(path):
    with open(path) as f:
        while True:
            line = f.readline()
            if not line:
                return
            f.readline()                       # timestep
            f.readline(); n = int(f.readline())
            f.readline()
            L = [(lambda w: float(w[1]) - float(w[0]))(f.readline().split()) for _ in range(3)]
            f.readline()
            x = np.loadtxt([f.readline() for _ in range(n)])[:, 1:4]
            yield np.array(L), x


def shells():
    out = {1: [], 2: [], 3: []}
    for a in range(-1, 2):
        for b in range(-1, 2):
            for c in range(-1, 2):
                s = a * a + b * b + c * c
                if s and (a, b, c) > (0, 0, 0) and s in out:    # k and -k give the same S
                    out[s].append((a, b, c))
    return out


if __name__ == "__main__":
    sh = shells()
    print("| run | frames | L | k_min sigma | S(k), \\|n\\|^2 = 1 | 2 | 3 | S(k_min): first, second half of the frames |")
    print("|---|---|---|---|---|---|---|---|")
    for path in sys.argv[1:]:
        per = {s: [] for s in sh}
        nf, Lb = 0, None
        for L, x in frames(path):
            Lb = L[0]
            for s, ns in sh.items():
                k = 2 * math.pi * np.array(ns) / L    # (m, 3)
                ph = x @ k.T                           # (N, m)
                sk = (np.cos(ph).sum(0) ** 2 + np.sin(ph).sum(0) ** 2) / len(x)
                per[s].append(sk.mean())
            nf += 1
        cells = " | ".join(f"{np.mean(per[s]):.3f} ± {blocking_se(per[s]):.3f}" for s in sorted(per))
        h = nf // 2
        halves = f"{np.mean(per[1][:h]):.2f}, {np.mean(per[1][h:]):.2f}"
        print(f"| {os.path.basename(path)} | {nf} | {Lb:.3f} | {2 * math.pi / Lb:.3f} | {cells} | {halves} |")
