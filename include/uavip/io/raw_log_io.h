#pragma once
/// \file
/// The raw log directory (docs/raw_log_format.md): what `uavip simulate` writes and
/// `uavip assemble` reads. SCANS/log.json holds the scanner settings, the mounts and
/// one record per station; each station has three CSV files (vertical scans,
/// horizontal scans, IMU samples); SCANS/truth.json (simulated logs only) holds the
/// true poses and the true world, and is read only to score.
///
/// Reading is strict about structure and lenient about ranges: a truncated line, a
/// missing file, timestamps that do not increase, an IMU gap longer than a scan
/// period or a station without scans throws InputError "<file>:<line>: <what>" (one
/// line); a range of 0, negative, non-finite, below min_range_m or beyond
/// max_range_m is a no-return beam and becomes 0.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "uavip/core/raw_log.h"
#include "uavip/sim/world_model.h"

namespace uavip::io {

/// The ground truth of a simulated raw log (SCANS/truth.json), in the log frame.
struct RawLogTruthFile {
  RawLogTruth poses;            ///< true body poses at every scan start
  Vec3 origin_m{Vec3::Zero()};  ///< the log frame's origin in scenario coordinates [m]
  sim::WorldModel world;        ///< the true world, already shifted into the log frame
  std::string scenario;         ///< the scenario file it was simulated from
};

/// What reading found besides the data.
struct RawLogReadStats {
  std::size_t scans{0};      ///< scans read (both scanners, every station)
  std::size_t beams{0};      ///< beams read
  std::size_t no_return{0};  ///< beams that are no-returns (including those below)
  /// Non-zero ranges outside [min_range_m, max_range_m] or non-finite, set to 0.
  std::size_t replaced_ranges{0};
  std::size_t imu_samples{0};  ///< IMU samples read
};

/// File names inside a raw log directory.
std::string rawLogIndexName();  ///< "log.json"
std::string rawLogTruthName();  ///< "truth.json"
std::string rawLogScanFileName(int station_id,
                               bool vertical);  ///< "station_<id>_vertical.csv" / "_horizontal.csv"
std::string rawLogImuFileName(int station_id);  ///< "station_<id>_imu.csv"

/// Writes log.json and the per-station CSV files into `dir` (created if missing),
/// each file atomically. Throws InputError if the log is not writable as documented
/// (duplicate station ids, non-finite values).
void writeRawLog(const std::string& dir, const RawLog& log);

/// Writes truth.json: the poses, the origin, the scenario path and `world` (given in
/// scenario coordinates) shifted by −origin_m into the log frame.
void writeRawLogTruth(const std::string& dir, const RawLogTruth& truth,
                      const sim::WorldModel& world, const Vec3& origin_m,
                      const std::string& scenario);

/// A raw log read one station at a time, so that memory holds one station's scans,
/// not the whole recording: log.json is read and checked when the reader is made,
/// a station's three CSV files when that station is asked for.
class RawLogReader {
 public:
  /// Reads log.json of `dir`. Throws InputError "<file>: <key> ..." like readRawLog.
  explicit RawLogReader(const std::string& dir);
  /// The mounts and ranges, and every station's record (id, recorded position and
  /// yaw) without its scans and IMU samples.
  const RawLog& header() const { return header_; }
  std::size_t stationCount() const { return header_.stations.size(); }
  /// Bytes of station i's three files on disk (0 for a missing one): its text holds
  /// each range in 2-8 characters, so this bounds what reading it allocates.
  std::uintmax_t stationFileBytes(std::size_t i) const;
  /// Station i (0-based, in log.json's order) with its scans and IMU samples; adds to
  /// `stats`. Throws InputError "<file>:<line>: <what>" on bad data.
  Station readStation(std::size_t i, RawLogReadStats& stats) const;

 private:
  struct StationFiles {
    std::string vertical, horizontal, imu;
  };
  RawLog header_;
  std::vector<StationFiles> files_;
};

/// Reads a whole raw log directory (RawLogReader, every station). Throws InputError
/// "<file>:<line>: <what>" on bad data.
RawLog readRawLog(const std::string& dir, RawLogReadStats* stats = nullptr);

/// Reads truth.json when present (std::nullopt if the file does not exist).
std::optional<RawLogTruthFile> readRawLogTruth(const std::string& dir);

}  // namespace uavip::io
