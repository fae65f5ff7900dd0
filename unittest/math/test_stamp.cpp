// HardSphere::bump_epoch (hs_stamp.h): marks of one pass are not marks of
// the next, also across the counter's wrap (where the stamps are cleared)
#include "hs_stamp.h"

#include "gtest/gtest.h"

#include <cstdint>
#include <vector>

using HardSphere::bump_epoch;

TEST(Stamp, NewEpochForgetsEveryMark)
{
  std::vector<uint32_t> stamp(5, 0u);
  uint32_t e = 0;
  bump_epoch(e, stamp);
  EXPECT_EQ(e, 1u);
  stamp[2] = e;
  bump_epoch(e, stamp);
  EXPECT_EQ(e, 2u);
  for (uint32_t s : stamp) EXPECT_NE(s, e);
}

TEST(Stamp, WrapClearsTheStamps)
{
  std::vector<uint32_t> stamp(4, 0u);
  uint32_t e = UINT32_MAX - 1;
  bump_epoch(e, stamp);    // UINT32_MAX
  stamp[0] = stamp[3] = e;
  bump_epoch(e, stamp);    // wraps: 0 -> cleared, epoch 1
  EXPECT_EQ(e, 1u);
  for (uint32_t s : stamp) EXPECT_EQ(s, 0u);
  stamp[1] = e;
  bump_epoch(e, stamp);
  for (uint32_t s : stamp) EXPECT_NE(s, e);
}
