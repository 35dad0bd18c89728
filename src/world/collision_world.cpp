#include "uavip/world/collision_world.h"

#include <fcl/fcl.h>
#include <octomap/OcTree.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>
#include <mutex>
#include <vector>

#include "uavip/core/error.h"
#include "uavip/core/geometry.h"
#include "uavip/core/key_sort.h"
#include "uavip/core/math.h"
#include "uavip/core/neighbour_index.h"
#include "uavip/core/voxel_key.h"
#include "uavip/world/solids.h"

namespace uavip::world {
/// The cloud index lives in a named namespace: CollisionWorld::Impl (external linkage)
/// holds one, and a unity build includes this file from another unit.
namespace detail {

/// The cloud's segment distance is computed piece by piece, at most this long [m].
constexpr double kPieceLength = 0.5;
/// Edge of the cells the cloud is grouped in for its distance queries [m].
constexpr double kCellEdge = 0.1;

// ---------------------------------------------------------------- cloud index

/// Exact point distances through cells and a kd-tree over the cells. The points are
/// grouped in cells of kCellEdge; a cell stands for its points by the centre of their
/// box and half its diagonal (every point of the cell lies within that of the
/// centre). The kd-tree (float, relative to `offset`) holds the centres, so a query
/// walks a tree 4–25 × smaller than the cloud (a 2 cm safety cloud on a surface
/// holds ~25 points per cell) and then reads the points of the cells that can hold a
/// closer point, in double. Not movable: the tree refers to `centre`.
struct PointIndex {
  PointList points;
  Vec3 offset{Vec3::Zero()};
  Aabb box;                          ///< of the points
  std::vector<std::uint32_t> order;  ///< point indices, cell by cell
  std::vector<std::uint32_t> begin;  ///< per cell its first entry in `order` (+ the end)
  PointList centre;                  ///< per cell: the centre of its points' box [m]
  std::vector<double> half_diag;     ///< per cell: half the diagonal of that box [m]
  double max_half_diag{0.0};
  std::unique_ptr<NeighbourIndex> tree;  ///< over `centre`
  double pad{1e-3};                      ///< slack added to search radii for the float kd-tree [m]

  PointIndex() = default;
  PointIndex(PointIndex&&) = delete;
  PointIndex& operator=(PointIndex&&) = delete;

  void build(const PointList& pts) {
    points = pts;
    tree.reset();
    if (pts.empty()) return;
    box = boundingBox(pts);
    offset = 0.5 * (box.min + box.max);
    pad = 1e-3 + 1e-6 * (box.max - box.min).norm();
    double edge = kCellEdge;  // grown where the cloud spans more than 2^21 cells
    while ((box.max - box.min).maxCoeff() / edge > 0.5 * static_cast<double>(VoxelKeyer::kCells))
      edge *= 2.0;
    const VoxelKeyer keyer(box.min, box.max, edge, "collision cell");
    std::vector<KeyedIndex> keyed(pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i)
      keyed[i] = {keyer.key(pts[i]), static_cast<std::uint32_t>(i)};
    sortByKey(keyed);
    order.resize(pts.size());
    for (std::size_t k = 0; k < keyed.size(); ++k) {
      order[k] = keyed[k].second;
      if (k == 0 || keyed[k].first != keyed[k - 1].first)
        begin.push_back(static_cast<std::uint32_t>(k));
    }
    begin.push_back(static_cast<std::uint32_t>(keyed.size()));
    for (std::size_t c = 0; c + 1 < begin.size(); ++c) {
      Aabb cell;
      for (std::uint32_t k = begin[c]; k < begin[c + 1]; ++k) cell.extend(pts[order[k]]);
      centre.push_back(0.5 * (cell.min + cell.max));
      half_diag.push_back(0.5 * (cell.max - cell.min).norm());
      max_half_diag = std::max(max_half_diag, half_diag.back());
    }
    tree = std::make_unique<NeighbourIndex>(centre, offset);
  }

  /// Exact distance from segment [a, b] to the nearest point; `q` gets that point.
  /// The segment is cut into pieces of kPieceLength; a piece whose mid-point lies
  /// farther from the cloud's box than the best distance so far plus its half length
  /// cannot hold the minimum and costs no search, so a segment reaching far beyond
  /// the cloud stays cheap. `best` is always a true point–segment distance, so it
  /// bounds the answer D from above. The nearest point p* has its foot on the
  /// segment either in some piece of length L and mid-point m, and then
  /// |p* − m|² = D² + |foot − m|² ≤ best² + L²/4 (Pythagoras; the cell nearest to m
  /// tightens `best` first), or at the segment's end a or b, and then |p* − end| =
  /// D ≤ best. One ball per piece and one per end of the whole segment make the
  /// minimum exact (the joints between pieces need no ball: a foot there lies in
  /// both pieces). A ball of radius R finds every cell whose centre is within
  /// R + max_half_diag; a cell whose centre is at least best + half its diagonal from
  /// the piece holds no closer point and is not read.
  double distance(const Vec3& a, const Vec3& b, Vec3& q) const {
    double best = kInf;
    if (points.empty()) return best;
    const auto scanCell = [&](int c, const Vec3& pa, const Vec3& pb) {
      if (c < 0) return;
      const auto cell = static_cast<std::size_t>(c);
      if (pointSegmentDistance(centre[cell], pa, pb) - half_diag[cell] >= best) return;
      for (std::uint32_t k = begin[cell]; k < begin[cell + 1]; ++k) {
        const Vec3& p = points[order[k]];
        const double d = pointSegmentDistance(p, pa, pb);
        if (d < best) {
          best = d;
          q = p;
        }
      }
    };
    thread_local std::vector<int> cells;
    thread_local std::vector<float> d2;
    const auto scanBall = [&](const Vec3& c, double radius, const Vec3& pa, const Vec3& pb) {
      tree->within(c, radius + max_half_diag + pad, cells, d2, /*sorted=*/false);
      for (const int cell : cells) scanCell(cell, pa, pb);
    };
    // A true distance to start from: the points of the cell nearest to the segment's
    // point closest to the cloud's centre (one piece: its mid-point's cell does that).
    const Vec3 ab = b - a;
    const double len = ab.norm();
    const int pieces = static_cast<int>(std::clamp(std::ceil(len / kPieceLength), 1.0, 1e9));
    if (pieces > 1) {
      const double t = std::clamp((offset - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
      scanCell(tree->nearestTo(a + t * ab), a, b);
    }
    for (int k = 0; k < pieces; ++k) {
      const Vec3 pa = a + ab * (static_cast<double>(k) / pieces);
      const Vec3 pb = a + ab * (static_cast<double>(k + 1) / pieces);
      const Vec3 mid = 0.5 * (pa + pb);
      const double piece = (pb - pa).norm();
      if ((mid - mid.cwiseMax(box.min).cwiseMin(box.max)).norm() - 0.5 * piece >= best) continue;
      scanCell(tree->nearestTo(mid), pa, pb);
      scanBall(mid, std::sqrt(best * best + 0.25 * piece * piece), pa, pb);
    }
    scanBall(a, best, a, b);
    scanBall(b, best, a, b);
    return best;
  }
};

}  // namespace detail

namespace {

/// Smallest pruning bound handed back to FCL's broadphase: objects whose AABB
/// overlaps the query capsule (AABB distance 0) are always visited [m].
constexpr double kMinPrune = 1e-12;

/// The object index stored as an FCL object's user data.
int objectOf(const fcl::CollisionObjectd* o) { return *static_cast<const int*>(o->getUserData()); }

fcl::Transform3d capsulePose(const Vec3& a, const Vec3& b) {
  fcl::Transform3d tf = fcl::Transform3d::Identity();
  tf.translation() = 0.5 * (a + b);
  const Vec3 d = b - a;
  if (d.norm() > 0.0)
    tf.linear() = Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), d).toRotationMatrix();
  return tf;
}

/// The UAV swept along a→b: a capsule of radius r (a sphere if a == b).
fcl::CollisionObjectd sweptVolume(const Vec3& a, const Vec3& b, double radius) {
  const double len = (b - a).norm();
  std::shared_ptr<fcl::CollisionGeometryd> g;
  if (len > 0.0) {
    g = std::make_shared<fcl::Capsuled>(radius, len);
  } else {
    g = std::make_shared<fcl::Sphered>(radius);
  }
  fcl::CollisionObjectd obj(g, capsulePose(a, b));
  obj.computeAABB();
  return obj;
}

}  // namespace

// ---------------------------------------------------------------- world

struct CollisionWorld::Impl {
  std::vector<Polyhedron> solids;  ///< per object; empty for the cloud
  detail::PointIndex points;
  /// The cloud as an fcl::OcTree, built on the first sweepContacts() or octreeLeaves()
  /// (proximity() reads the points through `points`; building the OcTree cost 0.1 s
  /// of every bridge plan). Until then the manager holds the cloud object as a box
  /// with the OcTree's own bounds, so the broadphase is the same either way.
  PointList octree_points;
  double octree_resolution_m{0.05};
  std::once_flag octree_once;
  std::unique_ptr<fcl::CollisionObjectd> octree_object;
  std::size_t octree_leaves{0};
  int cloud_object{-1};  ///< index of the cloud object, −1 without one
  std::vector<std::unique_ptr<fcl::CollisionObjectd>> fcl_objects;  ///< per object
  std::vector<int> index;  ///< per fcl object: its object index (stable storage for user data)
  std::unique_ptr<fcl::DynamicAABBTreeCollisionManagerd> manager;

  /// The cloud's OcTree object (built once, thread-safe); null without a cloud.
  const fcl::CollisionObjectd* octreeObject();
};

namespace {

/// Octomap's tree depth: every OcTree spans 2^16 leaves per axis around the origin.
constexpr int kOctreeDepth = 16;

/// The box fcl::OcTree reports as its bounds (OcTree::getRootBV: the whole tree,
/// centred on the origin), as a stand-in geometry of the same AABB.
std::shared_ptr<fcl::CollisionGeometryd> octreeBoundsBox(double resolution_m) {
  const double edge = static_cast<double>(1 << kOctreeDepth) * resolution_m;
  return std::make_shared<fcl::Boxd>(edge, edge, edge);
}

}  // namespace

const fcl::CollisionObjectd* CollisionWorld::Impl::octreeObject() {
  if (cloud_object < 0) return nullptr;
  std::call_once(octree_once, [this] {
    auto octree = std::make_shared<octomap::OcTree>(octree_resolution_m);
    for (const auto& p : octree_points) {
      octomap::OcTreeKey key;
      const octomap::point3d q(static_cast<float>(p.x()), static_cast<float>(p.y()),
                               static_cast<float>(p.z()));
      if (octree->coordToKeyChecked(q, key)) octree->updateNode(key, true, true);
    }
    octree->updateInnerOccupancy();
    for (auto it = octree->begin_leafs(); it != octree->end_leafs(); ++it)
      octree_leaves += octree->isNodeOccupied(*it) ? 1 : 0;
    octree_object = std::make_unique<fcl::CollisionObjectd>(
        std::make_shared<fcl::OcTreed>(std::shared_ptr<const octomap::OcTree>(octree)));
    octree_object->setUserData(&index[static_cast<std::size_t>(cloud_object)]);
    octree_object->computeAABB();
    PointList().swap(octree_points);
  });
  return octree_object.get();
}

std::string WorldObject::name() const {
  switch (kind) {
    case ObjectKind::Surface:
      return "surface " + std::to_string(id);
    case ObjectKind::Obstacle:
      return "obstacle " + std::to_string(id);
    case ObjectKind::Cloud:
      return "cloud";
    case ObjectKind::KeepOut:
      return "keep-out " + std::to_string(id);
  }
  return "object";
}

void WorldOptions::validate(const std::string& where) const {
  requirePositive(octree_resolution_m, where, "octree_resolution_m");
  requirePositive(slab_thickness_m, where, "slab_thickness_m");
  requirePositive(obstacle_piece_m, where, "obstacle_piece_m");
  requirePositive(obstacle_min_thickness_m, where, "obstacle_min_thickness_m");
}

CollisionWorld::CollisionWorld(const Scene& scene, const WorldOptions& options)
    : options_(options) {
  options_.validate();
  build(scene);
}

CollisionWorld CollisionWorld::fromCloud(const PointList& cloud, const WorldOptions& options) {
  CollisionWorld w;
  w.options_ = options;
  w.options_.validate();
  Scene scene;
  scene.cloud = cloud;
  w.build(scene);
  return w;
}

CollisionWorld::~CollisionWorld() = default;
CollisionWorld::CollisionWorld(CollisionWorld&&) noexcept = default;
CollisionWorld& CollisionWorld::operator=(CollisionWorld&&) noexcept = default;

void CollisionWorld::build(const Scene& scene) {
  impl_ = std::make_unique<Impl>();
  Impl& im = *impl_;
  std::vector<std::shared_ptr<fcl::CollisionGeometryd>> geoms;

  auto addSolid = [&](ObjectKind kind, int id, Polyhedron&& poly) {
    if (poly.triangles.empty()) return;
    auto verts =
        std::make_shared<std::vector<fcl::Vector3d>>(poly.vertices.begin(), poly.vertices.end());
    auto faces = std::make_shared<std::vector<int>>();
    for (const auto& t : poly.triangles) faces->insert(faces->end(), {3, t[0], t[1], t[2]});
    geoms.push_back(
        std::make_shared<fcl::Convexd>(verts, static_cast<int>(poly.triangles.size()), faces));
    objects_.push_back({kind, id, poly.bounds()});
    im.solids.push_back(std::move(poly));
  };
  if (options_.include_surfaces) {
    for (const auto& s : scene.surfaces)
      addSolid(ObjectKind::Surface, s.id, surfaceSlab(s, options_.slab_thickness_m));
  }
  if (options_.include_obstacles) {
    for (const auto& o : scene.obstacles) {
      for (const auto& piece : obstaclePieces(o, options_.obstacle_piece_m)) {
        addSolid(ObjectKind::Obstacle, o.id,
                 obstacleSolid(piece, options_.obstacle_min_thickness_m));
      }
    }
  }
  for (std::size_t k = 0; k < scene.keep_out.size(); ++k)  // always: the operator's word
    addSolid(ObjectKind::KeepOut, static_cast<int>(k), keepOutSolid(scene.keep_out[k]));
  const PointList cloud = safetyPoints(scene);
  if (options_.include_cloud && !cloud.empty()) {
    im.points.build(cloud);
    im.octree_points = cloud;
    im.octree_resolution_m = options_.octree_resolution_m;
    im.cloud_object = static_cast<int>(objects_.size());
    geoms.push_back(octreeBoundsBox(options_.octree_resolution_m));
    objects_.push_back({ObjectKind::Cloud, -1, boundingBox(cloud)});
    im.solids.emplace_back();
  }

  im.index.resize(objects_.size());
  std::vector<fcl::CollisionObjectd*> raw;
  for (std::size_t i = 0; i < objects_.size(); ++i) {
    im.index[i] = static_cast<int>(i);
    im.fcl_objects.push_back(std::make_unique<fcl::CollisionObjectd>(geoms[i]));
    im.fcl_objects.back()->setUserData(&im.index[i]);
    im.fcl_objects.back()->computeAABB();
    raw.push_back(im.fcl_objects.back().get());
  }
  im.manager = std::make_unique<fcl::DynamicAABBTreeCollisionManagerd>();
  im.manager->registerObjects(raw);
  im.manager->setup();
}

PointList CollisionWorld::solidSamples(double spacing, const PointList& occupied,
                                       const Aabb* region) const {
  requirePositive(spacing, "world", "solid sample spacing");
  if (!impl_) return {};
  return shellSamples(impl_->solids, spacing, occupied, region);
}

std::size_t CollisionWorld::cloudSize() const { return impl_ ? impl_->points.points.size() : 0; }
std::size_t CollisionWorld::octreeLeaves() const {
  if (!impl_ || !impl_->octreeObject()) return 0;
  return impl_->octree_leaves;
}

namespace {

struct ProximityQuery {
  const std::vector<Polyhedron>* solids{nullptr};
  const detail::PointIndex* points{nullptr};
  const fcl::CollisionObjectd* query{nullptr};
  Vec3 a, b;
  double radius{0.0};
  Proximity best;
};

struct ContactQuery {
  const fcl::CollisionObjectd* query{nullptr};
  const fcl::CollisionObjectd* cloud_box{nullptr};  ///< the cloud's stand-in in the manager
  const fcl::CollisionObjectd* octree{nullptr};     ///< the cloud's OcTree, collided instead
  std::vector<int> hits;
};

}  // namespace

Proximity CollisionWorld::proximity(const Vec3& a, const Vec3& b, double radius) const {
  ProximityQuery q;
  if (!impl_ || objects_.empty()) return q.best;
  fcl::CollisionObjectd swept = sweptVolume(a, b, std::max(0.0, radius));
  q.solids = &impl_->solids;
  q.points = &impl_->points;
  q.query = &swept;
  q.a = a;
  q.b = b;
  q.radius = std::max(0.0, radius);
  // Broadphase by FCL; narrowphase exact. `dist` is FCL's pruning bound: subtrees
  // whose AABB lies farther than it from the capsule's AABB are skipped.
  auto callback = [](fcl::CollisionObjectd* o1, fcl::CollisionObjectd* o2, void* data,
                     double& dist) {
    auto& pq = *static_cast<ProximityQuery*>(data);
    const fcl::CollisionObjectd* obj = o1 == pq.query ? o2 : o1;
    const int i = objectOf(obj);
    const auto& solid = (*pq.solids)[static_cast<std::size_t>(i)];
    Vec3 point;
    const double d = solid.triangles.empty() ? pq.points->distance(pq.a, pq.b, point)
                                             : solid.distance(pq.a, pq.b, point);
    if (d < pq.best.distance_m) {
      pq.best.distance_m = d;
      pq.best.object = i;
      pq.best.point = point;
    }
    dist = std::max(pq.best.distance_m - pq.radius, kMinPrune);
    return false;
  };
  impl_->manager->distance(&swept, &q, callback);
  return q.best;
}

std::vector<int> CollisionWorld::sweepContacts(const Vec3& a, const Vec3& b, double radius) const {
  ContactQuery q;
  if (!impl_ || objects_.empty()) return q.hits;
  fcl::CollisionObjectd swept = sweptVolume(a, b, std::max(0.0, radius));
  q.query = &swept;
  if (impl_->cloud_object >= 0) {
    q.cloud_box = impl_->fcl_objects[static_cast<std::size_t>(impl_->cloud_object)].get();
    q.octree = impl_->octreeObject();
  }
  auto callback = [](fcl::CollisionObjectd* o1, fcl::CollisionObjectd* o2, void* data) {
    auto& cq = *static_cast<ContactQuery*>(data);
    const fcl::CollisionObjectd* other = o1 == cq.query ? o2 : o1;
    if (other == cq.cloud_box) other = cq.octree;
    fcl::CollisionRequestd request;
    fcl::CollisionResultd result;
    fcl::collide(cq.query, other, request, result);
    if (result.isCollision()) cq.hits.push_back(objectOf(other));
    return false;
  };
  impl_->manager->collide(&swept, &q, callback);
  std::sort(q.hits.begin(), q.hits.end());
  q.hits.erase(std::unique(q.hits.begin(), q.hits.end()), q.hits.end());
  return q.hits;
}

}  // namespace uavip::world
