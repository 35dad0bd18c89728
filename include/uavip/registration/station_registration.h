#pragma once
/// \file
/// Stage 2 (paper §II-B): station clouds → one cloud in station 0's frame (= world:
/// origin at the UAV centre at the first scan of station 0, ENU axes).
///
/// Each station's initial pose world_T_station comes from the recorded positions
/// (GPS-like): translation recorded_position_i − recorded_position_0, rotation
/// identity because the station clouds are already in the IMU's world-aligned axes
/// (optionally the recorded yaw instead, for an IMU without a heading reference).
/// Stations are then registered in order, each against the union of the ones
/// already placed: the overlap is predicted from the initial poses (points of the
/// new station inside the placed cloud's bounding box grown by a margin, and
/// placed points inside the new station's box) and ICP runs on the predicted
/// overlap only, down-sampled. Because the rotation is known (IMU) and the recorded
/// positions may be a metre off (GPS), ICP starts from a coarse translation search:
/// the offset within ±search_radius that puts most points into occupied cells of
/// the placed cloud. The default refinement is a translation-only point-to-plane ICP
/// (rotation from the IMU), measured better and faster than PCL's ICP / GICP / NDT on
/// the bridge: normal-space sampling (all upright-surface points, as many level
/// ones), pairs only between normals within 45°, and no motion along a direction
/// that fewer than kMinInformationPairs effective pairs fix — such a direction keeps
/// the recorded position and is reported (StationResult::information). The result
/// is chained to station 0, whose pose is fixed.

#include <Eigen/Geometry>
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "uavip/core/params.h"
#include "uavip/core/raw_log.h"
#include "uavip/core/types.h"

namespace uavip::registration {

/// The registration algorithm (PCL).
enum class Method {
  None,                     ///< keep the initial poses
  PointToPlaneTranslation,  ///< translation only (rotation from the IMU), point-to-plane, Eigen +
                            ///< kd-tree
  Icp,                      ///< pcl::IterativeClosestPoint (point-to-point)
  IcpPointToPlane,          ///< pcl::IterativeClosestPointWithNormals (point-to-plane)
  Gicp,                     ///< pcl::GeneralizedIterativeClosestPoint (plane-to-plane)
  Ndt                       ///< pcl::NormalDistributionsTransform
};

/// "none" | "translation" | "icp" | "icp_point_to_plane" | "gicp" | "ndt"; throws InputError
/// otherwise.
Method methodFromString(const std::string& name);
std::string toString(Method method);

/// A direction fixed by fewer effective point-to-plane pairs than this is not
/// registered (it keeps the start) and is reported as unobserved.
constexpr double kMinInformationPairs = 20.0;

/// Options of stage 2.
struct RegistrationOptions {
  Method method{Method::PointToPlaneTranslation};
  double overlap_margin_m{1.0};  ///< growth of the bounding boxes that predict the overlap [m]
  double search_radius_m{2.0};   ///< coarse translation search around the recorded position, ±this
                                 ///< per axis (0: none) [m]
  double search_step_m{0.2};     ///< its grid step (and occupancy cell) [m]
  double downsample_m{0.15};     ///< voxel edge of the clouds ICP sees [m]
  double max_correspondence_m{1.0};  ///< ICP pairs farther apart are rejected [m]
  int max_iterations{40};
  double ndt_resolution_m{1.0};  ///< NDT cell [m]
  bool use_recorded_yaw{
      false};  ///< rotate each station by recorded_yaw − IMU yaw at its first scan
  double output_voxel_m{
      0.02};  ///< merged cloud down-sampled to this voxel (0: keep every point) [m]
  /// Threads for the stations' down-sampling and normals, the coarse search's offsets
  /// and the ICP's pair searches (the result does not depend on it).
  int threads{2};
  int normal_k{
      10};  ///< neighbours of a point's PCA normal (translation method; its coarse search too)
  int pcl_normal_k{12};  ///< the same for PCL's point-to-plane ICP (icp_point_to_plane)
  /// The last this many placed stations are registration targets with every
  /// down-sampled point; the older ones only with the first point of each
  /// downsample_m voxel, so the target, its memory and its time stay bounded
  /// however many stations a log holds (not a config key).
  int recent_stations{8};

  /// Throws InputError naming the bad field (prefix `where`).
  void validate(const std::string& where = "registration") const;
  /// The keys of `registration:` this struct holds (core/params.h).
  static const params::Table<RegistrationOptions>& table();
};

/// One station's cloud in its own frame and its initial pose in the world.
struct StationInput {
  int id{0};
  PointList points;                                               ///< station frame [m]
  Eigen::Isometry3d initial_pose{Eigen::Isometry3d::Identity()};  ///< world_T_station guess
};

/// What registration did to one station.
struct StationResult {
  int id{0};
  Eigen::Isometry3d initial_pose{Eigen::Isometry3d::Identity()};
  Eigen::Isometry3d pose{Eigen::Isometry3d::Identity()};  ///< world_T_station after ICP
  std::size_t points{0};
  std::size_t overlap_points{
      0};  ///< this station's points in the predicted overlap (after down-sampling)
  double fitness_rms_m{0.0};  ///< RMS pair distance after ICP (pairs within max_correspondence) [m]
  bool converged{false};      ///< ICP converged (station 0 and method None: true)
  int iterations{0};          ///< ICP iterations run (translation method)
  std::size_t pairs{0};       ///< point-to-plane pairs in the last iteration (translation method)
  /// How well the pairs fix each direction (translation method): eigenvalues of
  /// Σ w·n nᵀ over the pairs, ascending, in effective pairs (a pair whose normal lies
  /// along a direction adds 1 to it). Below kMinInformationPairs a direction keeps
  /// the coarse search / recorded position: the scans do not see it.
  Vec3 information{Vec3::Zero()};
  Vec3 weakest_direction{Vec3::Zero()};  ///< unit eigenvector of information(0)
  double time_s{0.0};
};

/// The merged cloud and per-station results.
struct RegistrationResult {
  PointList merged;  ///< world frame [m]
  std::vector<StationResult> stations;
  double time_s{0.0};
};

/// Initial pose of station `index` from the recorded positions (and yaw if asked;
/// imu_yaw_rad is the IMU's heading at the station's first scan) relative to station 0.
Eigen::Isometry3d initialStationPose(const RawLog& log, std::size_t index,
                                     bool use_recorded_yaw = false, double imu_yaw_rad = 0.0,
                                     double imu_yaw0_rad = 0.0);

/// A station's down-sampled cloud (downsample_m) and its PCA normals, in the station
/// frame, oriented toward the station: the part of registration that does not
/// depend on the other stations.
struct PreparedStation {
  PointList downsampled;
  std::vector<Vec3> normals;
  double seconds{0.0};  ///< time it took [s]
};

/// Stage 2 one station at a time: what registerStations does, in memory that does
/// not grow with the number of stations. Each station added is registered against
/// the ones placed before it (the targets: RegistrationOptions::recent_stations) and
/// its full cloud is at once moved to its pose and summed into the merged voxels
/// (output_voxel_m), so the caller may release it. The merged cloud is the one
/// registerStations returns, bit for bit: the same centroids (sums in station
/// order, then point order) in the same voxel key order.
/// prepare() is const and may run on several stations at once; add() and finish()
/// are called from one thread, add() in station order.
class StationMerger {
 public:
  /// Throws InputError for bad options.
  explicit StationMerger(const RegistrationOptions& options);
  ~StationMerger();
  StationMerger(const StationMerger&) = delete;
  StationMerger& operator=(const StationMerger&) = delete;

  /// Station `in`'s down-sampled cloud and normals (empty for a station without points).
  PreparedStation prepare(const StationInput& in) const;
  /// Registers station `in` (the first with points is the reference and keeps its
  /// initial pose) and merges its cloud; `prepared` is prepare(in).
  StationResult add(const StationInput& in, PreparedStation prepared);
  /// Points merged so far (voxels, or points with output_voxel_m = 0).
  std::size_t mergedSize() const;
  /// The merged cloud, world frame; the merger is empty afterwards. Throws
  /// InputError if no station had a point.
  PointList finish();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

/// Registers the stations (the first is the reference, pose = its initial pose)
/// and merges them (StationMerger, each station prepared on options.threads).
/// Stations with no points are kept in the result with converged = false and
/// contribute nothing. Throws InputError if every station is empty.
RegistrationResult registerStations(const std::vector<StationInput>& stations,
                                    const RegistrationOptions& options = {});

}  // namespace uavip::registration
