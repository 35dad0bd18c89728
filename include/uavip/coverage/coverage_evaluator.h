#pragma once
/// \file
/// Coverage evaluation: what share of a surface's points some photo really images
/// (the check behind paper §II-F's "every part of the surface is photographed").
///
/// A point p_i with outward normal n_i is imaged by a view (camera at c, frame
/// forward/right/up) when all of these hold:
///  1. range r = |p_i − c| ≤ R, R = CoverageCriteria::max_range_m, or the camera
///     model's maxRange(max_gsd) when that is 0;
///  2. incidence: angle(n_i, c − p_i) ≤ max_incidence_deg;
///  3. the camera model projects p_i inside its image (CameraModel::project);
///  4. GSD at p_i ≤ max_gsd_mm_per_px (when > 0), GSD = r·1000 / focal_px;
///  5. the line of sight c → p_i is clear (when a LineOfSight is given).
/// Tests 1–4 are cheap and run first; only points within R of a camera are visited
/// (the points are bucketed in a uniform grid of cell R, stored cell by cell).
///
/// Camera frame (2-DOF mount, no roll; the conventions of flight_strategy.cpp):
/// yaw y counter-clockwise from +x (east), gimbal pitch p up positive (−90 = straight
/// down), world ENU metres with z up:
///   forward f = (cos p·cos y, cos p·sin y, sin p),
///   right   r = (sin y, −cos y, 0)   (image width axis, horizontal),
///   up      u = r × f                (image height axis, "up" in the photo).
/// Camera coordinates of a world point q: x = r·(q − c) (right), y = −u·(q − c)
/// (down, as in OpenCV), z = f·(q − c) (depth). With this, a flight-strategy Stop
/// (yaw_deg, gimbal_pitch_deg) images its footprint with the width along axis_w and
/// the height along axis_h.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "uavip/core/math.h"
#include "uavip/core/types.h"
#include "uavip/coverage/camera.h"

namespace uavip {
class WorkerGate;  // core/parallel.h
}  // namespace uavip

namespace uavip::coverage {

/// A camera pose: position [m], yaw [deg], gimbal pitch [deg] (as Stop in
/// flight_strategy.h: yaw counter-clockwise from +x, pitch up positive, −90 = down).
struct ViewPose {
  Vec3 position{Vec3::Zero()};  ///< camera centre [m]
  double yaw_deg{0.0};          ///< heading, counter-clockwise from +x (east) [deg]
  double pitch_deg{0.0};        ///< gimbal pitch, up positive, 0 = horizontal [deg]
};

/// The orthonormal camera frame of a pose (see the file comment); right × up = −forward.
struct ViewFrame {
  ViewPose pose;                ///< the pose it was made from
  Vec3 forward{Vec3::UnitX()};  ///< optical axis (unit)
  Vec3 right{-Vec3::UnitY()};   ///< image width axis, horizontal (unit)
  Vec3 up{Vec3::UnitZ()};       ///< image height axis, "up" in the photo (unit)
};

/// Frame of a pose: f = (cos p cos y, cos p sin y, sin p), r = (sin y, −cos y, 0), u = r × f.
ViewFrame makeViewFrame(const ViewPose& pose);

/// What a camera sees of one world point from one pose.
struct Projection {
  bool in_image{false};  ///< in front of the camera and inside the image (edges included)
  double range_m{0.0};   ///< |point − camera| [m]
  /// GSD at that point [mm/px]: range·1000 / focal_px. Exact for a patch facing the
  /// camera on the optical axis; an upper bound off axis (the local GSD there is
  /// range·cos θ/f tangentially, range·cos²θ/f radially) and for a fronto-parallel
  /// patch (depth ≤ range). Incidence is a separate criterion.
  double gsd_mm_per_px{0.0};
};

/// A camera model. Implementations are immutable after construction and their const
/// members are thread-safe (evaluateCoverage calls them from several threads).
class CameraModel {
 public:
  virtual ~CameraModel() = default;

  /// Projection of world point `point` [m] seen from `pose`.
  virtual Projection project(const ViewPose& pose, const Vec3& point) const = 0;

  /// The same from a prepared frame (makeViewFrame(frame.pose)); evaluateCoverage
  /// calls this once per (view, point) pair so the trigonometry is done once per
  /// view. The default forwards to project(frame.pose, point); override for speed.
  virtual Projection projectInFrame(const ViewFrame& frame, const Vec3& point) const {
    return project(frame.pose, point);
  }

  /// Farthest range at which a point still counts as imaged [m]: the range where the
  /// GSD reaches `max_gsd_mm_per_px` (0 = no GSD limit), capped by the model's own
  /// range limit; +infinity when neither applies. Throws InputError for a negative
  /// or non-finite GSD.
  virtual double maxRange(double max_gsd_mm_per_px) const = 0;

  /// Largest angle between the optical axis and the direction of any point in the
  /// image [rad]; π when the model does not say (evaluations then cull by range only).
  virtual double maxOffAxisRad() const { return kPi; }
};

/// Options of FootprintCamera.
struct FootprintCameraOptions {
  Camera camera;            ///< footprint (paper: 0.6 × 0.4 m) or sensor description
  double standoff_m{1.5};   ///< standoff when the camera gives its footprint directly [m] (as
                            ///< CoverageOptions::standoff_m)
  double range_slack{1.5};  ///< the model's own range limit = standoff × range_slack (≥ 1)
  /// Pixels across the footprint width assumed for a camera given by its footprint
  /// only (it has no pixels): focal_px = assumed_image_w_px·standoff / footprint_w,
  /// so the GSD at the standoff is footprint_w·1000 / assumed_image_w_px [mm/px]
  /// (0.6 mm/px for the paper's 0.6 m photo). Ignored for a sensor camera.
  int assumed_image_w_px{1000};

  /// Throws InputError naming the bad field (prefix `where`).
  void validate(const std::string& where = "footprint_camera") const;
};

/// A central camera: one focal length for the GSD (range·1000 / focal_px) and a
/// projection done in the view's frame (project() makes the frame and forwards).
class CentralCamera : public CameraModel {
 public:
  Projection project(const ViewPose& pose, const Vec3& point) const final;
  double focalPx() const { return focal_px_; }  ///< focal length of the GSD rule [px]

 protected:
  /// r [m] capped by the range where the GSD reaches max_gsd_mm_per_px (0 = no cap);
  /// throws InputError, naming `where`, for a negative or non-finite GSD.
  double cappedRange(double r, double max_gsd_mm_per_px, const std::string& where) const;

  double focal_px_{0.0};  ///< [px]
};

/// The flight strategy's camera (paper §II-F): a frustum whose footprint at the
/// standoff D is footprint_w × footprint_h (solveCamera), i.e. a point is in the
/// image when z > 0, |x| ≤ z·footprint_w/(2D) and |y| ≤ z·footprint_h/(2D).
/// GSD rule: with a sensor, focal_px = min(Iw·f/Sw, Ih·f/Sh) (the GSD is met on both
/// axes, as in solveCamera); with a direct footprint, the equivalent focal length of
/// FootprintCameraOptions::assumed_image_w_px. Own range limit: D × range_slack.
/// Immutable; thread-safe.
class FootprintCamera final : public CentralCamera {
 public:
  /// Validates the options (InputError) and solves the camera.
  explicit FootprintCamera(const FootprintCameraOptions& options);

  Projection projectInFrame(const ViewFrame& frame, const Vec3& point) const override;
  double maxRange(double max_gsd_mm_per_px) const override;
  /// atan of the half footprint's diagonal over the standoff.
  double maxOffAxisRad() const override;
  const CameraGeometry& geometry() const { return geometry_; }  ///< footprint and standoff

 private:
  FootprintCameraOptions options_;
  CameraGeometry geometry_;
  double tan_half_w_{0.0};  ///< footprint_w / (2·standoff)
  double tan_half_h_{0.0};  ///< footprint_h / (2·standoff)
};

/// Intrinsics of a pinhole camera (defaults: FC-Planner's 640 × 480 camera).
/// Pixel coordinates u = cx + fx·x/z, v = cy + fy·y/z (x right, y down, z depth);
/// the image is the closed rectangle 0 ≤ u ≤ width, 0 ≤ v ≤ height, so the
/// horizontal half field of view to the right is atan((width − cx)/fx).
struct PinholeIntrinsics {
  int width_px{640};        ///< image width [px]
  int height_px{480};       ///< image height [px]
  double fx_px{417.0467};   ///< focal length along the width [px]
  double fy_px{461.0951};   ///< focal length along the height [px]
  double cx_px{320.0};      ///< principal point [px]
  double cy_px{240.0};      ///< principal point [px]
  double max_range_m{0.0};  ///< the model's own range limit [m]; 0 = none

  /// Throws InputError naming the bad field (prefix `where`).
  void validate(const std::string& where = "pinhole") const;
};

/// Pinhole camera. GSD = range·1000 / min(fx, fy) (the worse axis). Immutable;
/// thread-safe.
class PinholeCamera final : public CentralCamera {
 public:
  /// Validates the intrinsics (InputError).
  explicit PinholeCamera(const PinholeIntrinsics& intrinsics);

  Projection projectInFrame(const ViewFrame& frame, const Vec3& point) const override;
  double maxRange(double max_gsd_mm_per_px) const override;
  /// atan of the image corner farthest from the principal point, in focal lengths.
  double maxOffAxisRad() const override;
  const PinholeIntrinsics& intrinsics() const { return k_; }

 private:
  PinholeIntrinsics k_;
};

/// Line of sight between a camera and a surface point. Implementations are immutable
/// after construction and thread-safe.
class LineOfSight {
 public:
  virtual ~LineOfSight() = default;
  /// True when nothing blocks the segment from → to [m].
  virtual bool clear(const Vec3& from, const Vec3& to) const = 0;
};

/// Line of sight through the occupied voxels of a cloud. Voxel (i, j, k) is the cube
/// [i·v, (i+1)·v) × … with v = voxel_m (grid anchored at the world origin); it is
/// occupied when it holds a point. Keys are VoxelKeyer's (64-bit, 21 bits per axis: the
/// occupied box may span 2^21 voxels per axis, anywhere) in an open-addressing hash set.
///
/// clear(from, to): with L = |to − from|, the segment from + t·(to − from)/L,
/// t ∈ [0, L − end_slack_m], is walked voxel by voxel (exact 3D DDA,
/// Amanatides & Woo 1987) and is blocked when any voxel it enters is occupied — the
/// voxel holding `from` included. The last end_slack_m before the target are not
/// tested, so the target's own voxel and its surface neighbours do not block: a
/// point on a surface lies up to √3·v below the top of the occupied layer, so
/// end_slack_m ≥ √3·v / cos(max incidence) keeps a surface from hiding itself
/// (3.5·v at 60°). A segment shorter than end_slack_m is clear. The walk is clipped
/// to the bounding box of the occupied voxels, and a bitmap of 8³-voxel bricks (larger
/// for huge boxes, ≤ 2^26 bricks) spares the hash lookups in empty bricks. Throws InputError for a
/// non-finite end point.
class VoxelLineOfSight final : public LineOfSight {
 public:
  /// Throws InputError for voxel_m ≤ 0, end_slack_m < 0 (or non-finite), a
  /// non-finite point, or points spanning more than 2^21 voxels on an axis.
  VoxelLineOfSight(const PointList& occupied_points, double voxel_m, double end_slack_m);

  bool clear(const Vec3& from, const Vec3& to) const override;

  /// True when the voxel holding p is occupied.
  bool occupied(const Vec3& p) const;
  double voxelSize() const { return voxel_m_; }     ///< [m]
  double endSlack() const { return end_slack_m_; }  ///< [m]
  std::size_t occupiedVoxels() const { return count_; }

 private:
  bool occupiedIndex(std::int64_t i, std::int64_t j, std::int64_t k) const;
  /// Linear index of the brick holding voxel (i, j, k), which must be in the box.
  std::uint64_t brickIndex(std::int64_t i, std::int64_t j, std::int64_t k) const;
  /// Linear index of voxel (i, j, k) in the box (dense_bits_).
  std::uint64_t denseIndex(std::int64_t i, std::int64_t j, std::int64_t k) const;
  /// Voxel (i, j, k), in the box, is occupied: the dense bits, else the hash table.
  bool occupiedInBox(std::int64_t i, std::int64_t j, std::int64_t k) const;

  double voxel_m_{0.0};
  double end_slack_m_{0.0};
  std::vector<std::uint64_t> table_;  ///< open addressing, linear probing; empty = ~0
  std::uint64_t mask_{0};
  std::size_t count_{0};
  std::int64_t lo_[3]{0, 0, 0};  ///< index bounding box of the occupied voxels
  std::int64_t hi_[3]{-1, -1, -1};
  /// Bricks of 2^brick_shift_ voxels per edge over the box: a bit per brick that holds
  /// an occupied voxel, so the walk skips the hash lookups in empty space.
  int brick_shift_{3};
  std::int64_t brick_dims_[3]{0, 0, 0};
  std::vector<std::uint64_t> brick_bits_;
  /// A bit per voxel of the box when it holds at most 2^28 voxels, else empty.
  std::vector<std::uint64_t> dense_bits_;
};

/// What counts as "imaged".
struct CoverageCriteria {
  double max_gsd_mm_per_px{0.0};  ///< 0 = no GSD limit [mm/px]
  /// Largest angle between the surface normal and the ray point → camera, in (0, 180]
  /// [deg]; 90 accepts every point facing the camera, 180 disables the test.
  double max_incidence_deg{60.0};
  double max_range_m{0.0};  ///< 0 = from the camera model (CameraModel::maxRange) [m]
  /// True when a normal's sign is unknown (normals estimated from a cloud): the
  /// incidence test then takes the angle to whichever side faces the camera, and
  /// only the line of sight tells the sides of a solid apart.
  bool two_sided_normals{false};

  /// Throws InputError naming the bad field (prefix `where`).
  void validate(const std::string& where = "coverage_criteria") const;
};

/// Coverage of a point set by a set of views.
struct CoverageResult {
  std::size_t points{0};               ///< number of points evaluated
  std::size_t covered{0};              ///< points imaged by at least one view
  double fraction{0.0};                ///< covered / points (1 for 0 points)
  std::vector<std::size_t> uncovered;  ///< indices of points no view images, ascending
  std::vector<int> views_per_point;    ///< how many views image each point
  double range_limit_m{0.0};           ///< R used (criteria or camera model) [m]; +inf = none
  std::size_t pairs_in_range{0};       ///< (view, point) pairs within R (statistics)
  std::size_t los_queries{0};          ///< pairs that passed tests 1–4 and needed a line of sight
};

/// Point i is covered when some view images it (criteria 1–5 of the file comment):
/// inside the image, range ≤ R, GSD ≤ max, incidence ≤ max (normals[i] oriented toward
/// free space; `normals` holds one normal per point or one normal for all, any
/// non-zero length), line of sight clear (`los` may be null = no occlusion test).
/// `two_sided`, if given, holds one flag per point: 1 where that point's normal is
/// two-sided (as two_sided_normals, for that point only).
/// The views are split over `threads` workers (core/parallel.h) with per-worker
/// counters summed at the end: the result does not depend on the thread count. With a
/// `gate`, the workers beyond the caller join once it opens. Throws InputError
/// for non-finite points, views or normals, a zero normal, a normal count other than points.size()
/// or 1, invalid criteria or threads < 1.
CoverageResult evaluateCoverage(const PointList& points, const std::vector<Vec3>& normals,
                                const std::vector<ViewPose>& views, const CameraModel& camera,
                                const CoverageCriteria& criteria, const LineOfSight* los,
                                int threads = 2, const std::vector<char>* two_sided = nullptr,
                                WorkerGate* gate = nullptr);

/// The same test, view by view: for each view, the indices of the points it images
/// (ascending). What a view selection scores its candidates with. Same checks and
/// exceptions as evaluateCoverage.
std::vector<std::vector<std::uint32_t>> imagedByView(
    const PointList& points, const std::vector<Vec3>& normals, const std::vector<ViewPose>& views,
    const CameraModel& camera, const CoverageCriteria& criteria, const LineOfSight* los,
    int threads = 2, const std::vector<char>* two_sided = nullptr);

}  // namespace uavip::coverage
