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
#include <cstdint>
#include <cstring>
#include <limits>
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

/// One coordinate of a PCLPointCloud2 field, whatever its stored type. PCL's own
/// conversion to PointXYZ copies the bytes of a double or integer field as if they
/// were a float (a double PCD read back as zeros), so the fields are read here.
double fieldValue(const std::uint8_t* at, std::uint8_t datatype) {
  switch (datatype) {
    case pcl::PCLPointField::INT8: return static_cast<double>(*reinterpret_cast<const std::int8_t*>(at));
    case pcl::PCLPointField::UINT8: return static_cast<double>(*at);
    case pcl::PCLPointField::INT16: { std::int16_t v; std::memcpy(&v, at, 2); return v; }
    case pcl::PCLPointField::UINT16: { std::uint16_t v; std::memcpy(&v, at, 2); return v; }
    case pcl::PCLPointField::INT32: { std::int32_t v; std::memcpy(&v, at, 4); return v; }
    case pcl::PCLPointField::UINT32: { std::uint32_t v; std::memcpy(&v, at, 4); return v; }
    case pcl::PCLPointField::FLOAT32: { float v; std::memcpy(&v, at, 4); return v; }
    case pcl::PCLPointField::FLOAT64: { double v; std::memcpy(&v, at, 8); return v; }
    default: return std::numeric_limits<double>::quiet_NaN();
  }
}

/// x, y, z of every point of a PCD/PLY blob, in double, any numeric field type.
/// An organized cloud (height > 1, a sensor frame) marks missing returns with NaN:
/// those are skipped. Any other non-finite point is an error naming its index.
PointList fromBlob(const pcl::PCLPointCloud2& blob, const std::string& path) {
  const pcl::PCLPointField* fields[3] = {nullptr, nullptr, nullptr};
  const char* names[3] = {"x", "y", "z"};
  for (const auto& f : blob.fields) {
    for (int a = 0; a < 3; ++a) {
      if (f.name == names[a]) fields[a] = &f;
    }
  }
  for (int a = 0; a < 3; ++a) {
    if (fields[a] == nullptr) throw InputError(path + ": no field '" + names[a] + "'");
    const auto t = fields[a]->datatype;
    if (t < pcl::PCLPointField::INT8 || t > pcl::PCLPointField::FLOAT64) {
      throw InputError(path + ": field '" + names[a] + "' has type code " + std::to_string(t) +
                       ", which is not a number type (use float, double or an integer)");
    }
  }
  const std::size_t width = blob.width, height = blob.height;
  const std::size_t sizes[9] = {0, 1, 1, 2, 2, 4, 4, 4, 8};
  for (int a = 0; a < 3; ++a) {
    if (fields[a]->offset + sizes[fields[a]->datatype] > blob.point_step) {
      throw InputError(path + ": field '" + std::string(names[a]) + "' lies outside the point record");
    }
  }
  if (height > 0 && width > 0 &&
      (static_cast<std::size_t>(blob.row_step) < width * blob.point_step || blob.data.size() < height * blob.row_step)) {
    throw InputError(path + ": the point data is shorter than the header says (" + std::to_string(width * height) +
                     " points)");
  }
  const bool organized = height > 1;
  PointList out;
  out.reserve(width * height);
  for (std::size_t r = 0; r < height; ++r) {
    for (std::size_t c = 0; c < width; ++c) {
      const std::uint8_t* at = blob.data.data() + r * blob.row_step + c * blob.point_step;
      const Vec3 p(fieldValue(at + fields[0]->offset, fields[0]->datatype),
                   fieldValue(at + fields[1]->offset, fields[1]->datatype),
                   fieldValue(at + fields[2]->offset, fields[2]->datatype));
      if (!p.allFinite()) {
        if (organized) continue;  // no return in a sensor frame
        throw InputError(path + ": point " + std::to_string(r * width + c) + " " + formatPoint(p) +
                         " is not finite; remove NaN/inf points (e.g. pcl::removeNaNFromPointCloud)");
      }
      out.push_back(p);
    }
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
    pcl::PCLPointCloud2 cloud;
    const int rc = ext == ".pcd" ? pcl::io::loadPCDFile(path, cloud) : pcl::io::loadPLYFile(path, cloud);
    if (rc < 0) throw InputError(path + ": cannot parse as " + ext.substr(1) + " (corrupt or not x/y/z?)");
    points = fromBlob(cloud, path);
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
