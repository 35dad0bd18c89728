#pragma once
/// \file
/// Stage 4 (paper §II-D): surfaces and their boundaries. Planes are extracted one
/// after another by RANSAC (PCL SACSegmentation, SACMODEL_PLANE), refined on their
/// inliers; isolated groups are trimmed by keeping the largest Euclidean cluster of
/// the inliers; small planes (area < min_area_m2) go back to the object points;
/// the boundary is the 2D convex hull (PCL ConvexHull) of the projected inliers.

#include "uavip/core/types.h"

#include <cstdint>
#include <string>
#include <vector>

namespace uavip::perception {

/// Options of stage 4.
struct PlaneDetectionOptions {
  double distance_threshold_m{0.2};  ///< RANSAC inlier distance (paper: 20 cm) [m]
  int max_iterations{200};           ///< RANSAC iterations per plane (paper: 200)
  double min_area_m2{2.0};           ///< planes smaller than this are objects (paper: 2 m²) [m²]
  double cluster_tolerance_m{0.3};   ///< neighbour distance that joins inliers into one cluster [m]
  /// Cell of the occupied-area estimate: the inliers are projected on their plane
  /// and area = occupied cells × cell² (app/config.h resolves it from the spacing) [m]
  double cell_size_m{0.1};
  int min_inliers{3};                ///< a plane with fewer points is an object, whatever its area
  int max_planes{64};                ///< stop after this many accepted planes
  int max_failures{8};               ///< stop after this many consecutive rejected candidates
  Vec3 viewpoint{Vec3::Zero()};      ///< sensor position, used to orient a normal when free space is ambiguous [m]
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
  std::uint32_t seed{42};            ///< RANSAC seed (the same inputs give the same planes)

  /// Throws InputError naming the bad field (prefix `where`).
  void validate(const std::string& where = "perception") const;
};

/// Statistics of stage 4.
struct PlaneDetectionStats {
  int candidates{0};        ///< planes proposed by RANSAC
  int rejected_small{0};    ///< candidates under the area threshold (returned to the objects)
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
