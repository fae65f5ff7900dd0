/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: a cell list over explicit points (no periodic
   wrapping: a rank's ghost atoms are the images), for the local engine's
   on-demand interaction rows (issue 20, hs_local_forces.h "rows").

   LAMMPS' own pair list cannot give every term of a colliding sphere on
   several ranks: with newton on, a pair of an owned atom and a ghost is
   listed on one of the two ranks only, and a ghost has no row at all. The
   local engine computes a cluster on one rank (the owner of its lowest
   tag) from that rank's copies of its members, owned or ghost, so it needs
   the rows of any local atom on demand. The grid is built from the
   positions at a neighbor list build; points move by less than `slack`
   (the neighbor skin) until the next one, so a query for the points within
   `cut` of a current position scans the cells within cut + slack of it:
   with cells at least (cut + slack) / sub wide, the (2 sub + 1)^3 cells
   around it.

   LAMMPS-free (unit-tested alone: unittest/math/test_cells.cpp).
------------------------------------------------------------------------- */

#ifndef LMP_HS_CELLS_H
#define LMP_HS_CELLS_H

#include "hs_near.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace HardSphere {

class CellGrid {
 public:
  // bin points x[0..n) (x[i][0..2]) into cells at least width / sub wide;
  // a query scans the cells within sub cells of its own (finer cells, sub
  // > 1, scan less volume: (2 sub + 1)^3 / sub^3 of width^3 against 27)
  template <class X> void build(const X &x, int n, double width, int sub = 1)
  {
    n_ = n;
    sub_ = std::max(1, sub);
    width /= sub_;
    if (n == 0 || !(width > 0.0)) {
      for (int d = 0; d < 3; d++) {
        nc_[d] = 1;
        lo_[d] = hi_[d] = inv_[d] = 0.0;
      }
      start_.assign(2, 0);
      start_[1] = n;
      idx_.resize(n);
      pos_.resize(3 * (size_t) n);
      for (int i = 0; i < n; i++) {
        idx_[i] = i;
        for (int d = 0; d < 3; d++) pos_[3 * (size_t) i + d] = x[i][d];
      }
      return;
    }
    for (int d = 0; d < 3; d++) {
      lo_[d] = hi_[d] = x[0][d];
    }
    for (int i = 1; i < n; i++)
      for (int d = 0; d < 3; d++) {
        lo_[d] = std::min(lo_[d], x[i][d]);
        hi_[d] = std::max(hi_[d], x[i][d]);
      }
    size_t total = 1;
    for (int d = 0; d < 3; d++) {
      const double span = hi_[d] - lo_[d];
      // cells at least `width` wide, at most ~2 per point along an axis
      int m = (int) std::floor(span / width);
      m = std::max(1, std::min(m, 2 * n + 1));
      nc_[d] = m;
      inv_[d] = (span > 0.0) ? m / span : 0.0;
      total *= (size_t) m;
    }
    // the points in cell order, their positions copied alongside: a query
    // reads each cell's points from one contiguous stretch (the scan is
    // bound by memory reads, not arithmetic)
    start_.assign(total + 1, 0);
    std::vector<size_t> cell(n);
    for (int i = 0; i < n; i++) {
      cell[i] = cell_of(x[i]);
      start_[cell[i] + 1]++;
    }
    for (size_t c = 0; c < total; c++) start_[c + 1] += start_[c];
    idx_.resize(n);
    pos_.resize(3 * (size_t) n);
    std::vector<int> fill(start_.begin(), start_.end() - 1);
    for (int i = 0; i < n; i++) {    // increasing index within each cell
      const int k = fill[cell[i]]++;
      idx_[k] = i;
      for (int d = 0; d < 3; d++) pos_[3 * (size_t) k + d] = x[i][d];
    }
  }

  int size() const { return n_; }

  // every point j whose cell is within sub cells of q's (every point within
  // `width` of q, and more); calls fn(j, xj) with xj its position at the
  // build. The caller tests distances.
  template <class F> void for_each_candidate(const double *q, F fn) const
  {
    stretches(q, [&](const int *ks, const int *ke, int ns) {
      for (int b = 0; b < ns; b++)
        for (int k = ks[b]; k < ke[b]; k++) fn(idx_[k], &pos_[3 * (size_t) k]);
    });
  }

  // the candidates of for_each_candidate() whose position at the build
  // lies within sqrt(cut2) of q (squared distance not greater than cut2,
  // as hs_near.h's near<true>() computes it), in the same order: the
  // candidates' slots are listed, stretch after stretch, and tested four at
  // a time before fn(j, xj) is called (the local engine's rows keep about
  // one candidate in four; a stretch holds ~8, too few to test alone)
  template <class F> void for_each_within(const double *q, double cut2, F fn) const
  {
    constexpr int CHUNK = 256;    // slots tested per kernel call
    int slot[CHUNK], hit[CHUNK + 4];
    int ns = 0;
    auto test = [&](int n) {
      const int m = near<true>(slot, n, -1, pos_.data(), q[0], q[1], q[2], cut2, hit);
      for (int o = 0; o < m; o++) fn(idx_[hit[o]], &pos_[3 * (size_t) hit[o]]);
    };
    stretches(q, [&](const int *ks, const int *ke, int nb) {
      int n = ns;
      for (int b = 0; b < nb; b++)
        for (int k0 = ks[b]; k0 < ke[b];) {
          if (n == CHUNK) {
            test(n);
            n = 0;
          }
          const int len = std::min(ke[b] - k0, CHUNK - n);
          for (int t = 0; t < len; t++) slot[n + t] = k0 + t;
          n += len;
          k0 += len;
        }
      ns = n;
    });
    if (ns) test(ns);
  }

 private:
  // the cells (a, b, e0..e1) within sub cells of q's are consecutive: one
  // stretch [ks, ke) of points each. The stretches are listed (in batches,
  // in (a, b) order) and their first lines prefetched before batch(ks, ke,
  // ns) reads any: a query's cells are cold (the local engine asks for rows
  // of spheres all over the box), and asking for them at once lets their
  // cache misses overlap instead of waiting for each in turn
  template <class B> void stretches(const double *q, B batch) const
  {
    if (n_ == 0) return;
    int c[3];
    for (int d = 0; d < 3; d++) c[d] = axis_cell(q[d], d);
    const int s = sub_;
    const int a0 = std::max(0, c[0] - s), a1 = std::min(nc_[0] - 1, c[0] + s);
    const int b0 = std::max(0, c[1] - s), b1 = std::min(nc_[1] - 1, c[1] + s);
    const int e0 = std::max(0, c[2] - s), e1 = std::min(nc_[2] - 1, c[2] + s);
    constexpr int MAXS = 81;    // (2 sub + 1)^2 for sub <= 4: one batch
    int ks[MAXS], ke[MAXS];
    int ns = 0;
    for (int a = a0; a <= a1; a++)
      for (int b = b0; b <= b1; b++) {
        const size_t first = ((size_t) a * nc_[1] + b) * nc_[2];
        ks[ns] = start_[first + e0];
        ke[ns] = start_[first + e1 + 1];
        if (ks[ns] < ke[ns]) {
          __builtin_prefetch(&pos_[3 * (size_t) ks[ns]]);
          __builtin_prefetch(&idx_[ks[ns]]);
        }
        if (++ns == MAXS) {
          batch(ks, ke, ns);
          ns = 0;
        }
      }
    batch(ks, ke, ns);
  }

  int n_ = 0, sub_ = 1;
  int nc_[3] = {1, 1, 1};
  double lo_[3] = {0.0, 0.0, 0.0}, hi_[3] = {0.0, 0.0, 0.0}, inv_[3] = {0.0, 0.0, 0.0};
  std::vector<int> start_, idx_;    // cell -> its points (CSR), in cell order
  std::vector<double> pos_;          // their positions at the build

  // a position outside the grid's box (a point that moved since the build,
  // or a query) goes to the nearest boundary cell: the cells beyond the
  // box are empty, so the candidates within one cell are still all there
  int axis_cell(double v, int d) const
  {
    const int k = (int) std::floor((v - lo_[d]) * inv_[d]);
    return std::max(0, std::min(nc_[d] - 1, k));
  }
  template <class P> size_t cell_of(const P &p) const
  {
    return ((size_t) axis_cell(p[0], 0) * nc_[1] + axis_cell(p[1], 1)) * nc_[2] +
        axis_cell(p[2], 2);
  }
};

// a row of entries T per point (its neighbours, as the caller defines
// them), built on first demand from the grid and kept until the grid is
// built again: the local engine's interaction rows (HSLocalForces) and
// contact candidates (HSLocalEngine::crow) both live for one list build
template <class T> class CellRows {
 public:
  CellGrid grid;

  // a new grid over x[0..n); every row is forgotten
  template <class X> void rebuild(const X &x, int n, double width, int sub = 1)
  {
    grid.build(x, n, width, sub);
    forget(n);
  }

  // every row forgotten, the grid left as it is (rows a caller fills from
  // a scan of its own, for points 0..n)
  void forget(int n)
  {
    for (int a : built_) start_[a] = -1;
    built_.clear();
    pool_.clear();
    if ((int) start_.size() < n) {
      start_.resize(n, -1);
      len_.resize(n, 0);
    }
  }
  // the row of a if it was built since the last rebuild() or forget(), else
  // nullptr
  const T *built(int a, int &n) const
  {
    if (a < 0 || a >= (int) start_.size() || start_[a] < 0) return nullptr;
    n = len_[a];
    return pool_.data() + start_[a];
  }

  // the row of point a (n entries); fill(pool) appends its entries the
  // first time. The pointer is valid until the next row() that builds.
  template <class F> const T *row(int a, int &n, F fill)
  {
    if (start_[a] < 0) {
      const size_t first = pool_.size();
      fill(pool_);
      start_[a] = (int) first;
      len_[a] = (int) (pool_.size() - first);
      built_.push_back(a);
    }
    n = len_[a];
    return pool_.data() + start_[a];
  }

 private:
  std::vector<int> start_, len_, built_;    // -1: not built since the grid
  std::vector<T> pool_;
};

}    // namespace HardSphere

#endif
