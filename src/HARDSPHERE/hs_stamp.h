/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: epoch stamps. A pass marks items by writing the
   current epoch into their stamp, so "seen in this pass" needs no clearing
   between passes; the stamps are cleared only when the counter wraps. And
   the memory-order helpers of the local engine: RowSet, a bitmap that
   reads listed rows back in index order; prefetch_row() for loops
   whose order is fixed; Batch, a loop's items tested a batch at a time;
   RowLists, per-row lists in one flat array;
   sort_by_row(), pairs in std::sort's order by per-row counts;
   capacity_bytes() for memory_usage(). LAMMPS-free.
------------------------------------------------------------------------- */

#ifndef LMP_HS_STAMP_H
#define LMP_HS_STAMP_H

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

namespace HardSphere {

// the bytes a vector holds (its capacity), for the fix's memory_usage()
template <class T, class A> double capacity_bytes(const std::vector<T, A> &v)
{
  return (double) v.capacity() * sizeof(T);
}

// a new epoch e for stamp: afterwards no entry equals e
inline void bump_epoch(uint32_t &e, std::vector<uint32_t> &stamp)
{
  if (++e == 0) {
    std::fill(stamp.begin(), stamp.end(), 0u);
    e = 1;
  }
}

// row indices collected in any order, with repeats, and read back once
// each in increasing order: a bitmap of n bits (n / 8 bytes, in cache
// where the per-atom rows are not). The local engine lists the rows its
// clusters touch cluster by cluster, all over memory; read in index order,
// the rows' own arrays are read forward through memory
class RowSet {
 public:
  // empty, for indices 0 <= i < n
  void reset(int n)
  {
    n_ = n;
    bits_.assign(((size_t) n + 63) >> 6, 0);
  }
  void add(int i) { bits_[(size_t) i >> 6] |= uint64_t(1) << (i & 63); }
  bool has(int i) const { return (bits_[(size_t) i >> 6] >> (i & 63)) & 1; }
  int size() const { return n_; }
  // fn(i) for every index added, in increasing order
  template <class F> void for_each(F fn) const
  {
    for (size_t w = 0; w < bits_.size(); w++)
      for (uint64_t b = bits_[w]; b; b &= b - 1) fn((int) ((w << 6) + __builtin_ctzll(b)));
  }

 private:
  int n_ = 0;
  std::vector<uint64_t> bits_;
};

// short lists of values per row (e.g. the runs that saw an atom), each
// read back in the order appended: one flat array of nodes and a head and
// tail per row, so appending allocates nothing once the arrays have grown
// (a vector per row reallocated ~7000 times per step at 32000 atoms).
// clear() costs the rows used, not n
template <class V> class RowLists {
 public:
  // rows 0 <= i < n (keeps what was appended to rows below n)
  void resize(int n)
  {
    if ((int) head_.size() < n) {
      head_.resize(n, -1);
      tail_.resize(n, -1);
    }
  }
  void append(int i, V v)
  {
    const int k = (int) nodes_.size();
    nodes_.push_back({v, -1});
    if (head_[i] < 0) {
      head_[i] = k;
      used_.push_back(i);
    } else
      nodes_[tail_[i]].next = k;
    tail_[i] = k;
  }
  bool empty(int i) const { return head_[i] < 0; }
  // fn(v) for row i's values in the order appended (fn may append to
  // other rows, not to row i)
  template <class F> void for_each(int i, F fn) const
  {
    for (int k = head_[i]; k >= 0; k = nodes_[k].next) fn(nodes_[k].v);
  }
  void clear()
  {
    for (int i : used_) head_[i] = tail_[i] = -1;
    used_.clear();
    nodes_.clear();
  }
  double bytes() const
  {
    return capacity_bytes(head_) + capacity_bytes(tail_) + capacity_bytes(used_) +
        capacity_bytes(nodes_);
  }

 private:
  struct Node {
    V v;
    int next;
  };
  std::vector<int> head_, tail_, used_;
  std::vector<Node> nodes_;
};

// loops over rows listed cluster by cluster (all over memory) whose order
// is fixed (sums in key or tag order) ask for the row this many entries
// on while they work on the current one, so the misses overlap
constexpr int PREFETCH_AHEAD = 8;
// a loop whose test reads rows all over memory and branches on them (a
// mispredicted branch takes the misses one at a time): the caller
// prefetches an item's rows as it queues it, and the test runs on up to N
// queued items at once, in the order queued. flush() before anything that
// must come after the items queued so far, and at the loop's end
template <int N> class Batch {
 public:
  template <class F> void push(int item, F test)
  {
    items_[n_++] = item;
    if (n_ == N) flush(test);
  }
  template <class F> void flush(F test)
  {
    for (int b = 0; b < n_; b++) test(items_[b]);
    n_ = 0;
  }

 private:
  int items_[N];
  int n_ = 0;
};

// row i of a contiguous ncol-column array (LAMMPS' memory->create(): row i
// at base + ncol i), by its offset: a[i] would first load a row pointer
// from another place, a second miss where rows are taken at random
inline double *row_at(double *base, int ncol, int i)
{
  return base + (size_t) ncol * i;
}
inline const double *row_at(const double *base, int ncol, int i)
{
  return base + (size_t) ncol * i;
}
// row i (as row_at()); both ends, for a row that straddles two cache lines
inline void prefetch_row(const double *base, int ncol, int i, bool write = false)
{
  const double *row = row_at(base, ncol, i);
  if (write) {
    __builtin_prefetch(row, 1);
    __builtin_prefetch(row + ncol - 1, 1);
  } else {
    __builtin_prefetch(row);
    __builtin_prefetch(row + ncol - 1);
  }
}

// pairs (row, value) with rows in [0, nrows) put in the order std::sort
// gives them (row ascending, then value), in O(pairs) plus the sorts of
// the distinct rows and of each row's entries: for many pairs over few
// entries per row (a restricted evaluation of a large set's terms) instead
// of O(pairs log pairs). count: zero over [0, nrows) before and after;
// rows, tmp: scratch
inline void sort_by_row(std::vector<std::pair<int, int>> &pairs, int nrows,
                        std::vector<int> &count, std::vector<int> &rows,
                        std::vector<std::pair<int, int>> &tmp)
{
  const size_t n = pairs.size();
  if (n < 64) {
    std::sort(pairs.begin(), pairs.end());
    return;
  }
  if ((int) count.size() < nrows) count.resize(nrows, 0);
  rows.clear();
  for (const auto &e : pairs)
    if (count[e.first]++ == 0) rows.push_back(e.first);
  std::sort(rows.begin(), rows.end());
  int at = 0;    // counts -> each row's start
  for (int i : rows) {
    const int k = count[i];
    count[i] = at;
    at += k;
  }
  tmp.resize(n);
  for (const auto &e : pairs) tmp[count[e.first]++] = e;
  int begin = 0;    // (count[i] is row i's end now)
  for (int i : rows) {
    const int end = count[i];
    if (end - begin > 1)
      std::sort(tmp.begin() + begin, tmp.begin() + end,
                [](const std::pair<int, int> &a, const std::pair<int, int> &b) {
                  return a.second < b.second;
                });
    count[i] = 0;
    begin = end;
  }
  pairs.swap(tmp);
}

}    // namespace HardSphere

#endif
