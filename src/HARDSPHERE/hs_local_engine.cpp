/* ----------------------------------------------------------------------
   HARDSPHERE package: the local step engine (`substep local`).
   See hs_local_engine.h and doc/fix_hardsphere.rst, "Step engines".
------------------------------------------------------------------------- */

#include "hs_local_engine.h"

#include "hs_contact.h"
#include "hs_fix_rule.h"
#include "hs_local_forces.h"
#include "hs_method.h"
#include "hs_system.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "fix.h"
#include "force.h"
#include "memory.h"
#include "modify.h"
#include "neighbor.h"
#include "pair.h"
#include "update.h"

#include <algorithm>
#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;
using HardSphere::Contact;

// Phi_H2's lines of atoms near a cluster deviate from fix nve's by the V_C
// kicks; pairs (walls) that pass fix nve's lines farther than this
// (relative to the contact distance) need no check in Phi_H2 as long as
// every deviation stays below half of it (checked, else all are checked)
static constexpr double LINE_MARGIN = 1.0e-3;
// growth rounds of one step beyond which something is wrong
static constexpr int MAX_ROUNDS = 10000;

/* ---------------------------------------------------------------------- */

HSLocalEngine::HSLocalEngine(LAMMPS *lmp, HSSystem &system, HSMethod &method) :
    HSStepEngine(lmp), sys(&system), meth(method)
{
  locf = new HSLocalForces(lmp, "Fix " + system.style_name);
}

HSLocalEngine::~HSLocalEngine()
{
  delete locf;
  for (double ***a : peratom()) memory->destroy(*a);
}

/* ----------------------------------------------------------------------
   can this set-up run locally? "" if yes, else the reasons
------------------------------------------------------------------------- */

std::string HSLocalEngine::limits()
{
  std::string why;
  auto add = [&why](const std::string &s) { why += (why.empty() ? "" : "; ") + s; };
  if (comm->nprocs > 1)
    add(fmt::format("{} MPI ranks (the local engine runs on one rank so far)", comm->nprocs));
  if (atom->map_style == Atom::MAP_NONE)
    add("no atom map (use atom_modify map array or yes)");
  else {
    locf->init();
    if (!locf->exact()) add(locf->unrestrictable());
  }
  // fixes with conservative forces: not part of the restricted V_C
  for (int k = 0; k < modify->nfix; k++) {
    Fix *other = modify->fix[k];
    if (other == sys->host || !(modify->fmask[k] & FixConst::POST_FORCE)) continue;
    const std::string base = HardSphere::base_style(other->style);
    if (base == "enforce2d") continue;    // zero z forces: V_C's are zero in z already
    const auto kind = HardSphere::fix_force_kind(other->style);
    if (kind == HardSphere::FixForceKind::CONSERVATIVE || kind == HardSphere::FixForceKind::UNKNOWN)
      add(fmt::format("fix {} {} (its forces are not restricted to the colliding spheres' "
                      "terms)",
                      other->id, other->style));
  }
  // V_C's forces from rank-local rows (the form several ranks need), else
  // from the pair list restriction (newton_pair off, neigh_modify exclude)
  rows = locf->exact() && locf->rows_unsupported().empty();
  cand_version = -1;
  bonded = (atom->molecular != Atom::ATOMIC) &&
      (force->bond || force->angle || force->dihedral || force->improper);
  return why;
}

/* ---------------------------------------------------------------------- */

// -grad V_C for the atoms c[0..n) (HSLocalForces)
void HSLocalEngine::vc(const int *c, int n)
{
  if (rows) {
    // the rows are taken at the list build's positions (HSSystem::xref,
    // owned and ghosts, set at every build)
    locf->set_reference(sys->xref);
    locf->compute_rows(c, n);
  } else
    locf->compute(c, n, false);
}

const int *HSLocalEngine::crow(int a, int &n)
{
  HSSystem &F = *sys;
  if (crows_version != F.cand_version) {
    crows.rebuild(F.xref, atom->nlocal + atom->nghost, F.list_cutoff, 2);
    crows_version = F.cand_version;
  }
  return crows.row(a, n, [&](std::vector<int> &out) {
    const int *mask = atom->mask;
    const tagint *tag = atom->tag;
    const double cut2 = F.list_cutoff * F.list_cutoff;
    const double *xa = F.xref[a];
    const size_t s0 = out.size();
    crows.grid.for_each_candidate(xa, [&](int j, const double *xj) {
      const double dx = xa[0] - xj[0], dy = xa[1] - xj[1], dz = xa[2] - xj[2];
      // (bonded partners too: the fix adds those LAMMPS' lists leave out)
      if (dx * dx + dy * dy + dz * dz > cut2) return;
      if (j == a || tag[j] == tag[a] || !(mask[j] & F.groupbit)) return;
      out.push_back(j);
    });
    std::sort(out.begin() + s0, out.end(), [tag](int p, int q) {
      return tag[p] != tag[q] ? tag[p] < tag[q] : p < q;
    });
  });
}

void HSLocalEngine::grow_arrays()
{
  if (atom->nmax > nmax) {
    nmax = atom->nmax;
    for (double ***a : peratom()) {
      memory->destroy(*a);
      memory->create(*a, nmax, 3, "hardsphere/local:peratom");
    }
  }
  if ((int) cnt.size() < nmax) {
    // per-atom bookkeeping that refers to local indices: a new size means
    // a new step's indices, so nothing of a previous step is kept
    cnt.assign(nmax, 0);
    in_sums.assign(nmax, 0);
    sums_used.clear();
    dstamp.assign(nmax, 0);
    hstamp.assign(nmax, 0);
    atom_runs.assign(nmax, {});
    runs_used.clear();
  }
  if ((int) estamp.size() < nmax) {
    estamp.resize(nmax, 0);
    astamp.resize(nmax, 0);
    astamp0.resize(nmax, 0);
    xstamp.resize(nmax, 0);
    pathv.resize(nmax, 0.0);
  }
}

void HSLocalEngine::bump_epoch(uint32_t &e, std::vector<uint32_t> &stamp)
{
  if (++e == 0) {
    std::fill(stamp.begin(), stamp.end(), 0u);
    e = 1;
  }
}

/* ----------------------------------------------------------------------
   the contact candidates by owned atom, once per list build (one rank:
   every ghost is an image of an owned atom)
------------------------------------------------------------------------- */

void HSLocalEngine::build_adjacency()
{
  if (sys->cand_version == cand_version) return;
  const int nlocal = atom->nlocal, nall = nlocal + atom->nghost;
  own.resize(nall);
  for (int k = 0; k < nlocal; k++) own[k] = k;
  for (int k = nlocal; k < nall; k++) {
    const int o = atom->map(atom->tag[k]);
    if (o < 0 || o >= nlocal)
      error->one(FLERR, "Fix {} substep local: ghost atom {} has no owned copy on this rank",
                 sys->style_name, atom->tag[k]);
    own[k] = o;
  }
  const std::vector<int> &cand = sys->cand;
  const int np = (int) cand.size() / 2;
  adj_off.assign(nlocal + 1, 0);
  for (int p = 0; p < np; p++) {
    const int a = own[cand[2 * p]], b = own[cand[2 * p + 1]];
    if (a == b) continue;
    adj_off[a + 1]++;
    adj_off[b + 1]++;
  }
  for (int i = 0; i < nlocal; i++) adj_off[i + 1] += adj_off[i];
  adj.resize(adj_off[nlocal]);
  std::vector<int> pos(adj_off.begin(), adj_off.end() - 1);
  for (int p = 0; p < np; p++) {
    const int a = own[cand[2 * p]], b = own[cand[2 * p + 1]];
    if (a == b) continue;
    adj[pos[a]++] = p;
    adj[pos[b]++] = p;
  }
  pstamp.assign(np, 0u);
  pepoch = 0;
  cand_version = sys->cand_version;
}

/* ----------------------------------------------------------------------
   move owned atom i (and its images) to xn, resp. give it velocity vn
------------------------------------------------------------------------- */

void HSLocalEngine::set_x(int i, const double *xn)
{
  double **x = atom->x;
  const double d[3] = {xn[0] - x[i][0], xn[1] - x[i][1], xn[2] - x[i][2]};
  x[i][0] = xn[0];
  x[i][1] = xn[1];
  x[i][2] = xn[2];
  for (int k = atom->sametag[i]; k >= 0; k = atom->sametag[k]) {
    x[k][0] += d[0];
    x[k][1] += d[1];
    x[k][2] += d[2];
  }
}

void HSLocalEngine::set_v(int i, const double *vn)
{
  double **v = atom->v;
  for (int k = i; k >= 0; k = atom->sametag[k]) {
    v[k][0] = vn[0];
    v[k][1] = vn[1];
    v[k][2] = vn[2];
  }
}

/* ----------------------------------------------------------------------
   every contact of the step on the unsplit Verlet paths q + t v + t^2/2 a
   (the first guess of C): walls of active spheres, candidate pairs with an
   active sphere
------------------------------------------------------------------------- */

void HSLocalEngine::predict_all(std::vector<Hit> &hits)
{
  HSSystem &F = *sys;
  double **x = atom->x, **v = atom->v, **acc = F.acc;
  const double *active = F.active;
  const int nlocal = atom->nlocal;
  const int *mask = atom->mask;
  double **xref = F.xref;
  const double *gap = F.gap;
  const double dt = F.dtv;
  double c[5];
  auto path = [&](int k) {
    const double vv = sqrt(v[k][0] * v[k][0] + v[k][1] * v[k][1] + v[k][2] * v[k][2]);
    const double aa = sqrt(acc[k][0] * acc[k][0] + acc[k][1] * acc[k][1] + acc[k][2] * acc[k][2]);
    return dt * vv + 0.5 * dt * dt * aa;
  };
  // the screen's active spheres, and those within LINE_MARGIN / 2 of being
  // active (Phi_H2's lines may deviate that much from fix nve's, below)
  bump_epoch(pepoch0, astamp0);
  act0.clear();
  near_pairs.clear();
  near_walls.clear();
  const double mhalf = 0.5 * LINE_MARGIN * 2.0 * F.rmax;
  const double t2 = dt * dt, h4 = 0.25 * t2 * t2;
  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & F.groupbit)) continue;
    if (active[i] == 0.0) {
      // as HSSystem::screen_atom(): (a+b+c)^2 <= 3(a^2+b^2+c^2)
      const double dx = x[i][0] - xref[i][0], dy = x[i][1] - xref[i][1],
                   dz = x[i][2] - xref[i][2];
      const double d2 = dx * dx + dy * dy + dz * dz;
      const double v2 = t2 * (v[i][0] * v[i][0] + v[i][1] * v[i][1] + v[i][2] * v[i][2]);
      const double a2 =
          h4 * (acc[i][0] * acc[i][0] + acc[i][1] * acc[i][1] + acc[i][2] * acc[i][2]);
      const double g = gap[i] - mhalf;
      if (g > 0.0 && 3.0 * (d2 + v2 + a2) <= g * g) continue;
      if (sqrt(d2) + sqrt(v2) + sqrt(a2) <= g) continue;
    }
    act0.push_back(i);
    astamp0[i] = pepoch0;
    pathv[i] = path(i);
  }
  for (int i : act0) {
    const double Di = pathv[i], r = F.radius_of(i);
    for (int wl = 0; wl < (int) F.walls.size(); wl++) {
      const Wall &W = F.walls[wl];
      const double g = F.wall_gap(W, x[i], r);
      if (g > Di) continue;
      const double s = (W.side < 0) ? 1.0 : -1.0;
      const Contact ct = wall_contact(i, wl, g, v[i][W.dim], acc[i][W.dim], dt);
      if (ct.status != HardSphere::NO_CONTACT) {
        hits.push_back({i, -1 - wl});
        continue;
      }
      // fix nve's straight line (Phi_H2's, up to the V_C kicks): a contact
      // joins the guess, a near miss is listed for Phi_H2's check
      const double m = LINE_MARGIN * 2.0 * r;
      const double wn = s * (v[i][W.dim] + 0.5 * dt * acc[i][W.dim]);
      HardSphere::wall_gap_poly(g - m, wn, 0.0, c);
      if (HardSphere::first_contact(c, 2, dt, TOUCH_TOL * 2.0 * r).status ==
          HardSphere::NO_CONTACT)
        continue;
      HardSphere::wall_gap_poly(g, wn, 0.0, c);
      const Contact cl = HardSphere::first_contact(c, 2, dt, TOUCH_TOL * 2.0 * r);
      if (cl.status != HardSphere::NO_CONTACT) hits.push_back({i, -1 - wl});
      else near_walls.push_back(i);
    }
  }
  // candidate pairs with an active sphere (ghosts are active with their
  // owner): a sequential pass, as HSSystem::predict()
  const std::vector<int> &cand = F.cand;
  const int np = (int) cand.size() / 2;
  for (int p = 0; p < np; p++) {
      const int i = cand[2 * p], j = cand[2 * p + 1];
      if (astamp0[own[i]] != pepoch0 && astamp0[own[j]] != pepoch0) continue;
      if (own[i] == own[j]) continue;
      const double sigma = F.radius_of(i) + F.radius_of(j);
      const double dq[3] = {x[i][0] - x[j][0], x[i][1] - x[j][1], x[i][2] - x[j][2]};
      const double r2 = dq[0] * dq[0] + dq[1] * dq[1] + dq[2] * dq[2];
      const double sm = sigma * (1.0 + LINE_MARGIN);
      // the path bound of act0's atoms is kept; a pair may have one other end
      const double pi = (astamp0[own[i]] == pepoch0) ? pathv[own[i]] : path(i);
      const double pj = (astamp0[own[j]] == pepoch0) ? pathv[own[j]] : path(j);
      const double reach = sm + pi + pj;
      if (r2 > reach * reach) continue;
      const double dv[3] = {v[i][0] - v[j][0], v[i][1] - v[j][1], v[i][2] - v[j][2]};
      const double da[3] = {acc[i][0] - acc[j][0], acc[i][1] - acc[j][1], acc[i][2] - acc[j][2]};
      const Contact ct = pair_contact(i, j, dq, dv, da, sigma, dt);
      if (ct.status != HardSphere::NO_CONTACT) {
        hits.push_back({own[i], own[j]});
        continue;
      }
      // fix nve's straight lines (Phi_H2's, up to the V_C kicks of the
      // partners): a contact joins the guess, a near miss within the margin
      // is listed for Phi_H2's check
      const double dw[3] = {dv[0] + 0.5 * dt * da[0], dv[1] + 0.5 * dt * da[1],
                            dv[2] + 0.5 * dt * da[2]};
      const double zero[3] = {0.0, 0.0, 0.0};
      if (r2 >= sm * sm) {
        HardSphere::pair_gap_poly(dq, dw, zero, sm, c);
        if (HardSphere::first_contact(c, 4, dt, TOUCH_TOL * sm * sm).status ==
            HardSphere::NO_CONTACT)
          continue;
      }
      HardSphere::pair_gap_poly(dq, dw, zero, sigma, c);
      const Contact cl =
          HardSphere::first_contact(c, 4, dt, TOUCH_TOL * sigma * sigma);
      if (cl.status != HardSphere::NO_CONTACT) hits.push_back({own[i], own[j]});
      else near_pairs.push_back(p);
    }
}

/* ----------------------------------------------------------------------
   the terms of new members join V_C: members sharing a term are one
   cluster (partners stay out: frozen-partner clusters)
------------------------------------------------------------------------- */

void HSLocalEngine::add_terms(const std::vector<int> &newm)
{
  // pair terms between members do not join clusters (cross terms: a
  // constant force in each half of the flow), bonded terms with two members do
  if (newm.empty() || !bonded) return;
  locf->terms(newm.data(), (int) newm.size());
  const std::vector<int> &ta = locf->term_atoms();
  const std::vector<int> &off = locf->term_offsets();
  const int npair = locf->npair_last();
  for (size_t t = npair; t + 1 < off.size(); t++) cs.add_term(ta.data() + off[t], off[t + 1] - off[t]);
}

// the cluster labels (key: smallest member) on every local copy of the
// members, for HSLocalForces' cross terms
void HSLocalEngine::label_members()
{
  for (int k : labelled) lab[k] = -1;
  labelled.clear();
  for (int c = 0; c < cs.nclusters(); c++) label_cluster(c);
}

void HSLocalEngine::label_cluster(int c)
{
  const int key = cs.members(c)[0];
  for (int m : cs.members(c))
    for (int k = m; k >= 0; k = atom->sametag[k]) {
      lab[k] = key;
      labelled.push_back(k);
    }
}

// the held (thermostat) force f - F(x0) of new members (nheld only):
// their conservative force at the step's start from all their terms, with
// every atom in them put back at x0 for the evaluation
void HSLocalEngine::held_at_start(const std::vector<int> &newm)
{
  if (!sys->nheld || newm.empty()) return;
  double **x = atom->x, **f = atom->f;
  locf->set_labels(nullptr);
  vc(newm.data(), (int) newm.size());
  const std::vector<int> T = locf->touched();
  std::vector<Vec> saved(T.size());
  for (size_t k = 0; k < T.size(); k++) {
    saved[k] = {x[T[k]][0], x[T[k]][1], x[T[k]][2]};
    set_x(T[k], x0[T[k]]);
  }
  locf->recompute();
  ncompute += 2.0;
  double **fl = locf->forces();
  for (int i : newm)
    for (int d = 0; d < 3; d++) held0[i][d] = f[i][d] - fl[i][d];
  for (size_t k = 0; k < T.size(); k++) set_x(T[k], saved[k].data());
  locf->set_labels(lab.data());
}

/* ----------------------------------------------------------------------
   the cross terms' force on a cluster's members at the step's start,
   F_X(x0), with every atom in them put back at x0 (issue 19, doc "Step
   engines"): the cross force acts inside both halves of the members'
   flow, as F_X(x0) in the first and 2 F_X(x_mid) - F_X(x0) in the second,
   instead of a kick dt F_X(x_mid) between them. A kick between the halves
   gives a contact inside a half the wrong normal velocity by
   2 min(t_c, dt - t_c) a_X.n, O(dt); a constant force within each half
   errs by O(dt^2) at any time, and the total impulse is still
   dt F_X(x_mid), so momentum is kept. Cross terms pair two members, both
   at x0 here: the forces on the two clusters are equal and opposite.
------------------------------------------------------------------------- */

void HSLocalEngine::cross_at_start(Run &r)
{
  const int nm = (int) r.members.size();
  r.fx0.assign(nm, Vec{0.0, 0.0, 0.0});
  if (!force->pair) return;
  double **x = atom->x;
  locf->set_labels(lab.data(), HSLocalForces::CROSS);
  vc(r.members.data(), nm);
  ncompute += 1.0;
  const std::vector<int> T = locf->touched();
  std::vector<Vec> &saved = scratch_env_x0;
  saved.resize(T.size());
  bool moved = false;
  for (size_t k = 0; k < T.size(); k++) {
    const int t = T[k];
    saved[k] = {x[t][0], x[t][1], x[t][2]};
    if (x[t][0] != x0[t][0] || x[t][1] != x0[t][1] || x[t][2] != x0[t][2]) {
      set_x(t, x0[t]);
      moved = true;
    }
  }
  if (moved) {
    locf->recompute();
    ncompute += 1.0;
  }
  double **fl = locf->forces();
  for (int k = 0; k < nm; k++) {
    const int i = r.members[k];
    r.fx0[k] = {fl[i][0], fl[i][1], fl[i][2]};
  }
  if (moved)
    for (size_t k = 0; k < T.size(); k++) set_x(T[k], saved[k].data());
  locf->set_labels(lab.data());
}

/* ----------------------------------------------------------------------
   the cross terms (pair terms between members of two clusters) at the
   members' mid positions (xm): F_X(x_mid), which sets the constant cross
   force of the second halves (see cross_at_start()). A cluster whose
   members' cross forces changed redoes its second half
------------------------------------------------------------------------- */

void HSLocalEngine::cross_at_mid()
{
  if (!force->pair) {
    workX.clear();
    return;
  }
  // the clusters whose members moved (ran their first half) and their
  // cross neighbours before and after: one wave (the neighbours' members
  // did not move, so their neighbours' kicks stay)
  bump_epoch(xepoch, xstamp);
  std::vector<int> wave;
  for (int key : workX)
    if (xstamp[key] != xepoch) {
      xstamp[key] = xepoch;
      wave.push_back(key);
    }
  workX.clear();
  for (size_t w = 0; w < wave.size(); w++) {
    const int key = wave[w];
    const int c = cs.cluster_of(key);
    if (c < 0 || cs.members(c)[0] != key) continue;
    auto it = runs.find(key);
    if (it == runs.end() || !it->second->a_done) continue;
    Run &r = *it->second;
    std::vector<int> old = r.xnbrs;
    cross_of(r);
    for (const std::vector<int> *L : {&old, &r.xnbrs})
        for (int k : *L)
          if (xstamp[k] != xepoch) {
            xstamp[k] = xepoch;
            wave2.push_back(k);
          }
  }
  for (int key : wave2) {
    const int c = cs.cluster_of(key);
    if (c < 0 || cs.members(c)[0] != key) continue;
    auto it = runs.find(key);
    if (it == runs.end() || !it->second->a_done) continue;
    cross_of(*it->second);
  }
  wave2.clear();
}

// the cross-term forces on one cluster's members (from all their cross
// terms at the members' current positions) and its cross neighbours
void HSLocalEngine::cross_of(Run &r)
{
  const int nm = (int) r.members.size();
  locf->set_labels(lab.data(), HSLocalForces::CROSS);
  vc(r.members.data(), nm);
  locf->set_labels(lab.data());
  ncompute += 1.0;
  double **fl = locf->forces();
  const int key = r.members[0];
  r.xnbrs.clear();
  for (int t : locf->touched())
    if (lab[t] >= 0 && lab[t] != key) r.xnbrs.push_back(lab[t]);
  std::sort(r.xnbrs.begin(), r.xnbrs.end());
  r.xnbrs.erase(std::unique(r.xnbrs.begin(), r.xnbrs.end()), r.xnbrs.end());
  bool changed = (int) r.fx.size() != nm;
  r.fx.resize(nm);
  for (int k = 0; k < nm; k++) {
    const int i = r.members[k];
    const Vec d = {fl[i][0], fl[i][1], fl[i][2]};
    if (d != r.fx[k]) changed = true;
    r.fx[k] = d;
  }
  if (changed && r.b_done) {
    r.b_done = false;
    workB.push_back(key);
  }
}

void HSLocalEngine::grow_clusters(const std::vector<Hit> &hits)
{
  for (const Hit &h : hits) {
    cs.grow_contact(h.i, h.j < 0 ? -1 : h.j);
    mark_dirty(h.i);
    if (h.j >= 0) mark_dirty(h.j);
  }
  const std::vector<int> newm = cs.new_members();
  add_terms(newm);
  const std::vector<int> redo = cs.rebuild();
  // a cluster whose flows saw a new member as a partner or a static atom
  // is redone too: the terms between them are cross terms now
  for (int m : newm)
    for (int key : atom_runs[m]) {
      auto it = runs.find(key);
      if (it == runs.end() || it->second->members.empty()) continue;
      retire(*it->second);
      runs.erase(it);
      const int c = cs.cluster_of(key);
      if (c >= 0) workA.push_back(cs.members(c)[0]);
    }
  for (int c : redo) {
    label_cluster(c);
    workA.push_back(cs.members(c)[0]);
    for (int m : cs.members(c)) {
      auto it = runs.find(m);
      if (it == runs.end()) continue;
      retire(*it->second);
      runs.erase(it);
    }
  }
  held_at_start(newm);
  nrounds += 1.0;
}


/* ----------------------------------------------------------------------
   the sums over clusters of V_C's start forces and the partners' first-half
   kicks (for Phi_H2's velocities), kept as clusters are run and dropped
------------------------------------------------------------------------- */

void HSLocalEngine::contribute(Run &r, double sign)
{
  const int *mask = atom->mask;
  for (size_t k = 0; k < r.touched.size(); k++) {
    const int p = r.touched[k];
    if (sign > 0.0 && cnt[p] == 0) {
      for (int d = 0; d < 3; d++) fc0[p][d] = dvt[p][d] = 0.0;
      if (!in_sums[p]) {
        in_sums[p] = 1;
        sums_used.push_back(p);
      }
    }
    cnt[p] += (sign > 0.0) ? 1 : -1;
    if (cnt[p] == 0) {    // no cluster left: exactly fix nve's kick again
      for (int d = 0; d < 3; d++) fc0[p][d] = dvt[p][d] = 0.0;
      continue;
    }
    for (int d = 0; d < 3; d++) fc0[p][d] += sign * r.fk0[k][d];
    if (mask[p] & sys->groupbit)
      for (int d = 0; d < 3; d++) dvt[p][d] += sign * r.dvA[k][d];
  }
  r.contributed = sign > 0.0;
}

// a run that is dropped: its contributions go, its atoms' paths change
void HSLocalEngine::retire(Run &r)
{
  if (r.contributed) contribute(r, -1.0);
  for (int k : r.xnbrs) workX.push_back(k);    // their cross terms with it change
  for (int t : r.touched) mark_dirty(t);
  for (int e : r.env) mark_dirty(e);
  for (int m : r.members) mark_dirty(m);
}

void HSLocalEngine::mark_dirty(int i)
{
  if (dstamp[i] != depoch) {    // for the drift and the second half
    dstamp[i] = depoch;
    dirty.push_back(i);
  }
  if (hstamp[i] != hepoch) {    // for Phi_H2's next check
    hstamp[i] = hepoch;
    hdirty.push_back(i);
  }
}

/* ----------------------------------------------------------------------
   Phi_H1(h) of one cluster: CVA sub-steps of its members under its terms
   of V_C; everyone else stays put (members of other clusters are checked
   afterwards, cross_check()). first_half: from the step's start (x0, v0
   and the held half kick), else from the state after the first half with
   the non-members at their end positions. Returns false (hits gets the
   contact) if a member touches a non-member: C must grow.
------------------------------------------------------------------------- */

bool HSLocalEngine::flow(Run &r, double h, bool first_half, std::vector<Hit> &hits)
{
  HSSystem &F = *sys;
  double **x = atom->x, **v = atom->v;
  const double ftm2v = force->ftm2v;
  const std::vector<int> &M = r.members;
  const int nm = (int) M.size();
  const int c = cs.cluster_of(M[0]);

  if (first_half)
    for (int i : M) set_x(i, x0[i]);
  else
    for (int k = 0; k < nm; k++) set_x(M[k], r.xm[k].data());
  if (first_half) cross_at_start(r);
  // the constant cross force on the members in this half (fx0 is set by
  // every first half; fx only once cross_at_mid() ran, else F_X(q0) again)
  std::vector<Vec> &fc = scratch_fc;
  const bool mid = (int) r.fx.size() == nm;
  fc.resize(nm);
  for (int k = 0; k < nm; k++)
    for (int d = 0; d < 3; d++)
      fc[k][d] = (first_half || !mid) ? r.fx0[k][d] : 2.0 * r.fx[k][d] - r.fx0[k][d];
  if (first_half) vc(M.data(), nm);
  else locf->recompute(r.snap);    // the lists of the first half
  ncompute += 1.0;
  std::vector<Vec> &env_saved = scratch_env;
  env_saved.clear();
  if (first_half) {
    locf->save(r.snap);
    r.touched = locf->touched();
    // the static atoms of this flow: partners and contact candidates
    r.env.clear();
    for (int t : r.touched)
      if (!cs.is_member(t)) r.env.push_back(t);
    for (int i : M) {
      int nc;
      const int *cr = crow(i, nc);
      for (int e = 0; e < nc; e++) {
        const int o = own[cr[e]];
        if (!cs.is_member(o)) r.env.push_back(o);
      }
    }
    std::sort(r.env.begin(), r.env.end());
    r.env.erase(std::unique(r.env.begin(), r.env.end()), r.env.end());
    // after the drift of Phi_H2 (a later growth round) they wait at x0 for
    // this flow, and go back to their end positions after it
    if (drifted) {
      env_saved.resize(r.env.size());
      for (size_t k = 0; k < r.env.size(); k++) {
        const int e = r.env[k];
        env_saved[k] = {x[e][0], x[e][1], x[e][2]};
        set_x(e, x0[e]);
      }
      locf->recompute();
      ncompute += 1.0;
    }
  } else if (locf->touched() != r.touched)
    error->one(FLERR, "Fix {} substep local: the terms of a cluster changed within step {}",
               F.style_name, update->ntimestep);
  const std::vector<int> &T = r.touched;
  const int nt = (int) T.size();
  std::vector<Vec> &fk = scratch_fk, &fk1 = scratch_fk1;
  fk.resize(nt);
  fk1.resize(nt);
  double **fl = locf->forces();
  for (int k = 0; k < nt; k++) fk[k] = {fl[T[k]][0], fl[T[k]][1], fl[T[k]][2]};
  // where each member sits in T (both sorted)
  std::vector<int> &mi = scratch_mi;
  mi.resize(nm);
  for (int k = 0, t = 0; k < nm; k++) {
    while (T[t] != M[k]) t++;
    mi[k] = t;
  }
  if (first_half) {
    r.fk0 = fk;
    // the held forces' half kick (f - F_C: LAMMPS' forces minus V_C's)
    for (int k = 0; k < nm; k++) {
      const int i = M[k];
      double vn[3] = {v0[i][0], v0[i][1], v0[i][2]};
      if (F.nheld) {
        const double dtfm = F.dtf / F.mass_of(i);
        for (int d = 0; d < 3; d++) vn[d] += dtfm * held0[i][d];
      }
      set_v(i, vn);
    }
  } else
    for (int k = 0; k < nm; k++) set_v(M[k], r.vm[k].data());

  std::vector<Vec> &dv = first_half ? r.dvA : r.dvB;
  dv.assign(nt, Vec{0.0, 0.0, 0.0});
  std::vector<std::vector<Seg>> &segs = first_half ? r.segsA : r.segsB;
  segs.resize(nm);
  for (auto &sg : segs) sg.clear();
  std::vector<double> &im = scratch_im;
  im.resize(nm);
  for (int k = 0; k < nm; k++) im[k] = ftm2v / F.mass_of(M[k]);
  auto member_k = [&](int o) {    // index of owned o in M, -1 if not in this cluster
    if (cs.cluster_of(o) != c) return -1;
    return (int) (std::lower_bound(M.begin(), M.end(), o) - M.begin());
  };

  // this flow's collisions and impulse virial, kept apart from the fix's
  const int half = first_half ? 0 : 1;
  double vir_saved[6], npair_saved = F.ncoll_pair, nwall_saved = F.ncoll_wall;
  for (int k = 0; k < 6; k++) vir_saved[k] = F.host->virial[k];
  auto keep_counts = [&]() {
    r.npair[half] = F.ncoll_pair - npair_saved;
    r.nwall[half] = F.ncoll_wall - nwall_saved;
    for (int k = 0; k < 6; k++) {
      r.vir[half][k] = F.host->virial[k] - vir_saved[k];
      F.host->virial[k] = vir_saved[k];
    }
    F.ncoll_pair = npair_saved;
    F.ncoll_wall = nwall_saved;
  };

  const std::vector<int> &cand = F.cand;
  double t = 0.0;
  int stuck = 0;
  bigint nsub = 0;
  while (true) {
    const double tau = h - t;
    double tbest = BIG;
    int bi = -1, bj = -1, bwall = -1, bli = -1, blj = -1;
    bool bstatic = false;
    for (int k = 0; k < nm; k++) {
      const int i = M[k];
      const double *a = fk[mi[k]].data();
      const double ai[3] = {(a[0] + fc[k][0]) * im[k], (a[1] + fc[k][1]) * im[k],
                            (a[2] + fc[k][2]) * im[k]};
      const double vv = sqrt(v[i][0] * v[i][0] + v[i][1] * v[i][1] + v[i][2] * v[i][2]);
      const double aa = sqrt(ai[0] * ai[0] + ai[1] * ai[1] + ai[2] * ai[2]);
      const double Di = tau * vv + 0.5 * tau * tau * aa;
      const double ri = F.radius_of(i);
      for (int wl = 0; wl < (int) F.walls.size(); wl++) {
        const Wall &W = F.walls[wl];
        const double g = F.wall_gap(W, x[i], ri);
        if (g > Di) continue;
        const Contact ct = wall_contact(i, wl, g, v[i][W.dim], ai[W.dim], tau);
        if (ct.status != HardSphere::NO_CONTACT && ct.t < tbest) {
          tbest = ct.t;
          bi = i;
          bj = -1;
          bwall = wl;
          bli = i;
          bstatic = false;
        }
      }
      int ncr;
      const int *cr = crow(i, ncr);
      for (int e = 0; e < ncr; e++) {
        const int mine = i, theirs = cr[e];
        const int o = own[theirs];
        const int ko = member_k(o);
        double vo[3] = {0.0, 0.0, 0.0}, ao[3] = {0.0, 0.0, 0.0}, Do = 0.0;
        if (ko >= 0) {
          if (o < i) continue;    // the pair is handled from its lower member
          const double *b = fk[mi[ko]].data();
          for (int d = 0; d < 3; d++) {
            vo[d] = v[o][d];
            ao[d] = (b[d] + fc[ko][d]) * im[ko];
          }
          Do = tau * sqrt(vo[0] * vo[0] + vo[1] * vo[1] + vo[2] * vo[2]) +
              0.5 * tau * tau * sqrt(ao[0] * ao[0] + ao[1] * ao[1] + ao[2] * ao[2]);
        } else if (cs.is_member(o))
          continue;    // another cluster's member: cross_check()
        const double sigma = ri + F.radius_of(theirs);
        const double dq[3] = {x[mine][0] - x[theirs][0], x[mine][1] - x[theirs][1],
                              x[mine][2] - x[theirs][2]};
        const double r2 = dq[0] * dq[0] + dq[1] * dq[1] + dq[2] * dq[2];
        const double reach = sigma + Di + Do;
        if (r2 > reach * reach) continue;
        const double dvv[3] = {v[i][0] - vo[0], v[i][1] - vo[1], v[i][2] - vo[2]};
        const double da[3] = {ai[0] - ao[0], ai[1] - ao[1], ai[2] - ao[2]};
        const Contact ct = pair_contact(mine, theirs, dq, dvv, da, sigma, tau);
        if (ct.status != HardSphere::NO_CONTACT && ct.t < tbest) {
          tbest = ct.t;
          bi = i;
          bj = o;
          bwall = -1;
          bli = mine;
          blj = theirs;
          bstatic = ko < 0;
        }
      }
    }
    const bool hit = tbest <= tau;
    if (hit && bstatic) {    // a non-member: it joins C, the cluster is redone
      hits.push_back({bi, bj});
      r.a_done = false;
      keep_counts();
      for (size_t k = 0; k < env_saved.size(); k++) set_x(r.env[k], env_saved[k].data());
      return false;
    }
    const double d = hit ? tbest : tau;
    if (d > 0.0) {
      const double dtfk = 0.5 * d * ftm2v;
      for (int k = 0; k < nm; k++) {
        const int i = M[k];
        const double dtfm = dtfk / F.mass_of(i);
        Seg s;
        s.t0 = t;
        s.t1 = t + d;
        for (int dd = 0; dd < 3; dd++) {
          s.q[dd] = x[i][dd];
          s.v[dd] = v[i][dd];
          s.a[dd] = (fk[mi[k]][dd] + fc[k][dd]) * im[k];
        }
        segs[k].push_back(s);
        double vn[3], xn[3];
        for (int dd = 0; dd < 3; dd++) {
          vn[dd] = v[i][dd] + dtfm * (fk[mi[k]][dd] + fc[k][dd]);
          xn[dd] = x[i][dd] + d * vn[dd];
        }
        set_v(i, vn);
        set_x(i, xn);
      }
      locf->recompute();    // the same terms: their restricted lists again
      ncompute += 1.0;
      fl = locf->forces();
      for (int k = 0; k < nt; k++) fk1[k] = {fl[T[k]][0], fl[T[k]][1], fl[T[k]][2]};
      for (int k = 0; k < nm; k++) {
        const int i = M[k];
        const double dtfm = dtfk / F.mass_of(i);
        const double vn[3] = {v[i][0] + dtfm * (fk1[mi[k]][0] + fc[k][0]),
                              v[i][1] + dtfm * (fk1[mi[k]][1] + fc[k][1]),
                              v[i][2] + dtfm * (fk1[mi[k]][2] + fc[k][2])};
        set_v(i, vn);
      }
      // partners stay put and take V_C's momentum (trapezoid over the sub-step)
      const int *mask = atom->mask;
      for (int k = 0; k < nt; k++) {
        const int p = T[k];
        if (cs.is_member(p) || !(mask[p] & F.groupbit)) continue;
        const double dtfm = dtfk / F.mass_of(p);
        for (int dd = 0; dd < 3; dd++) dv[k][dd] += dtfm * (fk[k][dd] + fk1[k][dd]);
      }
      fk.swap(fk1);
      stuck = 0;
    }
    if (!hit) break;

    // the contact: the method's collision operator (CVA: R of section 2)
    Impulse imp;
    memset(&imp, 0, sizeof(imp));
    imp.type = (bwall >= 0) ? WALL_EVENT : PAIR_EVENT;
    imp.itag = atom->tag[bi];
    imp.jtag = (bwall >= 0) ? 0 : atom->tag[bj];
    imp.wall = bwall;
    if (bwall >= 0) meth.collide_wall(bli, F.walls[bwall], imp);
    else meth.collide_pair(bli, blj, imp);
    if (imp.apply) meth.modify_impulse(imp);
    if (imp.apply) F.add_impulse_virial(imp);
    F.apply_impulse(imp);
    if (imp.apply) {
      if (bwall >= 0) F.ncoll_wall += 1.0;
      else F.ncoll_pair += 1.0;
    } else if (d == 0.0 && ++stuck > MAX_STUCK)
      F.resting_contact_error(imp);
    t += d;
    F.check_runaway(++nsub);
  }

  keep_counts();
  if (first_half) {
    r.xm.resize(nm);
    r.vm.resize(nm);
    for (int k = 0; k < nm; k++) {
      const int i = M[k];
      r.xm[k] = {x[i][0], x[i][1], x[i][2]};
      r.vm[k] = {v[i][0], v[i][1], v[i][2]};
    }
    r.a_done = true;
    for (size_t k = 0; k < env_saved.size(); k++) set_x(r.env[k], env_saved[k].data());
  } else {
    // the end state is kept; the members wait at xm again (where Phi_H2's
    // checks of later growth rounds see them)
    r.fend = fk;
    r.xe.resize(nm);
    r.ve.resize(nm);
    for (int k = 0; k < nm; k++) {
      const int i = M[k];
      r.xe[k] = {x[i][0], x[i][1], x[i][2]};
      r.ve[k] = {v[i][0], v[i][1], v[i][2]};
      set_x(i, r.xm[k].data());
      set_v(i, r.vm[k].data());
    }
    r.b_done = true;
  }
  return true;
}

/* ----------------------------------------------------------------------
   contacts between members of two clusters, whose flows ran apart: on
   their piecewise Verlet paths (the segments of the last flow). Only pairs
   with a cluster in fresh (run in this round): the others were checked
------------------------------------------------------------------------- */

void HSLocalEngine::cross_check(bool first_half, const std::vector<int> &fresh,
                                std::vector<Hit> &hits)
{
  HSSystem &F = *sys;
  double **x = atom->x;
  const std::vector<int> &cand = F.cand;
  double cc[5];
  std::vector<char> isfresh(cs.nclusters(), 0);
  for (int c : fresh) isfresh[c] = 1;
  auto pos = [](const Seg &s, double t, int d) {
    const double h = t - s.t0;
    return s.q[d] + h * s.v[d] + 0.5 * h * h * s.a[d];
  };
  auto vel = [](const Seg &s, double t, int d) { return s.v[d] + (t - s.t0) * s.a[d]; };
  auto path = [](const std::vector<Seg> &S) {
    double p = 0.0;
    for (const Seg &s : S) {
      const double d = s.t1 - s.t0;
      p += d * sqrt(s.v[0] * s.v[0] + s.v[1] * s.v[1] + s.v[2] * s.v[2]) +
          0.5 * d * d * sqrt(s.a[0] * s.a[0] + s.a[1] * s.a[1] + s.a[2] * s.a[2]);
    }
    return p;
  };
  for (int c : fresh) {
    const std::vector<int> &M = cs.members(c);
    const Run &r = *runs.at(M[0]);
    for (int k = 0; k < (int) M.size(); k++) {
      const int i = M[k];
      int ncr;
      const int *cr = crow(i, ncr);
      for (int e = 0; e < ncr; e++) {
        const int mine = i, theirs = cr[e];
        const int o = own[theirs];
        if (!cs.is_member(o)) continue;
        const int oc = cs.cluster_of(o);
        if (oc == c || (isfresh[oc] && oc < c)) continue;    // same, or done from oc
        const std::vector<int> &Mo = cs.members(oc);
        auto it = runs.find(Mo[0]);
        if (it == runs.end()) continue;
        const Run &ro = *it->second;
        const int ko = (int) (std::lower_bound(Mo.begin(), Mo.end(), o) - Mo.begin());
        const std::vector<std::vector<Seg>> &Si = first_half ? r.segsA : r.segsB;
        const std::vector<std::vector<Seg>> &Sj = first_half ? ro.segsA : ro.segsB;
        if (k >= (int) Si.size() || ko >= (int) Sj.size()) continue;
        const std::vector<Seg> &si = Si[k], &sj = Sj[ko];
        if (si.empty() || sj.empty()) continue;
        // image shifts
        double sh[3];
        for (int d = 0; d < 3; d++) sh[d] = (x[mine][d] - x[i][d]) - (x[theirs][d] - x[o][d]);
        const double sigma = F.radius_of(i) + F.radius_of(o);
        double dq0[3];
        for (int d = 0; d < 3; d++) dq0[d] = si[0].q[d] - sj[0].q[d] + sh[d];
        const double r0 = sqrt(dq0[0] * dq0[0] + dq0[1] * dq0[1] + dq0[2] * dq0[2]);
        if (r0 > sigma + path(si) + path(sj)) continue;
        // walk the common breakpoints
        size_t a = 0, b = 0;
        double t = si[0].t0;
        const double tend_all = std::min(si.back().t1, sj.back().t1);
        bool found = false;
        while (!found && t < tend_all && a < si.size() && b < sj.size()) {
          const double tend = std::min(si[a].t1, sj[b].t1);
          if (tend > t) {
            double dq[3], dv[3], da[3];
            for (int d = 0; d < 3; d++) {
              dq[d] = pos(si[a], t, d) - pos(sj[b], t, d) + sh[d];
              dv[d] = vel(si[a], t, d) - vel(sj[b], t, d);
              da[d] = si[a].a[d] - sj[b].a[d];
            }
            HardSphere::pair_gap_poly(dq, dv, da, sigma, cc);
            const Contact ct = HardSphere::first_contact(cc, 4, tend - t,
                                                         TOUCH_TOL * sigma * sigma);
            if (ct.status != HardSphere::NO_CONTACT) found = true;
          }
          t = tend;
          if (si[a].t1 <= t) a++;
          if (b < sj.size() && sj[b].t1 <= t) b++;
        }
        if (found) hits.push_back({i, o});
      }
    }
  }
}

/* ----------------------------------------------------------------------
   the velocity of Phi_H2's straight line: v0 + dt/2 (f - F_C(x0)) / m plus
   the first half's partner kicks; zero for a member; fix nve's kick for an
   atom in no term of V_C
------------------------------------------------------------------------- */

void HSLocalEngine::wvel(int i, double *wi) const
{
  if (cs.is_member(i)) {
    wi[0] = wi[1] = wi[2] = 0.0;
    return;
  }
  double **f = atom->f;
  const double dtfm = sys->dtf / sys->mass_of(i);
  if (cnt[i] > 0)
    for (int d = 0; d < 3; d++) wi[d] = v0[i][d] + dtfm * (f[i][d] - fc0[i][d]) + dvt[i][d];
  else
    for (int d = 0; d < 3; d++) wi[d] = v0[i][d] + dtfm * f[i][d];
}

/* ----------------------------------------------------------------------
   Phi_H2(dt): non-members on straight lines from x0 with velocity w,
   members waiting at xm. Any contact in it grows C. full: every atom that
   may touch something (the screen's active ones: an atom in no term of V_C
   stays within the screen's bound of its Verlet path; and every atom V_C
   touched); else only the atoms whose path changed since (dirty)
------------------------------------------------------------------------- */

void HSLocalEngine::h2_check(bool full, std::vector<Hit> &hits)
{
  HSSystem &F = *sys;
  const int *mask = atom->mask;
  const double dt = F.dtv, skin = F.skin;
  double **xref = F.xref;
  const double *gap = F.gap;
  // the position of local index l at the start of Phi_H2
  bump_epoch(aepoch, astamp);
  std::vector<int> act;
  // w of every group atom is kept in w[] from the full check on; a later
  // round updates the dirty atoms' (every atom whose w changed is dirty)
  const int nlocal = atom->nlocal;
  if (full) {
    for (int i = 0; i < nlocal; i++)
      if (mask[i] & F.groupbit) wvel(i, w[i]);
  } else
    for (int i : hdirty)
      if (mask[i] & F.groupbit) wvel(i, w[i]);
  // an atom that may touch something in Phi_H2. always: check all its
  // pairs (its path changed while its partners' did not: only the pairs of
  // an atom outside its gap can touch, and that may be the partner)
  auto consider = [&](int i, bool always) {
    if (astamp[i] == aepoch || !(mask[i] & F.groupbit)) return;
    astamp[i] = aepoch;
    double q[3];
    const double *wi = w[i];
    h2_pos(i, q);
    const double D = dt * sqrt(wi[0] * wi[0] + wi[1] * wi[1] + wi[2] * wi[2]);
    const double dx = q[0] - xref[i][0], dy = q[1] - xref[i][1], dz = q[2] - xref[i][2];
    const double reach = sqrt(dx * dx + dy * dy + dz * dz) + D;
    if (!always && reach <= gap[i]) return;
    if (reach > skin)
      error->one(FLERR,
                 "Fix {}: atom {} may be {} away from where the neighbor list was built, "
                 "more than the skin {} (the fix rebuilds lists at skin/2): use a smaller "
                 "timestep or a larger neighbor skin",
                 F.style_name, atom->tag[i], reach, skin);
    act.push_back(i);
  };
  // full: if every line deviates from fix nve's by less than LINE_MARGIN / 2
  // of the contact distance, only the pairs predict_all() listed as near
  // misses and the pairs with a member (waiting at xm) can touch
  bool lists = false;
  if (full) {
    double dev = 0.0;
    for (int p : sums_used) {
      if (cnt[p] == 0 || cs.is_member(p) || !(mask[p] & F.groupbit)) continue;
      const double dtfm = F.dtf / F.mass_of(p);
      double d2 = 0.0;
      for (int d = 0; d < 3; d++) {
        const double e = w[p][d] - (v0[p][d] + dtfm * atom->f[p][d]);
        d2 += e * e;
      }
      dev = std::max(dev, sqrt(d2));
    }
    lists = dt * dev <= 0.5 * LINE_MARGIN * 2.0 * F.rmax * 0.999;
    if (!lists) {
      for (int i : act0) consider(i, false);
      for (auto &kv : runs)
        for (int t : kv.second->touched) consider(t, false);
    }
  } else
    for (int i : hdirty) consider(i, true);
  bump_epoch(hepoch, hstamp);
  hdirty.clear();
  if (lists) {
    // members: every candidate pair; the listed near misses; walls
    for (int c = 0; c < cs.nclusters(); c++)
      for (int m : cs.members(c)) consider(m, true);
    bump_epoch(pepoch, pstamp);
    for (int p : near_pairs) pstamp[p] = pepoch;    // checked below, with act's
    for (int p : near_pairs) check_pair(p, hits);
    for (int i : near_walls)
      if (!cs.is_member(i)) check_walls(i, hits);
  } else
    bump_epoch(pepoch, pstamp);

  for (int i : act) {
    if (!cs.is_member(i)) check_walls(i, hits);
    for (int e = adj_off[i]; e < adj_off[i + 1]; e++) {
      const int p = adj[e];
      if (pstamp[p] == pepoch) continue;
      pstamp[p] = pepoch;
      check_pair(p, hits);
    }
  }
}

// the position of local index l at the start of Phi_H2 (members wait at xm)
void HSLocalEngine::h2_pos(int l, double *q) const
{
  double **x = atom->x;
  const int o = own[l];
  if (cs.is_member(o))
    for (int d = 0; d < 3; d++) q[d] = x[l][d];
  else
    for (int d = 0; d < 3; d++) q[d] = x0[o][d] + (x[l][d] - x[o][d]);
}

// a contact of candidate pair p on Phi_H2's lines
void HSLocalEngine::check_pair(int p, std::vector<Hit> &hits)
{
  HSSystem &F = *sys;
  const std::vector<int> &cand = F.cand;
  const int la = cand[2 * p], lb = cand[2 * p + 1];
  const int oa = own[la], ob = own[lb];
  if (cs.is_member(oa) && cs.is_member(ob)) return;    // both wait
  const double dt = F.dtv;
  double qa[3], qb[3];
  const double *wa = w[oa], *wb = w[ob];
  h2_pos(la, qa);
  h2_pos(lb, qb);
  const double sigma = F.radius_of(la) + F.radius_of(lb);
  const double dq[3] = {qa[0] - qb[0], qa[1] - qb[1], qa[2] - qb[2]};
  const double dv[3] = {wa[0] - wb[0], wa[1] - wb[1], wa[2] - wb[2]};
  const double r2 = dq[0] * dq[0] + dq[1] * dq[1] + dq[2] * dq[2];
  const double reach = sigma + dt * sqrt(dv[0] * dv[0] + dv[1] * dv[1] + dv[2] * dv[2]);
  if (r2 > reach * reach) return;
  const double da[3] = {0.0, 0.0, 0.0};
  if (pair_contact(la, lb, dq, dv, da, sigma, dt).status != HardSphere::NO_CONTACT)
    hits.push_back({oa, ob});
}

// wall contacts of non-member i on its Phi_H2 line
void HSLocalEngine::check_walls(int i, std::vector<Hit> &hits)
{
  HSSystem &F = *sys;
  for (int wl = 0; wl < (int) F.walls.size(); wl++) {
    const Wall &W = F.walls[wl];
    const double g = F.wall_gap(W, x0[i], F.radius_of(i));
    if (wall_contact(i, wl, g, w[i][W.dim], 0.0, F.dtv).status != HardSphere::NO_CONTACT)
      hits.push_back({i, -1 - wl});
  }
}

/* ----------------------------------------------------------------------
   the first approaching contact in (0, tmax] of sphere i with wall W
   (gap g now; velocity vd and acceleration ad along the wall's axis), resp.
   of local atoms la, lb on the relative path dq + t dv + t^2/2 da; an
   overlap now is the fix's missed-collision error
------------------------------------------------------------------------- */

Contact HSLocalEngine::wall_contact(int i, int wl, double g, double vd, double ad, double tmax)
{
  const double s = (sys->walls[wl].side < 0) ? 1.0 : -1.0, r = sys->radius_of(i);
  double c[5];
  HardSphere::wall_gap_poly(g, s * vd, s * ad, c);
  const Contact ct = HardSphere::first_contact(c, 2, tmax, TOUCH_TOL * 2.0 * r);
  if (ct.status == HardSphere::OVERLAP)
    error->one(FLERR, "Fix {}: atom {} is {} through a wall on step {}: a collision was missed",
               sys->style_name, atom->tag[i], -g, update->ntimestep);
  return ct;
}

Contact HSLocalEngine::pair_contact(int la, int lb, const double *dq, const double *dv,
                                   const double *da, double sigma, double tmax)
{
  double c[5];
  HardSphere::pair_gap_poly(dq, dv, da, sigma, c);
  const Contact ct =
      HardSphere::first_contact(c, 4, tmax, TOUCH_TOL * sigma * sigma);
  if (ct.status == HardSphere::OVERLAP)
    sys->pair_overlap_error(la, lb, sqrt(dq[0] * dq[0] + dq[1] * dq[1] + dq[2] * dq[2]), sigma);
  return ct;
}

/* ----------------------------------------------------------------------
   the clusters of the step from the first guess hits, grown until no flow
   has a contact with a non-member. After the first round, a round redoes
   only what a growth changed (its clusters, the paths of their atoms and
   the clusters around them). False if a member left the reach the cluster
   rule assumed (then redo with every term joining)
------------------------------------------------------------------------- */

void HSLocalEngine::settle(const std::vector<Hit> &hits)
{
  HSSystem &F = *sys;
  double **x = atom->x;
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  const double dt = F.dtv;

  // per-atom bookkeeping of the previous attempt
  for (int p : sums_used) {
    cnt[p] = 0;
    in_sums[p] = 0;
  }
  sums_used.clear();
  for (int a : runs_used) atom_runs[a].clear();
  runs_used.clear();
  bump_epoch(depoch, dstamp);
  dirty.clear();
  bump_epoch(hepoch, hstamp);
  hdirty.clear();
  drifted = false;
  bool checked = false;    // Phi_H2 checked in full once
  bool b_ran = false;      // a second half ran (its results may need redoing)

  cs.reset(nlocal);
  cs.set_partners_join(false);
  for (const Hit &h : hits) cs.add_contact(h.i, h.j < 0 ? -1 : h.j);
  const std::vector<int> first = cs.new_members();
  add_terms(first);
  cs.build();
  runs.clear();
  label_members();
  locf->set_labels(lab.data());
  held_at_start(first);

  auto enroll = [&](int a, int key) {
    if (atom_runs[a].empty()) runs_used.push_back(a);
    atom_runs[a].push_back(key);
  };

  workA.clear();
  workB.clear();
  workX.clear();
  uncheckedA.clear();
  uncheckedB.clear();
  for (int c = 0; c < cs.nclusters(); c++) workA.push_back(cs.members(c)[0]);
  // the cluster index of a key, -1 if it is no longer a cluster's key
  auto cluster_of_key = [&](int key) {
    const int c = cs.cluster_of(key);
    return (c >= 0 && cs.members(c)[0] == key) ? c : -1;
  };
  // keys -> cluster indices, once each
  auto clusters_of = [&](std::vector<int> &keys) {
    std::vector<int> out;
    for (int key : keys) {
      const int c = cluster_of_key(key);
      if (c >= 0) out.push_back(c);
    }
    keys.clear();
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  };

  // every round does only what the last growth changed: the clusters it
  // made or that saw a new member (first half), the atoms whose paths
  // changed (Phi_H2's check and drift), the kicks of their cross neighbours
  // and the second halves whose start or surroundings changed
  for (int round = 0;; round++) {
    if (round > MAX_ROUNDS)
      error->one(FLERR, "Fix {} substep local: the collision clusters of step {} did not settle "
                 "in {} rounds", F.style_name, update->ntimestep, MAX_ROUNDS);
    std::vector<Hit> ev;
    // Phi_H1(dt/2) of the clusters not run yet, their static atoms at x0
    for (int c : clusters_of(workA)) {
      const int key = cs.members(c)[0];
      Run &r = runs[key];
      if (r.a_done) continue;
      r.members = cs.members(c);
      r.b_done = false;
      if (!flow(r, 0.5 * dt, true, ev)) continue;
      contribute(r, 1.0);
      for (int t : r.touched) mark_dirty(t);
      for (int a : r.env) enroll(a, key);
      for (int a : r.members) enroll(a, key);
      uncheckedA.push_back(key);
      workX.push_back(key);
      workB.push_back(key);
    }
    // the flows not yet checked against the others (a round that grew
    // before its check leaves some for the next)
    if (ev.empty()) cross_check(true, clusters_of(uncheckedA), ev);
    if (!ev.empty()) {
      grow_clusters(ev);
      continue;
    }
    // Phi_H2(dt): its contacts; then the non-members' drift
    h2_check(!checked, ev);
    checked = true;
    if (!ev.empty()) {
      grow_clusters(ev);
      continue;
    }
    if (!drifted) {
      for (int i = 0; i < nlocal; i++)
        if ((mask[i] & F.groupbit) && !cs.is_member(i)) {
          x[i][0] = x0[i][0] + dt * w[i][0];
          x[i][1] = x0[i][1] + dt * w[i][1];
          x[i][2] = x0[i][2] + dt * w[i][2];
        }
      comm->forward_comm();
      drifted = true;
    } else
      for (int i : dirty)
        if ((mask[i] & F.groupbit) && !cs.is_member(i)) {
          const double xn[3] = {x0[i][0] + dt * w[i][0], x0[i][1] + dt * w[i][1],
                                x0[i][2] + dt * w[i][2]};
          set_x(i, xn);
        }
    // the cross terms' forces at the members' mid positions (second halves)
    cross_at_mid();
    // Phi_H1(dt/2) of the clusters whose start or surroundings changed
    if (b_ran)    // (the first time there is nothing to invalidate)
      for (int a : dirty)
        for (int key : atom_runs[a]) {
          auto it = runs.find(key);
          if (it != runs.end() && it->second->b_done) {
            it->second->b_done = false;
            workB.push_back(key);
          }
        }
    b_ran = true;
    bump_epoch(depoch, dstamp);
    dirty.clear();
    for (int c : clusters_of(workB)) {
      const int key = cs.members(c)[0];
      auto it = runs.find(key);
      if (it == runs.end() || it->second->b_done || !it->second->a_done) continue;
      if (flow(*it->second, 0.5 * dt, false, ev)) uncheckedB.push_back(key);
    }
    if (ev.empty()) cross_check(false, clusters_of(uncheckedB), ev);
    if (!ev.empty()) {
      grow_clusters(ev);
      continue;
    }
    break;
  }
  locf->set_labels(nullptr);
}

/* ----------------------------------------------------------------------
   a step with spheres that may touch (HSStepEngine): by clusters if a
   contact is predicted, else fix nve's step; the method sees the step
   through HSStepView
------------------------------------------------------------------------- */

void HSLocalEngine::step()
{
  HSSystem &F = *sys;
  if (step_clusters()) {
    local_step = 1;
    if (F.step_collided) F.ncoll_steps += 1.0;
    meth.cluster_step_begun(*this);
  } else {    // no contact after all: fix nve's step
    F.nve_initial();
    F.dtf_last = F.dtf;
  }
  F.request_rebuild();
}

// the closing kick of a step taken by clusters
bool HSLocalEngine::finish()
{
  if (!local_step) return false;
  HSSystem &F = *sys;
  final_kick();
  meth.cluster_step_done(*this);
  local_step = 0;
  F.step_substeps = 0;
  F.screened_step = -1;
  return true;
}

// clusters, mean and largest members, growth rounds, fall-backs, restricted evaluations
double HSLocalEngine::counter(int k)
{
  if (k == 4) return sys->nfallback;
  const HardSphere::ClusterCounters &c = counters();
  switch (k) {
    case 0:
      return c.clusters;
    case 1:
      return c.mean_members();
    case 2:
      return c.max_members;
    case 3:
      return nrounds;
    case 5:
      return ncompute;
  }
  return 0.0;
}

/* ----------------------------------------------------------------------
   one step: Phi_H1(dt/2) . Phi_H2(dt) . Phi_H1(dt/2) with C grown until no
   flow has a contact with a non-member
------------------------------------------------------------------------- */

bool HSLocalEngine::step_clusters()
{
  HSSystem &F = *sys;
  grow_arrays();
  build_adjacency();
  F.comm_vel_acc();    // ghosts' v, a, active: the first guess needs them
  std::vector<Hit> hits;
  predict_all(hits);
  if (hits.empty()) return false;

  double **x = atom->x, **v = atom->v;
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  for (int i = 0; i < nlocal; i++)
    for (int d = 0; d < 3; d++) {
      x0[i][d] = x[i][d];
      v0[i][d] = v[i][d];
    }

  const int nall = nlocal + atom->nghost;
  if ((int) lab.size() < nall) lab.resize(nall, -1);
  settle(hits);

  // the final clusters: their end states, collisions, impulse virial, and
  // on the touched atoms V_C's end forces and the partners' second-half kicks
  bump_epoch(eepoch, estamp);
  for (int c = 0; c < cs.nclusters(); c++) {
    const Run &r = *runs.at(cs.members(c)[0]);
    for (size_t k = 0; k < r.members.size(); k++) {
      set_x(r.members[k], r.xe[k].data());
      set_v(r.members[k], r.ve[k].data());
    }
    for (int h = 0; h < 2; h++) {
      F.ncoll_pair += r.npair[h];
      F.ncoll_wall += r.nwall[h];
      for (int k = 0; k < 6; k++) F.host->virial[k] += r.vir[h][k];
      if (r.npair[h] + r.nwall[h] > 0.0) F.step_collided = 1;
    }
    for (size_t k = 0; k < r.touched.size(); k++) {
      const int p = r.touched[k];
      if (estamp[p] != eepoch) {
        estamp[p] = eepoch;
        for (int d = 0; d < 3; d++) fcend[p][d] = dvb[p][d] = 0.0;
      }
      for (int d = 0; d < 3; d++) {
        fcend[p][d] += r.fend[k][d];
        dvb[p][d] += r.dvB[k][d];
      }
    }
  }

  // the non-members' velocities: w plus the second half's partner kicks
  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & F.groupbit) || cs.is_member(i)) continue;
    if (estamp[i] == eepoch)
      for (int d = 0; d < 3; d++) v[i][d] = w[i][d] + dvb[i][d];
    else
      for (int d = 0; d < 3; d++) v[i][d] = w[i][d];
  }
  // what the closing kick needs, by tag (see remap_after_rebuild())
  const tagint *tag = atom->tag;
  end_mtags.clear();
  end_ptags.clear();
  end_pfc.clear();
  for (int c = 0; c < cs.nclusters(); c++)
    for (int m : cs.members(c)) end_mtags.push_back(tag[m]);
  for (int i = 0; i < nlocal; i++)
    if (estamp[i] == eepoch && !cs.is_member(i)) {
      end_ptags.push_back(tag[i]);
      end_pfc.push_back({fcend[i][0], fcend[i][1], fcend[i][2]});
    }
  end_ncalls = neighbor->ncalls;
  cs.flush_counters();
  return true;
}

/* ----------------------------------------------------------------------
   a neighbor list rebuild since step() may have sorted the atoms: the
   members (kstamp) and partners (estamp, fcend) at their new indices
------------------------------------------------------------------------- */

void HSLocalEngine::remap_after_rebuild()
{
  if ((int) kstamp.size() < atom->nmax) kstamp.resize(atom->nmax, 0u);
  if ((int) estamp.size() < atom->nmax) estamp.resize(atom->nmax, 0u);
  grow_arrays();
  bump_epoch(kepoch, kstamp);
  bump_epoch(eepoch, estamp);
  for (tagint t : end_mtags) kstamp[owned(t)] = kepoch;
  for (size_t k = 0; k < end_ptags.size(); k++) {
    const int i = owned(end_ptags[k]);
    estamp[i] = eepoch;
    for (int d = 0; d < 3; d++) fcend[i][d] = end_pfc[k][d];
  }
}

/* ----------------------------------------------------------------------
   closing half kick with f - F_C(end): V_R and held forces. Members' V_C
   kick closed their last sub-step; without held forces they take none
------------------------------------------------------------------------- */

void HSLocalEngine::final_kick()
{
  HSSystem &F = *sys;
  double **v = atom->v, **f = atom->f;
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  // indices as step() left them, or as a rebuild since (atom sort) made them
  const bool remapped = neighbor->ncalls != end_ncalls;
  if (remapped) remap_after_rebuild();
  auto member = [&](int i) { return remapped ? kstamp[i] == kepoch : cs.is_member(i); };
  // members' held forces: f - their conservative force from all their terms
  if (F.nheld) {
    std::vector<int> all;
    for (tagint t : end_mtags) all.push_back(owned(t));
    vc(all.data(), (int) all.size());
    ncompute += 1.0;
    double **fl = locf->forces();
    for (int i : all) {
      const double dtfm = F.dtf / F.mass_of(i);
      for (int d = 0; d < 3; d++) v[i][d] += dtfm * (f[i][d] - fl[i][d]);
    }
  }
  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & F.groupbit)) continue;
    const double dtfm = F.dtf / F.mass_of(i);
    if (member(i)) continue;    // above
    if (estamp[i] == eepoch) {
      for (int d = 0; d < 3; d++) v[i][d] += dtfm * (f[i][d] - fcend[i][d]);
    } else
      for (int d = 0; d < 3; d++) v[i][d] += dtfm * f[i][d];
  }
}

int HSLocalEngine::owned(tagint t) const
{
  const int i = atom->map(t);
  if (i < 0 || i >= atom->nlocal)
    error->one(FLERR, "Fix {} substep local: atom {} of a collision cluster is not owned at the "
               "step's end (after a neighbor list rebuild)", sys->style_name, t);
  return i;
}

void HSLocalEngine::partner_kicks(int i, double *first, double *second) const
{
  const bool a = i < (int) cnt.size() && cnt[i] > 0 && (atom->mask[i] & sys->groupbit);
  const bool b = i < (int) estamp.size() && estamp[i] == eepoch;
  for (int d = 0; d < 3; d++) {
    first[d] = a ? dvt[i][d] : 0.0;
    second[d] = b ? dvb[i][d] : 0.0;
  }
}

const HardSphere::ClusterCounters &HSLocalEngine::counters()
{
  return cs.counters();
}
