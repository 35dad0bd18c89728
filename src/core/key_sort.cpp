#include "uavip/core/key_sort.h"

#include <algorithm>
#include <array>
#include <cstddef>

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

}  // namespace

void sortByKey(std::vector<KeyedIndex>& keyed) {
  if (keyed.size() < kSmall) {
    std::stable_sort(keyed.begin(), keyed.end(),
                     [](const KeyedIndex& a, const KeyedIndex& b) { return a.first < b.first; });
    return;
  }
  // All histograms in one read; a pass whose digit is shared by every key is a no-op.
  std::vector<std::array<std::size_t, kBuckets>> counts(kPasses);
  for (auto& c : counts) c.fill(0);
  for (const auto& k : keyed) {
    for (int p = 0; p < kPasses; ++p) ++counts[static_cast<std::size_t>(p)][digit(k.first, p)];
  }
  std::vector<KeyedIndex> buffer(keyed.size());
  for (int p = 0; p < kPasses; ++p) {
    auto& count = counts[static_cast<std::size_t>(p)];
    if (count[digit(keyed.front().first, p)] == keyed.size()) continue;
    std::size_t offset = 0;
    for (auto& c : count) {
      const std::size_t n = c;
      c = offset;
      offset += n;
    }
    for (const auto& k : keyed) buffer[count[digit(k.first, p)]++] = k;
    keyed.swap(buffer);
  }
}

}  // namespace uavip
