// uavip tile (tiling/tiles.h): every tile's cloud against a brute-force assignment of
// the input points, and the streamed reader against the whole-cloud reader.

#include "uavip/tiling/tiles.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>

#include "uavip/core/error.h"
#include "uavip/io/cloud_io.h"

namespace {

namespace fs = std::filesystem;
using uavip::PointList;
using uavip::Vec3;
namespace tiling = uavip::tiling;
namespace io = uavip::io;

fs::path tempDir(const std::string& name) {
  fs::path d =
      fs::temp_directory_path() / ("uavip_tiles_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

/// A random cloud: `n` points in a box of `size` starting at `at`, written as x y z text.
PointList writeCloud(const fs::path& file, std::size_t n, const Vec3& at, const Vec3& size,
                     unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  PointList points;
  std::ofstream out(file);
  out.precision(12);
  out << "x,y,z\n";
  for (std::size_t i = 0; i < n; ++i) {
    const double x = u(rng), y = u(rng), z = u(rng);
    const Vec3 p = at + Vec3(x * size.x(), y * size.y(), z * size.z());
    points.push_back(p);
    out << p.x() << "," << p.y() << "," << p.z() << "\n";
  }
  return points;
}

using Key = std::array<float, 3>;
std::map<Key, int> asFloats(const PointList& points) {
  std::map<Key, int> out;
  for (const Vec3& p : points)
    ++out[{static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())}];
  return out;
}

TEST(StreamCloud, SamePointsAndFrameAsLoadCloud) {
  const fs::path d = tempDir("stream");
  // Far from the origin (a UTM-like position): both readers recentre, the same way.
  writeCloud(d / "far.xyz", 5000, Vec3(500100.0, 5400200.0, 30.0), Vec3(80.0, 40.0, 10.0), 3);
  io::CloudReadInfo whole_info;
  const PointList whole = io::loadCloud((d / "far.xyz").string(), {}, &whole_info);
  PointList streamed;
  std::size_t largest_chunk = 0;
  const io::CloudStreamInfo info =
      io::streamCloud((d / "far.xyz").string(), {}, 333, [&](const PointList& chunk) {
        largest_chunk = std::max(largest_chunk, chunk.size());
        streamed.insert(streamed.end(), chunk.begin(), chunk.end());
      });
  EXPECT_LE(largest_chunk, 333U);
  EXPECT_EQ(info.points, whole.size());
  EXPECT_EQ(info.read.origin_m, whole_info.origin_m);
  ASSERT_EQ(streamed.size(), whole.size());
  for (std::size_t i = 0; i < whole.size(); ++i) EXPECT_EQ(streamed[i], whole[i]) << i;
  fs::remove_all(d);
}

TEST(TileCloud, EveryPointInItsOwnerAndEveryBufferedTile) {
  const fs::path d = tempDir("assign");
  const PointList input =
      writeCloud(d / "site.csv", 20000, Vec3(-12.0, 3.0, 0.0), Vec3(95.0, 41.0, 8.0), 7);
  tiling::TileOptions options;
  options.tile_size_m = 20.0;
  options.buffer_m = 4.5;
  options.chunk_points = 1000;  // many flushes of the per-tile buffers
  io::StagedOutputs outputs;
  const fs::path tiles = d / "tiles";
  tiling::Manifest m =
      tiling::tileCloud((d / "site.csv").string(), {}, options, tiles.string(), outputs);
  outputs.commit();
  m.path = (tiles / "manifest.json").string();
  EXPECT_EQ(m.input_points, input.size());
  EXPECT_EQ(m.columns, 5);
  EXPECT_EQ(m.rows, 3);
  // No temporary point file is left behind.
  for (const auto& e : fs::directory_iterator(tiles))
    EXPECT_EQ(e.path().extension(), ".pcd") << e.path();

  // Brute force: per tile, the input points in its core (owner by the half-open rule,
  // computed here from the grid numbers) and those in its closed buffered box.
  std::size_t owned_total = 0;
  for (const tiling::TileRecord& t : m.tiles) {
    PointList core, extra;
    for (const Vec3& p : input) {
      const double cx = std::clamp(std::floor((p.x() - m.grid_origin.x()) / 20.0), 0.0, 4.0);
      const double cy = std::clamp(std::floor((p.y() - m.grid_origin.y()) / 20.0), 0.0, 2.0);
      const bool own = static_cast<int>(cx) == t.column && static_cast<int>(cy) == t.row;
      const bool near = p.x() >= m.grid_origin.x() + t.column * 20.0 - 4.5 &&
                        p.x() <= m.grid_origin.x() + (t.column + 1) * 20.0 + 4.5 &&
                        p.y() >= m.grid_origin.y() + t.row * 20.0 - 4.5 &&
                        p.y() <= m.grid_origin.y() + (t.row + 1) * 20.0 + 4.5;
      if (own)
        core.push_back(p);
      else if (near)
        extra.push_back(p);
    }
    EXPECT_EQ(t.core_points, core.size()) << "tile " << t.index;
    EXPECT_EQ(t.buffer_points, extra.size()) << "tile " << t.index;
    owned_total += t.core_points;
    const PointList read = io::loadCloud((tiles / t.cloud).string());
    PointList expected = core;
    expected.insert(expected.end(), extra.begin(), extra.end());
    EXPECT_EQ(asFloats(read), asFloats(expected)) << "tile " << t.index;
    // The core points come first.
    const PointList first(read.begin(), read.begin() + static_cast<long>(core.size()));
    EXPECT_EQ(asFloats(first), asFloats(core)) << "tile " << t.index;
  }
  EXPECT_EQ(owned_total, input.size());  // each point owned exactly once

  // The manifest reads back as written.
  io::writeFileAtomic(m.path, tiling::manifestJsonText(m));
  const tiling::Manifest back = tiling::loadManifest(m.path);
  ASSERT_EQ(back.tiles.size(), m.tiles.size());
  for (std::size_t i = 0; i < m.tiles.size(); ++i) {
    EXPECT_EQ(back.tiles[i].core_points, m.tiles[i].core_points);
    EXPECT_EQ(back.tiles[i].sha256, m.tiles[i].sha256);
  }
  EXPECT_THROW(back.tile(static_cast<long>(m.tiles.size())), uavip::InputError);
  fs::remove_all(d);
}

TEST(TileCloud, RefusesBadOptions) {
  tiling::TileOptions o;
  o.tile_size_m = 0.0;
  EXPECT_THROW(o.validate(), uavip::InputError);
  o.tile_size_m = 10.0;
  o.buffer_m = -1.0;
  EXPECT_THROW(o.validate(), uavip::InputError);
}

}  // namespace
