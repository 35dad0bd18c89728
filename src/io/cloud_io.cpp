#include "uavip/io/cloud_io.h"

#include "uavip/io/las_reader.h"

#include "uavip/core/error.h"
#include "uavip/io/atomic_file.h"

#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

namespace uavip::io {
namespace {

std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

std::string formatPoint(const Vec3& p) {
  std::ostringstream os;
  os << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
  return os.str();
}

PointList loadXyz(const std::string& path) {
  std::istringstream in(readFile(path));
  PointList out;
  std::string line;
  std::size_t line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream fields(line);
    std::string sx, sy, sz;
    if (!(fields >> sx >> sy >> sz)) {
      throw InputError(path + ":" + std::to_string(line_no) + ": expected 'x y z', got '" + line + "'");
    }
    Vec3 p;
    try {
      std::size_t used = 0;
      const std::string* parts[3] = {&sx, &sy, &sz};
      for (int i = 0; i < 3; ++i) {
        p[i] = std::stod(*parts[i], &used);
        if (used != parts[i]->size()) throw std::invalid_argument(*parts[i]);
      }
    } catch (const std::exception&) {
      throw InputError(path + ":" + std::to_string(line_no) + ": not a number in '" + line + "'");
    }
    if (!p.allFinite()) {
      throw InputError(path + ":" + std::to_string(line_no) + ": point " + formatPoint(p) +
                       " is not finite; remove the line");
    }
    out.push_back(p);
  }
  return out;
}

/// PCL's readers crash on some malformed headers, so the header is checked first:
/// the fields x y z, a point count and a DATA line (PCD), or "ply" with a vertex
/// element and x y z properties (PLY).
void checkHeader(const std::string& path, const std::string& ext) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot read (permission?)");
  std::string line;
  bool has_xyz = false, has_count = false, has_data = false;
  std::size_t lines = 0;
  const auto hasXyz = [](const std::string& l) {
    std::istringstream words(l);
    std::set<std::string> names;
    for (std::string w; words >> w;) names.insert(w);
    return names.count("x") && names.count("y") && names.count("z");
  };
  if (ext == ".pcd") {
    while (lines++ < 64 && std::getline(in, line)) {
      if (line.rfind("FIELDS", 0) == 0) has_xyz = hasXyz(line);
      if (line.rfind("POINTS", 0) == 0) has_count = true;
      if (line.rfind("DATA", 0) == 0) {
        has_data = true;
        break;
      }
    }
    if (!has_xyz || !has_count || !has_data) {
      throw InputError(path + ": not a PCD file with x y z fields (header needs FIELDS x y z, POINTS and DATA)");
    }
  } else {
    std::getline(in, line);
    if (line.rfind("ply", 0) != 0) throw InputError(path + ": not a PLY file (first line must be 'ply')");
    bool has_vertex = false;
    int xyz = 0;
    while (lines++ < 256 && std::getline(in, line)) {
      if (line.rfind("element vertex", 0) == 0) has_vertex = true;
      if (has_vertex && line.rfind("property", 0) == 0) {
        const std::string name = line.substr(line.find_last_of(' ') + 1);
        xyz += (name == "x" || name == "y" || name == "z");
      }
      if (line.rfind("end_header", 0) == 0) break;
    }
    if (!has_vertex || xyz < 3) throw InputError(path + ": PLY file has no vertex element with x y z properties");
  }
}

PointList fromPcl(const pcl::PointCloud<pcl::PointXYZ>& cloud, const std::string& path) {
  PointList out;
  out.reserve(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const auto& q = cloud[i];
    const Vec3 p(q.x, q.y, q.z);
    if (!p.allFinite()) {
      throw InputError(path + ": point " + std::to_string(i) + " " + formatPoint(p) +
                       " is not finite; remove NaN/inf points (e.g. pcl::removeNaNFromPointCloud)");
    }
    out.push_back(p);
  }
  return out;
}

}  // namespace

void CloudReadOptions::validate(const std::string& where) const {
  for (const int c : drop_classes) {
    if (c < 0 || c > 255) throw InputError(where + ": drop_classes holds " + std::to_string(c) + ", a class must be 0..255");
  }
}

PointList loadCloud(const std::string& path, const CloudReadOptions& options, CloudReadInfo* info) {
  options.validate();
  const std::string ext = lowerExtension(path);
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw InputError(path + ": no such file");
  PointList points;
  if (ext == ".las" || ext == ".laz") {
    LasOptions las_options;
    las_options.drop_classes = options.drop_classes;
    LasCloud las = readLas(path, las_options);
    if (info != nullptr) {
      std::ostringstream os;
      os << path << ": LAS " << las.version_major << "." << las.version_minor << " point format " << las.point_format
         << ", " << las.points_in_file << " points";
      if (las.dropped > 0) os << " (" << las.dropped << " dropped by class)";
      os << "; unit " << las.unit_name << " (" << las.unit_source << ")";
      if (las.unit_to_m != 1.0 || las.z_unit_to_m != 1.0) os << " converted to metres";
      os << "; recentred by (" << las.origin_m.x() << ", " << las.origin_m.y() << ", " << las.origin_m.z() << ") m";
      info->note = os.str();
      info->origin_m = las.origin_m;
    }
    points = std::move(las.points);
    if (points.empty()) throw InputError(path + ": no point is left after drop_classes; drop fewer classes");
  } else if (ext == ".xyz" || ext == ".txt") {
    points = loadXyz(path);
  } else if (ext == ".pcd" || ext == ".ply") {
    checkHeader(path, ext);
    pcl::PointCloud<pcl::PointXYZ> cloud;
    const int rc = ext == ".pcd" ? pcl::io::loadPCDFile(path, cloud) : pcl::io::loadPLYFile(path, cloud);
    if (rc < 0) throw InputError(path + ": cannot parse as " + ext.substr(1) + " (corrupt or not x/y/z?)");
    points = fromPcl(cloud, path);
  } else {
    throw InputError(path + ": unknown cloud extension '" + ext + "' (use .pcd, .ply, .xyz, .txt or .las)");
  }
  if (points.empty()) throw InputError(path + ": the cloud has no points");
  return points;
}

void saveCloudPcd(const std::string& path, const PointList& cloud) {
  pcl::PointCloud<pcl::PointXYZ> out;
  out.reserve(cloud.size());
  for (const auto& p : cloud) {
    out.push_back(pcl::PointXYZ(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())));
  }
  replaceFileAtomic(path, [&](const std::string& tmp) {
    // PCL refuses to write an empty binary cloud; an empty ASCII PCD is still valid.
    const int rc = out.empty() ? pcl::io::savePCDFileASCII(tmp, out) : pcl::io::savePCDFileBinary(tmp, out);
    if (rc < 0) throw std::runtime_error(path + ": cannot write the PCD file");
  });
}

}  // namespace uavip::io
