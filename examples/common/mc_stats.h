// Statistics shared by the examples' Monte Carlo references
// (examples/hard-core-yukawa/mc_hcy.cpp, examples/depletion/mc_ao.cpp): the
// contact value g(sigma+) from the cavity function, blocking error bars,
// means. No LAMMPS; included by relative path.

#ifndef HS_EXAMPLES_MC_STATS_H
#define HS_EXAMPLES_MC_STATS_H

#include <algorithm>
#include <cmath>
#include <vector>

namespace mc_stats {

// g(sigma+): the cavity function y(r) = g(r) exp(u_w(r)/kT) is smooth through
// contact where g itself has the slope of u_w, so ln y is fitted by a
// quadratic in (r - sigma) over the first nfit bins of width h (each bin
// holds the average of exp(u_w/kT) over its pairs) and
// g(sigma+) = y(sigma) exp(-u_w(sigma)/kT). System: n, L, uw(r), p.T.
template <class System>
double contact_value(const System &s, const std::vector<double> &ybin, double nsamples,
                     double h, int nfit)
{
  const double PI = 3.14159265358979323846;
  const double ideal = 0.5 * s.n * (s.n - 1) / (s.L * s.L * s.L);    // pairs per volume
  double A[3][4] = {{0}};
  for (int b = 0; b < nfit; ++b) {
    const double r0 = 1.0 + b * h, r1 = r0 + h;
    const double shell = 4.0 / 3.0 * PI * (r1 * r1 * r1 - r0 * r0 * r0);
    const double y = ybin[b] / (nsamples * ideal * shell);
    if (!(y > 0)) return NAN;
    const double t = 0.5 * (r0 + r1) - 1.0, ly = std::log(y);
    const double f[3] = {1.0, t, t * t};
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) A[i][j] += f[i] * f[j];
      A[i][3] += f[i] * ly;
    }
  }
  // 3x3 normal equations, Gauss elimination; we need the constant term
  for (int c = 0; c < 3; ++c)
    for (int r = c + 1; r < 3; ++r) {
      const double m = A[r][c] / A[c][c];
      for (int k = c; k < 4; ++k) A[r][k] -= m * A[c][k];
    }
  double coef[3];
  for (int r = 2; r >= 0; --r) {
    double v = A[r][3];
    for (int k = r + 1; k < 3; ++k) v -= A[r][k] * coef[k];
    coef[r] = v / A[r][r];
  }
  return std::exp(coef[0]) * std::exp(-s.uw(1.0) / s.p.T);
}

// blocking error as in the MD analysis: coarsen by pairs while >= 16 blocks
// remain and keep the largest standard error
inline double block_se(std::vector<double> v)
{
  double best = 0;
  while (v.size() >= 16) {
    double m = 0, q = 0;
    for (double a : v) m += a;
    m /= v.size();
    for (double a : v) q += (a - m) * (a - m);
    best = std::max(best, std::sqrt(q / (v.size() - 1) / v.size()));
    std::vector<double> w;
    for (size_t i = 0; i + 1 < v.size(); i += 2) w.push_back(0.5 * (v[i] + v[i + 1]));
    v.swap(w);
  }
  return best;
}

inline double mean(const std::vector<double> &v)
{
  double m = 0;
  for (double a : v) m += a;
  return m / v.size();
}

}    // namespace mc_stats

#endif
