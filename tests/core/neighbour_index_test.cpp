// Queries of core/neighbour_index.h at arbitrary points against brute force, near
// and far (UTM-like) from the origin.
#include "uavip/core/neighbour_index.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <random>
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

}  // namespace
}  // namespace uavip
