#pragma once
/// \file
/// Stage 5 (paper §II-E): Euclidean clustering of the points that belong to no
/// surface (euclidean_clusters.h: PCL EuclideanClusterExtraction's partition, on a
/// voxel grid).

#include <string>
#include <vector>

#include "uavip/core/params.h"
#include "uavip/core/types.h"

namespace uavip::perception {

/// Options of stage 5.
struct ClusterOptions {
  double tolerance_m{0.3};  ///< r < epsilon of the paper's pseudo code [m]
  /// Clusters smaller than this are merged into one "residual" obstacle, never dropped.
  int min_points{1};

  /// Throws InputError naming the bad key (prefix `where`).
  void validate(const std::string& where = "perception") const;
  /// The keys of `perception:` this struct holds (core/params.h).
  static const params::Table<ClusterOptions>& table();
};

/// Clusters `points` into obstacles with ids 0..n-1, largest first (ties: by
/// smallest coordinate), each with its axis-aligned box. Every input point ends in
/// exactly one obstacle. Deterministic.
std::vector<Obstacle> clusterObstacles(const PointList& points, const ClusterOptions& options);

}  // namespace uavip::perception
