#include "uavip/core/key_sort.h"

#include <algorithm>
#include <array>
#include <cstddef>

#include "uavip/core/parallel.h"

namespace uavip {

namespace {

constexpr int kDigitBits = 16;
constexpr int kPasses = 64 / kDigitBits;
constexpr std::size_t kBuckets = std::size_t{1} << kDigitBits;
/// Below this many pairs std::sort is as fast and needs no histogram.
constexpr std::size_t kSmall = 4096;

std::size_t digit(std::uint64_t key, int pass) {
  return static_cast<std::size_t>((key >> (pass * kDigitBits)) & (kBuckets - 1));
}

/// The key of an element: a KeyedIndex's first, or the key itself.
std::uint64_t keyOf(const KeyedIndex& k) { return k.first; }
std::uint64_t keyOf(std::uint64_t k) { return k; }

/// LSD radix sort by keyOf (stable), small inputs by std::stable_sort.
template <typename T>
void radixSort(std::vector<T>& keyed) {
  if (keyed.size() < kSmall) {
    std::stable_sort(keyed.begin(), keyed.end(),
                     [](const T& a, const T& b) { return keyOf(a) < keyOf(b); });
    return;
  }
  // All histograms in one read; a pass whose digit is shared by every key is a no-op.
  std::vector<std::array<std::size_t, kBuckets>> counts(kPasses);
  for (auto& c : counts) c.fill(0);
  for (const auto& k : keyed) {
    for (int p = 0; p < kPasses; ++p) ++counts[static_cast<std::size_t>(p)][digit(keyOf(k), p)];
  }
  std::vector<T> buffer(keyed.size());
  for (int p = 0; p < kPasses; ++p) {
    auto& count = counts[static_cast<std::size_t>(p)];
    if (count[digit(keyOf(keyed.front()), p)] == keyed.size()) continue;
    std::size_t offset = 0;
    for (auto& c : count) {
      const std::size_t n = c;
      c = offset;
      offset += n;
    }
    for (const auto& k : keyed) buffer[count[digit(keyOf(k), p)]++] = k;
    keyed.swap(buffer);
  }
}

}  // namespace

void sortByKey(std::vector<KeyedIndex>& keyed) { radixSort(keyed); }

void sortByKey(std::vector<KeyedIndex>& keyed, int threads) {
  constexpr std::size_t kParallelPairs = std::size_t{1} << 17;
  if (threads < 2 || keyed.size() < kParallelPairs) {
    radixSort(keyed);
    return;
  }
  const auto half = static_cast<std::ptrdiff_t>(keyed.size() / 2);
  std::vector<KeyedIndex> low(keyed.begin(), keyed.begin() + half);
  std::vector<KeyedIndex> high(keyed.begin() + half, keyed.end());
  parallelFor(2, 2, [&](std::size_t part, std::size_t) { radixSort(part == 0 ? low : high); });
  std::merge(low.begin(), low.end(), high.begin(), high.end(), keyed.begin(),
             [](const KeyedIndex& a, const KeyedIndex& b) { return a.first < b.first; });
}

std::size_t runStart(const std::vector<KeyedIndex>& keyed, std::size_t i) {
  while (i > 0 && i < keyed.size() && keyed[i].first == keyed[i - 1].first) ++i;
  return std::min(i, keyed.size());
}

PointList fromRunsInHalves(const std::vector<KeyedIndex>& keyed, int threads,
                           const std::function<PointList(std::size_t, std::size_t)>& of_runs) {
  const std::size_t n = keyed.size();
  const std::size_t cut = threads < 2 ? n : runStart(keyed, n / 2);
  std::array<PointList, 2> parts;
  parallelFor(2, threads, [&](std::size_t part, std::size_t) {
    parts[part] = part == 0 ? of_runs(0, cut) : of_runs(cut, n);
  });
  parts[0].insert(parts[0].end(), parts[1].begin(), parts[1].end());
  return std::move(parts[0]);
}

void sortUniqueKeys(std::vector<std::uint64_t>& keys) {
  radixSort(keys);
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
}

}  // namespace uavip
