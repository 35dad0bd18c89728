// uavip tile (tiling/tiles.h): every tile's cloud against a brute-force assignment of
// the input points, and the streamed reader against the whole-cloud reader.

#include "uavip/tiling/tiles.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "uavip/core/error.h"
#include "uavip/io/cloud_io.h"
#include "uavip/io/file_digest.h"

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

/// Every point and the info of a stream in a known frame (one pass).
PointList streamedInFrame(const std::string& path, const Vec3& frame, io::CloudStreamInfo* info) {
  PointList out;
  *info = io::streamCloudInFrame(path, {}, frame, 333, [&](const PointList& chunk) {
    EXPECT_LE(chunk.size(), 333U);
    out.insert(out.end(), chunk.begin(), chunk.end());
  });
  return out;
}

TEST(StreamCloud, InAKnownFrameOnePassGivesTheTwoPassPoints) {
  const fs::path d = tempDir("frame");
  writeCloud(d / "far.xyz", 5000, Vec3(500100.0, 5400200.0, 30.0), Vec3(80.0, 40.0, 10.0), 3);
  writeCloud(d / "near.xyz", 3000, Vec3(-5.0, 2.0, 0.0), Vec3(30.0, 20.0, 5.0), 4);
  for (const std::string& f : {(d / "far.xyz").string(), (d / "near.xyz").string(),
                               std::string(UAVIP_SOURCE_DIR) + "/tests/data/autzen_trim.las"}) {
    PointList two;
    const io::CloudStreamInfo two_info = io::streamCloud(f, {}, 333, [&](const PointList& chunk) {
      two.insert(two.end(), chunk.begin(), chunk.end());
    });
    io::CloudStreamInfo info;
    const PointList one = streamedInFrame(f, two_info.read.origin_m, &info);
    EXPECT_EQ(one, two) << f;  // bit for bit
    EXPECT_EQ(info.read.origin_m, two_info.read.origin_m) << f;
    EXPECT_EQ(info.points, two_info.points) << f;
    EXPECT_EQ(info.min, two_info.min) << f;
    EXPECT_EQ(info.max, two_info.max) << f;
    // Another frame: the points shifted by the difference, the file's own frame said.
    const Vec3 other = two_info.read.origin_m + Vec3(3.0, -2.0, 1.0);
    const PointList shifted = streamedInFrame(f, other, &info);
    EXPECT_EQ(info.read.origin_m, two_info.read.origin_m) << f;
    ASSERT_EQ(shifted.size(), two.size()) << f;
    for (std::size_t i = 0; i < two.size(); i += 97)
      EXPECT_LT((shifted[i] - (two[i] - Vec3(3.0, -2.0, 1.0))).norm(), 1e-6) << f << " " << i;
  }
  fs::remove_all(d);
}

/// Writes `points` as a PLY file of double x y z after a uchar and a float property:
/// "ascii", "binary_little_endian" or "binary_big_endian".
void writePly(const fs::path& file, const PointList& points, const std::string& format) {
  std::ofstream out(file, std::ios::binary);
  out << "ply\nformat " << format << " 1.0\ncomment uavip test\nelement vertex " << points.size()
      << "\nproperty uchar quality\nproperty double x\nproperty double y\nproperty double "
         "z\nproperty float intensity\nelement extra 1\nproperty int tag\nend_header\n";
  out.precision(17);
  const auto put = [&](const auto& value) {
    char bytes[sizeof value];
    std::memcpy(bytes, &value, sizeof value);
    if (format == "binary_big_endian") std::reverse(bytes, bytes + sizeof value);
    out.write(bytes, sizeof value);
  };
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3& p = points[i];
    if (format == "ascii") {
      out << i % 200 << " " << p.x() << " " << p.y() << " " << p.z() << " "
          << 0.5 * static_cast<double>(i) << "\n";
      continue;
    }
    put(static_cast<std::uint8_t>(i % 200));
    put(p.x());
    put(p.y());
    put(p.z());
    put(static_cast<float>(0.5 * static_cast<double>(i)));
  }
  if (format == "ascii")
    out << "7\n";
  else
    put(std::int32_t{7});
}

TEST(TileCloud, APlySiteTiledInAStreamAsReadWhole) {
  // The same points as ascii and little-endian PLY (streamed) and big-endian PLY
  // (read whole by PCL): the same points read, the same tiles byte for byte.
  const fs::path d = tempDir("ply");
  const PointList input =
      writeCloud(d / "site.csv", 6000, Vec3(300010.0, 4100020.0, 5.0), Vec3(61.0, 33.0, 8.0), 9);
  const std::vector<std::string> formats = {"ascii", "binary_little_endian", "binary_big_endian"};
  for (const std::string& format : formats) writePly(d / (format + ".ply"), input, format);
  EXPECT_TRUE(io::streamsInBoundedMemory((d / "ascii.ply").string()));
  EXPECT_TRUE(io::streamsInBoundedMemory((d / "binary_little_endian.ply").string()));
  EXPECT_FALSE(io::streamsInBoundedMemory((d / "binary_big_endian.ply").string()));
  tiling::TileOptions options;
  options.tile_size_m = 20.0;
  options.buffer_m = 4.5;
  options.chunk_points = 1000;
  std::vector<std::vector<std::string>> digests;
  for (const std::string& format : formats) {
    const std::string ply = (d / (format + ".ply")).string();
    io::CloudReadInfo whole_info;
    const PointList whole = io::loadCloud(ply, {}, &whole_info);
    ASSERT_EQ(whole.size(), input.size()) << format;
    PointList streamed;
    const io::CloudStreamInfo info = io::streamCloud(ply, {}, 777, [&](const PointList& chunk) {
      EXPECT_LE(chunk.size(), 777U);
      streamed.insert(streamed.end(), chunk.begin(), chunk.end());
    });
    EXPECT_EQ(streamed, whole) << format;  // bit for bit, in the same frame
    EXPECT_EQ(info.read.origin_m, whole_info.origin_m) << format;
    io::StagedOutputs outputs;
    const tiling::Manifest m =
        tiling::tileCloud(ply, {}, options, (d / ("tiles_" + format)).string(), outputs);
    outputs.commit();
    EXPECT_EQ(m.input_points, input.size()) << format;
    digests.emplace_back();
    for (const auto& t : m.tiles) {
      EXPECT_EQ(io::sha256File((d / ("tiles_" + format) / t.cloud).string()), t.sha256);
      digests.back().push_back(t.sha256);
    }
  }
  EXPECT_GT(digests[0].size(), 3U);
  EXPECT_EQ(digests[0], digests[2]);  // ascii streamed, big endian read whole
  EXPECT_EQ(digests[1], digests[2]);  // little endian streamed
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
