#include "uavip/planning/path_simplifier.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>

#include "planners/astar.h"
#include "uavip/core/geometry.h"

namespace uavip::planning {
namespace {

using world::GridOptions;
using world::VoxelGrid;

/// A wall of points x = 2, y ∈ [−1, 3], z ∈ [0, 2] in a padded grid.
PointList wallCloud() {
  PointList cloud;
  for (double y = -1.0; y <= 3.0001; y += 0.1)
    for (double z = 0.0; z <= 2.0001; z += 0.1) cloud.emplace_back(2.0, y, z);
  return cloud;
}

TEST(PathSimplifier, ShortcutsKeepEndsLengthAndClearance) {
  const PointList cloud = wallCloud();
  GridOptions o;
  o.resolution_m = 0.2;
  o.inflation_radius_m = 0.3;
  o.padding_m = 1.5;
  const VoxelGrid grid = VoxelGrid::build(cloud, {Vec3(0.0, -2.0, 0.0), Vec3(4.0, 3.5, 2.5)}, o);
  planners::AStarPlanner planner(planners::AStarOptions{});
  const std::vector<std::pair<Vec3, Vec3>> legs = {
      {Vec3(0.0, 0.0, 1.0), Vec3(4.0, 1.0, 1.0)},   // around the wall
      {Vec3(0.0, -2.0, 0.5), Vec3(0.5, 3.5, 2.5)},  // along it
      {Vec3(0.3, 0.1, 0.1), Vec3(3.9, 2.8, 1.7)}};
  for (const auto& [a, b] : legs) {
    const PathResult r = planner.plan(grid, a, b);
    ASSERT_TRUE(r.solved()) << planning::toString(r.status);
    const PointList s = simplifyPath(r.path, grid);
    ASSERT_GE(s.size(), 2u);
    EXPECT_EQ(s.front(), r.path.front());
    EXPECT_EQ(s.back(), r.path.back());
    EXPECT_LE(polylineLength(s), polylineLength(r.path) + 1e-12);
    EXPECT_LT(s.size(), r.path.size());
    // Kept points are a subsequence of the raw path; each segment is a raw step or
    // a free line of sight, and keeps the clearance from every measured point.
    std::size_t pos = 0;
    for (std::size_t i = 0; i < s.size(); ++i) {
      const auto it =
          std::find(r.path.begin() + static_cast<std::ptrdiff_t>(pos), r.path.end(), s[i]);
      ASSERT_NE(it, r.path.end());
      const auto next = static_cast<std::size_t>(it - r.path.begin());
      if (i > 0) {
        EXPECT_TRUE(next == pos + 1 || grid.segmentFree(s[i - 1], s[i]));
        double d = std::numeric_limits<double>::infinity();
        for (const auto& p : cloud) d = std::min(d, pointSegmentDistance(p, s[i - 1], s[i]));
        EXPECT_GE(d, o.inflation_radius_m);
      }
      pos = next;
    }
  }
}

TEST(PathSimplifier, RandomWorldsRawAndSimplifiedKeepClearance) {
  // The grid's safety argument, checked by brute force: every raw step (exact ends
  // included) and every shortcut keeps >= r from every measured point.
  std::mt19937 rng(77);
  std::uniform_real_distribution<double> u(0.0, 4.0);
  int planned = 0;
  for (int world = 0; world < 4; ++world) {
    PointList cloud;
    for (int i = 0; i < 40; ++i) cloud.emplace_back(u(rng), u(rng), u(rng));
    GridOptions o;
    o.resolution_m = 0.25;
    o.inflation_radius_m = 0.2 + 0.1 * world;
    o.padding_m = 1.0;
    const VoxelGrid grid = VoxelGrid::build(cloud, {}, o);
    planners::AStarOptions ao;
    ao.cost = world % 2 ? planners::AStarCost::Euclidean : planners::AStarCost::Paper;
    planners::AStarPlanner planner(ao);
    std::uniform_real_distribution<double> v(-0.9, 4.9);
    for (int k = 0; k < 25; ++k) {
      const Vec3 a(v(rng), v(rng), v(rng)), b(v(rng), v(rng), v(rng));
      const PathResult r = planner.plan(grid, a, b);
      if (!r.solved()) continue;
      ++planned;
      for (const PointList& path : {r.path, simplifyPath(r.path, grid)}) {
        for (std::size_t i = 0; i + 1 < path.size(); ++i) {
          double d = std::numeric_limits<double>::infinity();
          for (const auto& p : cloud)
            d = std::min(d, pointSegmentDistance(p, path[i], path[i + 1]));
          EXPECT_GE(d, o.inflation_radius_m)
              << "world " << world << " leg " << k << " segment " << i;
        }
      }
    }
  }
  EXPECT_GT(planned, 30);
}

TEST(PathSimplifier, StraightFreeRunCollapsesAndShortInputsStay) {
  GridOptions o;
  o.resolution_m = 0.5;
  o.padding_m = 0.0;
  const VoxelGrid grid = VoxelGrid::build({}, {Vec3(0, 0, 0), Vec3(10, 10, 10)}, o);
  PointList line;
  for (int i = 0; i <= 12; ++i) line.emplace_back(0.25 + 0.5 * i, 1.0 + 0.25 * i, 3.0);
  EXPECT_EQ(simplifyPath(line, grid), (PointList{line.front(), line.back()}));
  const PointList two = {Vec3(1, 1, 1), Vec3(2, 2, 2)};
  EXPECT_EQ(simplifyPath(two, grid), two);
  EXPECT_TRUE(simplifyPath({}, grid).empty());
}

}  // namespace
}  // namespace uavip::planning
