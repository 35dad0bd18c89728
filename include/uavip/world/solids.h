#pragma once
/// \file
/// The solids of the collision world (world/collision_world.h): convex polyhedra with
/// exact segment distances, built from what perception found:
///  - a Surface (paper §II-D) becomes a thin slab: its boundary's 2D convex hull on the
///    plane, extruded `thickness` behind the plane (against the normal);
///  - an Obstacle cluster (paper §II-E) becomes the 3D convex hull of its points
///    (qhull), or its oriented bounding box (PCA axes) when it is flat, linear or tiny;
///    a wide cluster is first cut into pieces, one solid each;
///  - the shell of the solids, sampled on a voxel lattice, marks them in a planning
///    grid (§II-G).
/// Plain geometry: no FCL, no kd-tree; every function is exact in double precision.

#include <array>
#include <vector>

#include "uavip/core/geometry.h"
#include "uavip/core/types.h"

namespace uavip::world {

/// Exact distance from segment [a, b] (a point if a == b) to the triangle (t0, t1, t2)
/// of positive area [m], 0 when they meet; `q` gets the triangle's nearest point
/// (Ericson, Real-Time Collision Detection §5.1.5 and §5.1.9: the segment's crossing
/// of the plane inside the triangle, else an end of the segment or an edge).
double segmentTriangle(const Vec3& a, const Vec3& b, const Vec3& t0, const Vec3& t1, const Vec3& t2,
                       Vec3& q);

/// A convex polyhedron as triangles with outward normals (empty: no triangles).
struct Polyhedron {
  std::vector<Vec3> vertices;
  std::vector<std::array<int, 3>> triangles;
  std::vector<Vec3> normals;       ///< outward unit normal per triangle
  std::vector<double> offsets;     ///< n·x + offset = 0 per triangle
  std::vector<Vec3> ball_centres;  ///< a ball holding each triangle: its box centre…
  std::vector<double> ball_radii;  ///< …and the farthest vertex from it, plus slack [m]

  /// Orients every triangle outward (the solid is convex: away from the centroid)
  /// and caches its plane.
  void finish();
  /// True when p lies inside or on the solid.
  bool contains(const Vec3& p) const;
  /// Exact distance from segment [a, b] (a point if a == b) to the solid [m], 0 when
  /// they meet; `q` gets the solid's nearest point.
  double distance(const Vec3& a, const Vec3& b, Vec3& q) const;
  /// Axis-aligned bounds of the vertices [m].
  Aabb bounds() const;
};

/// A prism: the convex polygon `top` (in order) and `top − depth` as its bottom.
Polyhedron prism(const std::vector<Vec3>& top, const Vec3& depth);

/// The slab of a surface: the 2D convex hull of its boundary on its plane, extruded
/// `thickness` [m] against the normal, so the face the UAV sees is the plane itself.
/// Empty if the boundary is degenerate (fewer than 3 hull vertices, no area).
Polyhedron surfaceSlab(const Surface& s, double thickness);

/// The 3D convex hull of `pts` (qhull, on the points relative to `centre`) as a
/// polyhedron that contains every point: its planes are checked against every point
/// and the solid scaled about its centre by the tiny factor any rounding needs.
/// Empty if qhull fails or the hull is degenerate (flat, fewer than 4 points).
Polyhedron hullSolid(const PointList& pts, const Vec3& centre);

/// The solid of an obstacle cluster; empty if it has no points. The 3D convex hull
/// of its points when they span a volume at least `min_edge` [m] thick along every
/// PCA axis; otherwise (1–3 points, flat sheets, rods) or when qhull fails, the
/// oriented bounding box, every edge at least `min_edge` long. Either contains every
/// point.
Polyhedron obstacleSolid(const Obstacle& o, double min_edge);

/// A cluster larger than `edge` [m] on some axis, cut into cells of that edge (64-bit
/// voxel keys): a sparse, concave real cluster (a tree line, a podium wrapping round a
/// tower) then becomes several tight solids instead of one hull over the free space
/// between its parts. Each piece keeps the cluster's id; a smaller cluster is
/// returned whole.
std::vector<Obstacle> obstaclePieces(const Obstacle& o, double edge);

/// The solid of a keep-out volume (app/edits.h): its box, or for a cylinder the prism
/// over the 32-gon circumscribed about its circle (contains the cylinder).
Polyhedron keepOutSolid(const KeepOut& k);

/// Points of a lattice of edge `spacing` [m] inside the solid and inside `region` (when
/// given): with the shell samples they mark a solid's inside in a planning grid, so no
/// stop or waypoint is put in a large one.
PointList interiorSamples(const Polyhedron& solid, double spacing, const Aabb* region = nullptr);

/// Voxel centres (edge `spacing` [m]) on the shell of every non-empty solid, each
/// triangle sampled in rows at most `spacing` apart, leaving out the voxels that
/// already hold a point of one of the `occupied` clouds (read in place). Only solids whose bounds
/// meet `region` (when given) are sampled, and only their samples inside it. Sorted by voxel key.
/// The triangles of `mesh` (when given) are sampled as the solids' are.
PointList shellSamples(const std::vector<Polyhedron>& solids, double spacing,
                       const std::vector<const PointList*>& occupied = {},
                       const Aabb* region = nullptr, const TriangleMesh* mesh = nullptr);

}  // namespace uavip::world
