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
/// The camera models and their frame: coverage/camera.h.

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
/// occupied when it holds a point or, with `point_extent_m` e > 0, meets the cube of edge
/// e centred on a point: a surface sampled at a spacing ≤ e then closes into a wall with
/// no hole (its points only, on a lattice near the grid's own, leave holes a ray slips
/// through; issue 46: photos of the tower's far face taken through the near one). Keys are
/// VoxelKeyer's (64-bit, 21 bits per axis: the occupied box may span 2^21 voxels per axis,
/// anywhere) in an open-addressing hash set.
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
  /// Throws InputError for voxel_m ≤ 0, end_slack_m < 0 or point_extent_m < 0 (or
  /// non-finite), a non-finite point, or points spanning more than 2^21 voxels on an axis.
  VoxelLineOfSight(const PointList& occupied_points, double voxel_m, double end_slack_m,
                   double point_extent_m = 0.0);

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
  /// Marks voxel (i, j, k) occupied: widens the box, and doubles the table at half full.
  void insert(std::int64_t i, std::int64_t j, std::int64_t k);
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
