#pragma once
/// \file
/// One scene from the scenes of the tiles: every point kept once, by the
/// tile whose core owns it (tiling/tiles.h), and the surfaces and obstacles that
/// cross a tile border joined into one.
///
/// The rule: a tile's surface or obstacle keeps only the points its tile owns (a part
/// with none is dropped: another tile owns all of it). Two parts of neighbouring tiles
/// are joined when they come within the detector's plane cluster tolerance of each other
/// and, for surfaces, lie on the same plane within the detector's thresholds: normals
/// within `max_angle_deg` (same orientation) and each part's centroid within
/// `distance_threshold_m` of the other's plane. A joined surface is refitted (PCA plane
/// oriented like its largest part, the detector's kind of boundary: the occupied cells'
/// outline with its holes, or the convex hull; both areas); a surface part
/// whose kept points no longer reach `min_area_m2` becomes an obstacle. The safety
/// cloud is the union of each tile's owned safety points. Ids are given in the order
/// of (tile, id in the tile), so the result is deterministic.

#include <string>
#include <vector>

#include "uavip/core/types.h"
#include "uavip/perception/plane_detector.h"
#include "uavip/tiling/tiles.h"

namespace uavip::tiling {

/// Thresholds of the join: the detector's own options (app::Config::mergeOptions builds
/// them from the resolved config), so a joined surface meets the rules its parts met.
struct MergeOptions {
  /// Same plane when each part's centroid is within `distance_threshold_m` of the other's
  /// plane; parts closer than `cluster_tolerance_m` (perception.plane_cluster_tolerance_m)
  /// touch; a surface under `min_area_m2` becomes an obstacle; the density area's cell is
  /// `cell_size_m`; a refitted surface gets the detector's `boundary` and outline
  /// (PlaneDetectionOptions::outlineOptions()).
  perception::PlaneDetectionOptions planes;
  double max_angle_deg{10.0};  ///< same plane when the normals are within it [deg]
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
