#include "uavip/core/memory.h"

#include <gtest/gtest.h>
#include <sys/resource.h>

#include <cstring>
#include <memory>

namespace uavip {
namespace {

long minorFaults() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return ru.ru_minflt;
}

/// Page faults taken by allocating, touching and freeing `bytes`.
long faultsOfOneCloudSizedBuffer(std::size_t bytes) {
  const long before = minorFaults();
  {
    std::unique_ptr<char[]> buffer(new char[bytes]);
    std::memset(buffer.get(), 1, bytes);
    EXPECT_EQ(buffer[bytes - 1], 1);
  }
  return minorFaults() - before;
}

TEST(KeepFreedMemoryForReuse, ASecondCloudSizedBufferTakesNoNewPageFaults) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer replaces the allocator";
#elif !defined(__GLIBC__)
  GTEST_SKIP() << "glibc only";
#else
  keepFreedMemoryForReuse();
  constexpr std::size_t kBytes = 24u << 20;  // 1 M points as (key, index) pairs
  const long pages = static_cast<long>(kBytes / 4096);
  const long first = faultsOfOneCloudSizedBuffer(kBytes);
  const long second = faultsOfOneCloudSizedBuffer(kBytes);
  const long third = faultsOfOneCloudSizedBuffer(kBytes);
  // The first touch faults the pages in (fewer with huge pages); the memory then
  // stays in the process, where by default it would be unmapped and faulted again.
  EXPECT_GT(first, 0);
  EXPECT_LT(second, pages / 20) << "first " << first << " faults";
  EXPECT_LT(third, pages / 20) << "first " << first << " faults";
#endif
}

}  // namespace
}  // namespace uavip
