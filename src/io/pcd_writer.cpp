// The binary PCD writer (PCL's) of every cloud uavip writes.

#include <pcl/io/pcd_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "uavip/core/error.h"
#include "uavip/io/atomic_file.h"
#include "uavip/io/cloud_io.h"

namespace uavip::io {

void writeCloudPcdFile(const std::string& file, const PointList& cloud, const std::string& path) {
  pcl::PointCloud<pcl::PointXYZ> out;
  out.reserve(cloud.size());
  for (const auto& p : cloud) {
    out.push_back(pcl::PointXYZ(static_cast<float>(p.x()), static_cast<float>(p.y()),
                                static_cast<float>(p.z())));
  }
  // PCL refuses to write an empty binary cloud; an empty ASCII PCD is still valid.
  const int rc =
      out.empty() ? pcl::io::savePCDFileASCII(file, out) : pcl::io::savePCDFileBinary(file, out);
  if (rc < 0)
    throw InputError(path + ": cannot write the PCD file (no permission, or the disk is full)");
}

void saveCloudPcd(const std::string& path, const PointList& cloud) {
  replaceFileAtomic(path, [&](const std::string& tmp) { writeCloudPcdFile(tmp, cloud, path); });
}

}  // namespace uavip::io
