// The merge of tile scenes (tiling/merge.h) against the simulator's truth: a wall and
// a ground crossing tile borders come out as one surface each holding every sampled
// point once, parallel planes stay apart, an obstacle cut by a border is one again.

#include "uavip/tiling/merge.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <map>

#include "uavip/core/geometry.h"
#include "uavip/sim/surface_sampler.h"
#include "uavip/sim/world_model.h"

namespace {

using uavip::Obstacle;
using uavip::PointList;
using uavip::Scene;
using uavip::Surface;
using uavip::Vec3;
namespace tiling = uavip::tiling;
namespace sim = uavip::sim;

/// Two tiles of 20 m side by side in x (x in [0, 40)), 3 m buffer.
tiling::Manifest twoTiles() {
  tiling::Manifest m;
  m.tile_size_m = 20.0;
  m.buffer_m = 3.0;
  m.grid_origin = Eigen::Vector2d(0.0, 0.0);
  m.columns = 2;
  m.rows = 1;
  for (int c = 0; c < 2; ++c) {
    tiling::TileRecord t;
    t.index = c;
    t.column = c;
    t.core.min = Eigen::Vector2d(20.0 * c, 0.0);
    t.core.max = t.core.min + Eigen::Vector2d(20.0, 20.0);
    t.buffered.min = t.core.min - Eigen::Vector2d(3.0, 3.0);
    t.buffered.max = t.core.max + Eigen::Vector2d(3.0, 3.0);
    m.tiles.push_back(t);
  }
  return m;
}

/// The tile's view of a detected plane: every sample in its buffered box.
Surface seenBy(const tiling::TileRecord& t, const PointList& samples, const Vec3& normal, int id) {
  Surface s;
  s.id = id;
  for (const Vec3& p : samples)
    if (t.buffered.contains(p)) s.inliers.push_back(p);
  Vec3 c = Vec3::Zero();
  for (const Vec3& p : s.inliers) c += p;
  s.centroid = c / static_cast<double>(s.inliers.size());
  s.plane.normal = normal;
  s.plane.offset = -normal.dot(s.centroid);
  return s;
}

using Key = std::array<double, 3>;
std::map<Key, int> multiset(const PointList& points) {
  std::map<Key, int> out;
  for (const Vec3& p : points) ++out[{p.x(), p.y(), p.z()}];
  return out;
}

TEST(MergeTileScenes, JoinsPlanesAcrossTheBorderKeepingEachPointOnce) {
  // A 36 m wall facing -y across the border at x = 20, and a ground 1 m below its foot.
  sim::WorldModel w, g;
  w.addPlane({"wall", Vec3(2.0, 5.0, 0.0), Vec3(0.0, 0.0, 3.0), Vec3(36.0, 0.0, 0.0)});
  g.addPlane({"ground", Vec3(1.0, 1.0, -1.0), Vec3(38.0, 0.0, 0.0), Vec3(0.0, 3.0, 0.0)});
  sim::SampleOptions so;
  so.spacing_m = 0.1;
  so.noise_sigma_m = 0.0;
  const PointList wall = sim::sampleSurfaces(w, so), ground = sim::sampleSurfaces(g, so);

  const tiling::Manifest m = twoTiles();
  std::vector<tiling::TileScene> tiles;
  for (const auto& t : m.tiles) {
    Scene s;
    s.surfaces.push_back(seenBy(t, wall, -Vec3::UnitY(), 0));
    s.surfaces.push_back(seenBy(t, ground, Vec3::UnitZ(), 1));
    tiles.push_back({t, s});
  }
  tiling::MergeStats st;
  const Scene merged = tiling::mergeTileScenes(m, tiles, {}, &st);
  ASSERT_EQ(merged.surfaces.size(), 2U);
  EXPECT_EQ(st.surfaces_joined, 2);
  // Each merged surface holds every sample of its truth rectangle exactly once.
  EXPECT_EQ(multiset(merged.surfaces[0].inliers), multiset(wall));
  EXPECT_EQ(multiset(merged.surfaces[1].inliers), multiset(ground));
  // Refitted plane and area against the truth (36 x 3 m; 38 x 3 m).
  EXPECT_GT(merged.surfaces[0].plane.normal.dot(-Vec3::UnitY()), 0.9999);
  EXPECT_NEAR(merged.surfaces[0].area_m2, 36.0 * 3.0, 1e-6);
  EXPECT_NEAR(merged.surfaces[1].area_m2, 38.0 * 3.0, 1e-6);
  EXPECT_EQ(merged.cloud.size(), wall.size() + ground.size());
}

TEST(MergeTileScenes, KeepsParallelPlanesApartAndJoinsACutObstacle) {
  sim::SampleOptions so;
  so.spacing_m = 0.1;
  so.noise_sigma_m = 0.0;
  sim::WorldModel a, b;
  a.addPlane({"top", Vec3(10.0, 2.0, 4.5), Vec3(20.0, 0.0, 0.0), Vec3(0.0, 6.0, 0.0)});
  // Its parallel twin 1 m lower, on the other side of the border only.
  b.addPlane({"lower", Vec3(20.5, 2.0, 3.5), Vec3(8.0, 0.0, 0.0), Vec3(0.0, 6.0, 0.0)});
  const PointList top = sim::sampleSurfaces(a, so), lower = sim::sampleSurfaces(b, so);
  sim::WorldModel box;
  box.addBox("pole", Vec3(19.5, 15.0, 0.0), Vec3(20.5, 15.4, 2.0));
  const PointList pole = sim::sampleSurfaces(box, so);

  const tiling::Manifest m = twoTiles();
  std::vector<tiling::TileScene> tiles;
  for (const auto& t : m.tiles) {
    Scene s;
    s.surfaces.push_back(seenBy(t, top, Vec3::UnitZ(), 0));
    if (t.column == 1) s.surfaces.push_back(seenBy(t, lower, Vec3::UnitZ(), 1));
    Obstacle o;
    for (const Vec3& p : pole)
      if (t.buffered.contains(p)) o.points.push_back(p);
    s.obstacles.push_back(o);
    tiles.push_back({t, s});
  }
  const Scene merged = tiling::mergeTileScenes(m, tiles, {});
  ASSERT_EQ(merged.surfaces.size(), 2U);
  EXPECT_EQ(multiset(merged.surfaces[0].inliers), multiset(top));
  EXPECT_EQ(multiset(merged.surfaces[1].inliers), multiset(lower));
  ASSERT_EQ(merged.obstacles.size(), 1U);
  EXPECT_EQ(multiset(merged.obstacles[0].points), multiset(pole));
  const uavip::Aabb truth = uavip::boundingBox(pole);
  EXPECT_EQ(merged.obstacles[0].aabb_min, truth.min);
  EXPECT_EQ(merged.obstacles[0].aabb_max, truth.max);
}

}  // namespace
