// hs_cells.h: the cell list of the local engine's on-demand rows, against
// brute force: every point within `cut` of a query must be a candidate,
// also after the points moved by up to `slack` since the build (cells
// cut + slack wide), for queries inside and outside the points' box,
// degenerate boxes (flat, one point, all points equal) and no points.

#include "hs_cells.h"

#include "gtest/gtest.h"

#include <array>
#include <cmath>
#include <random>
#include <set>
#include <vector>

using HardSphere::CellGrid;
using P = std::array<double, 3>;

namespace {

double dist(const P &a, const double *b)
{
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                   (a[2] - b[2]) * (a[2] - b[2]));
}

// the points within cut of q (brute force) must all be candidates; the
// candidates are distinct
std::vector<P> built_;    // the points at the build (check_query's)

void check_query(const CellGrid &g, const std::vector<P> &now, const double *q, double cut)
{
  std::set<int> cand;
  int calls = 0;
  g.for_each_candidate(q, [&](int j, const double *xj) {
    cand.insert(j);
    calls++;
    // the position handed over is the point's at the build
    EXPECT_EQ(xj[0], built_[j][0]);
    EXPECT_EQ(xj[2], built_[j][2]);
  });
  EXPECT_EQ(calls, (int) cand.size()) << "a candidate came twice";
  for (int j = 0; j < (int) now.size(); j++)
    if (dist(now[j], q) <= cut) EXPECT_TRUE(cand.count(j)) << "point " << j << " missed";
}

}    // namespace

TEST(CellGrid, FindsEveryPointWithinCutAfterMoves)
{
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  for (int trial = 0; trial < 200; trial++) {
    const int n = 1 + (int) (U(rng) * 400);
    const double L[3] = {0.5 + 20 * U(rng), 0.5 + 20 * U(rng), trial % 7 == 0 ? 0.0 : 0.5 + 20 * U(rng)};
    const double cut = 0.2 + 3.0 * U(rng), slack = 0.5 * U(rng);
    std::vector<P> built(n), now(n);
    for (int i = 0; i < n; i++)
      for (int d = 0; d < 3; d++) built[i][d] = L[d] * U(rng) - 3.0;
    CellGrid g;
    // (sub up to 6: the stretches of sub <= 4 are one prefetched batch,
    // larger ones several)
    g.build(built, n, cut + slack, 1 + trial % 6);
    built_ = built;
    ASSERT_EQ(g.size(), n);
    // each point moved by at most slack since the build
    for (int i = 0; i < n; i++) {
      P s;
      double r2 = 0.0;
      for (int d = 0; d < 3; d++) {
        s[d] = 2.0 * U(rng) - 1.0;
        r2 += s[d] * s[d];
      }
      const double f = slack * U(rng) / std::max(1e-300, std::sqrt(r2));
      for (int d = 0; d < 3; d++) now[i][d] = built[i][d] + f * s[d];
    }
    // queries at the points, and anywhere around and beyond the box
    for (int k = 0; k < 30; k++) {
      const P &q = now[(size_t) (U(rng) * n) % n];
      check_query(g, now, q.data(), cut);
      double r[3];
      for (int d = 0; d < 3; d++) r[d] = (L[d] + 2.0 * cut) * U(rng) - 3.0 - cut;
      check_query(g, now, r, cut);
    }
  }
}

TEST(CellGrid, DegenerateBoxes)
{
  const double cut = 1.0;
  // all points equal
  std::vector<P> same(50, P{1.0, 2.0, 3.0});
  CellGrid g;
  g.build(same, 50, cut);
  built_ = same;
  const double q[3] = {1.5, 2.0, 3.0};
  check_query(g, same, q, cut);
  // one point
  std::vector<P> one(1, P{0.0, 0.0, 0.0});
  g.build(one, 1, cut);
  built_ = one;
  check_query(g, one, q, 2.0);
  // none: no candidate at all
  std::vector<P> none;
  g.build(none, 0, cut);
  int calls = 0;
  g.for_each_candidate(q, [&](int, const double *) { calls++; });
  EXPECT_EQ(calls, 0);
  // a line of points far apart: the grid has many cells along one axis
  std::vector<P> line(100);
  for (int i = 0; i < 100; i++) line[i] = {0.0, 0.0, 3.0 * i};
  g.build(line, 100, cut);
  built_ = line;
  for (int i = 0; i < 100; i++) {
    std::set<int> c;
    g.for_each_candidate(line[i].data(), [&](int j, const double *) { c.insert(j); });
    EXPECT_TRUE(c.count(i));
    // cells of width >= 1 on a 297-long line: not every point is a candidate
    EXPECT_LT(c.size(), 10u);
  }
}

// CellRows: a row is filled once per grid build, kept until the next build
// (then filled again), and holds what its fill appended
TEST(CellRows, FilledOncePerBuild)
{
  std::vector<P> pts(20);
  for (int i = 0; i < 20; i++) pts[i] = {0.5 * i, 0.0, 0.0};
  HardSphere::CellRows<int> rows;
  int fills = 0;
  auto neighbours = [&](int a) {
    return [&, a](std::vector<int> &out) {
      ++fills;
      rows.grid.for_each_candidate(pts[a].data(), [&](int j, const double *xj) {
        if (j != a && std::fabs(xj[0] - pts[a][0]) <= 1.0) out.push_back(j);
      });
    };
  };
  for (int build = 0; build < 2; build++) {
    rows.rebuild(pts, 20, 1.0, 2);
    fills = 0;
    for (int pass = 0; pass < 3; pass++)
      for (int a : {0, 7, 19}) {
        int n;
        const int *r = rows.row(a, n, neighbours(a));
        std::set<int> got(r, r + n), want;
        for (int j = 0; j < 20; j++)
          if (j != a && std::fabs(pts[j][0] - pts[a][0]) <= 1.0) want.insert(j);
        EXPECT_EQ(got, want) << "point " << a << " build " << build;
      }
    EXPECT_EQ(fills, 3) << "each row filled once per build";
  }
}

// for_each_within(): exactly the candidates of for_each_candidate() whose
// squared distance (the same operations, q - xj) is not greater than cut2,
// in the same order, with the same positions; queries with more candidates
// than one kernel call takes (256: dense points, a coarse grid), and
// distances equal to the cutoff to the bit (points on a lattice)
TEST(CellGrid, WithinIsTheCandidatesWithinTheCutoffInOrder)
{
  std::mt19937 rng(20261206);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  int kept = 0, dropped = 0, large = 0;
  for (int trial = 0; trial < 150; trial++) {
    const int n = 1 + (int) (U(rng) * (trial % 3 == 0 ? 3000 : 400));
    const double L = 2.0 + 8.0 * U(rng);
    const bool lattice = trial % 2 == 1;
    std::vector<P> pts(n);
    for (auto &p : pts)
      for (double &v : p) v = lattice ? 0.25 * std::floor(U(rng) * L / 0.25) : L * U(rng);
    CellGrid g;
    const double width = 0.5 + 2.0 * U(rng);
    g.build(pts, n, width, 1 + trial % 3);
    for (int qn = 0; qn < 20; qn++) {
      const P q = {L * U(rng), L * U(rng), lattice ? 0.25 * (qn % 8) : L * U(rng)};
      const double cut2 = lattice ? 0.0625 * (qn % 40) : width * width * U(rng);
      std::vector<std::pair<int, const double *>> want, got;
      int cand = 0;
      g.for_each_candidate(q.data(), [&](int j, const double *xj) {
        cand++;
        const double dx = q[0] - xj[0], dy = q[1] - xj[1], dz = q[2] - xj[2];
        if (!(dx * dx + dy * dy + dz * dz > cut2)) want.emplace_back(j, xj);
      });
      g.for_each_within(q.data(), cut2, [&](int j, const double *xj) { got.emplace_back(j, xj); });
      ASSERT_EQ(want, got) << "trial " << trial << " query " << qn;
      kept += (int) want.size();
      dropped += cand - (int) want.size();
      large += cand > 256;
    }
  }
  EXPECT_GT(kept, 10000);
  EXPECT_GT(dropped, 10000);
  EXPECT_GT(large, 50);    // (queries past one kernel call's 256 slots)
}
