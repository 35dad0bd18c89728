// Queries of core/neighbour_index.h at arbitrary points against brute force, near
// and far (UTM-like) from the origin.
#include "uavip/core/neighbour_index.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <utility>
#include <vector>

#include "uavip/core/error.h"

namespace uavip {
namespace {

/// A random cloud in a 10 m box at `corner`, and random queries around it (some outside).
struct Case {
  PointList cloud, queries;
};

Case randomCase(const Vec3& corner, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 10.0), w(-2.0, 12.0);
  Case c;
  for (int i = 0; i < 2000; ++i) c.cloud.push_back(corner + Vec3(u(rng), u(rng), u(rng)));
  for (int i = 0; i < 200; ++i) c.queries.push_back(corner + Vec3(w(rng), w(rng), w(rng)));
  return c;
}

const Vec3 kCorners[] = {Vec3(0, 0, 0), Vec3(-5, -5, -5), Vec3(5.0e5, 5.0e6, 250.0)};

TEST(NeighbourIndexQueries, NearestToMatchesBruteForce) {
  std::uint32_t seed = 1;
  for (const Vec3& corner : kCorners) {
    const Case c = randomCase(corner, seed++);
    // Default frame (min corner) and a caller's frame (the box centre).
    for (const bool centre : {false, true}) {
      const auto index = centre
                             ? std::make_unique<NeighbourIndex>(c.cloud, corner + Vec3::Constant(5))
                             : std::make_unique<NeighbourIndex>(c.cloud);
      for (const auto& q : c.queries) {
        double brute = std::numeric_limits<double>::infinity();
        for (const auto& p : c.cloud) brute = std::min(brute, (p - q).norm());
        float d2 = -1.0f;
        const int i = index->nearestTo(q, &d2);
        ASSERT_GE(i, 0);
        // Floats near 0 keep ~1e-6 m: the found point is the nearest up to that.
        EXPECT_NEAR((c.cloud[static_cast<std::size_t>(i)] - q).norm(), brute, 1e-5);
        EXPECT_NEAR(std::sqrt(static_cast<double>(d2)), brute, 1e-5);
      }
    }
  }
}

TEST(NeighbourIndexQueries, WithinMatchesBruteForce) {
  std::uint32_t seed = 10;
  for (const Vec3& corner : kCorners) {
    const Case c = randomCase(corner, seed++);
    const NeighbourIndex index(c.cloud);
    std::vector<int> idx;
    std::vector<float> d2;
    for (const auto& q : c.queries) {
      for (const double r : {0.3, 1.0, 2.5}) {
        std::vector<int> brute;
        bool on_sphere = false;  // a point within float rounding of the sphere: skip
        for (std::size_t i = 0; i < c.cloud.size(); ++i) {
          const double d = (c.cloud[i] - q).norm();
          on_sphere = on_sphere || std::abs(d - r) < 1e-4;
          if (d < r) brute.push_back(static_cast<int>(i));
        }
        if (on_sphere) continue;
        for (const bool sorted : {true, false}) {
          index.within(q, r, idx, d2, sorted);
          ASSERT_EQ(idx.size(), d2.size());
          if (sorted) {
            EXPECT_TRUE(std::is_sorted(d2.begin(), d2.end()));
          }
          std::vector<int> got = idx;
          std::sort(got.begin(), got.end());
          EXPECT_EQ(got, brute) << "query " << q.transpose() << " radius " << r;
        }
      }
    }
  }
}

TEST(NeighbourIndexQueries, KnnOfStoredPointsFarFromTheOrigin) {
  const Case c = randomCase(Vec3(5.0e5, 5.0e6, 250.0), 20);
  const NeighbourIndex index(c.cloud);
  std::vector<int> idx;
  std::vector<float> d2;
  for (std::size_t i = 0; i < c.cloud.size(); i += 101) {
    index.nearest(i, 6, idx, d2);
    std::vector<double> brute;
    for (const auto& p : c.cloud) brute.push_back((p - c.cloud[i]).norm());
    std::sort(brute.begin(), brute.end());
    ASSERT_EQ(idx.size(), 6u);
    for (std::size_t j = 0; j < 6; ++j) {
      EXPECT_NEAR((c.cloud[static_cast<std::size_t>(idx[j])] - c.cloud[i]).norm(), brute[j], 1e-5);
    }
  }
}

TEST(NeighbourIndexQueries, BadInput) {
  EXPECT_THROW(NeighbourIndex(PointList{}, Vec3::Zero()), InputError);
  const PointList one{Vec3(1, 2, 3)};
  EXPECT_THROW(NeighbourIndex(one, Vec3(NAN, 0, 0)), InputError);
  const NeighbourIndex index(one, Vec3::Zero());
  EXPECT_EQ(index.nearestTo(Vec3(100, 0, 0)), 0);
  std::vector<int> idx{7};
  std::vector<float> d2{1.0f};
  index.within(Vec3(100, 0, 0), 1.0, idx, d2);
  EXPECT_TRUE(idx.empty());
  EXPECT_TRUE(d2.empty());
}

/// The 200 smallest squared distances from q to the points in the index's float
/// frame, as FLANN computes them (float differences, summed x, y, z), sorted.
std::vector<std::pair<float, int>> bruteForceFloat(const PointList& cloud, const Vec3& origin,
                                                   const Vec3& q) {
  const auto fl = [&](const Vec3& p) {
    const Vec3 d = p - origin;
    return std::array<float, 3>{static_cast<float>(d.x()), static_cast<float>(d.y()),
                                static_cast<float>(d.z())};
  };
  const auto fq = fl(q);
  std::vector<std::pair<float, int>> all(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const auto fp = fl(cloud[i]);
    float d2 = 0.0f;
    for (int a = 0; a < 3; ++a) {
      const float diff = fq[static_cast<std::size_t>(a)] - fp[static_cast<std::size_t>(a)];
      d2 += diff * diff;
    }
    all[i] = {d2, static_cast<int>(i)};
  }
  const std::size_t keep = std::min<std::size_t>(200, all.size());
  std::partial_sort(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(keep), all.end());
  all.resize(keep);
  return all;
}

// From 2^18 points the index is two trees split at the median of the longest axis
// (x here, at about 20 m), built at once. Every query kind against brute force in
// the same float arithmetic, for points right at the split (whose neighbours lie on
// both sides) and elsewhere, near the origin and at UTM-like coordinates, in random
// order and sorted along the split axis (each half then a run of the cloud).
TEST(NeighbourIndexQueries, SplitIndexMatchesBruteForceAcrossTheSplit) {
  for (const bool sorted_x : {false, true}) {
    const Vec3 corner = sorted_x ? Vec3(5.0e5, 5.0e6, 250.0) : Vec3(0, 0, 0);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> ux(0.0, 40.0), u(0.0, 10.0);
    PointList cloud(270000);
    for (auto& p : cloud) p = corner + Vec3(ux(rng), u(rng), u(rng));
    if (sorted_x) {
      std::sort(cloud.begin(), cloud.end(),
                [](const Vec3& a, const Vec3& b) { return a.x() < b.x(); });
    }
    const NeighbourIndex index(cloud);
    std::vector<std::size_t> queries;
    for (std::size_t i = 0; i < cloud.size() && queries.size() < 120; ++i) {
      if (std::abs(cloud[i].x() - corner.x() - 20.0) < 0.03) queries.push_back(i);
    }
    for (std::size_t i = 0; i < cloud.size(); i += 4999) queries.push_back(i);
    ASSERT_GT(queries.size(), 150u);
    constexpr int k = 17;
    std::vector<int> idx(k);
    std::vector<float> d2(k);
    for (const std::size_t i : queries) {
      const auto brute = bruteForceFloat(cloud, index.origin(), cloud[i]);
      index.nearest(i, 1, k, idx.data(), d2.data());
      for (int j = 0; j < k; ++j) {
        ASSERT_EQ(d2[static_cast<std::size_t>(j)], brute[static_cast<std::size_t>(j)].first)
            << "point " << i << ", neighbour " << j;
        ASSERT_EQ(idx[static_cast<std::size_t>(j)], brute[static_cast<std::size_t>(j)].second)
            << "point " << i << ", neighbour " << j;
      }
      // Arbitrary points beside it: the nearest, and every point within a radius.
      const Vec3 q = cloud[i] + Vec3(0.01, -0.02, 0.015);
      const auto around = bruteForceFloat(cloud, index.origin(), q);
      float nearest_d2 = -1.0f;
      EXPECT_EQ(index.nearestTo(q, &nearest_d2), around.front().second);
      EXPECT_EQ(nearest_d2, around.front().first);
      const float r2 = static_cast<float>(0.2 * 0.2);
      ASSERT_GT(around.back().first, r2);  // the radius holds fewer than 200 points
      std::vector<int> expected;
      for (const auto& [d, j] : around) {
        if (d <= r2) expected.push_back(j);
      }
      std::vector<int> within;
      std::vector<float> within_d2;
      index.within(q, 0.2, within, within_d2, true);
      EXPECT_TRUE(std::is_sorted(within_d2.begin(), within_d2.end()));
      EXPECT_EQ(within, expected) << "point " << i;
      index.within(q, 0.2, within, within_d2, false);
      std::sort(within.begin(), within.end());
      std::sort(expected.begin(), expected.end());
      EXPECT_EQ(within, expected) << "point " << i;
    }
  }
}

// Half the points or more on the lowest value of the longest axis (a wall seen edge
// on): no split there, one tree, the same answers.
TEST(NeighbourIndexQueries, NoSplitWhenHalfThePointsShareTheLowestValue) {
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> u(0.0, 10.0);
  PointList cloud(270000);
  for (std::size_t i = 0; i < cloud.size(); ++i)
    cloud[i] = Vec3(i % 3 == 0 ? 4.0 * u(rng) : 0.0, u(rng) * 0.1, u(rng) * 0.1);
  const NeighbourIndex index(cloud);
  for (std::size_t i = 0; i < cloud.size(); i += 27001) {
    const auto brute = bruteForceFloat(cloud, index.origin(), cloud[i]);
    std::vector<int> idx(5);
    std::vector<float> d2(5);
    index.nearest(i, 1, 5, idx.data(), d2.data());
    for (std::size_t j = 0; j < 5; ++j) EXPECT_EQ(d2[j], brute[j].first) << "point " << i;
  }
}

}  // namespace
}  // namespace uavip
