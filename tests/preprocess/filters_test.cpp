#include "uavip/preprocess/filters.h"

#include <gtest/gtest.h>
#include <pcl/filters/statistical_outlier_removal.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <random>
#include <set>
#include <tuple>
#include <vector>

#include "uavip/core/error.h"

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
  const PointList planted = {
      {1.2, 1.2, 3.0}, {-4.0, 0.5, 0.0}, {0.3, 6.0, -2.0}, {5.0, 5.0, 5.0}, {1.0, -3.0, 1.0}};
  for (const auto& p : planted) cloud.push_back(p);

  const PointList out = removeStatisticalOutliers(cloud, 16, 2.0);
  for (const auto& p : planted) {
    for (const auto& q : out)
      EXPECT_FALSE(q.isApprox(p)) << "planted outlier kept: " << p.transpose();
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

/// A scene whose neighbour statistic is a continuum, so that mu + d_t·sigma cuts
/// through it: a floor sampled at random with a density falling along x, a noisy
/// wall, a pole (a line of points) and duplicated points, plus `planted` isolated
/// outliers 0.6 m above the floor, 0.25 m apart (also returned in `outliers`).
PointList mixedScene(std::size_t planted, std::uint32_t seed, PointList* outliers) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.004);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  PointList cloud;
  for (int i = 0; i < 3000; ++i) {  // floor 3 m x 1.5 m, density ~ (1 - x/3.3)^2
    const double x = 3.3 * (1.0 - std::sqrt(u(rng)));
    cloud.emplace_back(std::min(x, 3.0), 1.5 * u(rng), noise(rng));
  }
  for (int i = 0; i < 30; ++i) {  // wall x = 3.2 m, 3 m x 1.5 m at 10 cm
    for (int j = 0; j < 15; ++j)
      cloud.emplace_back(3.2 + noise(rng), 0.1 * i - 0.5, 0.1 * j + 0.05);
  }
  for (int i = 0; i < 200; ++i) cloud.emplace_back(1.5, -0.3, 0.01 * i);  // pole, 1 cm steps
  for (int i = 0; i < 20; ++i) cloud.push_back(cloud[1000]);              // duplicates
  for (std::size_t i = 0; i < planted; ++i) {
    const Vec3 p(0.1 + 0.25 * static_cast<double>(i), 0.75, 0.6);
    cloud.push_back(p);
    if (outliers != nullptr) outliers->push_back(p);
  }
  return cloud;
}

/// The reference: pcl::StatisticalOutlierRemoval on the cloud shifted to its lower
/// bounding corner (PCL stores floats), kept points in input order.
PointList pclStatisticalOutlierRemoval(const PointList& cloud, int k, double std_ratio) {
  Vec3 lo = cloud.front();
  for (const auto& p : cloud) lo = lo.cwiseMin(p);
  auto pc = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  for (const auto& p : cloud) {
    const Vec3 q = p - lo;
    pc->push_back(pcl::PointXYZ(static_cast<float>(q.x()), static_cast<float>(q.y()),
                                static_cast<float>(q.z())));
  }
  pcl::StatisticalOutlierRemoval<pcl::PointXYZ> sor;
  sor.setInputCloud(pc);
  sor.setMeanK(k);
  sor.setStddevMulThresh(std_ratio);
  pcl::Indices kept;
  sor.filter(kept);
  PointList out;
  for (const auto i : kept) out.push_back(cloud[static_cast<std::size_t>(i)]);
  return out;
}

bool contains(const PointList& cloud, const Vec3& p) {
  return std::find(cloud.begin(), cloud.end(), p) != cloud.end();
}

TEST(StatisticalOutliers, KeepsExactlyThePointsPclKeepsWithAnyThreadCount) {
  PointList outliers;
  const PointList cloud = mixedScene(12, 11, &outliers);
  for (const double ratio : {2.0, 1.0}) {
    const PointList reference = pclStatisticalOutlierRemoval(cloud, 16, ratio);
    // The threshold cuts the continuum, not just the planted outliers.
    ASSERT_GT(cloud.size() - reference.size(), outliers.size() + 20);
    for (const int threads : {1, 2, 3}) {
      const PointList out = removeStatisticalOutliers(cloud, 16, ratio, threads);
      EXPECT_EQ(out, reference) << "ratio " << ratio << ", " << threads
                                << " threads: " << out.size() << " kept, PCL keeps "
                                << reference.size();
    }
  }
  const PointList out = removeStatisticalOutliers(cloud, 16, 2.0);
  for (const auto& p : outliers)
    EXPECT_FALSE(contains(out, p)) << "planted outlier kept: " << p.transpose();
}

TEST(StatisticalOutliers, KeepsExactlyThePointsPclKeepsFarFromTheOrigin) {
  // Geo-referenced coordinates (UTM-like), a cloud big enough to use both threads.
  PointList outliers;
  PointList cloud = mixedScene(8, 12, &outliers);
  PointList more = noisyPlane(90, 90, 0.03, 0.003, 13);  // second floor, 2.7 m x 2.7 m
  for (auto& p : more) p += Vec3(0.0, 2.0, 1.0);
  cloud.insert(cloud.begin(), more.begin(), more.end());
  const Vec3 base(500000.0, 5000000.0, 100.0);
  for (auto& p : cloud) p += base;
  for (auto& p : outliers) p += base;
  const PointList out = removeStatisticalOutliers(cloud, 16, 2.0, 2);
  EXPECT_EQ(out, pclStatisticalOutlierRemoval(cloud, 16, 2.0));
  for (const auto& p : outliers)
    EXPECT_FALSE(contains(out, p)) << "planted outlier kept: " << p.transpose();
}

TEST(StatisticalOutliers, AgreesWithABruteForceStatistic) {
  // Brute force in double: mean distance to the k nearest other points, then
  // mu + 2 sigma (sample sigma). Points clearly above the threshold must go, points
  // clearly below must stay (the filter works in float: a thin band is not checked).
  PointList outliers;
  const PointList cloud = mixedScene(10, 21, &outliers);
  const int k = 8;
  const std::size_t n = cloud.size();
  std::vector<double> mean_dist(n);
  std::vector<double> d(n);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < n; ++j) d[j] = (cloud[i] - cloud[j]).norm();
    d[i] = std::numeric_limits<double>::infinity();  // not its own neighbour
    std::partial_sort(d.begin(), d.begin() + k, d.end());
    double s = 0.0;
    for (int j = 0; j < k; ++j) s += d[static_cast<std::size_t>(j)];
    mean_dist[i] = s / k;
  }
  double mu = 0.0;
  for (const double m : mean_dist) mu += m / static_cast<double>(n);
  double var = 0.0;
  for (const double m : mean_dist) var += (m - mu) * (m - mu) / static_cast<double>(n - 1);
  const double threshold = mu + 2.0 * std::sqrt(var);

  const PointList out = removeStatisticalOutliers(cloud, k, 2.0, 2);
  std::size_t checked = 0;
  std::size_t j = 0;  // out is a subsequence of cloud
  for (std::size_t i = 0; i < n; ++i) {
    const bool kept = j < out.size() && out[j] == cloud[i];
    if (kept) ++j;
    if (mean_dist[i] > threshold * (1.0 + 1e-5)) {
      EXPECT_FALSE(kept) << "point " << i << " mean distance " << mean_dist[i] << " > "
                         << threshold;
      ++checked;
    } else if (mean_dist[i] < threshold * (1.0 - 1e-5)) {
      EXPECT_TRUE(kept) << "point " << i << " mean distance " << mean_dist[i] << " < " << threshold;
      ++checked;
    }
  }
  EXPECT_EQ(j, out.size()) << "output is not a subsequence of the input";
  EXPECT_GE(checked, n - 5);
  for (const auto& p : outliers)
    EXPECT_FALSE(contains(out, p)) << "planted outlier kept: " << p.transpose();
}

TEST(StatisticalOutliers, BadArgumentsThrow) {
  PointList cloud = noisyPlane(6, 6, 0.1, 0.0, 1);
  EXPECT_THROW(removeStatisticalOutliers(cloud, 4, 2.0, 0), InputError);
  EXPECT_THROW(removeStatisticalOutliers(cloud, 0, 2.0), InputError);
  EXPECT_THROW(removeStatisticalOutliers(cloud, 4, 0.0), InputError);
  cloud[3].z() = std::numeric_limits<double>::quiet_NaN();
  try {
    removeStatisticalOutliers(cloud, 4, 2.0);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("point 3"), std::string::npos) << e.what();
  }
  PreprocessOptions o;
  o.threads = 0;
  EXPECT_THROW(o.validate(), InputError);
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

TEST(VoxelGrid, TwoThreadsGiveTheOneThreadOutput) {
  // 300 k points (the two-thread path: keys by slices, the sort and the centroids in
  // halves): the same points in the same order, bit for bit.
  std::mt19937 rng(41);
  std::uniform_real_distribution<double> u(-20.0, 20.0);
  PointList cloud(300000);
  for (auto& p : cloud) p = Vec3(u(rng), u(rng), 0.1 * u(rng));
  const PointList one = voxelGrid(cloud, 0.3, 1);
  EXPECT_EQ(voxelGrid(cloud, 0.3, 2), one);
  EXPECT_GT(one.size(), 10000u);
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

TEST(VoxelGrid, ExtentBeyondA32BitIndexWorks) {
  // 10 km at 1 cm: 1e18 voxels in all (PCL's 32-bit index overflows), 1e6 per axis.
  const PointList cloud = {{0, 0, 0}, {0.004, 0.004, 0.004}, {10000, 10000, 10000}};
  const PointList out = voxelGrid(cloud, 0.01);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_LT((out[0] - Vec3(0.002, 0.002, 0.002)).norm(), 1e-9);
  EXPECT_LT((out[1] - cloud[2]).norm(), 1e-9);
}

TEST(VoxelGrid, HugeExtentForTinyLeafThrows) {
  const PointList cloud = {{0, 0, 0}, {100000, 10, 10}};  // 1e7 voxels on x > 2^21
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
  for (auto& p : cloud) p += Vec3(0.0125, 0.0125, 0.05);  // away from voxel borders
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
