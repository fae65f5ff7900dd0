/* -*- c++ -*- ----------------------------------------------------------
   Helpers of the fix hardsphere/press tests: the Carnahan-Starling
   equation of state of the hard-sphere fluid (diameter 1, kT = 1), a
   melted hard-sphere fluid under the barostat, and block averages of a
   sampled series. Expected values come from the equation of state, never
   from the program. Include after hs_test_main.h.
------------------------------------------------------------------------- */

#ifndef HS_NPT_H
#define HS_NPT_H

#include "hs_test_main.h"

#include <cmath>
#include <string>
#include <vector>

namespace hs_npt {

constexpr double PI = 3.14159265358979323846;

// Carnahan-Starling: Z = (1 + eta + eta^2 - eta^3) / (1 - eta)^3, and the
// reduced pressure P sigma^3 / kT = rho Z = 6 eta Z / pi (sigma = 1)
inline double cs_z(double eta)
{
  return (1 + eta + eta * eta - eta * eta * eta) / std::pow(1 - eta, 3);
}
inline double cs_pstar(double eta)
{
  return 6.0 * eta * cs_z(eta) / PI;
}
// the packing fraction at reduced pressure pstar (bisection; P* increases with eta)
inline double cs_eta(double pstar)
{
  double lo = 0.0, hi = 0.7;
  for (int k = 0; k < 200; k++) {
    const double m = 0.5 * (lo + hi);
    (cs_pstar(m) < pstar ? lo : hi) = m;
  }
  return 0.5 * (lo + hi);
}
// d(beta P)/d rho = d(rho Z)/d rho = (1 + 4 eta + 4 eta^2 - 4 eta^3 + eta^4) / (1 - eta)^4;
// the volume fluctuation of N spheres: <dV^2> = kT V kappa_T, i.e.
// <dV^2> / <V>^2 = 1 / (N d(beta P)/d rho)
inline double cs_dbetap_drho(double eta)
{
  const double e2 = eta * eta;
  return (1 + 4 * eta + 4 * e2 - 4 * e2 * eta + e2 * e2) / std::pow(1 - eta, 4);
}

// 4 n^3 hard spheres (diameter 1, mass 1, kT 1; n = 3: 108) started from an
// fcc lattice at packing fraction 0.3 (it melts at once; a lattice at the
// density of P* = 10 does not, and stays a crystal under the barostat),
// hardsphere/<method> (dt 0.003) and the
// barostat at P* = pstar (press_extra: more keywords, every: attempt period)
inline std::string fluid_input(double pstar, const std::string &method, int seed,
                               const std::string &press_extra = "", const std::string &every = "1",
                               int n = 3)
{
  char buf[2048];
  snprintf(buf, sizeof(buf),
           "units lj\natom_style atomic\natom_modify map array\nlattice fcc %.17g\n"
           "region box block 0 %d 0 %d 0 %d\ncreate_box 1 box\ncreate_atoms 1 box\nmass 1 1.0\n"
           "velocity all create 1.0 %d mom yes rot no dist gaussian loop geom\n"
           "neighbor 0.3 bin\nneigh_modify every 1 delay 0 check yes\ncomm_modify cutoff 2.0\n"
           "timestep 0.003\nfix hs all hardsphere/%s diameter 1.0\n"
           "fix press all hardsphere/press iso %.17g %.17g 0.003 temp 1.0 seed %d every %s %s\n"
           "thermo 1000\n",
           6.0 * 0.3 / PI, n, n, n, seed + 1, method.c_str(), pstar, pstar, seed,
           every.c_str(), press_extra.c_str());
  return buf;
}

struct Blocks {
  double mean = 0.0, err = 0.0;    // of the samples, error from block means
  double var = 0.0, var_err = 0.0; // variance about the mean, error from blocks
  int nblocks = 0;
};

// block averages of a series: nb blocks of equal length (a tail that does
// not fill a block is dropped)
inline Blocks block_stats(const std::vector<double> &x, int nb)
{
  Blocks b;
  b.nblocks = nb;
  const size_t len = x.size() / nb;
  if (len < 2) return b;
  double mean = 0.0;
  for (size_t k = 0; k < len * nb; k++) mean += x[k];
  mean /= (double) (len * nb);
  std::vector<double> bm(nb, 0.0), bv(nb, 0.0);
  for (int j = 0; j < nb; j++) {
    for (size_t k = 0; k < len; k++) {
      const double v = x[j * len + k];
      bm[j] += v;
      bv[j] += (v - mean) * (v - mean);
    }
    bm[j] /= (double) len;
    bv[j] /= (double) len;
  }
  auto sem = [nb](const std::vector<double> &a, double &avg) {
    avg = 0.0;
    for (double v : a) avg += v;
    avg /= nb;
    double s = 0.0;
    for (double v : a) s += (v - avg) * (v - avg);
    return std::sqrt(s / (nb - 1) / nb);
  };
  double m2;
  b.err = sem(bm, m2);
  b.mean = mean;
  b.var_err = sem(bv, b.var);
  return b;
}

// the n entries of fix ID's global vector
inline std::vector<double> fix_series(HSLammps &h, const char *id, int n)
{
  std::vector<double> out;
  for (int k = 0; k < n; k++) out.push_back(h.fix_vector(id, k));
  return out;
}

}    // namespace hs_npt

#endif
