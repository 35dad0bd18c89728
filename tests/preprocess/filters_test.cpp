#include "uavip/preprocess/filters.h"

#include "uavip/core/error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <tuple>

namespace uavip::preprocess {
namespace {

/// Grid of points on the plane z = 0 (spacing step, nx × ny) with Gaussian noise in z.
PointList noisyPlane(int nx, int ny, double step, double sigma, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma);
  PointList pts;
  for (int i = 0; i < nx; ++i) {
    for (int j = 0; j < ny; ++j) pts.emplace_back(i * step, j * step, noise(rng));
  }
  return pts;
}

TEST(StatisticalOutliers, RemovesFarIsolatedPointsAndKeepsThePlane) {
  PointList cloud = noisyPlane(50, 50, 0.05, 0.005, 7);  // 2.5 m x 2.5 m, 2500 points
  const std::size_t plane_points = cloud.size();
  const PointList planted = {{1.2, 1.2, 3.0}, {-4.0, 0.5, 0.0}, {0.3, 6.0, -2.0},
                             {5.0, 5.0, 5.0}, {1.0, -3.0, 1.0}};
  for (const auto& p : planted) cloud.push_back(p);

  const PointList out = removeStatisticalOutliers(cloud, 16, 2.0);
  for (const auto& p : planted) {
    for (const auto& q : out) EXPECT_FALSE(q.isApprox(p)) << "planted outlier kept: " << p.transpose();
  }
  std::size_t kept_plane = 0;
  for (const auto& q : out) kept_plane += std::abs(q.z()) < 0.1 ? 1 : 0;
  EXPECT_GE(static_cast<double>(kept_plane), 0.95 * static_cast<double>(plane_points));
  // The output is a subset of the input, in input order.
  std::size_t j = 0;
  for (const auto& q : out) {
    while (j < cloud.size() && cloud[j] != q) ++j;
    ASSERT_LT(j, cloud.size()) << "output point not in input order";
    ++j;
  }
}

TEST(StatisticalOutliers, SmallCloudIsUnchanged) {
  const PointList cloud = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {100, 100, 100}};
  EXPECT_EQ(removeStatisticalOutliers(cloud, 4, 1.0), cloud);
  EXPECT_EQ(removeStatisticalOutliers(cloud, 16, 1.0), cloud);
}

TEST(VoxelGrid, EachOutputIsTheCentroidOfItsVoxel) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  PointList cloud;
  for (int i = 0; i < 600; ++i) cloud.emplace_back(u(rng), u(rng), 0.5 * u(rng));
  const double leaf = 0.3;

  // Brute force: voxel key floor(p / leaf), centroid per key.
  std::map<std::tuple<long, long, long>, std::pair<Vec3, int>> voxels;
  for (const auto& p : cloud) {
    const auto key = std::make_tuple(static_cast<long>(std::floor(p.x() / leaf)),
                                     static_cast<long>(std::floor(p.y() / leaf)),
                                     static_cast<long>(std::floor(p.z() / leaf)));
    auto& [sum, count] = voxels[key];
    if (count == 0) sum = Vec3::Zero();
    sum += p;
    ++count;
  }

  const PointList out = voxelGrid(cloud, leaf);
  ASSERT_EQ(out.size(), voxels.size());
  std::set<std::tuple<long, long, long>> seen;
  for (const auto& q : out) {
    const auto key = std::make_tuple(static_cast<long>(std::floor(q.x() / leaf)),
                                     static_cast<long>(std::floor(q.y() / leaf)),
                                     static_cast<long>(std::floor(q.z() / leaf)));
    const auto it = voxels.find(key);
    ASSERT_NE(it, voxels.end());
    const Vec3 centroid = it->second.first / it->second.second;
    EXPECT_LT((q - centroid).norm(), 1e-4);
    EXPECT_TRUE(seen.insert(key).second) << "two outputs in one voxel";
  }
  // Deterministic.
  EXPECT_EQ(voxelGrid(cloud, leaf), out);
}

TEST(VoxelGrid, FarFromOriginKeepsPrecision) {
  // Geo-referenced coordinates: centroids stay exact to well below a millimetre.
  const Vec3 base(500000.0, 5000000.0, 100.0);
  const PointList cloud = {base + Vec3(0.01, 0.01, 0.01), base + Vec3(0.03, 0.03, 0.03),
                           base + Vec3(1.01, 0.01, 0.01)};
  const PointList out = voxelGrid(cloud, 0.5);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_LT((out[0] - (base + Vec3(0.02, 0.02, 0.02))).norm(), 1e-3);
  EXPECT_LT((out[1] - cloud[2]).norm(), 1e-3);
}

TEST(VoxelGrid, HugeExtentForTinyLeafThrows) {
  const PointList cloud = {{0, 0, 0}, {10000, 10000, 10000}};
  try {
    voxelGrid(cloud, 0.01);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("voxel_m"), std::string::npos) << e.what();
  }
}

TEST(Preprocess, EmptyCloudThrows) {
  try {
    preprocess({}, PreprocessOptions{});
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("empty"), std::string::npos) << e.what();
  }
}

TEST(Preprocess, NonFinitePointThrowsNamingTheIndex) {
  PointList cloud = noisyPlane(5, 5, 0.1, 0.0, 1);
  cloud[7].y() = std::numeric_limits<double>::quiet_NaN();
  try {
    preprocess(cloud, PreprocessOptions{});
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("7"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("nan"), std::string::npos) << e.what();
  }
  cloud[7].y() = std::numeric_limits<double>::infinity();
  EXPECT_THROW(preprocess(cloud, PreprocessOptions{}), InputError);
}

TEST(Preprocess, BadOptionsThrowNamingTheField) {
  const PointList cloud = noisyPlane(5, 5, 0.1, 0.0, 1);
  PreprocessOptions o;
  o.voxel_m = 0.0;
  try {
    preprocess(cloud, o);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("voxel_m"), std::string::npos) << e.what();
  }
  o = PreprocessOptions{};
  o.outlier_k = 0;
  EXPECT_THROW(o.validate(), InputError);
  o = PreprocessOptions{};
  o.outlier_std_ratio = -1.0;
  EXPECT_THROW(o.validate(), InputError);
}

TEST(Preprocess, StatsAndStages) {
  PointList cloud = noisyPlane(40, 40, 0.025, 0.001, 5);  // 1 m x 1 m at 2.5 cm
  for (auto& p : cloud) p += Vec3(0.0125, 0.0125, 0.05);   // away from voxel borders
  cloud.emplace_back(0.5, 0.5, 4.0);                      // one far outlier
  PreprocessOptions o;
  o.voxel_m = 0.1;
  PreprocessStats stats;
  const PointList out = preprocess(cloud, o, &stats);
  EXPECT_EQ(stats.input_points, cloud.size());
  EXPECT_LT(stats.after_outliers, cloud.size());
  EXPECT_EQ(stats.output_points, out.size());
  // 1 m x 1 m (0 .. 0.975) at 10 cm voxels: 10 x 10 occupied voxels, all on the plane.
  EXPECT_EQ(out.size(), 100u);
  for (const auto& p : out) EXPECT_LT(std::abs(p.z() - 0.05), 0.01);

  o.remove_outliers = false;
  o.voxelize = false;
  EXPECT_EQ(preprocess(cloud, o, &stats), cloud);
  EXPECT_EQ(stats.after_outliers, cloud.size());
}

}  // namespace
}  // namespace uavip::preprocess
