#pragma once
/// \file
/// Value types shared by every pipeline stage (docs/ARCHITECTURE.md, "Modules").
/// World frame: ENU metres, z up.

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace uavip {

/// A 3D point or vector in the world frame [m].
using Vec3 = Eigen::Vector3d;
/// An unordered point cloud [m]. Vector3d needs no special allocator (12-byte
/// alignment is not a vectorisable fixed size for Eigen).
using PointList = std::vector<Vec3>;

/// Infinite plane n·x + d = 0 with unit normal n (paper §II-D, M = [a b c d]).
struct Plane {
  Vec3 normal{0.0, 0.0, 1.0};  ///< unit normal; for a Surface it points toward free space
  double offset{0.0};          ///< d [m]

  /// Signed distance of p to the plane [m], positive on the normal's side.
  double signedDistance(const Vec3& p) const { return normal.dot(p) + offset; }
  /// Orthogonal projection of p onto the plane.
  Vec3 project(const Vec3& p) const { return p - signedDistance(p) * normal; }
};

/// A planar surface to inspect (paper §II-D): RANSAC plane, the inliers of its
/// largest cluster, and its boundary on the plane: by default the outline of the
/// cells its projected inliers occupy (outer outline and holes, so an L-shaped wall or
/// a window is not covered as air); with `perception.boundary: convex` the paper's
/// convex hull of the projected inliers (then no holes).
struct Surface {
  int id{0};           ///< 0-based, stable for the same input and options
  Plane plane;         ///< normal oriented toward free space
  PointList inliers;   ///< inliers of the largest cluster [m]
  PointList boundary;  ///< outer outline on the plane, counter-clockwise seen from +normal [m]
  /// Openings inside the outline (a window), each a polygon on the plane, clockwise
  /// seen from +normal; empty for a convex-hull boundary [m].
  std::vector<PointList> holes;
  Vec3 centroid{Vec3::Zero()};  ///< mean of the inliers [m]
  Vec3 axis_u{Vec3::UnitX()};   ///< first principal in-plane axis (unit)
  Vec3 axis_v{Vec3::UnitY()};   ///< second in-plane axis, axis_u × axis_v = normal
  double area_m2{0.0};          ///< area of the boundary polygon minus its holes [m²]
  double density_area_m2{
      0.0};  ///< area the inliers occupy: cells of a spacing-sized grid in the plane × cell² [m²]
};

/// A cluster of points that belongs to no surface (paper §II-E).
struct Obstacle {
  int id{0};
  PointList points;             ///< [m]
  Vec3 aabb_min{Vec3::Zero()};  ///< axis-aligned bounding box [m]
  Vec3 aabb_max{Vec3::Zero()};
};

/// A volume the operator forbids (an edits file's `keep_out`, app/edits.h): what the
/// scan cannot show — a crane's swing, a road with traffic, a power line, a no-fly
/// box. Planning and validation treat it as solid: no stop, waypoint or leg inside,
/// and the UAV keeps its clearance from it.
struct KeepOut {
  enum class Shape { Box, Cylinder };
  std::string name;
  Shape shape{Shape::Box};
  /// Box: its centre; cylinder: the point of its axis at mid-height [m].
  Vec3 center{Vec3::Zero()};
  /// Box: edge lengths along its own x and y (turned by yaw_deg about z) and z [m].
  /// Cylinder: (2 r, 2 r, height) [m].
  Vec3 size{Vec3::Ones()};
  double yaw_deg{0.0};  ///< box: turn about the vertical axis, counter-clockwise [deg]

  /// True when p lies inside the volume grown by `margin` [m].
  bool contains(const Vec3& p, double margin = 0.0) const;
};

/// Measured properties of a cloud.
struct CloudStats {
  std::size_t points{0};
  /// Median distance from a sampled point to its nearest distinct neighbour [m].
  double spacing_m{0.0};
  Vec3 extent_m{Vec3::Zero()};  ///< size of the axis-aligned bounding box [m]
  Vec3 min{Vec3::Zero()};       ///< bounding box [m]
  Vec3 max{Vec3::Zero()};
  /// Median RMS distance of a point's noise_k neighbours to their least-squares
  /// plane [m]: sensor noise on flat parts (edges and curvature add to it, the
  /// median keeps it to the flat majority).
  double noise_m{0.0};
  /// True when the points lie on a regular lattice (a voxel grid's output, a
  /// sampled synthetic surface): each point then stands for spacing² of surface.
  /// False for irregular sampling (airborne or mobile LiDAR), where the area a
  /// point stands for varies; set by the caller that knows (measureCloud: false).
  bool lattice{false};
  /// True when the cloud looks like one terrestrial scan taken at the origin (a
  /// room scan, a Velodyne frame): the point spacing grows with the range from the
  /// origin (a constant angular step), so spacing / range varies far less than the
  /// spacing itself. The origin is then the sensor position.
  bool scanned_from_origin{false};
  /// spread(spacing / range) / spread(spacing), the number behind scanned_from_origin
  /// (spread = median absolute deviation / median); 0 when not measured.
  double station_ratio{0.0};
};

/// Triangles over shared vertices [m] (a mesh input, io/mesh_reader.h).
struct TriangleMesh {
  PointList vertices;                                   ///< [m]
  std::vector<std::array<std::uint32_t, 3>> triangles;  ///< indices into vertices
};

/// Every measured point, for safety (preprocess/safety_cloud.h): what planning and
/// validation keep clear of besides the clean cloud. Stage 3 never removes a point
/// from here; only input options the user sets (LAS classes) do.
struct SafetyCloud {
  PointList points;      ///< one input point per occupied cell of edge cell_m [m]
  double cell_m{0.0};    ///< edge of the thinning lattice [m]
  double margin_m{0.0};  ///< every input point lies within this of some point here (√3·cell_m) [m]
  std::size_t input_points{0};  ///< points read from the input
  /// Input points stage 3's outlier removal dropped (kept here).
  std::size_t perception_dropped{0};
  std::string source;  ///< the input file as given (empty for a simulated scenario)
  std::string sha256;  ///< of the input file's bytes (empty when no file)
  /// A mesh input's triangles with area, in the scene's frame, vertices rounded to
  /// float (so the copy beside scene.json reads back identically): the exact surface
  /// the points were sampled on. The collision world measures distances to these
  /// instead of to the points, so no sparse-cloud allowance is kept (pipeline.h,
  /// safetyClearance). Null for a cloud input.
  std::shared_ptr<const TriangleMesh> mesh;
};

/// Result of perception: what the clean cloud means. Every measured point stays an
/// obstacle for planning, whether it ended in a surface, a cluster or neither.
struct Scene {
  std::vector<Surface> surfaces;
  std::vector<Obstacle> obstacles;
  PointList cloud;  ///< the clean cloud (after stage 3) [m]
  /// The raw cloud as measured before stage 3 (spacing, extent, noise); its
  /// numbers resolve the `auto` parameters of planning too (app/config.h).
  std::optional<CloudStats> measured;
  /// Every measured point (absent in scenes written before it): planning and the
  /// validator keep clear of these too, with its margin added.
  std::optional<SafetyCloud> safety;
  /// Volumes the operator forbids (edits file `keep_out`); solid for planning.
  std::vector<KeepOut> keep_out;
};

}  // namespace uavip
