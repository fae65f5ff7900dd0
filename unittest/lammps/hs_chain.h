/* -*- c++ -*- ----------------------------------------------------------
   Shared helpers of the convergence tests on the 5-sphere impact pendulum
   chain (examples/pendulum-chain/in.pendulum-chain, Bond & Leimkuhler 2007,
   section 4): run the example with a method, dt, T and seed; read its
   max|H(t) - H(0)| series; fit the order (least-squares slope in log-log).
   Include after hs_test_main.h.
------------------------------------------------------------------------- */

#ifndef HS_CHAIN_H
#define HS_CHAIN_H

#include "hs_test_main.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace hs_chain {

inline std::string chain_path()
{
  return std::string(hs_test_paths::source_dir) + "/examples/pendulum-chain/in.pendulum-chain";
}

inline std::string slurp(const std::string &path)
{
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

inline std::string f17(double v)
{
  char buf[32];
  snprintf(buf, sizeof(buf), "%.17g", v);
  return buf;
}

// the example's |H(t) - H(0)| file ("step dE" lines): its maximum (-1 if
// empty) and the number of samples; the file is removed
inline double read_max_dE(const std::string &path, long *nsamples = nullptr)
{
  double dEmax = -1.0;
  long n = 0;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    double step, dE;
    if (ls >> step >> dE) {
      dEmax = std::max(dEmax, dE);
      n++;
    }
  }
  in.close();
  std::remove(path.c_str());
  if (nsamples) *nsamples = n;
  return dEmax;
}

struct ChainRun {
  double dEmax = -1.0;
  long nsamples = 0;
  double ncoll = -1.0, npair = -1.0, nwall = -1.0;
  std::vector<double> extra;    // the values of the requested extra fields
};

// Run the example in an lmp process with fix hardsphere/<method>; parse its
// summary line (all, sphere-sphere and wall collisions) and the series of
// |H - H0|. extra: LAMMPS expressions printed after the run, e.g.
// "$(f_hs[7])", returned in ChainRun::extra (a missing line is a failure).
// substep: the fix's engine ("" = the example's default, global)
inline ChainRun run_chain(const std::string &method, double dt, double T, int seed,
                          const std::vector<std::string> &extra = {},
                          const std::string &substep = "")
{
  ChainRun r;
  std::string input = slurp(chain_path());
  EXPECT_FALSE(input.empty());
  if (!extra.empty()) {
    input += "print \"EXTRA";
    for (const auto &e : extra) input += " " + e;
    input += "\"\n";
  }
  const std::string out =
      scratch_name(method + "_conv_dE_" + std::to_string(seed) + "_" + f17(dt) + ".txt");
  std::vector<std::string> args = {"-var", "method", method, "-var", "dt", f17(dt), "-var", "T",
                                   std::to_string(T), "-var", "seed", std::to_string(seed),
                                   "-var", "out", out};
  if (!substep.empty()) args.insert(args.end(), {"-var", "substep", substep});
  RunResult res = run_lmp(input, args);
  EXPECT_EQ(res.exit_code, 0) << res.output;
  std::smatch m;
  // the summary line printed by the input (not its echo, which starts with "print")
  const std::regex re(R"((?:^|\n)pendulum chain: [^\n]*: ([0-9.eE+-]+) collisions \(([0-9.eE+-]+) sphere-sphere, ([0-9.eE+-]+) wall\))");
  if (std::regex_search(res.output, m, re)) {
    r.ncoll = std::stod(m[1]);
    r.npair = std::stod(m[2]);
    r.nwall = std::stod(m[3]);
  } else
    ADD_FAILURE() << "no summary line in output:\n" << res.output;
  if (!extra.empty()) {
    const std::regex rx(R"((?:^|\n)EXTRA ([^\n]*))");
    if (std::regex_search(res.output, m, rx)) {
      std::istringstream ls(m[1].str());
      double v;
      while (ls >> v) r.extra.push_back(v);
    }
    if (r.extra.size() != extra.size()) {
      ADD_FAILURE() << "no EXTRA line with " << extra.size() << " values in output:\n" << res.output;
      r.extra.assign(extra.size(), -1.0);
    }
  }
  r.dEmax = read_max_dE(out, &r.nsamples);
  return r;
}

// least-squares slope of ly against lx
inline double fitted_slope(const std::vector<double> &lx, const std::vector<double> &ly)
{
  const double n = (double) lx.size();
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (size_t k = 0; k < lx.size(); k++) {
    sx += lx[k];
    sy += ly[k];
    sxx += lx[k] * lx[k];
    sxy += lx[k] * ly[k];
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

// least-squares slope of log y against log x (the order of y in x)
inline double loglog_slope(const std::vector<double> &x, const std::vector<double> &y)
{
  std::vector<double> lx, ly;
  for (size_t k = 0; k < x.size(); k++) {
    lx.push_back(std::log(x[k]));
    ly.push_back(std::log(y[k]));
  }
  return fitted_slope(lx, ly);
}

}    // namespace hs_chain

#endif
