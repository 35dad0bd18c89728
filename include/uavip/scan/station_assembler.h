#pragma once
/// \file
/// Stage 1 (paper §II-A): one station's raw scans → one 3D cloud.
///
/// Each vertical-scanner beam (ρ, α) at time t becomes, by eq. (1),
///   x* = −ρ·cos α, y* = 0, z* = −ρ·sin α          (vertical scanner frame)
///   x  = R(t)·(body_R_v·x* + body_t_v) + T(t)       (station frame)
/// where body_T_vertical = (body_R_v, body_t_v) is the scanner mount, R(t) the IMU
/// attitude world_q_body slerp-interpolated at the beam's own time (deskewing within
/// the 25 ms sweep) and T(t) the UAV centre's translation since the station's first
/// horizontal scan, interpolated linearly between the horizontal scans' poses.
///
/// T comes first from ICP between horizontal scans (the odometry). With the paper's
/// customisation (use_imu_prior, the default) each horizontal beam is first rotated
/// by the IMU attitude at its time, which levels and de-yaws the scan: consecutive
/// scans then differ only by the (small) wind translation, and a 2D ICP finds it,
/// plus a small residual yaw that absorbs the IMU error. Without the prior ("plain
/// ICP") the ICP has to find the yaw as well, from the scans alone, and accumulates
/// its error. Scans are matched against a keyframe (not the previous scan) so that
/// drift grows with keyframes, not scans. The odometry has no vertical component;
/// optionally (estimate_z) the vertical drift is found from the vertical scanner's
/// near-nadir/near-zenith beams (ground, deck underside).
///
/// The odometry sees only what lies in the horizontal scanner's plane: under a
/// bridge deck that can be one wall direction, or nothing at all in the first
/// keyframe. With refine_drift (the default) every beam of the sweep, from both
/// scanners, then joins one estimate of T (drift_refinement.h): the vertical scans see
/// the deck underside, the piers and the ground all around, so that drift is
/// corrected in every direction some surface fixes, and the loop closure is measured
/// in 3D.
///
/// Station frame: origin at the UAV centre at the station's first horizontal scan,
/// axes those of the IMU's reference (world ENU, gravity-aligned).
/// Invalid ranges (0, < min_range, > max_range, NaN, inf) are skipped and counted.

#include <Eigen/Geometry>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "uavip/core/params.h"
#include "uavip/core/raw_log.h"
#include "uavip/core/types.h"
#include "uavip/scan/drift_refinement.h"

namespace uavip::scan {

/// The ICP used between horizontal scans.
enum class IcpMethod {
  PointToLine2D,   ///< Gauss–Newton point-to-line on (x, y, yaw), Eigen (default)
  PclPointToPoint  ///< pcl::IterativeClosestPoint with a 2D transformation estimate
};

/// "point_to_line" | "pcl"; throws InputError for another name.
IcpMethod icpMethodFromString(const std::string& name);
std::string toString(IcpMethod method);

/// uavip's own tuning of stage 1 beyond the paper (which gives none of these); the
/// defaults were measured on the simulated Hokuyo UTM-30LX + Xsens MTi-10 sweeps.
/// Not read from YAML: change them in code, with a measurement.
struct AssemblerTuning {
  /// Line normals of a horizontal scan: a point's line is fitted (PCA) to its
  /// beam-order neighbours ± line_half_window that lie within line_reach_m +
  /// line_reach_per_m × range of it, and is a line when the smaller eigenvalue is
  /// below line_ratio × the larger.
  int line_half_window{8};
  double line_reach_m{0.2};       ///< [m]
  double line_reach_per_m{0.02};  ///< [m per m of range]
  double line_ratio{0.1};
  /// Point-to-line ICP: Huber scale for the first huber_steps steps (the guess may be
  /// centimetres off), then Tukey: pairs across an occlusion edge or a corner get no
  /// weight [m].
  double huber_m{0.05};
  double tukey_m{0.1};
  int huber_steps{3};
  double normal_cos{0.94};      ///< pairs need normals within acos(this) of each other (20°)
  std::size_t min_pairs{30};    ///< fewer pairs: the scan keeps the previous pose
  double prior_weight{1e-3};    ///< weight of the prior toward the guess, per pair
  double typical_range_m{5.0};  ///< scales yaw against translation in the degeneracy test [m]
  /// Directions whose (range-scaled) eigenvalue is below this fraction of the largest
  /// are not updated by an ICP step (e.g. only one flat face in view).
  double degenerate_fraction{0.02};
  double map_spacing_m{
      0.03};  ///< keyframe points join the reference map only this far from its points [m]
  double min_loop_information{
      10.0};  ///< effective pairs the least constrained direction needs for a loop-closure figure
  /// Drift refinement points: every drift_beam_stride-th beam of every vertical scan
  /// and of every drift_horizontal_scan_stride-th horizontal scan (~10⁵ per station).
  std::size_t drift_beam_stride{4};
  std::size_t drift_horizontal_scan_stride{2};
  /// Position noise of a beam: range noise [m] and attitude error [rad] (Hokuyo
  /// UTM-30LX: 1–3 cm; Xsens MTi-10: 0.5°, here about its mean).
  double beam_range_sigma_m{0.015};
  double beam_angle_sigma_rad{0.005};
  double odometry_smoothing{
      0.25};  ///< before the refinement, xy is averaged over ± this fraction of a segment
  double loop_window_deg{
      30.0};  ///< the loop closure's end window: the last this much of the sweep's yaw [deg]
  double max_drift_segments{
      120.0};  ///< at most this many refinement segments (dense normal equations: 3 per node)
  DriftTuning drift;  ///< the refinement's own (drift_refinement.h)

  /// Throws InputError naming the bad field (prefix `where`).
  void validate(const std::string& where) const;
};

/// Options of stage 1.
struct AssemblerOptions {
  bool use_imu_prior{true};  ///< rotate horizontal scans by the IMU before ICP (paper)
  IcpMethod icp{IcpMethod::PointToLine2D};
  int max_iterations{30};            ///< ICP iterations per scan pair
  double max_correspondence_m{0.5};  ///< pairs farther apart are ignored [m]
  double convergence_m{1e-4};     ///< stop when an ICP step moves less than this [m] (and 1e-5 rad)
  double keyframe_yaw_deg{15.0};  ///< new keyframe after this much yaw since the last one [deg]
  double keyframe_translation_m{0.2};  ///< … or this much translation [m]
  int horizontal_stride{1};            ///< use every n-th horizontal beam in ICP
  double imu_smoothing_s{0.0};  ///< > 0: local-linear fit of the IMU attitude over this window [s]
  double max_imu_gap_s{0.025};  ///< an IMU gap longer than this (one scan) is an error [s]
  bool estimate_z{true};        ///< vertical drift from the vertical scanner's nadir/zenith beams
  double z_cone_deg{20.0};  ///< beams within this angle of straight down/up are used for z [deg]
  bool include_horizontal{
      false};               ///< also put the horizontal scanner's points in the cloud (paper: no)
  bool refine_drift{true};  ///< all beams of the sweep join the drift estimate (drift_refinement.h)
  double drift_segment_deg{12.0};  ///< refinement node spacing: this much yaw, in (0, 360] [deg]
  int drift_iterations{3};    ///< refinement steps (voxels and normals rebuilt between them), >= 1
  double drift_voxel_m{0.5};  ///< refinement voxel and column edge, > 0 [m]
  AssemblerTuning tuning;     ///< uavip's own tuning (above)

  /// Throws InputError naming the bad field (prefix `where`).
  void validate(const std::string& where = "scan") const;
  /// The keys of `assembly:` this struct holds (core/params.h).
  static const params::Table<AssemblerOptions>& table();
};

/// Counts and timings of one station's assembly.
struct AssemblyStats {
  std::size_t vertical_scans{0};
  std::size_t horizontal_scans{0};
  std::size_t beams{0};          ///< vertical beams seen
  std::size_t invalid_beams{0};  ///< skipped: 0, NaN, < min_range, > max_range
  std::size_t keyframes{0};
  std::size_t failed_icp{
      0};  ///< scans with too few ICP pairs or no convergence (they keep the previous pose)
  double mean_icp_iterations{0.0};
  double mean_icp_rms_m{0.0};  ///< mean point-to-line (or point) residual after ICP [m]
  double icp_s{0.0};           ///< wall time of the horizontal ICP [s]
  double points_s{0.0};  ///< wall time of the z drift and of eq. (1) on all vertical beams [s]
  double refine_s{0.0};  ///< wall time of the drift refinement [s]
  std::size_t drift_segments{0};  ///< refinement segments (0: not refined)
  std::size_t drift_planes{0};    ///< voxel planes of the refinement's last step
};

/// One station's cloud and trajectory.
struct StationCloud {
  int station_id{0};
  PointList points;                  ///< station frame [m]
  std::vector<double> pose_times_s;  ///< mid time of each horizontal scan [s]
  std::vector<Eigen::Isometry3d>
      poses;  ///< station_T_body at each horizontal scan (IMU R; T: odometry, refined)
  /// Loop closure (paper §III: 10 cm) [m]: the length of the translation that would
  /// bring the end of the sweep onto its start, each placed with its estimated T.
  /// With refine_drift: the beams of the last 30° of yaw, both scanners, moved alone
  /// onto the planes the rest of the sweep saw (3D, point-to-plane; drift_refinement.h).
  /// Without: the last horizontal scan ICP'd onto the first (2D). −1 if < 2 scans or
  /// if some direction is not fixed (fewer than 10 effective pairs along it: in 3D,
  /// e.g. a floor and one wall; in 2D, one flat face in view).
  double loop_closure_m{-1.0};
  /// Effective pairs fixing the least constrained direction of that fit (3D: counted
  /// at the scanners' full resolution, weighted by their noise).
  double loop_closure_information{0.0};
  AssemblyStats stats;
};

/// Eq. (1): the vertical scanner's beam (ρ [m], and cos α, sin α) in its own frame.
inline Vec3 verticalBeam(double range_m, double cos_a, double sin_a) {
  return {-range_m * cos_a, 0.0, -range_m * sin_a};
}

/// The same from α [rad].
inline Vec3 verticalBeam(double range_m, double angle_rad) {
  return verticalBeam(range_m, std::cos(angle_rad), std::sin(angle_rad));
}

/// The horizontal scanner's beam in its own frame: (ρ·cos α, ρ·sin α, 0).
inline Vec3 horizontalBeam(double range_m, double cos_a, double sin_a) {
  return {range_m * cos_a, range_m * sin_a, 0.0};
}

/// The same from α [rad].
inline Vec3 horizontalBeam(double range_m, double angle_rad) {
  return horizontalBeam(range_m, std::cos(angle_rad), std::sin(angle_rad));
}

/// True for a usable return: finite, > 0, within [min_range, max_range].
inline bool validRange(float range_m, double min_range_m, double max_range_m) {
  return std::isfinite(range_m) && range_m > 0.0f && range_m >= min_range_m &&
         range_m <= max_range_m;
}

/// Eq. (2) for one vertical beam: world_T_body · body_T_vertical · x*.
inline Vec3 verticalBeamToFrame(double range_m, double angle_rad,
                                const Eigen::Isometry3d& body_T_vertical,
                                const Eigen::Isometry3d& frame_T_body) {
  return frame_T_body * (body_T_vertical * verticalBeam(range_m, angle_rad));
}

/// The IMU attitude over time: slerp between samples, clamped at the ends.
class ImuTrack {
 public:
  /// Throws InputError ("<where>: ...") if samples is empty, times go backwards or
  /// two samples are more than max_gap_s apart. smoothing_s > 0 replaces each
  /// sample by a local-linear fit of the attitude over that window (white IMU noise).
  ImuTrack(const std::vector<ImuSample>& samples, double max_gap_s, double smoothing_s,
           const std::string& where);
  /// Attitude world_q_body at time t [s].
  Eigen::Quaterniond at(double t_s) const;
  double startTime() const { return t_.front(); }
  double endTime() const { return t_.back(); }

 private:
  /// Slerp terms of the interval [t_i, t_i+1]: q_i·q_i+1, its angle and sine.
  struct Slerp {
    double dot{1.0};
    double theta{0.0};
    double sin_theta{0.0};
  };
  std::vector<double> t_;
  std::vector<Eigen::Quaterniond> q_;
  std::vector<Slerp> slerp_;
};

/// Yaw (rotation about world z) of an attitude [rad], in (−π, π].
double yawOf(const Eigen::Quaterniond& q);

/// Assembles station `index` of `log`. A station without vertical scans gives an
/// empty cloud; without horizontal scans, T has only the vertical drift (and the
/// refinement's correction, from the vertical scans alone). Throws InputError for
/// a station without IMU samples, an IMU gap longer than max_imu_gap_s, or scans
/// outside the IMU's time span.
StationCloud assembleStation(const RawLog& log, std::size_t index,
                             const AssemblerOptions& options = {});

/// The first half of assembleStation: the horizontal odometry (ICP, §II-A's T in
/// xy) of station `index`, which the second half takes up. Split so that a caller
/// with several stations can spread each half over its threads: one station's ICP
/// is often most of the work.
struct StationOdometry {
  std::size_t index{0};                ///< the station in the log
  bool empty{false};                   ///< no scans at all: an empty cloud follows
  std::vector<double> theta;           ///< per horizontal scan: residual yaw [rad]
  std::vector<Eigen::Vector2d> trans;  ///< per horizontal scan: xy in the station frame [m]
  double loop_closure_m{-1.0};         ///< the 2D loop closure (−1: none measured) [m]
  double loop_closure_information{0.0};
  AssemblyStats stats;  ///< scan counts, keyframes, ICP figures and icp_s so far
};

/// The first half (same checks and errors as assembleStation).
StationOdometry stationOdometry(const RawLog& log, std::size_t index,
                                const AssemblerOptions& options = {});
/// The second half: z drift, refinement and eq. (1) on the beams, from `odometry`
/// (of this log and options). assembleStation(log, i, o) equals
/// assembleStation(log, o, stationOdometry(log, i, o)).
StationCloud assembleStation(const RawLog& log, const AssemblerOptions& options,
                             const StationOdometry& odometry);

}  // namespace uavip::scan
