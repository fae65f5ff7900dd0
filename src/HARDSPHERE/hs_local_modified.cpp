/* ----------------------------------------------------------------------
   HARDSPHERE package: H_[2,VV]'s change over a local step from the
   clusters' terms. See hs_local_modified.h.
------------------------------------------------------------------------- */

#include "hs_local_modified.h"

#include "hs_local_forces.h"
#include "hs_mpi.h"
#include "hs_potential.h"
#include "hs_step_view.h"
#include "hs_stamp.h"
#include "hs_system.h"

#include "atom.h"
#include "domain.h"
#include "comm.h"
#include "memory.h"
#include "error.h"
#include "force.h"
#include "neighbor.h"
#include "pair.h"

#include <algorithm>
#include <cmath>
#include <mpi.h>

using namespace LAMMPS_NS;

HSLocalModified::HSLocalModified(LAMMPS *lmp, HSSystem *s, HSPotential *p) :
    Pointers(lmp), sys(s), pot(p)
{
}

HSLocalModified::~HSLocalModified()
{
  memory->destroy(red);
  memory->destroy(fwd);
  memory->destroy(xs);
  memory->destroy(fs);
}

// the per-copy columns (kept zero outside the rows in use: a reverse
// communication sums every ghost row)
void HSLocalModified::grow()
{
  if (atom->nmax <= nmax) return;
  memory->destroy(red);
  memory->destroy(fwd);
  nmax = atom->nmax;
  memory->create(red, nmax, 7, "hs_local_modified:red");
  memory->create(fwd, nmax, 7, "hs_local_modified:fwd");
  for (int i = 0; i < nmax; i++)
    for (int d = 0; d < 7; d++) red[i][d] = fwd[i][d] = 0.0;
  red_rows.clear();
  if ((int) ostamp.size() < nmax) ostamp.resize(nmax, 0u);
  if ((int) cstamp.size() < nmax) {
    cstamp.resize(nmax, 0u);
    fcons_.resize(nmax);
    vcons_.resize(nmax);
  }
}

double HSLocalModified::memory_usage() const
{
  const auto bytes = [](const auto &vec) { return HardSphere::capacity_bytes(vec); };
  double b = (double) nmax * 14 * sizeof(double);    // red, fwd
  b += (double) nmax_xs * 6 * sizeof(double);         // xs, fs
  b += bytes(mtag) + bytes(mem) + bytes(cid) + bytes(ptag) + bytes(pstart) + bytes(remap_ms) +
      bytes(remap_ps) + bytes(remap_st) + bytes(remap_out) + bytes(remap_all) + bytes(pidx) +
      bytes(tloc) + bytes(toff) + bytes(textra) + bytes(tcopies) + bytes(owners) +
      bytes(is_mem) + bytes(ghosted) + bytes(ostamp) + bytes(rel) + bytes(red_rows) +
      bytes(pmark) + bytes(fcons_) + bytes(vcons_) + bytes(cstamp) + bytes(cs_atoms) +
      bytes(cs_set) + bytes(cs_moved) + bytes(cs_saved);
  return b;
}

void HSLocalModified::zero_red()
{
  for (int l : red_rows)
    for (int d = 0; d < 7; d++) red[l][d] = 0.0;
  red_rows.clear();
}

/* ----------------------------------------------------------------------
   V_CX, v^T V_CX'' v over this rank's share of the terms of find_terms()
   (pair and bond terms: the single path), each at its copies' positions
   xpos(copy) with the velocities and projection directions forwarded to
   the copies (fwd); F of V_CX and V_CX'' v summed on the copies and
   reversed into the owners (red)
------------------------------------------------------------------------- */

template <bool WITH_B, class X>
void HSLocalModified::terms_eval(X xpos, double &E, double &Q, double &Qbb, bool flags)
{
  const int *type = atom->type, *mask = atom->mask;
  const int gb = sys->groupbit;
  const int nlocal = atom->nlocal;
  const int newton_pair = force->newton_pair, newton_bond = force->newton_bond;
  const bool bond_single = pot->bond_by_single();
  double **cutsq = force->pair ? force->pair->cutsq : nullptr;
  static const double zero[3] = {0.0, 0.0, 0.0};
  E = Q = Qbb = 0.0;
  zero_red();
  // lj/cut: pair_term()'s arithmetic inline (a call per term was ~30 % of
  // this loop's instructions); else pair_term(). Either takes up changed
  // coefficients first (begin_terms())
  const HardSphere::LJCutTable ljt = pot->lj_cut_table();
  const double *special_lj = force->special_lj;
  const int nterm = (int) toff.size() - 1;
  // the terms come cluster by cluster, their copies' rows all over memory;
  // the order is fixed (the sums' round-off), so the rows of the term
  // PREFETCH_AHEAD on are fetched while this one is evaluated (on the
  // 32000-bead melt the rows outgrow the caches: this loop's cost per
  // collision was 1.5x that at 4000 beads)
  const int ahead = HardSphere::PREFETCH_AHEAD;
  for (int t = 0; t < nterm; t++) {
    if (t + ahead < nterm) {
      const int o = toff[t + ahead];
      for (int l : {tloc[o], tloc[o + 1]}) {
        __builtin_prefetch(xpos(l));
        HardSphere::prefetch_row(fwd[0], 7, l);
        HardSphere::prefetch_row(red[0], 7, l, true);
      }
    }
    const bool pair = t < npair;
    if (!pair && (toff[t + 1] - toff[t] != 2 || !bond_single)) {
      general_term<WITH_B>(t, xpos, E, Q, Qbb);
      continue;
    }
    const int i = tloc[toff[t]], j = tloc[toff[t] + 1];
    if (!pair && textra[t] <= 0) continue;    // a broken bond
    const double *xi = xpos(i), *xj = xpos(j);
    const double del[3] = {xi[0] - xj[0], xi[1] - xj[1], xi[2] - xj[2]};
    const double rsq = del[0] * del[0] + del[1] * del[1] + del[2] * del[2];
    double phi[5], w;
    const double r = sqrt(rsq);
    if (pair) {
      const int ti = type[i], tj = type[j];
      if (rsq >= cutsq[ti][tj]) continue;
      if (ljt.coef) {
        const double *c = ljt.of(ti, tj);
        const double fl = special_lj[textra[t]];
        HardSphere::lj_cut_phi01(c, fl, rsq, r, phi);
        HardSphere::lj_derivs(c[5], c[6], fl, rsq, r, 2, phi);
      } else
        pot->pair_term(i, j, textra[t], rsq, phi);
      w = (newton_pair || j < nlocal) ? 1.0 : 0.5;
    } else {
      pot->bond_term(textra[t], i, j, rsq, phi);
      w = newton_bond ? 1.0 : 0.5 * ((i < nlocal) + (j < nlocal));
    }
    const double e[3] = {del[0] / r, del[1] / r, del[2] / r};
    // (rows by offset, HardSphere::row_at())
    const double *fi = HardSphere::row_at(fwd[0], 7, i), *fj = HardSphere::row_at(fwd[0], 7, j);
    const double *vi = (mask[i] & gb) ? fi : zero, *vj = (mask[j] & gb) ? fj : zero;
    const double vij[3] = {vi[0] - vj[0], vi[1] - vj[1], vi[2] - vj[2]};
    const double ev = e[0] * vij[0] + e[1] * vij[1] + e[2] * vij[2];
    const double vv = vij[0] * vij[0] + vij[1] * vij[1] + vij[2] * vij[2];
    const double pr = phi[1] / r;
    // V_t'' on x_i - x_j: phi'' e e^T + phi'/r (I - e e^T)
    double kvij[3];
    for (int d = 0; d < 3; d++) kvij[d] = phi[2] * e[d] * ev + pr * (vij[d] - e[d] * ev);
    E += w * phi[0];
    Q += w * (phi[2] * ev * ev + pr * (vv - ev * ev));
    if (WITH_B) {
      const double *bi = (mask[i] & gb) ? fi + 3 : zero, *bj = (mask[j] & gb) ? fj + 3 : zero;
      const double bij[3] = {bi[0] - bj[0], bi[1] - bj[1], bi[2] - bj[2]};
      const double eb = e[0] * bij[0] + e[1] * bij[1] + e[2] * bij[2];
      const double bb = bij[0] * bij[0] + bij[1] * bij[1] + bij[2] * bij[2];
      Qbb += w * (phi[2] * eb * eb + pr * (bb - eb * eb));
    }
    double *ri = HardSphere::row_at(red[0], 7, i), *rj = HardSphere::row_at(red[0], 7, j);
    for (int d = 0; d < 3; d++) {
      ri[d] -= w * phi[1] * e[d];
      rj[d] += w * phi[1] * e[d];
      ri[3 + d] += w * kvij[d];
      rj[3 + d] -= w * kvij[d];
    }
  }
  red_rows.insert(red_rows.end(), tcopies.begin(), tcopies.end());
  if (flags) mark_copies();
  sys->reverse_columns(red, flags ? 7 : 6, &red_rows);
}

/* ----------------------------------------------------------------------
   a term that is not radial (angle, dihedral, improper; a bond whose style
   has no single()): its energy and forces from its style's compute() on
   that term alone (HSLocalForces::bonded_term()), V_t'' v and V_t'' b by
   central differences of those forces along v and b, F(x +- s w), with a
   displacement s |w|max = 1e-4 L (L: HSPotential's length scale, a tenth
   of the shortest cutoff or bond length): truncation (s|w|/L)^2 / 6 ~ 2e-9
   relative, the positions' round-off |x| eps / (s|w|) ~ 1e-10. These
   enter L at dt^2/12, far below the ledger's O(dt^4); the global path's
   five-point stencil (doc "FDIFF") would cost four evaluations instead of
   two. Each term takes its own step from its copies' velocities alone, the
   same on every rank that lists it. With newton_bond off the style adds
   forces to owned copies only and tallies the owned share of the energy, as
   LAMMPS does: the sums over the ranks are whole
------------------------------------------------------------------------- */

template <bool WITH_B, class X>
void HSLocalModified::general_term(int t, X xpos, double &E, double &Q, double &Qbb)
{
  const int *mask = atom->mask;
  const int gb = sys->groupbit;
  const int o = toff[t], w = toff[t + 1] - o;
  if (w > 4)
    error->one(FLERR, "Fix {} substep local: internal error: a bonded term of {} atoms",
               sys->style_name, w);
  int kind = 0;
  while (kind < 3 && t >= kend[kind]) kind++;
  const int *a = &tloc[o];
  const int type = textra[t];
  if (type <= 0) return;    // (a broken bond)
  if (!xs || nmax_xs < nmax) {
    memory->destroy(xs);
    memory->destroy(fs);
    nmax_xs = nmax;
    memory->create(xs, nmax_xs, 3, "hs_local_modified:xs");
    memory->create(fs, nmax_xs, 3, "hs_local_modified:fs");
  }
  static const double zero[3] = {0.0, 0.0, 0.0};
  const double *vk[4], *bk[4];
  double vmax = 0.0, bmax = 0.0;
  for (int k = 0; k < w; k++) {
    const bool in = mask[a[k]] & gb;
    const double *row = HardSphere::row_at(fwd[0], 7, a[k]);
    vk[k] = in ? row : zero;
    bk[k] = (WITH_B && in) ? row + 3 : zero;
    vmax = std::max(vmax, sqrt(vk[k][0] * vk[k][0] + vk[k][1] * vk[k][1] + vk[k][2] * vk[k][2]));
    bmax = std::max(bmax, sqrt(bk[k][0] * bk[k][0] + bk[k][1] * bk[k][1] + bk[k][2] * bk[k][2]));
  }
  HSLocalForces &lf = *terms_lf;
  // forces of the term at x + s dir, into F[k]; its energy tally
  auto at = [&](double s, const double *const *dir, double (*F)[3]) {
    for (int k = 0; k < w; k++) {
      const double *x0 = xpos(a[k]);
      for (int d = 0; d < 3; d++) {
        xs[a[k]][d] = x0[d] + s * dir[k][d];
        fs[a[k]][d] = 0.0;
      }
    }
    const double e = lf.bonded_term(kind, a, type, xs, fs);
    for (int k = 0; k < w; k++)
      for (int d = 0; d < 3; d++) F[k][d] = fs[a[k]][d];
    return e;
  };
  double F0[4][3];
  E += at(0.0, vk, F0);
  for (int k = 0; k < w; k++) {
    double *r = HardSphere::row_at(red[0], 7, a[k]);
    for (int d = 0; d < 3; d++) r[d] += F0[k][d];
  }
  // H[k] = (V_t'' dir)_k from F(x +- s dir)
  const double L = pot->length();
  auto hess = [&](const double *const *dir, double dmax, double (*H)[3]) {
    double Fp[4][3], Fm[4][3];
    const double s = FD_STEP * L / dmax;
    at(s, dir, Fp);
    at(-s, dir, Fm);
    for (int k = 0; k < w; k++)
      for (int d = 0; d < 3; d++) H[k][d] = -(Fp[k][d] - Fm[k][d]) / (2.0 * s);
  };
  if (vmax > 0.0) {
    double H[4][3];
    hess(vk, vmax, H);
    for (int k = 0; k < w; k++) {
      double *r = HardSphere::row_at(red[0], 7, a[k]);
      for (int d = 0; d < 3; d++) {
        r[3 + d] += H[k][d];
        Q += vk[k][d] * H[k][d];
      }
    }
  }
  if (WITH_B && bmax > 0.0) {
    double H[4][3];
    hess(bk, bmax, H);
    for (int k = 0; k < w; k++)
      for (int d = 0; d < 3; d++) Qbb += bk[k][d] * H[k][d];
  }
}

/* ----------------------------------------------------------------------
   this rank's part of L = T_C + V_CX + dt^2/24 (2 Q - G) with the
   conservative forces cons() and F of V_CX (red, owners), T the members'
   kinetic energy
------------------------------------------------------------------------- */

double HSLocalModified::local_L(double E, double Q, double T)
{
  const int *mask = atom->mask;
  const int gb = sys->groupbit;
  double G = 0.0;
  const size_t no = owners.size();
  for (size_t s = 0; s < no; s++) {
    const int i = owners[s];
    // (members in cluster order: rows all over memory, as in terms_eval())
    if (s + HardSphere::PREFETCH_AHEAD < no) {
      const int n = owners[s + HardSphere::PREFETCH_AHEAD];
      __builtin_prefetch(cons(n));
      HardSphere::prefetch_row(red[0], 7, n);
    }
    if (!(mask[i] & gb)) continue;
    const double *F = cons(i);
    double g;
    if (is_mem[s])
      g = F[0] * F[0] + F[1] * F[1] + F[2] * F[2];
    else {
      const double *c = red[i];
      g = 0.0;
      for (int d = 0; d < 3; d++) g += 2.0 * c[d] * (F[d] - c[d]) + c[d] * c[d];
    }
    G += g / sys->mass_of(i);
  }
  const double dt = sys->dtv;
  return T + E + dt * dt / 24.0 * (2.0 * Q - force->ftm2v * G);
}

/* ----------------------------------------------------------------------
   the terms of the members (owned local indices mem, collective): this
   rank's share of them (each term is listed on one rank, or with newton
   off on two with half weights), and the owned atoms in a term on any
   rank (a flag reversed into the owners): members first, then partners
------------------------------------------------------------------------- */

void HSLocalModified::list_terms(HSStepView &eng)
{
  grow();
  HSLocalForces &lf = eng.local_forces();
  lf.set_labels(nullptr);
  lf.terms(mem.data(), (int) mem.size());
  npair = lf.npair_last();
  for (int b = 0; b < 4; b++) kend[b] = lf.kind_end(b);
  terms_lf = &lf;
  lf.take_terms(tloc, toff, textra);
  terms_ncalls = neighbor->ncalls;

  // each copy in a term once, by stamp (not a sort of the ~2 x terms
  // entries: 4.6 % of a pcva step at 32000 atoms); its order only marks rows
  tcopies.clear();
  HardSphere::bump_epoch(oepoch, ostamp);
  for (int l : tloc)
    if (ostamp[l] != oepoch) {
      ostamp[l] = oepoch;
      tcopies.push_back(l);
    }
}

// the owners from the flags (red column 6) reversed into them: members in
// mem's order, then partners in increasing local index (marked, then one
// scan of the marked range: a sort of ~10 partners per member cost 0.9 % of
// a pcva step)
void HSLocalModified::owners_from_flags()
{
  const int nlocal = atom->nlocal;
  HardSphere::bump_epoch(oepoch, ostamp);
  owners.clear();
  is_mem.clear();
  ghosted.clear();
  for (int m : mem)
    if (ostamp[m] != oepoch) {
      ostamp[m] = oepoch;
      owners.push_back(m);
      is_mem.push_back(1);
    }
  if ((int) pmark.size() < nlocal) pmark.resize(nlocal, 0);
  int lo = nlocal, hi = -1;
  for (int l : red_rows)
    if (l < nlocal && red[l][6] > 0.0 && ostamp[l] != oepoch) {
      pmark[l] = 1;
      lo = std::min(lo, l);
      hi = std::max(hi, l);
    }
  for (int p = lo; p <= hi; p++)
    if (pmark[p]) {
      pmark[p] = 0;
      owners.push_back(p);
      is_mem.push_back(0);
    }
  for (int o : owners)
    if (red[o][6] >= GHOST_COPY) ghosted.push_back(o);
}

// the flag of each copy in this rank's terms (red column 6, reversed into
// the owners by the caller): 1 for an owned copy, GHOST_COPY for a ghost
// one, so that the sum an owner gets says both that it is in a term
// somewhere and whether a ghost copy of it is (forward_state() sends it)
void HSLocalModified::mark_copies()
{
  const int nlocal = atom->nlocal;
  for (int l : tcopies) red[l][6] = l < nlocal ? 1.0 : GHOST_COPY;
}

void HSLocalModified::find_terms(HSStepView &eng)
{
  list_terms(eng);
  zero_red();
  red_rows.insert(red_rows.end(), tcopies.begin(), tcopies.end());
  mark_copies();
  sys->reverse_columns(red, 7, &red_rows);
  owners_from_flags();
  zero_red();
}

/* ----------------------------------------------------------------------
   the owners' velocities (conservative map) and projection directions to
   their ghost copies
------------------------------------------------------------------------- */

void HSLocalModified::forward_state(bool with_rel)
{
  for (size_t s = 0; s < owners.size(); s++) {
    const int i = owners[s];
    for (int d = 0; d < 3; d++) {
      fwd[i][d] = vcons(i)[d];
      fwd[i][3 + d] = (with_rel && is_mem[s]) ? rel[s][d] : 0.0;
    }
  }
  // only the rows of owners with a ghost copy in a term (owners_from_flags()):
  // the ghosts terms_eval() reads are copies of them (sparse forward,
  // hs_system.h). Sending every owner's row, about half of all atoms at the
  // fluid's collision rate, cost as much as a full forward
  sys->forward_columns(fwd, 6, nullptr, 0, &ghosted);
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
  ncl = eng.nclusters();

  // the step's start: x0 and the conservative map's start velocities
  // (held forces: after their first half kick) and forces. The lists hold
  // every pair within cutoff + skin: every atom that can share a term with
  // a member during the step has a copy here
  double E, Q, Qbb;
  const double *const *x0 = eng.start_x_rows();
  auto xstart = [x0](int l) { return x0[l]; };
  if (sys->nheld) {
    find_terms(eng);
    conservative_state(eng, true);
    forward_state(false);
    terms_eval<false>(xstart, E, Q, Qbb, false);
  } else {
    // the conservative map starts from v0 itself, which every copy has
    // (the engine forwards v at the step's start): no forward, and the
    // owners' flags travel with the terms' sums (one reverse)
    list_terms(eng);
    const double *const *v0 = eng.start_v_rows();
    for (int l : tcopies)
      for (int d = 0; d < 3; d++) {
        fwd[l][d] = v0[l][d];
        fwd[l][3 + d] = 0.0;
      }
    terms_eval<false>(xstart, E, Q, Qbb, true);
    owners_from_flags();
    conservative_state(eng, true);
  }
  double T = 0.0;
  for (int m : mem)
    if (mask[m] & gb) {
      const double *v = vcons(m);
      T += sys->mass_of(m) * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    }
  T *= 0.5 * force->mvv2e;
  L0 = local_L(E, Q, T) + const_energy(eng, true);
  mstart.clear();
  if (held_work)
    for (int m : mem) {
      MemberStart ms{};
      if (mask[m] & gb) held_state(eng, m, eng.start_x(m), ms.g0, ms.q0);
      mstart.push_back(ms);
    }
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
      st.fr0[d] = F[d] - red[p][d];
    }
    ptag.push_back(tag[p]);
    pstart.push_back(st);
  }
  zero_red();
}

/* ----------------------------------------------------------------------
   the members' one-atom terms of constant force F (fix gravity: F = m g),
   V = -F.q, in V_C: this rank's members at the step's start (x0, with the
   image flags of the start: begin() runs before LAMMPS' reneighboring) or
   end (x and image now), unwrapped, so that a member that crosses a
   periodic face along F changes it by its displacement only
------------------------------------------------------------------------- */

double HSLocalModified::const_energy(HSStepView &eng, bool at_start) const
{
  const int *mask = atom->mask;
  const int gb = sys->groupbit;
  double V = 0.0, fc[3], q[3];
  for (int m : mem) {
    if (!(mask[m] & gb)) continue;
    eng.const_force(m, fc);
    if (fc[0] == 0.0 && fc[1] == 0.0 && fc[2] == 0.0) continue;
    domain->unmap(at_start ? eng.start_x(m) : atom->x[m], atom->image[m], q);
    V -= fc[0] * q[0] + fc[1] * q[1] + fc[2] * q[2];
  }
  return V;
}

/* ----------------------------------------------------------------------
   the conservative forces and velocities of the owners (and, at the end,
   of the start's partners) at the step's start (x0, v0, atom->f of the
   start) or end (x, v, f now). Without held forces: f and v themselves.
   With held (thermostat) forces, the conservative map is between the held
   half kicks: velocities v0 + dt/2 h / m at the start and v - dt/2 h / m
   at the end, h = f - F_cons; F_cons from a restricted evaluation of all
   their terms (collective; at the start with every copy in those terms at
   x0)
------------------------------------------------------------------------- */

void HSLocalModified::conservative_state(HSStepView &eng, bool at_start)
{
  double **x = atom->x, **v = atom->v, **f = atom->f;
  const int *mask = atom->mask;
  const int gb = sys->groupbit;
  grow();
  cons_direct = !sys->nheld;
  cons_start = at_start;
  cons_view = &eng;
  if (cons_direct) return;    // (cons(), vcons())
  HardSphere::bump_epoch(cepoch, cstamp);
  std::vector<int> &atoms = cs_atoms;
  atoms.clear();
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

  // F_cons of the group's owners: LAMMPS' own if the fix copied f before
  // the held fixes added theirs (HSSystem::capture_forces(); the same
  // forces as below, to round-off), else a restricted evaluation of all
  // their terms (collective: every rank calls it, with its own part; the
  // choice is the same on every rank, FixHardSphere::capture_rule())
  std::vector<int> &set = cs_set;
  set.clear();
  for (int i : atoms)
    if (mask[i] & gb) set.push_back(i);
  if (double **fcap = sys->captured(at_start)) {
    const double dtf = sys->dtf;
    for (int i : set) {
      const double s = (at_start ? dtf : -dtf) / sys->mass_of(i);
      for (int d = 0; d < 3; d++) {
        fcons_[i][d] = fcap[i][d];
        vcons_[i][d] += s * (f[i][d] - fcons_[i][d]);
      }
    }
    return;
  }
  HSLocalForces &lf = eng.local_forces();
  lf.set_labels(nullptr);
  std::vector<int> &moved = cs_moved;
  std::vector<Vec> &saved = cs_saved;
  moved.clear();
  saved.clear();
  if (at_start) {
    lf.terms(set.data(), (int) set.size());
    // each copy in a term once, by stamp (as list_terms(): a sort of the
    // ~2 x terms entries was the largest item of a pcva step with fix
    // langevin, 16 % of it at 256000 atoms on 2 ranks); each is moved and
    // put back on its own, so their order does not matter
    HardSphere::bump_epoch(cepoch, cstamp);
    for (int l : lf.term_local()) {
      if (cstamp[l] == cepoch) continue;
      cstamp[l] = cepoch;
      moved.push_back(l);
      saved.push_back({x[l][0], x[l][1], x[l][2]});
      for (int d = 0; d < 3; d++) x[l][d] = eng.start_x(l)[d];
    }
  }
  lf.compute(set.data(), (int) set.size(), false);
  double **fl = lf.forces();
  const double dtf = sys->dtf;
  double fc[3];
  for (int i : set) {
    const double s = (at_start ? dtf : -dtf) / sys->mass_of(i);
    // (fix gravity's force: conservative, in no restricted evaluation)
    eng.const_force(i, fc);
    for (int d = 0; d < 3; d++) {
      fcons_[i][d] = fl[i][d] + fc[d];
      vcons_[i][d] += s * (f[i][d] - fcons_[i][d]);
    }
  }
  for (size_t k = 0; k < moved.size(); k++)
    for (int d = 0; d < 3; d++) x[moved[k]][d] = saved[k][d];
}

/* ----------------------------------------------------------------------
   after a list rebuild between begin() and end() (atoms sorted, or moved
   to other ranks): the members (ID, cluster) and the start's partners (ID,
   start data) this rank owns now. An entry whose atom is still owned here
   stays; only the others travel, by ID to every rank (a list rebuild moves
   few atoms across a face: gathering every entry cost 3 % of a 2-rank pcva
   step at 256000 atoms, most of it in page faults of the large buffers)
------------------------------------------------------------------------- */

void HSLocalModified::remap()
{
  const int nlocal = atom->nlocal;
  const int me = comm->me;
  auto here = [&](tagint t) {
    const int i = atom->map(t);
    return i >= 0 && i < nlocal;
  };
  // members keep begin()'s order: cluster, then the rank and position
  // where begin() listed them (the order of a gather of every entry)
  std::vector<RemapMember> &ms = remap_ms;
  std::vector<std::pair<tagint, int>> &ps = remap_ps;
  std::vector<double> &out = remap_out;
  HardSphere::GatherBuffer<double> &all = remap_all;
  ms.clear();
  ps.clear();
  out.clear();
  // (with held_work a member's MemberStart travels with it: 6 more values)
  const int nmw = held_work ? 6 : 0;
  for (size_t k = 0; k < mtag.size(); k++) {
    if (here(mtag[k])) {
      ms.push_back({cid[k], me, (int) k, mtag[k], (int) k});
      continue;
    }
    for (double d : {0.0, (double) mtag[k], (double) cid[k], (double) me, (double) k})
      out.push_back(d);
    if (held_work)
      for (const Vec *a : {&mstart[k].g0, &mstart[k].q0})
        for (int d = 0; d < 3; d++) out.push_back((*a)[d]);
  }
  for (size_t k = 0; k < ptag.size(); k++) {
    if (here(ptag[k])) {
      ps.emplace_back(ptag[k], (int) k);
      continue;
    }
    out.push_back(1.0);
    out.push_back((double) ptag[k]);
    const Start &st = pstart[k];
    for (const Vec *a : {&st.v0, &st.d1, &st.d2, &st.fr0})
      for (int d = 0; d < 3; d++) out.push_back((*a)[d]);
  }
  HardSphere::allgatherv(world, MPI_DOUBLE, out, all);
  for (size_t p = 0; p < all.size();) {
    const bool partner = all[p] > 0.5;
    const tagint t = (tagint) all[p + 1];
    if (!partner) {
      if (here(t))
        ms.push_back({(int) all[p + 2], (int) all[p + 3], (int) all[p + 4], t, -1 - (int) (p + 5)});
      p += 5 + nmw;
      continue;
    }
    if (here(t)) ps.emplace_back(t, -1 - (int) (p + 2));    // (its data in all)
    p += 14;
  }
  std::sort(ms.begin(), ms.end(), [](const RemapMember &a, const RemapMember &b) {
    if (a.cid != b.cid) return a.cid < b.cid;
    return a.rank != b.rank ? a.rank < b.rank : a.seq < b.seq;
  });
  mtag.clear();
  cid.clear();
  remap_mst.clear();
  for (const RemapMember &m : ms) {
    mtag.push_back(m.tag);
    cid.push_back(m.cid);
    if (!held_work) continue;
    MemberStart st;
    if (m.src >= 0)
      st = mstart[m.src];
    else {
      int q = -1 - m.src;
      for (Vec *a : {&st.g0, &st.q0})
        for (int d = 0; d < 3; d++) (*a)[d] = all[q++];
    }
    remap_mst.push_back(st);
  }
  mstart.swap(remap_mst);
  // (partners by ID: (ID, where its data is) sorted, the data then copied
  // once in that order)
  std::sort(ps.begin(), ps.end());
  std::vector<Start> &st = remap_st;
  st.resize(ps.size());
  ptag.clear();
  for (size_t k = 0; k < ps.size(); k++) {
    ptag.push_back(ps[k].first);
    const int w = ps[k].second;
    if (w >= 0) {
      st[k] = pstart[w];
      continue;
    }
    int q = -1 - w;
    for (Vec *a : {&st[k].v0, &st[k].d1, &st[k].d2, &st[k].fr0})
      for (int d = 0; d < 3; d++) (*a)[d] = all[q++];
  }
  pstart.swap(st);
}

/* ---------------------------------------------------------------------- */

void HSLocalModified::end(HSStepView &eng, double &A, double &B, double &C0)
{
  double **x = atom->x;
  const int *mask = atom->mask;
  const int gb = sys->groupbit;
  // the start's terms and owners still hold unless the lists were rebuilt
  // (then atoms may also have been sorted, or moved to other ranks)
  if (neighbor->ncalls != terms_ncalls) {
    if (comm->nprocs > 1) remap();
    mem.resize(mtag.size());
    for (size_t k = 0; k < mtag.size(); k++) mem[k] = eng.owned(mtag[k]);
    find_terms(eng);
  } else
    for (size_t k = 0; k < mtag.size(); k++) mem[k] = eng.owned(mtag[k]);
  pidx.resize(ptag.size());
  for (size_t k = 0; k < ptag.size(); k++) pidx[k] = eng.owned(ptag[k]);
  conservative_state(eng, false);

  // b of the projection on the members (owners' order: members first)
  relative();
  forward_state(true);
  double E, Q, Qbb;
  terms_eval<true>([&](int l) { return x[l]; }, E, Q, Qbb, false);
  const double mvv2e = force->mvv2e, dt = sys->dtv;
  double T = 0.0;
  for (int m : mem)
    if (mask[m] & gb) {
      const double *vm = vcons(m);
      T += sys->mass_of(m) * (vm[0] * vm[0] + vm[1] * vm[1] + vm[2] * vm[2]);
    }
  T *= 0.5 * mvv2e;
  const double L1 = local_L(E, Q, T) + const_energy(eng, false);

  // what the Phi_H1 flows did to H~2: the partners' kinetic energy and
  // dt^2/6 (V_R'' v)_p . dv_p, (V_R'' v)_p = -(F^R_p(end) - F^R_p(start)) / dt
  double dTP = 0.0, gk = 0.0;
  for (size_t k = 0; k < ptag.size(); k++) {
    const int p = pidx[k];
    const Start &st = pstart[k];
    const double *vp = vcons(p), *F = cons(p);
    double kin = 0.0;
    for (int d = 0; d < 3; d++) {
      const double a = st.v0[d] + st.d1[d], b = vp[d] - st.d2[d];
      kin += a * a - st.v0[d] * st.v0[d] + vp[d] * vp[d] - b * b;
      const double fr1 = F[d] - red[p][d];    // (red: zero if p is in no term now)
      gk += -(fr1 - st.fr0[d]) / dt * (st.d1[d] + st.d2[d]);
    }
    dTP += 0.5 * mvv2e * sys->mass_of(p) * kin;
  }
  double sums[3];
  sums[0] = L1 - L0 + dTP + dt * dt / 6.0 * gk + (held_work ? held_energy_change(eng) : 0.0);

  // the projection's coefficients
  double mb2 = 0.0, bkv = 0.0;
  for (size_t k = 0; k < mem.size(); k++) {
    const int m = mem[k];
    if (!(mask[m] & gb)) continue;
    const double *kvm = red[m] + 3;
    for (int d = 0; d < 3; d++) {
      mb2 += sys->mass_of(m) * rel[k][d] * rel[k][d];
      bkv += rel[k][d] * kvm[d];
    }
  }
  sums[1] = 0.5 * mvv2e * mb2 + dt * dt / 12.0 * Qbb;
  sums[2] = mvv2e * mb2 + dt * dt / 6.0 * bkv;
  zero_red();
  // every rank's part (one reduction: the same coefficients everywhere)
  double tot[3] = {sums[0], sums[1], sums[2]};
  if (comm->nprocs > 1) MPI_Allreduce(sums, tot, 3, MPI_DOUBLE, MPI_SUM, world);
  C0 = tot[0];
  A = tot[1];
  B = tot[2];
}

// minus the work of the held smooth forces on this rank's members over the
// step, by the trapezoid rule: -1/2 (G0 + G1).(q1 - q0), G1 = f - F_C - m g
// now (red: V_CX's forces at the end), q unwrapped. The rule's error is
// O(dG/dt dt^2 dv) in a step where a member's velocity jumps by dv: second
// order, with the held terms' curvature as its constant (doc
// fix_hardsphere_pcva, "Held smooth forces")
double HSLocalModified::held_energy_change(HSStepView &eng)
{
  const int *mask = atom->mask;
  const int gb = sys->groupbit;
  double W = 0.0;
  Vec g1, q1;
  for (size_t k = 0; k < mem.size(); k++) {
    const int m = mem[k];
    if (!(mask[m] & gb)) continue;
    held_state(eng, m, atom->x[m], g1, q1);
    const MemberStart &st = mstart[k];
    for (int d = 0; d < 3; d++) W += 0.5 * (st.g0[d] + g1[d]) * (q1[d] - st.q0[d]);
  }
  return -W;
}

// member m's held force G = f - F_C - m g now (cons(): f; red: the force of
// V_CX, every term of a member) and x, its position, unwrapped with its
// image flags now (begin() runs before LAMMPS' reneighboring: those of x0)
void HSLocalModified::held_state(HSStepView &eng, int m, const double *x, Vec &g, Vec &q) const
{
  double fc[3];
  eng.const_force(m, fc);
  const double *F = cons(m);
  for (int d = 0; d < 3; d++) g[d] = F[d] - red[m][d] - fc[d];
  domain->unmap(x, atom->image[m], q.data());
}

// b = v - the cluster's centre-of-mass velocity for the members (v itself
// for a one-sphere cluster: a wall contact); zero outside the group. The
// clusters' sums over every rank's members (one reduction: momentum,
// mass, members in the group)
void HSLocalModified::relative()
{
  const int *mask = atom->mask;
  const int gb = sys->groupbit;
  std::vector<double> s(5 * ncl, 0.0), tot(5 * ncl, 0.0);
  for (size_t k = 0; k < mem.size(); k++) {
    const int m = mem[k];
    if (!(mask[m] & gb)) continue;
    const double ms = sys->mass_of(m);
    double *c = &s[5 * cid[k]];
    for (int d = 0; d < 3; d++) c[d] += ms * vcons(m)[d];
    c[3] += ms;
    c[4] += 1.0;
  }
  if (comm->nprocs > 1 && ncl > 0)
    MPI_Allreduce(s.data(), tot.data(), 5 * ncl, MPI_DOUBLE, MPI_SUM, world);
  else
    tot = s;
  rel.assign(mem.size(), {0.0, 0.0, 0.0});
  for (size_t k = 0; k < mem.size(); k++) {
    const int m = mem[k];
    if (!(mask[m] & gb)) continue;
    const double *c = &tot[5 * cid[k]];
    for (int d = 0; d < 3; d++) rel[k][d] = vcons(m)[d] - (c[4] > 1.5 ? c[d] / c[3] : 0.0);
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
