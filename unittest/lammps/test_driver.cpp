// Smoke tests of the build infrastructure: the lmp driver, the in-process
// HSLammps helper and the style table.

#include "hs_test_main.h"

#include <cmath>
#include <set>

namespace {
const char *lj_melt = R"(
units           lj
atom_style      atomic
lattice         fcc 0.8442
region          box block 0 4 0 4 0 4
create_box      1 box
create_atoms    1 box
mass            1 1.0
velocity        all create 3.0 87287 loop geom
pair_style      lj/cut 2.5
pair_coeff      1 1 1.0 1.0 2.5
neighbor        0.3 bin
neigh_modify    every 20 delay 0 check no
fix             1 all nve
thermo          5
run             10
)";
}

TEST(Driver, LmpBinaryRunsLJMelt)
{
  RunResult r = run_lmp(lj_melt, {});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("Loop time of"), std::string::npos) << r.output;
}

TEST(Driver, LmpBinaryRunsLJMeltTwoRanks)
{
  RunResult r = run_lmp(lj_melt, {}, 2);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("on 2 procs"), std::string::npos) << r.output;
}

TEST(Driver, LmpBinaryPassesVariables)
{
  RunResult r = run_lmp("print \"hs-value=${x}\"\n", {"-var", "x", "42"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("hs-value=42"), std::string::npos) << r.output;
}

TEST(Driver, LmpBinaryFailsOnError)
{
  RunResult r = run_lmp("this_is_not_a_command\n", {});
  EXPECT_NE(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("ERROR"), std::string::npos) << r.output;
}

TEST(Driver, InProcessLJMelt)
{
  HSLammps h;
  std::string text(lj_melt);
  size_t pos = 0;
  while (pos < text.size()) {
    size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    std::string line = text.substr(pos, end - pos);
    if (!line.empty()) h.cmd(line);
    pos = end + 1;
  }
  EXPECT_DOUBLE_EQ(h.thermo("step"), 10.0);
  EXPECT_DOUBLE_EQ(h.thermo("atoms"), 256.0);
  double pe = h.thermo("pe");
  EXPECT_TRUE(std::isfinite(pe));
  EXPECT_LT(pe, 0.0);
}

TEST(Driver, StyleTable)
{
  const auto &styles = hardsphere_styles();
  std::set<std::string> names;
  for (const auto &s : styles) {
    ASSERT_NE(s.kind, nullptr);
    ASSERT_NE(s.name, nullptr);
    EXPECT_NE(s.creator, nullptr) << s.name;
    const std::string kind(s.kind);
    EXPECT_TRUE(kind == "fix" || kind == "compute") << kind;
    EXPECT_TRUE(names.insert(std::string(s.kind) + " " + s.name).second)
        << "duplicate style " << s.name;
  }
  // registered styles are visible to the instance
  HSLammps h;
  for (const auto &s : styles) {
    if (std::string(s.kind) == "fix")
      EXPECT_EQ(h.lmp->modify->fix_map->count(s.name), 1u) << s.name;
    else
      EXPECT_EQ(h.lmp->modify->compute_map->count(s.name), 1u) << s.name;
  }
}
