#pragma once
/// \file
/// Sensing mode `scan` (paper §II-A, §III): the two orthogonal 2D laser scanners
/// and the IMU of the paper's UAV, simulated by ray casting a WorldModel while the
/// UAV yaws 360° at each station and the wind pushes it. Produces the RawLog that
/// stages 1–2 (scan/, registration/) assemble, and the RawLogTruth that scores them.
///
/// What the rays see: rectangles exactly (so boxes, trees and grass, which are made
/// of rectangles); segments as capsules and points as spheres of radius
/// thin_radius_m (0 makes them invisible). Nothing else: the UAV body is not modelled.
///
/// Motion of one station (all seeded): yaw(t) = start_yaw + yaw_rate·t; the body
/// position is the station plus a wind offset, a bounded random walk (a step of σ
/// wind_step_m per axis every scanner period, each axis clamped to ±wind_bound_m,
/// linear between ticks, 0 at the first scan); roll and pitch follow the same kind of
/// walk (tilt_step_deg, tilt_bound_deg). world_R_body = Rz(yaw)·Ry(pitch)·Rx(roll).
///
/// Frames (core/raw_log.h): the log's world frame is the scenario frame shifted so
/// that its origin is the UAV centre at the first scan of station 0
/// (SimulatedLog::origin_m is that point in scenario coordinates); axes unchanged.

#include <Eigen/Geometry>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "uavip/core/raw_log.h"
#include "uavip/core/types.h"
#include "uavip/sim/world_model.h"

namespace uavip::sim {

/// A 2D laser scanner (paper §III: Hokuyo UTM-30LX).
struct ScannerModel {
  double max_range_m{30.0};    ///< farther surfaces give no return [m]
  double min_range_m{0.1};     ///< nearer surfaces give no return [m]
  double fov_deg{270.0};       ///< field of view, centred on α = 0 [deg]
  double step_deg{0.25};       ///< angular resolution [deg]
  double period_s{0.025};      ///< time between scan starts (one mirror turn) [s]
  double range_noise_m{0.02};  ///< σ of the Gaussian range noise [m]

  /// Beams per scan: round(fov / step) + 1 (1081 for the UTM-30LX).
  int beamCount() const;
  /// α of beam 0: −fov/2 [rad].
  double angleMinRad() const;
  /// α increment per beam [rad].
  double angleStepRad() const;
  /// Time from beam 0 to the last beam: period × fov / 360° (18.75 ms) [s].
  double sweepDurationS() const;
  /// Throws InputError naming the bad field (prefix `where`).
  void validate(const std::string& where = "scanner") const;
};

/// Options of the raw two-scanner + IMU simulation (scenarios/README.md, `sensing: {mode: scan}`).
struct ScanSimOptions {
  std::vector<Vec3> stations;  ///< true UAV centre at each station's first scan, scenario frame [m]
  double start_yaw_deg{
      0.0};  ///< heading (body +x from world +x, CCW) at each station's first scan [deg]
  double yaw_rate_deg_s{30.0};  ///< yaw rate; the turn takes turn_deg / yaw_rate [deg/s]
  double turn_deg{360.0};       ///< yaw swept per station (paper: 360°) [deg]
  /// Most range readings of the whole recording (stations × scans × 2 scanners ×
  /// beams): bounds time and memory before anything is simulated (the bridge takes
  /// 4.2 M; 20 M take about 1 GB) [readings].
  double max_readings{20e6};
  ScannerModel scanner;                     ///< both scanners are the same model
  Vec3 vertical_mount_m{-0.15, 0.0, 0.0};   ///< vertical scanner centre in the body frame [m]
  Vec3 horizontal_mount_m{0.15, 0.0, 0.0};  ///< horizontal scanner centre in the body frame [m]
  Vec3 vertical_mount_rpy_deg{
      0.0, 0.0, 0.0};  ///< vertical scanner orientation (roll, pitch, yaw about body x, y, z) [deg]
  Vec3 horizontal_mount_rpy_deg{0.0, 0.0, 0.0};  ///< horizontal scanner orientation [deg]
  double horizontal_time_offset_s{
      0.0125};                ///< horizontal scans start this much after the vertical ones [s]
  double imu_rate_hz{400.0};  ///< IMU sample rate (MTi-10: up to 2000) [Hz]
  double imu_error_deg{
      0.5};  ///< each sample is rotated by a random axis and an angle uniform in [0, this] [deg]
  double wind_step_m{0.003};   ///< σ per axis of the wind walk step per scanner period [m]
  double wind_bound_m{0.2};    ///< the wind offset stays within ±this per axis [m]
  double tilt_step_deg{0.05};  ///< σ of the roll/pitch walk step per scanner period [deg]
  double tilt_bound_deg{1.0};  ///< roll and pitch stay within ±this [deg]
  double gps_sigma_m{
      0.5};  ///< σ per axis of the recorded station position error (not station 0) [m]
  double thin_radius_m{
      0.02};          ///< radius of segments (capsules) and points (spheres) seen by rays [m]
  bool deskew{true};  ///< each beam is cast from the pose at its own time (else the scan start's)
  double station_gap_s{
      10.0};              ///< time between the end of one station and the start of the next [s]
  std::uint32_t seed{1};  ///< seed of every random draw

  /// Mount transforms (body_T_scanner) from the offsets and angles.
  Eigen::Isometry3d bodyTVertical() const;
  Eigen::Isometry3d bodyTHorizontal() const;
  /// Scans per scanner per station: ⌊turn / (yaw_rate · period)⌋ + 1 (481 at 30°/s),
  /// so the last scan starts after the full turn.
  int scansPerStation() const;
  /// Throws InputError naming the bad field (prefix `where`).
  void validate(const std::string& where = "sensing") const;
};

/// A simulated recording.
struct SimulatedLog {
  RawLog log;                   ///< what the pipeline reads
  RawLogTruth truth;            ///< true body poses at every scan start (log frame)
  Vec3 origin_m{Vec3::Zero()};  ///< the log frame's origin in scenario coordinates [m]
  std::size_t rays{0};          ///< rays cast
  std::size_t returns{0};       ///< beams with a valid range
};

/// Exact ray–rectangle intersection: the distance t > 0 along the unit direction
/// `dir` from `origin` to the closed rectangle, or +inf (miss, parallel, behind).
double intersectRayRect(const Vec3& origin, const Vec3& dir, const Rect& rect);

/// First-hit ray casting against a WorldModel through a bounding-volume hierarchy.
/// Built once; `cast` is const and thread-safe. Borrows nothing from the world.
class RayCaster {
 public:
  /// Segments become capsules and points spheres of radius thin_radius_m (0: invisible).
  explicit RayCaster(const WorldModel& world, double thin_radius_m = 0.02);
  /// Distance to the first hit along the unit direction in (0, max_range_m], or +inf.
  double cast(const Vec3& origin, const Vec3& dir,
              double max_range_m = std::numeric_limits<double>::infinity()) const;
  /// Number of shapes (rectangles, capsules, spheres).
  std::size_t shapeCount() const { return kinds_.size(); }

 private:
  enum class Kind : std::uint8_t { Rect, Capsule, Sphere };
  struct Node {
    Eigen::Vector3d lo{Eigen::Vector3d::Zero()};
    Eigen::Vector3d hi{Eigen::Vector3d::Zero()};
    int first{0};  ///< leaf: first shape index; inner: left child index
    int count{0};  ///< leaf: number of shapes; inner: 0
    int right{0};  ///< inner: right child index
  };
  double hitShape(int i, const Vec3& o, const Vec3& d, double best) const;
  int build(std::vector<int>& order, int begin, int end, const std::vector<Eigen::Vector3d>& lo,
            const std::vector<Eigen::Vector3d>& hi);

  std::vector<Kind> kinds_;
  // Per shape: Rect: a = corner, b = edge_u / |edge_u|², c = edge_v / |edge_v|², n = unit normal.
  // Capsule: a, b = ends. Sphere: a = centre.
  std::vector<Eigen::Vector3d> a_, b_, c_, n_;
  double radius_{0.0};
  std::vector<Node> nodes_;
};

/// Progress messages (one per station).
using SimProgress = std::function<void(const std::string&)>;

/// Simulates every station (ScanSimOptions::validate first). Deterministic for the
/// same world and options. Station k starts at t = k · (turn time + one period +
/// station_gap_s); every station's IMU covers its scans. Station 0's recorded
/// position is exactly 0 (it defines the origin); the others are true + N(0, gps_sigma_m).
SimulatedLog simulateScans(const WorldModel& world, const ScanSimOptions& options,
                           const SimProgress& progress = {});

}  // namespace uavip::sim
