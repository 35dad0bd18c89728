#include "uavip/core/parallel.h"

#include <gtest/gtest.h>

#include <atomic>
#include <new>
#include <numeric>
#include <stdexcept>
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

}  // namespace
}  // namespace uavip
