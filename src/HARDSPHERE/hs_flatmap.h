/* -*- c++ -*- ----------------------------------------------------------
   HARDSPHERE package: a hash map from positive integer keys (atom IDs) to
   values, in one flat array (open addressing, linear probing, capacity a
   power of two, at most half full; erase by backward shift, no tombstones).

   The local engine looks up its runs by key (the lowest member ID) a few
   hundred thousand times per 10 steps at 256000 atoms; std::unordered_map
   takes a division by a prime and two dependent loads (bucket, node) per
   lookup, and perf put ~1 % of a step in its find(). Here a lookup is a
   multiply, a mask and, nearly always, one cache line.

   Keys must be > 0 (0 marks an empty slot): LAMMPS' atom IDs are. The
   order of for_each() is the slots', not the keys': callers that need an
   order sort. LAMMPS-free (unit-tested alone: unittest/math/test_flatmap.cpp).
------------------------------------------------------------------------- */

#ifndef LMP_HS_FLATMAP_H
#define LMP_HS_FLATMAP_H

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace HardSphere {

template <class K, class V> class FlatMap {
 public:
  // the value of key k, nullptr if k is not in the map
  V *find(K k)
  {
    if (n_ == 0) return nullptr;
    for (size_t s = slot(k);; s = (s + 1) & mask_) {
      if (keys_[s] == k) return &vals_[s];
      if (keys_[s] == 0) return nullptr;
    }
  }
  const V *find(K k) const { return const_cast<FlatMap *>(this)->find(k); }

  // the value of key k (> 0), inserted as v if k was not in the map
  V &insert(K k, const V &v)
  {
    if (2 * (n_ + 1) > keys_.size()) grow();
    size_t s = slot(k);
    for (; keys_[s] != 0; s = (s + 1) & mask_)
      if (keys_[s] == k) return vals_[s];
    keys_[s] = k;
    vals_[s] = v;
    n_++;
    return vals_[s];
  }

  // removes key k if present; true if it was
  bool erase(K k)
  {
    if (n_ == 0) return false;
    size_t s = slot(k);
    for (; keys_[s] != k; s = (s + 1) & mask_)
      if (keys_[s] == 0) return false;
    // backward shift: every later entry of the probe run that may live in
    // the hole moves into it, so no lookup passes an empty slot it needs
    size_t hole = s;
    for (size_t t = (s + 1) & mask_; keys_[t] != 0; t = (t + 1) & mask_) {
      const size_t home = slot(keys_[t]);
      // t may move to hole if its home is not in (hole, t] (cyclically)
      const bool stays = (hole < t) ? (home > hole && home <= t) : (home > hole || home <= t);
      if (stays) continue;
      keys_[hole] = keys_[t];
      vals_[hole] = std::move(vals_[t]);
      hole = t;
    }
    keys_[hole] = 0;
    vals_[hole] = V();
    n_--;
    return true;
  }

  // (every slot by std::fill, which vectorises, where a test of each slot
  // did not: a table keeps the capacity of its largest content, and mcva's
  // partner map is cleared for every flow; ~1 % of its time)
  void clear()
  {
    if (n_ == 0) return;
    std::fill(keys_.begin(), keys_.end(), K(0));
    std::fill(vals_.begin(), vals_.end(), V());
    n_ = 0;
  }

  size_t size() const { return n_; }

  // fn(key, value&) for every entry, in slot order
  template <class F> void for_each(F fn)
  {
    for (size_t s = 0; s < keys_.size(); s++)
      if (keys_[s] != 0) fn(keys_[s], vals_[s]);
  }

 private:
  std::vector<K> keys_;
  std::vector<V> vals_;
  size_t n_ = 0, mask_ = 0;
  int shift_ = 64;

  // Fibonacci hashing: the top bits of k times 2^64 / golden ratio (IDs
  // that are close, as a cluster's are, spread over the table)
  size_t slot(K k) const
  {
    return (size_t) (((uint64_t) k * 0x9E3779B97F4A7C15ull) >> shift_) & mask_;
  }

  void grow()
  {
    const size_t cap = keys_.empty() ? 16 : 2 * keys_.size();
    std::vector<K> ok(cap, 0);
    std::vector<V> ov(cap);
    ok.swap(keys_);
    ov.swap(vals_);
    mask_ = cap - 1;
    shift_ = 64;
    for (size_t c = cap; c > 1; c >>= 1) shift_--;
    n_ = 0;
    for (size_t s = 0; s < ok.size(); s++)
      if (ok[s] != 0) insert(ok[s], ov[s]);
  }
};

}    // namespace HardSphere

#endif
