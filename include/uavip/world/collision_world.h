#pragma once
/// \file
/// The collision world of docs/ARCHITECTURE.md ("world"): what the UAV must not touch,
/// as FCL 0.7 collision objects in one broadphase manager
/// (fcl::DynamicAABBTreeCollisionManager):
///  - every Surface (paper §II-D) as a thin convex slab: its boundary polygon on the
///    plane, extruded by `slab_thickness_m` *behind* the plane (against the normal,
///    into the structure), so the face the UAV sees is the fitted plane itself;
///  - every Obstacle cluster (paper §II-E) as the 3D convex hull of its points (qhull),
///    or its oriented bounding box (PCA axes) when the cluster is flat, linear or
///    tiny, see WorldOptions::obstacle_min_thickness_m; a cluster wider than
///    obstacle_piece_m is cut into pieces of that size, one solid each (the solids
///    and their exact distances: world/solids.h);
///  - every measured point (the clean cloud and the safety cloud, core/geometry.h
///    safetyPoints) as one fcl::OcTree built from an octomap::OcTree. proximity() reads
///    the points themselves, so the OcTree is built on the first sweepContacts() or
///    octreeLeaves() only; until then the broadphase holds a box of its bounds;
///  - for a mesh input (SafetyCloud::mesh), its triangles in place of the measured
///    points (the points were sampled on them): one "mesh" object whose distances are
///    exact segment–triangle distances through a box tree over the triangles, and an
///    fcl::BVHModel<OBBRSS> of them for sweepContacts() (built on first use). No
///    sparse-cloud allowance is then needed (app/pipeline.h, safetyClearance).
///
/// Two queries, both sweeping the UAV as a capsule (a sphere of radius r swept along
/// a segment; a capsule contains exactly the points within r of the segment):
///  - proximity(): exact distance from a segment to the nearest object. FCL's
///    broadphase prunes objects by the capsule's AABB; the narrowphase is exact:
///    segment–polyhedron distance for slabs, hulls and boxes, exact point distances
///    for the cloud (a box tree over its 10 cm cells; an OcTree leaf is a box, so
///    FCL's own distance to the cloud is conservative by up to the leaf's
///    half-diagonal, √3/2·resolution).
///  - sweepContacts(): FCL's own discrete fcl::collide of the capsule against every
///    object (GJK; the OcTree's occupied leaves as boxes), the pure-FCL check.
/// Not fcl::continuousCollide: FCL 0.7's naive CCD samples ~10 poses along the
/// motion and misses walls thinner than the step (docs/architecture_notes.md).
///
/// Immutable after construction; const queries are thread-safe.

#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "uavip/core/geometry.h"
#include "uavip/core/types.h"

namespace uavip::world {

/// Options of the collision world.
struct WorldOptions {
  double octree_resolution_m{0.05};  ///< leaf edge of the cloud's OcTree [m]
  double slab_thickness_m{0.05};     ///< extrusion of each surface polygon behind its plane [m]
  /// Smallest thickness of an obstacle solid [m]. A cluster of at least 4 points
  /// whose extent along each of its PCA axes is at least this becomes the 3D convex
  /// hull of its points: a box would reach past the outside corner of an L-shaped
  /// cluster into free space the points leave open. Any other cluster (1–3 points,
  /// flat sheets, rods: most clusters left after plane extraction, where qhull would
  /// fail), or one qhull fails on, becomes its oriented bounding box (PCA axes), every
  /// edge at least this long. Either solid contains every point of the cluster
  /// (the hull is checked point by point), so it is conservative.
  double obstacle_min_thickness_m{0.02};
  /// A cluster wider than this on some axis is cut into cells of this edge, each its
  /// own solid (hull or box) with the cluster's id: a sparse concave real cluster
  /// would otherwise enclose the free space between its parts [m].
  double obstacle_piece_m{4.0};
  bool include_surfaces{true};   ///< add a slab per Surface
  bool include_obstacles{true};  ///< add a solid (hull or box) per Obstacle
  bool include_cloud{true};      ///< add the cloud (OcTree + exact point index)

  /// Throws InputError naming the bad field (prefix `where`).
  void validate(const std::string& where = "world") const;
};

/// What a collision object stands for.
enum class ObjectKind { Surface, Obstacle, Cloud, KeepOut, Mesh };

/// One collision object of the world.
struct WorldObject {
  ObjectKind kind{ObjectKind::Cloud};
  int id{-1};  ///< Surface::id or Obstacle::id, a keep-out's index in Scene::keep_out; −1 for the
               ///< cloud
  Aabb box;    ///< axis-aligned bounds of the object's geometry [m]
  /// "surface 3", "obstacle 12", "cloud", "keep-out 0" or "mesh triangle".
  std::string name() const;
};

/// Nearest object to a segment.
struct Proximity {
  double distance_m{std::numeric_limits<double>::infinity()};  ///< segment–object distance [m]
  int object{-1};            ///< index into CollisionWorld::objects(), −1 if none
  Vec3 point{Vec3::Zero()};  ///< nearest point of the object (a measured point for the cloud) [m]
};

/// Surfaces, obstacles and cloud of a Scene as FCL objects in a broadphase manager.
class CollisionWorld {
 public:
  /// Builds every object of `scene` (throws InputError for bad options).
  explicit CollisionWorld(const Scene& scene, const WorldOptions& options = {});
  /// A world of just these points (one "cloud" object; nothing if empty).
  static CollisionWorld fromCloud(const PointList& cloud, const WorldOptions& options = {});
  /// A world of just these triangles (one "mesh" object; nothing if there is none):
  /// `uavip validate` against a mesh input's every triangle.
  static CollisionWorld fromMesh(std::shared_ptr<const TriangleMesh> mesh,
                                 const WorldOptions& options = {});
  ~CollisionWorld();
  CollisionWorld(CollisionWorld&&) noexcept;
  CollisionWorld& operator=(CollisionWorld&&) noexcept;

  const WorldOptions& options() const { return options_; }
  const std::vector<WorldObject>& objects() const { return objects_; }
  /// Number of measured points held by the cloud object.
  std::size_t cloudSize() const;
  /// Number of triangles held by the mesh object (0 without one).
  std::size_t meshTriangles() const;
  /// Number of occupied OcTree leaves of the cloud object (builds the OcTree once).
  std::size_t octreeLeaves() const;

  /// Exact distance from the segment a→b (a point if a == b) to the nearest object,
  /// found through FCL's broadphase with the capsule of radius `radius` [m] as the
  /// query: objects farther than the best distance found so far are pruned by their
  /// AABB. Whenever the true minimum is below `radius`, every object that touches the
  /// capsule is visited, so the result is exact either way. Ties keep the first
  /// object visited.
  Proximity proximity(const Vec3& a, const Vec3& b, double radius) const;

  /// Indices of the objects that FCL's discrete collide reports in contact with the
  /// capsule of radius `radius` around a→b, ascending. Conservative for the cloud
  /// (OcTree leaves are boxes) and GJK-accurate (~1e-6 m) for slabs, hulls and boxes.
  std::vector<int> sweepContacts(const Vec3& a, const Vec3& b, double radius) const;
  /// Voxel centres (edge `spacing` [m]) on the shell of every solid (surface slabs,
  /// obstacle hulls and boxes) and on a mesh input's triangles, each face sampled at
  /// ≤ `spacing` (so a triangle too small to get a sampled point still marks its
  /// voxels), leaving out the
  /// voxels that already hold a point of one of the `occupied` clouds. A planning grid that marks
  /// these occupied cannot cross what the validator's solids enclose — on sparse,
  /// concave real clusters a hull spans free space the points leave open, and a
  /// planner that flew there would fail validation. The interior of a solid is
  /// reachable only through its shell.
  /// Only solids whose bounds meet `region` (when given) are sampled, and only
  /// their samples inside it.
  PointList solidSamples(double spacing, const std::vector<const PointList*>& occupied = {},
                         const Aabb* region = nullptr) const;

 private:
  CollisionWorld() = default;
  void build(const Scene& scene);

  struct Impl;
  std::unique_ptr<Impl> impl_;
  WorldOptions options_;
  std::vector<WorldObject> objects_;
};

}  // namespace uavip::world
