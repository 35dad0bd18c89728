#include "uavip/world/voxel_grid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <deque>
#include <limits>
#include <map>
#include <random>

#include "uavip/core/error.h"
#include "uavip/core/geometry.h"

namespace uavip::world {
namespace {

PointList randomCloud(std::size_t n, double extent, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, extent);
  PointList pts;
  for (std::size_t i = 0; i < n; ++i) pts.emplace_back(u(rng), u(rng), u(rng));
  return pts;
}

double nearestDistance(const Vec3& p, const PointList& cloud) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& q : cloud) best = std::min(best, (p - q).norm());
  return best;
}

template <typename F>
void forEachVoxel(const VoxelGrid& g, F f) {
  for (int z = 0; z < g.dims()[2]; ++z)
    for (int y = 0; y < g.dims()[1]; ++y)
      for (int x = 0; x < g.dims()[0]; ++x) f(Index3{x, y, z});
}

TEST(VoxelGrid, InflationMatchesBruteForceDistances) {
  for (unsigned seed : {1u, 2u, 3u}) {
    const PointList cloud = randomCloud(25, 2.0, seed);
    GridOptions o;
    o.resolution_m = 0.2;
    o.inflation_radius_m = 0.3;
    o.padding_m = 1.0;
    const VoxelGrid g = VoxelGrid::build(cloud, {}, o);
    const double r = o.inflation_radius_m;
    const double h = std::sqrt(3.0) / 2.0 * o.resolution_m;
    std::size_t blocked = 0;
    forEachVoxel(g, [&](const Index3& i) {
      const double d = nearestDistance(g.centreOf(i), cloud);
      // Within r of a measured point -> blocked.
      if (d <= r) {
        EXPECT_TRUE(g.isBlocked(i)) << "voxel " << i.x << "," << i.y << "," << i.z << " d=" << d;
      }
      // Free centre -> at least r + h from every point (the safety argument).
      if (g.isFree(i)) {
        EXPECT_GE(d, r + h - 1e-12);
      }
      // Not over-conservative: farther than r + √3·res + h from every point -> free.
      if (d > g.effectiveInflation() + h + 1e-9) {
        EXPECT_TRUE(g.isFree(i));
      }
      blocked += g.isBlocked(i);
    });
    EXPECT_EQ(blocked, g.blockedCount());
    for (const auto& p : cloud) EXPECT_TRUE(g.isOccupied(g.indexOf(p)));
    EXPECT_GT(g.occupiedCount(), 0u);
    EXPECT_LE(g.occupiedCount(), cloud.size());  // occupied voxels are those holding a point
  }
}

// Dense input (a solid slab, a wall along x with gaps, rows of points that touch):
// the inflated set equals, voxel for voxel, the brute-force union of the discrete
// spheres around every occupied voxel (the grid stamps runs of merged rows and skips
// interior voxels; neither may change a voxel).
TEST(VoxelGrid, InflationOfDenseRowsEqualsTheUnionOfSpheres) {
  PointList cloud;
  for (double x = 0.05; x < 1.2; x += 0.1)
    for (double y = 0.05; y < 0.6; y += 0.1)
      for (double z = 0.05; z < 0.4; z += 0.1) cloud.emplace_back(x, y, z);  // solid slab
  for (double x = 0.05; x < 3.0; x += 0.1)
    for (double z = 0.05; z < 1.0; z += 0.1)
      if (std::fmod(x, 0.7) > 0.25) cloud.emplace_back(x, 1.55, z);  // wall with gaps
  const PointList noise = randomCloud(40, 3.0, 7);
  cloud.insert(cloud.end(), noise.begin(), noise.end());
  GridOptions o;
  o.resolution_m = 0.1;
  o.inflation_radius_m = 0.25;
  o.padding_m = 0.5;
  const VoxelGrid g = VoxelGrid::build(cloud, {}, o);
  std::vector<Index3> occupied;
  forEachVoxel(g, [&](const Index3& i) {
    if (g.isOccupied(i)) occupied.push_back(i);
  });
  ASSERT_GT(occupied.size(), 400u);
  const double r = g.effectiveInflation() / o.resolution_m;
  const double r2 = r * r * (1.0 + 1e-12) + 1e-9;  // the grid's sphere test
  std::size_t blocked = 0;
  forEachVoxel(g, [&](const Index3& i) {
    bool near = false;
    for (const auto& q : occupied) {
      const double dx = i.x - q.x, dy = i.y - q.y, dz = i.z - q.z;
      if (dx * dx + dy * dy + dz * dz <= r2) {
        near = true;
        break;
      }
    }
    EXPECT_EQ(g.isBlocked(i), near) << "voxel " << i.x << "," << i.y << "," << i.z;
    blocked += near;
  });
  EXPECT_EQ(blocked, g.blockedCount());
}

TEST(VoxelGrid, OccupiedExactlyWhereMeasuredPointsLie) {
  // A solid block (OctoMap prunes it into bigger leaves) plus scattered points.
  PointList cloud;
  for (double x = 0.025; x < 1.6; x += 0.05)
    for (double y = 0.025; y < 1.6; y += 0.05)
      for (double z = 0.025; z < 0.8; z += 0.05) cloud.emplace_back(x, y, z);
  const PointList scattered = randomCloud(40, 3.0, 9);
  cloud.insert(cloud.end(), scattered.begin(), scattered.end());
  GridOptions o;
  o.resolution_m = 0.2;
  o.inflation_radius_m = 0.1;
  o.padding_m = 0.6;
  const VoxelGrid g = VoxelGrid::build(cloud, {}, o);
  std::vector<std::uint8_t> holds(g.voxelCount(), 0);
  for (const auto& p : cloud) holds[g.linear(g.indexOf(p))] = 1;
  std::size_t n = 0;
  forEachVoxel(g, [&](const Index3& i) {
    EXPECT_EQ(g.isOccupied(i), holds[g.linear(i)] != 0);
    n += holds[g.linear(i)];
  });
  EXPECT_EQ(g.occupiedCount(), n);
  EXPECT_GE(n, 8u * 8u * 4u);
}

TEST(VoxelGrid, BoundsCoverCloudAndExtraWithPadding) {
  const PointList cloud = {Vec3(1.03, -2.0, 0.5), Vec3(3.0, 1.0, 2.2)};
  const PointList extra = {Vec3(-4.0, 0.0, 1.0)};
  GridOptions o;
  o.resolution_m = 0.25;
  o.inflation_radius_m = 0.1;
  o.padding_m = 0.5;
  const VoxelGrid g = VoxelGrid::build(cloud, extra, o);
  const Vec3 lo(-4.5, -2.5, 0.0), hi(3.5, 1.5, 2.7);
  EXPECT_TRUE(g.inBounds(g.indexOf(lo)));
  EXPECT_TRUE(g.inBounds(g.indexOf(hi - Vec3::Constant(1e-9))));
  // Origin is no more than one voxel below the padded bound on each axis.
  for (int a = 0; a < 3; ++a) {
    EXPECT_LE(g.origin()[a], lo[a] + 1e-12);
    EXPECT_GT(g.origin()[a], lo[a] - o.resolution_m - 1e-12);
    EXPECT_LT(g.origin()[a] + g.dims()[a] * o.resolution_m, hi[a] + o.resolution_m + 1e-9);
  }
  EXPECT_EQ(g.voxelCount(), static_cast<std::size_t>(g.dims()[0]) *
                                static_cast<std::size_t>(g.dims()[1]) *
                                static_cast<std::size_t>(g.dims()[2]));
  EXPECT_TRUE(g.isBlocked(Index3{-1, 0, 0}));
  EXPECT_TRUE(g.isBlocked(Index3{0, g.dims()[1], 0}));
}

TEST(VoxelGrid, AsAFreeSpaceItIsItsBoxAndItsContentHasOneId) {
  GridOptions o;
  o.resolution_m = 0.25;
  o.padding_m = 0.5;
  const PointList cloud = randomCloud(200, 3.0, 5);
  const VoxelGrid g = VoxelGrid::build(cloud, {}, o);
  const FreeSpace& space = g;
  // The box is the voxels' box; outside it nothing is free.
  const Aabb box = space.bounds();
  EXPECT_EQ(box.min, g.origin());
  EXPECT_EQ(g.indexOf(box.max - Vec3::Constant(1e-9)),
            (Index3{g.dims()[0] - 1, g.dims()[1] - 1, g.dims()[2] - 1}));
  EXPECT_FALSE(space.isFree(box.max + Vec3::Constant(1e-9)));
  EXPECT_FALSE(space.isFree(box.min - Vec3::Constant(1e-9)));
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int k = 0; k < 300; ++k) {
    const Vec3 p = box.min + (box.max - box.min).cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
    const Vec3 q = box.min + (box.max - box.min).cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
    EXPECT_EQ(space.isFree(p), g.isFree(g.indexOf(p)));
    EXPECT_EQ(space.segmentFree(p, q), g.segmentFree(p, q));
  }
  EXPECT_EQ(space.resolution(), o.resolution_m);
  // A copy holds the same voxels, so the same id; a grid built anew gets a new one.
  // NOLINTNEXTLINE(performance-unnecessary-copy-initialization): the copy is what is tested
  const VoxelGrid copy = g;
  const VoxelGrid again = VoxelGrid::build(cloud, {}, o);
  EXPECT_NE(g.contentId(), 0u);
  EXPECT_EQ(copy.contentId(), g.contentId());
  EXPECT_NE(again.contentId(), g.contentId());
  EXPECT_EQ(VoxelGrid().contentId(), 0u);
}

TEST(VoxelGrid, IndexAndCentreRoundTrip) {
  GridOptions o;
  o.resolution_m = 0.3;
  o.padding_m = 0.0;
  const VoxelGrid g = VoxelGrid::build({}, {Vec3(-1.0, -2.0, -3.0), Vec3(2.0, 1.0, 0.5)}, o);
  EXPECT_EQ(g.blockedCount(), 0u);  // no cloud: all free
  std::mt19937 rng(7);
  for (int k = 0; k < 200; ++k) {
    const Index3 i{static_cast<int>(rng() % static_cast<unsigned>(g.dims()[0])),
                   static_cast<int>(rng() % static_cast<unsigned>(g.dims()[1])),
                   static_cast<int>(rng() % static_cast<unsigned>(g.dims()[2]))};
    EXPECT_EQ(g.indexOf(g.centreOf(i)), i);
    EXPECT_TRUE(g.isFree(i));
  }
  std::uniform_real_distribution<double> u(-1.0, 0.5);
  for (int k = 0; k < 200; ++k) {
    const Vec3 p(u(rng), u(rng), u(rng));
    const Vec3 c = g.centreOf(g.indexOf(p));
    EXPECT_LE((p - c).cwiseAbs().maxCoeff(), 0.5 * o.resolution_m + 1e-12);
    // Voxel i covers [origin + i·res, origin + (i+1)·res).
    const Index3 i = g.indexOf(p);
    EXPECT_LE(g.origin().x() + i.x * o.resolution_m, p.x() + 1e-12);
    EXPECT_GT(g.origin().x() + (i.x + 1) * o.resolution_m, p.x() - 1e-12);
  }
  EXPECT_EQ(g.linear(Index3{1, 0, 0}), 1u);
  EXPECT_EQ(g.linear(Index3{0, 1, 0}), static_cast<std::size_t>(g.dims()[0]));
  EXPECT_EQ(g.linear(Index3{0, 0, 1}), static_cast<std::size_t>(g.dims()[0] * g.dims()[1]));
}

TEST(VoxelGrid, MaxVoxelsGuardThrows) {
  GridOptions o;
  o.resolution_m = 0.1;
  o.padding_m = 0.0;
  o.max_voxels = 1000;  // 10 m cube at 0.1 m = 1e6 voxels
  try {
    VoxelGrid::build({Vec3(0, 0, 0), Vec3(10, 10, 10)}, {}, o);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("max_voxels"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("resolution_m"), std::string::npos);
  }
  o.max_voxels = 2'000'000;
  EXPECT_NO_THROW(VoxelGrid::build({Vec3(0, 0, 0), Vec3(10, 10, 10)}, {}, o));
}

TEST(VoxelGrid, RequireFitsRefusesBeforeAllocatingAndNamesTheResolutionThatFits) {
  GridOptions o;
  o.resolution_m = 1e-4;  // a 10 m region: 1e15 voxels, 5e6 GB
  o.padding_m = 0.0;
  const Aabb region{Vec3(0, 0, 0), Vec3(10, 10, 10)};
  try {
    VoxelGrid::requireFits(region, o);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("GB"), std::string::npos) << what;
    // cbrt(1000 m³ / 6e7 voxels) = 0.0255 m, rounded up to whole millimetres.
    EXPECT_NE(what.find("grid.resolution_m >= 0.026"), std::string::npos) << what;
  }
  o.resolution_m = 0.026;
  EXPECT_NO_THROW(VoxelGrid::requireFits(region, o));
  const PointList corners{Vec3(0, 0, 0), Vec3(10, 10, 10)};
  EXPECT_NO_THROW(VoxelGrid::build({&corners}, o, region));
}

TEST(VoxelGrid, BadOptionsThrow) {
  GridOptions o;
  o.resolution_m = 0.0;
  EXPECT_THROW(VoxelGrid::build({Vec3::Zero()}, {}, o), InputError);
  o = GridOptions{};
  o.inflation_radius_m = -1.0;
  EXPECT_THROW(VoxelGrid::build({Vec3::Zero()}, {}, o), InputError);
  o = GridOptions{};
  o.padding_m = std::nan("");
  EXPECT_THROW(VoxelGrid::build({Vec3::Zero()}, {}, o), InputError);
  o = GridOptions{};
  EXPECT_THROW(VoxelGrid::build({Vec3(std::nan(""), 0, 0)}, {}, o), InputError);
}

TEST(VoxelGrid, SegmentFreeKeepsClearanceAndCatchesObstacles) {
  const PointList cloud = randomCloud(15, 3.0, 11);
  GridOptions o;
  o.resolution_m = 0.2;
  o.inflation_radius_m = 0.25;
  o.padding_m = 1.0;
  const VoxelGrid g = VoxelGrid::build(cloud, {}, o);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 4.0);
  int free_count = 0, blocked_count = 0;
  for (int k = 0; k < 400; ++k) {
    const Vec3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng));
    if (g.segmentFree(a, b)) {
      ++free_count;
      double d = std::numeric_limits<double>::infinity();
      for (const auto& p : cloud) d = std::min(d, pointSegmentDistance(p, a, b));
      EXPECT_GE(d, o.inflation_radius_m);
      // Every dense sample lies in a free voxel.
      for (int s = 0; s <= 100; ++s) EXPECT_TRUE(g.isFree(Vec3(a + (b - a) * (s / 100.0))));
    } else {
      ++blocked_count;
    }
  }
  EXPECT_GT(free_count, 10);
  EXPECT_GT(blocked_count, 10);
  // A segment through a measured point is never free.
  EXPECT_FALSE(g.segmentFree(cloud[0] - Vec3(2, 0, 0), cloud[0] + Vec3(2, 0, 0)));
  EXPECT_FALSE(g.segmentFree(cloud[0], cloud[0]));
}

TEST(VoxelGrid, ReachabilityStopsAtAWall) {
  // A wall of points at x = 0 across the whole grid (padding 0) splits it in two.
  PointList cloud;
  for (double y = 0.0; y <= 2.0001; y += 0.05)
    for (double z = 0.0; z <= 2.0001; z += 0.05) cloud.emplace_back(0.0, y, z);
  GridOptions o;
  o.resolution_m = 0.1;
  o.inflation_radius_m = 0.05;
  o.padding_m = 0.0;
  const VoxelGrid g = VoxelGrid::build(cloud, {Vec3(-1.0, 0.0, 0.0), Vec3(1.0, 2.0, 2.0)}, o);
  const Index3 left = g.indexOf(Vec3(-0.8, 1.0, 1.0));
  const Index3 right = g.indexOf(Vec3(0.8, 1.0, 1.0));
  ASSERT_TRUE(g.isFree(left));
  ASSERT_TRUE(g.isFree(right));
  const std::int32_t mine = g.component(left);
  ASSERT_NE(mine, 0);
  forEachVoxel(g, [&](const Index3& i) {
    const bool r = g.component(i) == mine;
    if (r) {
      EXPECT_TRUE(g.isFree(i));
    }
    // Free voxels left of the wall are all connected; none right of it is reached.
    if (g.isFree(i)) {
      EXPECT_EQ(r, g.centreOf(i).x() < 0.0);
    }
  });
  EXPECT_TRUE(g.connected(left, g.indexOf(Vec3(-0.5, 0.3, 1.7))));
  EXPECT_FALSE(g.connected(left, right));
  EXPECT_EQ(g.component(g.indexOf(Vec3(0.0, 1.0, 1.0))), 0);  // in the wall
  EXPECT_EQ(g.component(Index3{-1, 0, 0}), 0);                // outside the grid
}

TEST(VoxelGrid, ComponentsMatchABruteForceFloodFill) {
  // Random clutter in a small grid; the reference labels each free voxel by a plain
  // breadth-first search over its 26 neighbours. Two voxels must share a component
  // in one labelling exactly when they do in the other.
  std::mt19937 rng(5);
  for (int trial = 0; trial < 6; ++trial) {
    std::uniform_real_distribution<double> u(0.0, 3.0);
    PointList cloud;
    for (int k = 0; k < 60 + 40 * trial; ++k) cloud.emplace_back(u(rng), u(rng), u(rng));
    GridOptions o;
    o.resolution_m = 0.1;
    o.inflation_radius_m = 0.05 + 0.02 * trial;
    o.padding_m = 0.0;
    const VoxelGrid g = VoxelGrid::build(cloud, {Vec3(0.0, 0.0, 0.0), Vec3(3.0, 3.0, 3.0)}, o);
    std::vector<int> ref(g.voxelCount(), -1);
    int components = 0;
    forEachVoxel(g, [&](const Index3& seed) {
      if (g.isBlocked(seed) || ref[g.linear(seed)] >= 0) return;
      std::deque<Index3> queue{seed};
      ref[g.linear(seed)] = components;
      while (!queue.empty()) {
        const Index3 c = queue.front();
        queue.pop_front();
        for (int dz = -1; dz <= 1; ++dz)
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
              const Index3 n{c.x + dx, c.y + dy, c.z + dz};
              if (g.isBlocked(n) || ref[g.linear(n)] >= 0) continue;
              ref[g.linear(n)] = components;
              queue.push_back(n);
            }
      }
      ++components;
    });
    // A bijection between the reference's components and the grid's labels.
    std::map<int, std::int32_t> to_label;
    std::map<std::int32_t, int> to_ref;
    forEachVoxel(g, [&](const Index3& i) {
      const std::int32_t l = g.component(i);
      const int r = ref[g.linear(i)];
      ASSERT_EQ(l == 0, r < 0);
      if (r < 0) return;
      EXPECT_EQ(to_label.emplace(r, l).first->second, l);
      EXPECT_EQ(to_ref.emplace(l, r).first->second, r);
    });
    EXPECT_EQ(static_cast<int>(to_label.size()), components);
    if (trial == 5) {
      EXPECT_GT(components, 1) << "the densest clutter should cut off pockets";
    }
  }
}

}  // namespace
}  // namespace uavip::world
