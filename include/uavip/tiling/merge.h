#pragma once
/// \file
/// One scene from the scenes of the tiles: every point kept once, by the
/// tile whose core owns it (tiling/tiles.h), and the surfaces and obstacles that
/// cross a tile border joined into one.
///
/// The rule: a tile's surface or obstacle keeps only the points its tile owns (a part
/// with none is dropped: another tile owns all of it). Two parts of neighbouring tiles
/// are joined when they come within `join_gap_m` of each other and, for surfaces, lie
/// on the same plane within the detector's thresholds: normals within
/// `max_angle_deg` (same orientation) and each part's centroid within
/// `distance_threshold_m` of the other's plane. A joined surface is refitted (PCA plane
/// oriented like its largest part, the detector's kind of boundary: the occupied cells'
/// outline with its holes, or the convex hull; both areas); a surface part
/// whose kept points no longer reach `min_area_m2` becomes an obstacle. The safety
/// cloud is the union of each tile's owned safety points. Ids are given in the order
/// of (tile, id in the tile), so the result is deterministic.

#include <string>
#include <vector>

#include "uavip/core/types.h"
#include "uavip/perception/surface_outline.h"
#include "uavip/tiling/tiles.h"

namespace uavip::tiling {

/// Thresholds of the join (defaults: the detector's).
struct MergeOptions {
  double distance_threshold_m{0.2};  ///< RANSAC band: same plane when within it [m]
  double max_angle_deg{10.0};        ///< same plane when the normals are within it [deg]
  double join_gap_m{0.3};            ///< parts closer than this touch [m]
  double min_area_m2{2.0};           ///< a surface smaller than this becomes an obstacle [m²]
  double area_cell_m{0.1};           ///< cell of the density area [m]
  /// Boundary of a refitted surface: "outline" (perception/surface_outline.h, with
  /// `outline`'s cell, closing and holes) or "convex" (the paper's hull).
  std::string boundary{"outline"};
  perception::OutlineOptions outline;
  /// Also keep the safety points the given tiles' buffers saw in cores of tiles not
  /// given (each once): a section of the site planned apart from its neighbours then
  /// keeps clear of what lies just past its border.
  bool keep_buffer_safety{false};
  /// Throws InputError "<where>: …" naming the bad value.
  void validate(const std::string& where = "merge") const;
};

/// One tile's scene (scene.json of uavip run-tile) and the tile.
struct TileScene {
  TileRecord tile;
  Scene scene;
};

/// What the merge did.
struct MergeStats {
  int surface_parts{0};     ///< surfaces read from the tiles
  int surfaces_dropped{0};  ///< with no owned point
  int surfaces_joined{0};   ///< parts joined into another
  int surfaces_demoted{0};  ///< too small once cut to the core: obstacles
  int obstacle_parts{0};    ///< obstacles read from the tiles
  int obstacles_joined{0};  ///< parts joined into another
  std::size_t safety_points{0};
};

/// The scene of the given tiles (the whole site, or a section of it) from their scenes
/// (each tile at most once). `measured` of the result: the largest tile's (spacing,
/// noise), with the count of the tiles' owned points and the box of the merged cloud.
Scene mergeTileScenes(const Manifest& manifest, const std::vector<TileScene>& tiles,
                      const MergeOptions& options, MergeStats* stats = nullptr);

}  // namespace uavip::tiling
