#pragma once
/// \file
/// PointList → PCL cloud, for the modules that run PCL algorithms (header-only, so
/// uavip_core itself does not link PCL; include it only where PCL is linked).

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <cstdint>
#include <memory>

#include "uavip/core/types.h"

namespace uavip {

/// Copies `points` into a PCL cloud shifted by −origin [m]: PCL stores floats, so the
/// shift keeps geo-referenced coordinates (1e6 m) at millimetre precision.
inline pcl::PointCloud<pcl::PointXYZ>::Ptr toPclCloud(const PointList& points, const Vec3& origin) {
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  cloud->points.reserve(points.size());
  for (const auto& p : points) {
    const Vec3 q = p - origin;
    cloud->points.emplace_back(static_cast<float>(q.x()), static_cast<float>(q.y()),
                               static_cast<float>(q.z()));
  }
  cloud->width = static_cast<std::uint32_t>(cloud->points.size());
  cloud->height = 1;
  cloud->is_dense = true;
  return cloud;
}

}  // namespace uavip
