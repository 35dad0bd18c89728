// Euclidean clustering against PCL's EuclideanClusterExtraction (the reference
// partition) and against hand-built cases.

#include "uavip/perception/euclidean_clusters.h"

#include <gtest/gtest.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/extract_clusters.h>

#include <algorithm>
#include <limits>
#include <numeric>
#include <random>

#include "uavip/core/error.h"

namespace uavip::perception {
namespace {

/// PCL's clusters of points[indices], each sorted, ordered by smallest index.
std::vector<std::vector<int>> pclClusters(const PointList& points, const std::vector<int>& indices,
                                          double tol) {
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  for (const auto& p : points) {
    cloud->push_back(pcl::PointXYZ(static_cast<float>(p.x()), static_cast<float>(p.y()),
                                   static_cast<float>(p.z())));
  }
  pcl::EuclideanClusterExtraction<pcl::PointXYZ> ec;
  ec.setInputCloud(cloud);
  ec.setIndices(std::make_shared<pcl::Indices>(indices.begin(), indices.end()));
  ec.setSearchMethod(std::make_shared<pcl::search::KdTree<pcl::PointXYZ>>());
  ec.setClusterTolerance(tol);
  ec.setMinClusterSize(1);
  ec.setMaxClusterSize(std::numeric_limits<int>::max());
  std::vector<pcl::PointIndices> raw;
  ec.extract(raw);
  std::vector<std::vector<int>> out;
  for (auto& c : raw) {
    std::vector<int> v(c.indices.begin(), c.indices.end());
    std::sort(v.begin(), v.end());
    out.push_back(std::move(v));
  }
  std::sort(out.begin(), out.end(),
            [](const auto& a, const auto& b) { return a.front() < b.front(); });
  return out;
}

/// Blobs of random size and spread, a noisy plane and scattered points: many
/// near-threshold links, so a wrong cell pair test would split or join something.
PointList mixedCloud(unsigned seed, std::size_t n) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> g(0.0, 1.0);
  PointList pts;
  for (int b = 0; b < 12; ++b) {
    const Vec3 c(10.0 * u(rng), 10.0 * u(rng), 3.0 * u(rng));
    const double spread = 0.05 + 0.3 * u(rng);
    for (std::size_t i = 0; i < n / 24; ++i)
      pts.push_back(c + spread * Vec3(g(rng), g(rng), g(rng)));
  }
  for (std::size_t i = 0; i < n / 3; ++i)
    pts.emplace_back(10.0 * u(rng), 10.0 * u(rng), 0.01 * g(rng));
  while (pts.size() < n) pts.emplace_back(10.0 * u(rng), 10.0 * u(rng), 3.0 * u(rng));
  return pts;
}

TEST(EuclideanClusters, SamePartitionAsPclOnRandomClouds) {
  for (unsigned seed = 1; seed <= 4; ++seed) {
    const PointList pts = mixedCloud(seed, 6000);
    std::vector<int> all(pts.size());
    std::iota(all.begin(), all.end(), 0);
    for (const double tol : {0.1, 0.3, 0.7}) {
      const auto ours = euclideanClusters(pts, all, tol);
      const auto ref = pclClusters(pts, all, tol);
      EXPECT_GT(ref.size(), 1u);
      EXPECT_EQ(ours, ref) << "seed " << seed << ", tolerance " << tol;
    }
  }
}

TEST(EuclideanClusters, OnlyTheGivenIndicesTakePart) {
  const PointList pts = mixedCloud(9, 3000);
  std::vector<int> odd;
  for (int i = 1; i < static_cast<int>(pts.size()); i += 2) odd.push_back(i);
  const auto ours = euclideanClusters(pts, odd, 0.3);
  EXPECT_EQ(ours, pclClusters(pts, odd, 0.3));
  std::size_t total = 0;
  for (const auto& c : ours) {
    total += c.size();
    for (const int i : c) EXPECT_EQ(i % 2, 1);
  }
  EXPECT_EQ(total, odd.size());
}

TEST(EuclideanClusters, HandBuiltChainsAndGaps) {
  // A chain of points 0.29 m apart is one cluster at 0.3 m; a 0.31 m gap splits it;
  // cells two apart are linked by a single close pair.
  PointList pts;
  for (int i = 0; i < 10; ++i) pts.emplace_back(0.29 * i, 0.0, 0.0);
  pts.emplace_back(0.29 * 9 + 0.31, 0.0, 0.0);
  pts.emplace_back(5.0, 5.0, 5.0);
  std::vector<int> all(pts.size());
  std::iota(all.begin(), all.end(), 0);
  const auto c = euclideanClusters(pts, all, 0.3);
  ASSERT_EQ(c.size(), 3u);
  EXPECT_EQ(c[0].size(), 10u);
  EXPECT_EQ(c[1], std::vector<int>{10});
  EXPECT_EQ(c[2], std::vector<int>{11});
  EXPECT_TRUE(euclideanClusters(pts, {}, 0.3).empty());
  EXPECT_THROW(euclideanClusters(pts, all, 0.0), InputError);
}

}  // namespace
}  // namespace uavip::perception
