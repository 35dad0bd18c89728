#include "uavip/core/parallel.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

namespace uavip {

int hardwareThreads() {
  return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

void WorkerGate::open() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    open_ = true;
  }
  changed_.notify_all();
}

bool WorkerGate::isOpen() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return open_;
}

bool WorkerGate::waitOpen(const std::function<bool()>& done) {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [&] { return open_ || done(); });
  return open_;
}

void WorkerGate::wake() {
  // Under the lock: a waiter between its check of done() and its sleep cannot miss it.
  { const std::lock_guard<std::mutex> lock(mutex_); }
  changed_.notify_all();
}

void parallelFor(std::size_t n, int threads,
                 const std::function<void(std::size_t, std::size_t)>& body, WorkerGate* gate) {
  std::atomic<std::size_t> next{0};
  std::atomic<bool> failed{false};
  std::atomic<bool> caller_done{false};  // every index is taken, or a body threw
  std::exception_ptr error;
  std::mutex error_mutex;
  auto work = [&](std::size_t worker) {
    if (worker > 0 && gate != nullptr && !gate->waitOpen([&] { return caller_done.load(); }))
      return;
    try {
      for (std::size_t i = next++; i < n && !failed.load(std::memory_order_relaxed); i = next++)
        body(i, worker);
    } catch (...) {
      const std::lock_guard<std::mutex> lock(error_mutex);
      if (!error) error = std::current_exception();
      failed = true;
    }
  };
  const std::size_t count =
      std::min<std::size_t>(n, static_cast<std::size_t>(std::max(1, threads)));
  std::vector<std::thread> pool;
  if (count > 1) pool.reserve(count - 1);
  try {
    for (std::size_t t = 1; t < count; ++t) pool.emplace_back(work, t);
  } catch (const std::system_error&) {
    // No more threads: the ones started and the caller share the work.
  }
  work(0);
  caller_done = true;
  if (gate != nullptr && !pool.empty()) gate->wake();  // the workers still waiting leave
  for (auto& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace uavip
