#pragma once
/// \file
/// Stage 5 (paper §II-E): Euclidean clustering of the points that belong to no
/// surface (euclidean_clusters.h: PCL EuclideanClusterExtraction's partition, on a
/// voxel grid).

#include <string>
#include <vector>

#include "uavip/core/types.h"

namespace uavip::perception {

/// Options of stage 5.
struct ClusterOptions {
  double tolerance_m{0.3};  ///< r < epsilon of the paper's pseudo code [m]
  int min_points{
      1};  ///< clusters smaller than this are merged into one "residual" obstacle, never dropped

  /// Throws InputError naming the bad field (prefix `where`).
  void validate(const std::string& where = "perception") const;
};

/// Clusters `points` into obstacles with ids 0..n-1, largest first (ties: by
/// smallest coordinate), each with its axis-aligned box. Every input point ends in
/// exactly one obstacle. Deterministic.
std::vector<Obstacle> clusterObstacles(const PointList& points, const ClusterOptions& options);

}  // namespace uavip::perception
