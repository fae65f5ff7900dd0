#!/usr/bin/python3
"""Z of in.lowdensity's trajectories against 1 + B2 rho + B3 rho^2 plus fix
langevin's bias of the impulse virial (README.md, "The thermostat bias:
mechanism"): Z_coll gamma dt / (2 - gamma dt), Z_coll = (2 pi/3) rho g(sigma+),
g(sigma+) = exp(-u(sigma)/kT) (1 + rho y1(sigma)).

  lowdensity.py DT blocks.*     (the block files of runs at timestep DT)
"""
import math, sys
import virial

RHO, KT, Q, GAMMA = 0.02, 2.0, 0.2, 0.5
dt = float(sys.argv[1])
b2, b3, y1 = virial.coefficients(Q, depth=3.0 / KT)
zcoll = 2 * math.pi / 3 * RHO * math.exp(-float(virial.u(1.0, Q, 3.0 / KT))) * (1 + RHO * y1(1.0))
zth = 1 + b2 * RHO + b3 * RHO ** 2 + zcoll * GAMMA * dt / (2 - GAMMA * dt)
zs = []
for f in sys.argv[2:]:
    z = [1 + float(l.split()[2]) / (RHO * KT) for l in open(f) if not l.startswith('#')]
    if len(z) != 20:
        print(f"{f}: {len(z)} blocks, skipped")
        continue
    zs.append(sum(z) / len(z))
n = len(zs)
m = sum(zs) / n
sd = math.sqrt(sum((x - m) ** 2 for x in zs) / (n - 1)) if n > 1 else float('nan')
print(f"{n} runs at dt {dt}: Z {m:.6f} +- {sd / math.sqrt(n):.6f} (sd between runs {sd:.5f}); "
      f"expected {zth:.6f} (B3 rho^2 {b3 * RHO ** 2:.6f}, bias {zcoll * GAMMA * dt / (2 - GAMMA * dt):.6f}); "
      f"Z - expected {m - zth:+.6f}")
