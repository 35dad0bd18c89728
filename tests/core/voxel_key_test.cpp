#include "uavip/core/voxel_key.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <set>

#include "uavip/core/error.h"

namespace uavip {
namespace {

/// Random points in the box [c − half, c + half].
PointList randomCloud(const Vec3& c, double half, std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-half, half);
  PointList out(n);
  for (auto& p : out) p = c + Vec3(u(rng), u(rng), u(rng));
  return out;
}

TEST(VoxelKeyerLattice, IndexIsFloorOfTheQuotient) {
  const double edge = 0.15;
  for (const Vec3& c : {Vec3(0, 0, 0), Vec3(-3, 2, -1), Vec3(5e5, 5e6, 120.0)}) {
    for (const Vec3& p : randomCloud(c, 20.0, 500, 1)) {
      const auto idx = VoxelKeyer::latticeIndex(p, edge);
      for (int a = 0; a < 3; ++a) {
        // The reference: the voxel [i·edge, (i+1)·edge) holds p (up to one rounding).
        const double i = static_cast<double>(idx[static_cast<std::size_t>(a)]);
        EXPECT_LE(i * edge, p[a] + 1e-9);
        EXPECT_GT((i + 1.0) * edge, p[a] - 1e-9);
      }
    }
  }
  EXPECT_THROW(VoxelKeyer::latticeIndex(Vec3(NAN, 0, 0), edge), InputError);
  EXPECT_THROW(VoxelKeyer::latticeIndex(Vec3(0, 1e300, 0), edge), InputError);
}

TEST(VoxelKeyerLattice, KeysAreUniquePerVoxelFarFromTheOrigin) {
  // UTM-like coordinates: the voxel indices are ~1e8, far beyond 21 bits. Brute force:
  // two points share a key exactly when they share a lattice index.
  const double edge = 0.05;
  const PointList cloud = randomCloud(Vec3(512345.6, 5412345.6, 230.0), 2.0, 3000, 2);
  const VoxelKeyer keyer = VoxelKeyer::forPointsOnLattice(cloud, edge);
  std::map<std::uint64_t, std::array<std::int64_t, 3>> wrapped, relative;
  for (const auto& p : cloud) {
    const auto idx = VoxelKeyer::latticeIndex(p, edge);
    const auto w = wrapped.emplace(VoxelKeyer::wrappedKey(idx), idx);
    EXPECT_EQ(w.first->second, idx);
    const auto r = relative.emplace(keyer.indexKey(idx), idx);
    EXPECT_EQ(r.first->second, idx);
    // indexKey is relative to the box's low corner: it unpacks to idx − lo.
    const auto c = VoxelKeyer::unpack(keyer.indexKey(idx));
    for (std::size_t a = 0; a < 3; ++a) {
      EXPECT_GE(c[a], 0);
      EXPECT_LT(c[a], VoxelKeyer::kCells);
    }
  }
  std::set<std::array<std::int64_t, 3>> voxels;
  for (const auto& p : cloud) voxels.insert(VoxelKeyer::latticeIndex(p, edge));
  EXPECT_EQ(wrapped.size(), voxels.size());
  EXPECT_EQ(relative.size(), voxels.size());
}

TEST(VoxelKeyerLattice, WrappedKeyOrdersLikeTheLowBitsOfEachAxis) {
  // Reference: lexicographic order of ((x mod 2^21), (y mod 2^21), (z mod 2^21)).
  auto low = [](std::int64_t v) {
    return ((v % VoxelKeyer::kCells) + VoxelKeyer::kCells) % VoxelKeyer::kCells;
  };
  std::mt19937 rng(3);
  std::uniform_int_distribution<std::int64_t> u(-3000, 3000);
  for (int n = 0; n < 2000; ++n) {
    const std::array<std::int64_t, 3> a{u(rng), u(rng), u(rng)}, b{u(rng), u(rng), u(rng)};
    const std::array<std::int64_t, 3> la{low(a[0]), low(a[1]), low(a[2])};
    const std::array<std::int64_t, 3> lb{low(b[0]), low(b[1]), low(b[2])};
    EXPECT_EQ(VoxelKeyer::wrappedKey(a) < VoxelKeyer::wrappedKey(b), la < lb);
    EXPECT_EQ(VoxelKeyer::unpack(VoxelKeyer::wrappedKey(a)), la);
  }
}

TEST(VoxelKeyerLattice, AHugeExtentThrowsInsteadOfWrapping) {
  // 2^21 + 1 voxels on x: two of them would share wrapped keys; the keyer refuses.
  const double edge = 0.05;
  const double span = static_cast<double>(VoxelKeyer::kCells) * edge;
  const PointList wide{Vec3(5e5 + 0.01, 0.01, 0.01), Vec3(5e5 + span + 0.01, 0.01, 0.01)};
  EXPECT_NE(VoxelKeyer::latticeIndex(wide[0], edge)[0], VoxelKeyer::latticeIndex(wide[1], edge)[0]);
  EXPECT_EQ(VoxelKeyer::wrappedKey(VoxelKeyer::latticeIndex(wide[0], edge)),
            VoxelKeyer::wrappedKey(VoxelKeyer::latticeIndex(wide[1], edge)));  // the old wrap
  EXPECT_THROW(VoxelKeyer::forPointsOnLattice(wide, edge), InputError);
  const PointList fits{wide[0], wide[0] + Vec3(span - 2.0 * edge, 0, 0)};
  EXPECT_NO_THROW(VoxelKeyer::forPointsOnLattice(fits, edge));
  EXPECT_THROW(VoxelKeyer::forPointsOnLattice({}, edge), InputError);
  EXPECT_THROW(VoxelKeyer::forPointsOnLattice(fits, 0.0), InputError);
  EXPECT_THROW(VoxelKeyer::forIndexBox({0, 0, 0}, {0, VoxelKeyer::kCells, 0}, edge), InputError);
  EXPECT_NO_THROW(VoxelKeyer::forIndexBox({0, 0, 0}, {0, VoxelKeyer::kCells - 1, 0}, edge));
}

TEST(PlaneCellKey, ExactOverTheWholeRange) {
  const std::int64_t half = std::int64_t{1} << 31;
  const std::vector<std::int64_t> values{-half, -half + 1, -1, 0, 1, half - 2, half - 1};
  std::set<std::uint64_t> keys;
  for (const auto x : values) {
    for (const auto y : values) keys.insert(planeCellKey(x, y));
  }
  EXPECT_EQ(keys.size(), values.size() * values.size());
  EXPECT_THROW(planeCellKey(half, 0), InputError);
  EXPECT_THROW(planeCellKey(0, -half - 1), InputError);
  EXPECT_EQ(planeCellIndex(-0.01, 0.25), -1);
  EXPECT_EQ(planeCellIndex(5e6 + 0.1, 0.25), 20000000);
  EXPECT_THROW(planeCellIndex(1e12, 0.25), InputError);
  EXPECT_THROW(planeCellIndex(NAN, 0.25), InputError);
}

}  // namespace
}  // namespace uavip
