// PLY (ascii and binary), read by PCL after uavip's header check; ascii and
// binary_little_endian vertices also streamed a chunk at a time (streamPly).

#include <pcl/io/ply_io.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <optional>
#include <string>
#include <vector>

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

/// A property of the vertex element.
struct PlyProperty {
  std::string name, type;
  std::uint64_t size{0};  ///< bytes (0 for a list)
};

/// An element of the header.
struct PlyElement {
  std::string name;
  std::uint64_t count{0};
  std::vector<PlyProperty> properties;
  bool lists() const {
    return std::any_of(properties.begin(), properties.end(),
                       [](const PlyProperty& p) { return p.size == 0; });
  }
  std::uint64_t step() const {
    std::uint64_t s = 0;
    for (const auto& p : properties) s += p.size;
    return s;
  }
};

/// What the header says, once checked.
struct PlyHeader {
  std::string format;
  std::uint64_t vertices{0};
  std::vector<PlyProperty> vertex;   ///< the vertex element's properties, in order
  std::vector<PlyElement> elements;  ///< every element, in order
  bool vertex_first{false};          ///< the vertex element is the first element
  bool lists{false};                 ///< the vertex element has a list property
  bool grid{false};                  ///< an `obj_info num_rows` other than 1 (a sensor frame)
  std::uint64_t body{0};             ///< offset of the first element's data [bytes]
};

/// PLY header: a vertex element with x y z, known property types, and no more
/// vertices than the data can hold.
PlyHeader checkPlyHeader(const std::string& path, std::istream& in, std::uint64_t file_size) {
  std::string line;
  std::getline(in, line);
  if (line.rfind("ply", 0) != 0)
    throw InputError(path + ": not a PLY file (first line must be 'ply')");
  PlyHeader h;
  std::optional<std::uint64_t> vertices;
  bool in_vertex = false, ended = false, first_element = true;
  int xyz = 0;
  std::uint64_t step = 0, properties = 0;
  for (int lines = 0; lines < 256 && std::getline(in, line); ++lines) {
    const std::vector<std::string> w = headerWords(line);
    if (w.empty()) continue;
    if (w[0] == "format" && w.size() >= 2) h.format = w[1];
    if (w[0] == "obj_info" && w.size() >= 3 && w[1] == "num_rows" && w[2] != "1") h.grid = true;
    if (w[0] == "element") {
      if (w.size() != 3)
        throw InputError(path + ": malformed PLY line '" + line.substr(0, 60) + "'");
      in_vertex = w[1] == "vertex";
      h.elements.push_back({w[1], headerCount(path, "element " + w[1], w[2]), {}});
      if (in_vertex) {
        vertices = headerCount(path, "element vertex", w[2]);
        h.vertex_first = first_element;
      }
      first_element = false;
    }
    if (w[0] == "property" && !h.elements.empty() && w.size() >= 3)
      h.elements.back().properties.push_back(
          {w.back(), w[1] == "list" ? "list" : w[1], w[1] == "list" ? 0 : plyTypeSize(w[1])});
    if (w[0] == "property" && in_vertex) {
      ++properties;
      if (w.size() >= 2 && w[1] == "list") {
        step += 1;  // at least the list's count
        h.lists = true;
        h.vertex.push_back({w.size() >= 5 ? w[4] : std::string(), "list", 0});
      } else if (w.size() == 3) {
        const std::uint64_t size = plyTypeSize(w[1]);
        if (size == 0)
          throw InputError(path + ": vertex property " + w[2] + " has unknown type '" + w[1] + "'");
        step += size;
        xyz += (w[2] == "x" || w[2] == "y" || w[2] == "z");
        h.vertex.push_back({w[2], w[1], size});
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
  if (h.format != "ascii" && h.format != "binary_little_endian" && h.format != "binary_big_endian")
    throw InputError(
        path + ": PLY format must be ascii, binary_little_endian or binary_big_endian, got '" +
        h.format + "'");
  const std::streamoff at = in.tellg();
  const std::uint64_t available =
      at < 0 ? 0 : file_size - std::min<std::uint64_t>(file_size, static_cast<std::uint64_t>(at));
  if (h.format == "ascii") {
    checkPayload(path, *vertices, 2 * properties, available + 1,
                 "ascii, a digit and a separator per value");
  } else {
    checkPayload(path, *vertices, step, available, "binary");
  }
  h.vertices = *vertices;
  h.body = at < 0 ? file_size : static_cast<std::uint64_t>(at);
  return h;
}

/// The rows PCL's reader gives the cloud from a camera element's `viewporty` (PCL
/// writes one after the vertices): 1 without one; 0 when it cannot be read here (the
/// file is then read whole).
std::int64_t cameraRows(const std::string& path, const PlyHeader& h, std::uint64_t file_size) {
  std::size_t camera = h.elements.size();
  for (std::size_t e = 0; e < h.elements.size(); ++e)
    if (h.elements[e].name == "camera") camera = e;
  if (camera == h.elements.size()) return 1;
  const PlyElement& c = h.elements[camera];
  std::size_t column = c.properties.size();
  for (std::size_t i = 0; i < c.properties.size(); ++i)
    if (c.properties[i].name == "viewporty") column = i;
  if (column == c.properties.size()) return 1;
  if (c.count != 1 || c.lists()) return 0;
  std::ifstream in(path, std::ios::binary);
  std::string record;
  if (h.format == "ascii") {
    // The camera's line is the file's last when every element after it, and every
    // one between the vertices and it, is empty.
    for (std::size_t e = 1; e < h.elements.size(); ++e)
      if (e != camera && h.elements[e].count != 0) return 0;
    const std::uint64_t tail = std::min<std::uint64_t>(file_size - h.body, 4096);
    record.resize(tail);
    in.seekg(static_cast<std::streamoff>(file_size - tail));
    in.read(record.data(), static_cast<std::streamsize>(tail));
    while (!record.empty() && std::isspace(static_cast<unsigned char>(record.back())))
      record.pop_back();
    const std::size_t start = record.find_last_of('\n');
    const std::vector<std::string> w =
        headerWords(start == std::string::npos ? record : record.substr(start + 1));
    if (!in || w.size() != c.properties.size()) return 0;
    return std::atoll(w[column].c_str());
  }
  std::uint64_t at = h.body;
  for (std::size_t e = 0; e < camera; ++e) {
    if (h.elements[e].count != 0 && h.elements[e].lists()) return 0;
    at += h.elements[e].count * h.elements[e].step();
  }
  for (std::size_t i = 0; i < column; ++i) at += c.properties[i].size;
  const std::uint64_t size = c.properties[column].size;
  if (size != 4 || at + size > file_size) return 0;
  std::int32_t rows = 0;
  in.seekg(static_cast<std::streamoff>(at));
  in.read(reinterpret_cast<char*>(&rows), 4);
  return in ? rows : 0;
}

/// True when streamPly reads the file `h` describes in chunks: ascii or
/// binary_little_endian, the vertices first and of scalar properties only, one row
/// (PCL's reader keeps a sensor frame's rows, and then skips its missing returns:
/// such a file, from obj_info num_rows, a camera's viewporty or a range_grid, is read
/// whole).
bool plyHeaderStreams(const std::string& path, const PlyHeader& h, std::uint64_t file_size) {
  const bool range_grid = std::any_of(h.elements.begin(), h.elements.end(),
                                      [](const PlyElement& e) { return e.name == "range_grid"; });
  return (h.format == "ascii" || h.format == "binary_little_endian") && h.vertex_first &&
         !h.lists && !h.grid && !range_grid && cameraRows(path, h, file_size) == 1;
}

/// PCL's field type of a PLY scalar type.
std::uint8_t pclType(const std::string& t) {
  if (t == "char" || t == "int8") return pcl::PCLPointField::INT8;
  if (t == "uchar" || t == "uint8") return pcl::PCLPointField::UINT8;
  if (t == "short" || t == "int16") return pcl::PCLPointField::INT16;
  if (t == "ushort" || t == "uint16") return pcl::PCLPointField::UINT16;
  if (t == "int" || t == "int32") return pcl::PCLPointField::INT32;
  if (t == "uint" || t == "uint32") return pcl::PCLPointField::UINT32;
  if (t == "float" || t == "float32") return pcl::PCLPointField::FLOAT32;
  return pcl::PCLPointField::FLOAT64;
}

/// One ascii value as PCL's parser stores it in a property of type `t` (a value it
/// cannot parse becomes NaN), as a double.
double asciiValue(const char* text, const std::string& t) {
  char* end = nullptr;
  errno = 0;
  double v = std::numeric_limits<double>::quiet_NaN();
  const std::uint8_t type = pclType(t);
  if (type == pcl::PCLPointField::FLOAT32) {
    const float f = std::strtof(text, &end);
    if (end != text && *end == '\0') v = f;
  } else if (type == pcl::PCLPointField::FLOAT64) {
    const double d = std::strtod(text, &end);
    if (end != text && *end == '\0') v = d;
  } else {
    const long long i = std::strtoll(text, &end, 10);
    if (end != text && *end == '\0' && errno == 0) {
      switch (type) {
        case pcl::PCLPointField::INT8:
          v = static_cast<std::int8_t>(i);
          break;
        case pcl::PCLPointField::UINT8:
          v = static_cast<std::uint8_t>(i);
          break;
        case pcl::PCLPointField::INT16:
          v = static_cast<std::int16_t>(i);
          break;
        case pcl::PCLPointField::UINT16:
          v = static_cast<std::uint16_t>(i);
          break;
        case pcl::PCLPointField::INT32:
          v = static_cast<std::int32_t>(i);
          break;
        default:
          v = static_cast<std::uint32_t>(i);
      }
    }
  }
  return v;
}

}  // namespace

bool plyStreams(const std::string& path, std::istream& in, std::uint64_t file_size) {
  return plyHeaderStreams(path, checkPlyHeader(path, in, file_size), file_size);
}

bool streamPly(const std::string& path, std::istream& in, std::uint64_t file_size,
               std::size_t chunk_points, const std::function<void(const PointList&)>& sink) {
  const PlyHeader h = checkPlyHeader(path, in, file_size);
  if (!plyHeaderStreams(path, h, file_size)) return false;
  // Each chunk as a blob of x y z only, so that fromBlob checks and converts it as it
  // does PCL's whole blob: binary records as they are, ascii values parsed as PCL does.
  const bool ascii = h.format == "ascii";
  const char* names[3] = {"x", "y", "z"};
  std::size_t column[3] = {0, 0, 0};
  pcl::PCLPointCloud2 blob;
  std::uint64_t offset = 0;
  for (int a = 0; a < 3; ++a) {
    pcl::PCLPointField f;
    f.name = names[a];
    f.count = 1;
    std::uint64_t at = 0;
    for (std::size_t i = 0; i < h.vertex.size(); ++i) {
      if (h.vertex[i].name == names[a]) {  // the first property of that name
        column[a] = i;
        f.offset = static_cast<std::uint32_t>(ascii ? std::size_t{8} * a : at);
        f.datatype = ascii ? std::uint8_t{pcl::PCLPointField::FLOAT64} : pclType(h.vertex[i].type);
        break;
      }
      at += h.vertex[i].size;
    }
    blob.fields.push_back(f);
  }
  for (const auto& p : h.vertex) offset += p.size;
  const std::uint64_t step = ascii ? 24 : offset;
  blob.point_step = static_cast<std::uint32_t>(step);
  std::ifstream data(path, std::ios::binary);
  data.seekg(static_cast<std::streamoff>(h.body));
  std::string line;
  std::vector<char*> words;
  for (std::uint64_t first = 0; first < h.vertices; first += chunk_points) {
    const std::uint64_t n = std::min<std::uint64_t>(chunk_points, h.vertices - first);
    blob.width = static_cast<std::uint32_t>(n);
    blob.height = 1;
    blob.row_step = static_cast<std::uint32_t>(step * n);
    blob.data.resize(step * n);
    if (!ascii) {
      data.read(reinterpret_cast<char*>(blob.data.data()), static_cast<std::streamsize>(step * n));
      if (!data)
        throw InputError(path + ": the vertex data ends before vertex " +
                         std::to_string(first + static_cast<std::uint64_t>(data.gcount()) / step) +
                         " of the " + std::to_string(h.vertices) +
                         " the header says; the file is truncated");
    } else {
      for (std::uint64_t k = 0; k < n; ++k) {
        if (!std::getline(data, line))
          throw InputError(path + ": the vertex data ends before vertex " +
                           std::to_string(first + k) + " of the " + std::to_string(h.vertices) +
                           " the header says; the file is truncated");
        words.clear();
        for (char* c = line.data(); *c != '\0';) {  // the line split in place
          while (*c != '\0' && std::isspace(static_cast<unsigned char>(*c))) *c++ = '\0';
          if (*c == '\0') break;
          words.push_back(c);
          while (*c != '\0' && !std::isspace(static_cast<unsigned char>(*c))) ++c;
        }
        if (words.size() < h.vertex.size())
          throw InputError(path + ": vertex " + std::to_string(first + k) + " has " +
                           std::to_string(words.size()) + " values, the header names " +
                           std::to_string(h.vertex.size()) + " properties");
        for (int a = 0; a < 3; ++a) {
          const double v = asciiValue(words[column[a]], h.vertex[column[a]].type);
          std::memcpy(blob.data.data() + k * step + std::size_t{8} * a, &v, 8);
        }
      }
    }
    sink(fromBlob(blob, path, false, first));
  }
  return true;
}

pcl::PCLPointCloud2 readPly(const std::string& path, std::istream& in, std::uint64_t file_size) {
  checkPlyHeader(path, in, file_size);
  pcl::PCLPointCloud2 cloud;
  if (pcl::io::loadPLYFile(path, cloud) < 0)
    throw InputError(path + ": cannot parse as ply (corrupt or not x/y/z?)");
  return cloud;
}

}  // namespace uavip::io
