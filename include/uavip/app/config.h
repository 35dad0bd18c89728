#pragma once
/// \file
/// Where every parameter is resolved. A config (app/scenario.h: the YAML's sections
/// with the paper's values as defaults) says which keys the user set; every other
/// key marked `auto` below follows the measured cloud (preprocess/cloud_stats.h).
/// A value set in the YAML always wins. On a dense scan (spacing ≤ 5 cm, noise
/// ≤ 5 cm) every rule gives the paper's value, so the synthetic scenarios keep
/// their outcomes.
///
/// The rules (s = measured spacing, σ = noise, v = voxel, s' = max(s, v) the
/// spacing after the voxel grid):
///   preprocess.voxel_m                     = max(0.05, s)            paper: 5 cm
///   perception.distance_threshold_m        = max(0.20, 4σ, s'/2)     paper: 20 cm band
///   perception.plane_cluster_tolerance_m   = max(0.30, 3 s')         joins a plane's inliers
///   perception.obstacle_tolerance_m        = max(0.30, 3 s')         §II-E's r
///   perception.area_cell_m                 = 2 s' on a lattice (a synthetic sampling, or
///                                            a voxel grid ≥ 1.5 s), 3 s' otherwise: a
///                                            cell holds several points, so a lattice
///                                            aligned with the cells cannot alias
///                                            (area = occupied cells × cell²)
///   perception.min_inliers                 = 30                      a plane needs support
///   perception.open_voxel_m                = max(0.1, 2 s')          openness rays (no sensor
///   known) perception.viewpoint                   = the origin when the cloud is one scan from
///                                            it (cloud_stats.h scanned_from_origin): each
///                                            normal faces it; otherwise none (openness)
///   grid.resolution_m                      = max(0.2, the edge that keeps the grid
///                                            ≤ grid.max_voxels / 4): here for the whole
///                                            site; app::plan applies it again to the
///                                            region it plans (the stops + 6 m)
///   camera (no camera.* and no coverage.standoff_m set) = the paper's 0.6 × 0.4 m
///                                            footprint at 1.5 m, or for a structure over
///                                            20 m (not a single scan from the origin:
///                                            rooms, streets) a 1-inch 20 MP camera (13.2 × 8.8 mm,
///                                            8.8 mm, 5472 × 3648 px) at 2 mm/px: 7.3 m off
/// Derived, never set directly: the area cell from the sensing spacing of a
/// synthetic scenario (a lattice), grid inflation from the UAV.

#include <string>
#include <vector>

#include "uavip/app/scenario.h"
#include "uavip/io/scene_json.h"
#include "uavip/preprocess/cloud_stats.h"

namespace uavip::app {

/// One resolved parameter, for the printout and scene.json: key, value, source
/// ("set", "auto: max(0.05, spacing)", "default (paper)").
using ResolvedValue = io::ParameterRecord;

/// The config every stage runs with, and how each auto value was chosen.
struct ResolvedConfig {
  app::Config config;
  std::vector<ResolvedValue> values;
};

/// The `auto` planning-grid edge for a box of this extent [m]: max(0.2 m, the edge
/// that keeps the grid (with its padding) ≤ grid.max_voxels / 4).
double autoGridResolution(const Vec3& extent_m, const world::GridOptions& grid);

/// Applies the rules above to every auto key the user did not set; validates the
/// result (InputError naming the key). Pure: the same inputs give the same config.
ResolvedConfig resolveConfig(const app::Config& config, const preprocess::CloudStats& stats);

}  // namespace uavip::app
