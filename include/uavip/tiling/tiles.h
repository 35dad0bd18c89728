#pragma once
/// \file
/// Square tiles of a large cloud: the cloud is streamed once (two passes of
/// io::streamCloud, never held whole) into tiles of edge `tile_size_m` in x and y, each
/// with an overlap buffer of `buffer_m` around its core, plus TILES/manifest.json.
///
/// Ownership: the grid starts at the cloud's minimum x, y; a point belongs to the core
/// of exactly one tile, cell (⌊(x − x0)/s⌋, ⌊(y − y0)/s⌋) clamped to the grid (half-open
/// cells; the last column and row also own their upper edge). A tile's cloud holds its
/// core points first, then every other point within its buffered box (the buffer is
/// flagged by position, not cut): stages 3–5 see past the border, and the merge keeps
/// each point once, in the tile that owns it (tiling/merge.h).
///
/// Files: TILES/manifest.json (manifestJsonText), TILES/tile_NNNN.pcd per tile with at
/// least one core point; a tile's results go to TILES/tile_NNNN/ (uavip run-tile).

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "uavip/core/types.h"
#include "uavip/io/atomic_file.h"
#include "uavip/io/cloud_io.h"

namespace uavip::tiling {

/// Options of `uavip tile`.
struct TileOptions {
  double tile_size_m{100.0};  ///< edge of a tile's square core in x and y [m]
  double buffer_m{10.0};      ///< overlap kept around each core [m]
  /// Points read and kept per tile in memory before they go to the tile's file.
  std::size_t chunk_points{std::size_t{1} << 20};
  /// Throws InputError "<where>: …" naming the bad value.
  void validate(const std::string& where = "tile") const;
};

/// An axis-aligned rectangle in x, y [m].
struct Box2 {
  Eigen::Vector2d min{Eigen::Vector2d::Zero()};  ///< [m]
  Eigen::Vector2d max{Eigen::Vector2d::Zero()};  ///< [m]
  /// True when p's x, y lie in the closed rectangle.
  bool contains(const Vec3& p) const {
    return p.x() >= min.x() && p.x() <= max.x() && p.y() >= min.y() && p.y() <= max.y();
  }
};

/// One tile of the manifest.
struct TileRecord {
  int index{0};                    ///< 0-based position in Manifest::tiles (the Slurm array index)
  int column{0};                   ///< grid cell in x
  int row{0};                      ///< grid cell in y
  Box2 core;                       ///< what the tile owns [m]
  Box2 buffered;                   ///< core grown by the buffer: what its cloud holds [m]
  std::uint64_t core_points{0};    ///< points owned
  std::uint64_t buffer_points{0};  ///< points of other cores within the buffer
  std::string cloud;               ///< file name of its cloud beside the manifest
  std::string sha256;              ///< of that file
  std::string out;                 ///< folder name of its results beside the manifest
};

/// TILES/manifest.json.
struct Manifest {
  std::string path;   ///< the manifest file read (not written)
  std::string input;  ///< the input cloud, absolute path
  std::string input_sha256;
  std::uint64_t input_points{0};
  io::CloudReadOptions read;           ///< how the input was read (input: section)
  Vec3 source_offset_m{Vec3::Zero()};  ///< add to a point to get file coordinates [m]
  std::string crs_unit;                ///< a LAS file's unit and its source; else empty
  /// The input's CRS (a LAS file's WKT) as detect records it, so every tile's and the
  /// merged scene.json keep it; empty when the input states none.
  std::string crs;
  std::string crs_source;    ///< where crs came from ("LAS WKT record 2112")
  std::string crs_vertical;  ///< "egm96", "egm2008", "ellipsoid" or empty (unknown)
  std::string config;        ///< the -c config given to tile (absolute), or empty
  double tile_size_m{0.0};   ///< [m]
  double buffer_m{0.0};      ///< [m]
  Eigen::Vector2d grid_origin{Eigen::Vector2d::Zero()};  ///< minimum x, y of the cloud [m]
  int columns{0};
  int rows{0};
  Vec3 min{Vec3::Zero()};  ///< bounding box of the cloud [m]
  Vec3 max{Vec3::Zero()};  ///< [m]
  std::vector<TileRecord> tiles;

  /// (column, row) of the tile whose core owns p.
  std::pair<int, int> cellOf(const Vec3& p) const;
  /// The tile of that index; throws InputError naming the manifest and the valid range.
  const TileRecord& tile(long index) const;
  /// The folder of the manifest (where the tile files are).
  std::string dir() const;
};

/// The text of manifest.json (its one writer).
std::string manifestJsonText(const Manifest& manifest);
/// Reads manifest.json; throws InputError naming the file and the bad field.
Manifest loadManifest(const std::string& path);

/// Streams `cloud` (read with `read`, as io::loadCloud would) into tiles: stages each
/// tile's cloud TILES/tile_NNNN.pcd in `outputs` and returns the manifest (not yet
/// written; `input_sha256` and `config` are the caller's). Memory: the per-tile write
/// buffers (chunk_points / 8 points each) and the largest tile when it is written; the
/// points go through temporary files in `out_dir`, removed on return or error.
Manifest tileCloud(const std::string& cloud, const io::CloudReadOptions& read,
                   const TileOptions& options, const std::string& out_dir,
                   io::StagedOutputs& outputs);

}  // namespace uavip::tiling
