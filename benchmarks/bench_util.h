#pragma once
// Small helpers shared by the benchmark programs (header-only; not part of the library).

#include <sys/resource.h>

#include <algorithm>
#include <cstddef>
#include <vector>

#include "uavip/core/memory.h"
#include "uavip/io/cloud_io.h"

namespace uavip::bench_util {

/// What every benchmark does first: keep freed memory for reuse (core/memory.h:
/// page faults, not work, were 0.3 s of stages 1-2) and silence PCL's console (its
/// warnings, e.g. a failing ICP variant, would bury the tables).
inline void prepareProcess() {
  keepFreedMemoryForReuse();
  io::setPclConsole(false);
}

/// Median of the values (the mean of the middle two for an even count; 0 if empty).
inline double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// Peak resident memory of this process so far [MiB] (ru_maxrss is in KiB on Linux).
inline double peakRssMiB() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return static_cast<double>(ru.ru_maxrss) / 1024.0;
}

}  // namespace uavip::bench_util
