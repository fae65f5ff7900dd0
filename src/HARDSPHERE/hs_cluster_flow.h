/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: one cluster's flow with contacts for the local form
   of fix hardsphere/mcva (issue 21; doc/fix_hardsphere_mcva.rst, "Local
   form"): the members follow the Gauss-Legendre flow of the cluster's
   modified Hamiltonian H~_1 (hs_cluster_gauss.h) from contact to contact,
   each contact gets the impulse alpha-hat that keeps H~_1 (Bond &
   Leimkuhler 2007, section 3.1), and the partners (static atoms in the
   terms) take the terms' momentum. It is to the local engine's Phi_H1
   what MCVA's sub-steps are to the global engine:

   - a sub-step is one Gauss step to the end of the flow; contacts are
     predicted on its collocation parabola (exact polynomial gaps,
     hs_contact.h), among members, against static spheres (the caller's
     contact candidates: a hit ends the flow, the cluster grows) and walls;
   - the earliest member-member or wall contact's time is refined on the
     flow (a Gauss step of each trial length, kept for the step to it,
     by safeguarded Newton on the gap); the step to it is checked again
     on its own parabola (a contact it reaches first is taken instead);
   - the partners' momentum over a sub-step is its Gauss quadrature, tau
     (F(Y1) + F(Y2))/2 of the partner forces of the last Newton
     iteration's stage passes (ClusterStepDetail::pf1, pf2): the members'
     momentum change over the step is the same quadrature of their dp/dt
     (to the stages' tolerance), so momentum is conserved to round-off;
   - the sub-steps' parabolas are kept (segments(): q0, v, a, on [t0, t1]),
     the paths the engine checks other clusters and atoms against.

   Pure math, no LAMMPS types, header-only, unit-tested alone
   (unittest/math/test_cluster_flow.cpp).
------------------------------------------------------------------------- */

#ifndef LMP_HS_CLUSTER_FLOW_H
#define LMP_HS_CLUSTER_FLOW_H

#include "hs_cluster_gauss.h"
#include "hs_contact.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace HardSphere {

// a plane x_dim = coord; the spheres stay on the side of sign (+1: above)
struct FlowWall {
  int dim = 0;
  double coord = 0.0, sign = 1.0;
};
// a static sphere the members may touch (a contact candidate that is not
// a member)
struct FlowStatic {
  double x[3] = {0.0, 0.0, 0.0};
  double radius = 0.5;
};
struct FlowSeg {
  double t0, t1;
  double q[3], v[3], a[3];    // q(t) = q + (t - t0) v + (t - t0)^2 / 2 a
};
// an impulse given: to member i the momentum J (member j, if any, -J; j <
// 0: wall -1 - j), in the kernel's units (a = im F: J = alpha u with u the
// unit normal), dq the contact normal (q_i - q_j, or q_i - the wall's plane)
struct FlowKick {
  int i, j;
  double J[3], dq[3];
};
// (the Gauss solves' counts: the kernel's ClusterTally)
struct FlowStats {
  double pair = 0.0, wall = 0.0;    // impulses given
  double substeps = 0.0;            // accepted Gauss steps
  double refine = 0.0;              // Gauss steps of the contact-time searches
};

template <class Phi> class ClusterFlow {
 public:
  // NONCONVEX: H~ is not convex in the momenta along a contact's normal
  // (dt too large for the curvature of V; the global form's error):
  // hit_member and hit_static name the contact (a wall w as -1 - w), y is
  // at it
  // OVERLAP: a pair or wall overlaps by more than the tolerance at a
  // sub-step's start (a missed contact: the caller's error)
  // RESTING: a contact stays touching with no normal approach on the flow
  // for max_stuck zero-length sub-steps running (a sphere pressed against a
  // wall or a neighbour: a resting contact, the caller's documented error);
  // hit_member and hit_static name it as for NONCONVEX
  enum End { DONE = 0, STATIC_HIT = 1, FAILED = 2, NONCONVEX = 3, OVERLAP = 4, RESTING = 5 };
  int max_stuck = 100;    // (hs_types.h, MAX_STUCK)

  // radii of the members; statics: contact candidates that do not move;
  // npartners: the partners' count (ClusterTerm::partner < npartners);
  // tol: touching within tol sigma^2 of a pair's |d|^2 - sigma^2, tol 2r of
  // a wall's gap (hs_types.h, TOUCH_TOL)
  ClusterFlow(const ClusterGauss<Phi> &g, std::vector<double> radii,
              std::vector<FlowStatic> statics, std::vector<FlowWall> walls, int npartners,
              double tol) :
      G(g)
  {
    rad = std::move(radii);
    stat = std::move(statics);
    wall = std::move(walls);
    reset(npartners, tol);
  }
  // another cluster of G's (radii, statics, walls: into radii(), statics(),
  // walls(), before), with this object's storage
  void reset(int npartners, double tol)
  {
    np = npartners;
    tol_ = tol;
    poff.assign(3 * rad.size() * rad.size(), 0.0);
    stats = FlowStats();
    hit_member = hit_static = -1;
  }
  std::vector<double> &radii() { return rad; }
  std::vector<FlowStatic> &statics() { return stat; }
  std::vector<FlowWall> &walls() { return wall; }
  // periodic images: the separation of members i and j is q_i - q_j +
  // off (off[3] for i < j; the caller's nearest images at the flow's start)
  void set_pair_offset(int i, int j, const double *off)
  {
    const int n = (int) rad.size();
    for (int d = 0; d < 3; d++) {
      poff[3 * (i * n + j) + d] = off[d];
      poff[3 * (j * n + i) + d] = -off[d];
    }
  }

  // the flow over time h from y (6n; left at the end, or at the static
  // hit's time for STATIC_HIT). pmom[3 np]: the partners' momentum (added)
  End run(double h, std::vector<double> &y, std::vector<double> &pmom)
  {
    const int n = G.members(), N = G.dim();
    // (the segments' rows, y1 and det kept from the last flow, emptied:
    // allocated anew at every flow they were ~1 % of mcva's samples in
    // malloc and free at 32000 atoms)
    segs.resize(n);
    for (auto &sg : segs) sg.clear();
    kick.clear();
    pmom.resize(3 * np, 0.0);
    std::vector<double> &y1 = y1_;
    y1.assign(N, 0.0);
    ClusterStepDetail &det = det_;
    for (auto *w : {&det.Y1, &det.Y2, &det.vq, &det.aq, &det.pf1, &det.pf2}) w->clear();
    double t = 0.0;
    int nsub = 0, stuck = 0;
    while (true) {
      const double tau = h - t;
      // the predictor's parabola first (ClusterGauss::predict(), no Newton
      // iteration): a contact between members or with a wall on it goes
      // straight to the contact-time search on the flow, whose first trial
      // is then the sub-step's first solve; the whole sub-step is solved
      // only where that parabola has none, or the flow reaches none within
      // tau (a contact with a static sphere, the cluster's growth, is left
      // to the solved step's parabola, as before). On the 4000 fluid the
      // search takes as many trials from that parabola's time as from the
      // solved step's, whose solve was a fifth of all
      Hit hit;
      double ts = -1.0;
      bool refined = false;
      ntrial_ = 0;    // (the kept trials are from one start: this one's)
      G.predict(y.data(), tau, newton_opt(), det);
      {
        const Hit hp = earliest(y, det, tau);
        if (!hp.overlap && (hp.kind == Hit::PAIR || hp.kind == Hit::WALL)) {
          ts = refine(y, hp, hp.t, tau, true);
          if (ts == -1.0) return FAILED;
          refined = ts >= 0.0;
          if (refined) hit = hp;
        }
      }
      if (!refined) {
        // (the search's trial at tau, if it made one)
        if (const Trial *tr = tried(tau)) {
          y1 = tr->y1;
          det = tr->det;
        } else if (!solve(y, tau, y1, det))
          return FAILED;
        hit = earliest(y, det, tau);
        if (hit.overlap) return OVERLAP;
        if (hit.kind == Hit::NONE) {
          accept(y, y1, det, t, tau, pmom);
          return DONE;
        }
        if (hit.kind == Hit::STATIC) {
          hit_member = hit.i;
          hit_static = hit.j;
          return STATIC_HIT;
        }
        ts = hit.t;
      }
      // refine on the flow; a contact the refined step reaches first
      // replaces it (at most a few times: each is earlier)
      for (int round = 0; round < 8; round++) {
        if (!(round == 0 && refined)) ts = refine(y, hit, ts, tau);
        if (!(ts >= 0.0)) return FAILED;
        if (const Trial *tr = tried(ts)) {
          y1 = tr->y1;
          det = tr->det;
        } else if (ts > 0.0 && !solve(y, ts, y1, det))
          return FAILED;
        if (ts == 0.0) {
          y1 = y;
          break;
        }
        const Hit h2 = earliest(y, det, ts * (1.0 - 1e-12));
        if (h2.kind == Hit::NONE) break;
        if (h2.kind == Hit::STATIC) {
          hit_member = h2.i;
          hit_static = h2.j;
          return STATIC_HIT;
        }
        hit = h2;
        ts = h2.t;
      }
      if (ts > 0.0) accept(y, y1, det, t, ts, pmom);
      t += ts;
      const size_t kicked = kick.size();
      if (!impulse(y, hit)) {
        hit_member = hit.i;
        hit_static = hit.kind == Hit::PAIR ? hit.j : -1 - hit.j;
        return NONCONVEX;
      }
      // a touching contact that neither moves on nor gets an impulse
      stuck = (ts == 0.0 && kick.size() == kicked) ? stuck + 1 : 0;
      if (stuck >= max_stuck) {
        hit_member = hit.i;
        hit_static = hit.kind == Hit::PAIR ? hit.j : -1 - hit.j;
        return RESTING;
      }
      if (++nsub > 100000) return FAILED;    // a Zeno sequence (the caller's error)
    }
  }

  const std::vector<std::vector<FlowSeg>> &segments() const { return segs; }
  // the impulses of the last run(), in time order
  const std::vector<FlowKick> &kicks() const { return kick; }
  FlowStats stats;
  int hit_member = -1, hit_static = -1;

 private:
  const ClusterGauss<Phi> &G;
  std::vector<double> rad;
  std::vector<FlowStatic> stat;
  std::vector<FlowWall> wall;
  int np = 0;
  double tol_ = 0.0;
  std::vector<double> poff;    // [n][n][3] pair offsets
  const double *pair_off(int i, int j) const { return &poff[3 * (i * (int) rad.size() + j)]; }
  std::vector<std::vector<FlowSeg>> segs;
  std::vector<double> y1_;    // run()'s scratch
  ClusterStepDetail det_;
  std::vector<FlowKick> kick;
  // the Gauss solves' options: the Jacobian of the flow's start kept for
  // all its sub-steps (ClusterNewtonOptions::keep)
  static ClusterNewtonOptions newton_opt()
  {
    ClusterNewtonOptions o;
    o.keep = true;
    o.history = false;
    return o;
  }

  struct Hit {
    enum { NONE = 0, PAIR = 1, WALL = 2, STATIC = 3 };
    int kind = NONE, i = -1, j = -1;
    double t = std::numeric_limits<double>::infinity();
    bool overlap = false;    // some pair or wall already overlaps (a missed contact)
  };

  bool solve(const std::vector<double> &y, double tau, std::vector<double> &y1,
             ClusterStepDetail &det)
  {
    return G.step(y.data(), tau, y1.data(), newton_opt(), &det).converged;
  }

  // the earliest contact on the step's parabola within (0, tmax]
  Hit earliest(const std::vector<double> &y, const ClusterStepDetail &det, double tmax) const
  {
    const int n = G.members();
    Hit b;
    auto consider = [&](const double *c, int deg, double tol, int kind, int i, int j) {
      const Contact ct = first_contact(c, deg, tmax, tol);
      if (ct.status == HardSphere::NO_CONTACT) return;
      if (ct.status == HardSphere::OVERLAP) b.overlap = true;
      const double tc = (ct.status == HardSphere::CONTACT) ? ct.t : 0.0;
      if (tc < b.t) {
        b.kind = kind;
        b.i = i;
        b.j = j;
        b.t = tc;
      }
    };
    double c[5];
    for (int i = 0; i < n; i++) {
      const double *qi = &y[3 * i], *vi = &det.vq[3 * i], *ai = &det.aq[3 * i];
      for (int j = i + 1; j < n; j++) {
        double dq[3], dv[3], da[3];
        const double *off = pair_off(i, j);
        for (int d = 0; d < 3; d++) {
          dq[d] = qi[d] - y[3 * j + d] + off[d];
          dv[d] = vi[d] - det.vq[3 * j + d];
          da[d] = ai[d] - det.aq[3 * j + d];
        }
        const double sig = rad[i] + rad[j];
        pair_gap_poly(dq, dv, da, sig, c);
        consider(c, 4, tol_ * sig * sig, Hit::PAIR, i, j);
      }
      for (int s = 0; s < (int) stat.size(); s++) {
        double dq[3];
        for (int d = 0; d < 3; d++) dq[d] = qi[d] - stat[s].x[d];
        const double sig = rad[i] + stat[s].radius;
        pair_gap_poly(dq, vi, ai, sig, c);
        consider(c, 4, tol_ * sig * sig, Hit::STATIC, i, s);
      }
      for (int w = 0; w < (int) wall.size(); w++) {
        const FlowWall &W = wall[w];
        wall_gap_poly(W.sign * (qi[W.dim] - W.coord) - rad[i], W.sign * vi[W.dim],
                      W.sign * ai[W.dim], c);
        consider(c, 2, tol_ * 2.0 * rad[i], Hit::WALL, i, w);
      }
    }
    return b;
  }
  // the contact time of hit on the flow from y, near the guess (each trial
  // one Gauss step from y; the last ones kept, so that the step to the
  // root found is not solved again: tried())
  struct Trial {
    double t;
    std::vector<double> y1;
    ClusterStepDetail det;
  };
  // the last ntrial_ (<= 3) trials, oldest first; their storage is reused
  std::vector<Trial> trials;
  int ntrial_ = 0;
  std::vector<double> kf_;    // refine()'s field at a trial's end
  // (predicted: the guess is the predictor's, and a flow that reaches no
  // contact within tmax returns -2, where a solved step's guess, within its
  // O(h^3) of a contact, is taken as a graze; -1: the solve failed)
  double refine(const std::vector<double> &y, const Hit &hit, double guess, double tmax,
                bool predicted = false)
  {
    ntrial_ = 0;
    if (guess <= 0.0) return 0.0;
    // to 1e-11 of the sub-step: the gap then errs by ~1e-11 h |v_n|, far
    // below the touching tolerance
    const double ttol = 1e-11 * std::max(tmax, 1e-300) + 1e-300;
    const int n = G.members(), N = G.dim();
    auto gap = [&](double tt, double &g, double &dg) {
      if (ntrial_ == 3) std::rotate(trials.begin(), trials.begin() + 1, trials.begin() + 3);
      else if ((int) trials.size() <= ntrial_) trials.emplace_back();
      if (ntrial_ < 3) ntrial_++;
      Trial &tr = trials[ntrial_ - 1];
      tr.t = tt;
      tr.y1.resize(N);
      G.step(y.data(), tt, tr.y1.data(), newton_opt(), &tr.det);
      const std::vector<double> &yt = tr.y1;
      if (hit.kind == Hit::PAIR) {
        const double *off = pair_off(hit.i, hit.j);
        // |dq|^2 - sigma^2: half the round-off of |dq| - sigma relative to
        // its slope (a grazing contact's time is set by it)
        double dq[3], dv[3], r2 = 0.0, rv = 0.0;
        for (int d = 0; d < 3; d++) {
          dq[d] = yt[3 * hit.i + d] - yt[3 * hit.j + d] + off[d];
          dv[d] = yt[3 * n + 3 * hit.i + d] - yt[3 * n + 3 * hit.j + d];
          r2 += dq[d] * dq[d];
          rv += dq[d] * dv[d];
        }
        const double s = rad[hit.i] + rad[hit.j];
        g = r2 - s * s;
        dg = 2.0 * rv;
      } else {
        const FlowWall &W = wall[hit.j];
        g = W.sign * (yt[3 * hit.i + W.dim] - W.coord) - rad[hit.i];
        dg = W.sign * yt[3 * n + 3 * hit.i + W.dim];
      }
    };
    // the gap's first and second derivatives along the flow at the last
    // trial's end, from the field there (dq/dt = v + 2c M^-1 V'' v, dv/dt):
    // the end state's v is not dq/dt (off by the modified Hamiltonian's
    // velocity correction, 3e-3 relative at the fluid's sub-steps), and a
    // Gauss step's end moves with its length as the flow does, to O(h^4)
    auto flow_slopes = [&](double &g1, double &g2) {
      const std::vector<double> &yt = trials[ntrial_ - 1].y1;
      kf_.resize(N);
      G.field(yt.data(), kf_.data());
      g1 = g2 = 0.0;
      if (hit.kind == Hit::PAIR) {
        const double *off = pair_off(hit.i, hit.j);
        for (int d = 0; d < 3; d++) {
          const double dq = yt[3 * hit.i + d] - yt[3 * hit.j + d] + off[d];
          const double dv = kf_[3 * hit.i + d] - kf_[3 * hit.j + d];
          const double da = kf_[3 * n + 3 * hit.i + d] - kf_[3 * n + 3 * hit.j + d];
          g1 += 2.0 * dq * dv;
          // (dv/dt for d^2q/dt^2: off by O(c) relative, enough for the curvature)
          g2 += 2.0 * (dv * dv + dq * da);
        }
      } else {
        const FlowWall &W = wall[hit.j];
        g1 = W.sign * kf_[3 * hit.i + W.dim];
        g2 = W.sign * kf_[3 * n + 3 * hit.i + W.dim];
      }
    };
    // safeguarded root search on the gap from the parabola's time (its
    // error is the step's O(h^3): 6e-5 of the time at the fluid's median
    // contact), stopped at a gap within gtol on the allowed side (a time
    // bracket of width ttol would need a point past the contact too) that
    // is also within ttol of the contact in time, g <= |g'| ttol: a grazing
    // contact's normal speed |g'| is small, and a gap of 1e-12 would put its
    // time off by 1e-12 / |g'| (the impulse's direction with it;
    // StressGrazing). Where round-off in g keeps the search from that
    // window, the bracket closes to ttol
    // (a pair's g is |dq|^2 - sigma^2: its gap of 1e-12 sigma is 2e-12 sigma^2)
    const double gtol0 = hit.kind == Hit::PAIR
        ? 2e-12 * (rad[hit.i] + rad[hit.j]) * (rad[hit.i] + rad[hit.j])
        : 2e-12 * rad[hit.i];
    // Each step solves g + g' d + g'' d^2 / 2 = gtol / 2 by one Newton step
    // from d = -g / g' (Halley's method), g' and g'' along the flow
    // (flow_slopes(), one field evaluation): the error left is the cubic
    // term's, and the O(c) error of g'' times d^2. From the parabola's guess
    // one step reaches the window on 92 % of the fluid's contacts: 2.1
    // trials a contact, against 3.0 with secant steps on the end state's v
    // (4000 fluid, 200 steps: 48031 Gauss solves against 56928)
    double lo = 0.0, hi = tmax, t = std::min(guess, tmax), best = -1.0;
    bool have_hi = false;
    for (int it = 0; it < 60; it++) {
      double g, dg;
      gap(t, g, dg);
      stats.refine += 1.0;
      if (!(g == g)) return -1.0;
      // (the window's width from the end state's g' = 2 dq.v: its 3e-3 does
      // not matter there)
      const double gtol = std::min(gtol0, std::fabs(dg) * ttol);
      if (g >= 0.0) {
        lo = std::max(lo, t);
        best = t;
        if (g <= gtol) return t;
      } else {
        hi = std::min(hi, t);
        have_hi = true;
      }
      if (have_hi && hi - lo <= ttol) return best >= 0.0 ? best : lo;
      if (!have_hi && t >= tmax && g > 0.0)    // the flow grazes: the parabola's time
        return predicted ? -2.0 : guess;
      // (aimed at the middle of the allowed window [0, gtol])
      double g1, g2, tn = -1.0;
      flow_slopes(g1, g2);
      if (g1 != 0.0 && g1 == g1) {
        const double d0 = (0.5 * gtol - g) / g1, den = g1 + 0.5 * g2 * d0;
        // (Newton's step where the curvature would turn the slope over)
        tn = t + ((den * g1 > 0.0) ? (0.5 * gtol - g) / den : d0);
      }
      if (!(tn > lo && tn < hi)) tn = have_hi ? 0.5 * (lo + hi) : std::min(tmax, 2.0 * t);
      t = tn;
    }
    return best >= 0.0 ? best : guess;
  }
  // the kept trial of length t, if any
  const Trial *tried(double t) const
  {
    for (int k = 0; k < ntrial_; k++)
      if (trials[k].t == t) return &trials[k];
    return nullptr;
  }

  void accept(std::vector<double> &y, const std::vector<double> &y1,
              const ClusterStepDetail &det, double t, double tau, std::vector<double> &pmom)
  {
    const int n = G.members();
    for (int i = 0; i < n; i++) {
      FlowSeg s;
      s.t0 = t;
      s.t1 = t + tau;
      for (int d = 0; d < 3; d++) {
        s.q[d] = y[3 * i + d];
        s.v[d] = det.vq[3 * i + d];
        s.a[d] = det.aq[3 * i + d];
      }
      segs[i].push_back(s);
    }
    // (the stage passes' partner forces: no pass of their own; through
    // raw pointers and a bound read once, as the vectors' sizes were
    // reloaded after every store: ~1 % of mcva's instructions)
    const int npf = std::min(3 * np, (int) det.pf1.size());
    const double half_tau = 0.5 * tau, *pf1 = det.pf1.data(), *pf2 = det.pf2.data();
    double *pm = pmom.data();
    for (int k = 0; k < npf; k++) pm[k] += half_tau * (pf1[k] + pf2[k]);
    y = y1;
    stats.substeps += 1.0;
  }

  // alpha-hat along the contact normal, if the spheres approach (false: no
  // alpha-hat exists)
  bool impulse(std::vector<double> &y, const Hit &hit)
  {
    const int n = G.members(), m = 3 * n;
    std::vector<double> u(m, 0.0);
    double un = 0.0;
    FlowKick fk;
    fk.i = hit.i;
    fk.j = hit.kind == Hit::PAIR ? hit.j : -1 - hit.j;
    for (int d = 0; d < 3; d++) fk.dq[d] = 0.0;
    if (hit.kind == Hit::PAIR) {
      double dq[3], r = 0.0;
      for (int d = 0; d < 3; d++) {
        dq[d] = y[3 * hit.i + d] - y[3 * hit.j + d] + pair_off(hit.i, hit.j)[d];
        fk.dq[d] = dq[d];
        r += dq[d] * dq[d];
      }
      r = std::sqrt(r);
      for (int d = 0; d < 3; d++) {
        u[3 * hit.i + d] = dq[d] / r;
        u[3 * hit.j + d] = -dq[d] / r;
      }
    } else {
      const FlowWall &W = wall[hit.j];
      u[3 * hit.i + W.dim] = W.sign;
      fk.dq[W.dim] = y[3 * hit.i + W.dim] - W.coord;
    }
    // approaching on the flow's own path: the normal part of dq/dt = A p
    // (A = M^-1 + 2c M^-1 V'' M^-1), which alpha-hat reverses (u^T A p); the
    // plain velocity's can differ in sign for a touching pair at large steps
    {
      std::vector<double> k(G.dim());
      G.field(y.data(), k.data());
      un = 0.0;
      for (int q = 0; q < m; q++) un += u[q] * k[q];
    }
    if (!(un < 0.0)) return true;    // grazing or separating: no impulse
    double alpha = 0.0;
    if (!G.alpha_hat(y.data(), u.data(), alpha)) return false;
    for (int k = 0; k < m; k++) y[m + k] += alpha * G.inverse_mass(k / 3) * u[k];
    for (int d = 0; d < 3; d++) fk.J[d] = alpha * u[3 * hit.i + d];
    kick.push_back(fk);
    (hit.kind == Hit::PAIR ? stats.pair : stats.wall) += 1.0;
    return true;
  }
};

}    // namespace HardSphere

#endif
