#include "uavip/preprocess/cloud_stats.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <random>
#include <stdexcept>
#include <tuple>
#include <utility>
#include <vector>

#include "uavip/core/geometry.h"
#include "uavip/core/math.h"
#include "uavip/core/parallel.h"
#include "uavip/core/text.h"

namespace uavip::preprocess {
namespace {

/// A cloud is one station's scan when spread(spacing / range) is below this
/// fraction of spread(spacing) (measured: room scans 0.3–0.4, models and airborne
/// LiDAR > 1).
constexpr double kStationSpreadRatio = 0.6;

/// The upper median, 0 for no values.
double medianOf(const std::vector<double>& v) { return v.empty() ? 0.0 : upperMedian(v); }

/// Robust spread of v: MAD / median (0 when the median is not positive).
double spread(const std::vector<double>& v) {
  const double med = medianOf(v);
  if (!(med > 0.0)) return 0.0;
  std::vector<double> dev(v.size());
  for (std::size_t k = 0; k < v.size(); ++k) dev[k] = std::abs(v[k] - med);
  return medianOf(dev) / med;
}

/// The indices of at most options.sample_points points (all, or a seeded shuffle).
std::vector<std::size_t> samplePoints(std::size_t n, const CloudStatsOptions& options) {
  std::vector<std::size_t> sample(n);
  std::iota(sample.begin(), sample.end(), std::size_t{0});
  if (sample.size() > options.sample_points) {
    std::mt19937 rng(options.seed);
    std::shuffle(sample.begin(), sample.end(), rng);
    sample.resize(options.sample_points);
  }
  return sample;
}

/// Per sampled point: the distance to its nearest distinct neighbour [m], that over
/// the point's range (angular spacing, for the one-station test) and the local noise
/// (√ of the smallest eigenvalue of its neighbourhood's covariance) [m].
struct Samples {
  std::vector<double> nearest, noise, angular;
};

/// Point i's nearest distinct neighbour distance (duplicates and the point itself are
/// at ~0) [m] and its angular spacing (that over the point's range), NaN where
/// undefined; idx are its neighbours, nearest first.
std::pair<double, double> nearestDistinct(const PointList& cloud, std::size_t i,
                                          const std::vector<int>& idx) {
  constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t j = 0; j < idx.size(); ++j) {
    const double d = (cloud[static_cast<std::size_t>(idx[j])] - cloud[i]).norm();
    if (d > 1e-9) {
      const double range = cloud[i].norm();
      return {d, range > 1e-6 ? d / range : kNone};
    }
  }
  return {kNone, kNone};
}

/// √ of the smallest eigenvalue of the covariance of the points idx [m].
double localNoise(const PointList& cloud, const std::vector<int>& idx) {
  Vec3 mean = Vec3::Zero();
  for (const auto j : idx) mean += cloud[static_cast<std::size_t>(j)];
  mean /= static_cast<double>(idx.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto j : idx) {
    const Vec3 d = cloud[static_cast<std::size_t>(j)] - mean;
    cov += d * d.transpose();
  }
  cov /= static_cast<double>(idx.size());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(cov, Eigen::EigenvaluesOnly);
  return std::sqrt(std::max(solver.eigenvalues()[0], 0.0));
}

/// One neighbour query (k + 1 nearest) per sampled point feeds all three statistics,
/// in sample order; the queries on every core, each writing its own slot.
Samples sampleNeighbourhoods(const PointList& cloud, const NeighbourIndex& index,
                             const std::vector<std::size_t>& sample, int k) {
  constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
  std::vector<std::array<double, 3>> slot(sample.size(), {kNone, kNone, kNone});
  constexpr std::size_t kBlock = 1024;
  parallelFor(
      (sample.size() + kBlock - 1) / kBlock, hardwareThreads(), [&](std::size_t b, std::size_t) {
        std::vector<int> idx;
        std::vector<float> d2;
        for (std::size_t s = b * kBlock; s < std::min(sample.size(), (b + 1) * kBlock); ++s) {
          index.nearest(sample[s], k + 1, idx, d2);
          if (idx.size() < 2) continue;
          std::tie(slot[s][0], slot[s][1]) = nearestDistinct(cloud, sample[s], idx);
          if (idx.size() >= 4) slot[s][2] = localNoise(cloud, idx);
        }
      });
  Samples out;
  out.nearest.reserve(sample.size());
  out.noise.reserve(sample.size());
  for (const auto& [nearest, angular, noise] : slot) {
    if (!std::isnan(nearest)) out.nearest.push_back(nearest);
    if (!std::isnan(angular)) out.angular.push_back(angular);
    if (!std::isnan(noise)) out.noise.push_back(noise);
  }
  return out;
}

}  // namespace

CloudStats measureCloud(const PointList& cloud, const CloudStatsOptions& options,
                        const NeighbourIndex* index) {
  if (index != nullptr && &index->cloud() != &cloud) {
    throw std::invalid_argument("measureCloud: the index is over another cloud");
  }
  CloudStats stats;
  stats.points = cloud.size();
  if (cloud.empty()) return stats;
  const Aabb box = boundingBox(cloud);
  stats.min = box.min;
  stats.max = box.max;
  stats.extent_m = box.max - box.min;
  if (cloud.size() < 2) return stats;

  std::unique_ptr<NeighbourIndex> own;
  if (index == nullptr) {
    own = std::make_unique<NeighbourIndex>(cloud);
    index = own.get();
  }
  const Samples s = sampleNeighbourhoods(cloud, *index, samplePoints(cloud.size(), options),
                                         std::max(options.noise_k, 8));
  stats.spacing_m = medianOf(s.nearest);
  stats.noise_m = medianOf(s.noise);
  // One station at the origin: spacing ∝ range. Compare the robust spread of
  // spacing/range with that of the spacing; the spread of a uniformly sampled model
  // grows when divided by the range, a station scan's shrinks.
  const Vec3 origin_margin = (Vec3::Zero() - box.min).cwiseMin(box.max - Vec3::Zero());
  const bool origin_inside = (origin_margin.array() > 0.0).all();
  const double base = spread(s.nearest);
  stats.station_ratio = base > 0.0 ? spread(s.angular) / base : 0.0;
  stats.scanned_from_origin = origin_inside && s.angular.size() >= 100 && base > 0.0 &&
                              stats.station_ratio < kStationSpreadRatio;
  return stats;
}

std::string unitWarning(const CloudStats& stats) {
  // Real structures are metres to kilometres across with centimetres to metres
  // between points; far outside that the file is in another unit.
  constexpr double kDegreesSpanMax = 0.1;        // x, y of a site in degrees (0.1° ≈ 11 km)
  constexpr double kDegreesHeightRatio = 100.0;  // z (metres) over that
  constexpr double kLargestStructureM = 5000.0;
  constexpr double kWidestSpacingM = 5.0;
  constexpr double kSmallestStructureM = 1.0;
  const Vec3& e = stats.extent_m;
  const double horizontal = std::max(e.x(), e.y());
  if (horizontal > 0.0 && horizontal < kDegreesSpanMax &&
      e.z() > kDegreesHeightRatio * horizontal) {
    return "x and y span only " + formatNumber(horizontal, 3) + " while z spans " +
           formatFixed(e.z(), 1) +
           ": the file looks like longitude/latitude in degrees; reproject it to a metric CRS "
           "(e.g. UTM, with "
           "PDAL or CloudCompare) first";
  }
  if (e.maxCoeff() > kLargestStructureM || stats.spacing_m > kWidestSpacingM) {
    return "a structure " + formatFixed(e.maxCoeff(), 0) + " m across with points " +
           formatFixed(stats.spacing_m, 2) +
           " m apart: if the file is not in metres, set 'input: {scale: 0.001}' (millimetres), "
           "0.01 (centimetres) "
           "or 0.3048 (feet) in the config";
  }
  if (stats.points >= 2 && e.maxCoeff() < kSmallestStructureM) {
    return "a structure only " + formatNumber(e.maxCoeff(), 3) +
           " m across: if the file is in kilometres, set "
           "'input: {scale: 1000}' in the config";
  }
  return "";
}

}  // namespace uavip::preprocess
