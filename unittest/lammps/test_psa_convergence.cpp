// fix hardsphere/psa is only first order in the energy when collisions meet
// smooth forces (Bond & Leimkuhler 2007, section 2.1: a collision at time
// dt_c inside a step changes H by -(dt - 2 dt_c)/m (q_c.p)/(q_c.q_c) q_c.grad V
// + O(dt^2)), while hardsphere/cva is second order (section 2.2). On the
// 5-sphere impact pendulum chain (examples/pendulum-chain), the fitted slope
// of log max|H - H0| against log dt must be ~1 for psa and ~2 for cva.
//
// The error of one run depends on where in their steps its few collisions
// fall, so the measure is the geometric mean over several random initial
// velocities (the input's seed) of max|H(t) - H(0)| on [0, T].

#include "hs_chain.h"

#include "library.h"

#include <cmath>
#include <fstream>
#include <sstream>

namespace {

struct ChainRun {
  double dEmax = -1.0;
  long nsamples = 0;
  double ncoll = -1.0, npair = -1.0, nwall = -1.0, fevals = -1.0;
};

ChainRun run_chain(const std::string &method, double dt, double T, int seed)
{
  char dts[32], Ts[32];
  snprintf(dts, sizeof(dts), "%.17g", dt);
  snprintf(Ts, sizeof(Ts), "%.17g", T);
  const std::string out = scratch_name("psa_conv_dE_" + method + ".txt");
  ChainRun r;
  {
    HSLammps h({"-var", "method", method, "-var", "dt", dts, "-var", "T", Ts, "-var", "seed",
                std::to_string(seed), "-var", "out", out});
    h.file(hs_chain::chain_path());
    r.ncoll = h.fix_vector("hs", 0);
    r.npair = h.fix_vector("hs", 1);
    r.nwall = h.fix_vector("hs", 2);
    r.fevals = h.fix_vector("hs", 4);
  }    // closes the fix ave/time file
  r.dEmax = hs_chain::read_max_dE(out, &r.nsamples);
  return r;
}

using hs_chain::fitted_slope;

// geometric mean over seeds of max|H - H0|, per dt; returns the fitted slope
double energy_error_order(const std::string &method, const std::vector<double> &dts, double T,
                          int nseeds, std::vector<double> &err)
{
  std::vector<double> lx, ly;
  err.clear();
  for (double dt : dts) {
    double slog = 0.0, coll = 0.0;
    for (int seed = 1; seed <= nseeds; seed++) {
      ChainRun r = run_chain(method, dt, T, seed);
      EXPECT_GT(r.npair, 0.0) << method << " dt " << dt << " seed " << seed;
      EXPECT_EQ(r.ncoll, r.npair + r.nwall);
      EXPECT_GE(r.nsamples, std::lround(T / dt));
      if (method == "psa") EXPECT_EQ(r.fevals, 0.0);
      EXPECT_GT(r.dEmax, 0.0);
      EXPECT_LT(r.dEmax, 0.2) << method << " dt " << dt << " seed " << seed;
      slog += std::log(std::max(r.dEmax, 1e-300));
      coll += r.ncoll;
    }
    const double g = std::exp(slog / nseeds);
    err.push_back(g);
    lx.push_back(std::log(dt));
    ly.push_back(std::log(g));
    printf("[ %s conv ] dt %-7g mean collisions per run %6.1f  geometric mean max|H-H0| %.4e\n",
           method.c_str(), dt, coll / nseeds, g);
  }
  const double slope = fitted_slope(lx, ly);
  printf("[ %s conv ] fitted order %.3f\n", method.c_str(), slope);
  return slope;
}

}    // namespace

TEST(PSAConvergence, PendulumChainEnergyErrorFirstOrder)
{
  const double T = 20.0;
  const int nseeds = 24;
  const std::vector<double> dts = {0.04, 0.02, 0.01, 0.005, 0.0025};
  std::vector<double> epsa, ecva;
  const double psa = energy_error_order("psa", dts, T, nseeds, epsa);
  EXPECT_GE(psa, 0.7);
  EXPECT_LE(psa, 1.4);

  // CVA on the same runs: second order, and far more accurate
  const std::vector<double> dts_cva = {0.04, 0.02, 0.01, 0.005};
  const double cva = energy_error_order("cva", dts_cva, T, nseeds / 6, ecva);
  EXPECT_GE(cva, 1.6);
  EXPECT_LE(cva, 2.6);
  for (size_t k = 0; k < dts_cva.size(); k++) EXPECT_GT(epsa[k], 10.0 * ecva[k]);
}

namespace {

struct OneStep {
  double x = 0, v = 0, nwall = -1;
};

// one sphere (diameter 1, mass 1) at x0 moving at v0 toward the wall plane
// x = -2 under the constant force -g (potential V = g x): one step of dt
OneStep wall_step(const std::string &method, double x0, double v0, double g, double dt)
{
  char buf[512];
  snprintf(buf, sizeof(buf),
           "units lj\natom_style atomic\natom_modify map array\nboundary f f f\n"
           "region box block -5 5 -5 5 -5 5 units box\ncreate_box 1 box\n"
           "create_atoms 1 single %.17g 0 0 units box\nmass 1 1.0\n"
           "velocity all set %.17g 0 0 units box\ncomm_modify cutoff 3.0\n"
           "fix grav all addforce %.17g 0 0\ntimestep %.17g\n"
           "fix hs all hardsphere/%s diameter 1.0 wall xlo -2.0\nrun 1\n",
           x0, v0, -g, dt, method.c_str());
  HSLammps h;
  h.lines(buf);
  std::vector<double> x(3), v(3);
  lammps_gather_atoms(h.lmp, (char *) "x", 1, 3, x.data());
  lammps_gather_atoms(h.lmp, (char *) "v", 1, 3, v.data());
  return {x[0], v[0], h.fix_vector("hs", 2)};
}

}    // namespace

TEST(PSAConvergence, OneWallCollisionEnergyChangeIsSection21Formula)
{
  // Section 2.1 with u the wall normal: p- = p0 - dt/2 g, contact after
  // dt_c = gap / |p-|, p+ = -p-, q1 = q_c + (dt - dt_c) p+, p1 = p+ - dt/2 g.
  // In a linear potential the O(dt^2) remainder of
  //   Delta H = -(dt - 2 dt_c) (u.p-) (u.grad V) / (m u.u)
  // vanishes, so it holds to round-off.
  const double x0 = -1.45, v0 = -1.0, g = 0.5, dt = 0.1, xc = -1.5;
  const double vm = v0 - 0.5 * dt * g;
  const double dtc = (x0 - xc) / -vm;
  const double x1 = xc + (dt - dtc) * (-vm), v1 = -vm - 0.5 * dt * g;
  const double dH_formula = -(dt - 2.0 * dtc) * vm * g;
  OneStep psa = wall_step("psa", x0, v0, g, dt);
  EXPECT_EQ(psa.nwall, 1.0);
  EXPECT_NEAR(psa.x, x1, 1e-15);
  EXPECT_NEAR(psa.v, v1, 1e-15);
  const double H0 = 0.5 * v0 * v0 + g * x0;
  const double dH = 0.5 * psa.v * psa.v + g * psa.x - H0;
  printf("[ psa dH   ] one wall collision at dt_c = %.5f of dt = %g: Delta H = %.6e, "
         "section 2.1 formula %.6e\n",
         dtc, dt, dH, dH_formula);
  EXPECT_GT(std::fabs(dH_formula), 1e-4);
  EXPECT_NEAR(dH, dH_formula, 1e-14);
  // CVA sub-steps with Verlet, exact in a linear potential: no energy change
  OneStep cva = wall_step("cva", x0, v0, g, dt);
  EXPECT_EQ(cva.nwall, 1.0);
  EXPECT_NEAR(0.5 * cva.v * cva.v + g * cva.x - H0, 0.0, 1e-14);
}
