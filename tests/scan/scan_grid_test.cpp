// ScanGrid (stage 1's 2D nearest-neighbour grid) against brute force, on both of its
// layouts: the dense array and the hash map it falls back to for a large box.

#include "uavip/scan/scan_grid.h"

#include <gtest/gtest.h>

#include <limits>
#include <random>
#include <vector>

#include "uavip/core/error.h"

namespace uavip::scan {
namespace {

using Vec2 = Eigen::Vector2d;

/// Squared distance to the nearest point strictly within `cell` of q (inf if none).
double bruteForce(const std::vector<Vec2>& pts, const Vec2& q, double cell) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& p : pts) {
    const double d2 = (p - q).squaredNorm();
    if (d2 < cell * cell) best = std::min(best, d2);
  }
  return best;
}

/// A scan-like cloud: two walls, a clump of repeated points (ties), scattered returns.
std::vector<Vec2> scanLikeCloud(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Vec2> pts;
  pts.reserve(1020);
  for (int i = 0; i < 400; ++i) pts.emplace_back(4.0 + 0.01 * u(rng), 3.0 * u(rng));
  for (int i = 0; i < 400; ++i) pts.emplace_back(3.0 * u(rng) - 1.0, -2.0 + 0.01 * u(rng));
  for (int i = 0; i < 20; ++i) pts.emplace_back(0.5, 0.5);
  for (int i = 0; i < 200; ++i) pts.emplace_back(6.0 * u(rng), 6.0 * u(rng));
  return pts;
}

TEST(ScanGrid, NearestMatchesBruteForceOnBothLayouts) {
  std::mt19937 rng(7);
  const std::vector<Vec2> pts = scanLikeCloud(rng);
  const double cell = 0.3;
  const ScanGrid dense(pts, cell);
  const ScanGrid sparse(pts, cell, /*max_dense_cells=*/1.0);
  ASSERT_TRUE(dense.dense());
  ASSERT_FALSE(sparse.dense());
  std::uniform_real_distribution<double> u(-8.0, 8.0);
  int found = 0;
  for (int k = 0; k < 5000; ++k) {
    const Vec2 q(u(rng), u(rng));
    const double want = bruteForce(pts, q, cell);
    const int i = dense.nearest(q);
    EXPECT_EQ(sparse.nearest(q), i) << "the layouts disagree at " << q.transpose();
    if (std::isinf(want)) {
      EXPECT_EQ(i, -1) << q.transpose();
      continue;
    }
    ASSERT_GE(i, 0) << q.transpose();
    EXPECT_EQ((pts[static_cast<std::size_t>(i)] - q).squaredNorm(), want) << q.transpose();
    ++found;
  }
  EXPECT_GT(found, 500);  // the queries do reach the points
}

TEST(ScanGrid, AStrayFarReturnSwitchesToTheHashMapAndStillFindsEveryPoint) {
  // 0.05 m cells over a 10 km square: far more cells than the dense bound.
  const std::vector<Vec2> pts{{0.0, 0.0}, {0.02, 0.0}, {10000.0, 10000.0}};
  const ScanGrid grid(pts, 0.05);
  EXPECT_FALSE(grid.dense());
  EXPECT_EQ(grid.nearest(Vec2(0.021, 0.0)), 1);
  EXPECT_EQ(grid.nearest(Vec2(10000.01, 10000.0)), 2);
  EXPECT_EQ(grid.nearest(Vec2(5000.0, 5000.0)), -1);
}

TEST(ScanGrid, EmptyAndNonFinite) {
  const std::vector<Vec2> none;
  EXPECT_EQ(ScanGrid(none, 0.5).nearest(Vec2(1.0, 2.0)), -1);
  const std::vector<Vec2> bad{{std::numeric_limits<double>::quiet_NaN(), 0.0}};
  EXPECT_THROW(ScanGrid(bad, 0.5), InputError);
}

}  // namespace
}  // namespace uavip::scan
