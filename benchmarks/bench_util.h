#pragma once
// Small helpers shared by the benchmark programs (header-only; not part of the library).

#include <sys/resource.h>

#include <algorithm>
#include <cstddef>
#include <cstdlib>
#include <string>
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

/// A benchmark's command line: `[SCENARIO.yaml] [RUNS]`.
struct BenchArgs {
  std::string scenario;
  int runs{1};
};

/// prepareProcess(), then the command line: the scenario (default `scenario`) and the
/// number of runs (default `runs`, at least 1).
inline BenchArgs startBench(int argc, char** argv, const char* scenario, int runs) {
  prepareProcess();
  BenchArgs args{argc > 1 ? argv[1] : scenario, runs};
  if (argc > 2) args.runs = std::max(1, std::atoi(argv[2]));
  return args;
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
