#include "uavip/planning/path_validator.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <random>

#include "uavip/core/geometry.h"

namespace uavip::planning {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct Brute {
  double min{kInf};
  int first_violation{-1};
};

Brute bruteForce(const PointList& cloud, const PointList& path, double required) {
  Brute b;
  for (std::size_t s = 0; s + 1 < path.size(); ++s) {
    double seg = kInf;
    for (const auto& p : cloud) seg = std::min(seg, pointSegmentDistance(p, path[s], path[s + 1]));
    b.min = std::min(b.min, seg);
    if (seg < required && b.first_violation < 0) b.first_violation = static_cast<int>(s);
  }
  return b;
}

TEST(PathValidator, AgreesWithBruteForceOnRandomWorlds) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> u(0.0, 4.0);
  std::uniform_real_distribution<double> v(-1.0, 5.0);
  const double required = 0.4;
  int violations = 0, clean = 0;
  for (int world = 0; world < 6; ++world) {
    PointList cloud;
    for (int i = 0; i < 150; ++i) cloud.emplace_back(u(rng), u(rng), u(rng));
    const PathValidator validator(cloud, required);
    EXPECT_DOUBLE_EQ(validator.requiredClearance(), required);
    for (int k = 0; k < 15; ++k) {
      PointList path;
      const int n = 2 + static_cast<int>(rng() % 4);
      for (int i = 0; i < n; ++i) path.emplace_back(v(rng), v(rng), v(rng));
      const Brute b = bruteForce(cloud, path, required);
      const ValidationResult r = validator.validate(path);
      EXPECT_NEAR(r.min_clearance_m, b.min, 1e-9);
      EXPECT_EQ(r.collision_free, b.first_violation < 0);
      EXPECT_EQ(r.first_violation_segment, b.first_violation);
      if (b.first_violation >= 0) {
        ++violations;
        const auto s = static_cast<std::size_t>(b.first_violation);
        EXPECT_LT(pointSegmentDistance(r.violation_point, path[s], path[s + 1]), required);
      } else {
        ++clean;
      }
      // clearance() is the brute-force nearest distance.
      double nn = kInf;
      for (const auto& p : cloud) nn = std::min(nn, (p - path[0]).norm());
      EXPECT_NEAR(validator.clearance(path[0]), nn, 1e-9);
    }
  }
  EXPECT_GT(violations, 5);
  (void)clean;
}

TEST(PathValidator, ThinWallIsCaughtOnTheRightSegment) {
  PointList wall;
  for (double y = -2.0; y <= 2.0001; y += 0.1)
    for (double z = -2.0; z <= 2.0001; z += 0.1) wall.emplace_back(5.0, y, z);
  const PathValidator validator(wall, 0.5);
  const PointList path = {Vec3(0, 0, 0), Vec3(3, 0, 0), Vec3(7, 0.5, 0), Vec3(10, 0, 0)};
  const ValidationResult r = validator.validate(path);
  EXPECT_FALSE(r.collision_free);
  EXPECT_EQ(r.first_violation_segment, 1);
  EXPECT_DOUBLE_EQ(r.violation_point.x(), 5.0);
  EXPECT_EQ(r.violation_object, "cloud");
  EXPECT_LT(r.min_clearance_m, 0.1);
  // Going around the wall passes.
  const PointList around = {Vec3(0, 0, 0), Vec3(4, 3, 0), Vec3(6, 3, 0), Vec3(10, 0, 0)};
  const ValidationResult ok = validator.validate(around);
  EXPECT_TRUE(ok.collision_free);
  EXPECT_EQ(ok.first_violation_segment, -1);
  EXPECT_NEAR(ok.min_clearance_m, 1.0,
              1e-9);  // from (5, 3, 0) to the wall's top edge point (5, 2, 0)
}

TEST(PathValidator, GrazingAtTheClearanceBoundary) {
  const double required = 0.75;
  const PathValidator validator({Vec3(0.3, 0.0, 0.0)}, required);
  const PointList pass = {Vec3(-1.0, required + 1e-6, 0.0), Vec3(1.0, required + 1e-6, 0.0)};
  const ValidationResult r = validator.validate(pass);
  EXPECT_TRUE(r.collision_free);
  EXPECT_NEAR(r.min_clearance_m, required + 1e-6, 1e-12);
  const PointList fail = {Vec3(-1.0, required - 1e-6, 0.0), Vec3(1.0, required - 1e-6, 0.0)};
  EXPECT_FALSE(validator.validate(fail).collision_free);
  // A single point is checked as a point.
  EXPECT_TRUE(validator.validate({Vec3(0.3, 0.0, required + 1e-6)}).collision_free);
  const ValidationResult p = validator.validate({Vec3(0.3, 0.0, 0.5)});
  EXPECT_FALSE(p.collision_free);
  EXPECT_EQ(p.first_violation_segment, 0);
  EXPECT_NEAR(p.min_clearance_m, 0.5, 1e-12);
}

TEST(PathValidator, EmptyCloudAndEmptyPath) {
  const PathValidator none({}, 1.0);
  const ValidationResult r = none.validate({Vec3(0, 0, 0), Vec3(1, 1, 1)});
  EXPECT_TRUE(r.collision_free);
  EXPECT_TRUE(std::isinf(r.min_clearance_m));
  EXPECT_TRUE(std::isinf(none.clearance(Vec3::Zero())));
  PathValidator one({Vec3::Zero()}, 1.0);
  EXPECT_TRUE(one.validate({}).collision_free);
  PathValidator moved = std::move(one);
  EXPECT_NEAR(moved.clearance(Vec3(3, 4, 0)), 5.0, 1e-12);
}

// ---------------------------------------------------------------- worlds with objects

/// A rectangular surface through `origin` with unit normal n and in-plane axis u
/// (v = n × u), boundary [0, w] × [0, h], and optionally inlier points on a grid.
Surface rectangle(int id, const Vec3& origin, const Vec3& n, const Vec3& u, double w, double h,
                  double spacing = 0.0) {
  Surface s;
  s.id = id;
  s.plane.normal = n;
  s.plane.offset = -n.dot(origin);
  s.axis_u = u;
  s.axis_v = n.cross(u);
  s.boundary = {origin, origin + w * u, origin + w * u + h * s.axis_v, origin + h * s.axis_v};
  s.centroid = origin + 0.5 * w * u + 0.5 * h * s.axis_v;
  if (spacing > 0.0) {
    for (double a = 0.0; a <= w + 1e-9; a += spacing)
      for (double b = 0.0; b <= h + 1e-9; b += spacing)
        s.inliers.push_back(origin + a * u + b * s.axis_v);
  }
  return s;
}

double pointBox(const Vec3& p, const Vec3& lo, const Vec3& hi) {
  return (p - p.cwiseMax(lo).cwiseMin(hi)).norm();
}

/// Segment–box distance by ternary search (convex along the segment).
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

TEST(PathValidator, ThinSurfaceWallWithoutPointsIsCaughtAndNamed) {
  // A wall x = 5 (y, z in [−2, 2]) that was detected as surface 3, but whose points
  // near the crossing are missing (only its outer rim was measured).
  Scene scene;
  Surface wall = rectangle(3, Vec3(5, 2, -2), -Vec3::UnitX(), -Vec3::UnitY(), 4.0, 4.0, 0.1);
  wall.inliers.erase(
      std::remove_if(wall.inliers.begin(), wall.inliers.end(),
                     [](const Vec3& p) { return std::abs(p.y()) < 1.8 && std::abs(p.z()) < 1.8; }),
      wall.inliers.end());
  scene.cloud = wall.inliers;
  scene.surfaces.push_back(wall);
  const double r = 0.5;
  const PointList path = {Vec3(0, 0, 0), Vec3(3, 0, 0), Vec3(7, 0.5, 0.2), Vec3(10, 0, 0)};
  // The points alone miss it: the hole is wider than 2r.
  const PathValidator points_only(scene.cloud, r);
  EXPECT_TRUE(points_only.validate(path).collision_free);
  const PathValidator v(std::make_shared<const world::CollisionWorld>(scene), r);
  const ValidationResult res = v.validate(path);
  EXPECT_FALSE(res.collision_free);
  EXPECT_EQ(res.first_violation_segment, 1);
  EXPECT_EQ(res.violation_object, "surface 3");
  EXPECT_NEAR(res.violation_point.x(), 5.0, 1e-9);
  EXPECT_NEAR(res.violation_point.y(), 0.25, 1e-9);  // where (3,0,0)→(7,0.5,0.2) crosses x = 5
  EXPECT_EQ(res.min_clearance_m, 0.0);
  ASSERT_EQ(res.segment_clearance_m.size(), 3u);
  EXPECT_NEAR(res.segment_clearance_m[0], 2.0, 1e-12);  // (3,0,0) to the wall's face
  // Going around the wall passes, with the hand-worked clearance to its edge.
  const PointList around = {Vec3(0, 0, 0), Vec3(4, 3, 0), Vec3(6, 3, 0), Vec3(10, 0, 0)};
  const ValidationResult ok = v.validate(around);
  EXPECT_TRUE(ok.collision_free);
  EXPECT_TRUE(ok.violation_object.empty());
  EXPECT_NEAR(ok.min_clearance_m, 1.0, 1e-9);  // (5, 3, 0) to the wall's edge y = 2
}

TEST(PathValidator, GrazingSurfacesAndObstaclesAtTheMargin) {
  Scene scene;
  scene.surfaces.push_back(
      rectangle(0, Vec3(0, 0, 0), Vec3::UnitZ(), Vec3::UnitX(), 4.0, 4.0));  // floor z = 0
  Obstacle box;
  box.id = 12;
  for (int i = 0; i < 8; ++i)
    box.points.emplace_back(10 + (i & 1) * 1.0, (i & 2) * 1.0, 1 + (i & 4) * 0.5);
  scene.obstacles.push_back(box);  // [10, 11] × [0, 2] × [1, 3]
  auto world = std::make_shared<const world::CollisionWorld>(scene);
  const double r = 0.6;
  const PathValidator v(world, r);
  for (const double eps : {1e-6, -1e-6}) {
    // Over the floor, parallel to it.
    const ValidationResult f = v.validate({Vec3(1, 1, r + eps), Vec3(3, 2, r + eps)});
    EXPECT_EQ(f.collision_free, eps > 0) << eps;
    EXPECT_NEAR(f.min_clearance_m, r + eps, 1e-12);
    // Beside the box's face x = 10, and past its edge (x = 11, y = 2) diagonally.
    const ValidationResult b = v.validate({Vec3(10 - r - eps, -1, 2), Vec3(10 - r - eps, 3, 2)});
    EXPECT_EQ(b.collision_free, eps > 0) << eps;
    EXPECT_NEAR(b.min_clearance_m, r + eps, 1e-12);
    const double d = (r + eps) / std::sqrt(2.0);
    const ValidationResult c = v.validate({Vec3(11 + d, 2 + d, 0), Vec3(11 + d, 2 + d, 4)});
    EXPECT_EQ(c.collision_free, eps > 0) << eps;
    if (eps < 0) {
      EXPECT_EQ(f.violation_object, "surface 0");
      EXPECT_EQ(b.violation_object, "obstacle 12");
      EXPECT_EQ(c.violation_object, "obstacle 12");
      EXPECT_EQ(c.first_violation_segment, 0);
    }
  }
}

TEST(PathValidator, AgreesWithBruteForceOnRandomWorldsWithObjects) {
  std::mt19937 rng(33);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_real_distribution<double> pos(0.0, 4.0);
  std::uniform_real_distribution<double> ext(0.3, 1.2);
  std::uniform_real_distribution<double> way(-1.0, 5.0);
  const double r = 0.45;
  const double t = world::WorldOptions{}.slab_thickness_m;
  int violations = 0, clean = 0;
  for (int w = 0; w < 5; ++w) {
    Scene scene;
    struct Box {
      Eigen::Matrix3d frame;  // columns: box axes in the world
      Vec3 origin, lo, hi;
      std::string name;
    };
    std::vector<Box> boxes;
    for (int k = 0; k < 2; ++k) {  // oriented surface slabs
      const Vec3 n = Vec3(u(rng), u(rng), u(rng)).normalized();
      const Vec3 au = n.unitOrthogonal();
      const Vec3 origin(pos(rng), pos(rng), pos(rng));
      const double sw = 2 * ext(rng), sh = 2 * ext(rng);
      scene.surfaces.push_back(rectangle(k, origin, n, au, sw, sh));
      Eigen::Matrix3d f;
      f << au, n.cross(au), n;
      boxes.push_back({f, origin, Vec3(0, 0, -t), Vec3(sw, sh, 0), "surface " + std::to_string(k)});
    }
    for (int k = 0; k < 2; ++k) {  // obstacles: the corners of an axis-aligned box
      Obstacle o;
      o.id = 10 + k;
      const Vec3 lo(pos(rng), pos(rng), pos(rng));
      const Vec3 hi = lo + Vec3(ext(rng), 1.5 * ext(rng), 2.0 * ext(rng));
      for (int i = 0; i < 8; ++i)
        o.points.emplace_back(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(),
                              i & 4 ? hi.z() : lo.z());
      scene.obstacles.push_back(o);
      boxes.push_back(
          {Eigen::Matrix3d::Identity(), Vec3::Zero(), lo, hi, "obstacle " + std::to_string(o.id)});
    }
    for (int i = 0; i < 60; ++i) scene.cloud.emplace_back(pos(rng), pos(rng), pos(rng));
    const PathValidator v(std::make_shared<const world::CollisionWorld>(scene), r);
    for (int k = 0; k < 12; ++k) {
      PointList path;
      const int n = 2 + static_cast<int>(rng() % 3);
      for (int i = 0; i < n; ++i) path.emplace_back(way(rng), way(rng), way(rng));
      double min = kInf;
      int first = -1;
      std::string first_name;
      for (std::size_t s = 0; s + 1 < path.size(); ++s) {
        double seg = kInf;
        std::string name;
        for (const auto& p : scene.cloud) {
          const double d = pointSegmentDistance(p, path[s], path[s + 1]);
          if (d < seg) {
            seg = d;
            name = "cloud";
          }
        }
        for (const auto& b : boxes) {
          const double d = segmentBox(b.frame.transpose() * (path[s] - b.origin),
                                      b.frame.transpose() * (path[s + 1] - b.origin), b.lo, b.hi);
          if (d < seg) {
            seg = d;
            name = b.name;
          }
        }
        min = std::min(min, seg);
        if (seg < r && first < 0) {
          first = static_cast<int>(s);
          first_name = name;
        }
      }
      const ValidationResult res = v.validate(path);
      EXPECT_NEAR(res.min_clearance_m, min, 1e-9);
      EXPECT_EQ(res.first_violation_segment, first);
      EXPECT_EQ(res.collision_free, first < 0);
      // Crossings (distance 0) of two objects in one segment may name either.
      if (first >= 0 && res.segment_clearance_m[static_cast<std::size_t>(first)] > 0.0) {
        EXPECT_EQ(res.violation_object, first_name);
      }
      (first < 0 ? clean : violations)++;
    }
  }
  EXPECT_GT(violations, 10);
  EXPECT_GT(clean, 5);
}

}  // namespace
}  // namespace uavip::planning
