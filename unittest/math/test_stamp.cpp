// HardSphere::bump_epoch (hs_stamp.h): marks of one pass are not marks of
// the next, also across the counter's wrap (where the stamps are cleared).
// HardSphere::RowSet: the rows added, in any order and with repeats, come
// back once each in increasing order (checked against std::set)
#include "hs_stamp.h"

#include "gtest/gtest.h"

#include <cstdint>
#include <random>
#include <set>
#include <vector>

using HardSphere::bump_epoch;
using HardSphere::RowSet;

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

TEST(RowSet, IncreasingOrderOnceEach)
{
  // sizes around the 64-bit words' edges, indices at both ends included
  for (int n : {1, 63, 64, 65, 128, 1000, 4097}) {
    std::mt19937 rng(12345 + n);
    std::uniform_int_distribution<int> pick(0, n - 1);
    RowSet rs;
    rs.reset(n);
    std::set<int> ref;
    const int adds = 3 * n;
    for (int k = 0; k < adds; k++) {
      const int i = (k == 0) ? 0 : (k == 1) ? n - 1 : pick(rng);
      rs.add(i);
      ref.insert(i);
    }
    std::vector<int> got;
    rs.for_each([&](int i) { got.push_back(i); });
    EXPECT_EQ(got, std::vector<int>(ref.begin(), ref.end())) << "n = " << n;
    for (int i = 0; i < n; i++) EXPECT_EQ(rs.has(i), ref.count(i) == 1) << "n = " << n;
  }
}

TEST(RowSet, ResetForgetsEveryRow)
{
  RowSet rs;
  rs.reset(200);
  for (int i : {0, 5, 64, 199}) rs.add(i);
  rs.reset(100);
  EXPECT_EQ(rs.size(), 100);
  int seen = 0;
  rs.for_each([&](int) { seen++; });
  EXPECT_EQ(seen, 0);
  for (int i = 0; i < 100; i++) EXPECT_FALSE(rs.has(i));
}
