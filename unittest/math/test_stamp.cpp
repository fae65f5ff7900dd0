// HardSphere::bump_epoch (hs_stamp.h): marks of one pass are not marks of
// the next, also across the counter's wrap (where the stamps are cleared).
// HardSphere::RowSet: the rows added, in any order and with repeats, come
// back once each in increasing order (checked against std::set).
// HardSphere::sort_by_row: the order std::sort gives the pairs
#include "hs_stamp.h"

#include "gtest/gtest.h"

#include <cstdint>
#include <random>
#include <set>
#include <vector>

using HardSphere::bump_epoch;
using HardSphere::RowLists;
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

TEST(RowLists, EachRowInTheOrderAppended)
{
  // against a vector per row (what the local engine kept before): random
  // appends to 500 rows over three rounds, cleared between rounds
  std::mt19937 rng(2026);
  const int n = 500;
  std::uniform_int_distribution<int> pick(0, n - 1);
  RowLists<long> rl;
  rl.resize(n);
  for (int round = 0; round < 3; round++) {
    std::vector<std::vector<long>> ref(n);
    for (int k = 0; k < 4000; k++) {
      const int i = pick(rng);
      const long v = (long) rng();
      rl.append(i, v);
      ref[i].push_back(v);
    }
    for (int i = 0; i < n; i++) {
      std::vector<long> got;
      rl.for_each(i, [&](long v) { got.push_back(v); });
      EXPECT_EQ(got, ref[i]) << "row " << i << ", round " << round;
      EXPECT_EQ(rl.empty(i), ref[i].empty());
    }
    rl.clear();
    for (int i = 0; i < n; i++) EXPECT_TRUE(rl.empty(i));
  }
}

TEST(RowLists, ResizeKeepsTheRowsBelow)
{
  RowLists<int> rl;
  rl.resize(4);
  rl.append(3, 7);
  rl.append(3, 8);
  rl.resize(1000);
  rl.append(999, 1);
  rl.append(3, 9);
  std::vector<int> got;
  rl.for_each(3, [&](int v) { got.push_back(v); });
  EXPECT_EQ(got, (std::vector<int>{7, 8, 9}));
  EXPECT_TRUE(rl.empty(500));
  EXPECT_FALSE(rl.empty(999));
}

TEST(Stamp, SortByRowIsStdSortOrder)
{
  std::mt19937 rng(7);
  std::vector<int> count, rows;
  std::vector<std::pair<int, int>> tmp;
  for (int nrows : {5, 300, 5000})
    for (int n : {0, 1, 63, 64, 1000, 20000}) {
      std::uniform_int_distribution<int> row(0, nrows - 1), val(-50, 1 << 30);
      std::vector<std::pair<int, int>> p(n);
      for (auto &e : p) e = {row(rng), val(rng)};
      if (n > 10) p[3] = p[7];    // a repeat
      std::vector<std::pair<int, int>> want = p;
      std::sort(want.begin(), want.end());
      HardSphere::sort_by_row(p, nrows, count, rows, tmp);
      EXPECT_EQ(p, want) << nrows << " rows, " << n << " pairs";
      for (int c : count) ASSERT_EQ(c, 0) << "counts not left at zero";
    }
}

// Batch: every item tested once, in the order pushed; a test runs only
// when a batch fills or at flush() (a wall's check in between sees the
// pairs queued before it already tested)
TEST(Stamp, BatchTestsInOrderOnFillAndFlush)
{
  HardSphere::Batch<4> b;
  std::vector<int> got;
  auto test = [&](int v) { got.push_back(v); };
  for (int v = 0; v < 3; v++) b.push(v, test);
  EXPECT_TRUE(got.empty());
  b.push(3, test);    // fills
  EXPECT_EQ(got, (std::vector<int>{0, 1, 2, 3}));
  b.push(4, test);
  b.push(5, test);
  b.flush(test);
  EXPECT_EQ(got, (std::vector<int>{0, 1, 2, 3, 4, 5}));
  b.flush(test);    // empty: nothing again
  EXPECT_EQ(got.size(), 6u);
  for (int v = 6; v < 17; v++) b.push(v, test);
  b.flush(test);
  std::vector<int> want(17);
  for (int v = 0; v < 17; v++) want[v] = v;
  EXPECT_EQ(got, want);
}
