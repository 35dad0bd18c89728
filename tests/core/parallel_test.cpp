#include "uavip/core/parallel.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <new>
#include <numeric>
#include <stdexcept>
#include <thread>
#include <vector>

namespace uavip {
namespace {

TEST(ParallelFor, EveryIndexOnceOnAnyThreadCount) {
  for (const int threads : {1, 2, 4, 16}) {
    std::vector<int> hits(1000, 0);
    parallelFor(hits.size(), threads, [&](std::size_t i, std::size_t) { ++hits[i]; });
    for (std::size_t i = 0; i < hits.size(); ++i)
      ASSERT_EQ(hits[i], 1) << "index " << i << ", threads " << threads;
  }
  int calls = 0;
  parallelFor(0, 4, [&](std::size_t, std::size_t) { ++calls; });
  EXPECT_EQ(calls, 0);
}

TEST(ParallelFor, WorkerIdsAreBelowTheThreadCount) {
  std::vector<std::atomic<int>> per_worker(3);
  parallelFor(500, 3, [&](std::size_t, std::size_t w) {
    ASSERT_LT(w, 3u);
    ++per_worker[w];
  });
  int total = 0;
  for (auto& c : per_worker) total += c;
  EXPECT_EQ(total, 500);
}

// A worker's exception (bad_alloc included) reaches the caller instead of ending
// the process with std::terminate, and the rest of the work stops.
TEST(ParallelFor, AWorkerExceptionIsRethrownInTheCaller) {
  for (const int threads : {1, 2, 4}) {
    std::atomic<std::size_t> done{0};
    EXPECT_THROW(parallelFor(100000, threads,
                             [&](std::size_t i, std::size_t) {
                               if (i == 50) throw std::bad_alloc();
                               ++done;
                             }),
                 std::bad_alloc);
    EXPECT_LT(done.load(), 100000u);
  }
  EXPECT_THROW(parallelFor(10, 2,
                           [](std::size_t i, std::size_t) {
                             if (i == 9) throw std::runtime_error("x");
                           }),
               std::runtime_error);
}

// A closed gate: the caller does every index alone and the waiting workers leave
// when it is done (no hang), on any thread count; a body that throws too.
TEST(WorkerGate, ClosedTheCallerWorksAloneAndTheOthersLeave) {
  for (const int threads : {2, 4}) {
    WorkerGate gate;
    std::vector<int> hits(3000, 0);
    std::vector<std::size_t> by(hits.size(), 99);
    std::atomic<int> by_others{0};
    parallelFor(
        hits.size(), threads,
        [&](std::size_t i, std::size_t w) {
          ++hits[i];
          by[i] = w;
          if (w > 0) ++by_others;
          if (i == 0) {  // time for the others to start: without the gate they would
            const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(300);
            while (by_others.load() == 0 && std::chrono::steady_clock::now() < until)
              std::this_thread::yield();
          }
        },
        &gate);
    for (std::size_t i = 0; i < hits.size(); ++i) {
      ASSERT_EQ(hits[i], 1) << "index " << i;
      ASSERT_EQ(by[i], 0u) << "index " << i << " ran on worker " << by[i];
    }
    EXPECT_FALSE(gate.isOpen());
    EXPECT_THROW(parallelFor(
                     100, threads,
                     [](std::size_t i, std::size_t) {
                       if (i == 5) throw std::runtime_error("x");
                     },
                     &gate),
                 std::runtime_error);
  }
}

// Opened while the caller works (as the flight ends beside the coverage), the other
// workers take the indices left; opened before, the gate changes nothing.
TEST(WorkerGate, OpenedTheOtherWorkersJoin) {
  WorkerGate gate;
  std::vector<std::atomic<int>> hits(2000);
  std::atomic<int> by_others{0};
  parallelFor(
      hits.size(), 2,
      [&](std::size_t i, std::size_t w) {
        ++hits[i];
        if (w > 0) ++by_others;
        if (i == 10) {
          gate.open();
          // Hold the caller until the other worker has taken an index (a bound in
          // case it never does: the assertion below then fails, nothing hangs).
          const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(30);
          while (by_others.load() == 0 && std::chrono::steady_clock::now() < until)
            std::this_thread::yield();
        }
      },
      &gate);
  for (std::size_t i = 0; i < hits.size(); ++i) ASSERT_EQ(hits[i].load(), 1) << "index " << i;
  EXPECT_GT(by_others.load(), 0);
  EXPECT_TRUE(gate.isOpen());

  std::vector<int> again(500, 0);
  parallelFor(
      again.size(), 3, [&](std::size_t i, std::size_t) { ++again[i]; }, &gate);
  for (std::size_t i = 0; i < again.size(); ++i) ASSERT_EQ(again[i], 1) << "index " << i;
}

}  // namespace
}  // namespace uavip
