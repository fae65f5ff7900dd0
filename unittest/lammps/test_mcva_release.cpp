// fix hardsphere/mcva at a large step: a touching pair can approach by the
// plain velocity (the contact prediction's test) while the Gauss flow of
// H_[2,VV] separates it (u^T A p >= 0). alpha-hat would then make it
// approach on the Gauss flow, the next zero-length sub-step would reverse
// that, and so on without end; such a contact is released without an
// impulse instead (doc/fix_hardsphere_mcva.rst). Regression: the pendulum
// chain, seed 1, dt 0.2, ran into exactly this at step 13185 (t = 2637) and
// stopped with "more than ... collisions in step 13185".

#include "hs_chain.h"

#include <regex>

// stages: "fixed" or "newton" (fix_modify hs stages ...). The release on
// step 13185 belongs to this chaotic trajectory with fixed-point stage
// solves (the one of the regression); Newton's stages agree to ~1e-14, and
// by step 13185 that is another trajectory: it must run through at the
// same accuracy, with or without a release
static void large_step_run(const std::string &stages, bool release_expected)
{
  std::string input = hs_chain::slurp(hs_chain::chain_path());
  const std::string fixline = "fix         2d all enforce2d\n";
  const size_t at = input.find(fixline);
  ASSERT_NE(at, std::string::npos);
  input.insert(at + fixline.size(), "fix_modify hs stages " + stages + "\n");
  input += "print \"RESULT $(f_hs[1]) $(f_hs[11]) $(v_dE:%.6e)\"\n";
  RunResult r = run_lmp(input, {"-var", "method", "mcva", "-var", "dt", "0.2", "-var", "seed", "1",
                                "-var", "box", "30", "-var", "skin", "1.2", "-var", "T",
                                "2700", "-var", "every", "100000"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::smatch m;
  const std::regex re(R"((?:^|\n)RESULT ([0-9.eE+-]+) ([0-9.eE+-]+) ([0-9.eE+-]+))");
  ASSERT_TRUE(std::regex_search(r.output, m, re)) << r.output;
  const double ncoll = std::stod(m[1]), nreleased = std::stod(m[2]), dE = std::stod(m[3]);
  printf("[ stages %s ] %g collisions, %g released, max |H - H0| %g\n", stages.c_str(), ncoll,
         nreleased, dE);
  // about 1.4 collisions per time unit on the chain (7000 in T = 5000)
  EXPECT_GT(ncoll, 2700.0);
  EXPECT_LT(ncoll, 5400.0);
  if (release_expected)
    EXPECT_GE(nreleased, 1.0) << "the released contact of step 13185 must be counted";
  // second order: CVA's own |H - H0| at dt 0.2 is ~0.1 (figure sweep)
  EXPECT_LT(dE, 0.1);
}

TEST(MCVARelease, PendulumChainLargeStepRunsThrough)
{
  large_step_run("fixed", true);
}

TEST(MCVARelease, PendulumChainLargeStepRunsThroughNewton)
{
  large_step_run("newton", false);
}
