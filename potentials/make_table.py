#!/usr/bin/python3
"""Write LAMMPS `pair_style table` files for the smooth tails of hard-core models.

The table holds the smooth part, from contact r = sigma to the cutoff; the
hard core r < sigma is the job of fix hardsphere/* (keyword diameter, equal
to sigma). The first point is a little inside contact, sigma (1 - margin),
with the same formula continued there (--margin, default 0.05): pair_style
table stops the run at any distance below its first point, and the
integrators evaluate forces there (contacts land a few ulp inside sigma; the
local engine's trial positions up to about v dt inside; README.md). Energies
and forces come from the closed formulas below; the force is -dU/dr written
out analytically, never a difference quotient.

Models (r in [sigma, rc]):

  ao          Asakura-Oosawa depletion attraction between two hard colloids
              of diameter sigma in an ideal polymer solution, polymer diameter
              sigma_p = q sigma, polymer reservoir packing fraction eta_p^r:
                U(r)/kT = -eta_p^r ((1+q)/q)^3
                          * [1 - 3r/(2 sigma(1+q)) + r^3/(2 (sigma(1+q))^3)]
              for sigma <= r <= rc = sigma(1+q), zero beyond. This is minus
              the polymer osmotic pressure n_p^r kT times the overlap volume
              of the two depletion spheres of diameter sigma(1+q):
              S. Asakura and F. Oosawa, J. Chem. Phys. 22, 1255 (1954);
              A. Vrij, Pure Appl. Chem. 48, 471 (1976); H. N. W. Lekkerkerker
              and R. Tuinier, Colloids and the Depletion Interaction, Lecture
              Notes in Physics 833 (Springer, 2011), chapter 2.
              U(sigma) = -eta_p^r (1 + 3/(2q)) kT; U and dU/dr vanish at rc.
  sutherland  hard core plus attractive inverse-power tail
                U(r) = -epsilon (sigma/r)^n            (unshifted, default)
                U(r) = -epsilon [(sigma/r)^n - (sigma/rc)^n]   (--shift yes)
              for sigma <= r < rc; e.g. A. Diez, J. Largo and J. R. Solana,
              Fluid Phase Equilib. 253, 67 (2007).

Examples (the committed tables; see README.md):
  /usr/bin/python3 potentials/make_table.py ao --q 0.1 --depth 3 -o potentials/ao_q0.1.table
  /usr/bin/python3 potentials/make_table.py sutherland --n 6 --rc 3 --shift both \\
      -o potentials/sutherland_n6.table
Add --check LMP (a LAMMPS binary with pair_style table) to read the table
back through LAMMPS (pair_write) and print the interpolation error against
the formula.
"""

import argparse
import math
import os
import subprocess
import sys
import tempfile

import numpy as np


# ---------------------------------------------------------------- models
# Each returns (U, F, dF/dr) at r (numpy arrays), F = -dU/dr, for
# sigma <= r <= rc (the value at rc is the limit from inside).

def ao(r, sigma, q, eta, kT):
    D = sigma * (1.0 + q)    # diameter of the depletion sphere = cutoff
    pref = eta * kT * ((1.0 + q) / q) ** 3
    x = r / D
    U = -pref * (1.0 - 1.5 * x + 0.5 * x ** 3)
    F = 1.5 * pref / D * (x ** 2 - 1.0)
    dF = 3.0 * pref * x / D ** 2
    return U, F, dF


def sutherland(r, sigma, n, eps, rc, shift):
    s = (sigma / r) ** n
    U = -eps * s + (eps * (sigma / rc) ** n if shift else 0.0)
    F = -n * eps * s / r
    dF = n * (n + 1) * eps * s / r ** 2
    return U, F, dF


# ---------------------------------------------------------------- sections

def fmt(x):
    """Shortest text that reads back as the same double (keywords, N line)."""
    return repr(float(x))


def ao_sections(a):
    positive("ao: q = sigma_p/sigma", a.q)
    if (a.eta is None) == (a.depth is None):
        fail("ao: give exactly one of --eta (polymer reservoir packing fraction) "
             "and --depth (|U(sigma)| in units of kT)")
    if a.eta is not None:
        positive("ao: --eta (eta_p^r)", a.eta)
    if a.depth is not None:
        positive("ao: --depth (|U(sigma)|/kT)", a.depth)
    positive("ao: --kT", a.kT)
    # U(sigma) = -eta (1 + 3/(2q)) kT  ->  eta for a wanted well depth
    eta = a.eta if a.eta is not None else a.depth / (1.0 + 1.5 / a.q)
    rc = a.sigma * (1.0 + a.q)
    key = a.keyword or f"AO_q{a.q:g}_eta{eta:.6g}_sigma{a.sigma:g}_kT{a.kT:g}"
    comments = [
        "Asakura-Oosawa depletion attraction (ideal polymers), hard core r < sigma not included",
        "U(r)/kT = -eta_p^r ((1+q)/q)^3 [1 - 3r/(2 sigma(1+q)) + r^3/(2 (sigma(1+q))^3)]"
        "  for sigma <= r <= sigma(1+q)",
        f"q = sigma_p/sigma = {fmt(a.q)}  eta_p^r = {fmt(eta)}  kT = {fmt(a.kT)}  sigma = {fmt(a.sigma)}",
        f"U(sigma) = {fmt(-eta * (1 + 1.5 / a.q) * a.kT)}  (= -eta_p^r (1 + 3/(2q)) kT);"
        f"  cutoff sigma(1+q) = {fmt(rc)}, where U = F = 0",
    ]
    if a.q > 2 / math.sqrt(3) - 1:
        comments.append("q > 2/sqrt(3) - 1: the AO pair potential is not the whole story "
                        "(three-body depletion terms exist)")
    return [(key, rc, comments, lambda r: ao(r, a.sigma, a.q, eta, a.kT))]


def sutherland_sections(a):
    positive("sutherland: exponent --n", a.n)
    positive("sutherland: --epsilon", a.epsilon)
    if not (math.isfinite(a.rc) and a.rc > a.sigma):
        fail(f"sutherland: cutoff --rc must be > sigma = {a.sigma} (got {a.rc})")
    out = []
    shifts = {"no": [False], "yes": [True], "both": [False, True]}[a.shift]
    for shift in shifts:
        base = a.keyword or f"SUTHERLAND_n{a.n:g}_eps{a.epsilon:g}_sigma{a.sigma:g}_rc{a.rc:g}"
        # a given --keyword names a single section as it is
        key = base + ("_shifted" if shift and (len(shifts) > 1 or not a.keyword) else "")
        Urc = -a.epsilon * (a.sigma / a.rc) ** a.n
        comments = [
            "Sutherland tail: hard core (r < sigma, not included) + attractive inverse power",
            ("U(r) = -epsilon [(sigma/r)^n - (sigma/rc)^n]" if shift else
             "U(r) = -epsilon (sigma/r)^n") + "  for sigma <= r < rc, 0 beyond",
            f"n = {a.n:g}  epsilon = {fmt(a.epsilon)}  sigma = {fmt(a.sigma)}  rc = {fmt(a.rc)}",
            ("shifted: U(rc) = 0 (the force still jumps there)" if shift else
             f"unshifted: U jumps by {fmt(-Urc)} at rc; no tail correction in pair_style table"),
        ]
        if a.n > 3 and not shift:
            # integral of the dropped tail r >= rc, per particle (times rho) and for P (times rho^2)
            eint = 2 * math.pi * a.epsilon * a.sigma ** a.n * a.rc ** (3 - a.n) / (a.n - 3)
            comments.append(f"tail correction (g = 1 beyond rc): E/N += -{fmt(eint)} rho, "
                            f"P += -{fmt(eint * a.n / 3)} rho^2")
        elif not shift:
            comments.append("n <= 3: the tail integral diverges, no tail correction exists")
        out.append((key, a.rc, comments,
                    lambda r, s=shift: sutherland(r, a.sigma, a.n, a.epsilon, a.rc, s)))
    return out


# ---------------------------------------------------------------- writing

def grid(lo, hi, N, spacing):
    """The r values LAMMPS recomputes from 'N n R|RSQ lo hi' (pair_table.cpp)."""
    i = np.arange(N, dtype=float)
    if spacing == "r":
        return lo + (hi - lo) * i / (N - 1)
    return np.sqrt(lo * lo + (hi * hi - lo * lo) * i / (N - 1))


def write(path, sections, a, argv):
    with open(path, "w") as fp:
        # no "UNITS:" tag: LAMMPS would then refuse the file in other unit systems
        fp.write("# LAMMPS pair_style table file (HARDSPHERE potentials/); energy in kT or "
                 "epsilon, length in sigma unless chosen otherwise below\n")
        fp.write("# made by: /usr/bin/python3 potentials/make_table.py " + " ".join(argv) + "\n")
        fp.write("# hard core: fix hardsphere/* ... diameter " + fmt(a.sigma) +
                 " (must equal sigma); the table starts at contact r = sigma\n")
        if a.margin > 0:
            # pair_style table aborts below its first point; see README.md
            fp.write(f"# less a margin: first point sigma (1 - {a.margin:g}) = "
                     f"{fmt(a.sigma * (1 - a.margin))}, the formula continued inside contact, "
                     "for force\n# evaluations the integrators make there (round-off at "
                     "contacts, trial positions); physical states never reach it\n")
        for key, rc, comments, model in sections:
            rlo = a.sigma * (1.0 - a.margin)
            r = grid(rlo, rc, a.N, a.spacing)
            U, F, dF = model(r)
            U, F = U + 0.0, F + 0.0    # no "-0" in the file
            fp.write("\n")
            for c in comments:
                fp.write("# " + c + "\n")
            fp.write(f"# pair_style table linear {a.N}   (or spline {a.N})\n")
            fp.write(f"# pair_coeff 1 1 {os.path.basename(path)} {key} {fmt(rc)}\n")
            fp.write(f"{key}\n")
            # FPRIME: exact dF/dr at both ends, used when LAMMPS splines the file
            fp.write(f"N {a.N} {a.spacing.upper()} {fmt(rlo)} {fmt(rc)} "
                     f"FPRIME {dF[0]:.17g} {dF[-1]:.17g}\n\n")
            for i in range(a.N):
                fp.write(f"{i + 1} {r[i]:.17g} {U[i]:.17g} {F[i]:.17g}\n")


# ---------------------------------------------------------------- check

def check(path, sections, a, lmp, M=20001):
    """Interpolation error of the table as LAMMPS evaluates it (pair_write,
    i.e. PairTable::single, the same lookup as compute), against the formula."""
    print(f"{'keyword':<44} {'style':<12} {'max|dU|':>10} {'max|dF|':>10} "
          f"{'|U(sigma)|':>10} {'max|F|':>10}")
    for key, rc, _, model in sections:
        for style in ("linear", "spline"):
            with tempfile.TemporaryDirectory() as tmp:
                out = os.path.join(tmp, "pw.txt")
                inp = "\n".join([
                    "units lj", "atom_style atomic",
                    f"region b block 0 {4 * rc} 0 {4 * rc} 0 {4 * rc} units box",
                    "create_box 1 b", "mass 1 1.0",
                    f"pair_style table {style} {a.N}",
                    f"pair_coeff 1 1 {os.path.abspath(path)} {key} {fmt(rc)}",
                    f"pair_write 1 1 {M} r {fmt(a.sigma)} {fmt(rc)} {out} {key}", ""])
                res = subprocess.run([lmp, "-log", "none", "-screen", "none", "-nocite"],
                                     input=inp, text=True, capture_output=True, cwd=tmp)
                if res.returncode != 0 or not os.path.exists(out):
                    fail(f"check: {lmp} failed on {key}:\n{res.stdout}{res.stderr}")
                # data lines: index r energy force (skip comments, keyword, N line)
                rows = [l.split() for l in open(out)]
                d = np.array([[float(x) for x in w] for w in rows
                              if len(w) == 4 and w[0].isdigit()])
            U, F = d[:, 2], d[:, 3]
            # pair_write prints r with 15 digits: recompute it as LAMMPS did
            rr = a.sigma + (rc - a.sigma) * np.arange(M) / (M - 1)
            Ue, Fe, _ = model(rr)
            Ue[rr >= rc] = Fe[rr >= rc] = 0.0    # LAMMPS: a pair interacts if r < rc
            print(f"{key:<44} {style + ' ' + str(a.N):<12} {np.max(abs(U - Ue)):10.3g} "
                  f"{np.max(abs(F - Fe)):10.3g} {abs(Ue[0]):10.3g} {np.max(abs(Fe)):10.3g}")


# ---------------------------------------------------------------- main

def fail(msg):
    sys.exit(f"make_table.py: error: {msg}")


def positive(name, x):
    if not (math.isfinite(x) and x > 0):    # also catches nan
        fail(f"{name} must be a finite number > 0 (got {x})")


def main(argv):
    p = argparse.ArgumentParser(
        description="LAMMPS pair_style table files for the smooth tails of hard-core models "
                    "(from contact r = sigma to the cutoff).",
        epilog="Formulas and sources: see the module docstring and potentials/README.md.")
    sub = p.add_subparsers(dest="model", required=True)

    def common(sp):
        sp.add_argument("-o", "--output", required=True, help="table file to write")
        sp.add_argument("--sigma", type=float, default=1.0,
                        help="hard-core diameter = contact distance = first table point (default 1)")
        sp.add_argument("-N", "--points", dest="N", type=int, default=2000,
                        help="number of table points (default 2000)")
        sp.add_argument("--spacing", choices=["rsq", "r"], default="rsq",
                        help="points evenly spaced in r^2 (default: what pair_style table linear "
                             "uses inside, so with the same N LAMMPS takes the file values "
                             "unchanged) or in r")
        sp.add_argument("--keyword", help="table keyword (default: model and parameters)")
        sp.add_argument("--margin", type=float, default=0.05,
                        help="start the table at sigma (1 - margin), the formula continued "
                             "inside contact: pair_style table stops the run at any r below its "
                             "first point, and the integrators evaluate forces a little inside "
                             "contact (round-off; cva's local engine: trial positions up to "
                             "~v dt inside); see README.md (default 0.05; 0: exactly at sigma)")
        sp.add_argument("--check", metavar="LMP",
                        help="LAMMPS binary: read the table back and print its error")

    s = sub.add_parser("ao", help="Asakura-Oosawa depletion attraction")
    common(s)
    s.add_argument("--q", type=float, required=True, help="size ratio sigma_p/sigma")
    s.add_argument("--eta", type=float, help="polymer reservoir packing fraction eta_p^r")
    s.add_argument("--depth", type=float,
                   help="instead of --eta: well depth |U(sigma)| in kT (eta_p^r = depth/(1+3/(2q)))")
    s.add_argument("--kT", type=float, default=1.0, help="energy unit kT (default 1)")

    s = sub.add_parser("sutherland", help="hard core + -epsilon (sigma/r)^n")
    common(s)
    s.add_argument("--n", type=float, required=True, help="exponent n")
    s.add_argument("--epsilon", type=float, default=1.0, help="contact depth (default 1)")
    s.add_argument("--rc", type=float, required=True, help="cutoff (> sigma)")
    s.add_argument("--shift", choices=["no", "yes", "both"], default="no",
                   help="subtract U(rc) so that U(rc) = 0 (both: two sections, the shifted "
                        "one's keyword ends in _shifted; default no)")

    a = p.parse_args(argv)
    positive("--sigma", a.sigma)
    if not (0 <= a.margin < 0.5):
        fail(f"--margin must be in [0, 0.5): an allowance below contact, not a core (got {a.margin})")
    if a.N < 2:
        fail(f"-N must be >= 2 (got {a.N})")
    sections = ao_sections(a) if a.model == "ao" else sutherland_sections(a)
    # the command that remakes this file, without the --check run
    made_by = list(argv)
    if a.check:
        k = made_by.index("--check") if "--check" in made_by else None
        made_by = made_by[:k] + made_by[k + 2:] if k is not None else \
            [w for w in made_by if not w.startswith("--check=")]
    write(a.output, sections, a, made_by)
    if a.check:
        check(a.output, sections, a, a.check)


if __name__ == "__main__":
    main(sys.argv[1:])
