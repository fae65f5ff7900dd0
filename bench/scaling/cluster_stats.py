#!/usr/bin/python3
"""bench/scaling: how large would the clusters of `substep local` be?
cluster_stats.py DATAFILE [dt] [diameter] [rc] [windows] [rule]
rule: issue (default) or frozen

Reads an equilibrated data file written by in.make-fluid (Atoms + Velocities),
and for `windows` consecutive windows [k dt, (k+1) dt] of the straight-line
motion q + t v (an estimate of one step: forces bend the paths by O(dt^2)):
  members  = spheres that touch (|q_ij(t)| = diameter) in the window,
  clusters = connected components of contacts and of pair terms (r < rc) that
             involve a member: the rule "clusters that share an atom are one
             cluster" of issue 10 (partners of two members join their clusters).
With rule "frozen" (the frozen-partner splitting of
unittest/math/test_local_splitting.cpp: partners do not move inside Phi_C) only
contacts and pair terms between two members join clusters.
Prints per window: contacts, members, clusters, largest cluster (atoms, members),
fraction of all atoms in clusters, and an estimate of the pair terms Phi_C
evaluates: sum over clusters of contacts_K x (pair terms with a member of K), in
units of a full force evaluation (N x neighbours / 2 pair terms).
Independent of the package (numpy + scipy's periodic KD tree)."""
import sys
import numpy as np
from scipy.spatial import cKDTree

path = sys.argv[1]
dt = float(sys.argv[2]) if len(sys.argv) > 2 else 0.005
diam = float(sys.argv[3]) if len(sys.argv) > 3 else 1.0
rc = float(sys.argv[4]) if len(sys.argv) > 4 else 2.5
nwin = int(sys.argv[5]) if len(sys.argv) > 5 else 5
rule = sys.argv[6] if len(sys.argv) > 6 else "issue"

lines = open(path).read().splitlines()
box = np.zeros(3)
lo = np.zeros(3)
for l in lines[:40]:
    for k, ax in enumerate("xyz"):
        if l.strip().endswith(f"{ax}lo {ax}hi"):
            a, b = map(float, l.split()[:2])
            lo[k], box[k] = a, b - a
def section(name):
    i = next(k for k, l in enumerate(lines) if l.strip().startswith(name))
    rows, k = [], i + 2
    while k < len(lines) and lines[k].strip():
        rows.append(lines[k].split())
        k += 1
    return rows
atoms = section("Atoms")
vels = section("Velocities")
n = len(atoms)
tag_x = {int(r[0]): [float(r[2]), float(r[3]), float(r[4])] for r in atoms}
tag_v = {int(r[0]): [float(r[1]), float(r[2]), float(r[3])] for r in vels}
tags = sorted(tag_x)
x0 = (np.array([tag_x[t] for t in tags]) - lo) % box
v = np.array([tag_v[t] for t in tags])

def find(par, i):
    while par[i] != i:
        par[i] = par[par[i]]
        i = par[i]
    return i

print(f"# {path}: N {n}, box {box[0]:.3f}, dt {dt}, diameter {diam}, rc {rc}, rule {rule}")
print("# window contacts members clusters largest_atoms largest_members frac_atoms_in_clusters "
      "phiC_pair_terms_in_force_evals")
vmax = np.max(np.linalg.norm(v, axis=1))
for w in range(nwin):
    x = (x0 + w * dt * v) % box
    tree = cKDTree(x, boxsize=box)
    cand = tree.query_pairs(diam + 2 * vmax * dt, output_type="ndarray")
    d = x[cand[:, 0]] - x[cand[:, 1]]
    d -= box * np.round(d / box)
    dv = v[cand[:, 0]] - v[cand[:, 1]]
    # |d + t dv|^2 = diam^2 for t in (0, dt], approaching
    a = (dv * dv).sum(1)
    b = 2 * (d * dv).sum(1)
    c = (d * d).sum(1) - diam * diam
    disc = b * b - 4 * a * c
    ok = (disc >= 0) & (b < 0) & (a > 0)
    t1 = np.where(ok, (-b - np.sqrt(np.maximum(disc, 0))) / (2 * np.where(a > 0, a, 1)), np.inf)
    hit = ok & (t1 <= dt) & (t1 > -1e-12)
    contacts = cand[hit]
    member = np.zeros(n, bool)
    member[contacts.ravel()] = True
    par = list(range(n))
    for i, j in contacts:
        ri, rj = find(par, i), find(par, j)
        par[ri] = rj
    pairs = tree.query_pairs(rc, output_type="ndarray")
    vc = pairs[member[pairs[:, 0]] | member[pairs[:, 1]]]
    touched = member.copy()
    if rule == "issue":
        touched[vc.ravel()] = True
        link = vc
    else:    # frozen: only terms between two members couple flows
        link = vc[member[vc[:, 0]] & member[vc[:, 1]]]
    for i, j in link:
        ri, rj = find(par, i), find(par, j)
        par[ri] = rj
    roots = np.array([find(par, i) for i in range(n)])
    ids = roots[touched]
    if len(ids) == 0:
        print(w, 0, 0, 0, 0, 0, 0.0, 0.0)
        continue
    uniq, size = np.unique(ids, return_counts=True)
    msize = {u: 0 for u in uniq}
    for i in np.nonzero(member)[0]:
        msize[roots[i]] += 1
    ncont = {u: 0 for u in uniq}
    for i, j in contacts:
        ncont[roots[i]] += 1
    # pair terms of V_C per cluster: pairs (within rc) with a member of K
    nterm = {u: 0 for u in uniq}
    for i, j in vc:
        nterm[roots[i] if member[i] else roots[j]] += 1
    full = len(pairs)
    cost = sum(ncont[u] * nterm[u] for u in uniq) / full
    big = uniq[np.argmax(size)]
    print(w, len(contacts), int(member.sum()), len(uniq), int(size.max()), msize[big],
          f"{touched.sum() / n:.3f}", f"{cost:.3f}")
