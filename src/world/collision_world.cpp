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
#include <future>
#include <limits>
#include <memory>
#include <mutex>
#include <vector>

#include "uavip/core/error.h"
#include "uavip/core/geometry.h"
#include "uavip/core/key_sort.h"
#include "uavip/core/math.h"
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

/// Cells a leaf of the bounding-volume tree holds at most.
constexpr std::uint32_t kLeafCells = 8;

/// Distance between two axis-aligned boxes (0 when they meet) [m].
double boxDistance(const Aabb& a, const Aabb& b) {
  const Vec3 gap = (a.min - b.max).cwiseMax(b.min - a.max).cwiseMax(0.0);
  return gap.norm();
}

/// A node of a box tree: the box of what it holds, a leaf's range of entries in the
/// owner's order, and its children (−1 for a leaf).
struct BoxNode {
  Aabb box;
  std::uint32_t first{0}, count{0};  ///< leaf: order[first … first + count)
  std::int32_t left{-1}, right{-1};  ///< children (−1 for a leaf)
};

/// Builds the subtree of a box tree over order[first … first + count) (median splits
/// of the boxes' centres on the longest axis, ties by index, up to kLeafCells entries
/// a leaf), appended to `nodes`; returns its index. PointIndex's cells and
/// TriangleIndex's triangles share it.
std::int32_t buildBoxNode(const std::vector<Aabb>& boxes, std::vector<std::uint32_t>& order,
                          std::vector<BoxNode>& nodes, std::uint32_t first, std::uint32_t count) {
  const auto at = static_cast<std::int32_t>(nodes.size());
  nodes.emplace_back();
  Aabb b;
  for (std::uint32_t k = first; k < first + count; ++k) {
    b.extend(boxes[order[k]].min);
    b.extend(boxes[order[k]].max);
  }
  nodes[static_cast<std::size_t>(at)].box = b;
  if (count <= kLeafCells) {
    nodes[static_cast<std::size_t>(at)].first = first;
    nodes[static_cast<std::size_t>(at)].count = count;
    return at;
  }
  int axis = 0;
  (b.max - b.min).maxCoeff(&axis);
  const std::uint32_t half = count / 2;
  const auto centre = [&](std::uint32_t c) { return boxes[c].min[axis] + boxes[c].max[axis]; };
  std::nth_element(order.begin() + first, order.begin() + first + half,
                   order.begin() + first + count, [&](std::uint32_t x, std::uint32_t y) {
                     return centre(x) < centre(y) || (centre(x) == centre(y) && x < y);
                   });
  const std::int32_t left = buildBoxNode(boxes, order, nodes, first, half);
  const std::int32_t right = buildBoxNode(boxes, order, nodes, first + half, count - half);
  nodes[static_cast<std::size_t>(at)].left = left;
  nodes[static_cast<std::size_t>(at)].right = right;
  return at;
}

/// Exact point distances through cells and a bounding-volume tree over the cells.
/// The points are grouped in cells of kCellEdge, each with the box of its points;
/// a binary tree of boxes (median splits on the longest axis, up to kLeafCells
/// cells a leaf) holds the cells. A segment is cut into pieces of kPieceLength; a
/// subtree, cell or piece whose box lies at least the best distance so far from the
/// piece's box is not read, nearer children first. Every point read is measured to
/// the whole segment (pointSegmentDistance, the brute-force formula), so the result
/// is that of brute force. Replaced a kd-tree over cell centres with balls around
/// the pieces: a ball 2 m above a dense surface returned ~100 cells, where the box
/// bound reads the few under the segment (docs/architecture_notes.md, "Speed").
struct PointIndex {
  using Node = BoxNode;  ///< a leaf holds cells cell_order[first … first + count)
  PointList points;
  Aabb box;                               ///< of the points
  std::vector<std::uint32_t> order;       ///< point indices, cell by cell
  std::vector<std::uint32_t> begin;       ///< per cell its first entry in `order` (+ the end)
  std::vector<Aabb> cell_box;             ///< per cell: the box of its points
  std::vector<std::uint32_t> cell_order;  ///< cells, leaf by leaf
  std::vector<Node> nodes;                ///< nodes[0] is the root

  void build(PointList pts) {
    points = std::move(pts);
    order.clear();
    begin.clear();
    cell_box.clear();
    cell_order.clear();
    nodes.clear();
    if (points.empty()) return;
    box = boundingBox(points);
    double edge = kCellEdge;  // grown where the cloud spans more than 2^21 cells
    while ((box.max - box.min).maxCoeff() / edge > 0.5 * static_cast<double>(VoxelKeyer::kCells))
      edge *= 2.0;
    const VoxelKeyer keyer(box.min, box.max, edge, "collision cell");
    std::vector<KeyedIndex> keyed(points.size());
    for (std::size_t i = 0; i < points.size(); ++i)
      keyed[i] = {keyer.key(points[i]), static_cast<std::uint32_t>(i)};
    sortByKey(keyed);
    order.resize(points.size());
    for (std::size_t k = 0; k < keyed.size(); ++k) {
      order[k] = keyed[k].second;
      if (k == 0 || keyed[k].first != keyed[k - 1].first)
        begin.push_back(static_cast<std::uint32_t>(k));
    }
    begin.push_back(static_cast<std::uint32_t>(keyed.size()));
    const std::size_t cells = begin.size() - 1;
    cell_box.resize(cells);
    for (std::size_t c = 0; c < cells; ++c)
      for (std::uint32_t k = begin[c]; k < begin[c + 1]; ++k) cell_box[c].extend(points[order[k]]);
    cell_order.resize(cells);
    for (std::size_t c = 0; c < cells; ++c) cell_order[c] = static_cast<std::uint32_t>(c);
    nodes.reserve(2 * cells / kLeafCells + 2);
    buildBoxNode(cell_box, cell_order, nodes, 0, static_cast<std::uint32_t>(cells));
  }

  /// Exact distance from segment [a, b] to the nearest point; `q` gets that point.
  /// The nearest point's foot on the segment lies in some piece, and that piece's
  /// box lies no farther from the point than the distance D, so the search of that
  /// piece reads it: the minimum over the points read is the brute-force one.
  /// `best` is always a true point–segment distance; a box is skipped only when it
  /// lies at least that far from the piece (a tiny slack covers rounding).
  double distance(const Vec3& a, const Vec3& b, Vec3& q) const {
    double best = kInf;
    if (points.empty()) return best;
    const Vec3 ab = b - a;
    const double len = ab.norm();
    const int pieces = static_cast<int>(std::clamp(std::ceil(len / kPieceLength), 1.0, 1e9));
    const double slack = 1e-9 * (1.0 + (box.max - box.min).norm() + len);
    thread_local std::vector<std::int32_t> stack;
    const auto far = [&](double bound) { return bound - slack >= best; };
    // Pieces nearest to the cloud's box first: `best` drops early.
    const auto pieceBox = [&](int k) {
      Aabb p;
      p.extend(a + ab * (static_cast<double>(k) / pieces));
      p.extend(a + ab * (static_cast<double>(k + 1) / pieces));
      return p;
    };
    int first_piece = 0;
    if (pieces > 1) {
      const double t =
          std::clamp((0.5 * (box.min + box.max) - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
      first_piece = std::min(pieces - 1, static_cast<int>(t * pieces));
    }
    for (int step = 0; step < pieces; ++step) {
      const int k = (first_piece + step) % pieces;
      const Aabb piece = pieceBox(k);
      if (far(boxDistance(piece, nodes[0].box))) continue;
      stack.clear();
      stack.push_back(0);
      while (!stack.empty()) {
        const Node& node = nodes[static_cast<std::size_t>(stack.back())];
        stack.pop_back();
        if (far(boxDistance(piece, node.box))) continue;
        if (node.left < 0) {
          for (std::uint32_t e = node.first; e < node.first + node.count; ++e) {
            const std::uint32_t cell = cell_order[e];
            if (far(boxDistance(piece, cell_box[cell]))) continue;
            for (std::uint32_t i = begin[cell]; i < begin[cell + 1]; ++i) {
              const Vec3& p = points[order[i]];
              const double d = pointSegmentDistance(p, a, b);
              if (d < best) {
                best = d;
                q = p;
              }
            }
          }
          continue;
        }
        // The nearer child on top of the stack.
        const Node& l = nodes[static_cast<std::size_t>(node.left)];
        const Node& r = nodes[static_cast<std::size_t>(node.right)];
        const bool left_first = boxDistance(piece, l.box) <= boxDistance(piece, r.box);
        stack.push_back(left_first ? node.right : node.left);
        stack.push_back(left_first ? node.left : node.right);
      }
    }
    return best;
  }
};

/// Exact triangle distances through a bounding-volume tree over a mesh's triangles:
/// the triangles' boxes in a binary tree (median splits of their centres on the
/// longest axis, up to kLeafCells triangles a leaf). A segment is cut into pieces of
/// kPieceLength and each piece searched as PointIndex does; every triangle read is
/// measured to the whole segment (segmentTriangle, exact), so the result is that of
/// brute force over every triangle: the nearest triangle's box lies no farther from
/// the piece holding the nearest point of the segment than the distance itself.
struct TriangleIndex {
  using Node = BoxNode;  ///< a leaf holds triangles order[first … first + count)
  std::shared_ptr<const TriangleMesh> mesh;
  std::vector<Aabb> tri_box;         ///< per triangle
  std::vector<std::uint32_t> order;  ///< triangles, leaf by leaf
  std::vector<Node> nodes;           ///< nodes[0] is the root

  void build(std::shared_ptr<const TriangleMesh> m) {
    mesh = std::move(m);
    const std::size_t n = mesh ? mesh->triangles.size() : 0;
    tri_box.assign(n, Aabb{});
    order.resize(n);
    nodes.clear();
    for (std::size_t i = 0; i < n; ++i) {
      for (const std::uint32_t v : mesh->triangles[i]) tri_box[i].extend(mesh->vertices[v]);
      order[i] = static_cast<std::uint32_t>(i);
    }
    if (n == 0) return;
    nodes.reserve(2 * n / kLeafCells + 2);
    buildBoxNode(tri_box, order, nodes, 0, static_cast<std::uint32_t>(n));
  }

  /// Exact distance from segment [a, b] to the nearest triangle; `q` gets its point.
  double distance(const Vec3& a, const Vec3& b, Vec3& q) const {
    double best = kInf;
    if (nodes.empty()) return best;
    const Vec3 ab = b - a;
    const double len = ab.norm();
    const int pieces = static_cast<int>(std::clamp(std::ceil(len / kPieceLength), 1.0, 1e9));
    const Aabb& root = nodes[0].box;
    const double slack = 1e-9 * (1.0 + (root.max - root.min).norm() + len);
    thread_local std::vector<std::int32_t> stack;
    const auto far = [&](double bound) { return bound - slack >= best; };
    int first_piece = 0;
    if (pieces > 1) {
      const double t =
          std::clamp((0.5 * (root.min + root.max) - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
      first_piece = std::min(pieces - 1, static_cast<int>(t * pieces));
    }
    for (int step = 0; step < pieces; ++step) {
      const int k = (first_piece + step) % pieces;
      Aabb piece;
      piece.extend(a + ab * (static_cast<double>(k) / pieces));
      piece.extend(a + ab * (static_cast<double>(k + 1) / pieces));
      if (far(boxDistance(piece, root))) continue;
      stack.clear();
      stack.push_back(0);
      while (!stack.empty()) {
        const Node& node = nodes[static_cast<std::size_t>(stack.back())];
        stack.pop_back();
        if (far(boxDistance(piece, node.box))) continue;
        if (node.left < 0) {
          for (std::uint32_t e = node.first; e < node.first + node.count; ++e) {
            const std::uint32_t t = order[e];
            if (far(boxDistance(piece, tri_box[t]))) continue;
            const auto& tri = mesh->triangles[t];
            Vec3 c;
            const double d = segmentTriangle(a, b, mesh->vertices[tri[0]], mesh->vertices[tri[1]],
                                             mesh->vertices[tri[2]], c);
            if (d < best) {
              best = d;
              q = c;
            }
          }
          continue;
        }
        const Node& l = nodes[static_cast<std::size_t>(node.left)];
        const Node& r = nodes[static_cast<std::size_t>(node.right)];
        const bool left_first = boxDistance(piece, l.box) <= boxDistance(piece, r.box);
        stack.push_back(left_first ? node.right : node.left);
        stack.push_back(left_first ? node.left : node.right);
      }
    }
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
  /// The cloud's point index, built on a second thread while the caller goes on
  /// (planning builds its grid meanwhile); `points_ready` is waited for before the
  /// first read (cloud()).
  detail::PointIndex points_index;
  std::shared_future<void> points_ready;
  const detail::PointIndex& cloud() const {
    if (points_ready.valid()) points_ready.get();  // rethrows what the build threw
    return points_index;
  }
  /// The cloud as an fcl::OcTree, built on the first sweepContacts() or octreeLeaves()
  /// (proximity() reads the points through `points`; building the OcTree cost 0.1 s
  /// of every bridge plan). Until then the manager holds the cloud object as a box
  /// with the OcTree's own bounds, so the broadphase is the same either way. Built
  /// from the point index's points.
  double octree_resolution_m{0.05};
  std::once_flag octree_once;
  std::unique_ptr<fcl::CollisionObjectd> octree_object;
  std::size_t octree_leaves{0};
  int cloud_object{-1};  ///< index of the cloud object, −1 without one
  /// A mesh input's triangles (SafetyCloud::mesh) in place of the cloud: their index,
  /// built on a second thread as the cloud's is, waited for before the first read.
  detail::TriangleIndex mesh_index;
  std::shared_future<void> mesh_ready;
  const detail::TriangleIndex& mesh() const {
    if (mesh_ready.valid()) mesh_ready.get();
    return mesh_index;
  }
  int mesh_object{-1};  ///< index of the mesh object, −1 without one
  /// The mesh as an fcl::BVHModel<OBBRSS> for sweepContacts, built on its first use;
  /// until then the manager holds a box of the mesh's bounds.
  std::once_flag bvh_once;
  std::unique_ptr<fcl::CollisionObjectd> bvh_object;
  const fcl::CollisionObjectd* bvhObject();
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
    for (const auto& p : cloud().points) {
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
  });
  return octree_object.get();
}

const fcl::CollisionObjectd* CollisionWorld::Impl::bvhObject() {
  if (mesh_object < 0) return nullptr;
  std::call_once(bvh_once, [this] {
    const TriangleMesh& m = *mesh().mesh;
    auto model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
    std::vector<fcl::Vector3d> vertices(m.vertices.begin(), m.vertices.end());
    std::vector<fcl::Triangle> triangles;
    triangles.reserve(m.triangles.size());
    for (const auto& t : m.triangles) triangles.emplace_back(t[0], t[1], t[2]);
    model->beginModel(static_cast<int>(triangles.size()), static_cast<int>(vertices.size()));
    model->addSubModel(vertices, triangles);
    model->endModel();
    bvh_object = std::make_unique<fcl::CollisionObjectd>(model);
    bvh_object->setUserData(&index[static_cast<std::size_t>(mesh_object)]);
    bvh_object->computeAABB();
  });
  return bvh_object.get();
}

std::string WorldObject::name() const {
  switch (kind) {
    case ObjectKind::Surface:
      return "surface " + std::to_string(id);
    case ObjectKind::Obstacle:
      return "obstacle " + std::to_string(id);
    case ObjectKind::Cloud:
      return "cloud";
    case ObjectKind::Mesh:
      return "mesh triangle";
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
  // A mesh input: its triangles are the measured surface, exactly (the points were
  // sampled on them), and stand for the cloud.
  if (options_.include_cloud && scene.safety && scene.safety->mesh &&
      !scene.safety->mesh->triangles.empty()) {
    const auto& mesh = scene.safety->mesh;
    const Aabb box = boundingBox(mesh->vertices);
    const Vec3 edge = (box.max - box.min).cwiseMax(1e-9);
    im.mesh_object = static_cast<int>(objects_.size());
    geoms.push_back(std::make_shared<fcl::Boxd>(edge.x(), edge.y(), edge.z()));
    objects_.push_back({ObjectKind::Mesh, -1, box});
    im.solids.emplace_back();
    im.mesh_ready = std::async(std::launch::async, [&index = im.mesh_index, mesh] {
                      index.build(mesh);
                    }).share();
  }
  PointList cloud = im.mesh_object >= 0 ? PointList{} : safetyPoints(scene);
  if (options_.include_cloud && !cloud.empty()) {
    im.octree_resolution_m = options_.octree_resolution_m;
    im.cloud_object = static_cast<int>(objects_.size());
    geoms.push_back(octreeBoundsBox(options_.octree_resolution_m));
    objects_.push_back({ObjectKind::Cloud, -1, boundingBox(cloud)});
    im.solids.emplace_back();
    // The index takes the cloud and is built on another thread (Impl's end waits
    // for it: the future is destroyed before the index).
    im.points_ready = std::async(std::launch::async, [&index = im.points_index,
                                                      pts = std::move(cloud)]() mutable {
                        index.build(std::move(pts));
                      }).share();
  }

  im.index.resize(objects_.size());
  std::vector<fcl::CollisionObjectd*> raw;
  for (std::size_t i = 0; i < objects_.size(); ++i) {
    im.index[i] = static_cast<int>(i);
    fcl::Transform3d at = fcl::Transform3d::Identity();
    if (static_cast<int>(i) == im.mesh_object)  // the stand-in box over the mesh's bounds
      at.translation() = 0.5 * (objects_[i].box.min + objects_[i].box.max);
    im.fcl_objects.push_back(std::make_unique<fcl::CollisionObjectd>(geoms[i], at));
    im.fcl_objects.back()->setUserData(&im.index[i]);
    im.fcl_objects.back()->computeAABB();
    raw.push_back(im.fcl_objects.back().get());
  }
  im.manager = std::make_unique<fcl::DynamicAABBTreeCollisionManagerd>();
  im.manager->registerObjects(raw);
  im.manager->setup();
}

PointList CollisionWorld::solidSamples(double spacing,
                                       const std::vector<const PointList*>& occupied,
                                       const Aabb* region) const {
  requirePositive(spacing, "world", "solid sample spacing");
  if (!impl_) return {};
  return shellSamples(impl_->solids, spacing, occupied, region,
                      impl_->mesh_object >= 0 ? impl_->mesh().mesh.get() : nullptr);
}

CollisionWorld CollisionWorld::fromMesh(std::shared_ptr<const TriangleMesh> mesh,
                                        const WorldOptions& options) {
  CollisionWorld w;
  w.options_ = options;
  w.options_.validate();
  Scene scene;
  scene.safety = SafetyCloud{};
  scene.safety->mesh = std::move(mesh);
  w.build(scene);
  return w;
}

std::size_t CollisionWorld::cloudSize() const { return impl_ ? impl_->cloud().points.size() : 0; }
std::size_t CollisionWorld::meshTriangles() const {
  return impl_ && impl_->mesh_object >= 0 ? impl_->mesh().mesh->triangles.size() : 0;
}
std::size_t CollisionWorld::octreeLeaves() const {
  if (!impl_ || !impl_->octreeObject()) return 0;
  return impl_->octree_leaves;
}

namespace {

struct ProximityQuery {
  const std::vector<Polyhedron>* solids{nullptr};
  const detail::PointIndex* points{nullptr};
  const detail::TriangleIndex* mesh{nullptr};
  int mesh_object{-1};
  const fcl::CollisionObjectd* query{nullptr};
  Vec3 a, b;
  double radius{0.0};
  Proximity best;
};

struct ContactQuery {
  const fcl::CollisionObjectd* query{nullptr};
  const fcl::CollisionObjectd* cloud_box{nullptr};  ///< the cloud's stand-in in the manager
  const fcl::CollisionObjectd* octree{nullptr};     ///< the cloud's OcTree, collided instead
  const fcl::CollisionObjectd* mesh_box{nullptr};   ///< the mesh's stand-in in the manager
  const fcl::CollisionObjectd* bvh{nullptr};        ///< the mesh's BVHModel, collided instead
  std::vector<int> hits;
};

}  // namespace

Proximity CollisionWorld::proximity(const Vec3& a, const Vec3& b, double radius) const {
  ProximityQuery q;
  if (!impl_ || objects_.empty()) return q.best;
  fcl::CollisionObjectd swept = sweptVolume(a, b, std::max(0.0, radius));
  q.solids = &impl_->solids;
  q.points = &impl_->cloud();
  q.mesh = &impl_->mesh();
  q.mesh_object = impl_->mesh_object;
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
    const double d = i == pq.mesh_object       ? pq.mesh->distance(pq.a, pq.b, point)
                     : solid.triangles.empty() ? pq.points->distance(pq.a, pq.b, point)
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
  if (impl_->mesh_object >= 0) {
    q.mesh_box = impl_->fcl_objects[static_cast<std::size_t>(impl_->mesh_object)].get();
    q.bvh = impl_->bvhObject();
  }
  auto callback = [](fcl::CollisionObjectd* o1, fcl::CollisionObjectd* o2, void* data) {
    auto& cq = *static_cast<ContactQuery*>(data);
    const fcl::CollisionObjectd* other = o1 == cq.query ? o2 : o1;
    if (other == cq.cloud_box) other = cq.octree;
    if (other == cq.mesh_box) other = cq.bvh;
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
