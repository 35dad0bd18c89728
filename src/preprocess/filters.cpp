#include "uavip/preprocess/filters.h"

#include "uavip/core/error.h"
#include "uavip/core/geometry.h"
#include "uavip/core/pcl_cloud.h"
#include "uavip/core/text.h"
#include "uavip/core/voxel_key.h"

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <thread>
#include <vector>

namespace uavip::preprocess {
namespace {

using PclCloud = pcl::PointCloud<pcl::PointXYZ>;

}  // namespace

void PreprocessOptions::validate(const std::string& where) const {
  if (outlier_k < 1) {
    throw InputError(where + ": outlier_k must be >= 1, got " + std::to_string(outlier_k));
  }
  requirePositive(outlier_std_ratio, where, "outlier_std_ratio");
  requirePositive(voxel_m, where, "voxel_m");
  if (threads < 1) throw InputError(where + ": threads must be >= 1, got " + std::to_string(threads));
}

PointList removeStatisticalOutliers(const PointList& cloud, int k, double std_ratio, int threads,
                                    const NeighbourIndex* index) {
  if (k < 1) {
    throw InputError("removeStatisticalOutliers: k must be >= 1, got " + std::to_string(k));
  }
  requirePositive(std_ratio, "removeStatisticalOutliers", "std_ratio");
  if (threads < 1) {
    throw InputError("removeStatisticalOutliers: threads must be >= 1, got " + std::to_string(threads));
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
  const auto meanDistances = [&](std::size_t begin, std::size_t end) {
    constexpr std::size_t kBatch = 2048;
    std::vector<int> nn_indices(kBatch * static_cast<std::size_t>(searcher_k));
    std::vector<float> nn_dists(kBatch * static_cast<std::size_t>(searcher_k));
    for (std::size_t b = begin; b < end; b += kBatch) {
      const std::size_t m = std::min(kBatch, end - b);
      index->nearest(b, m, searcher_k, nn_indices.data(), nn_dists.data());
      for (std::size_t r = 0; r < m; ++r) {
        const float* row = nn_dists.data() + r * static_cast<std::size_t>(searcher_k);
        double dist_sum = 0.0;
        for (int j = 1; j < searcher_k; ++j) dist_sum += std::sqrt(static_cast<double>(row[j]));
        distances[b + r] = static_cast<float>(dist_sum / k);
      }
    }
  };
  // At least ~1000 queries per thread, so a thread start (tens of µs) stays negligible.
  const std::size_t workers = std::min<std::size_t>(static_cast<std::size_t>(threads), n / 1024 + 1);
  std::vector<std::thread> pool;
  pool.reserve(workers - 1);
  std::size_t w = 1;
  try {
    for (; w < workers; ++w) pool.emplace_back(meanDistances, n * w / workers, n * (w + 1) / workers);
  } catch (const std::system_error&) {
    // No more threads available: this thread does the remaining slices too.
  }
  meanDistances(0, n / workers);
  for (; w < workers; ++w) meanDistances(n * w / workers, n * (w + 1) / workers);
  for (auto& t : pool) t.join();

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

PointList voxelGrid(const PointList& cloud, double leaf_m) {
  requirePositive(leaf_m, "preprocess", "voxel_m");
  try {
    return voxelDownsample(cloud, leaf_m, "voxel_m");
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
      throw InputError("preprocess: point " + std::to_string(i) + " is not finite: " +
                       formatRawPoint(cloud[i]));
    }
  }

  PointList current = options.remove_outliers
                          ? removeStatisticalOutliers(cloud, options.outlier_k,
                                                      options.outlier_std_ratio, options.threads, index)
                          : cloud;
  const std::size_t after_outliers = current.size();
  if (options.voxelize) current = voxelGrid(current, options.voxel_m);

  if (stats != nullptr) {
    stats->input_points = cloud.size();
    stats->after_outliers = after_outliers;
    stats->output_points = current.size();
  }
  return current;
}

}  // namespace uavip::preprocess
