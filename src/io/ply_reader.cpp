// PLY (ascii and binary), read by PCL after uavip's header check.

#include <pcl/io/ply_io.h>

#include <algorithm>
#include <optional>

#include "cloud_formats.h"
#include "uavip/core/error.h"

namespace uavip::io {
namespace {

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
    const std::vector<std::string> w = headerWords(line);
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

}  // namespace

pcl::PCLPointCloud2 readPly(const std::string& path, std::istream& in, std::uint64_t file_size) {
  checkPlyHeader(path, in, file_size);
  pcl::PCLPointCloud2 cloud;
  if (pcl::io::loadPLYFile(path, cloud) < 0)
    throw InputError(path + ": cannot parse as ply (corrupt or not x/y/z?)");
  return cloud;
}

}  // namespace uavip::io
