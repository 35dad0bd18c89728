#include "uavip/perception/obstacle_clusterer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>
#include <set>

#include "uavip/core/error.h"

namespace uavip::perception {
namespace {

/// Brute-force O(n²) flood fill: i and j are connected when |pi - pj| <= tol.
std::vector<int> floodFillLabels(const PointList& pts, double tol) {
  std::vector<int> label(pts.size(), -1);
  int next = 0;
  for (std::size_t s = 0; s < pts.size(); ++s) {
    if (label[s] >= 0) continue;
    std::vector<std::size_t> stack = {s};
    label[s] = next;
    while (!stack.empty()) {
      const std::size_t i = stack.back();
      stack.pop_back();
      for (std::size_t j = 0; j < pts.size(); ++j) {
        if (label[j] < 0 && (pts[i] - pts[j]).norm() <= tol) {
          label[j] = next;
          stack.push_back(j);
        }
      }
    }
    ++next;
  }
  return label;
}

/// Partition as a set of sets of point indices.
using Partition = std::set<std::set<std::size_t>>;

Partition partitionOf(const std::vector<int>& labels) {
  std::map<int, std::set<std::size_t>> groups;
  for (std::size_t i = 0; i < labels.size(); ++i) groups[labels[i]].insert(i);
  Partition p;
  for (auto& [label, g] : groups) p.insert(g);
  return p;
}

/// Index of every obstacle point in `pts` (points are unique), checking each input
/// point appears exactly once.
Partition partitionOf(const std::vector<Obstacle>& obstacles, const PointList& pts) {
  std::map<std::tuple<double, double, double>, std::size_t> index;
  for (std::size_t i = 0; i < pts.size(); ++i) index[{pts[i].x(), pts[i].y(), pts[i].z()}] = i;
  Partition p;
  std::vector<int> seen(pts.size(), 0);
  for (const auto& o : obstacles) {
    std::set<std::size_t> g;
    for (const auto& q : o.points) {
      const auto it = index.find({q.x(), q.y(), q.z()});
      EXPECT_NE(it, index.end());
      if (it == index.end()) continue;
      g.insert(it->second);
      ++seen[it->second];
    }
    p.insert(g);
  }
  for (int s : seen) EXPECT_EQ(s, 1);
  return p;
}

PointList randomCloud(std::size_t n, double extent, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, extent);
  PointList pts;
  for (std::size_t i = 0; i < n; ++i) pts.emplace_back(u(rng), u(rng), u(rng));
  return pts;
}

TEST(ObstacleClusterer, SamePartitionAsBruteForceFloodFill) {
  for (std::uint32_t seed : {1u, 2u, 3u}) {
    const PointList pts = randomCloud(300, 4.0, seed);
    ClusterOptions o;
    o.tolerance_m = 0.45;
    const auto obstacles = clusterObstacles(pts, o);
    const Partition reference = partitionOf(floodFillLabels(pts, o.tolerance_m));
    EXPECT_GT(reference.size(), 3u);  // the test needs several clusters
    EXPECT_EQ(partitionOf(obstacles, pts), reference) << "seed " << seed;

    // Ids 0..n-1, largest first; boxes are the brute-force bounds.
    for (std::size_t i = 0; i < obstacles.size(); ++i) {
      EXPECT_EQ(obstacles[i].id, static_cast<int>(i));
      if (i > 0) {
        EXPECT_GE(obstacles[i - 1].points.size(), obstacles[i].points.size());
      }
      Vec3 lo = obstacles[i].points[0];
      Vec3 hi = lo;
      for (const auto& p : obstacles[i].points) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      }
      EXPECT_EQ(obstacles[i].aabb_min, lo);
      EXPECT_EQ(obstacles[i].aabb_max, hi);
    }
  }
}

TEST(ObstacleClusterer, SmallClustersMergeIntoOneResidual) {
  PointList pts;
  for (int i = 0; i < 30; ++i) pts.emplace_back(0.1 * i, 0.0, 0.0);   // 30 points, 2.9 m
  for (int i = 0; i < 20; ++i) pts.emplace_back(10.0, 0.1 * i, 0.0);  // 20 points
  pts.emplace_back(-10.0, -10.0, 0.0);                                // three singletons
  pts.emplace_back(20.0, 20.0, 5.0);
  pts.emplace_back(0.0, 20.0, -5.0);
  ClusterOptions o;
  o.tolerance_m = 0.15;
  o.min_points = 5;
  const auto obstacles = clusterObstacles(pts, o);
  ASSERT_EQ(obstacles.size(), 3u);
  EXPECT_EQ(obstacles[0].points.size(), 30u);
  EXPECT_EQ(obstacles[1].points.size(), 20u);
  EXPECT_EQ(obstacles[2].points.size(), 3u);
  EXPECT_EQ(obstacles[2].aabb_min, Vec3(-10.0, -10.0, -5.0));
  EXPECT_EQ(obstacles[2].aabb_max, Vec3(20.0, 20.0, 5.0));
  std::size_t total = 0;
  for (const auto& ob : obstacles) total += ob.points.size();
  EXPECT_EQ(total, pts.size());

  // With min_points 1 the singletons are obstacles of their own.
  o.min_points = 1;
  EXPECT_EQ(clusterObstacles(pts, o).size(), 5u);
}

TEST(ObstacleClusterer, EqualSizesOrderedBySmallestCoordinate) {
  const PointList pts = {{5, 0, 0}, {5.1, 0, 0}, {-3, 1, 0}, {-3, 1.1, 0}, {0, 7, 0}, {0, 7, 0.1}};
  ClusterOptions o;
  o.tolerance_m = 0.2;
  const auto obstacles = clusterObstacles(pts, o);
  ASSERT_EQ(obstacles.size(), 3u);
  EXPECT_EQ(obstacles[0].aabb_min.x(), -3.0);
  EXPECT_EQ(obstacles[1].aabb_min.x(), 0.0);
  EXPECT_EQ(obstacles[2].aabb_min.x(), 5.0);
  // Input order does not change the result.
  PointList reversed(pts.rbegin(), pts.rend());
  const auto again = clusterObstacles(reversed, o);
  ASSERT_EQ(again.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(again[i].aabb_min, obstacles[i].aabb_min);
    EXPECT_EQ(again[i].aabb_max, obstacles[i].aabb_max);
  }
}

TEST(ObstacleClusterer, EmptyInputAndBadOptions) {
  EXPECT_TRUE(clusterObstacles({}, ClusterOptions{}).empty());
  ClusterOptions o;
  o.tolerance_m = 0.0;
  try {
    clusterObstacles({{0, 0, 0}}, o);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("tolerance_m"), std::string::npos) << e.what();
  }
  o = {};
  o.min_points = 0;
  EXPECT_THROW(o.validate(), InputError);
}

}  // namespace
}  // namespace uavip::perception
