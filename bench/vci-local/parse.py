"""Means over seeds (starts) of max|E(t)-E(0)| per atom by method and dt, the ratio to
fix nve's and the fitted order (least squares of log error on log dt)."""
import math
import sys
from collections import defaultdict

rows = [l.split() for l in open(sys.argv[1]) if l.strip()]
err = defaultdict(list)
sec = defaultdict(list)
coll = defaultdict(list)
for r in rows:
    m, dt = r[0], float(r[1])
    err[(m, dt)].append(float(r[3]))
    coll[(m, dt)].append(float(r[4]))
    sec[(m, dt)].append(float(r[-1]))
methods = sorted({m for m, _ in err}, key=lambda m: ["nve", "cva-local", "vci-local", "vci-global"].index(m)
                 if m in ["nve", "cva-local", "vci-local", "vci-global"] else 9)
dts = sorted({dt for _, dt in err}, reverse=True)
mean = lambda x: sum(x) / len(x)
print("| method | " + " | ".join(f"dt {dt:g}" for dt in dts) + " | fitted order |")
print("|---|" + "---|" * (len(dts) + 1))
for m in methods:
    have = [dt for dt in dts if (m, dt) in err]
    e = {dt: mean(err[(m, dt)]) for dt in have}
    n = len(have)
    lx = [math.log(d) for d in have]
    ly = [math.log(e[d]) for d in have]
    mx, my = sum(lx) / n, sum(ly) / n
    p = sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / sum((a - mx) ** 2 for a in lx) if n > 1 else float("nan")
    cells = []
    for dt in dts:
        if dt not in e:
            cells.append("--")
            continue
        v = e[dt]
        r = v / mean(err[("nve", dt)]) if ("nve", dt) in err else float("nan")
        spread = f"{min(err[(m, dt)]):.2e}..{max(err[(m, dt)]):.2e}"
        cells.append(f"{v:.3e} ({r:.2f}x nve; {len(err[(m, dt)])} starts {spread}; "
                     f"{mean(coll[(m, dt)]):.0f} coll., {mean(sec[(m, dt)]):.1f} s)")
    print(f"| {m} | " + " | ".join(cells) + f" | {p:.2f} |")
