// A run split in pieces is the same run: "run 0" (a set-up only, as users
// do to print the initial state) and a run cut in two must give the same
// trajectory and counters as one run, for every method and for compute
// hamiltonian/modified. Regression: LAMMPS keeps the neighbor lists of an
// unchanged request set across runs without calling init_list() again, and
// the derivative layer (pcva, mcva, vci, the compute) had dropped its list
// in init(), stopping the second run with "the single path has no neighbor
// list". Runs go through run_lmp(): a LAMMPS error ends the process.

#include "hs_test_main.h"

#include <regex>

namespace {

class SuccessiveRuns : public ::testing::TestWithParam<const char *> {};

// a small LJ fluid with hard cores (pair cutoffs reach the contact list)
std::string fluid_input(const std::string &method, const std::string &runs)
{
  return "units lj\natom_style atomic\nlattice fcc 0.6\nregion box block 0 4 0 4 0 4\n"
         "create_box 1 box\ncreate_atoms 1 box\nmass 1 1.0\n"
         "velocity all create 1.5 87287 loop geom\npair_style lj/cut 2.5\n"
         "pair_coeff 1 1 1.0 1.0 2.5\nneighbor 0.3 bin\nneigh_modify every 1 delay 0 check yes\n"
         "fix hs all hardsphere/" +
         method +
         " diameter 1.0\ncompute hm all hamiltonian/modified\ntimestep 0.005\n"
         "thermo_style custom step etotal c_hm[2]\nthermo 10\n" +
         runs +
         "print \"RESULT $(f_hs[1]) $(f_hs[2]) $(f_hs[4]) $(etotal:%.17g) $(c_hm[2]:%.17g)\"\n";
}

std::vector<double> result(const RunResult &r)
{
  std::smatch m;
  std::regex re(R"((?:^|\n)RESULT ([^\n]*))");
  std::vector<double> out;
  if (!std::regex_search(r.output, m, re)) {
    ADD_FAILURE() << "no RESULT line:\n" << r.output;
    return out;
  }
  std::istringstream in(m[1].str());
  double v;
  while (in >> v) out.push_back(v);
  return out;
}

}    // namespace

TEST_P(SuccessiveRuns, RunZeroThenRunsInPiecesIsOneRun)
{
  const std::string method = GetParam();
  RunResult one = run_lmp(fluid_input(method, "run 40\n"));
  ASSERT_EQ(one.exit_code, 0) << one.output;
  RunResult split = run_lmp(fluid_input(method, "run 0\nrun 20\nrun 20\n"));
  ASSERT_EQ(split.exit_code, 0) << split.output;
  const std::vector<double> a = result(one), b = result(split);
  ASSERT_EQ(a.size(), 5u);
  ASSERT_EQ(b.size(), 5u);
  EXPECT_GT(a[0], 0.0) << "the fluid must collide within 40 steps";
  EXPECT_EQ(a[0], b[0]) << "collisions";
  EXPECT_EQ(a[1], b[1]) << "sphere-sphere collisions";
  EXPECT_EQ(a[2], b[2]) << "collisional steps";
  EXPECT_NEAR(a[3], b[3], 1e-12 * std::fabs(a[3])) << "total energy";
  EXPECT_NEAR(a[4], b[4], 1e-12 * std::fabs(a[4])) << "H_[2,VV]";
}

// the pressure on the first thermo line of a run that goes on from the
// last one's final step is the one that step reported: the impulse virial
// of that step's collisions (the set-up takes no step), as fix nve's
// pressure is the same on both lines. Found in a user-style trial: the
// second line had lost the hard-sphere part (0.69 -> -0.48)
TEST_P(SuccessiveRuns, PressureAtARunBoundaryIsTheLastStepsOne)
{
  const std::string method = GetParam();
  std::string input = fluid_input(method, "run 20\nrun 20\n");
  input = std::regex_replace(input, std::regex("thermo_style custom step etotal c_hm\\[2\\]"),
                             "thermo_style custom step press f_hs[4] etotal c_hm[2]\n"
                             "thermo_modify format float %.17g");
  RunResult r = run_lmp(input);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // the thermo lines of step 20: the first run's last and the second's first
  std::vector<std::pair<double, double>> at20;
  std::regex line(R"(\n\s+20\s+(\S+)\s+(\S+))");
  for (auto it = std::sregex_iterator(r.output.begin(), r.output.end(), line);
       it != std::sregex_iterator(); ++it)
    at20.emplace_back(std::stod((*it)[1]), std::stod((*it)[2]));
  ASSERT_EQ(at20.size(), 2u) << r.output;
  EXPECT_GT(at20[0].second, 0.0) << "no collisional step in the first run";
  EXPECT_EQ(at20[0].second, at20[1].second);
  EXPECT_NEAR(at20[1].first, at20[0].first, 1e-12 * std::fabs(at20[0].first))
      << "pressure at step 20 on the first run's last line and the second run's first";
}

INSTANTIATE_TEST_SUITE_P(Methods, SuccessiveRuns,
                         ::testing::Values("psa", "cva", "pcva", "mcva", "vci"),
                         [](const ::testing::TestParamInfo<const char *> &info) {
                           return std::string(info.param);
                         });
