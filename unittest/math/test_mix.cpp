// HardSphere::mix64 (hs_mix.h) is splitmix64's finaliser: the generator of
// Vigna's splitmix64.c adds 0x9e3779b97f4a7c15 to its state and mixes it,
// and its published outputs from seed 0 are reproduced here; no two of a
// range of small IDs (what the local engine mixes) collide.
#include "hs_mix.h"

#include "gtest/gtest.h"

#include <cstdint>
#include <unordered_set>

TEST(Mix64, SplitMix64OutputsFromSeedZero)
{
  // splitmix64 with state 0: its first three outputs
  const uint64_t gamma = 0x9e3779b97f4a7c15ULL;
  EXPECT_EQ(HardSphere::mix64(1 * gamma), 0xe220a8397b1dcdafULL);
  EXPECT_EQ(HardSphere::mix64(2 * gamma), 0x6e789e6aa1b965f4ULL);
  EXPECT_EQ(HardSphere::mix64(3 * gamma), 0x06c45d188009454fULL);
}

TEST(Mix64, SmallIDsDoNotCollide)
{
  std::unordered_set<uint64_t> seen;
  for (uint64_t id = 1; id <= 100000; id++) EXPECT_TRUE(seen.insert(HardSphere::mix64(id)).second);
}
