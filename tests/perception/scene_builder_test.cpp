#include "uavip/perception/scene_builder.h"

#include <gtest/gtest.h>

#include <random>

#include "uavip/core/error.h"

namespace uavip::perception {
namespace {

/// A 6 m x 3 m wall x = 4 at 10 cm and a 0.4 m blob of 64 points 3.5 m in front of it.
PointList wallAndBlob() {
  std::mt19937 rng(9);
  std::normal_distribution<double> noise(0.0, 0.003);
  PointList pts;
  for (int i = 0; i <= 60; ++i) {
    for (int j = 0; j <= 30; ++j) pts.emplace_back(4.0 + noise(rng), -3.0 + 0.1 * i, 0.1 * j);
  }
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      for (int k = 0; k < 4; ++k) pts.emplace_back(0.2 + 0.1 * i, 0.1 * j, 1.0 + 0.1 * k);
    }
  }
  return pts;
}

TEST(SceneBuilder, WallBecomesASurfaceAndTheBlobAnObstacle) {
  const PointList clean = wallAndBlob();
  PerceptionOptions o;
  o.planes.cell_size_m = 0.1;
  PerceptionStats stats;
  const Scene scene = buildScene(clean, o, &stats);
  EXPECT_EQ(scene.cloud, clean);
  ASSERT_EQ(scene.surfaces.size(), 1u);
  // The wall faces the free side (where the viewpoint, the origin, is).
  EXPECT_LT((scene.surfaces[0].plane.normal - Vec3(-1, 0, 0)).norm(), 0.02);
  EXPECT_NEAR(scene.surfaces[0].plane.offset, 4.0, 0.01);
  ASSERT_GE(scene.obstacles.size(), 1u);
  EXPECT_EQ(scene.obstacles[0].points.size(), 64u);
  EXPECT_LT((scene.obstacles[0].aabb_min - Vec3(0.2, 0.0, 1.0)).norm(), 1e-9);
  EXPECT_LT((scene.obstacles[0].aabb_max - Vec3(0.5, 0.3, 1.3)).norm(), 1e-9);
  std::size_t total = scene.surfaces[0].inliers.size();
  for (const auto& ob : scene.obstacles) total += ob.points.size();
  EXPECT_EQ(total, clean.size());
  EXPECT_GE(stats.planes.candidates, 1);
  EXPECT_GE(stats.planes_seconds, 0.0);
  EXPECT_GE(stats.clusters_seconds, 0.0);
}

TEST(SceneBuilder, EmptyCloudGivesAnEmptyScene) {
  const Scene scene = buildScene({}, PerceptionOptions{});
  EXPECT_TRUE(scene.surfaces.empty());
  EXPECT_TRUE(scene.obstacles.empty());
  EXPECT_TRUE(scene.cloud.empty());
}

TEST(SceneBuilder, ValidateNamesTheKeyOfTheNestedField) {
  PerceptionOptions o;
  o.clusters.tolerance_m = -1.0;
  try {
    o.validate();
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    // The key a config file sets clusters.tolerance_m with.
    EXPECT_NE(std::string(e.what()).find("perception: obstacle_tolerance_m"), std::string::npos)
        << e.what();
  }
  o = {};
  o.planes.max_iterations = 0;
  EXPECT_THROW(buildScene({{0, 0, 0}}, o), InputError);
}

}  // namespace
}  // namespace uavip::perception
