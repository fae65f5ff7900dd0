// fix hardsphere/mcva on the 5-sphere impact pendulum chain of Bond &
// Leimkuhler (2007), section 4 (examples/pendulum-chain): the modified
// Hamiltonian H~ = H_[2,VV] is conserved to fourth order through the
// collisions (fitted slope of max|H~ - H~0| against dt about 4), the energy
// to second order, and H~ far better than by the collision Verlet
// algorithm (figure 4.3 of the paper).
//
// H~ and H are evaluated here independently of the fix, in closed form
// from a dump of x and v every step: V = sum K (r - 1)^2 with K = 0.5 (the
// example's harmonic bonds, anchor atom 1 fixed at the origin),
// H~ = H + dt^2/12 v^T V'' v - dt^2/24 |grad V|^2 (unit masses, lj units).

#include "hs_chain.h"

#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>

namespace {

using hs_chain::slurp;

struct Errors {
  double dH = 0.0, dHt = 0.0;    // max |H - H0|, max |H~ - H~0|
  long frames = 0;
  double ncoll = -1.0, npair = -1.0, nwall = -1.0, nsub = -1.0;
};

// H and H~ of the chain at one frame; q, v indexed by atom ID - 1
void chain_energies(const std::vector<double> &q, const std::vector<double> &v, double dt,
                    double &H, double &Ht)
{
  const double K = 0.5, r0 = 1.0;
  const int n = 6;
  double V = 0.0, vHv = 0.0, ke = 0.0;
  std::vector<double> grad(3 * n, 0.0);
  for (int a = 0; a + 1 < n; a++) {
    const int b = a + 1;
    double d[3], dv[3];
    for (int k = 0; k < 3; k++) {
      d[k] = q[3 * b + k] - q[3 * a + k];
      dv[k] = v[3 * b + k] - (a == 0 ? 0.0 : v[3 * a + k]);
    }
    const double r = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    V += K * (r - r0) * (r - r0);
    for (int k = 0; k < 3; k++) {
      const double g = 2.0 * K * (r - r0) * d[k] / r;
      grad[3 * b + k] += g;
      grad[3 * a + k] -= g;
    }
    // bond Hessian block 2K [e e^T + (r - r0)/r (I - e e^T)]
    const double ed = (d[0] * dv[0] + d[1] * dv[1] + d[2] * dv[2]) / r;
    const double dd = dv[0] * dv[0] + dv[1] * dv[1] + dv[2] * dv[2];
    vHv += 2.0 * K * (ed * ed + (r - r0) / r * (dd - ed * ed));
  }
  double g2 = 0.0;
  for (int i = 1; i < n; i++)
    for (int k = 0; k < 3; k++) {
      ke += 0.5 * v[3 * i + k] * v[3 * i + k];
      g2 += grad[3 * i + k] * grad[3 * i + k];
    }
  H = ke + V;
  Ht = H + dt * dt / 12.0 * vHv - dt * dt / 24.0 * g2;
}

Errors run_chain(const std::string &method, double dt, double T)
{
  Errors e;
  std::string input =
      slurp(hs_chain::chain_path());
  EXPECT_FALSE(input.empty());
  const std::string dump = scratch_name("mcva_conv_" + method + "_" + std::to_string(dt) + ".dump");
  const std::string anchor = "fix         dEout all ave/time 1 1 1 v_dE file ${out}\n";
  const size_t at = input.find(anchor);
  EXPECT_NE(at, std::string::npos) << "the example changed: no '" << anchor << "'";
  if (at == std::string::npos) return e;
  input.insert(at + anchor.size(),
               "dump hsd all custom 1 " + dump +
                   " id x y z vx vy vz\ndump_modify hsd sort id format float %.17g\n");
  // f_hs[7]: Gauss sub-steps (hardsphere/mcva only)
  input += std::string("print \"MCVATEST $(f_hs[1]) $(f_hs[2]) $(f_hs[3]) ") +
      (method == "mcva" ? "$(f_hs[7])" : "0") + "\"\n";
  char dts[32];
  snprintf(dts, sizeof(dts), "%.17g", dt);
  RunResult res =
      run_lmp(input, {"-var", "method", method, "-var", "dt", dts, "-var", "T", std::to_string(T),
                      "-var", "seed", "1", "-var", "every", "1000000"});
  EXPECT_EQ(res.exit_code, 0) << res.output;
  std::smatch m;
  std::regex re(R"((?:^|\n)MCVATEST ([0-9.eE+-]+) ([0-9.eE+-]+) ([0-9.eE+-]+) ([0-9.eE+-]+))");
  if (std::regex_search(res.output, m, re)) {
    e.ncoll = std::stod(m[1]);
    e.npair = std::stod(m[2]);
    e.nwall = std::stod(m[3]);
    e.nsub = std::stod(m[4]);
  } else
    ADD_FAILURE() << "no MCVATEST line in output:\n" << res.output;

  std::ifstream in(dump);
  std::string line;
  std::vector<double> q(18), v(18);
  double H0 = 0.0, Ht0 = 0.0;
  while (std::getline(in, line)) {
    if (line.rfind("ITEM: ATOMS", 0) != 0) continue;
    for (int a = 0; a < 6; a++) {
      std::getline(in, line);
      std::istringstream ls(line);
      int id;
      double x[3], u[3];
      ls >> id >> x[0] >> x[1] >> x[2] >> u[0] >> u[1] >> u[2];
      for (int k = 0; k < 3; k++) {
        q[3 * (id - 1) + k] = x[k];
        v[3 * (id - 1) + k] = u[k];
      }
    }
    double H, Ht;
    chain_energies(q, v, dt, H, Ht);
    if (e.frames == 0) {
      H0 = H;
      Ht0 = Ht;
    }
    e.dH = std::max(e.dH, std::fabs(H - H0));
    e.dHt = std::max(e.dHt, std::fabs(Ht - Ht0));
    e.frames++;
  }
  std::remove(dump.c_str());
  return e;
}

// the order of y in x
const auto fit_slope = hs_chain::loglog_slope;

}    // namespace

TEST(MCVAConvergence, PendulumChainModifiedHamiltonianFourthOrder)
{
  const double T = 20.0;
  const std::vector<double> dts = {0.04, 0.02, 0.01, 0.005};
  std::vector<double> eH, eHt, cHt;
  for (double dt : dts) {
    const Errors m = run_chain("mcva", dt, T);
    const Errors c = run_chain("cva", dt, T);
    EXPECT_GT(m.npair, 0.0) << "dt " << dt;
    EXPECT_GT(m.nwall, 0.0) << "dt " << dt;
    EXPECT_GE(m.nsub, m.ncoll) << "every collision comes with Gauss sub-steps";
    EXPECT_EQ(m.frames, std::lround(T / dt) + 1);
    ASSERT_GT(m.dHt, 0.0);
    ASSERT_GT(c.dHt, 0.0);
    eH.push_back(m.dH);
    eHt.push_back(m.dHt);
    cHt.push_back(c.dHt);
    printf("[ mcva conv ] dt %-6g mcva: %g collisions (%g pair, %g wall), max|H-H0| %.3e, "
           "max|H~-H~0| %.3e; cva: max|H~-H~0| %.3e\n",
           dt, m.ncoll, m.npair, m.nwall, m.dH, m.dHt, c.dHt);
    // far better than CVA (which keeps H~ only to second order)
    EXPECT_LT(100.0 * m.dHt, c.dHt) << "dt " << dt;
  }
  const double pHt = fit_slope(dts, eHt), pH = fit_slope(dts, eH), pC = fit_slope(dts, cHt);
  printf("[ mcva conv ] fitted orders: mcva H~ %.3f, mcva H %.3f, cva H~ %.3f\n", pHt, pH, pC);
  EXPECT_NEAR(pHt, 4.0, 0.4);
  EXPECT_NEAR(pH, 2.0, 0.3);
  EXPECT_NEAR(pC, 2.0, 0.4);
}

// The cost of a collision (doc/fix_hardsphere_mcva.rst quotes these lines):
// Gauss solves per collision (root finding included), stage iterations per
// solve (2 field evaluations each: a force evaluation plus V''v, V'''[v,v],
// V''a from the derivative layer), force evaluations per collision; for the
// Newton iteration (default) and the fixed point (fix_modify stages fixed).
// Newton's contraction here is ~h^2 |change of V''| / m << 1e-4
// (hs_newton.h), so a warm-started solve needs one or two corrections (the
// second often predicted to be below the tolerance); the fixed point
// contracts by ~h omega / sqrt(12) ~ 0.01 per sweep
static void chain_cost(const std::string &stages, double &iters_per_solve)
{
  std::string input = slurp(hs_chain::chain_path());
  const std::string fixline = "fix         2d all enforce2d\n";
  const size_t at = input.find(fixline);
  ASSERT_NE(at, std::string::npos);
  input.insert(at + fixline.size(), "fix_modify hs stages " + stages + "\n");
  input += "print \"MCVACOST $(f_hs[1]) $(f_hs[5]) $(f_hs[6]) $(f_hs[7]) $(f_hs[8]) $(f_hs[9]) "
           "$(f_hs[10])\"\n";
  RunResult res = run_lmp(input, {"-var", "method", "mcva", "-var", "dt", "0.02", "-var", "T",
                                  "500", "-var", "seed", "1", "-var", "every", "1000000"});
  ASSERT_EQ(res.exit_code, 0) << res.output;
  std::smatch m;
  std::regex re(R"((?:^|\n)MCVACOST (\S+) (\S+) (\S+) (\S+) (\S+) (\S+) (\S+))");
  ASSERT_TRUE(std::regex_search(res.output, m, re)) << res.output;
  const double ncoll = std::stod(m[1]), nforce = std::stod(m[2]), iters = std::stod(m[3]),
               nsub = std::stod(m[4]), maxit = std::stod(m[5]), solves = std::stod(m[6]),
               missed = std::stod(m[7]);
  printf("[ mcva cost, stages %s ] chain dt 0.02 T 500: %g collisions, %g Gauss sub-steps, %g "
         "Gauss solves (%.2f per collision), %g stage iterations (%.2f per solve, at most %g), %g "
         "force evaluations (%.1f per collision), %g contacts missed by the prediction\n",
         stages.c_str(), ncoll, nsub, solves, solves / ncoll, iters, iters / solves, maxit, nforce,
         nforce / ncoll, missed);
  ASSERT_GT(ncoll, 100.0);
  // a contact is reached with a few root-finder evaluations, each a
  // near-round-off stage solve from a warm start
  EXPECT_GE(solves / ncoll, 2.0);
  EXPECT_LT(solves / ncoll, 15.0);
  if (stages == "newton") {
    EXPECT_LT(iters / solves, 3.0);
    EXPECT_LE(maxit, 4.0);
  } else {
    EXPECT_LT(iters / solves, 10.0);
    EXPECT_LE(maxit, 20.0);
  }
  // each iteration evaluates the field at both stages (one force evaluation
  // each on this bonded system; the bond derivatives take no force evaluation)
  EXPECT_GE(nforce, 2.0 * iters);
  EXPECT_LT(nforce, 2.0 * iters + 4.0 * nsub + 4.0 * ncoll);
  iters_per_solve = iters / solves;
}

TEST(MCVAConvergence, PendulumChainCostPerCollision)
{
  double newton = 0.0, fixed = 0.0;
  chain_cost("newton", newton);
  chain_cost("fixed", fixed);
  EXPECT_LT(newton, 0.75 * fixed);
}
