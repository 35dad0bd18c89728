#include "uavip/core/key_sort.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace uavip {
namespace {

/// Pairs with ascending indices and keys drawn from [0, range) (range 0: any 64-bit key).
std::vector<KeyedIndex> randomPairs(std::size_t n, std::uint64_t range, std::uint32_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<KeyedIndex> v(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint64_t k = rng();
    v[i] = {range == 0 ? k : k % range, static_cast<std::uint32_t>(i)};
  }
  return v;
}

TEST(SortByKey, EqualsStdSortOnThePairsWhenIndicesAscend) {
  // Sizes on both sides of the small-input path; key ranges from one shared digit
  // (passes skipped) to every bit, and heavy duplication (the down-sampler's case).
  for (const std::size_t n : {0u, 1u, 7u, 4095u, 4096u, 100000u}) {
    for (const std::uint64_t range : {std::uint64_t{1}, std::uint64_t{50}, std::uint64_t{1} << 20,
                                      std::uint64_t{1} << 40, std::uint64_t{0}}) {
      auto pairs = randomPairs(n, range, static_cast<std::uint32_t>(n + range));
      auto expected = pairs;
      std::sort(expected.begin(), expected.end());
      sortByKey(pairs);
      EXPECT_EQ(pairs, expected) << n << " pairs, keys below " << range;
    }
  }
}

TEST(SortByKey, HighBitsOnlyAndVoxelLikeKeysSortCorrectly) {
  // Keys that differ only above bit 48 (the last pass) and keys packed like voxel
  // coordinates with negative values wrapped into 21 bits.
  std::vector<KeyedIndex> high, voxel;
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> coord(-300, 300);
  for (std::uint32_t i = 0; i < 20000; ++i) {
    high.push_back({static_cast<std::uint64_t>(rng() % 7) << 50, i});
    const auto wrap = [](int c) {
      return static_cast<std::uint64_t>(static_cast<std::int64_t>(c) & 0x1fffff);
    };
    voxel.push_back({(wrap(coord(rng)) << 42) | (wrap(coord(rng)) << 21) | wrap(coord(rng)), i});
  }
  for (auto* v : {&high, &voxel}) {
    auto expected = *v;
    std::sort(expected.begin(), expected.end());
    sortByKey(*v);
    EXPECT_EQ(*v, expected);
  }
}

TEST(SortByKey, TwoThreadsGiveStdSortsOrder) {
  // Large enough for the two-half path (2^17 pairs and up); duplicated keys across
  // the halves must keep ascending indices.
  for (const std::size_t n : {std::size_t{100000}, std::size_t{1} << 17, std::size_t{300001}}) {
    for (const std::uint64_t range : {std::uint64_t{7}, std::uint64_t{1} << 20, std::uint64_t{0}}) {
      auto pairs = randomPairs(n, range, static_cast<std::uint32_t>(n ^ range));
      auto expected = pairs;
      std::sort(expected.begin(), expected.end());
      sortByKey(pairs, 2);
      EXPECT_EQ(pairs, expected) << n << " pairs, keys below " << range;
    }
  }
}

TEST(RunStart, CutsBetweenRunsOfEqualKeys) {
  const std::vector<KeyedIndex> keyed{{1, 0}, {1, 1}, {2, 2}, {2, 3}, {2, 4}, {5, 5}};
  EXPECT_EQ(runStart(keyed, 0), 0u);
  EXPECT_EQ(runStart(keyed, 1), 2u);
  EXPECT_EQ(runStart(keyed, 2), 2u);
  EXPECT_EQ(runStart(keyed, 3), 5u);
  EXPECT_EQ(runStart(keyed, 5), 5u);
  EXPECT_EQ(runStart(keyed, 6), 6u);
  EXPECT_EQ(runStart({}, 0), 0u);
}

}  // namespace
}  // namespace uavip
