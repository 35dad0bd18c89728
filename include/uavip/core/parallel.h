#pragma once
/// \file
/// The one worker pool of the project: an index loop spread over threads, whose
/// worker exceptions reach the caller (a bad_alloc in a worker must not end the
/// process).

#include <cstddef>
#include <functional>

namespace uavip {

/// The number of hardware threads (at least 1): the default worker count.
int hardwareThreads();

/// Calls body(i, worker) for every i in [0, n) on up to `threads` threads; the
/// caller is worker 0 and the others are numbered 1… in start order. Indices are
/// handed out in increasing order from a shared counter. When a body throws, no
/// further index is started, every worker is joined and the first exception is
/// rethrown here. When no thread can be started the caller does all the work.
/// Results are deterministic when body(i, ·) writes only to slot i, or to its
/// worker's own tally that the caller merges in an order-free way.
void parallelFor(std::size_t n, int threads,
                 const std::function<void(std::size_t i, std::size_t worker)>& body);

}  // namespace uavip
