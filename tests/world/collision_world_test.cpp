#include "uavip/world/collision_world.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <random>

#include "uavip/core/error.h"
#include "uavip/core/geometry.h"

namespace uavip::world {
namespace {

/// A rectangular surface: plane through `origin` with unit normal n, in-plane axes
/// u, v; boundary [0, w] × [0, h] in (u, v).
Surface rectangle(int id, const Vec3& origin, const Vec3& n, const Vec3& u, double w, double h) {
  Surface s;
  s.id = id;
  s.plane.normal = n;
  s.plane.offset = -n.dot(origin);
  s.axis_u = u;
  s.axis_v = n.cross(u);
  s.boundary = {origin, origin + w * u, origin + w * u + h * s.axis_v, origin + h * s.axis_v};
  s.centroid = origin + 0.5 * w * u + 0.5 * h * s.axis_v;
  return s;
}

/// Distance from p to the box [lo, hi] (axis-aligned in its own frame).
double pointBox(const Vec3& p, const Vec3& lo, const Vec3& hi) {
  return (p - p.cwiseMax(lo).cwiseMin(hi)).norm();
}

/// Segment–box distance by ternary search: the distance to a convex set is convex
/// along the segment, so this converges to the exact minimum.
double segmentBox(const Vec3& a, const Vec3& b, const Vec3& lo, const Vec3& hi) {
  double l = 0.0, r = 1.0;
  auto f = [&](double t) { return pointBox(a + t * (b - a), lo, hi); };
  for (int i = 0; i < 200; ++i) {
    const double m1 = l + (r - l) / 3.0, m2 = r - (r - l) / 3.0;
    if (f(m1) <= f(m2))
      r = m2;
    else
      l = m1;
  }
  return std::min({f(0.0), f(1.0), f(0.5 * (l + r))});
}

TEST(CollisionWorld, ThinWallWithoutPointsIsCaughtAndNamed) {
  Scene scene;
  // Wall x = 5, facing −x, y, z in [−2, 2]; no measured point anywhere near the crossing.
  scene.surfaces.push_back(rectangle(7, Vec3(5, 2, -2), -Vec3::UnitX(), -Vec3::UnitY(), 4.0, 4.0));
  scene.cloud = {Vec3(20, 20, 20)};
  WorldOptions opt;
  opt.slab_thickness_m = 0.04;
  const CollisionWorld world(scene, opt);
  ASSERT_EQ(world.objects().size(), 2u);
  EXPECT_EQ(world.objects()[0].name(), "surface 7");
  EXPECT_EQ(world.objects()[1].name(), "cloud");

  const Proximity hit = world.proximity(Vec3(0, 0.3, 0.1), Vec3(10, 0.3, 0.1), 0.5);
  EXPECT_EQ(hit.distance_m, 0.0);
  EXPECT_EQ(hit.object, 0);
  EXPECT_NEAR(hit.point.x(), 5.0, 1e-9);
  EXPECT_NEAR(hit.point.y(), 0.3, 1e-9);
  // FCL's own discrete sweep sees it too, and a 10 m step is one capsule (no sampling).
  EXPECT_EQ(world.sweepContacts(Vec3(0, 0.3, 0.1), Vec3(10, 0.3, 0.1), 0.5), std::vector<int>{0});

  // Beside the wall: nearest is the edge x ∈ [5, 5.04], y = 2 → hand-worked distances.
  const Proximity side = world.proximity(Vec3(4, 3, -1), Vec3(4, 3, 1), 0.5);
  EXPECT_NEAR(side.distance_m, std::sqrt(2.0), 1e-12);
  EXPECT_EQ(side.object, 0);
  const Proximity behind = world.proximity(Vec3(6, 3, 0), Vec3(6, 3, 0), 0.5);  // behind the slab
  EXPECT_NEAR(behind.distance_m, std::hypot(6.0 - 5.04, 1.0), 1e-12);
  EXPECT_TRUE(world.sweepContacts(Vec3(4, 3, -1), Vec3(4, 3, 1), 1.0).empty());
  EXPECT_EQ(world.sweepContacts(Vec3(4, 3, -1), Vec3(4, 3, 1), 1.5), std::vector<int>{0});
}

TEST(CollisionWorld, SlabDistanceMatchesAnIndependentBoxDistance) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_real_distribution<double> size(0.5, 3.0);
  std::uniform_real_distribution<double> coord(-4.0, 4.0);
  int contacts = 0, clear = 0;
  for (int w = 0; w < 8; ++w) {
    const Vec3 n = Vec3(u(rng), u(rng), u(rng)).normalized();
    const Vec3 axis_u = n.unitOrthogonal();
    const Vec3 axis_v = n.cross(axis_u);
    const Vec3 origin(u(rng), u(rng), u(rng));
    const double sw = size(rng), sh = size(rng);
    Scene scene;
    scene.surfaces.push_back(rectangle(w, origin, n, axis_u, sw, sh));
    WorldOptions opt;
    opt.slab_thickness_m = 0.05;
    const CollisionWorld world(scene, opt);
    ASSERT_EQ(world.objects().size(), 1u);
    // Box frame: (u, v, n) from `origin`; the slab spans [0, sw] × [0, sh] × [−t, 0].
    Eigen::Matrix3d frame;
    frame << axis_u, axis_v, n;
    const Vec3 lo(0, 0, -0.05), hi(sw, sh, 0);
    for (int k = 0; k < 40; ++k) {
      const Vec3 a(coord(rng), coord(rng), coord(rng));
      const Vec3 b = k % 5 == 0 ? a : Vec3(coord(rng), coord(rng), coord(rng));
      const double ref =
          segmentBox(frame.transpose() * (a - origin), frame.transpose() * (b - origin), lo, hi);
      const double r = 0.4;
      const Proximity p = world.proximity(a, b, r);
      EXPECT_NEAR(p.distance_m, ref, 1e-9) << "world " << w << " segment " << k;
      EXPECT_NEAR(pointBox(frame.transpose() * (p.point - origin), lo, hi), 0.0, 1e-9);
      // FCL's GJK contact agrees away from the boundary.
      if (std::abs(ref - r) > 1e-4) {
        const bool touched = !world.sweepContacts(a, b, r).empty();
        EXPECT_EQ(touched, ref < r) << "world " << w << " segment " << k << " distance " << ref;
        (ref < r ? contacts : clear)++;
      }
    }
  }
  EXPECT_GT(contacts, 20);
  EXPECT_GT(clear, 20);
}

TEST(CollisionWorld, ObstacleIsAnOrientedBoxNotAnAxisAlignedOne) {
  Scene scene;
  Obstacle rod;
  rod.id = 12;
  for (int i = 0; i <= 20; ++i) rod.points.emplace_back(0.1 * i, 0.1 * i, 1.0);  // diagonal rod
  scene.obstacles.push_back(rod);
  WorldOptions opt;
  opt.obstacle_min_thickness_m = 0.02;
  opt.include_cloud = false;
  const CollisionWorld world(scene, opt);
  ASSERT_EQ(world.objects().size(), 1u);
  EXPECT_EQ(world.objects()[0].name(), "obstacle 12");
  // (2, 0, 1) is a corner of the rod's axis-aligned box, but √2 from the rod itself;
  // the box is 2 cm thick, so the distance lies within √2 − 0.01·√2 … √2 − 0.01.
  const Proximity p = world.proximity(Vec3(2, 0, 1), Vec3(2, 0, 1), 0.5);
  EXPECT_EQ(p.object, 0);
  EXPECT_LE(p.distance_m, std::sqrt(2.0) - 0.01 + 1e-9);
  EXPECT_GE(p.distance_m, std::sqrt(2.0) - 0.01 * std::sqrt(2.0) - 1e-9);
  // Every point of the cluster is inside its box; along the rod's axis the box ends
  // at its end points (2.83 m long, not grown), so (3, 3, 1) is √2 from the end face.
  for (const auto& q : rod.points) EXPECT_NEAR(world.proximity(q, q, 0.1).distance_m, 0.0, 1e-12);
  EXPECT_NEAR(world.proximity(Vec3(3, 3, 1), Vec3(3, 3, 1), 0.1).distance_m, std::sqrt(2.0), 1e-9);
  // A single point becomes a 2 cm cube.
  Scene one;
  Obstacle dot;
  dot.id = 3;
  dot.points = {Vec3(1, 1, 1)};
  one.obstacles.push_back(dot);
  const CollisionWorld w1(one, opt);
  EXPECT_NEAR(w1.proximity(Vec3(1, 1, 2), Vec3(1, 1, 2), 0.1).distance_m, 0.99, 1e-9);
}

TEST(CollisionWorld, CloudProximityIsExactAndTheOctreeIsConservative) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(0.0, 3.0);
  std::uniform_real_distribution<double> v(-1.0, 4.0);
  PointList cloud;
  for (int i = 0; i < 200; ++i) cloud.emplace_back(u(rng), u(rng), u(rng));
  WorldOptions opt;
  opt.octree_resolution_m = 0.1;
  const CollisionWorld world = CollisionWorld::fromCloud(cloud, opt);
  ASSERT_EQ(world.objects().size(), 1u);
  EXPECT_EQ(world.cloudSize(), cloud.size());
  EXPECT_GT(world.octreeLeaves(), 100u);
  const double r = 0.3;
  const double slack = std::sqrt(3.0) * opt.octree_resolution_m;  // a leaf box around a point
  int near = 0, far = 0;
  for (int k = 0; k < 60; ++k) {
    const Vec3 a(v(rng), v(rng), v(rng)), b(v(rng), v(rng), v(rng));
    double brute = std::numeric_limits<double>::infinity();
    for (const auto& p : cloud) brute = std::min(brute, pointSegmentDistance(p, a, b));
    const Proximity p = world.proximity(a, b, r);
    EXPECT_NEAR(p.distance_m, brute, 1e-12);
    EXPECT_NEAR(pointSegmentDistance(p.point, a, b), brute, 1e-12);
    const bool touched = !world.sweepContacts(a, b, r).empty();
    if (brute < r) {
      EXPECT_TRUE(touched) << k;  // never misses a point
      ++near;
    }
    if (brute > r + slack) {
      EXPECT_FALSE(touched) << k;  // conservative by at most a leaf's diagonal
      ++far;
    }
  }
  EXPECT_GT(near, 5);
  EXPECT_GT(far, 5);
}

TEST(CollisionWorld, SegmentsReachingFarBeyondTheCloudStayExact) {
  // Pieces far from the cloud are skipped by a box bound; the minimum must not change.
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(0.0, 3.0);
  PointList cloud;
  for (int i = 0; i < 300; ++i) cloud.emplace_back(u(rng), u(rng), u(rng));
  const CollisionWorld world = CollisionWorld::fromCloud(cloud, WorldOptions{});
  std::uniform_real_distribution<double> dir(-1.0, 1.0);
  for (int k = 0; k < 40; ++k) {
    const double reach = k % 2 == 0 ? 50.0 : 5e4;  // metres beyond the cloud
    const Vec3 through(u(rng), u(rng), u(rng));
    const Vec3 d = Vec3(dir(rng), dir(rng), dir(rng)).normalized();
    const Vec3 a = through - reach * d,
               b = through + (k % 3 == 0 ? 1.0 : reach) * d + Vec3(0, 0, 0.2 * (k % 4));
    double brute = std::numeric_limits<double>::infinity();
    for (const auto& p : cloud) brute = std::min(brute, pointSegmentDistance(p, a, b));
    const Proximity p = world.proximity(a, b, 0.5);
    EXPECT_NEAR(p.distance_m, brute, 1e-9) << k;
    EXPECT_NEAR(pointSegmentDistance(p.point, a, b), brute, 1e-9) << k;
  }
  // A segment that never comes near: its distance is still exact.
  const Vec3 a(-1e5, 50.0, 0.0), b(1e5, 50.0, 0.0);
  double brute = std::numeric_limits<double>::infinity();
  for (const auto& p : cloud) brute = std::min(brute, pointSegmentDistance(p, a, b));
  EXPECT_NEAR(world.proximity(a, b, 0.5).distance_m, brute, 1e-9);
}

TEST(CollisionWorld, SegmentsAlongADenseSurfaceAreExact) {
  // A dense, slightly rough wall (2 cm spacing): segments running along it, across
  // it and towards it, the shapes a flight path takes. The search balls around the
  // samples must still find the exact nearest point (brute force).
  std::mt19937 rng(12);
  std::normal_distribution<double> noise(0.0, 0.005);
  PointList cloud;
  for (double y = 0.0; y <= 4.0; y += 0.02)
    for (double z = 0.0; z <= 3.0; z += 0.02) cloud.emplace_back(noise(rng), y, z);
  const CollisionWorld world = CollisionWorld::fromCloud(cloud, WorldOptions{});
  std::uniform_real_distribution<double> u(-0.5, 4.5), off(0.05, 2.0);
  for (int k = 0; k < 60; ++k) {
    const Vec3 a(off(rng), u(rng), u(rng));
    const Vec3 b = k % 3 == 0 ? Vec3(a.x(), u(rng), u(rng)) : Vec3(off(rng), u(rng), u(rng));
    double brute = std::numeric_limits<double>::infinity();
    for (const auto& p : cloud) brute = std::min(brute, pointSegmentDistance(p, a, b));
    const Proximity p = world.proximity(a, b, 0.5);
    EXPECT_NEAR(p.distance_m, brute, 1e-12) << k;
    EXPECT_NEAR(pointSegmentDistance(p.point, a, b), brute, 1e-12) << k;
  }
}

TEST(CollisionWorld, CloudSpanningMoreCellsThanAKeyHoldsStaysExact) {
  // A site 300 km across (two clusters): the distance cells grow until the keys hold
  // the extent; distances, through and beside the clusters, stay exact.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 2.0);
  PointList cloud;
  for (int i = 0; i < 400; ++i) {
    const double x0 = i % 2 == 0 ? 0.0 : 3e5;
    cloud.emplace_back(x0 + u(rng), u(rng), u(rng));
  }
  const CollisionWorld world = CollisionWorld::fromCloud(cloud, WorldOptions{});
  std::uniform_real_distribution<double> v(-1.0, 3.0);
  for (int k = 0; k < 40; ++k) {
    const double x0 = k % 2 == 0 ? 0.0 : 3e5;
    const Vec3 a(x0 + v(rng), v(rng), v(rng)), b(x0 + v(rng), v(rng), v(rng));
    double brute = std::numeric_limits<double>::infinity();
    for (const auto& p : cloud) brute = std::min(brute, pointSegmentDistance(p, a, b));
    const Proximity p = world.proximity(a, b, 0.5);
    EXPECT_NEAR(p.distance_m, brute, 1e-9) << k;
    EXPECT_NEAR(pointSegmentDistance(p.point, a, b), brute, 1e-9) << k;
  }
}

TEST(CollisionWorld, NearestPointBetweenProbePositionsIsFound) {
  // Adversarial for a search that probes the cloud from points of the segment: a
  // row of points beside it, every 5 cm, alternately 10.4 cm and 10 cm away, so the
  // nearest neighbour of a probe is often not the point nearest to the segment.
  // Segments of every length and offset along the row against brute force.
  PointList cloud;
  for (int k = -10; k <= 40; ++k) cloud.emplace_back(0.05 * k, k % 2 == 0 ? 0.104 : 0.1, 0.0);
  const CollisionWorld world = CollisionWorld::fromCloud(cloud, WorldOptions{});
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> start(0.0, 0.5), length(0.02, 1.2), lift(0.0, 0.05);
  for (int k = 0; k < 200; ++k) {
    const Vec3 a(start(rng), 0.0, lift(rng));
    const Vec3 b(a.x() + length(rng), 0.0, lift(rng));
    double brute = std::numeric_limits<double>::infinity();
    for (const auto& p : cloud) brute = std::min(brute, pointSegmentDistance(p, a, b));
    EXPECT_NEAR(world.proximity(a, b, 0.05).distance_m, brute, 1e-12) << k;
  }
}

/// Exact distance from p to triangle (a, b, c), written independently of the world's
/// (projection onto the plane when it falls inside, else the nearest edge).
double pointTriangleRef(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a).normalized();
  const Vec3 x = p - n.dot(p - a) * n;
  const bool inside = n.dot((b - a).cross(x - a)) >= 0 && n.dot((c - b).cross(x - b)) >= 0 &&
                      n.dot((a - c).cross(x - c)) >= 0;
  if (inside) return std::abs(n.dot(p - a));
  return std::min({pointSegmentDistance(p, a, b), pointSegmentDistance(p, b, c),
                   pointSegmentDistance(p, c, a)});
}

/// Segment–triangle distance by golden-section search along the segment: the
/// distance to a convex set is convex along a segment.
double segmentTriangleRef(const Vec3& a, const Vec3& b, const std::array<Vec3, 3>& t) {
  auto f = [&](double s) { return pointTriangleRef(a + s * (b - a), t[0], t[1], t[2]); };
  double l = 0.0, r = 1.0;
  for (int i = 0; i < 200; ++i) {
    const double m1 = l + (r - l) / 3.0, m2 = r - (r - l) / 3.0;
    if (f(m1) < f(m2)) {
      r = m2;
    } else {
      l = m1;
    }
  }
  return std::min({f(0.0), f(1.0), f(0.5 * (l + r))});
}

TEST(CollisionWorld, MeshDistanceIsBruteForceOverEveryTriangle) {
  // A bumpy sheet of 2 × 20 × 20 triangles and a small tilted triangle above it.
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> bump(-0.2, 0.2);
  auto mesh = std::make_shared<TriangleMesh>();
  const int n = 20;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) mesh->vertices.emplace_back(0.25 * i, 0.25 * j, bump(rng));
  const auto at = [n](int i, int j) { return static_cast<std::uint32_t>(i * (n + 1) + j); };
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      mesh->triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      mesh->triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  }
  const auto base = static_cast<std::uint32_t>(mesh->vertices.size());
  mesh->vertices.insert(mesh->vertices.end(),
                        {Vec3(2, 2, 1.5), Vec3(2.3, 2.1, 1.7), Vec3(2.1, 2.4, 1.2)});
  mesh->triangles.push_back({base, base + 1, base + 2});
  const CollisionWorld world = CollisionWorld::fromMesh(mesh);
  ASSERT_EQ(world.objects().size(), 1u);
  EXPECT_EQ(world.objects()[0].name(), "mesh triangle");
  EXPECT_EQ(world.meshTriangles(), mesh->triangles.size());
  EXPECT_EQ(world.cloudSize(), 0u);
  std::uniform_real_distribution<double> xy(-1.0, 6.0), z(-1.0, 3.0);
  const double r = 0.4;
  int near = 0, far = 0;
  for (int k = 0; k < 80; ++k) {
    const Vec3 a(xy(rng), xy(rng), z(rng));
    const Vec3 b = k % 4 == 0 ? a : Vec3(xy(rng), xy(rng), z(rng));
    double brute = std::numeric_limits<double>::infinity();
    for (const auto& t : mesh->triangles)
      brute = std::min(
          brute, segmentTriangleRef(
                     a, b, {mesh->vertices[t[0]], mesh->vertices[t[1]], mesh->vertices[t[2]]}));
    const Proximity p = world.proximity(a, b, r);
    EXPECT_NEAR(p.distance_m, brute, 1e-9) << k;
    EXPECT_NEAR(pointSegmentDistance(p.point, a, b), brute, 1e-9) << k;
    // FCL's own sweep against the BVHModel agrees away from the boundary.
    const bool touched = !world.sweepContacts(a, b, r).empty();
    if (brute < r - 1e-3) {
      EXPECT_TRUE(touched) << k;
      ++near;
    } else if (brute > r + 1e-3) {
      EXPECT_FALSE(touched) << k;
      ++far;
    }
  }
  EXPECT_GT(near, 5);
  EXPECT_GT(far, 5);
  // The grid's samples reach every triangle, however small.
  const PointList samples = world.solidSamples(0.1);
  for (const auto& t : mesh->triangles) {
    const Vec3 c = (mesh->vertices[t[0]] + mesh->vertices[t[1]] + mesh->vertices[t[2]]) / 3.0;
    double nearest = std::numeric_limits<double>::infinity();
    for (const auto& q : samples) nearest = std::min(nearest, (q - c).norm());
    EXPECT_LE(nearest, 0.1 + std::sqrt(3.0) * 0.05);  // a row's step, half a voxel's diagonal
  }
}

TEST(CollisionWorld, EmptyWorldAndBadOptions) {
  const CollisionWorld none = CollisionWorld::fromCloud({});
  EXPECT_TRUE(none.objects().empty());
  EXPECT_TRUE(std::isinf(none.proximity(Vec3::Zero(), Vec3::Ones(), 1.0).distance_m));
  EXPECT_TRUE(none.sweepContacts(Vec3::Zero(), Vec3::Ones(), 1.0).empty());
  WorldOptions bad;
  bad.octree_resolution_m = 0.0;
  EXPECT_THROW(CollisionWorld::fromCloud({Vec3::Zero()}, bad), InputError);
  bad = {};
  bad.slab_thickness_m = -1.0;
  EXPECT_THROW(CollisionWorld(Scene{}, bad), InputError);
  // A surface with a degenerate (collinear) boundary gets no slab.
  Scene scene;
  Surface s = rectangle(1, Vec3::Zero(), Vec3::UnitZ(), Vec3::UnitX(), 1.0, 1.0);
  s.boundary = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)};
  scene.surfaces.push_back(s);
  EXPECT_TRUE(CollisionWorld(scene).objects().empty());
}

}  // namespace
}  // namespace uavip::world
