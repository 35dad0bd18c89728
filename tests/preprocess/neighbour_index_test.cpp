#include "uavip/core/neighbour_index.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include "uavip/core/error.h"
#include "uavip/preprocess/cloud_stats.h"
#include "uavip/preprocess/filters.h"

namespace uavip::preprocess {
namespace {

/// A noisy 2 m × 2 m wall far from the origin (the float frame must keep
/// millimetres) with a sprinkle of stray points.
PointList wallWithStrays(std::size_t n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 2.0);
  std::normal_distribution<double> noise(0.0, 0.003);
  PointList pts;
  for (std::size_t i = 0; i < n; ++i)
    pts.emplace_back(4.0e5 + u(rng), 5.0e6 + noise(rng), 120.0 + u(rng));
  for (int i = 0; i < 20; ++i)
    pts.emplace_back(4.0e5 + u(rng), 5.0e6 + 0.3 + u(rng), 120.0 + u(rng));
  return pts;
}

TEST(NeighbourIndex, NearestMatchesBruteForce) {
  const PointList pts = wallWithStrays(3000, 5);
  const NeighbourIndex index(pts);
  constexpr int k = 9;
  std::vector<int> idx;
  std::vector<float> d2;
  for (std::size_t i = 0; i < pts.size(); i += 97) {
    index.nearest(i, k, idx, d2);
    ASSERT_EQ(idx.size(), static_cast<std::size_t>(k));
    std::vector<double> brute;
    for (const auto& p : pts) brute.push_back((p - pts[i]).norm());
    std::sort(brute.begin(), brute.end());
    for (int j = 0; j < k; ++j) {
      EXPECT_NEAR((pts[static_cast<std::size_t>(idx[static_cast<std::size_t>(j)])] - pts[i]).norm(),
                  brute[static_cast<std::size_t>(j)], 1e-5)
          << "point " << i << " neighbour " << j;
      EXPECT_NEAR(std::sqrt(d2[static_cast<std::size_t>(j)]), brute[static_cast<std::size_t>(j)],
                  1e-5);
    }
  }
  // Fewer points than k: every point, itself first.
  const PointList three{{0, 0, 0}, {1, 0, 0}, {0, 2, 0}};
  const NeighbourIndex small(three);
  small.nearest(2, 5, idx, d2);
  ASSERT_EQ(idx.size(), 3u);
  EXPECT_EQ(idx[0], 2);
}

TEST(NeighbourIndex, SharedTreeGivesTheSameFilterAndMeasurement) {
  const PointList pts = wallWithStrays(5000, 9);
  const NeighbourIndex index(pts);
  EXPECT_EQ(removeStatisticalOutliers(pts, 16, 2.0, 2, &index),
            removeStatisticalOutliers(pts, 16, 2.0, 2));
  const CloudStats own = measureCloud(pts);
  const CloudStats shared = measureCloud(pts, {}, &index);
  EXPECT_EQ(own.spacing_m, shared.spacing_m);
  EXPECT_EQ(own.noise_m, shared.noise_m);
  EXPECT_EQ(own.station_ratio, shared.station_ratio);
  // An index over another cloud is a programming error, not bad input.
  const PointList copy = pts;
  EXPECT_THROW(removeStatisticalOutliers(copy, 16, 2.0, 2, &index), std::invalid_argument);
  EXPECT_THROW(measureCloud(copy, {}, &index), std::invalid_argument);
}

TEST(NeighbourIndex, EmptyOrNonFiniteCloudIsBadInput) {
  EXPECT_THROW(NeighbourIndex(PointList{}), InputError);
  PointList bad{{0, 0, 0}, {1, std::nan(""), 0}};
  try {
    const NeighbourIndex index(bad);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("point 1 is not finite"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace uavip::preprocess
