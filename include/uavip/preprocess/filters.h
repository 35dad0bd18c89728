#pragma once
/// \file
/// Stage 3 (paper §II-C): statistical outlier removal and voxel-grid
/// down-sampling. The outlier filter keeps exactly the points that
/// pcl::StatisticalOutlierRemoval keeps, computed on the same FLANN kd-tree with the
/// kNN queries split over threads; the voxel grid is core/voxel_key.h's
/// down-sampler (64-bit keys: PCL's VoxelGrid overflows its 32-bit index on a
/// 130 m building at 5 cm).

#include <cstddef>
#include <string>

#include "uavip/core/neighbour_index.h"
#include "uavip/core/params.h"
#include "uavip/core/types.h"

namespace uavip::preprocess {

/// Options of stage 3.
struct PreprocessOptions {
  bool remove_outliers{true};
  int outlier_k{16};  ///< neighbours for the mean distance of each point
  double outlier_std_ratio{
      2.0};  ///< d_t: a point whose mean neighbour distance is above mu + d_t·sigma is removed
  bool voxelize{true};
  double voxel_m{0.05};  ///< voxel edge; each occupied voxel is replaced by its centroid [m]
  int threads{
      2};  ///< threads for the outlier statistic's kNN queries; the result does not depend on it

  /// Throws InputError naming the bad field (prefix `where`).
  void validate(const std::string& where = "preprocess") const;
  /// The keys of `preprocess:` this struct holds (core/params.h).
  static const params::Table<PreprocessOptions>& table();
};

/// Counts of stage 3.
struct PreprocessStats {
  std::size_t input_points{0};
  std::size_t after_outliers{0};
  std::size_t output_points{0};
};

/// Removes points whose mean distance to their k nearest neighbours lies above
/// mu + d_t·sigma of all such means (Rusu 2008). Keeps exactly the points, in input
/// order, that pcl::StatisticalOutlierRemoval keeps (same FLANN kd-tree, same
/// arithmetic), with the kNN queries split over `threads` threads; the result does
/// not depend on `threads`. Clouds with ≤ k points are returned unchanged (the
/// statistics are meaningless there). `index`, if given, is a kd-tree over this very
/// cloud (built once for this and measureCloud); else one is built. Throws
/// InputError for k < 1, std_ratio ≤ 0, threads < 1 or a non-finite point, and
/// std::invalid_argument for an index over another cloud.
PointList removeStatisticalOutliers(const PointList& cloud, int k, double std_ratio,
                                    int threads = 2, const NeighbourIndex* index = nullptr);

/// Replaces the points of each occupied voxel (edge leaf_m) by their centroid.
/// Output order is deterministic. Throws InputError when the extent exceeds 2^21
/// voxels on an axis.
PointList voxelGrid(const PointList& cloud, double leaf_m, int threads = 1);

/// Stage 3 as configured. `index`: as for removeStatisticalOutliers. Throws
/// InputError for an empty cloud or non-finite points.
PointList preprocess(const PointList& cloud, const PreprocessOptions& options,
                     PreprocessStats* stats = nullptr, const NeighbourIndex* index = nullptr);

}  // namespace uavip::preprocess
