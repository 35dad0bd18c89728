#include "uavip/io/cloud_io.h"

#include <pcl/console/print.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <optional>
#include <set>
#include <sstream>

#include "uavip/core/error.h"
#include "uavip/core/text.h"
#include "uavip/io/atomic_file.h"
#include "uavip/io/las_reader.h"

namespace uavip::io {
namespace {

std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext;
}

/// Parses an x y z text cloud from `in` line by line, handing each point to `point`
/// (the one parser of .xyz/.txt/.csv; loadXyz and streamCloud use it).
void parseXyz(std::istream& in, const std::string& path,
              const std::function<void(const Vec3&)>& point) {
  std::string line;
  std::size_t line_no = 0;
  bool header_allowed = true;  // until the first line that is not blank or a comment
  while (std::getline(in, line)) {
    ++line_no;
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream fields(line);
    std::string sx, sy, sz;
    // A header of column names before the first point (CloudCompare writes
    // "//X,Y,Z", spreadsheets "x,y,z"): its first word starts with a letter or '/'.
    if (header_allowed &&
        (std::isalpha(static_cast<unsigned char>(line[first])) || line[first] == '/') &&
        line.find_first_of("0123456789") == std::string::npos) {
      header_allowed = false;
      continue;
    }
    header_allowed = false;
    if (!(fields >> sx >> sy >> sz)) {
      throw InputError(path + ":" + std::to_string(line_no) + ": expected 'x y z', got '" + line +
                       "'");
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
      throw InputError(path + ":" + std::to_string(line_no) + ": point " + formatRawPoint(p) +
                       " is not finite; remove the line");
    }
    point(p);
  }
}

PointList loadXyz(const std::string& path) {
  std::istringstream in(readFile(path));
  PointList out;
  parseXyz(in, path, [&](const Vec3& p) { out.push_back(p); });
  return out;
}

/// PCL's readers crash on some malformed headers, so the header is checked first:
/// the fields x y z, a point count and a DATA line (PCD), or "ply" with a vertex
/// element and x y z properties (PLY).
/// A header count: a whole number >= 0 (no sign, no fraction), else InputError
/// naming the file, the key and the text.
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

/// The header's claim against the bytes that follow it: a file that claims more
/// points than it can hold is refused before anything is allocated.
void checkPayload(const std::string& path, std::uint64_t points, std::uint64_t min_bytes_per_point,
                  std::uint64_t available, const std::string& what) {
  if (min_bytes_per_point == 0 || points <= available / min_bytes_per_point) return;
  throw InputError(path + ": the header claims " + std::to_string(points) + " points (" + what +
                   ", at least " + std::to_string(min_bytes_per_point) + " bytes each) but only " +
                   std::to_string(available) +
                   " bytes follow it; the file is truncated or its header is wrong");
}

std::vector<std::string> words(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> out;
  for (std::string w; in >> w;) out.push_back(w);
  return out;
}

/// PCD header (PCL's PCD v0.7): FIELDS with x y z; SIZE 1, 2, 4 or 8 and TYPE F
/// (4 or 8), I or U per field; WIDTH × HEIGHT = POINTS; DATA ascii, binary or
/// binary_compressed; and no more points than the data can hold.
/// What a checked PCD header says.
struct PcdHeader {
  std::vector<std::string> fields;
  std::vector<std::uint64_t> sizes, counts;
  std::vector<char> types;
  std::uint64_t width{0}, height{0}, points{0}, step{0};
  std::string data;
  std::uint64_t body{0};       ///< byte offset of the data
  std::uint64_t available{0};  ///< bytes from there to the end of the file
};

/// The key lines of a PCD header as written, before any check of their values.
struct PcdHeaderLines {
  std::vector<std::string> fields, sizes, types, counts;
  std::optional<std::uint64_t> width, height, points;
  std::string data, version;
};

/// Reads the header's key lines up to DATA: each must be one of the PCD keys, once.
PcdHeaderLines readPcdHeaderLines(const std::string& path, std::istream& in) {
  PcdHeaderLines h;
  std::string line;
  std::set<std::string> seen;
  static const std::set<std::string> kKeys{"VERSION", "FIELDS", "SIZE",      "TYPE",   "COUNT",
                                           "WIDTH",   "HEIGHT", "VIEWPOINT", "POINTS", "DATA"};
  for (int lines = 0; lines < 64 && h.data.empty() && std::getline(in, line); ++lines) {
    std::vector<std::string> w = words(line);
    if (w.empty() || w[0][0] == '#') continue;
    const std::string key = w[0];
    w.erase(w.begin());
    // PCL's reader crashes on some malformed headers (tests/fuzz/fuzz_cloud): every
    // line must be one of the PCD keys, each once.
    if (!kKeys.count(key))
      throw InputError(path + ": not a PCD file, or a damaged one: header line " +
                       std::to_string(lines + 1) +
                       " is not a PCD key (VERSION, FIELDS, SIZE, TYPE, COUNT, WIDTH, HEIGHT, "
                       "VIEWPOINT, POINTS, DATA)");
    if (!seen.insert(key).second) throw InputError(path + ": PCD header has " + key + " twice");
    if (key == "VERSION") h.version = w.empty() ? "?" : w[0];
    if (key == "FIELDS") h.fields = w;
    if (key == "SIZE") h.sizes = w;
    if (key == "TYPE") h.types = w;
    if (key == "COUNT") h.counts = w;
    if ((key == "WIDTH" || key == "HEIGHT" || key == "POINTS") && w.size() != 1)
      throw InputError(path + ": " + key + " must hold one number");
    if (key == "WIDTH") h.width = headerCount(path, "WIDTH", w[0]);
    if (key == "HEIGHT") h.height = headerCount(path, "HEIGHT", w[0]);
    if (key == "POINTS") h.points = headerCount(path, "POINTS", w[0]);
    if (key == "DATA") h.data = w.empty() ? "?" : w[0];
  }
  return h;
}

/// Checks SIZE, TYPE and COUNT of every field into `header` (sizes, counts, types);
/// returns the bytes of one point.
std::uint64_t checkPcdFields(const std::string& path, const PcdHeaderLines& h, PcdHeader& header) {
  std::uint64_t step = 0;
  for (std::size_t i = 0; i < h.fields.size(); ++i) {
    const std::string& size = h.sizes[i];
    const std::string& type = h.types[i];
    if (size != "1" && size != "2" && size != "4" && size != "8")
      throw InputError(path + ": SIZE of field " + h.fields[i] +
                       " must be 1, 2, 4 or 8 bytes, got '" + size + "'");
    if (type != "F" && type != "I" && type != "U")
      throw InputError(path + ": TYPE of field " + h.fields[i] + " must be F, I or U, got '" +
                       type + "'");
    if (type == "F" && size != "4" && size != "8")
      throw InputError(path + ": field " + h.fields[i] + " is a float of " + size +
                       " bytes; PCD floats have 4 or 8");
    const std::uint64_t count = h.counts.empty() ? 1 : headerCount(path, "COUNT", h.counts[i]);
    if (count == 0 || count > 1'000'000)
      throw InputError(path + ": COUNT of field " + h.fields[i] + " must be 1..1000000");
    step += count * std::stoull(size);
    header.sizes.push_back(std::stoull(size));
    header.counts.push_back(count);
    header.types.push_back(type[0]);
  }
  return step;
}

/// One check per PCD header line, in file order, each naming the line and what to do.
PcdHeader checkPcdHeader(const std::string& path, std::istream& in, std::uint64_t file_size) {
  const PcdHeaderLines h = readPcdHeaderLines(path, in);
  // PCL's reader dereferences a missing VERSION (found by tests/fuzz/fuzz_cloud).
  if (h.version != "0.7" && h.version != ".7" && h.version != "0.6" && h.version != ".6")
    throw InputError(path + ": PCD header needs VERSION 0.7 (or 0.6) before FIELDS, got '" +
                     h.version.substr(0, 20) + "'");
  const std::set<std::string> names(h.fields.begin(), h.fields.end());
  if (!names.count("x") || !names.count("y") || !names.count("z") || !h.points || h.data.empty())
    throw InputError(
        path + ": not a PCD file with x y z fields (header needs FIELDS x y z, POINTS and DATA)");
  if (!h.width || !h.height) throw InputError(path + ": PCD header needs WIDTH and HEIGHT");
  if (h.sizes.size() != h.fields.size() || h.types.size() != h.fields.size() ||
      (!h.counts.empty() && h.counts.size() != h.fields.size()))
    throw InputError(path + ": SIZE, TYPE and COUNT must give one value per field of FIELDS");
  PcdHeader header;
  const std::uint64_t step = checkPcdFields(path, h, header);
  const std::uint64_t points = *h.points;
  const std::uint64_t w = h.width.value_or(points), ht = h.height.value_or(1);
  if (ht != 0 && w > UINT64_MAX / ht) throw InputError(path + ": WIDTH x HEIGHT overflows");
  if (w * ht != points)
    throw InputError(path + ": WIDTH x HEIGHT (" + std::to_string(w) + " x " + std::to_string(ht) +
                     ") differs from POINTS " + std::to_string(points));
  const std::streamoff at = in.tellg();
  const std::uint64_t available =
      at < 0 ? 0 : file_size - std::min<std::uint64_t>(file_size, static_cast<std::uint64_t>(at));
  if (h.data == "binary") {
    checkPayload(path, points, step, available, "binary");
  } else if (h.data == "ascii") {
    checkPayload(path, points, 2 * h.fields.size(), available + 1,
                 "ascii, a digit and a separator per value");
  } else if (h.data == "binary_compressed") {
    // LZF expands at most about 100 times; beyond that the header cannot be right.
    checkPayload(path, points, std::max<std::uint64_t>(1, step / 100), available, "compressed");
  } else {
    throw InputError(path + ": DATA must be ascii, binary or binary_compressed, got '" + h.data +
                     "'");
  }
  header.fields = h.fields;
  header.width = w;
  header.height = ht;
  header.points = points;
  header.step = step;
  header.data = h.data;
  header.body = static_cast<std::uint64_t>(at);
  header.available = available;
  return header;
}

/// LZF decompression (liblzf's format, used by PCD binary_compressed), bounds-checked:
/// false when the stream is damaged or does not fill `out` exactly.
bool lzfDecompress(const std::uint8_t* in, std::size_t in_size, std::vector<std::uint8_t>& out) {
  std::size_t ip = 0, op = 0;
  while (ip < in_size) {
    const unsigned ctrl = in[ip++];
    if (ctrl < 32) {  // a literal run of ctrl + 1 bytes
      const std::size_t len = ctrl + 1;
      if (ip + len > in_size || op + len > out.size()) return false;
      std::memcpy(out.data() + op, in + ip, len);
      ip += len;
      op += len;
    } else {  // a back reference
      std::size_t len = ctrl >> 5;
      std::size_t back = (static_cast<std::size_t>(ctrl & 0x1f) << 8) + 1;
      if (len == 7) {
        if (ip >= in_size) return false;
        len += in[ip++];
      }
      if (ip >= in_size) return false;
      back += in[ip++];
      len += 2;
      if (back > op || op + len > out.size()) return false;
      for (std::size_t k = 0; k < len; ++k, ++op) out[op] = out[op - back];
    }
  }
  return op == out.size();
}

/// PCL's datatype code of a PCD field (0 when PCL has none, e.g. 8-byte integers).
std::uint8_t pclType(char type, std::uint64_t size) {
  if (type == 'F') return size == 4 ? pcl::PCLPointField::FLOAT32 : pcl::PCLPointField::FLOAT64;
  if (size == 1) return type == 'I' ? pcl::PCLPointField::INT8 : pcl::PCLPointField::UINT8;
  if (size == 2) return type == 'I' ? pcl::PCLPointField::INT16 : pcl::PCLPointField::UINT16;
  if (size == 4) return type == 'I' ? pcl::PCLPointField::INT32 : pcl::PCLPointField::UINT32;
  return 0;
}

/// The data of a checked PCD file as a PCLPointCloud2 (records of the fields in
/// order). uavip reads PCD itself: PCL's PCDReader crashes on damaged files that
/// pass every header check (tests/fuzz/fuzz_cloud), ours refuses them by name.
/// ascii values are stored as FLOAT64.
pcl::PCLPointCloud2 readPcdBody(const std::string& path, const PcdHeader& h) {
  pcl::PCLPointCloud2 blob;
  blob.width = static_cast<std::uint32_t>(h.width);
  blob.height = static_cast<std::uint32_t>(h.height);
  if (h.width > UINT32_MAX || h.height > UINT32_MAX)
    throw InputError(path + ": WIDTH or HEIGHT above 2^32");
  const bool ascii = h.data == "ascii";
  std::uint64_t offset = 0;
  for (std::size_t f = 0; f < h.fields.size(); ++f) {
    pcl::PCLPointField field;
    field.name = h.fields[f];
    field.offset = static_cast<std::uint32_t>(offset);
    field.datatype = ascii ? static_cast<std::uint8_t>(pcl::PCLPointField::FLOAT64)
                           : pclType(h.types[f], h.sizes[f]);
    field.count = static_cast<std::uint32_t>(h.counts[f]);
    blob.fields.push_back(field);
    offset += (ascii ? 8 : h.sizes[f]) * h.counts[f];
  }
  blob.point_step = static_cast<std::uint32_t>(offset);
  blob.row_step = static_cast<std::uint32_t>(offset * h.width);
  blob.data.resize(static_cast<std::size_t>(offset * h.points));

  std::ifstream in(path, std::ios::binary);
  in.seekg(static_cast<std::streamoff>(h.body));
  if (ascii) {
    // A 4-byte float field is parsed as a float (as PCL does), anything else as double.
    std::vector<bool> single;
    for (std::size_t f = 0; f < h.fields.size(); ++f)
      single.insert(single.end(), h.counts[f], h.types[f] == 'F' && h.sizes[f] == 4);
    const std::uint64_t values = single.size();
    auto* out = reinterpret_cast<double*>(blob.data.data());
    std::string token;
    for (std::uint64_t k = 0; k < values * h.points; ++k) {
      if (!(in >> token))
        throw InputError(path + ": point " + std::to_string(k / values) +
                         " has fewer values than FIELDS/COUNT say (" + std::to_string(values) +
                         " per point); the file is truncated");
      char* end = nullptr;
      const double v = single[k % values] ? static_cast<double>(std::strtof(token.c_str(), &end))
                                          : std::strtod(token.c_str(), &end);
      if (end != token.c_str() + token.size())
        throw InputError(path + ": point " + std::to_string(k / values) + ": '" +
                         token.substr(0, 20) + "' is not a number");
      out[k] = v;
    }
    return blob;
  }
  if (h.data == "binary") {
    in.read(reinterpret_cast<char*>(blob.data.data()),
            static_cast<std::streamsize>(blob.data.size()));
    if (static_cast<std::size_t>(in.gcount()) != blob.data.size())
      throw InputError(path + ": the binary data is truncated");
    return blob;
  }
  // binary_compressed: uint32 compressed size, uint32 size, LZF stream of the
  // fields one after the other (all x, then all y, …).
  std::uint32_t sizes[2] = {0, 0};
  in.read(reinterpret_cast<char*>(sizes), sizeof sizes);
  if (!in || sizes[0] > h.available - std::min<std::uint64_t>(h.available, 8) ||
      sizes[1] != blob.data.size())
    throw InputError(path + ": the compressed data's sizes do not match the header (" +
                     std::to_string(h.points) + " points); the file is damaged");
  std::vector<std::uint8_t> packed(sizes[0]);
  in.read(reinterpret_cast<char*>(packed.data()), static_cast<std::streamsize>(packed.size()));
  std::vector<std::uint8_t> columns(sizes[1]);
  if (static_cast<std::size_t>(in.gcount()) != packed.size() ||
      !lzfDecompress(packed.data(), packed.size(), columns))
    throw InputError(path + ": the compressed data is damaged (LZF)");
  std::uint64_t column = 0;
  for (std::size_t f = 0; f < h.fields.size(); ++f) {
    const std::uint64_t bytes = h.sizes[f] * h.counts[f];
    for (std::uint64_t i = 0; i < h.points; ++i) {
      std::memcpy(blob.data.data() + i * h.step + blob.fields[f].offset,
                  columns.data() + column + i * bytes, bytes);
    }
    column += bytes * h.points;
  }
  return blob;
}

/// Bytes of a PLY scalar type, 0 if unknown.
std::uint64_t plyTypeSize(const std::string& t) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" || t == "float32")
    return 4;
  if (t == "double" || t == "float64") return 8;
  return 0;
}

/// PLY header: a vertex element with x y z, known property types, and no more
/// vertices than the data can hold.
void checkPlyHeader(const std::string& path, std::istream& in, std::uint64_t file_size) {
  std::string line;
  std::getline(in, line);
  if (line.rfind("ply", 0) != 0)
    throw InputError(path + ": not a PLY file (first line must be 'ply')");
  std::string format;
  std::optional<std::uint64_t> vertices;
  bool in_vertex = false, ended = false;
  int xyz = 0;
  std::uint64_t step = 0, properties = 0;
  for (int lines = 0; lines < 256 && std::getline(in, line); ++lines) {
    const std::vector<std::string> w = words(line);
    if (w.empty()) continue;
    if (w[0] == "format" && w.size() >= 2) format = w[1];
    if (w[0] == "element") {
      if (w.size() != 3)
        throw InputError(path + ": malformed PLY line '" + line.substr(0, 60) + "'");
      in_vertex = w[1] == "vertex";
      if (in_vertex) vertices = headerCount(path, "element vertex", w[2]);
    }
    if (w[0] == "property" && in_vertex) {
      ++properties;
      if (w.size() >= 2 && w[1] == "list") {
        step += 1;  // at least the list's count
      } else if (w.size() == 3) {
        const std::uint64_t size = plyTypeSize(w[1]);
        if (size == 0)
          throw InputError(path + ": vertex property " + w[2] + " has unknown type '" + w[1] + "'");
        step += size;
        xyz += (w[2] == "x" || w[2] == "y" || w[2] == "z");
      }
    }
    if (w[0] == "end_header") {
      ended = true;
      break;
    }
  }
  if (!ended) throw InputError(path + ": PLY header has no end_header within 256 lines");
  if (!vertices || xyz < 3)
    throw InputError(path + ": PLY file has no vertex element with x y z properties");
  if (format != "ascii" && format != "binary_little_endian" && format != "binary_big_endian")
    throw InputError(
        path + ": PLY format must be ascii, binary_little_endian or binary_big_endian, got '" +
        format + "'");
  const std::streamoff at = in.tellg();
  const std::uint64_t available =
      at < 0 ? 0 : file_size - std::min<std::uint64_t>(file_size, static_cast<std::uint64_t>(at));
  if (format == "ascii") {
    checkPayload(path, *vertices, 2 * properties, available + 1,
                 "ascii, a digit and a separator per value");
  } else {
    checkPayload(path, *vertices, step, available, "binary");
  }
}

/// Reads a PCD (uavip's own reader, see readPcdBody) or PLY (PCL's reader after the
/// header checks) file into a PCLPointCloud2.
pcl::PCLPointCloud2 readBlob(const std::string& path, const std::string& ext) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot read (permission?)");
  std::error_code ec;
  const std::uint64_t size = std::filesystem::file_size(path, ec);
  if (ec) throw InputError(path + ": cannot read its size (" + ec.message() + ")");
  if (ext == ".pcd") return readPcdBody(path, checkPcdHeader(path, in, size));
  checkPlyHeader(path, in, size);
  pcl::PCLPointCloud2 cloud;
  if (pcl::io::loadPLYFile(path, cloud) < 0)
    throw InputError(path + ": cannot parse as ply (corrupt or not x/y/z?)");
  return cloud;
}

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
        throw InputError(
            path + ": point " + std::to_string(r * width + c) + " " + formatRawPoint(p) +
            " is not finite; remove NaN/inf points (e.g. pcl::removeNaNFromPointCloud)");
      }
      out.push_back(p);
    }
  }
  return out;
}

/// Throws InputError when the cloud spans more than kMaxCloudExtentM on an axis,
/// naming the point farthest (on one axis) from the per-axis median of the cloud:
/// a stray point such as 1e308, or a cloud in the wrong unit. `origin` is added back
/// so that the point is shown as in the file.
void requirePhysicalExtent(const std::string& path, const PointList& points, const Vec3& lo,
                           const Vec3& hi, const Vec3& origin) {
  const Vec3 extent = hi - lo;
  if (extent.allFinite() && extent.maxCoeff() <= kMaxCloudExtentM) {
    // Narrow, but maybe far: a lone point at 1e308, a georeferenced file in millimetres.
    if (std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff()) > kMaxCoordinateM) {
      std::size_t i = 0;
      while (i + 1 < points.size() && !(points[i].cwiseAbs().maxCoeff() > kMaxCoordinateM)) ++i;
      throw InputError(path + ": point " + std::to_string(i) + " " +
                       formatRawPoint(points[i] + origin) + " lies beyond " +
                       formatNumber(kMaxCoordinateM / 1e3) +
                       " km of the file's origin, on no map of "
                       "the earth: remove it, or set input.scale if the file is not in metres");
    }
    return;
  }
  Vec3 median;
  std::vector<double> axis(points.size());
  for (int a = 0; a < 3; ++a) {
    for (std::size_t i = 0; i < points.size(); ++i) axis[i] = points[i][a];
    std::nth_element(axis.begin(), axis.begin() + static_cast<std::ptrdiff_t>(axis.size() / 2),
                     axis.end());
    median[a] = axis[axis.size() / 2];
  }
  std::size_t worst = 0, strays = 0;
  double worst_d = -1.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double d = (points[i] - median).cwiseAbs().maxCoeff();
    if (!(d <= 0.5 * kMaxCloudExtentM)) ++strays;
    if (d > worst_d || std::isnan(d)) {
      worst_d = d;
      worst = i;
    }
  }
  const std::string span = path + ": the cloud spans " + formatNumber(extent.maxCoeff(), 3) +
                           " m (more than " + formatNumber(kMaxCloudExtentM / 1e3) +
                           " km, beyond any structure to inspect); ";
  // A few stray points (at most 1 %): named. Most of the cloud: a unit, not a point.
  if (strays <= std::max<std::size_t>(1, points.size() / 100))
    throw InputError(
        span +
        (strays > 1 ? std::to_string(strays) + " points lie far from the others, the farthest "
                    : "") +
        "point " + std::to_string(worst) + " " + formatRawPoint(points[worst] + origin) + " lies " +
        formatNumber(worst_d, 3) + " m from the cloud's median: remove it");
  throw InputError(span + std::to_string(strays) + " of " + std::to_string(points.size()) +
                   " points lie over " + formatNumber(0.5 * kMaxCloudExtentM / 1e3) +
                   " km from the median: the file is not in metres (set input.scale, e.g. 0.001 "
                   "for millimetres) "
                   "or holds more than one site");
}

}  // namespace

Vec3 recentringOrigin(const Vec3& lo, const Vec3& hi) {
  const Vec3 centre = lo + 0.5 * (hi - lo);  // lo + hi could overflow
  const bool z_far = std::max(std::abs(lo.z()), std::abs(hi.z())) > kRecentreBeyondM;
  return Vec3(std::round(centre.x()), std::round(centre.y()), z_far ? std::round(centre.z()) : 0.0);
}

bool farFromOrigin(const Vec3& lo, const Vec3& hi) {
  return std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff()) > kRecentreBeyondM;
}

void CloudReadOptions::validate(const std::string& where) const {
  for (const int c : drop_classes) {
    if (c < 0 || c > 255)
      throw InputError(where + ": drop_classes holds " + std::to_string(c) +
                       ", a class must be 0..255");
  }
  if (!(std::isfinite(scale) && scale > 0.0)) {
    throw InputError(
        where + ": scale must be > 0 and finite (0.001 for millimetres, 0.3048 for feet), got " +
        formatNumber(scale));
  }
}

PointList loadCloud(const std::string& path, const CloudReadOptions& options, CloudReadInfo* info) {
  options.validate();
  const std::string ext = lowerExtension(path);
  requireRegularFile(path);
  PointList points;
  Vec3 origin = Vec3::Zero();  // already subtracted from points (LAS)
  if (ext == ".las" || ext == ".laz") {
    LasOptions las_options;
    las_options.drop_classes = options.drop_classes;
    LasCloud las = readLas(path, las_options);
    if (info != nullptr) {
      std::ostringstream os;
      os << path << ": LAS " << las.version_major << "." << las.version_minor << " point format "
         << las.point_format << ", " << las.points_in_file << " points";
      if (!options.drop_classes.empty()) {
        os << " (" << las.dropped << " dropped: input.drop_classes";
        for (const int c : options.drop_classes) os << " " << c;
        os << (options.drop_classes == std::vector<int>{7, 18} ? ", the classes LAS flags as noise"
                                                               : "")
           << ")";
      }
      os << "; unit " << las.unit_name << " (" << las.unit_source << ")";
      if (las.unit_to_m != 1.0 || las.z_unit_to_m != 1.0) os << " converted to metres";
      os << "; recentred by (" << formatNumber(las.origin_m.x(), 12) << ", "
         << formatNumber(las.origin_m.y(), 12) << ", " << formatNumber(las.origin_m.z(), 12)
         << ") m";  // every metre of a UTM northing
      if (!las.crs.empty()) os << "; CRS from " << las.crs_source;
      info->note = os.str();
      info->origin_m = las.origin_m;
      info->crs = las.crs;
      info->crs_source = las.crs_source;
    }
    origin = las.origin_m;
    points = std::move(las.points);
    if (points.empty())
      throw InputError(path + ": no point is left after drop_classes; drop fewer classes");
  } else if (ext == ".xyz" || ext == ".txt" || ext == ".csv") {
    points = loadXyz(path);
  } else if (ext == ".pcd" || ext == ".ply") {
    points = fromBlob(readBlob(path, ext), path);
  } else {
    throw InputError(path + ": unknown cloud extension '" + ext +
                     "' (use .pcd, .ply, .xyz, .txt, .csv or .las)");
  }
  if (points.empty()) throw InputError(path + ": the cloud has no points");
  if (options.scale != 1.0) {
    for (auto& p : points) p *= options.scale;
    origin *= options.scale;
    if (info != nullptr) {
      info->note += std::string(info->note.empty() ? "" : "; ") +
                    "coordinates scaled by input.scale " + formatNumber(options.scale) +
                    " to metres";
      info->origin_m = origin;
    }
  }
  Vec3 lo = points.front(), hi = points.front();
  for (const Vec3& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  requirePhysicalExtent(path, points, lo, hi, origin);
  // A cloud far from the origin (UTM, a national grid): recentred while still in double.
  if (farFromOrigin(lo, hi)) {
    const Vec3 shift = recentringOrigin(lo, hi);
    for (Vec3& p : points) p -= shift;
    origin += shift;
    if (info != nullptr) {
      info->origin_m = origin;
      info->note += std::string(info->note.empty() ? path + ": " : "; ") +
                    "far from the origin, recentred by (" + formatNumber(shift.x(), 12) + ", " +
                    formatNumber(shift.y(), 12) + ", " + formatNumber(shift.z(), 12) +
                    ") m (scene.json source_offset_m adds it back)";
    }
  }
  return points;
}

namespace {

/// One pass over the cloud in the frame loadCloud gives before its own recentring
/// (a LAS file recentred by its header, then input.scale), in chunks to `sink`.
/// Returns the LAS header information for LAS files (nullopt otherwise).
std::optional<LasCloud> readChunks(const std::string& path, const CloudReadOptions& options,
                                   std::size_t chunk_points, const CloudChunkSink& sink) {
  const std::string ext = lowerExtension(path);
  PointList chunk;
  chunk.reserve(chunk_points);
  const auto flush = [&] {
    if (chunk.empty()) return;
    if (options.scale != 1.0)
      for (Vec3& p : chunk) p *= options.scale;
    sink(chunk);
    chunk.clear();
  };
  const auto add = [&](const Vec3& p) {
    chunk.push_back(p);
    if (chunk.size() >= chunk_points) flush();
  };
  std::optional<LasCloud> las;
  if (ext == ".las" || ext == ".laz") {
    LasOptions las_options;
    las_options.drop_classes = options.drop_classes;
    las = streamLas(path, las_options,
                    [&](const PointList& points, const std::vector<std::uint8_t>&) {
                      for (const Vec3& p : points) add(p);
                    });
  } else if (ext == ".xyz" || ext == ".txt" || ext == ".csv") {
    std::ifstream in(path);
    if (!in) throw InputError(path + ": cannot open the file, check its permissions");
    parseXyz(in, path, add);
  } else if (ext == ".pcd" || ext == ".ply") {
    // PCD and PLY are read whole (PCL's blob), then handed on in chunks.
    for (const Vec3& p : fromBlob(readBlob(path, ext), path)) add(p);
  } else {
    throw InputError(path + ": unknown cloud extension '" + ext +
                     "' (use .pcd, .ply, .xyz, .txt, .csv or .las)");
  }
  flush();
  return las;
}

}  // namespace

bool streamsInBoundedMemory(const std::string& path) {
  const std::string ext = lowerExtension(path);
  return ext == ".las" || ext == ".xyz" || ext == ".txt" || ext == ".csv";
}

CloudStreamInfo streamCloud(const std::string& path, const CloudReadOptions& options,
                            std::size_t chunk_points, const CloudChunkSink& sink,
                            const std::function<void(const CloudStreamInfo&)>& on_bounds) {
  options.validate();
  requireRegularFile(path);
  if (chunk_points == 0) throw InputError("streamCloud: chunk_points must be > 0");
  // Pass 1: count and bounds, so that the frame is loadCloud's before any point is handed on.
  CloudStreamInfo info;
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  const std::optional<LasCloud> las =
      readChunks(path, options, chunk_points, [&](const PointList& points) {
        for (const Vec3& p : points) {
          if (p.cwiseAbs().maxCoeff() > kMaxCoordinateM)
            throw InputError(path + ": point " + formatRawPoint(p) + " lies beyond " +
                             formatNumber(kMaxCoordinateM / 1e3) +
                             " km of the origin; remove it or fix input.scale");
          lo = lo.cwiseMin(p);
          hi = hi.cwiseMax(p);
        }
        info.points += points.size();
      });
  if (info.points == 0)
    throw InputError(path + (las ? ": no point is left after drop_classes; drop fewer classes"
                                 : ": the cloud has no points"));
  if ((hi - lo).maxCoeff() > kMaxCloudExtentM)
    throw InputError(path + ": the cloud spans " + formatNumber((hi - lo).maxCoeff() / 1e3, 4) +
                     " km, wider than " + formatNumber(kMaxCloudExtentM / 1e3) +
                     " km: it is not in metres (set input.scale) or holds a stray point");
  Vec3 origin = las ? Vec3(las->origin_m * options.scale) : Vec3::Zero();
  const Vec3 shift = farFromOrigin(lo, hi) ? recentringOrigin(lo, hi) : Vec3::Zero();
  origin += shift;
  info.read.origin_m = origin;
  info.min = lo - shift;
  info.max = hi - shift;
  if (las) {
    info.crs_unit = las->unit_name + " (" + las->unit_source + ")";
    info.read.note = path + ": LAS " + std::to_string(las->version_major) + "." +
                     std::to_string(las->version_minor) + ", " +
                     std::to_string(las->points_in_file) + " points, " +
                     std::to_string(las->dropped) + " dropped by input.drop_classes";
  }
  if (on_bounds) on_bounds(info);
  // Pass 2: the points in that frame.
  readChunks(path, options, chunk_points, [&](const PointList& points) {
    if (shift == Vec3::Zero()) {
      sink(points);
      return;
    }
    PointList shifted = points;
    for (Vec3& p : shifted) p -= shift;
    sink(shifted);
  });
  return info;
}

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

void setPclConsole(bool verbose) {
  pcl::console::setVerbosityLevel(verbose ? pcl::console::L_WARN : pcl::console::L_ALWAYS);
}

void saveCloudPcd(const std::string& path, const PointList& cloud) {
  replaceFileAtomic(path, [&](const std::string& tmp) { writeCloudPcdFile(tmp, cloud, path); });
}

}  // namespace uavip::io
