"""Shared by the examples' analysis scripts: the standard error of a mean of
correlated samples by blocking (Flyvbjerg and Petersen 1989): pairwise block
averages until fewer than minb blocks remain; the largest standard error
seen (the plateau, or the last level before too few blocks)."""
import math

import numpy as np


def blocking_se(x, minb=16):
    x = np.asarray(x, float)
    best = x.std(ddof=1) / math.sqrt(len(x))
    while len(x) >= minb:
        best = max(best, x.std(ddof=1) / math.sqrt(len(x)))
        m = len(x) // 2
        x = 0.5 * (x[0:2 * m:2] + x[1:2 * m:2])
    return best
