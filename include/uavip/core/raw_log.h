#pragma once
/// \file
/// The paper's raw data (§II-A): two orthogonal 2D laser scanners (one vertical,
/// one horizontal, mounted symmetrically about the UAV centre) and an IMU, recorded
/// while the UAV yaws 360° at each of several stations. Pure data: produced by
/// sim/ (ray casting) or read from disk by io/, consumed by scan/ and registration/.
///
/// Frames: world = ENU, z up, origin at the UAV centre at the first scan of station 0
/// (paper). Body = UAV centre, x forward, y left, z up. Each scanner frame is given
/// by its mount (body_T_scanner). Vertical scanner beams follow eq. (1):
/// x* = −ρ·cos α, y* = 0, z* = −ρ·sin α. Horizontal scanner beams: x* = ρ·cos α,
/// y* = ρ·sin α, z* = 0.

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "uavip/core/types.h"

namespace uavip {

/// One sweep of a 2D scanner (Hokuyo UTM-30LX: 1081 beams, 0.25°, 270°, 25 ms).
struct LaserScan {
  double t_start_s{0.0};        ///< time of beam 0 [s]
  double duration_s{0.025};     ///< time from beam 0 to the last beam [s]
  double angle_min_rad{0.0};    ///< α of beam 0 in the scanner frame [rad]
  double angle_step_rad{0.0};   ///< α increment per beam [rad]
  std::vector<float> ranges_m;  ///< ρ per beam [m]; 0 = no return
  /// Time of beam i [s] (beams are evenly spaced in time over the sweep).
  double beamTime(std::size_t i) const {
    return ranges_m.size() < 2 ? t_start_s
                               : t_start_s + duration_s * static_cast<double>(i) /
                                                 static_cast<double>(ranges_m.size() - 1);
  }
};

/// One IMU reading (Xsens MTi-10: up to 2 kHz, 0.5° error, no drift).
struct ImuSample {
  double t_s{0.0};
  Eigen::Quaterniond world_q_body{Eigen::Quaterniond::Identity()};  ///< body → world rotation
};

/// A station: the UAV hovers, yaws 360°, both scanners and the IMU record.
struct Station {
  int id{0};
  Vec3 recorded_position{
      Vec3::Zero()};  ///< approximate position (GPS-like) of the UAV centre at the first scan [m]
  double recorded_yaw_rad{0.0};       ///< approximate heading at the first scan [rad]
  std::vector<LaserScan> vertical;    ///< time-ordered
  std::vector<LaserScan> horizontal;  ///< time-ordered
  std::vector<ImuSample> imu;         ///< time-ordered
};

/// A whole raw recording.
struct RawLog {
  Eigen::Isometry3d body_T_vertical{
      Eigen::Isometry3d::Identity()};  ///< mount of the vertical scanner
  Eigen::Isometry3d body_T_horizontal{
      Eigen::Isometry3d::Identity()};  ///< mount of the horizontal scanner
  double max_range_m{30.0};            ///< returns beyond this are invalid
  double min_range_m{0.1};             ///< returns below this are invalid
  std::vector<Station> stations;
};

/// Ground truth of a simulated recording (never read by the pipeline, only to score).
struct RawLogTruth {
  /// True body pose (world_T_body) at every vertical and horizontal scan's start, per station.
  struct StationTruth {
    int id{0};
    std::vector<Eigen::Isometry3d> vertical_poses;
    std::vector<Eigen::Isometry3d> horizontal_poses;
  };
  std::vector<StationTruth> stations;
};

}  // namespace uavip
