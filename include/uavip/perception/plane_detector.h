#pragma once
/// \file
/// Stage 4 (paper §II-D): surfaces and their boundaries. Planes are extracted one
/// after another by RANSAC (PCL RandomSampleConsensus on its plane model, whose
/// hypothesis count runs over contiguous arrays; issue 31), refined on their
/// inliers; isolated groups are trimmed by keeping the largest Euclidean cluster of
/// the inliers; small planes (area < min_area_m2) go back to the object points;
/// the boundary is the outline of the cells the projected inliers occupy, holes
/// included (surface_outline.h; default), or with `boundary: convex` the paper's 2D
/// convex hull (PCL ConvexHull) of the projected inliers.

#include <cstdint>
#include <string>
#include <vector>

#include "uavip/core/params.h"
#include "uavip/core/types.h"
#include "uavip/perception/surface_outline.h"

namespace uavip::perception {

/// uavip's own tuning of stage 4, beyond the paper's parameters (the paper gives
/// none of these; the defaults were measured on the paper's cases, the bridge and
/// the real clouds of benchmarks/README.md). Not read from YAML: change them in code, with a
/// measurement.
struct PlaneTuning {
  /// Inlier band: a candidate's RANSAC inliers are tightened to median ± this many
  /// robust sigmas (1.4826 · MAD) of their plane distances, so points of an adjacent
  /// face caught by the 20 cm RANSAC band stay for their own surface.
  double band_sigmas{4.0};
  /// The band is never narrower than this fraction of distance_threshold_m.
  double band_floor{0.1};
  int band_iterations{3};  ///< refits of the plane and its band
  /// At most this many points (a seeded random subset of the pool) score RANSAC's
  /// hypotheses; a 2 m² plane at 5 cm spacing (800 of 300 k points) keeps ~160.
  std::size_t ransac_scoring_points{60000};
  /// Orientation by enclosure: columns from orient_near_m to orient_depth_m in front
  /// of / behind the surface, over cells of orient_cell_m; a side is enclosed (the
  /// inside of a closed object) when enclosed_fraction of the cells sees a point in
  /// its column [m].
  double orient_near_m{0.3};
  double orient_depth_m{6.0};
  double orient_cell_m{0.5};
  double enclosed_fraction{0.9};
  /// Line of sight from the scanning stations (viewpoints_scanned): occupancy voxel
  /// the rays cross [m], longest ray (the Hokuyo UTM-30LX's range) [m], a ray's end
  /// short of its target [m], rays per surface, and the share of a side's rays that
  /// must get through.
  double sight_voxel_m{0.1};
  double sight_range_m{30.0};
  double sight_stop_m{0.15};
  int sight_rays{48};
  double sight_fraction{0.5};
  /// Openness (no sensor position): rays from this many inliers per side, and the
  /// least difference between the sides' open shares that decides.
  int open_samples{32};
  double open_margin{0.2};
  /// Outline boundary: its cell is this fraction of the area cell (cell_size_m, 2
  /// spacings on a lattice). At 1 the outline reaches about one spacing past the
  /// points, which is what stage 3's outlier removal takes off a surface's edge
  /// (measured on the concave walls: area within 0.1–2.5 %; at 0.5 it fell 3 % short).
  /// Gaps of up to 2 × outline_close_cells cells between occupied cells are bridged
  /// (sampling gaps); openings under outline_min_hole_m2 are filled (a few missing
  /// points are not a window) [m²].
  double outline_cell_fraction{1.0};
  int outline_close_cells{1};
  double outline_min_hole_m2{0.25};

  /// Throws InputError naming the bad field (prefix `where`).
  void validate(const std::string& where) const;
};

/// Options of stage 4. The keys a config sets are in `table()` (section `perception:`).
struct PlaneDetectionOptions {
  double distance_threshold_m{0.2};  ///< RANSAC inlier distance (paper: 20 cm) [m]
  int max_iterations{200};           ///< RANSAC iterations per plane (paper: 200)
  double min_area_m2{2.0};           ///< planes smaller than this are objects (paper: 2 m²) [m²]
  double cluster_tolerance_m{0.3};   ///< neighbour distance that joins inliers into one cluster [m]
  /// Cell of the occupied-area estimate: the inliers are projected on their plane
  /// and area = occupied cells × cell² (app/config.h resolves it from the spacing) [m]
  double cell_size_m{0.1};
  int min_inliers{3};   ///< a plane with fewer points is an object, whatever its area
  int max_planes{64};   ///< stop after this many accepted planes
  int max_failures{8};  ///< stop after this many consecutive rejected candidates
  /// Sensor position, used to orient a normal when free space is ambiguous [m].
  Vec3 viewpoint{Vec3::Zero()};
  /// More sensor positions (e.g. every scanning station); the one nearest to a
  /// surface's centroid, among these and `viewpoint`, orients it [m].
  std::vector<Vec3> extra_viewpoints;
  /// True when the viewpoints are the stations that actually scanned the cloud
  /// (sensing mode scan): a scanner sees only the front of a surface, so the
  /// normal points to the side from which the viewpoints have a clear line of sight
  /// to the surface's points (the cloud occludes), before any other rule.
  bool viewpoints_scanned{false};
  /// False for a cloud file with no sensor position (airborne, mobile, a model):
  /// a normal then faces the side from which rays leave the cloud (openness), else
  /// up for level surfaces and away from the cloud's middle for walls. A scenario
  /// always knows its sensor (its viewpoint, default the origin).
  bool viewpoint_known{true};
  /// The cloud is one scan taken at `viewpoint` (a room, a street-side frame): a
  /// single station sees only the front of every surface, so each normal faces it.
  bool single_station{false};
  /// Voxel edge of the openness rays: large enough that a sparse wall blocks them [m].
  double open_voxel_m{0.1};
  /// The boundary of a surface: "outline" (the occupied cells' outline with its
  /// holes, at cell_size_m; photo stops stay over the points) or "convex" (the
  /// paper's convex hull of the projected inliers).
  std::string boundary{"outline"};
  std::uint32_t seed{42};  ///< RANSAC seed (the same inputs give the same planes)
  /// 0: every core; 1: one step at a time. With two or more, the next RANSAC step
  /// runs while a surface is built (the same surfaces either way).
  int threads{0};
  PlaneTuning tuning;  ///< uavip's own tuning (above)

  /// Throws InputError naming the bad key (prefix `where`): the table's bounds, then the
  /// fields no file sets.
  void validate(const std::string& where = "perception") const;
  /// The outline's options of a surface: its cell is tuning.outline_cell_fraction of
  /// the area cell.
  OutlineOptions outlineOptions() const;
  /// The keys of `perception:` this struct holds (core/params.h).
  static const params::Table<PlaneDetectionOptions>& table();
};

/// Statistics of stage 4.
struct PlaneDetectionStats {
  int candidates{0};              ///< planes proposed by RANSAC
  int rejected_small{0};          ///< candidates under the area threshold (returned to the objects)
  std::size_t trimmed_points{0};  ///< inliers dropped as isolated groups (returned to the objects)
};

/// Result of stage 4: the accepted surfaces and the points that belong to none.
struct PlaneDetectionResult {
  std::vector<Surface> surfaces;  ///< ids 0..n-1 in extraction order (largest first)
  PointList remaining;            ///< every input point that is in no surface
  PlaneDetectionStats stats;
};

/// Runs stage 4 on the clean cloud. Never throws on a cloud with too few points:
/// it returns no surface. Normals point toward free space: with viewpoints_scanned,
/// toward the side the scanning stations see the surface from (line of sight);
/// otherwise (or if no station sees it) away from the side that encloses the
/// surface (the inside of a closed object: ≥ 90 % of the surface sees a point
/// within 6 m on that side), otherwise toward the nearest viewpoint.
PlaneDetectionResult detectPlanes(const PointList& cloud, const PlaneDetectionOptions& options);

}  // namespace uavip::perception
