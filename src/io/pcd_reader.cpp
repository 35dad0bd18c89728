// PCD (PCL's PCD v0.7 and 0.6; ascii, binary, binary_compressed with LZF), read by
// uavip itself after a header check: PCL's PCDReader crashes on damaged files.

#include <pcl/PCLPointField.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <optional>
#include <set>

#include "cloud_formats.h"
#include "uavip/core/error.h"

namespace uavip::io {
namespace {

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
    std::vector<std::string> w = headerWords(line);
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

/// An empty blob of `n` records of the layout of `h` (records of the fields in order;
/// ascii values stored as FLOAT64): width and height of the file when n is all of its
/// points, else n × 1.
pcl::PCLPointCloud2 pcdBlob(const std::string& path, const PcdHeader& h, std::uint64_t n) {
  pcl::PCLPointCloud2 blob;
  if (h.width > UINT32_MAX || h.height > UINT32_MAX)
    throw InputError(path + ": WIDTH or HEIGHT above 2^32");
  const bool whole = n == h.points;
  blob.width = static_cast<std::uint32_t>(whole ? h.width : n);
  blob.height = static_cast<std::uint32_t>(whole ? h.height : 1);
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
  blob.row_step = static_cast<std::uint32_t>(offset * blob.width);
  blob.data.resize(static_cast<std::size_t>(offset * n));
  return blob;
}

/// Reads the next records of an ascii or binary PCD body from `in` into `blob`
/// (pcdBlob); `first` is the index of the first of them in the file (messages).
void readPcdRecords(const std::string& path, const PcdHeader& h, std::istream& in,
                    std::uint64_t first, pcl::PCLPointCloud2& blob) {
  if (h.data == "ascii") {
    // A 4-byte float field is parsed as a float (as PCL does), anything else as double.
    std::vector<bool> single;
    for (std::size_t f = 0; f < h.fields.size(); ++f)
      single.insert(single.end(), h.counts[f], h.types[f] == 'F' && h.sizes[f] == 4);
    const std::uint64_t values = single.size();
    const std::uint64_t n = blob.data.size() / 8 / std::max<std::uint64_t>(values, 1);
    auto* out = reinterpret_cast<double*>(blob.data.data());
    std::string token;
    for (std::uint64_t k = 0; k < values * n; ++k) {
      if (!(in >> token))
        throw InputError(path + ": point " + std::to_string(first + k / values) +
                         " has fewer values than FIELDS/COUNT say (" + std::to_string(values) +
                         " per point); the file is truncated");
      char* end = nullptr;
      const double v = single[k % values] ? static_cast<double>(std::strtof(token.c_str(), &end))
                                          : std::strtod(token.c_str(), &end);
      if (end != token.c_str() + token.size())
        throw InputError(path + ": point " + std::to_string(first + k / values) + ": '" +
                         token.substr(0, 20) + "' is not a number");
      out[k] = v;
    }
    return;
  }
  in.read(reinterpret_cast<char*>(blob.data.data()),
          static_cast<std::streamsize>(blob.data.size()));
  if (static_cast<std::size_t>(in.gcount()) != blob.data.size())
    throw InputError(path + ": the binary data is truncated");
}

/// The data of a checked PCD file as a PCLPointCloud2 (pcdBlob). uavip reads PCD
/// itself: PCL's PCDReader crashes on damaged files that pass every header check
/// (tests/fuzz/fuzz_cloud), ours refuses them by name.
pcl::PCLPointCloud2 readPcdBody(const std::string& path, const PcdHeader& h) {
  pcl::PCLPointCloud2 blob = pcdBlob(path, h, h.points);
  std::ifstream in(path, std::ios::binary);
  in.seekg(static_cast<std::streamoff>(h.body));
  if (h.data != "binary_compressed") {
    readPcdRecords(path, h, in, 0, blob);
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

}  // namespace

pcl::PCLPointCloud2 readPcd(const std::string& path, std::istream& in, std::uint64_t file_size) {
  return readPcdBody(path, checkPcdHeader(path, in, file_size));
}

bool pcdStreams(const std::string& path, std::istream& in, std::uint64_t file_size) {
  return checkPcdHeader(path, in, file_size).data != "binary_compressed";
}

bool streamPcd(const std::string& path, std::istream& in, std::uint64_t file_size,
               std::size_t chunk_points, const std::function<void(const PointList&)>& sink) {
  const PcdHeader h = checkPcdHeader(path, in, file_size);
  if (h.data == "binary_compressed") return false;
  std::ifstream data(path, std::ios::binary);
  data.seekg(static_cast<std::streamoff>(h.body));
  const bool organized = h.height > 1;
  for (std::uint64_t first = 0; first < h.points; first += chunk_points) {
    const std::uint64_t n = std::min<std::uint64_t>(chunk_points, h.points - first);
    pcl::PCLPointCloud2 blob = pcdBlob(path, h, n);
    blob.width = static_cast<std::uint32_t>(n);
    blob.height = 1;
    blob.row_step = static_cast<std::uint32_t>(blob.point_step * n);
    readPcdRecords(path, h, data, first, blob);
    sink(fromBlob(blob, path, organized, first));
  }
  return true;
}

}  // namespace uavip::io
