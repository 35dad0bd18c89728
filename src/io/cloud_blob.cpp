// What the PCD and PLY readers share: the header counts and the payload check (PCL's
// readers crash on some malformed headers, so every header is checked first), and
// the x y z of the PCLPointCloud2 either gives.

#include <pcl/PCLPointField.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <initializer_list>
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

namespace {

/// The field named one of `names` (first found), or null.
const pcl::PCLPointField* findField(const pcl::PCLPointCloud2& blob,
                                    std::initializer_list<const char*> names) {
  for (const char* name : names) {
    for (const auto& f : blob.fields) {
      if (f.name == name && f.datatype >= pcl::PCLPointField::INT8 &&
          f.datatype <= pcl::PCLPointField::FLOAT64)
        return &f;
    }
  }
  return nullptr;
}

/// The records of the points fromBlob keeps (finite x y z), in order.
std::vector<const std::uint8_t*> keptRecords(const pcl::PCLPointCloud2& blob,
                                             const pcl::PCLPointField* const (&xyz)[3]) {
  std::vector<const std::uint8_t*> kept;
  kept.reserve(static_cast<std::size_t>(blob.width) * blob.height);
  for (std::size_t r = 0; r < blob.height; ++r) {
    for (std::size_t c = 0; c < blob.width; ++c) {
      const std::uint8_t* at = blob.data.data() + r * blob.row_step + c * blob.point_step;
      bool finite = true;
      for (const auto* f : xyz)
        finite = finite && std::isfinite(fieldValue(at + f->offset, f->datatype));
      if (finite) kept.push_back(at);
    }
  }
  return kept;
}

}  // namespace

PointColours coloursFromBlob(const pcl::PCLPointCloud2& blob) {
  PointColours out;
  const pcl::PCLPointField* xyz[3] = {findField(blob, {"x"}), findField(blob, {"y"}),
                                      findField(blob, {"z"})};
  const pcl::PCLPointField* packed = findField(blob, {"rgb", "rgba"});
  const pcl::PCLPointField* rgb[3] = {findField(blob, {"red", "r"}),
                                      findField(blob, {"green", "g"}),
                                      findField(blob, {"blue", "b"})};
  const bool channels = rgb[0] != nullptr && rgb[1] != nullptr && rgb[2] != nullptr;
  const pcl::PCLPointField* intensity =
      findField(blob, {"intensity", "Intensity", "scalar_Intensity", "i"});
  if (xyz[0] == nullptr || xyz[1] == nullptr || xyz[2] == nullptr) return out;
  // A packed colour is 4 bytes; an ascii PCD's are parsed as floats and stored in double.
  if (packed != nullptr && packed->datatype != pcl::PCLPointField::FLOAT32 &&
      packed->datatype != pcl::PCLPointField::FLOAT64 &&
      packed->datatype != pcl::PCLPointField::UINT32 &&
      packed->datatype != pcl::PCLPointField::INT32)
    packed = nullptr;
  if (packed == nullptr && !channels && intensity == nullptr) return out;
  const std::size_t sizes[9] = {0, 1, 1, 2, 2, 4, 4, 4, 8};
  for (const auto* f : {xyz[0], xyz[1], xyz[2], packed, rgb[0], rgb[1], rgb[2], intensity}) {
    if (f != nullptr && f->offset + sizes[f->datatype] > blob.point_step) return out;
  }
  const std::size_t width = blob.width, height = blob.height;
  if (height == 0 || width == 0 || blob.row_step < width * blob.point_step ||
      blob.data.size() < height * blob.row_step)
    return out;
  const std::vector<const std::uint8_t*> kept = keptRecords(blob, xyz);
  out.rgb.reserve(kept.size());
  if (packed != nullptr) {
    out.source = packed->name;
    for (const std::uint8_t* at : kept) {
      std::uint32_t v = 0;
      if (packed->datatype == pcl::PCLPointField::FLOAT64) {
        const auto f = static_cast<float>(fieldValue(at + packed->offset, packed->datatype));
        std::memcpy(&v, &f, 4);
      } else {
        std::memcpy(&v, at + packed->offset, 4);
      }
      out.rgb.push_back({static_cast<std::uint8_t>((v >> 16) & 0xff),
                         static_cast<std::uint8_t>((v >> 8) & 0xff),
                         static_cast<std::uint8_t>(v & 0xff)});
    }
    return out;
  }
  // Channels or intensity: scaled by the 1st and 99th percentiles (16-bit channels and
  // any intensity range alike).
  const int n = channels ? 3 : 1;
  std::vector<double> all;
  all.reserve(kept.size() * static_cast<std::size_t>(n));
  for (const std::uint8_t* at : kept) {
    for (int a = 0; a < n; ++a) {
      const auto* f = channels ? rgb[a] : intensity;
      all.push_back(fieldValue(at + f->offset, f->datatype));
    }
  }
  std::vector<double> sorted = all;
  std::sort(sorted.begin(), sorted.end());
  const double lo = channels ? 0.0 : sorted[sorted.size() / 100];
  double hi = sorted[sorted.size() - 1 - sorted.size() / 100];
  if (channels) hi = hi > 255.0 ? 65535.0 : 255.0;
  const double span = hi > lo ? hi - lo : 1.0;
  const auto byte = [&](double v) {
    return static_cast<std::uint8_t>(std::lround(255.0 * std::clamp((v - lo) / span, 0.0, 1.0)));
  };
  out.source = channels ? rgb[0]->name + "," + rgb[1]->name + "," + rgb[2]->name : intensity->name;
  for (std::size_t i = 0; i < kept.size(); ++i) {
    if (channels)
      out.rgb.push_back({byte(all[3 * i]), byte(all[3 * i + 1]), byte(all[3 * i + 2])});
    else
      out.rgb.push_back({byte(all[i]), byte(all[i]), byte(all[i])});
  }
  return out;
}

}  // namespace uavip::io
