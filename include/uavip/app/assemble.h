#pragma once
/// \file
/// Stages 1–2 as one call (paper §II-A, §II-B): a raw log → each station's cloud
/// (scan/) → registered and merged (registration/), with the numbers of
/// `cloud.report.json`: per station drift, loop closure and pose, and, when the
/// ground truth is given, the errors against it. `uavip assemble`, `uavip run` on a
/// scenario with sensing mode `scan`, and the bridge benchmark call this; nothing
/// here prints.

#include <Eigen/Geometry>
#include <cstddef>
#include <functional>
#include <optional>
#include <vector>

#include "uavip/app/pipeline.h"
#include "uavip/core/raw_log.h"
#include "uavip/registration/station_registration.h"
#include "uavip/scan/station_assembler.h"
#include "uavip/sim/world_model.h"

namespace uavip::app {

/// Options of stages 1–2.
struct AssembleOptions {
  scan::AssemblerOptions scan;
  registration::RegistrationOptions registration;
  int threads{2};  ///< stations assembled in parallel (stage 1 is independent per station)
};

/// What stages 1–2 did at one station (cloud.report.json, `stations[]`).
struct StationReport {
  int id{0};
  std::size_t points{0};         ///< points of the station cloud
  std::size_t invalid_beams{0};  ///< vertical beams skipped (no return, out of range)
  std::size_t keyframes{0};
  double mean_icp_iterations{0.0};
  /// First vs last horizontal scan (paper: 10 cm); −1 if < 2 scans or unobservable.
  double loop_closure_m{-1.0};
  double drift_final_m{0.0};  ///< estimated UAV displacement at the last scan (wind) [m]
  double drift_max_m{0.0};    ///< largest estimated displacement during the turn [m]
  Eigen::Isometry3d initial_pose{Eigen::Isometry3d::Identity()};  ///< from the recorded position
  Eigen::Isometry3d pose{Eigen::Isometry3d::Identity()};          ///< after registration
  bool registered{false};          ///< registration converged (station 0: true)
  double registration_rms_m{0.0};  ///< ICP pair RMS [m]
  /// Stage 2's information per direction (registration::StationResult::information):
  /// effective point-to-plane pairs, ascending, and the weakest direction.
  Vec3 registration_information{Vec3::Zero()};
  Vec3 weakest_direction{Vec3::Zero()};
  /// False when some direction had < registration::kMinInformationPairs pairs: the
  /// station's position along weakest_direction is the recorded one (GPS), not the scans'.
  bool position_observed{true};
  double assembly_s{0.0};
  double registration_s{0.0};
  // With the ground truth:
  std::optional<double>
      drift_error_max_m;  ///< max |estimated − true displacement| over the turn [m]
  std::optional<double> drift_error_rms_m;     ///< RMS of the same [m]
  std::optional<double> true_drift_max_m;      ///< largest true displacement during the turn [m]
  std::optional<double> initial_pose_error_m;  ///< |recorded − true station position| [m]
  std::optional<double> pose_error_m;          ///< |registered − true station position| [m]
  std::optional<double> pose_error_deg;        ///< rotation error of the registered station [deg]
};

/// The merged cloud and the report.
struct AssembleResult {
  PointList cloud;  ///< merged, in the log frame (station 0) [m]
  std::vector<StationReport> stations;
  std::size_t station_points{0};  ///< points of all station clouds before merging
  double assembly_s{0.0};         ///< stage 1 wall time [s]
  double registration_s{0.0};     ///< stage 2 wall time [s]
  double total_s{0.0};
  std::optional<double>
      rms_to_truth_m;  ///< RMS distance of the merged cloud to the true surfaces [m]
  std::optional<double> p95_to_truth_m;  ///< 95th percentile of the same [m]
  std::size_t scored_points{0};          ///< points used for the two above (an even subsample)
};

/// The stations of a raw log, handed to assemble one at a time so that memory holds
/// a few stations' scans, not the recording (io::RawLogReader reads each from disk).
struct StationSource {
  /// The mounts and ranges, and every station's record (id, recorded position and
  /// yaw); its stations need no scans or IMU samples.
  RawLog header;
  /// Station i with its scans and IMU samples; called once per station, from
  /// options.threads threads at once (it must be thread-safe).
  std::function<Station(std::size_t)> read;
  /// Each station's bytes on disk (empty: unknown), for the memory estimate.
  std::vector<double> file_bytes;
};

/// Runs stages 1–2 on the stations of `source`, options.threads × 2 at a time:
/// each is read, assembled (stage 1), registered against the ones before it and
/// merged into the cloud (registration::StationMerger), then released, so memory
/// grows with the merged cloud, not with the number of stations. Before each
/// batch, refuses (requireMemory) when its stations' estimated memory exceeds the
/// budget. `truth` (true poses) and `world` (the true surfaces in the log
/// frame) are optional and only score. Throws InputError for bad raw data (see
/// scan::assembleStation) or when no station has any point.
AssembleResult assemble(const StationSource& source, const AssembleOptions& options = {},
                        const RawLogTruth* truth = nullptr, const sim::WorldModel* world = nullptr,
                        const Progress& progress = {});

/// The same on a raw log held in memory.
AssembleResult assemble(const RawLog& log, const AssembleOptions& options = {},
                        const RawLogTruth* truth = nullptr, const sim::WorldModel* world = nullptr,
                        const Progress& progress = {});

/// Sensing mode `scan` for `uavip run`: simulate the scenario's raw scans
/// (sim::simulateScans), assemble them, and return the merged cloud shifted back
/// into scenario coordinates, with the scenario's `assembly:` and `registration:`
/// options (app::Config). The report is scored against the scenario's world.
AssembleResult senseScans(const app::Scenario& scenario, const Progress& progress = {});

}  // namespace uavip::app
