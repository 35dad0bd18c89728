#include "uavip/preprocess/filters.h"

#include "uavip/core/error.h"
#include "uavip/core/pcl_cloud.h"
#include "uavip/core/geometry.h"

#include <pcl/filters/statistical_outlier_removal.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>

namespace uavip::preprocess {
namespace {

using PclCloud = pcl::PointCloud<pcl::PointXYZ>;

std::string formatPoint(const Vec3& p) {
  std::ostringstream os;
  os << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
  return os.str();
}

}  // namespace

void PreprocessOptions::validate(const std::string& where) const {
  if (outlier_k < 1) {
    throw InputError(where + ": outlier_k must be >= 1, got " + std::to_string(outlier_k));
  }
  requirePositive(outlier_std_ratio, where, "outlier_std_ratio");
  requirePositive(voxel_m, where, "voxel_m");
}

PointList removeStatisticalOutliers(const PointList& cloud, int k, double std_ratio) {
  if (k < 1) {
    throw InputError("removeStatisticalOutliers: k must be >= 1, got " + std::to_string(k));
  }
  requirePositive(std_ratio, "removeStatisticalOutliers", "std_ratio");
  if (cloud.size() <= static_cast<std::size_t>(k)) return cloud;

  const Vec3 origin = boundingBox(cloud).min;
  pcl::StatisticalOutlierRemoval<pcl::PointXYZ> sor;
  sor.setInputCloud(toPclCloud(cloud, origin));
  sor.setMeanK(k);
  sor.setStddevMulThresh(std_ratio);
  pcl::Indices kept;
  sor.filter(kept);  // indices of the kept points, in input order

  PointList out;
  out.reserve(kept.size());
  for (const auto i : kept) out.push_back(cloud[static_cast<std::size_t>(i)]);
  return out;
}

PointList voxelGrid(const PointList& cloud, double leaf_m) {
  requirePositive(leaf_m, "voxelGrid", "voxel_m");
  if (cloud.empty()) return {};

  const Aabb box = boundingBox(cloud);
  // PCL indexes voxels with 32-bit ints (and refuses silently beyond): check first.
  double cells = 1.0;
  for (int a = 0; a < 3; ++a) {
    cells *= std::floor((box.max[a] - box.min[a]) / leaf_m) + 1.0;
  }
  if (!(cells <= static_cast<double>(std::numeric_limits<std::int32_t>::max()))) {
    const Vec3 extent = box.max - box.min;
    std::ostringstream os;
    os << "preprocess: voxel_m " << leaf_m << " m is too small for the cloud extent "
       << extent.x() << " x " << extent.y() << " x " << extent.z() << " m (" << cells
       << " voxels >= 2^31); use a larger voxel_m";
    throw InputError(os.str());
  }

  // Shift by a whole number of voxels so the voxel borders stay at multiples of
  // leaf_m in the world frame while PCL works near its float origin.
  const Vec3 origin = (box.min / leaf_m).array().floor().matrix() * leaf_m;
  pcl::VoxelGrid<pcl::PointXYZ> grid;
  grid.setInputCloud(toPclCloud(cloud, origin));
  const auto leaf = static_cast<float>(leaf_m);
  grid.setLeafSize(leaf, leaf, leaf);
  PclCloud filtered;
  grid.filter(filtered);  // sorted by voxel index: deterministic

  PointList out;
  out.reserve(filtered.size());
  for (const auto& p : filtered.points) {
    out.emplace_back(origin + Vec3(p.x, p.y, p.z));
  }
  return out;
}

PointList preprocess(const PointList& cloud, const PreprocessOptions& options,
                     PreprocessStats* stats) {
  options.validate();
  if (cloud.empty()) throw InputError("preprocess: cloud is empty");
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (!cloud[i].allFinite()) {
      throw InputError("preprocess: point " + std::to_string(i) + " is not finite: " +
                       formatPoint(cloud[i]));
    }
  }

  PointList current = options.remove_outliers
                          ? removeStatisticalOutliers(cloud, options.outlier_k,
                                                      options.outlier_std_ratio)
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
