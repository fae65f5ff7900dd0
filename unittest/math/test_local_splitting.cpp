// Brute-force reference of local collision sub-stepping (issue 10), written
// independently of the package's integrators (LAMMPS-free; it uses only the
// contact-time kernels of hs_contact.h and the cluster bookkeeping of
// hs_cluster.h).
//
// System: the impact pendulum chain of Bond & Leimkuhler (2007), section 4,
// lengthened to 8 and 12 spheres: 2D, unit masses, diameter 0.9, linear
// springs k_s = 1, rest length 1, the first sphere tied to an anchor at the
// origin, a hard wall at x = 0.
//
// Global CVA (section 2.2): every sphere takes Verlet sub-steps to every
// contact, impulse R at the contact.
//
// Local splitting: per step K_R(dt/2) . Phi_C(dt) . K_R(dt/2). C = spheres
// that collide in the step (members), V_C = springs with a member, V_R =
// the rest, so V_R exerts no force on a member and its kicks commute with
// the collision operator. Phi_C is the CVA flow of K + V_C with the hard
// constraints; it splits into independent flows per cluster (a member, its
// partners, joined through shared atoms: hs_cluster.h). Atoms outside every
// cluster move on straight lines q0 + t (v0 + dt/2 a0) during Phi_C. C is
// first guessed from contacts on those straight lines; a contact between a
// cluster's atom and an atom outside it (another cluster or none), found by
// comparing their sub-step trajectories, grows the clusters and the changed
// ones are redone from the step's start, until no such contact is left.
//
// Checks: no overlap ever; second order in energy for both (fitted slope
// >= 1.8 over dt 0.08 .. 0.01); local within 0.5 .. 2x of global at every
// dt; the growth path is taken; with no contacts at all both reduce to
// plain Verlet. A second variant ("frozen partners", below) is checked the
// same way.

#include "hs_cluster.h"
#include "hs_contact.h"

#include "gtest/gtest.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

namespace {

using Vec = std::array<double, 3>;
using HardSphere::ClusterSet;
using HardSphere::Contact;
using HardSphere::first_contact;

constexpr double KS = 1.0, R0 = 1.0, SIGMA = 0.9, RAD = 0.45;
constexpr double TOL_PAIR = 1e-10, TOL_WALL = 1e-10;

struct Chain {
  int n;
  std::vector<Vec> q, p;
};

// spring t joins atoms t-1 and t; atom -1 is the anchor at the origin
inline int term_a(int t) { return t - 1; }
inline int term_b(int t) { return t; }

// -grad of the springs with use[t] (all if use is null) on every atom
void forces(const Chain &c, const std::vector<Vec> &q, const std::vector<char> *use,
            std::vector<Vec> &f)
{
  f.assign(c.n, Vec{0, 0, 0});
  for (int t = 0; t < c.n; t++) {
    if (use && !(*use)[t]) continue;
    const int a = term_a(t), b = term_b(t);
    const Vec qa = a >= 0 ? q[a] : Vec{0, 0, 0};
    Vec d;
    double r2 = 0;
    for (int k = 0; k < 3; k++) {
      d[k] = q[b][k] - qa[k];
      r2 += d[k] * d[k];
    }
    const double r = std::sqrt(r2);
    const double s = -KS * (r - R0) / r;
    for (int k = 0; k < 3; k++) {
      f[b][k] += s * d[k];
      if (a >= 0) f[a][k] -= s * d[k];
    }
  }
}

double energy(const Chain &c)
{
  double e = 0;
  for (int i = 0; i < c.n; i++)
    for (int k = 0; k < 3; k++) e += 0.5 * c.p[i][k] * c.p[i][k];
  for (int t = 0; t < c.n; t++) {
    const int a = term_a(t), b = term_b(t);
    const Vec qa = a >= 0 ? c.q[a] : Vec{0, 0, 0};
    double r2 = 0;
    for (int k = 0; k < 3; k++) r2 += (c.q[b][k] - qa[k]) * (c.q[b][k] - qa[k]);
    e += 0.5 * KS * (std::sqrt(r2) - R0) * (std::sqrt(r2) - R0);
  }
  return e;
}

// one piece of a trajectory: q(t) = q + (t-t0) v + (t-t0)^2/2 a on [t0, t1]
struct Seg {
  double t0, t1;
  Vec q, v, a;
};

Vec seg_pos(const Seg &s, double t)
{
  const double h = t - s.t0;
  Vec r;
  for (int k = 0; k < 3; k++) r[k] = s.q[k] + h * s.v[k] + 0.5 * h * h * s.a[k];
  return r;
}
Vec seg_vel(const Seg &s, double t)
{
  const double h = t - s.t0;
  Vec r;
  for (int k = 0; k < 3; k++) r[k] = s.v[k] + h * s.a[k];
  return r;
}

struct Stats {
  long contacts = 0, overlaps = 0, growths = 0, redone = 0, steps = 0;
};

// earliest contact among the atoms of A (pairs within A) and with the wall,
// on the Verlet trajectories q + t v + t^2/2 a, within (0, tmax]
struct Hit {
  double t;
  int i, j;    // j = -1: wall
};

Hit earliest(const std::vector<int> &A, const std::vector<Vec> &q, const std::vector<Vec> &v,
             const std::vector<Vec> &a, double tmax, Stats &st)
{
  Hit h{tmax + 1.0, -1, -1};
  double c[5];
  for (size_t x = 0; x < A.size(); x++) {
    const int i = A[x];
    HardSphere::wall_gap_poly(q[i][0] - RAD, v[i][0], a[i][0], c);
    const Contact w = first_contact(c, 2, tmax, TOL_WALL);
    if (w.status == HardSphere::OVERLAP) st.overlaps++;
    if ((w.status == HardSphere::CONTACT || w.status == HardSphere::CONTACT_NOW) && w.t < h.t)
      h = {w.t, i, -1};
    for (size_t y = x + 1; y < A.size(); y++) {
      const int j = A[y];
      Vec dq, dv, da;
      for (int k = 0; k < 3; k++) {
        dq[k] = q[i][k] - q[j][k];
        dv[k] = v[i][k] - v[j][k];
        da[k] = a[i][k] - a[j][k];
      }
      HardSphere::pair_gap_poly(dq.data(), dv.data(), da.data(), SIGMA, c);
      const Contact p = first_contact(c, 4, tmax, TOL_PAIR);
      if (p.status == HardSphere::OVERLAP) st.overlaps++;
      if ((p.status == HardSphere::CONTACT || p.status == HardSphere::CONTACT_NOW) && p.t < h.t)
        h = {p.t, i, j};
    }
  }
  return h;
}

void impulse(std::vector<Vec> &q, std::vector<Vec> &p, int i, int j)
{
  if (j < 0) {    // wall x = 0: the normal component reverses
    p[i][0] = -p[i][0];
    return;
  }
  Vec dq, dv, J;
  for (int k = 0; k < 3; k++) {
    dq[k] = q[i][k] - q[j][k];
    dv[k] = p[i][k] - p[j][k];    // unit masses
  }
  HardSphere::pair_impulse(dq.data(), dv.data(), 1.0, 1.0, J.data());
  for (int k = 0; k < 3; k++) {
    p[i][k] += J[k];
    p[j][k] -= J[k];
  }
}

// CVA flow (section 2.2) over (0, dt] of the atoms A under the springs with
// use[t] (they involve atoms of A only), hard constraints within A and the
// wall. q, p: all atoms, only A's entries change. segs: A's sub-step pieces.
// member (optional): a contact of an atom that is not a member stops the
// flow and is returned (the clusters must grow), else {-1,-1} is returned
Hit cva_flow(const Chain &c, const std::vector<int> &A, const std::vector<char> *use, double dt,
             std::vector<Vec> &q, std::vector<Vec> &p, std::vector<std::vector<Seg>> *segs,
             Stats &st, const ClusterSet *member = nullptr)
{
  std::vector<Vec> f, f1, q1 = q;
  forces(c, q, use, f);
  double t = 0.0, tau = dt;
  if (segs)
    for (int i : A) (*segs)[i].clear();
  while (tau > 0.0) {
    const Hit h = earliest(A, q, p, f, tau, st);
    const bool hit = h.t <= tau;
    if (hit && member && (!member->is_member(h.i) || (h.j >= 0 && !member->is_member(h.j))))
      return {t + h.t, h.i, h.j};
    const double d = hit ? h.t : tau;
    for (int i : A)
      for (int k = 0; k < 3; k++) q1[i][k] = q[i][k] + d * p[i][k] + 0.5 * d * d * f[i][k];
    if (segs && d > 0.0)
      for (int i : A) (*segs)[i].push_back({t, t + d, q[i], p[i], f[i]});
    forces(c, q1, use, f1);
    for (int i : A)
      for (int k = 0; k < 3; k++) {
        p[i][k] += 0.5 * d * (f[i][k] + f1[i][k]);
        q[i][k] = q1[i][k];
      }
    f = f1;
    if (hit) {
      impulse(q, p, h.i, h.j);
      st.contacts++;
    }
    t += d;
    tau = hit ? dt - t : 0.0;
  }
  if (segs)
    for (int i : A)
      if ((*segs)[i].empty()) (*segs)[i].push_back({0.0, dt, q[i], p[i], f[i]});
  return {dt, -1, -1};
}

void step_global(Chain &c, double dt, Stats &st)
{
  std::vector<int> all(c.n);
  for (int i = 0; i < c.n; i++) all[i] = i;
  cva_flow(c, all, nullptr, dt, c.q, c.p, nullptr, st);
  st.steps++;
}

// earliest contact of two piecewise trajectories on [0, dt]
bool traj_contact(const std::vector<Seg> &si, const std::vector<Seg> &sj, double dt, double &tc,
                  Stats &st)
{
  size_t a = 0, b = 0;
  double t = 0.0;
  double c[5];
  while (t < dt && a < si.size() && b < sj.size()) {
    const double tend = std::min(si[a].t1, sj[b].t1);
    if (tend > t) {
      const Vec qi = seg_pos(si[a], t), qj = seg_pos(sj[b], t);
      const Vec vi = seg_vel(si[a], t), vj = seg_vel(sj[b], t);
      Vec dq, dv, da;
      for (int k = 0; k < 3; k++) {
        dq[k] = qi[k] - qj[k];
        dv[k] = vi[k] - vj[k];
        da[k] = si[a].a[k] - sj[b].a[k];
      }
      HardSphere::pair_gap_poly(dq.data(), dv.data(), da.data(), SIGMA, c);
      const Contact k = first_contact(c, 4, tend - t, TOL_PAIR);
      if (k.status != HardSphere::NO_CONTACT) {
        if (k.status == HardSphere::OVERLAP && t == 0.0) st.overlaps++;
        tc = t + k.t;
        return true;
      }
    }
    t = tend;
    if (si[a].t1 <= t) a++;
    if (b < sj.size() && sj[b].t1 <= t) b++;
  }
  return false;
}

struct LocalIntegrator {
  ClusterSet cs;
  Stats st;

  // springs with a member
  std::vector<char> vc_terms(const Chain &c)
  {
    std::vector<char> u(c.n, 0);
    for (int t = 0; t < c.n; t++) {
      const int a = term_a(t), b = term_b(t);
      u[t] = cs.is_member(b) || (a >= 0 && cs.is_member(a));
    }
    return u;
  }
  void add_terms(const Chain &c)
  {
    for (int t = 0; t < c.n; t++) {
      const int a = term_a(t), b = term_b(t);
      if (a >= 0) {
        const int at[2] = {a, b};
        cs.add_term(at, 2);
      } else
        cs.add_term(&b, 1);
    }
  }

  void step(Chain &c, double dt)
  {
    const int n = c.n;
    std::vector<Vec> f0;
    forces(c, c.q, nullptr, f0);
    // straight lines of the atoms outside every cluster: velocity after K_R(dt/2)
    std::vector<Vec> w(n);
    for (int i = 0; i < n; i++)
      for (int k = 0; k < 3; k++) w[i][k] = c.p[i][k] + 0.5 * dt * f0[i][k];

    // first guess of C: contacts on those straight lines
    cs.reset(n);
    {
      std::vector<int> all(n);
      for (int i = 0; i < n; i++) all[i] = i;
      std::vector<Vec> zero(n, Vec{0, 0, 0});
      double cc[5];
      for (int i = 0; i < n; i++) {
        HardSphere::wall_gap_poly(c.q[i][0] - RAD, w[i][0], 0.0, cc);
        const Contact k = first_contact(cc, 2, dt, TOL_WALL);
        if (k.status == HardSphere::OVERLAP) st.overlaps++;
        if (k.status != HardSphere::NO_CONTACT) cs.add_contact(i, -1);
        for (int j = i + 1; j < n; j++) {
          Vec dq, dv;
          for (int d = 0; d < 3; d++) {
            dq[d] = c.q[i][d] - c.q[j][d];
            dv[d] = w[i][d] - w[j][d];
          }
          HardSphere::pair_gap_poly(dq.data(), dv.data(), zero[0].data(), SIGMA, cc);
          const Contact m = first_contact(cc, 4, dt, TOL_PAIR);
          if (m.status == HardSphere::OVERLAP) st.overlaps++;
          if (m.status != HardSphere::NO_CONTACT) cs.add_contact(i, j);
        }
      }
    }
    add_terms(c);
    cs.build();

    // results per atom: mid-step momenta (after Phi_C) and final positions
    std::vector<Vec> qf(n), pf(n);
    std::vector<std::vector<Seg>> segs(n);
    std::vector<char> done_(n, 0);    // atom has its result for this step
    std::vector<int> pending(cs.nclusters());
    for (int k = 0; k < cs.nclusters(); k++) pending[k] = k;
    for (int guard = 0;; guard++) {
      ASSERT_LT(guard, 10 * n) << "cluster growth does not terminate";
      const std::vector<char> use = vc_terms(c);
      std::vector<char> use_r(n);
      for (int t = 0; t < n; t++) use_r[t] = !use[t];
      std::vector<Vec> fr0;
      forces(c, c.q, &use_r, fr0);
      // atoms outside every cluster: straight lines
      for (int i = 0; i < n; i++)
        if (cs.cluster_of(i) < 0) {
          for (int k = 0; k < 3; k++) {
            qf[i][k] = c.q[i][k] + dt * w[i][k];
            pf[i][k] = w[i][k];
          }
          segs[i].assign(1, {0.0, dt, c.q[i], w[i], Vec{0, 0, 0}});
          done_[i] = 1;
        }
      // the pending clusters: K_R(dt/2) (V_R acts on partners only), then
      // CVA under their own terms of V_C. A partner that collides inside the
      // flow must become a member (its springs move from V_R to V_C, or the
      // kicks would not commute with its collision): grow and redo.
      int gi = -1, gj = -1;
      for (int k : pending) {
        const auto &A = cs.atoms(k);
        std::vector<char> use_k(n, 0);
        for (int t = 0; t < n; t++) {
          const int b = term_b(t);
          use_k[t] = use[t] && cs.cluster_of(b) == k;
        }
        std::vector<Vec> q = c.q, p = c.p;
        for (int i : A)
          for (int d = 0; d < 3; d++) p[i][d] += 0.5 * dt * fr0[i][d];
        const Hit h = cva_flow(c, A, &use_k, dt, q, p, &segs, st, &cs);
        if (h.i >= 0) {
          gi = h.i;
          gj = h.j;
          break;
        }
        for (int i : A) {
          qf[i] = q[i];
          pf[i] = p[i];
          done_[i] = 1;
        }
      }
      if (gi >= 0) {
        // clusters already done keep their results unless rebuild() says
        // they changed; the rest of pending is redone anyway
        EXPECT_TRUE(cs.grow_contact(gi, gj));
        add_terms(c);
        const std::vector<int> redo = cs.rebuild();
        std::vector<char> again(cs.nclusters(), 0);
        for (int k : redo) again[k] = 1;
        std::vector<int> next;
        // the pending clusters not reached yet have no results: redo them too
        // (their numbering changed; find them by their atoms)
        for (int k = 0; k < cs.nclusters(); k++) {
          bool done = true;
          for (int i : cs.atoms(k)) done = done && done_[i];
          if (again[k] || !done) next.push_back(k);
        }
        pending = next;
        st.growths++;
        st.redone += (long) redo.size();
        continue;
      }
      // a contact of a cluster's atom with an atom outside that cluster?
      double tbest = dt + 1.0;
      int bi = -1, bj = -1;
      for (int i = 0; i < n; i++)
        for (int j = i + 1; j < n; j++) {
          const int ci = cs.cluster_of(i), cj = cs.cluster_of(j);
          if (ci == cj) continue;    // same cluster, or both on straight lines (screened)
          double tc;
          if (traj_contact(segs[i], segs[j], dt, tc, st) && tc < tbest) {
            tbest = tc;
            bi = i;
            bj = j;
          }
        }
      if (bi < 0) break;
      EXPECT_TRUE(cs.grow_contact(bi, bj));
      add_terms(c);    // only terms with a new member join; the rest is idempotent
      pending = cs.rebuild();
      st.growths++;
      st.redone += (long) pending.size();
    }
    // K_R(dt/2) at the end, V_R at the new positions
    const std::vector<char> use = vc_terms(c);
    std::vector<char> use_r(n);
    for (int t = 0; t < n; t++) use_r[t] = !use[t];
    std::vector<Vec> fr1;
    forces(c, qf, &use_r, fr1);
    for (int i = 0; i < n; i++)
      for (int k = 0; k < 3; k++) {
        c.q[i][k] = qf[i][k];
        c.p[i][k] = pf[i][k] + 0.5 * dt * fr1[i][k];
      }
    st.steps++;
  }
};

// Variant "frozen partners" (not the splitting; a candidate for
// systems where the clusters percolate, bench/scaling/README.md):
// H = H1 + H2 with H1 = T_C + V_C (kinetic energy of the members only) and
// H2 = T_N + V_R (kinetic energy of the non-members), integrated as
// Phi_H1(dt/2) . Phi_H2(dt) . Phi_H1(dt/2). In Phi_H1 only members move
// (CVA sub-steps); partners stay put and take V_C's impulses, so two
// members that only share a partner are independent. Phi_H2 is one plain
// Verlet step of the non-members under V_R (members do not move and V_R
// does not act on them). A non-member that touches anything in either flow
// becomes a member and the step is redone. Here Phi_H1 moves all members
// together (one flow): per-cluster flows would differ only in where the
// Verlet sub-steps fall, as the variant above shows.
struct FrozenIntegrator {
  Stats st;

  // Phi_H1 over (0, h]: members move; a contact with a non-member is returned
  Hit flow_h1(const Chain &c, const std::vector<char> &mem, const std::vector<char> &use_c,
              double h, std::vector<Vec> &q, std::vector<Vec> &p)
  {
    const int n = c.n;
    std::vector<int> M;
    for (int i = 0; i < n; i++)
      if (mem[i]) M.push_back(i);
    std::vector<Vec> f, f1, zero(n, Vec{0, 0, 0}), q1;
    forces(c, q, &use_c, f);
    double t = 0.0, tau = h;
    while (tau > 0.0) {
      // members on Verlet paths, everyone else static: velocity and
      // acceleration of a static atom are zero
      std::vector<Vec> v(n, Vec{0, 0, 0}), a(n, Vec{0, 0, 0});
      for (int i : M) {
        v[i] = p[i];
        a[i] = f[i];
      }
      std::vector<int> all(n);
      for (int i = 0; i < n; i++) all[i] = i;
      // earliest over pairs with at least one member (static pairs never meet)
      Hit best{tau + 1.0, -1, -1};
      double cc[5];
      for (int i : M) {
        HardSphere::wall_gap_poly(q[i][0] - RAD, v[i][0], a[i][0], cc);
        const Contact w = first_contact(cc, 2, tau, TOL_WALL);
        if (w.status == HardSphere::OVERLAP) st.overlaps++;
        if (w.status != HardSphere::NO_CONTACT && w.t < best.t) best = {w.t, i, -1};
        for (int j = 0; j < n; j++) {
          if (j == i || (mem[j] && j < i)) continue;
          Vec dq, dv, da;
          for (int k = 0; k < 3; k++) {
            dq[k] = q[i][k] - q[j][k];
            dv[k] = v[i][k] - v[j][k];
            da[k] = a[i][k] - a[j][k];
          }
          HardSphere::pair_gap_poly(dq.data(), dv.data(), da.data(), SIGMA, cc);
          const Contact k = first_contact(cc, 4, tau, TOL_PAIR);
          if (k.status == HardSphere::OVERLAP) st.overlaps++;
          if (k.status != HardSphere::NO_CONTACT && k.t < best.t) best = {k.t, i, j};
        }
      }
      const bool hit = best.t <= tau;
      if (hit && best.j >= 0 && !mem[best.j]) return best;
      const double d = hit ? best.t : tau;
      q1 = q;
      for (int i : M)
        for (int k = 0; k < 3; k++) q1[i][k] = q[i][k] + d * p[i][k] + 0.5 * d * d * f[i][k];
      forces(c, q1, &use_c, f1);
      // every atom takes V_C's momentum (trapezoid); only members move
      for (int i = 0; i < n; i++)
        for (int k = 0; k < 3; k++) p[i][k] += 0.5 * d * (f[i][k] + f1[i][k]);
      q = q1;
      f = f1;
      if (hit) {
        impulse(q, p, best.i, best.j);
        st.contacts++;
      }
      t += d;
      tau = hit ? h - t : 0.0;
    }
    return {h, -1, -1};
  }

  void step(Chain &c, double dt)
  {
    const int n = c.n;
    std::vector<char> mem(n, 0);
    {
      // first guess: contacts on the Verlet paths of the unsplit step
      std::vector<Vec> f0;
      forces(c, c.q, nullptr, f0);
      std::vector<int> all(n);
      for (int i = 0; i < n; i++) all[i] = i;
      Stats tmp;
      for (int i = 0; i < n; i++)
        for (int j = -1; j < n; j++) {
          if (j >= 0 && j <= i) continue;
          double cc[5];
          Contact k;
          if (j < 0) {
            HardSphere::wall_gap_poly(c.q[i][0] - RAD, c.p[i][0], f0[i][0], cc);
            k = first_contact(cc, 2, dt, TOL_WALL);
          } else {
            Vec dq, dv, da;
            for (int d = 0; d < 3; d++) {
              dq[d] = c.q[i][d] - c.q[j][d];
              dv[d] = c.p[i][d] - c.p[j][d];
              da[d] = f0[i][d] - f0[j][d];
            }
            HardSphere::pair_gap_poly(dq.data(), dv.data(), da.data(), SIGMA, cc);
            k = first_contact(cc, 4, dt, TOL_PAIR);
          }
          if (k.status == HardSphere::OVERLAP) st.overlaps++;
          if (k.status != HardSphere::NO_CONTACT) {
            mem[i] = 1;
            if (j >= 0) mem[j] = 1;
          }
        }
    }
    for (int guard = 0;; guard++) {
      ASSERT_LT(guard, 2 * n + 2) << "growth does not terminate";
      std::vector<char> use_c(n), use_r(n);
      for (int t = 0; t < n; t++) {
        const int a = term_a(t), b = term_b(t);
        use_c[t] = mem[b] || (a >= 0 && mem[a]);
        use_r[t] = !use_c[t];
      }
      std::vector<Vec> q = c.q, p = c.p;
      Hit h = flow_h1(c, mem, use_c, 0.5 * dt, q, p);
      if (h.i < 0) {
        // Phi_H2: one Verlet step of the non-members; any contact of theirs grows
        std::vector<Vec> fr, fr1;
        forces(c, q, &use_r, fr);
        std::vector<Vec> v(n, Vec{0, 0, 0}), a(n, Vec{0, 0, 0});
        for (int i = 0; i < n; i++)
          if (!mem[i]) {
            v[i] = p[i];
            a[i] = fr[i];
          }
        double cc[5];
        for (int i = 0; i < n && h.i < 0; i++) {
          if (mem[i]) continue;
          HardSphere::wall_gap_poly(q[i][0] - RAD, v[i][0], a[i][0], cc);
          Contact w = first_contact(cc, 2, dt, TOL_WALL);
          if (w.status != HardSphere::NO_CONTACT) h = {w.t, i, -1};
          for (int j = 0; j < n && h.i < 0; j++) {
            if (j == i || (!mem[j] && j < i)) continue;
            Vec dq, dv, da;
            for (int k = 0; k < 3; k++) {
              dq[k] = q[i][k] - q[j][k];
              dv[k] = v[i][k] - v[j][k];
              da[k] = a[i][k] - a[j][k];
            }
            HardSphere::pair_gap_poly(dq.data(), dv.data(), da.data(), SIGMA, cc);
            Contact k = first_contact(cc, 4, dt, TOL_PAIR);
            if (k.status != HardSphere::NO_CONTACT) h = {k.t, i, j};
          }
        }
        if (h.i < 0) {
          for (int i = 0; i < n; i++)
            if (!mem[i])
              for (int k = 0; k < 3; k++) {
                p[i][k] += 0.5 * dt * fr[i][k];
                q[i][k] += dt * p[i][k];
              }
          forces(c, q, &use_r, fr1);
          for (int i = 0; i < n; i++)
            if (!mem[i])
              for (int k = 0; k < 3; k++) p[i][k] += 0.5 * dt * fr1[i][k];
          h = flow_h1(c, mem, use_c, 0.5 * dt, q, p);
        }
      }
      if (h.i < 0) {
        c.q = q;
        c.p = p;
        break;
      }
      mem[h.i] = 1;
      if (h.j >= 0) mem[h.j] = 1;
      st.growths++;
    }
    st.steps++;
  }
};

Chain initial(int n, unsigned seed)
{
  Chain c;
  c.n = n;
  c.q.assign(n, Vec{0, 0, 0});
  c.p.assign(n, Vec{0, 0, 0});
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 2.0 * M_PI);
  for (int i = 0; i < n; i++) {
    c.q[i][0] = i + 1.0;
    if (i % 2 == 1) {    // spheres 2, 4, ...: random unit velocities (section 4)
      const double th = u(rng);
      c.p[i][0] = std::cos(th);
      c.p[i][1] = std::sin(th);
    }
  }
  return c;
}

struct RunOut {
  double max_de;
  Stats st;
};

template <class StepFn> RunOut run(Chain c, double dt, double T, StepFn stepfn, Stats &st)
{
  const double e0 = energy(c);
  double m = 0.0;
  const long nsteps = std::lround(T / dt);
  for (long s = 0; s < nsteps; s++) {
    stepfn(c, dt);
    if (::testing::Test::HasFatalFailure()) break;
    m = std::max(m, std::fabs(energy(c) - e0));
  }
  return {m, st};
}

double slope(const std::vector<double> &x, const std::vector<double> &y)
{
  double mx = 0, my = 0;
  for (size_t k = 0; k < x.size(); k++) {
    mx += std::log(x[k]) / x.size();
    my += std::log(y[k]) / y.size();
  }
  double sxy = 0, sxx = 0;
  for (size_t k = 0; k < x.size(); k++) {
    sxy += (std::log(x[k]) - mx) * (std::log(y[k]) - my);
    sxx += (std::log(x[k]) - mx) * (std::log(x[k]) - mx);
  }
  return sxy / sxx;
}

}    // namespace

class LocalSplitting : public ::testing::TestWithParam<int> {};

TEST_P(LocalSplitting, SecondOrderAndCloseToGlobal)
{
  // the largest |H(t) - H(0)| over T = 100 of one chaotic trajectory is a
  // noisy number; its mean over NSEED initial conditions is the statistic
  const int n = GetParam();
  const double T = 100.0;
  const int NSEED = 8;
  const std::vector<double> dts = {0.08, 0.04, 0.02, 0.01};
  std::vector<double> eg, el;
  long growths = 0, contacts_l = 0;
  for (double dt : dts) {
    double mg = 0.0, ml = 0.0;
    Stats sg;
    LocalIntegrator L;
    for (int seed = 1; seed <= NSEED; seed++) {
      RunOut g = run(initial(n, 1000 + seed), dt, T,
                     [&](Chain &c, double h) { step_global(c, h, sg); }, sg);
      RunOut l = run(initial(n, 1000 + seed), dt, T, [&](Chain &c, double h) { L.step(c, h); },
                     L.st);
      ASSERT_FALSE(HasFatalFailure());
      mg += g.max_de / NSEED;
      ml += l.max_de / NSEED;
    }
    EXPECT_EQ(sg.overlaps, 0) << "global dt " << dt;
    EXPECT_EQ(L.st.overlaps, 0) << "local dt " << dt;
    EXPECT_GT(sg.contacts, 1000) << "too few collisions to test anything, dt " << dt;
    eg.push_back(mg);
    el.push_back(ml);
    growths += L.st.growths;
    contacts_l += L.st.contacts;
    L.cs.flush_counters();
    const auto &k = L.cs.counters();
    printf("n %2d dt %.2f  mean max|dE| global %.3e local %.3e (ratio %.2f)  contacts %ld / %ld  "
           "growths %ld redone %ld  clusters/step %.2f mean atoms %.2f members %.2f max %d\n",
           n, dt, mg, ml, ml / mg, sg.contacts, L.st.contacts, L.st.growths, L.st.redone,
           k.clusters / k.steps, k.mean_atoms(), k.mean_members(), k.max_atoms);
    EXPECT_GE(ml / mg, 0.5) << "dt " << dt;
    EXPECT_LE(ml / mg, 2.0) << "dt " << dt;
  }
  const double sg = slope(dts, eg), sl = slope(dts, el);
  printf("n %2d fitted slopes: global %.3f local %.3f\n", n, sg, sl);
  EXPECT_GE(sg, 1.8);
  EXPECT_GE(sl, 1.8);
  EXPECT_GT(growths, 0) << "the growth/redo path was never taken";
  EXPECT_GT(contacts_l, 4000);
}

INSTANTIATE_TEST_SUITE_P(Chains, LocalSplitting, ::testing::Values(8, 12),
                         [](const ::testing::TestParamInfo<int> &i) {
                           return "n" + std::to_string(i.param);
                         });

// without any contact both integrators are plain Verlet: identical steps
TEST(LocalSplittingNoContacts, ReducesToVerlet)
{
  Chain c = initial(6, 1);
  for (auto &p : c.p) p = Vec{0.0, 0.05 * p[1], 0.0};    // gentle: nothing collides
  Chain a = c, b = c;
  Stats sg;
  LocalIntegrator L;
  for (int s = 0; s < 200; s++) {
    step_global(a, 0.02, sg);
    L.step(b, 0.02);
  }
  ASSERT_EQ(sg.contacts, 0);
  ASSERT_EQ(L.st.contacts, 0);
  // plain velocity Verlet, written out here
  std::vector<Vec> f, f1;
  for (int s = 0; s < 200; s++) {
    forces(c, c.q, nullptr, f);
    for (int i = 0; i < c.n; i++)
      for (int k = 0; k < 3; k++) {
        c.p[i][k] += 0.01 * f[i][k];
        c.q[i][k] += 0.02 * c.p[i][k];
      }
    forces(c, c.q, nullptr, f1);
    for (int i = 0; i < c.n; i++)
      for (int k = 0; k < 3; k++) c.p[i][k] += 0.01 * f1[i][k];
  }
  for (int i = 0; i < c.n; i++)
    for (int k = 0; k < 3; k++) {
      EXPECT_NEAR(a.q[i][k], c.q[i][k], 1e-12);
      EXPECT_NEAR(b.q[i][k], c.q[i][k], 1e-12);
      EXPECT_NEAR(b.p[i][k], c.p[i][k], 1e-12);
    }
}

// the frozen-partner variant: second order too, and how close to global CVA
class FrozenPartners : public ::testing::TestWithParam<int> {};

TEST_P(FrozenPartners, SecondOrderAndCloseToGlobal)
{
  const int n = GetParam();
  const double T = 100.0;
  const int NSEED = 8;
  const std::vector<double> dts = {0.08, 0.04, 0.02, 0.01};
  std::vector<double> eg, ef;
  long growths = 0;
  for (double dt : dts) {
    double mg = 0.0, mf = 0.0;
    Stats sg;
    FrozenIntegrator F;
    for (int seed = 1; seed <= NSEED; seed++) {
      RunOut g = run(initial(n, 1000 + seed), dt, T,
                     [&](Chain &c, double h) { step_global(c, h, sg); }, sg);
      RunOut f = run(initial(n, 1000 + seed), dt, T, [&](Chain &c, double h) { F.step(c, h); },
                     F.st);
      ASSERT_FALSE(HasFatalFailure());
      mg += g.max_de / NSEED;
      mf += f.max_de / NSEED;
    }
    EXPECT_EQ(F.st.overlaps, 0) << "frozen dt " << dt;
    eg.push_back(mg);
    ef.push_back(mf);
    growths += F.st.growths;
    printf("n %2d dt %.2f  mean max|dE| global %.3e frozen-partners %.3e (ratio %.2f)  "
           "contacts %ld / %ld  growths %ld\n",
           n, dt, mg, mf, mf / mg, sg.contacts, F.st.contacts, F.st.growths);
  }
  const double sg = slope(dts, eg), sf = slope(dts, ef);
  printf("n %2d fitted slopes: global %.3f frozen-partners %.3f\n", n, sg, sf);
  EXPECT_GE(sf, 1.8);
  for (size_t k = 0; k < dts.size(); k++) {
    EXPECT_GE(ef[k] / eg[k], 0.5) << "dt " << dts[k];
    EXPECT_LE(ef[k] / eg[k], 2.0) << "dt " << dts[k];
  }
  EXPECT_GT(growths, 0);
}

INSTANTIATE_TEST_SUITE_P(Chains, FrozenPartners, ::testing::Values(8, 12),
                         [](const ::testing::TestParamInfo<int> &i) {
                           return "n" + std::to_string(i.param);
                         });
