// Test-side reference for the derivative layer: truncated Taylor series in
// s (order 4) and a hand-written potential energy V(x + s u) of a small
// molecule (lj/cut pairs with special factors, harmonic bonds, cosine/squared
// angles, minimum image in a periodic box). d^k/ds^k V(x + s u) at s = 0 is
// k! times the k-th coefficient: exact up to round-off, and independent of
// hs_jet.h (generic series arithmetic on the whole energy expression).
// Mixed derivatives follow by polarization:
//   V''[a,b]    = (D2(a+b) - D2(a-b)) / 4
//   V'''[a,w,w] = (D3(w+a) - D3(w-a) - 2 D3(a)) / 6

#ifndef HS_SERIES_H
#define HS_SERIES_H

#include <array>
#include <cmath>
#include <vector>

namespace hs_series {

struct S {
  double c[5] = {0, 0, 0, 0, 0};
};
inline S cst(double a)
{
  S r;
  r.c[0] = a;
  return r;
}
inline S operator+(const S &a, const S &b)
{
  S r;
  for (int k = 0; k < 5; k++) r.c[k] = a.c[k] + b.c[k];
  return r;
}
inline S operator-(const S &a, const S &b)
{
  S r;
  for (int k = 0; k < 5; k++) r.c[k] = a.c[k] - b.c[k];
  return r;
}
inline S operator*(double a, const S &b)
{
  S r;
  for (int k = 0; k < 5; k++) r.c[k] = a * b.c[k];
  return r;
}
inline S operator*(const S &a, const S &b)
{
  S r;
  for (int k = 0; k < 5; k++)
    for (int i = 0; i <= k; i++) r.c[k] += a.c[i] * b.c[k - i];
  return r;
}
inline S inv(const S &a)
{
  S b;
  b.c[0] = 1.0 / a.c[0];
  for (int k = 1; k < 5; k++) {
    double s = 0.0;
    for (int i = 1; i <= k; i++) s += a.c[i] * b.c[k - i];
    b.c[k] = -s / a.c[0];
  }
  return b;
}
inline S sqrt(const S &a)
{
  S b;
  b.c[0] = std::sqrt(a.c[0]);
  for (int k = 1; k < 5; k++) {
    double s = 0.0;
    for (int i = 1; i < k; i++) s += b.c[i] * b.c[k - i];
    b.c[k] = (a.c[k] - s) / (2.0 * b.c[0]);
  }
  return b;
}

using Vec = std::array<double, 3>;

struct Molecule {
  std::vector<Vec> x;    // positions, index = tag - 1
  double box[3] = {0, 0, 0};    // periodic box lengths (0: not periodic)
  // lj/cut
  double eps = 1.0, sigma = 1.0, rc = 3.0;
  // lj/smooth/linear: LJ - LJ(rc) - (r - rc) LJ'(rc) (force and energy zero at rc)
  bool smooth_linear = false;
  double special[4] = {1.0, 0.0, 0.0, 0.0};    // factor by bond distance 0(none),1,2,3
  std::vector<std::vector<int>> hops;    // hops[i][j] = bonds between i and j (0: > 3)
  // harmonic bonds K (r - r0)^2
  std::vector<std::array<int, 2>> bonds;
  double kb = 0.0, r0 = 1.0;
  // cosine/squared angles K (cos theta - cos theta0)^2
  std::vector<std::array<int, 3>> angles;
  double ka = 0.0, cos0 = 0.0;

  void min_image(double d[3]) const
  {
    for (int k = 0; k < 3; k++)
      if (box[k] > 0.0) d[k] -= box[k] * std::round(d[k] / box[k]);
  }
  // d(s) = x_i - x_j + s (u_i - u_j), nearest image at s = 0
  std::array<S, 3> dist(int i, int j, const std::vector<Vec> &u) const
  {
    double d[3] = {x[i][0] - x[j][0], x[i][1] - x[j][1], x[i][2] - x[j][2]};
    min_image(d);
    std::array<S, 3> r;
    for (int k = 0; k < 3; k++) {
      r[k].c[0] = d[k];
      r[k].c[1] = u[i][k] - u[j][k];
    }
    return r;
  }
  static S dot(const std::array<S, 3> &a, const std::array<S, 3> &b)
  {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  }

  void compute_hops()
  {
    const int n = (int) x.size();
    hops.assign(n, std::vector<int>(n, 0));
    std::vector<std::vector<int>> d(n, std::vector<int>(n, 99));
    for (int i = 0; i < n; i++) d[i][i] = 0;
    for (auto &b : bonds) d[b[0]][b[1]] = d[b[1]][b[0]] = 1;
    for (int k = 0; k < n; k++)
      for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++)
          if (d[i][k] + d[k][j] < d[i][j]) d[i][j] = d[i][k] + d[k][j];
    for (int i = 0; i < n; i++)
      for (int j = 0; j < n; j++) hops[i][j] = (d[i][j] <= 3) ? d[i][j] : 0;
  }

  // V(x + s u) as a series in s; mask: u is used as given
  S energy(const std::vector<Vec> &u) const
  {
    const int n = (int) x.size();
    S v;
    const double s6 = std::pow(sigma, 6.0);
    for (int i = 0; i < n; i++)
      for (int j = i + 1; j < n; j++) {
        const double f = special[hops[i][j]];
        if (f == 0.0) continue;
        auto d = dist(i, j, u);
        S rsq = dot(d, d);
        if (rsq.c[0] >= rc * rc) continue;
        S r6inv = inv(rsq * rsq * rsq);
        v = v + (4.0 * eps * f) * (s6 * s6 * (r6inv * r6inv) - s6 * r6inv);
        if (smooth_linear) {
          const double c6 = s6 / std::pow(rc, 6.0);
          const double vc = 4.0 * eps * (c6 * c6 - c6);
          const double dvc = 4.0 * eps * (-12.0 * c6 * c6 + 6.0 * c6) / rc;
          v = v - f * (cst(vc) + dvc * (sqrt(rsq) - cst(rc)));
        }
      }
    for (auto &b : bonds) {
      auto d = dist(b[0], b[1], u);
      S dr = sqrt(dot(d, d)) - cst(r0);
      v = v + kb * (dr * dr);
    }
    for (auto &a : angles) {
      auto d1 = dist(a[0], a[1], u);
      auto d2 = dist(a[2], a[1], u);
      S c = dot(d1, d2) * inv(sqrt(dot(d1, d1) * dot(d2, d2)));
      S dc = c - cst(cos0);
      v = v + ka * (dc * dc);
    }
    return v;
  }

  double D(int k, const std::vector<Vec> &u) const
  {
    const double fact[5] = {1, 1, 2, 6, 24};
    return fact[k] * energy(u).c[k];
  }
  static std::vector<Vec> comb(const std::vector<Vec> &a, double ca, const std::vector<Vec> &b,
                               double cb)
  {
    std::vector<Vec> r(a.size());
    for (size_t i = 0; i < a.size(); i++)
      for (int k = 0; k < 3; k++) r[i][k] = ca * a[i][k] + cb * b[i][k];
    return r;
  }
  double d2_mixed(const std::vector<Vec> &a, const std::vector<Vec> &b) const
  {
    return (D(2, comb(a, 1, b, 1)) - D(2, comb(a, 1, b, -1))) / 4.0;
  }
  double d3_mixed(const std::vector<Vec> &a, const std::vector<Vec> &w) const
  {
    return (D(3, comb(w, 1, a, 1)) - D(3, comb(w, 1, a, -1)) - 2.0 * D(3, a)) / 6.0;
  }
  // unit field: component k of atom i
  std::vector<Vec> unit(int i, int k) const
  {
    std::vector<Vec> e(x.size(), Vec{0, 0, 0});
    e[i][k] = 1.0;
    return e;
  }
};

}    // namespace hs_series

#endif
