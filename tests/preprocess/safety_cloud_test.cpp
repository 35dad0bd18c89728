// The safety cloud against brute force: every input point lies within margin_m of a
// safety point, every safety point is an input point, and nothing depends on order.

#include "uavip/preprocess/safety_cloud.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "uavip/core/error.h"

namespace uavip::preprocess {
namespace {

PointList randomCloud(std::size_t n, double extent, std::uint32_t seed,
                      const Vec3& offset = Vec3::Zero()) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, extent);
  PointList pts;
  for (std::size_t i = 0; i < n; ++i) pts.push_back(offset + Vec3(u(rng), u(rng), 0.2 * u(rng)));
  return pts;
}

double nearest(const Vec3& p, const PointList& cloud) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& q : cloud) best = std::min(best, (p - q).norm());
  return best;
}

TEST(SafetyCloud, EveryInputPointLiesWithinTheMarginOfASafetyPoint) {
  const PointList raw = randomCloud(3000, 1.0, 7);
  const SafetyCloud s = safetyCloud(raw, 0.05);
  EXPECT_EQ(s.input_points, raw.size());
  EXPECT_NEAR(s.margin_m, std::sqrt(3.0) * 0.05, 1e-6);
  ASSERT_LT(s.points.size(), raw.size());  // thinned: 3000 points in ≤ 20·20·4 cells
  double worst = 0.0;
  for (const auto& p : raw) worst = std::max(worst, nearest(p, s.points));
  EXPECT_LE(worst, s.margin_m);
  EXPECT_GT(worst, 0.3 * s.margin_m);  // the bound is not vacuous on this cloud
}

TEST(SafetyCloud, SafetyPointsAreInputPointsRoundedToFloat) {
  const PointList raw = randomCloud(500, 3.0, 11);
  for (const auto& q : safetyCloud(raw, 0.05).points) {
    EXPECT_LE(nearest(q, raw), 1e-6);
    EXPECT_EQ(q.x(), static_cast<double>(static_cast<float>(q.x())));
  }
}

TEST(SafetyCloud, ASparseCloudKeepsEveryPoint) {
  // 2 m apart on a line: no two points share a 2 cm cell, so the outliers stage 3
  // would drop all stay.
  PointList raw;
  for (int i = 0; i < 50; ++i) raw.emplace_back(2.0 * i, 0.5, 1.0);
  EXPECT_EQ(safetyCloud(raw, 0.02).points.size(), raw.size());
}

TEST(SafetyCloud, TheResultDoesNotDependOnTheInputOrder) {
  PointList raw = randomCloud(2000, 2.0, 3);
  const PointList a = safetyCloud(raw, 0.1).points;
  std::reverse(raw.begin(), raw.end());
  const PointList b = safetyCloud(raw, 0.1).points;
  ASSERT_EQ(a.size(), b.size());
  // Each cell keeps its first point, so the chosen points differ; the cells do not.
  for (const auto& p : a) EXPECT_LE(nearest(p, b), std::sqrt(3.0) * 0.1);
}

TEST(SafetyCloud, FarFromTheOriginTheMarginCountsTheFloatRounding) {
  const PointList raw = randomCloud(200, 1.0, 5, Vec3(500000.0, 5400000.0, 0.0));
  const SafetyCloud s = safetyCloud(raw, 0.02);
  double worst = 0.0;
  for (const auto& p : raw) worst = std::max(worst, nearest(p, s.points));
  EXPECT_LE(worst, s.margin_m);
}

TEST(SafetyCloud, AHugeExtentGrowsTheCellInsteadOfFailing) {
  const PointList raw = {Vec3::Zero(), Vec3(1e6, 0.0, 0.0)};
  const SafetyCloud s = safetyCloud(raw, 0.02);
  EXPECT_GT(s.cell_m, 0.02);
  EXPECT_EQ(s.points.size(), 2u);
}

TEST(SafetyCloud, BadInputIsRefused) {
  EXPECT_THROW(safetyCloud({Vec3(0.0, std::nan(""), 0.0)}, 0.02), InputError);
  EXPECT_THROW(safetyCloud({Vec3::Zero()}, 0.0), InputError);
  SafetyOptions o;
  o.cell_m = -1.0;
  EXPECT_THROW(o.validate(), InputError);
  o = {};
  o.sparse_factor = std::nan("");
  EXPECT_THROW(o.validate(), InputError);
}

TEST(SafetyCloud, MarginAddsTheSparseShareOfTheSpacing) {
  SafetyCloud s;
  s.margin_m = 0.03;
  SafetyOptions o;
  o.sparse_factor = 0.5;
  EXPECT_DOUBLE_EQ(safetyMargin(s, 0.4, o), 0.03 + 0.2);
  EXPECT_DOUBLE_EQ(safetyMargin(s, 0.0, o), 0.03);
}

}  // namespace
}  // namespace uavip::preprocess
