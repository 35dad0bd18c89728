#include "uavip/planning/path_validator.h"

#include "uavip/core/geometry.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

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
  EXPECT_LT(r.min_clearance_m, 0.1);
  // Going around the wall passes.
  const PointList around = {Vec3(0, 0, 0), Vec3(4, 3, 0), Vec3(6, 3, 0), Vec3(10, 0, 0)};
  const ValidationResult ok = validator.validate(around);
  EXPECT_TRUE(ok.collision_free);
  EXPECT_EQ(ok.first_violation_segment, -1);
  EXPECT_NEAR(ok.min_clearance_m, 1.0, 1e-9);  // from (5, 3, 0) to the wall's top edge point (5, 2, 0)
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

}  // namespace
}  // namespace uavip::planning
