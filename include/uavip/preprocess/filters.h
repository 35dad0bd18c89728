#pragma once
/// \file
/// Stage 3 (paper §II-C): statistical outlier removal and voxel-grid
/// down-sampling, on PCL (StatisticalOutlierRemoval, VoxelGrid).

#include "uavip/core/types.h"

#include <cstddef>
#include <string>

namespace uavip::preprocess {

/// Options of stage 3.
struct PreprocessOptions {
  bool remove_outliers{true};
  int outlier_k{16};             ///< neighbours for the mean distance of each point
  double outlier_std_ratio{2.0}; ///< d_t: a point whose mean neighbour distance is outside mu ± d_t·sigma is removed
  bool voxelize{true};
  double voxel_m{0.05};          ///< voxel edge; each occupied voxel is replaced by its centroid [m]

  /// Throws InputError naming the bad field (prefix `where`).
  void validate(const std::string& where = "preprocess") const;
};

/// Counts of stage 3.
struct PreprocessStats {
  std::size_t input_points{0};
  std::size_t after_outliers{0};
  std::size_t output_points{0};
};

/// Removes points whose mean distance to their k nearest neighbours lies outside
/// mu ± d_t·sigma of all such means (Rusu 2008). Clouds with ≤ k points are returned
/// unchanged (the statistics are meaningless there).
PointList removeStatisticalOutliers(const PointList& cloud, int k, double std_ratio);

/// Replaces the points of each occupied voxel (edge leaf_m) by their centroid.
/// Output order is deterministic.
PointList voxelGrid(const PointList& cloud, double leaf_m);

/// Stage 3 as configured. Throws InputError for an empty cloud or non-finite points.
PointList preprocess(const PointList& cloud, const PreprocessOptions& options,
                     PreprocessStats* stats = nullptr);

}  // namespace uavip::preprocess
