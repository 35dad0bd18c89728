// libFuzzer target: the raw scan log reader (io/raw_log_io.h readRawLog), which
// reads a folder. The input is split on "@@@@" into up to four files written into
// a per-process folder: log.json, station_0_vertical.csv, station_0_horizontal.csv
// and station_0_imu.csv (a missing part is a missing file; log.json may name any of
// them, or other names). The reader may refuse the folder with InputError; anything
// else (a crash, a sanitizer report, another exception, a leak) is a finding, and so
// is an accepted log that breaks what the header promises (a station without scans
// or IMU samples, a range that is negative or non-finite, times that do not
// increase, stats that do not match the data). scripts/fuzz.sh.

#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "uavip/core/error.h"
#include "uavip/io/raw_log_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace fs = std::filesystem;
  static const std::string dir = "/tmp/uavip_fuzz_rawlog_" + std::to_string(::getpid());
  static const std::string kNames[] = {
      uavip::io::rawLogIndexName(), uavip::io::rawLogScanFileName(0, true),
      uavip::io::rawLogScanFileName(0, false), uavip::io::rawLogImuFileName(0)};
  constexpr std::string_view kSeparator = "@@@@";
  // New files every time (removed at the end): rewriting a file in place is slow on
  // ext4 (it flushes the old data first), and a part that is missing must be missing.
  static const bool made = fs::create_directories(dir);
  (void)made;
  std::string_view rest(reinterpret_cast<const char*>(data), size);
  for (std::size_t i = 0; i < 4 && rest.data() != nullptr; ++i) {
    const std::size_t end = i < 3 ? rest.find(kSeparator) : std::string_view::npos;
    const std::string_view part = rest.substr(0, end);
    {
      std::ofstream out(dir + "/" + kNames[i], std::ios::binary);
      out.write(part.data(), static_cast<std::streamsize>(part.size()));
    }
    rest =
        end == std::string_view::npos ? std::string_view() : rest.substr(end + kSeparator.size());
  }
  try {
    uavip::io::RawLogReadStats stats;
    const uavip::RawLog log = uavip::io::readRawLog(dir, &stats);
    std::size_t scans = 0, beams = 0, imu = 0;
    for (const auto& st : log.stations) {
      if (st.vertical.empty() || st.horizontal.empty() || st.imu.empty()) __builtin_trap();
      for (const auto* list : {&st.vertical, &st.horizontal}) {
        for (std::size_t k = 0; k < list->size(); ++k) {
          const auto& s = (*list)[k];
          if (k > 0 && !(s.t_start_s > (*list)[k - 1].t_start_s)) __builtin_trap();
          for (const float r : s.ranges_m) {
            if (!std::isfinite(r) || r < 0.0f) __builtin_trap();
          }
          ++scans;
          beams += s.ranges_m.size();
        }
      }
      for (std::size_t k = 1; k < st.imu.size(); ++k) {
        if (!(st.imu[k].t_s > st.imu[k - 1].t_s)) __builtin_trap();
      }
      imu += st.imu.size();
    }
    if (log.stations.empty() || stats.scans != scans || stats.beams != beams ||
        stats.imu_samples != imu) {
      __builtin_trap();
    }
  } catch (const uavip::InputError&) {
  }
  for (const auto& name : kNames) fs::remove(dir + "/" + name);
  return 0;
}
