/* ----------------------------------------------------------------------
   HARDSPHERE package: H_[2,VV]'s change over a local step from the
   clusters' terms. See hs_local_modified.h.
------------------------------------------------------------------------- */

#include "hs_local_modified.h"

#include "hs_local_forces.h"
#include "hs_potential.h"
#include "hs_step_view.h"
#include "hs_system.h"

#include "atom.h"
#include "error.h"
#include "force.h"
#include "neighbor.h"
#include "pair.h"

#include <algorithm>
#include <cmath>

using namespace LAMMPS_NS;

HSLocalModified::HSLocalModified(LAMMPS *lmp, HSSystem *s, HSPotential *p) :
    Pointers(lmp), sys(s), pot(p)
{
}

/* ----------------------------------------------------------------------
   V_CX, v^T V_CX'' v, F of V_CX and V_CX'' v on the owners, over the terms
   of begin() (pair and bond terms: the single path), at the positions
   xpos(owner) + (x[k] - x[owner]) of each local copy k (the image offset)
------------------------------------------------------------------------- */

template <class X, class V, class B>
void HSLocalModified::terms_eval(X xpos, V vel, B bvel, double &E, double &Q, double &Qbb)
{
  double **x = atom->x;
  const int *type = atom->type;
  const int nlocal = atom->nlocal;
  const int newton_pair = force->newton_pair, newton_bond = force->newton_bond;
  double **cutsq = force->pair ? force->pair->cutsq : nullptr;
  E = Q = Qbb = 0.0;
  for (auto &a : fc) a = {0.0, 0.0, 0.0};
  for (auto &a : kv) a = {0.0, 0.0, 0.0};
  const int nterm = (int) toff.size() - 1;
  for (int t = 0; t < nterm; t++) {
    if (toff[t + 1] - toff[t] != 2)
      error->one(FLERR, "Fix {} substep local: a term of {} atoms (only pair and bond terms "
                 "are supported by the local projection)", sys->style_name, toff[t + 1] - toff[t]);
    const int i = tloc[toff[t]], j = tloc[toff[t] + 1];
    const int oi = tatoms[toff[t]], oj = tatoms[toff[t] + 1];
    const bool pair = t < npair;
    if (!pair && textra[t] <= 0) continue;    // a broken bond
    const double *xi = xpos(oi), *xj = xpos(oj);
    double del[3];
    for (int d = 0; d < 3; d++)
      del[d] = (xi[d] + (x[i][d] - x[oi][d])) - (xj[d] + (x[j][d] - x[oj][d]));
    const double rsq = del[0] * del[0] + del[1] * del[1] + del[2] * del[2];
    double phi[3], w;
    if (pair) {
      if (rsq >= cutsq[type[i]][type[j]]) continue;
      pot->pair_term(i, j, textra[t], rsq, phi);
      w = (newton_pair || j < nlocal) ? 1.0 : 0.5;
    } else {
      pot->bond_term(textra[t], i, j, rsq, phi);
      w = newton_bond ? 1.0 : 0.5 * ((i < nlocal) + (j < nlocal));
    }
    const double r = sqrt(rsq);
    const double e[3] = {del[0] / r, del[1] / r, del[2] / r};
    const double *vi = vel(oi), *vj = vel(oj);
    const double vij[3] = {vi[0] - vj[0], vi[1] - vj[1], vi[2] - vj[2]};
    const double ev = e[0] * vij[0] + e[1] * vij[1] + e[2] * vij[2];
    const double vv = vij[0] * vij[0] + vij[1] * vij[1] + vij[2] * vij[2];
    const double pr = phi[1] / r;
    // V_t'' on x_i - x_j: phi'' e e^T + phi'/r (I - e e^T)
    double kvij[3];
    for (int d = 0; d < 3; d++) kvij[d] = phi[2] * e[d] * ev + pr * (vij[d] - e[d] * ev);
    E += w * phi[0];
    Q += w * (phi[2] * ev * ev + pr * (vv - ev * ev));
    const double *bi = bvel(oi), *bj = bvel(oj);
    const double bij[3] = {bi[0] - bj[0], bi[1] - bj[1], bi[2] - bj[2]};
    const double eb = e[0] * bij[0] + e[1] * bij[1] + e[2] * bij[2];
    const double bb = bij[0] * bij[0] + bij[1] * bij[1] + bij[2] * bij[2];
    Qbb += w * (phi[2] * eb * eb + pr * (bb - eb * eb));
    const int si = slot[oi], sj = slot[oj];
    for (int d = 0; d < 3; d++) {
      fc[si][d] -= w * phi[1] * e[d];
      fc[sj][d] += w * phi[1] * e[d];
      kv[si][d] += w * kvij[d];
      kv[sj][d] -= w * kvij[d];
    }
  }
}

/* ----------------------------------------------------------------------
   L = T_C + V_CX + dt^2/24 (2 Q - G) with the conservative forces cons()
   and fc, T the members' kinetic energy
------------------------------------------------------------------------- */

double HSLocalModified::local_L(double E, double Q, double T)
{
  const int *mask = atom->mask;
  const int gb = sys->groupbit;
  double G = 0.0;
  for (size_t s = 0; s < owners.size(); s++) {
    const int i = owners[s];
    if (!(mask[i] & gb)) continue;
    const double *F = cons(i);
    double g;
    if (is_mem[s])
      g = F[0] * F[0] + F[1] * F[1] + F[2] * F[2];
    else {
      const Vec &c = fc[s];
      g = 0.0;
      for (int d = 0; d < 3; d++) g += 2.0 * c[d] * (F[d] - c[d]) + c[d] * c[d];
    }
    G += g / sys->mass_of(i);
  }
  const double dt = sys->dtv;
  return T + E + dt * dt / 24.0 * (2.0 * Q - force->ftm2v * G);
}

/* ----------------------------------------------------------------------
   the terms of the members (local indices mem) in the current lists, and
   their owners: members first, then the partners
------------------------------------------------------------------------- */

void HSLocalModified::find_terms(HSStepView &eng)
{
  HSLocalForces &lf = eng.local_forces();
  lf.set_labels(nullptr);
  lf.terms(mem.data(), (int) mem.size());
  tloc = lf.term_local();
  toff = lf.term_offsets();
  textra = lf.term_extra();
  tatoms = lf.term_atoms();
  npair = lf.npair_last();
  terms_ncalls = neighbor->ncalls;

  if ((int) sstamp.size() < atom->nmax) {
    sstamp.assign(atom->nmax, 0u);
    slot.assign(atom->nmax, -1);
    sepoch = 0;
  }
  if (++sepoch == 0) {
    std::fill(sstamp.begin(), sstamp.end(), 0u);
    sepoch = 1;
  }
  owners.clear();
  is_mem.clear();
  auto add = [&](int i, bool member) {
    if (i < 0)
      error->one(FLERR, "Fix {} substep local: an atom of a collision cluster's terms is owned "
                 "by another rank", sys->style_name);
    if (sstamp[i] == sepoch) return;
    sstamp[i] = sepoch;
    slot[i] = (int) owners.size();
    owners.push_back(i);
    is_mem.push_back(member ? 1 : 0);
  };
  for (int m : mem) add(m, true);
  for (int o : tatoms) add(o, false);
  fc.assign(owners.size(), {0.0, 0.0, 0.0});
  kv.assign(owners.size(), {0.0, 0.0, 0.0});
}

/* ---------------------------------------------------------------------- */

void HSLocalModified::begin(HSStepView &eng)
{
  const int *mask = atom->mask;
  const tagint *tag = atom->tag;
  const int gb = sys->groupbit;
  mem.clear();
  cid.clear();
  mtag.clear();
  for (int c = 0; c < eng.nclusters(); c++)
    for (int m : eng.members(c)) {
      mem.push_back(m);
      cid.push_back(c);
      mtag.push_back(tag[m]);
    }
  find_terms(eng);

  // the step's start: x0 and the conservative map's start velocities
  // (held forces: after their first half kick) and forces. The lists hold
  // every pair within cutoff + skin: every atom that can share a term with
  // a member during the step is an owner here
  conservative_state(eng, true);
  static const double zero[3] = {0.0, 0.0, 0.0};
  double E, Q, Qbb;
  terms_eval([&](int o) { return eng.start_x(o); },
             [&](int o) { return (mask[o] & gb) ? vcons(o) : zero; },
             [&](int) { return zero; }, E, Q, Qbb);
  double T = 0.0;
  for (int m : mem)
    if (mask[m] & gb) {
      const double *v = vcons(m);
      T += sys->mass_of(m) * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    }
  T *= 0.5 * force->mvv2e;
  L0 = local_L(E, Q, T);
  ptag.clear();
  pstart.clear();
  for (size_t s = 0; s < owners.size(); s++) {
    const int p = owners[s];
    if (is_mem[s] || !(mask[p] & gb)) continue;
    Start st;
    eng.partner_kicks(p, st.d1.data(), st.d2.data());
    const double *v0 = vcons(p), *F = cons(p);
    for (int d = 0; d < 3; d++) {
      st.v0[d] = v0[d];
      st.fr0[d] = F[d] - fc[s][d];
    }
    ptag.push_back(tag[p]);
    pstart.push_back(st);
  }
}

/* ----------------------------------------------------------------------
   the conservative forces and velocities of the members and partners
   (and, at the end, of the start's partners) at the step's start (x0, v0,
   atom->f of the start) or end (x, v, f now). Without held forces: f and v
   themselves. With held (thermostat) forces, the conservative map is
   between the held half kicks: velocities v0 + dt/2 h / m at the start
   and v - dt/2 h / m at the end, h = f - F_cons; F_cons of the members and
   partners from all their terms (restricted evaluations, at x0 for the
   start)
------------------------------------------------------------------------- */

void HSLocalModified::conservative_state(HSStepView &eng, bool at_start)
{
  double **x = atom->x, **v = atom->v, **f = atom->f;
  const int *mask = atom->mask;
  const int gb = sys->groupbit;
  if ((int) cstamp.size() < atom->nmax) {
    cstamp.assign(atom->nmax, 0u);
    fcons_.resize(atom->nmax);
    vcons_.resize(atom->nmax);
    cepoch = 0;
  }
  if (++cepoch == 0) {
    std::fill(cstamp.begin(), cstamp.end(), 0u);
    cepoch = 1;
  }
  std::vector<int> atoms;
  auto note = [&](int i) {
    if (cstamp[i] == cepoch) return;
    cstamp[i] = cepoch;
    atoms.push_back(i);
  };
  for (int o : owners) note(o);
  if (!at_start)
    for (int p : pidx) note(p);
  for (int i : atoms)
    for (int d = 0; d < 3; d++) {
      fcons_[i][d] = f[i][d];
      vcons_[i][d] = at_start ? eng.start_v(i)[d] : v[i][d];
    }
  if (!sys->nheld) return;

  // F_cons of the group's members and partners: a restricted evaluation of
  // all their terms (at the start with every atom of those terms at x0)
  std::vector<int> set;
  for (int i : atoms)
    if (mask[i] & gb) set.push_back(i);
  if (set.empty()) return;
  HSLocalForces &lf = eng.local_forces();
  lf.set_labels(nullptr);
  std::vector<int> moved;
  std::vector<Vec> saved;
  if (at_start) {
    lf.terms(set.data(), (int) set.size());
    std::vector<int> own = lf.term_atoms();
    std::sort(own.begin(), own.end());
    own.erase(std::unique(own.begin(), own.end()), own.end());
    for (int o : own) {
      if (o < 0) continue;
      moved.push_back(o);
      saved.push_back({x[o][0], x[o][1], x[o][2]});
      eng.put_x(o, eng.start_x(o));
    }
  }
  lf.compute(set.data(), (int) set.size(), false);
  double **fl = lf.forces();
  const double dtf = sys->dtf;
  for (int i : set) {
    const double s = (at_start ? dtf : -dtf) / sys->mass_of(i);
    for (int d = 0; d < 3; d++) {
      fcons_[i][d] = fl[i][d];
      vcons_[i][d] += s * (f[i][d] - fl[i][d]);
    }
  }
  for (size_t k = 0; k < moved.size(); k++) eng.put_x(moved[k], saved[k].data());
}

/* ---------------------------------------------------------------------- */

void HSLocalModified::end(HSStepView &eng, double &A, double &B, double &C0)
{
  double **x = atom->x;
  const int *mask = atom->mask;
  const int gb = sys->groupbit;
  for (size_t k = 0; k < mtag.size(); k++) mem[k] = eng.owned(mtag[k]);
  // the start's terms and owners still hold unless the lists were rebuilt
  // (then atoms may also have been sorted)
  if (neighbor->ncalls != terms_ncalls)
    find_terms(eng);
  else {
    fc.assign(owners.size(), {0.0, 0.0, 0.0});
    kv.assign(owners.size(), {0.0, 0.0, 0.0});
  }
  pidx.resize(ptag.size());
  for (size_t k = 0; k < ptag.size(); k++) pidx[k] = eng.owned(ptag[k]);
  conservative_state(eng, false);

  // b of the projection on the members (slot order: members first)
  relative(eng);
  static const double zero[3] = {0.0, 0.0, 0.0};
  double E, Q, Qbb;
  terms_eval([&](int o) { return x[o]; }, [&](int o) { return (mask[o] & gb) ? vcons(o) : zero; },
             [&](int o) {
               const int sl = slot[o];
               return is_mem[sl] ? rel[sl].data() : zero;
             },
             E, Q, Qbb);
  const double mvv2e = force->mvv2e, dt = sys->dtv;
  double T = 0.0;
  for (int m : mem)
    if (mask[m] & gb) {
      const double *vm = vcons(m);
      T += sys->mass_of(m) * (vm[0] * vm[0] + vm[1] * vm[1] + vm[2] * vm[2]);
    }
  T *= 0.5 * mvv2e;
  const double L1 = local_L(E, Q, T);

  // what the Phi_H1 flows did to H~2: the partners' kinetic energy and
  // dt^2/6 (V_R'' v)_p . dv_p, (V_R'' v)_p = -(F^R_p(end) - F^R_p(start)) / dt
  double dTP = 0.0, gk = 0.0;
  for (size_t k = 0; k < ptag.size(); k++) {
    const int p = pidx[k];
    const Start &st = pstart[k];
    const int sl = slot_of(p);
    const double *vp = vcons(p), *F = cons(p);
    double kin = 0.0;
    for (int d = 0; d < 3; d++) {
      const double a = st.v0[d] + st.d1[d], b = vp[d] - st.d2[d];
      kin += a * a - st.v0[d] * st.v0[d] + vp[d] * vp[d] - b * b;
      const double fr1 = F[d] - (sl >= 0 ? fc[sl][d] : 0.0);
      gk += -(fr1 - st.fr0[d]) / dt * (st.d1[d] + st.d2[d]);
    }
    dTP += 0.5 * mvv2e * sys->mass_of(p) * kin;
  }
  C0 = L1 - L0 + dTP + dt * dt / 6.0 * gk;

  // the projection's coefficients
  double mb2 = 0.0, bkv = 0.0;
  for (size_t k = 0; k < mem.size(); k++) {
    const int m = mem[k];
    if (!(mask[m] & gb)) continue;
    const Vec &kvm = kv[slot[m]];
    for (int d = 0; d < 3; d++) {
      mb2 += sys->mass_of(m) * rel[k][d] * rel[k][d];
      bkv += rel[k][d] * kvm[d];
    }
  }
  A = 0.5 * mvv2e * mb2 + dt * dt / 12.0 * Qbb;
  B = mvv2e * mb2 + dt * dt / 6.0 * bkv;
}

// b = v - the cluster's centre-of-mass velocity for the members (v itself
// for a one-sphere cluster: a wall contact); zero outside the group
void HSLocalModified::relative(HSStepView &eng)
{
  const int *mask = atom->mask;
  const int gb = sys->groupbit;
  const int ncl = eng.nclusters();
  std::vector<Vec> pc(ncl, {0.0, 0.0, 0.0});
  std::vector<double> mc(ncl, 0.0);
  std::vector<int> nc(ncl, 0);
  for (size_t k = 0; k < mem.size(); k++) {
    const int m = mem[k];
    if (!(mask[m] & gb)) continue;
    const double ms = sys->mass_of(m);
    for (int d = 0; d < 3; d++) pc[cid[k]][d] += ms * vcons(m)[d];
    mc[cid[k]] += ms;
    nc[cid[k]]++;
  }
  rel.assign(mem.size(), {0.0, 0.0, 0.0});
  for (size_t k = 0; k < mem.size(); k++) {
    const int m = mem[k];
    if (!(mask[m] & gb)) continue;
    const int c = cid[k];
    for (int d = 0; d < 3; d++) rel[k][d] = vcons(m)[d] - (nc[c] > 1 ? pc[c][d] / mc[c] : 0.0);
  }
}

// v_i -> v_i + beta b_i with the b of end()
void HSLocalModified::scale(HSStepView &eng, double beta)
{
  double **v = atom->v;
  const int *mask = atom->mask;
  for (size_t k = 0; k < mem.size(); k++) {
    const int m = mem[k];
    if (!(mask[m] & sys->groupbit)) continue;
    const double vn[3] = {v[m][0] + beta * rel[k][0], v[m][1] + beta * rel[k][1],
                          v[m][2] + beta * rel[k][2]};
    eng.put_v(m, vn);
  }
}
