#include "uavip/core/memory.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>  // defines __GLIBC__ on glibc
#include <fstream>
#include <limits>
#include <string>
#include <thread>

#include "uavip/core/error.h"
#include "uavip/core/text.h"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace uavip {
namespace {

/// The budget set by setMemoryBudget (0: not set).
double g_budget_bytes = 0.0;

/// The first number in a file ("max" or a missing file: 0).
double numberIn(const std::string& path) {
  std::ifstream in(path);
  double v = 0.0;
  return in >> v ? v : 0.0;
}

/// MemAvailable from /proc/meminfo [bytes] (0 if absent).
double memAvailable() {
  std::ifstream in("/proc/meminfo");
  std::string key;
  double kb = 0.0;
  std::string unit;
  while (in >> key >> kb) {
    std::getline(in, unit);
    if (key == "MemAvailable:") return kb * 1024.0;
  }
  return 0.0;
}

}  // namespace

void keepFreedMemoryForReuse() {
#if defined(__GLIBC__)
  // 32 MB: glibc's largest accepted mmap threshold on 64-bit (4 MB · sizeof(long)).
  mallopt(M_MMAP_THRESHOLD, 32 * 1024 * 1024);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);  // trim only above 1 GiB of free heap top
  mallopt(M_ARENA_MAX, static_cast<int>(std::max(1U, std::thread::hardware_concurrency())));
#endif
}

double availableMemoryBytes() {
  double best = memAvailable();
  // A cgroup without a limit reads "max" (v2) or a huge number (v1).
  for (const char* f :
       {"/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"}) {
    const double limit = numberIn(f);
    if (limit > 0.0 && limit < 1e18 && (best <= 0.0 || limit < best)) best = limit;
  }
  return best;
}

double memoryBudgetBytes() {
  if (g_budget_bytes > 0.0) return g_budget_bytes;
  static const double by_default = [] {
    const double available = availableMemoryBytes();
    return available > 0.0 ? 0.8 * available : std::numeric_limits<double>::infinity();
  }();
  return by_default;
}

void setMemoryBudget(double bytes) {
  require(bytes > 0.0 && std::isfinite(bytes), "--max-memory", "must be above 0");
  g_budget_bytes = bytes;
}

std::string formatBytes(double bytes) {
  if (bytes >= 1e9) return formatNumber(bytes / 1e9, 3) + " GB";
  return formatNumber(bytes / 1e6, 3) + " MB";
}

void requireMemory(double bytes, const std::string& what, const std::string& how_to_fix) {
  const double budget = memoryBudgetBytes();
  if (!(bytes > budget)) return;
  throw InputError(what + " needs about " + formatBytes(bytes) +
                   ", more than the memory budget of " + formatBytes(budget) +
                   " (--max-memory; by default 80 % of the available memory): " + how_to_fix +
                   ", or raise --max-memory");
}

double parseMemorySize(const std::string& text, const std::string& option) {
  std::size_t end = 0;
  double v = 0.0;
  try {
    v = std::stod(text, &end);
  } catch (const std::exception&) {
    end = 0;
  }
  std::string unit = text.substr(end);
  for (char& c : unit) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  double scale = 0.0;
  if (unit.empty() || unit == "B") scale = 1.0;
  if (unit == "K" || unit == "KB") scale = 1e3;
  if (unit == "M" || unit == "MB") scale = 1e6;
  if (unit == "G" || unit == "GB") scale = 1e9;
  if (unit == "T" || unit == "TB") scale = 1e12;
  if (unit == "KIB") scale = 1024.0;
  if (unit == "MIB") scale = 1024.0 * 1024.0;
  if (unit == "GIB") scale = 1024.0 * 1024.0 * 1024.0;
  if (end == 0 || scale == 0.0 || !(v > 0.0) || !std::isfinite(v * scale)) {
    throw InputError(option + ": '" + escapeControl(text.substr(0, 40)) +
                     "' is not a memory size; give e.g. 4G, 512M or 1.5GB");
  }
  return v * scale;
}

}  // namespace uavip
