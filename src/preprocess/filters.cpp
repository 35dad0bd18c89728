#include "uavip/preprocess/filters.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "uavip/core/error.h"
#include "uavip/core/geometry.h"
#include "uavip/core/parallel.h"
#include "uavip/core/text.h"
#include "uavip/core/voxel_key.h"

namespace uavip::preprocess {

void PreprocessOptions::validate(const std::string& where) const {
  table().check(*this, where);
  if (threads < 1)
    throw InputError(where + ": threads must be >= 1, got " + std::to_string(threads));
}

const params::Table<PreprocessOptions>& PreprocessOptions::table() {
  static const params::Table<PreprocessOptions> t = [] {
    using O = PreprocessOptions;
    params::Table<O> p;
    p.add("remove_outliers", &O::remove_outliers, "statistical outlier removal (paper: on)");
    p.add("outlier_k", &O::outlier_k, "neighbours of each point's mean distance (PCL's meanK)")
        .atLeast(1);
    p.add("outlier_std_ratio", &O::outlier_std_ratio,
          "d_t: a point whose mean neighbour distance is above mu + d_t·sigma is removed")
        .positive();
    p.add("voxelize", &O::voxelize, "voxel-grid down-sampling (paper: on)");
    p.add("voxel_m", &O::voxel_m,
          "voxel edge; each occupied voxel becomes its centroid (paper: 5 cm)")
        .unitIs("m")
        .positive()
        .mayBeAuto();
    return p;
  }();
  return t;
}

PointList removeStatisticalOutliers(const PointList& cloud, int k, double std_ratio, int threads,
                                    const NeighbourIndex* index) {
  if (k < 1) {
    throw InputError("removeStatisticalOutliers: k must be >= 1, got " + std::to_string(k));
  }
  requirePositive(std_ratio, "removeStatisticalOutliers", "std_ratio");
  if (threads < 1) {
    throw InputError("removeStatisticalOutliers: threads must be >= 1, got " +
                     std::to_string(threads));
  }
  if (index != nullptr && &index->cloud() != &cloud) {
    throw std::invalid_argument("removeStatisticalOutliers: the index is over another cloud");
  }
  if (cloud.size() <= static_cast<std::size_t>(k)) return cloud;

  // The same computation as pcl::StatisticalOutlierRemoval<PointXYZ> (PCL 1.13), on the
  // same FLANN kd-tree (neighbour_index.h) that its pcl::search::KdTree builds, and
  // with the same float/double arithmetic, so the kept set is identical (tested
  // against PCL's filter). What differs: the float copy goes straight from the
  // PointList into FLANN (no intermediate PCL cloud), the tree may be shared with the
  // cloud's measurement, the queries are batched (no per-query wrapper) and split
  // over `threads` threads. Each point's statistic depends on its own query only,
  // and the mean and sigma are summed in index order by one thread, so the result
  // does not depend on the scheduling.
  std::unique_ptr<NeighbourIndex> own;
  if (index == nullptr) {
    try {
      own = std::make_unique<NeighbourIndex>(cloud);
    } catch (const InputError& e) {
      throw InputError(std::string("removeStatisticalOutliers: ") + e.what());
    }
    index = own.get();
  }
  const std::size_t n = cloud.size();

  // First pass: mean distance of each point to its k nearest neighbours (the query
  // point itself is the first of the k + 1 results).
  const int searcher_k = k + 1;
  std::vector<float> distances(n);
  // Batches of kBatch queries on the worker pool, a scratch row block per worker.
  constexpr std::size_t kBatch = 2048;
  const auto row_block = kBatch * static_cast<std::size_t>(searcher_k);
  std::vector<std::vector<int>> nn_indices(static_cast<std::size_t>(threads));
  std::vector<std::vector<float>> nn_dists(static_cast<std::size_t>(threads));
  parallelFor((n + kBatch - 1) / kBatch, threads, [&](std::size_t batch, std::size_t worker) {
    auto& idx = nn_indices[worker];
    auto& dst = nn_dists[worker];
    idx.resize(row_block);
    dst.resize(row_block);
    const std::size_t b = batch * kBatch;
    const std::size_t m = std::min(kBatch, n - b);
    index->nearest(b, m, searcher_k, idx.data(), dst.data());
    for (std::size_t r = 0; r < m; ++r) {
      const float* row = dst.data() + r * static_cast<std::size_t>(searcher_k);
      double dist_sum = 0.0;
      for (int j = 1; j < searcher_k; ++j) dist_sum += std::sqrt(static_cast<double>(row[j]));
      distances[b + r] = static_cast<float>(dist_sum / k);
    }
  });

  // Mean and standard deviation of the statistic, then the threshold mu + d_t * sigma.
  double sum = 0.0;
  double sq_sum = 0.0;
  for (const float d : distances) {
    sum += d;
    sq_sum += d * d;  // float product, as PCL
  }
  const auto valid = static_cast<double>(n);
  const double mean = sum / valid;
  const double variance = (sq_sum - sum * sum / valid) / (valid - 1.0);
  const double threshold = mean + std_ratio * std::sqrt(variance);

  PointList out;
  out.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (!(static_cast<double>(distances[i]) > threshold)) out.push_back(cloud[i]);
  }
  return out;
}

PointList voxelGrid(const PointList& cloud, double leaf_m, int threads) {
  requirePositive(leaf_m, "preprocess", "voxel_m");
  try {
    return voxelDownsample(cloud, leaf_m, "voxel_m", threads);
  } catch (const InputError& e) {
    throw InputError(std::string("preprocess: ") + e.what());
  }
}

PointList preprocess(const PointList& cloud, const PreprocessOptions& options,
                     PreprocessStats* stats, const NeighbourIndex* index) {
  options.validate();
  if (cloud.empty()) throw InputError("preprocess: cloud is empty");
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (!cloud[i].allFinite()) {
      throw InputError("preprocess: point " + std::to_string(i) +
                       " is not finite: " + formatRawPoint(cloud[i]));
    }
  }

  PointList current = options.remove_outliers ? removeStatisticalOutliers(cloud, options.outlier_k,
                                                                          options.outlier_std_ratio,
                                                                          options.threads, index)
                                              : cloud;
  const std::size_t after_outliers = current.size();
  if (options.voxelize) current = voxelGrid(current, options.voxel_m, options.threads);

  if (stats != nullptr) {
    stats->input_points = cloud.size();
    stats->after_outliers = after_outliers;
    stats->output_points = current.size();
  }
  return current;
}

}  // namespace uavip::preprocess
