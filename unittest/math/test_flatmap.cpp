// HardSphere::FlatMap (hs_flatmap.h): after any sequence of inserts, erases
// and clears, every key's lookup agrees with std::unordered_map's, and
// for_each() visits exactly the map's entries (keys clustered as a step's
// cluster keys are, and spread; tables that grow and wrap around)
#include "hs_flatmap.h"

#include "gtest/gtest.h"

#include <algorithm>
#include <cstdint>
#include <map>
#include <random>
#include <unordered_map>

using HardSphere::FlatMap;

namespace {

void check_same(FlatMap<int, int> &fm, const std::unordered_map<int, int> &ref, int kmax)
{
  ASSERT_EQ(fm.size(), ref.size());
  for (int k = 1; k <= kmax; k++) {
    const int *v = fm.find(k);
    auto it = ref.find(k);
    if (it == ref.end())
      ASSERT_EQ(v, nullptr) << "key " << k << " found after its erase";
    else {
      ASSERT_NE(v, nullptr) << "key " << k << " lost";
      ASSERT_EQ(*v, it->second);
    }
  }
  std::map<int, int> seen;
  fm.for_each([&](int k, int &v) { seen[k] = v; });
  ASSERT_EQ(seen.size(), ref.size());
  for (auto &kv : seen) ASSERT_EQ(ref.at(kv.first), kv.second);
}

}    // namespace

TEST(FlatMap, AgreesWithUnorderedMapUnderRandomOperations)
{
  std::mt19937_64 rng(20261127);
  for (int kmax : {40, 3000, 200000}) {
    FlatMap<int, int> fm;
    std::unordered_map<int, int> ref;
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int round = 0; round < 30; round++) {
      // keys of a step: runs of close IDs (a cluster's), some far apart
      const int nop = 2000;
      for (int op = 0; op < nop; op++) {
        const int base = 1 + (int) (u(rng) * kmax);
        const int k = std::min(kmax, base + (int) (u(rng) * 8.0));
        const double r = u(rng);
        if (r < 0.55) {
          const int v = (int) (u(rng) * 1e6);
          const bool had = ref.count(k) > 0;
          int &got = fm.insert(k, v);
          if (had)
            ASSERT_EQ(got, ref[k]) << "insert of a present key changed it";
          else
            ref[k] = v;
        } else {
          ASSERT_EQ(fm.erase(k), ref.erase(k) > 0) << "key " << k;
        }
      }
      check_same(fm, ref, kmax);
      if (round % 10 == 9) {
        fm.clear();
        ref.clear();
        check_same(fm, ref, kmax);
      }
    }
  }
}

TEST(FlatMap, EraseInWrappedProbeRuns)
{
  // a small table, nearly half full, keys erased in every order: the probe
  // runs wrap around the end of the slots
  std::mt19937_64 rng(7);
  for (int trial = 0; trial < 2000; trial++) {
    FlatMap<int, int> fm;
    std::unordered_map<int, int> ref;
    std::vector<int> keys;
    for (int k = 0; k < 8; k++) {
      const int key = 1 + (int) (rng() % 64);
      if (ref.count(key)) continue;
      keys.push_back(key);
      fm.insert(key, key * 3);
      ref[key] = key * 3;
    }
    std::shuffle(keys.begin(), keys.end(), rng);
    for (int key : keys) {
      ASSERT_TRUE(fm.erase(key));
      ref.erase(key);
      check_same(fm, ref, 64);
    }
    EXPECT_FALSE(fm.erase(keys.empty() ? 1 : keys[0]));
  }
}
