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
     flow (ClusterGauss::contact_time(): a Gauss step of each trial length,
     as the global form's contact_root()); the step to it is checked again
     on its own parabola (a contact it reaches first is taken instead);
   - the partners' momentum over a sub-step is its Gauss quadrature, tau
     (F(Y1) + F(Y2))/2 of ClusterGauss::partner_forces(): the members'
     momentum change over the step is the same quadrature of their dp/dt,
     so momentum is conserved to round-off;
   - the sub-steps' parabolas are kept (segments(): q0, v, a, on [t0, t1]),
     the paths the engine checks other clusters and atoms against.

   Pure math, no LAMMPS types, header-only, unit-tested alone
   (unittest/math/test_cluster_flow.cpp).
------------------------------------------------------------------------- */

#ifndef LMP_HS_CLUSTER_FLOW_H
#define LMP_HS_CLUSTER_FLOW_H

#include "hs_cluster_gauss.h"
#include "hs_contact.h"

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
struct FlowStats {
  double pair = 0.0, wall = 0.0;    // impulses given
  double substeps = 0.0;            // accepted Gauss steps
  double solves = 0.0;              // Gauss steps solved (sub-steps and trial lengths)
  double iterations = 0.0;          // Newton iterations of all solves
  double maxit = 0.0;               // most Newton iterations of one solve
  double fields = 0.0, jacobians = 0.0;
  double refine = 0.0;              // Gauss steps of the contact-time searches
};

template <class Phi> class ClusterFlow {
 public:
  // NONCONVEX: H~ is not convex in the momenta along a contact's normal
  // (dt too large for the curvature of V; the global form's error):
  // hit_member and hit_static name the contact (a wall w as -1 - w), y is
  // at it
  enum End { DONE = 0, STATIC_HIT = 1, FAILED = 2, NONCONVEX = 3 };

  // radii of the members; statics: contact candidates that do not move;
  // npartners: the partners' count (ClusterTerm::partner < npartners);
  // tol: the contact tolerance of a gap in length units (hs_types.h)
  ClusterFlow(const ClusterGauss<Phi> &g, std::vector<double> radii,
              std::vector<FlowStatic> statics, std::vector<FlowWall> walls, int npartners,
              double tol) :
      G(g), rad(std::move(radii)), stat(std::move(statics)), wall(std::move(walls)),
      np(npartners), tol_(tol)
  {
  }

  // the flow over time h from y (6n; left at the end, or at the static
  // hit's time for STATIC_HIT). pmom[3 np]: the partners' momentum (added)
  End run(double h, std::vector<double> &y, std::vector<double> &pmom)
  {
    const int n = G.members(), N = G.dim();
    segs.assign(n, {});
    pmom.resize(3 * np, 0.0);
    std::vector<double> y1(N), pf(3 * np);
    ClusterStepDetail det;
    double t = 0.0;
    int nsub = 0;
    while (true) {
      const double tau = h - t;
      if (!solve(y, tau, y1, det)) return FAILED;
      Hit hit = earliest(y, det, tau);
      if (hit.kind == Hit::NONE) {
        accept(y, y1, det, t, tau, pf, pmom);
        return DONE;
      }
      if (hit.kind == Hit::STATIC) {
        hit_member = hit.i;
        hit_static = hit.j;
        return STATIC_HIT;
      }
      // refine on the flow; a contact the refined step reaches first
      // replaces it (at most a few times: each is earlier)
      double ts = hit.t;
      for (int round = 0; round < 8; round++) {
        ts = refine(y, hit, ts, tau);
        if (!(ts >= 0.0)) return FAILED;
        if (ts > 0.0 && !solve(y, ts, y1, det)) return FAILED;
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
      if (ts > 0.0) accept(y, y1, det, t, ts, pf, pmom);
      t += ts;
      if (!impulse(y, hit)) {
        hit_member = hit.i;
        hit_static = hit.kind == Hit::PAIR ? hit.j : -1 - hit.j;
        return NONCONVEX;
      }
      if (++nsub > 100000) return FAILED;    // a Zeno sequence (the caller's error)
    }
  }

  const std::vector<std::vector<FlowSeg>> &segments() const { return segs; }
  FlowStats stats;
  int hit_member = -1, hit_static = -1;

 private:
  const ClusterGauss<Phi> &G;
  std::vector<double> rad;
  std::vector<FlowStatic> stat;
  std::vector<FlowWall> wall;
  int np;
  double tol_;
  std::vector<std::vector<FlowSeg>> segs;

  struct Hit {
    enum { NONE = 0, PAIR = 1, WALL = 2, STATIC = 3 };
    int kind = NONE, i = -1, j = -1;
    double t = std::numeric_limits<double>::infinity();
  };

  bool solve(const std::vector<double> &y, double tau, std::vector<double> &y1,
             ClusterStepDetail &det)
  {
    const ClusterNewtonStatus st = G.step(y.data(), tau, y1.data(), ClusterNewtonOptions(), &det);
    stats.solves += 1.0;
    stats.iterations += st.iterations;
    stats.maxit = std::max(stats.maxit, (double) st.iterations);
    stats.fields += st.fields;
    stats.jacobians += st.jacobians;
    return st.converged;
  }

  // the earliest contact on the step's parabola within (0, tmax]
  Hit earliest(const std::vector<double> &y, const ClusterStepDetail &det, double tmax) const
  {
    const int n = G.members();
    Hit b;
    auto consider = [&](const double *c, int deg, int kind, int i, int j) {
      const Contact ct = first_contact(c, deg, tmax, tol_);
      if (ct.status == NO_CONTACT) return;
      const double tc = (ct.status == CONTACT) ? ct.t : 0.0;
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
        for (int d = 0; d < 3; d++) {
          dq[d] = qi[d] - y[3 * j + d];
          dv[d] = vi[d] - det.vq[3 * j + d];
          da[d] = ai[d] - det.aq[3 * j + d];
        }
        pair_gap_poly(dq, dv, da, rad[i] + rad[j], c);
        scale_tol(c, rad[i] + rad[j]);
        consider(c, 4, Hit::PAIR, i, j);
      }
      for (int s = 0; s < (int) stat.size(); s++) {
        double dq[3];
        for (int d = 0; d < 3; d++) dq[d] = qi[d] - stat[s].x[d];
        const double sig = rad[i] + stat[s].radius;
        pair_gap_poly(dq, vi, ai, sig, c);
        scale_tol(c, sig);
        consider(c, 4, Hit::STATIC, i, s);
      }
      for (int w = 0; w < (int) wall.size(); w++) {
        const FlowWall &W = wall[w];
        wall_gap_poly(W.sign * (qi[W.dim] - W.coord) - rad[i], W.sign * vi[W.dim],
                      W.sign * ai[W.dim], c);
        consider(c, 2, Hit::WALL, i, w);
      }
    }
    return b;
  }
  // the pair gap polynomial is |d|^2 - sigma^2 ~ 2 sigma (|d| - sigma): in
  // length units, as the wall's (so one tolerance serves both)
  static void scale_tol(double *c, double sigma)
  {
    for (int k = 0; k < 5; k++) c[k] /= 2.0 * sigma;
  }

  // the contact time of hit on the flow from y, near the guess
  double refine(const std::vector<double> &y, const Hit &hit, double guess, double tmax)
  {
    if (guess <= 0.0) return 0.0;
    RootResult rr;
    const double ttol = 1e-14 * std::max(tmax, 1e-300) + 1e-300;
    if (hit.kind == Hit::PAIR)
      rr = G.contact_time(y.data(), hit.i, hit.j, nullptr, rad[hit.i] + rad[hit.j], guess, tmax,
                          ttol);
    else {
      const FlowWall &W = wall[hit.j];
      std::vector<double> yt(G.dim());
      auto gap = [&](double tt, double &g, double &dg) {
        G.step(y.data(), tt, yt.data());
        g = W.sign * (yt[3 * hit.i + W.dim] - W.coord) - rad[hit.i];
        dg = W.sign * yt[3 * G.members() + 3 * hit.i + W.dim];
      };
      rr = contact_root(gap, guess, tmax, ttol, 60);
    }
    stats.refine += rr.nevals;
    stats.solves += rr.nevals;
    if (rr.status != ROOT_FOUND) return guess;    // the parabola's time (the flow grazes)
    return rr.t;
  }

  void accept(std::vector<double> &y, const std::vector<double> &y1,
              const ClusterStepDetail &det, double t, double tau, std::vector<double> &pf,
              std::vector<double> &pmom)
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
    if (np > 0) {
      std::fill(pf.begin(), pf.end(), 0.0);
      G.partner_forces(det.Y1.data(), pf.data());
      G.partner_forces(det.Y2.data(), pf.data());
      for (int k = 0; k < 3 * np; k++) pmom[k] += 0.5 * tau * pf[k];
    }
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
    if (hit.kind == Hit::PAIR) {
      double dq[3], r = 0.0;
      for (int d = 0; d < 3; d++) {
        dq[d] = y[3 * hit.i + d] - y[3 * hit.j + d];
        r += dq[d] * dq[d];
      }
      r = std::sqrt(r);
      for (int d = 0; d < 3; d++) {
        u[3 * hit.i + d] = dq[d] / r;
        u[3 * hit.j + d] = -dq[d] / r;
        un += dq[d] / r * (y[m + 3 * hit.i + d] - y[m + 3 * hit.j + d]);
      }
    } else {
      const FlowWall &W = wall[hit.j];
      u[3 * hit.i + W.dim] = W.sign;
      un = W.sign * y[m + 3 * hit.i + W.dim];
    }
    if (!(un < 0.0)) return true;    // grazing or separating: no impulse
    double alpha = 0.0;
    if (!G.alpha_hat(y.data(), u.data(), alpha)) return false;
    for (int k = 0; k < m; k++) y[m + k] += alpha * G.inverse_mass(k / 3) * u[k];
    (hit.kind == Hit::PAIR ? stats.pair : stats.wall) += 1.0;
    return true;
  }
};

}    // namespace HardSphere

#endif
