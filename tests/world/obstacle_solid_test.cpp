// Obstacle solids of the collision world: the 3D convex hull of a cluster that spans a
// volume, the oriented box (min thickness) of flat, linear and tiny clusters.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "uavip/core/geometry.h"
#include "uavip/world/collision_world.h"

namespace uavip::world {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// An L-shaped cluster in its own frame: points on a 0.1 m grid of the two faces
/// y = 0 (x ∈ [0, 2]) and x = 0 (y ∈ [0, 2]), both z ∈ [0, 3], meeting along the
/// z axis. Its convex hull is the prism over the triangle (0,0), (2,0), (0,2).
PointList lCluster() {
  PointList pts;
  for (int i = 0; i <= 20; ++i) {
    for (int k = 0; k <= 30; ++k) {
      pts.emplace_back(0.1 * i, 0.0, 0.1 * k);
      if (i > 0) pts.emplace_back(0.0, 0.1 * i, 0.1 * k);
    }
  }
  return pts;
}

double minPointDistance(const PointList& pts, const Vec3& a, const Vec3& b) {
  double d = kInf;
  for (const auto& p : pts) d = std::min(d, pointSegmentDistance(p, a, b));
  return d;
}

/// Distance from p (L frame) to the prism over the triangle (0,0), (2,0), (0,2),
/// z ∈ [0, 3]: 2D distance to the triangle combined with the z overshoot.
double pointPrism(const Vec3& p) {
  const Eigen::Vector2d q(p.x(), p.y());
  double d_xy = 0.0;
  if (!(q.x() >= 0.0 && q.y() >= 0.0 && q.x() + q.y() <= 2.0)) {
    const std::array<Eigen::Vector2d, 3> c{Eigen::Vector2d(0, 0), Eigen::Vector2d(2, 0),
                                           Eigen::Vector2d(0, 2)};
    d_xy = kInf;
    for (int e = 0; e < 3; ++e) {
      const Eigen::Vector2d a = c[static_cast<std::size_t>(e)],
                            b = c[static_cast<std::size_t>((e + 1) % 3)];
      const double t = std::clamp((q - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
      d_xy = std::min(d_xy, (q - (a + t * (b - a))).norm());
    }
  }
  const double dz = std::max({0.0, -p.z(), p.z() - 3.0});
  return std::hypot(d_xy, dz);
}

/// Segment–prism distance by ternary search (distance to a convex set is convex
/// along the segment).
double segmentPrism(const Vec3& a, const Vec3& b) {
  auto f = [&](double t) { return pointPrism(a + t * (b - a)); };
  double l = 0.0, r = 1.0;
  for (int i = 0; i < 200; ++i) {
    const double m1 = l + (r - l) / 3.0, m2 = r - (r - l) / 3.0;
    if (f(m1) <= f(m2))
      r = m2;
    else
      l = m1;
  }
  return std::min({f(0.0), f(1.0), f(0.5 * (l + r))});
}

Scene oneObstacle(int id, const PointList& pts) {
  Scene scene;
  Obstacle o;
  o.id = id;
  o.points = pts;
  scene.obstacles.push_back(o);
  return scene;
}

WorldOptions obstaclesOnly() {
  WorldOptions opt;
  opt.include_cloud = false;
  opt.obstacle_min_thickness_m = 0.02;
  return opt;
}

TEST(ObstacleSolid, LShapedClusterDoesNotReachPastItsOutsideCorner) {
  const PointList pts = lCluster();
  const CollisionWorld world(oneObstacle(1, pts), obstaclesOnly());
  ASSERT_EQ(world.objects().size(), 1u);
  EXPECT_EQ(world.objects()[0].name(), "obstacle 1");

  // A segment in front of the face y = 0, 0.7 m from every point (brute force).
  const Vec3 a(0.3, -0.7, 0.5), b(1.2, -0.7, 2.5);
  const double to_points = minPointDistance(pts, a, b);
  EXPECT_NEAR(to_points, 0.7, 1e-12);
  // By symmetry the cluster's PCA axes are (1,1,0)/√2, (1,−1,0)/√2 and z, so its
  // oriented box spans 0 ≤ (x+y)/√2 ≤ √2, |x−y|/√2 ≤ √2, 0 ≤ z ≤ 3: it reaches past
  // the corner to (1, −1) and holds the segment's end b (the old solid's false hit).
  EXPECT_GE((b.x() + b.y()) / std::sqrt(2.0), 0.0);
  EXPECT_LE(std::abs(b.x() - b.y()) / std::sqrt(2.0), std::sqrt(2.0));

  const double r = 0.6;
  const Proximity p = world.proximity(a, b, r);
  EXPECT_EQ(p.object, 0);
  EXPECT_NEAR(p.distance_m, 0.7, 1e-9);  // the hull's face y = 0
  EXPECT_GE(p.distance_m, r);
  EXPECT_TRUE(world.sweepContacts(a, b, r).empty());
  // The same segment 0.2 m closer is flagged by both queries.
  const Vec3 shift(0.0, 0.2, 0.0);
  EXPECT_NEAR(world.proximity(a + shift, b + shift, r).distance_m, 0.5, 1e-9);
  EXPECT_EQ(world.sweepContacts(a + shift, b + shift, r), std::vector<int>{0});

  // Every point of the cluster is inside or on the solid.
  for (const auto& q : pts) ASSERT_EQ(world.proximity(q, q, 0.1).distance_m, 0.0) << q.transpose();
}

TEST(ObstacleSolid, RotatedLHullDistanceMatchesThePrismAndNeverExceedsThePoints) {
  // The L cluster rotated and moved to bridge-like coordinates; the solid must be
  // its convex hull (the prism), never farther than the nearest point.
  const Eigen::Matrix3d rot =
      (Eigen::AngleAxisd(0.7, Vec3::UnitZ()) * Eigen::AngleAxisd(0.3, Vec3(1, 2, 0).normalized()))
          .toRotationMatrix();
  const Vec3 offset(12.0, 3.5, 0.1);
  PointList pts;
  for (const auto& p : lCluster()) pts.push_back(rot * p + offset);
  const CollisionWorld world(oneObstacle(4, pts), obstaclesOnly());
  ASSERT_EQ(world.objects().size(), 1u);
  for (const auto& q : pts) ASSERT_EQ(world.proximity(q, q, 0.1).distance_m, 0.0) << q.transpose();

  std::mt19937 rng(17);
  std::uniform_real_distribution<double> coord(-2.0, 4.0);
  int outside = 0;
  for (int k = 0; k < 60; ++k) {
    const Vec3 la(coord(rng), coord(rng), coord(rng));
    const Vec3 lb = k % 6 == 0 ? la : Vec3(coord(rng), coord(rng), coord(rng));
    const Vec3 a = rot * la + offset, b = rot * lb + offset;
    const double ref = segmentPrism(la, lb);
    const Proximity p = world.proximity(a, b, 0.5);
    EXPECT_NEAR(p.distance_m, ref, 1e-6) << "segment " << k;
    EXPECT_LE(p.distance_m, minPointDistance(pts, a, b) + 1e-12) << "segment " << k;
    EXPECT_NEAR(pointPrism(rot.transpose() * (p.point - offset)), 0.0, 1e-6);
    outside += ref > 0.0 ? 1 : 0;
  }
  EXPECT_GT(outside, 20);
}

TEST(ObstacleSolid, NoisyClustersAreContainedAndBuiltQuietly) {
  // Tree-like blobs far from the origin with noise; the solid holds every point
  // exactly (no rounding slack) and qhull writes nothing to the console.
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 0.3);
  Scene scene;
  for (int c = 0; c < 5; ++c) {
    Obstacle o;
    o.id = c;
    const Vec3 centre(1000.0 + 3.0 * c, -500.0, 20.0);
    for (int i = 0; i < 60 + 40 * c; ++i)
      o.points.push_back(centre + Vec3(noise(rng), noise(rng), 2.0 * noise(rng)));
    scene.obstacles.push_back(o);
  }
  testing::internal::CaptureStderr();
  testing::internal::CaptureStdout();
  const CollisionWorld world(scene, obstaclesOnly());
  const std::string err = testing::internal::GetCapturedStderr();
  const std::string out = testing::internal::GetCapturedStdout();
  EXPECT_EQ(err, "");
  EXPECT_EQ(out, "");
  ASSERT_EQ(world.objects().size(), scene.obstacles.size());
  for (const auto& o : scene.obstacles) {
    for (const auto& q : o.points) {
      const Proximity p = world.proximity(q, q, 0.05);
      ASSERT_EQ(p.distance_m, 0.0) << "obstacle " << o.id;
    }
    // A point just outside the farthest point from the cluster's centroid, along
    // that direction, is outside the hull: no point reaches farther along it.
    Vec3 mean = Vec3::Zero();
    for (const auto& q : o.points) mean += q;
    mean /= static_cast<double>(o.points.size());
    Vec3 far = mean;
    for (const auto& q : o.points) {
      if ((q - mean).norm() > (far - mean).norm()) far = q;
    }
    const Vec3 probe = far + 0.01 * (far - mean).normalized();
    EXPECT_GT(world.proximity(probe, probe, 0.05).distance_m, 0.0) << "obstacle " << o.id;
  }
}

TEST(ObstacleSolid, FlatLinearAndTinyClustersStillGetABox) {
  const WorldOptions opt = obstaclesOnly();  // 2 cm minimum thickness
  // A flat 1 m × 1 m sheet at z = 1 (no thickness): a 2 cm slab z ∈ [0.99, 1.01].
  PointList sheet;
  for (int i = 0; i <= 10; ++i) {
    for (int j = 0; j <= 10; ++j) sheet.emplace_back(0.1 * i, 0.1 * j, 1.0);
  }
  const CollisionWorld flat(oneObstacle(2, sheet), opt);
  ASSERT_EQ(flat.objects().size(), 1u);
  EXPECT_EQ(flat.proximity(Vec3(0.5, 0.5, 0.0), Vec3(0.5, 0.5, 2.0), 0.3).distance_m, 0.0);
  EXPECT_EQ(flat.sweepContacts(Vec3(0.5, 0.5, 0.0), Vec3(0.5, 0.5, 2.0), 0.3), std::vector<int>{0});
  EXPECT_NEAR(flat.proximity(Vec3(-1, 0.5, 1.25), Vec3(2, 0.5, 1.25), 0.3).distance_m, 0.24, 1e-9);
  EXPECT_EQ(flat.sweepContacts(Vec3(-1, 0.5, 1.25), Vec3(2, 0.5, 1.25), 0.3), std::vector<int>{0});

  // One point: a 2 cm cube around it.
  const CollisionWorld dot(oneObstacle(3, {Vec3(5, 5, 5)}), opt);
  ASSERT_EQ(dot.objects().size(), 1u);
  EXPECT_EQ(dot.proximity(Vec3(4, 5, 5), Vec3(6, 5, 5), 0.3).distance_m, 0.0);
  EXPECT_EQ(dot.sweepContacts(Vec3(4, 5, 5), Vec3(6, 5, 5), 0.3), std::vector<int>{0});
  EXPECT_NEAR(dot.proximity(Vec3(4, 5, 5.5), Vec3(6, 5, 5.5), 0.3).distance_m, 0.49, 1e-9);

  // Three points (a triangle) and a collinear rod of five: boxes, crossed → flagged.
  const CollisionWorld tri(oneObstacle(5, {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}), opt);
  ASSERT_EQ(tri.objects().size(), 1u);
  EXPECT_EQ(tri.proximity(Vec3(0.2, 0.2, -1), Vec3(0.2, 0.2, 1), 0.3).distance_m, 0.0);
  EXPECT_EQ(tri.sweepContacts(Vec3(0.2, 0.2, -1), Vec3(0.2, 0.2, 1), 0.3), std::vector<int>{0});
  PointList rod;
  for (int i = 0; i < 5; ++i) rod.emplace_back(0.5 * i, 1.0, 2.0);
  const CollisionWorld line(oneObstacle(6, rod), opt);
  ASSERT_EQ(line.objects().size(), 1u);
  EXPECT_EQ(line.proximity(Vec3(1.3, 0, 2), Vec3(1.3, 2, 2), 0.3).distance_m, 0.0);
  EXPECT_EQ(line.sweepContacts(Vec3(1.3, 0, 2), Vec3(1.3, 2, 2), 0.3), std::vector<int>{0});
  for (const auto& q : rod) EXPECT_EQ(line.proximity(q, q, 0.1).distance_m, 0.0);

  // Four points in a volume thinner than 2 cm: still a box, 2 cm thick.
  const CollisionWorld thin(
      oneObstacle(7, {Vec3(0, 0, 0), Vec3(1, 0, 0.005), Vec3(0, 1, 0.005), Vec3(1, 1, 0)}), opt);
  ASSERT_EQ(thin.objects().size(), 1u);
  EXPECT_EQ(thin.proximity(Vec3(0.5, 0.5, -1), Vec3(0.5, 0.5, 1), 0.3).distance_m, 0.0);
  const Aabb box = thin.objects()[0].box;
  EXPECT_GE(box.max.z() - box.min.z(), 0.02 - 1e-9);
}

}  // namespace
}  // namespace uavip::world
