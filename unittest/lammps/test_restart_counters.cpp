// Every hardsphere fix writes its counters (the base's, then the method's
// own) to restart files and gets them back when a fix with the same ID is
// defined after read_restart: after a run of the pendulum chain, write a
// restart, read it in a fresh instance, and every entry of the fix vector
// must be the same, bit for bit. One suite, instantiated per method (test
// names start with the method).

#include "hs_chain.h"

#include <vector>

namespace {

struct RestartCase {
  const char *method;
  int ncounters;      // length of the fix vector
  int also_nonzero;   // 0-based entry (besides the collisions) that must be > 0 (-1: none)
};

class RestartCounters : public ::testing::TestWithParam<RestartCase> {};

std::string case_name(const ::testing::TestParamInfo<RestartCase> &info)
{
  return info.param.method;
}

}    // namespace

TEST_P(RestartCounters, CountersContinue)
{
  const RestartCase &c = GetParam();
  const std::string method = c.method;
  const std::string file = scratch_name(method + "_restart.bin");
  std::vector<double> before(c.ncounters);
  {
    HSLammps h({"-var", "method", method, "-var", "T", "20", "-var", "every", "100000"});
    h.file(hs_chain::chain_path());
    for (int k = 0; k < c.ncounters; k++) before[k] = h.fix_vector("hs", k);
    h.cmd("write_restart " + file);
  }
  ASSERT_GT(before[0], 0.0);
  if (c.also_nonzero >= 0) ASSERT_GT(before[c.also_nonzero], 0.0);
  HSLammps h;
  h.cmd("read_restart " + file);
  h.cmd("comm_modify cutoff 2.0");
  h.cmd("fix hs chain hardsphere/" + method + " diameter 0.9 wall xlo 0.0");
  h.cmd("fix 2d all enforce2d");
  h.cmd("run 0");
  for (int k = 0; k < c.ncounters; k++)
    EXPECT_EQ(h.fix_vector("hs", k), before[k]) << "entry " << k + 1;
  std::remove(file.c_str());
}

// mcva: entry [6] is the Gauss stage iterations
INSTANTIATE_TEST_SUITE_P(PSA, RestartCounters, ::testing::Values(RestartCase{"psa", 5, -1}), case_name);
INSTANTIATE_TEST_SUITE_P(CVA, RestartCounters, ::testing::Values(RestartCase{"cva", 5, -1}), case_name);
INSTANTIATE_TEST_SUITE_P(PCVA, RestartCounters, ::testing::Values(RestartCase{"pcva", 8, -1}), case_name);
INSTANTIATE_TEST_SUITE_P(MCVA, RestartCounters, ::testing::Values(RestartCase{"mcva", 11, 5}), case_name);
INSTANTIATE_TEST_SUITE_P(VCI, RestartCounters, ::testing::Values(RestartCase{"vci", 11, -1}), case_name);
