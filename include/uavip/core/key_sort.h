#pragma once
/// \file
/// Sorting (64-bit key, 32-bit index) pairs and plain keys, the step every voxel
/// down-sampler and cell hasher spends most of its time in.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include "uavip/core/types.h"

namespace uavip {

/// One (voxel key, point index) pair.
using KeyedIndex = std::pair<std::uint64_t, std::uint32_t>;

/// Sorts by key, stably: pairs with equal keys keep their input order. When the
/// indices ascend on input (keyed[i].second == i, as a down-sampler builds them) the
/// result equals std::sort's on the pairs. Least-significant-digit radix sort,
/// 16 bits per pass, passes whose digit is the same for every key skipped: about
/// 5× faster than std::sort on 10⁶ pairs. Memory: a second buffer of the same size.
void sortByKey(std::vector<KeyedIndex>& keyed);

/// The same order on up to two threads: the two halves sorted at once, then merged
/// stably (a stable merge of stable sorts is the one stable order). Large inputs
/// only (below 2^17 pairs, or with threads < 2, it is sortByKey).
void sortByKey(std::vector<KeyedIndex>& keyed, int threads);

/// The first position at or after i where a run of equal keys starts in the sorted
/// `keyed` (keyed.size() when none): a cut that splits no voxel.
std::size_t runStart(const std::vector<KeyedIndex>& keyed, std::size_t i);

/// What `of_runs(from, to)` makes of the whole runs of equal keys in [from, to) of
/// the sorted `keyed`, over all of it: with threads ≥ 2 in two halves cut between
/// runs (runStart) on two threads, joined in order, so the result is the one-thread
/// result (a down-sampler's centroids, one per voxel).
PointList fromRunsInHalves(const std::vector<KeyedIndex>& keyed, int threads,
                           const std::function<PointList(std::size_t, std::size_t)>& of_runs);

/// Sorts keys ascending and drops repeats; the same radix sort (equal to std::sort
/// then std::unique).
void sortUniqueKeys(std::vector<std::uint64_t>& keys);

}  // namespace uavip
