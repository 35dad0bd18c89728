#include "uavip/preprocess/normals.h"

#include <pcl/features/normal_3d.h>
#include <pcl/search/kdtree.h>

#include <cmath>
#include <string>

#include "uavip/core/error.h"
#include "uavip/core/pcl_cloud.h"

namespace uavip::preprocess {

std::vector<Vec3> estimateNormals(const PointList& queries, const PointList& surface, int k) {
  if (k < 3) throw InputError("normals: k = " + std::to_string(k) + " neighbours; give at least 3");
  std::vector<Vec3> normals(queries.size(), Vec3::UnitZ());
  if (queries.empty()) return normals;
  if (surface.empty())
    throw InputError("normals: no surface points to estimate " + std::to_string(queries.size()) +
                     " normals from");
  const Vec3& origin = surface.front();  // float precision near the cloud
  const auto surface_cloud = toPclCloud(surface, origin);
  const auto query_cloud = toPclCloud(queries, origin);
  pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> estimation;
  estimation.setInputCloud(query_cloud);
  estimation.setSearchSurface(surface_cloud);
  estimation.setSearchMethod(pcl::make_shared<pcl::search::KdTree<pcl::PointXYZ>>());
  estimation.setKSearch(k);
  pcl::PointCloud<pcl::Normal> out;
  estimation.compute(out);
  for (std::size_t i = 0; i < queries.size() && i < out.size(); ++i) {
    Vec3 n(out[i].normal_x, out[i].normal_y, out[i].normal_z);
    const double len = n.norm();
    if (!std::isfinite(len) || len < 1e-6) continue;  // degenerate: keep +z
    n /= len;
    const bool flip =
        n.z() < -1e-9 ||
        (std::abs(n.z()) <= 1e-9 && (n.x() < -1e-9 || (std::abs(n.x()) <= 1e-9 && n.y() < 0.0)));
    normals[i] = flip ? Vec3(-n) : n;
  }
  return normals;
}

}  // namespace uavip::preprocess
