// The real plugin: the stock LAMMPS executable of the LAMMPS we build against
// (build-2025/lammps/lmp, PLUGIN package) loads build-2025/hardsphereplugin.so
// with "plugin load". Its pendulum-chain trajectory must equal our lmp
// driver's to round-off; plugin list/unload and clear must behave as LAMMPS
// documents for plugins; a plugin built for the other LAMMPS version must
// fail with a message, not a crash. Skipped where there is no stock LAMMPS
// with PLUGIN (Debian bookworm's lmp is built without it).

#include "hs_test_main.h"

#include "hs_chain.h"

#include <cmath>
#include <fstream>
#include <sstream>

namespace {

const std::string STOCK_LMP = hs_test_paths::stock_lmp;
const std::string PLUGIN = hs_test_paths::plugin_path;
const std::string OTHER_PLUGIN = hs_test_paths::other_plugin;

bool exists(const std::string &path)
{
  return !path.empty() && access(path.c_str(), X_OK | R_OK) == 0;
}

#define SKIP_WITHOUT_STOCK_LMP()                                                               \
  if (!exists(STOCK_LMP))                                                                      \
  GTEST_SKIP() << "no stock LAMMPS executable with the PLUGIN package for this LAMMPS version " \
                  "at '" << STOCK_LMP << "' (Debian bookworm's lmp is built without PLUGIN; "  \
                  "build-2025/lammps/lmp is the one for LAMMPS 4Feb2025)"

std::vector<double> numbers_of(const std::string &path, int skip_comment_lines = 1)
{
  std::ifstream in(path);
  std::vector<double> v;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (skip_comment_lines && line.rfind("ITEM", 0) == 0) continue;
    std::istringstream ss(line);
    double x;
    while (ss >> x) v.push_back(x);
  }
  return v;
}

std::string line_with(const std::string &text, const std::string &start)
{
  std::istringstream ss(text);
  std::string line;
  while (std::getline(ss, line))
    if (line.rfind(start, 0) == 0) return line;
  return "";
}

// a two-sphere head-on collision, the style given by the caller
const char *two_spheres = R"IN(units lj
atom_style atomic
atom_modify map array
boundary f f f
region box block -5 5 -5 5 -5 5
create_box 1 box
create_atoms 1 single -1 0 0
create_atoms 1 single 1 0 0
mass 1 1.0
group a id 1
group b id 2
velocity a set 1 0 0
velocity b set -1 0 0
pair_style zero 1.0
pair_coeff * *
comm_modify cutoff 2.0
fix hs all hardsphere/cva diameter 1.0
run 100
print "collisions $(f_hs[1]) x1 $(x[1]:%.17g) vx1 $(vx[1]:%.17g)"
)IN";

}    // namespace

class StockPlugin : public ::testing::TestWithParam<std::string> {};

TEST_P(StockPlugin, PendulumChainTrajectoryEqualsDriver)
{
  SKIP_WITHOUT_STOCK_LMP();
  const std::string method = GetParam();
  const std::string example = hs_chain::chain_path();
  struct Run {
    std::string out, dump, series;
  } run[2];
  for (int k = 0; k < 2; k++) {
    const std::string tag = scratch_name(method + (k ? ".stock" : ".driver"));
    run[k].dump = tag + ".dump";
    run[k].series = tag + ".v";
    std::string input;
    if (k == 1) input += "plugin load " + PLUGIN + "\n";
    input += "include " + example + "\n";
    input += "write_dump all custom " + run[k].dump +
        " id x y z vx vy vz modify sort id format float %.17g\n";
    const auto res = run_program(k ? STOCK_LMP : std::string(hs_test_paths::lmp_binary), input,
                                 {"-var", "method", method, "-var", "T", "40", "-var", "every",
                                  "1000", "-var", "vevery", "1", "-var", "vout", run[k].series});
    ASSERT_EQ(res.exit_code, 0) << (k ? "stock lmp + plugin" : "driver") << ":\n" << res.output;
    run[k].out = res.output;
  }
  EXPECT_NE(run[1].out.find("Loading plugin"), std::string::npos) << run[1].out;

  // the same collisions, counted by each executable
  const std::string summary0 = line_with(run[0].out, "pendulum chain: method");
  const std::string summary1 = line_with(run[1].out, "pendulum chain: method");
  ASSERT_FALSE(summary0.empty()) << run[0].out;
  EXPECT_EQ(summary0, summary1);
  EXPECT_EQ(summary0.find(": 0 collisions"), std::string::npos)
      << "the test needs collisions: " << summary0;

  // final state (17 digits) and the velocity of sphere 1 at every step
  for (const auto &file : {&Run::dump, &Run::series}) {
    const auto a = numbers_of(run[0].*file), b = numbers_of(run[1].*file);
    ASSERT_GT(a.size(), 10u) << run[0].*file;
    ASSERT_EQ(a.size(), b.size()) << run[0].*file << " vs " << run[1].*file;
    double worst = 0.0;
    for (size_t i = 0; i < a.size(); i++)
      worst = std::max(worst, std::fabs(a[i] - b[i]) / (1.0 + std::fabs(a[i])));
    EXPECT_LE(worst, 1e-12) << run[0].*file << " vs " << run[1].*file;
  }
  for (auto &r : run) {
    unlink(r.dump.c_str());
    unlink(r.series.c_str());
  }
}

INSTANTIATE_TEST_SUITE_P(Methods, StockPlugin,
                         ::testing::Values("psa", "cva", "pcva", "mcva", "vci"),
                         [](const ::testing::TestParamInfo<std::string> &p) { return p.param; });

// plugin list names every style; plugin unload removes the style and deletes
// the fix instance that uses it (LAMMPS' plugin doc)
TEST(StockPluginCommands, ListAndUnload)
{
  SKIP_WITHOUT_STOCK_LMP();
  const std::string input = "plugin load " + PLUGIN + "\nplugin list\n" +
      two_spheres +
      "plugin unload fix hardsphere/cva\n"
      // accepted only if the unload deleted fix hs (else: new style != old style)
      "fix hs all nve\n"
      "run 0\n"
      "print \"after unload\"\n"
      "plugin list\n"
      "fix hs2 all hardsphere/cva diameter 1.0\n";
  const auto res = run_program(STOCK_LMP, input);
  const auto &out = res.output;
  for (const char *style :
       {"fix style plugin hardsphere/cva", "fix style plugin hardsphere/mcva",
        "fix style plugin hardsphere/pcva", "fix style plugin hardsphere/psa",
        "fix style plugin hardsphere/vci", "compute style plugin hamiltonian/modified"})
    EXPECT_NE(out.find(style), std::string::npos) << style << "\n" << out;
  EXPECT_NE(out.find("collisions 1 "), std::string::npos) << out;
  EXPECT_NE(out.find("Unloading fix style hardsphere/cva"), std::string::npos) << out;
  EXPECT_NE(out.find("after unload"), std::string::npos) << out;
  // the second list has the other five only
  const size_t after = out.find("after unload");
  ASSERT_NE(after, std::string::npos);
  EXPECT_EQ(out.find("fix style plugin hardsphere/cva", after), std::string::npos) << out;
  EXPECT_NE(out.find("fix style plugin hardsphere/pcva", after), std::string::npos) << out;
  EXPECT_NE(out.find("ERROR: Unrecognized fix style 'hardsphere/cva'", after), std::string::npos)
      << out;
  EXPECT_EQ(res.exit_code, 1) << out;
}

// clear starts LAMMPS over, plugins included (LAMMPS::destroy() unloads
// them): the styles are gone until the next plugin load, which then gives
// the same run as the first
TEST(StockPluginCommands, ClearUnloadsAndReloadWorks)
{
  SKIP_WITHOUT_STOCK_LMP();
  const std::string input = "plugin load " + PLUGIN + "\n" + two_spheres +
      "clear\n"
      "print \"after clear\"\n"
      "plugin list\n"
      "plugin load " + PLUGIN + "\n" +
      two_spheres + "clear\n" + two_spheres;
  const auto res = run_program(STOCK_LMP, input);
  const auto &out = res.output;
  const size_t after = out.find("after clear");
  ASSERT_NE(after, std::string::npos) << out;
  // the list right after clear is empty
  const size_t list = out.find("Currently loaded plugins", after);
  ASSERT_NE(list, std::string::npos) << out;
  const size_t next_load = out.find("Loading plugin", list);
  EXPECT_EQ(out.substr(list, next_load - list).find("style plugin"), std::string::npos) << out;
  // the reloaded plugin reproduces the first run exactly
  const std::string first = line_with(out, "collisions");
  const std::string second = line_with(out.substr(after), "collisions");
  EXPECT_NE(first.find("collisions 1 "), std::string::npos) << out;
  EXPECT_EQ(first, second);
  // and the last clear dropped the styles again
  EXPECT_NE(out.find("ERROR: Unrecognized fix style 'hardsphere/cva'", after), std::string::npos)
      << out;
  EXPECT_EQ(res.exit_code, 1) << out;
}

// a plugin built for the other LAMMPS version: a clean stop with a message
// naming the file (dlopen's missing symbol, or our version check), not a crash
TEST(StockPluginCommands, PluginOfOtherVersionFailsCleanly)
{
  SKIP_WITHOUT_STOCK_LMP();
  if (access(OTHER_PLUGIN.c_str(), R_OK) != 0)
    GTEST_SKIP() << "no plugin built for the other LAMMPS version at '" << OTHER_PLUGIN
                 << "' (scripts/setup.sh builds both build/ and build-2025/)";
  const std::string input = "plugin load " + OTHER_PLUGIN + "\n" + two_spheres;
  const auto res = run_program(STOCK_LMP, input);
  const auto &out = res.output;
  const bool dlopen_failed = out.find("Open of file " + OTHER_PLUGIN + " failed") != std::string::npos;
  const bool version_refused =
      out.find("ERROR: HARDSPHERE plugin was compiled for LAMMPS") != std::string::npos;
  EXPECT_TRUE(dlopen_failed || version_refused) << out;
  if (dlopen_failed)
    EXPECT_NE(out.find("ERROR: Unrecognized fix style 'hardsphere/cva'"), std::string::npos) << out;
  EXPECT_EQ(res.exit_code, 1) << "expected a LAMMPS error exit, not a crash:\n" << out;
  EXPECT_EQ(out.find("Segmentation"), std::string::npos) << out;
  EXPECT_EQ(out.find("terminate called"), std::string::npos) << out;
}
