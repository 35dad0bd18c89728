// What the PCD and PLY readers share: the header counts and the payload check (PCL's
// readers crash on some malformed headers, so every header is checked first), and
// the x y z of the PCLPointCloud2 either gives.

#include <pcl/PCLPointField.h>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <limits>
#include <sstream>

#include "cloud_formats.h"
#include "uavip/core/error.h"
#include "uavip/core/text.h"

namespace uavip::io {
namespace {

/// One coordinate of a PCLPointCloud2 field, whatever its stored type. PCL's own
/// conversion to PointXYZ copies the bytes of a double or integer field as if they
/// were a float (a double PCD read back as zeros), so the fields are read here.
double fieldValue(const std::uint8_t* at, std::uint8_t datatype) {
  switch (datatype) {
    case pcl::PCLPointField::INT8:
      return static_cast<double>(*reinterpret_cast<const std::int8_t*>(at));
    case pcl::PCLPointField::UINT8:
      return static_cast<double>(*at);
    case pcl::PCLPointField::INT16: {
      std::int16_t v;
      std::memcpy(&v, at, 2);
      return v;
    }
    case pcl::PCLPointField::UINT16: {
      std::uint16_t v;
      std::memcpy(&v, at, 2);
      return v;
    }
    case pcl::PCLPointField::INT32: {
      std::int32_t v;
      std::memcpy(&v, at, 4);
      return v;
    }
    case pcl::PCLPointField::UINT32: {
      std::uint32_t v;
      std::memcpy(&v, at, 4);
      return v;
    }
    case pcl::PCLPointField::FLOAT32: {
      float v;
      std::memcpy(&v, at, 4);
      return v;
    }
    case pcl::PCLPointField::FLOAT64: {
      double v;
      std::memcpy(&v, at, 8);
      return v;
    }
    default:
      return std::numeric_limits<double>::quiet_NaN();
  }
}

}  // namespace

std::uint64_t headerCount(const std::string& path, const std::string& key,
                          const std::string& text) {
  const bool digits =
      !text.empty() && text.size() <= 19 && std::all_of(text.begin(), text.end(), [](char c) {
        return std::isdigit(static_cast<unsigned char>(c));
      });
  if (!digits)
    throw InputError(path + ": " + key + " must be a whole number >= 0, got '" +
                     text.substr(0, 40) + "'");
  return std::stoull(text);
}

void checkPayload(const std::string& path, std::uint64_t points, std::uint64_t min_bytes_per_point,
                  std::uint64_t available, const std::string& what) {
  if (min_bytes_per_point == 0 || points <= available / min_bytes_per_point) return;
  throw InputError(path + ": the header claims " + std::to_string(points) + " points (" + what +
                   ", at least " + std::to_string(min_bytes_per_point) + " bytes each) but only " +
                   std::to_string(available) +
                   " bytes follow it; the file is truncated or its header is wrong");
}

std::vector<std::string> headerWords(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> out;
  for (std::string w; in >> w;) out.push_back(w);
  return out;
}

PointList fromBlob(const pcl::PCLPointCloud2& blob, const std::string& path) {
  return fromBlob(blob, path, blob.height > 1, 0);
}

PointList fromBlob(const pcl::PCLPointCloud2& blob, const std::string& path, bool organized,
                   std::uint64_t first) {
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
      throw InputError(path + ": field '" + std::string(names[a]) +
                       "' lies outside the point record");
    }
  }
  if (height > 0 && width > 0 &&
      (static_cast<std::size_t>(blob.row_step) < width * blob.point_step ||
       blob.data.size() < height * blob.row_step)) {
    throw InputError(path + ": the point data is shorter than the header says (" +
                     std::to_string(width * height) + " points)");
  }
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
        throw InputError(
            path + ": point " + std::to_string(first + r * width + c) + " " + formatRawPoint(p) +
            " is not finite; remove NaN/inf points (e.g. pcl::removeNaNFromPointCloud)");
      }
      out.push_back(p);
    }
  }
  return out;
}

}  // namespace uavip::io
