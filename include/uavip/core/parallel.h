#pragma once
/// \file
/// The one worker pool of the project: an index loop spread over threads, whose
/// worker exceptions reach the caller (a bad_alloc in a worker must not end the
/// process).

#include <condition_variable>
#include <cstddef>
#include <functional>
#include <mutex>

namespace uavip {

/// The number of hardware threads (at least 1): the default worker count.
int hardwareThreads();

/// Where parallelFor's extra workers wait until a core is free: for work done beside a
/// thread on the critical path (the coverage of the photos beside the flight), that
/// thread opens the gate when it ends. Before that the caller works alone; extra workers
/// that find every index taken leave without waiting. Only the scheduling changes.
class WorkerGate {
 public:
  /// Lets waiting and later workers in (idempotent, thread-safe).
  void open();
  bool isOpen() const;

 private:
  friend void parallelFor(std::size_t, int, const std::function<void(std::size_t, std::size_t)>&,
                          WorkerGate*);
  /// Blocks until the gate is open (true) or done() holds (false).
  bool waitOpen(const std::function<bool()>& done);
  /// Wakes the waiters to re-check their done().
  void wake();

  mutable std::mutex mutex_;
  std::condition_variable changed_;
  bool open_{false};
};

/// Calls body(i, worker) for every i in [0, n) on up to `threads` threads; the
/// caller is worker 0 and the others are numbered 1… in start order. Indices are
/// handed out in increasing order from a shared counter. When a body throws, no
/// further index is started, every worker is joined and the first exception is
/// rethrown here. When no thread can be started the caller does all the work.
/// With a `gate`, the workers other than the caller start only once it is open.
/// Results are deterministic when body(i, ·) writes only to slot i, or to its
/// worker's own tally that the caller merges in an order-free way.
void parallelFor(std::size_t n, int threads,
                 const std::function<void(std::size_t i, std::size_t worker)>& body,
                 WorkerGate* gate = nullptr);

}  // namespace uavip
