#include "uavip/io/las_reader.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <map>
#include <optional>
#include <sstream>

#include "uavip/core/error.h"
#include "uavip/io/cloud_io.h"

namespace uavip::io {
namespace {

namespace fs = std::filesystem;

// Byte sizes from the ASPRS LAS 1.4 specification (R15), public header block and
// point data record formats 0–10.
constexpr std::array<int, 11> kFormatLength{20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};
constexpr std::size_t kHeaderSize12 = 227;  // LAS 1.0–1.2
constexpr std::size_t kHeaderSize13 = 235;  // LAS 1.3: + start of waveform data
constexpr std::size_t kHeaderSize14 = 375;  // LAS 1.4: + EVLRs, 64-bit counts
constexpr std::size_t kVlrHeaderSize = 54;
constexpr std::size_t kEvlrHeaderSize = 60;
constexpr std::uint64_t kMaxPoints = std::uint64_t{1} << 31;
constexpr std::uint64_t kMaxProjectionRecord = std::uint64_t{1} << 24;  // WKT, GeoTIFF keys [bytes]
constexpr std::size_t kChunkBytes = std::size_t{1} << 18;               // point block read size
constexpr int kMaxWktDepth = 64;

// GeoTIFF keys (GeoTIFF 1.0 specification, 6.2) and EPSG unit codes.
constexpr std::uint16_t kKeyModelType = 1024;        // GTModelTypeGeoKey
constexpr std::uint16_t kKeyProjectedCsType = 3072;  // ProjectedCSTypeGeoKey
constexpr std::uint16_t kKeyProjLinearUnits = 3076;  // ProjLinearUnitsGeoKey
constexpr std::uint16_t kKeyProjLinearUnitSize = 3077;
constexpr std::uint16_t kKeyVerticalUnits = 4099;   // VerticalUnitsGeoKey
constexpr std::uint16_t kKeyVerticalCsType = 4096;  // VerticalCSTypeGeoKey
constexpr std::uint16_t kModelTypeGeographic = 2;
constexpr std::uint16_t kUserDefined = 32767;
constexpr std::uint16_t kTagGeoDoubleParams = 34736;

constexpr double kInternationalFoot = 0.3048;      // [m]
constexpr double kUsSurveyFoot = 1200.0 / 3937.0;  // [m]

const char* const kDecompress =
    "decompress it first: `laszip -i x.laz -o x.las` (LAStools) or `pdal translate x.laz x.las`";
const char* const kReproject =
    "reproject it to a projected CRS in metres, e.g. `pdal translate x.las y.las reprojection "
    "--filters.reprojection.out_srs=EPSG:<UTM zone code>`";
const char* const kDamaged =
    "the file is damaged or was written wrongly; re-export or re-download it";

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw InputError(path + ": " + what);
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

bool endsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

template <typename T>
std::string str(T value) {
  std::ostringstream os;
  os.precision(17);
  os << value;
  return os.str();
}

// Little-endian loads, independent of the host's byte order.
std::uint16_t u16(const unsigned char* p) { return static_cast<std::uint16_t>(p[0] | (p[1] << 8)); }
std::uint32_t u32(const unsigned char* p) {
  return std::uint32_t{p[0]} | (std::uint32_t{p[1]} << 8) | (std::uint32_t{p[2]} << 16) |
         (std::uint32_t{p[3]} << 24);
}
std::uint64_t u64(const unsigned char* p) { return u32(p) | (std::uint64_t{u32(p + 4)} << 32); }
std::int32_t i32(const unsigned char* p) {
  const std::uint32_t u = u32(p);
  std::int32_t v = 0;
  std::memcpy(&v, &u, sizeof v);
  return v;
}
double f64(const unsigned char* p) {
  const std::uint64_t u = u64(p);
  double v = 0.0;
  std::memcpy(&v, &u, sizeof v);
  return v;
}

/// The file, read at absolute byte offsets; every read is checked against its size first.
class LasFile {
 public:
  LasFile(const std::string& path, std::uint64_t size)
      : path_(path), size_(size), in_(path, std::ios::binary) {
    if (!in_) fail(path_, "cannot open the file, check its permissions");
  }
  std::uint64_t size() const { return size_; }
  void seek(std::uint64_t offset) {
    in_.seekg(static_cast<std::streamoff>(offset));
    if (!in_) fail(path_, "cannot seek to byte " + str(offset) + ", " + kDamaged);
  }
  /// Reads n bytes from the current position.
  void read(unsigned char* dst, std::size_t n) {
    in_.read(reinterpret_cast<char*>(dst), static_cast<std::streamsize>(n));
    if (!in_)
      fail(path_, "read error (file shorter than its header says?), " + std::string(kDamaged));
  }
  std::vector<unsigned char> readAt(std::uint64_t offset, std::size_t n) {
    std::vector<unsigned char> out(n);
    seek(offset);
    if (n > 0) read(out.data(), n);
    return out;
  }

 private:
  std::string path_;
  std::uint64_t size_;
  std::ifstream in_;
};

/// The public header block fields this reader uses.
struct Header {
  int major{1};
  int minor{0};
  std::size_t header_size{0};
  std::uint64_t offset_to_points{0};
  std::uint32_t vlr_count{0};
  int format{0};
  std::size_t record_length{0};
  std::uint64_t count{0};
  std::array<double, 3> scale{};
  std::array<double, 3> offset{};
  std::array<double, 3> max{};
  std::array<double, 3> min{};
  std::uint64_t evlr_start{0};
  std::uint32_t evlr_count{0};
};

/// Version and header size (bytes 24, 25, 94): LAS 1.0–1.4, a header as long as its
/// version needs and no longer than the file.
void readVersion(const std::vector<unsigned char>& b, std::uint64_t file_size,
                 const std::string& path, Header& h) {
  h.major = b[24];
  h.minor = b[25];
  const std::string version = str(h.major) + "." + str(h.minor);
  if (h.major != 1 || h.minor > 4)
    fail(path, "unsupported LAS version " + version +
                   " (this reader knows 1.0–1.4), convert it, e.g. `pdal translate x.las y.las "
                   "--writers.las.minor_version=4`");
  h.header_size = u16(b.data() + 94);
  const std::size_t required = h.minor <= 2   ? kHeaderSize12
                               : h.minor == 3 ? kHeaderSize13
                                              : kHeaderSize14;
  if (h.header_size < required)
    fail(path, "header size " + str(h.header_size) + " bytes is smaller than the " + str(required) +
                   " bytes LAS " + version + " requires, " + kDamaged);
  if (h.header_size > file_size)
    fail(path, "header size " + str(h.header_size) + " bytes exceeds the file size " +
                   str(file_size) + " bytes, " + kDamaged);
}

/// Point data format and record length (bytes 104–106): no LASzip bit, a known
/// format, records long enough for it.
void readPointFormat(const std::vector<unsigned char>& b, const std::string& path, Header& h) {
  const unsigned format_byte = b[104];
  if ((format_byte & 0xC0u) != 0)
    fail(path, "point data format byte " + str(format_byte) +
                   " has the LASzip compression bit set (LAZ content), " + kDecompress);
  h.format = static_cast<int>(format_byte);
  if (h.format > 10)
    fail(path, "unknown point data format " + str(h.format) +
                   " (LAS 1.4 defines 0–10), convert it, e.g. `pdal translate x.las y.las "
                   "--writers.las.dataformat_id=6`");
  h.record_length = u16(b.data() + 105);
  const auto needed = static_cast<std::size_t>(kFormatLength[static_cast<std::size_t>(h.format)]);
  if (h.record_length < needed)
    fail(path, "point record length " + str(h.record_length) + " bytes is shorter than the " +
                   str(needed) + " bytes point format " + str(h.format) + " needs, " + kDamaged);
}

/// Where the points start and how many there are (bytes 96–107; 1.4: 235–254),
/// within the file and this reader's limit.
void readPointCount(const std::vector<unsigned char>& b, std::uint64_t file_size,
                    const std::string& path, Header& h) {
  h.offset_to_points = u32(b.data() + 96);
  h.vlr_count = u32(b.data() + 100);
  if (h.offset_to_points < h.header_size || h.offset_to_points > file_size)
    fail(path, "offset to the point data " + str(h.offset_to_points) + " lies outside bytes " +
                   str(h.header_size) + ".." + str(file_size) + ", " + kDamaged);

  const std::uint64_t legacy_count = u32(b.data() + 107);
  h.count = legacy_count;
  if (h.minor >= 4) {
    h.evlr_start = u64(b.data() + 235);
    h.evlr_count = u32(b.data() + 243);
    const std::uint64_t count64 = u64(b.data() + 247);
    if (legacy_count == 0 || h.format >= 6) h.count = count64;
  }
  if (h.count == 0)
    fail(path, "contains no points (point count 0 in the header), give a file with points");
  const std::uint64_t room = (file_size - h.offset_to_points) / h.record_length;
  if (h.count > room)
    fail(path, "header says " + str(h.count) + " points of " + str(h.record_length) +
                   " bytes from byte " + str(h.offset_to_points) + ", but the file (" +
                   str(file_size) + " bytes) has room for " + str(room) +
                   ": it is truncated or its header is damaged; re-export or re-download it");
  if (h.count > kMaxPoints)
    fail(path, str(h.count) +
                   " points are more than this reader takes (2^31), split the file first, e.g. "
                   "`pdal split --capacity 100000000 x.las part.las` or `lastile`");
}

/// Scale, offset and bounds of each axis (bytes 131–226): finite, scales non-zero.
void readAxes(const std::vector<unsigned char>& b, const std::string& path, Header& h) {
  const char* axis[3] = {"x", "y", "z"};
  for (std::size_t k = 0; k < 3; ++k) {
    h.scale[k] = f64(b.data() + 131 + 8 * k);
    h.offset[k] = f64(b.data() + 155 + 8 * k);
    h.max[k] = f64(b.data() + 179 + 16 * k);
    h.min[k] = f64(b.data() + 187 + 16 * k);
    if (!std::isfinite(h.scale[k]) || h.scale[k] == 0.0)
      fail(path, std::string(axis[k]) + " scale factor " + str(h.scale[k]) +
                     " must be finite and non-zero, " + kDamaged);
    if (!std::isfinite(h.offset[k]))
      fail(path,
           std::string(axis[k]) + " offset " + str(h.offset[k]) + " must be finite, " + kDamaged);
  }
}

/// One read and one named check per field of the LAS 1.0–1.4 public header block, in
/// file order.
Header readHeader(LasFile& file, const std::string& path) {
  if (file.size() < 4) fail(path, "not a LAS file (no \"LASF\" signature), give a .las file");
  const std::size_t first =
      static_cast<std::size_t>(std::min<std::uint64_t>(file.size(), kHeaderSize14));
  const std::vector<unsigned char> b = file.readAt(0, first);
  if (std::memcmp(b.data(), "LASF", 4) != 0)
    fail(path, "not a LAS file (no \"LASF\" signature), give a .las file");
  if (first < kHeaderSize12)
    fail(path, "file is " + str(file.size()) + " bytes, shorter than a LAS header (227 bytes), " +
                   kDamaged);

  Header h;
  readVersion(b, file.size(), path, h);
  readPointFormat(b, path, h);
  readPointCount(b, file.size(), path, h);
  readAxes(b, path, h);
  return h;
}

/// Payloads of the LASF_Projection records (VLRs and EVLRs); the first of each kind wins.
struct Projection {
  std::optional<std::string> wkt;                  // record 2112
  std::optional<std::vector<std::uint16_t>> keys;  // record 34735 GeoKeyDirectoryTag
  std::vector<double> doubles;                     // record 34736 GeoDoubleParamsTag
};

/// The header of a VLR (54 bytes) or EVLR (60 bytes): reserved u16, user ID char[16],
/// record ID u16, record length after the header (u16 VLR, u64 EVLR), description char[32].
struct RecordHeader {
  std::string user;  // up to the first null
  std::uint16_t record_id{0};
  std::uint64_t length{0};  // [bytes] after the header
};

RecordHeader parseRecordHeader(const std::vector<unsigned char>& v, bool extended) {
  const auto user_begin = v.begin() + 2;
  const auto user_end = std::find(user_begin, user_begin + 16, '\0');
  return {std::string(user_begin, user_end), u16(v.data() + 18),
          extended ? u64(v.data() + 20) : std::uint64_t{u16(v.data() + 20)}};
}

void keepRecord(Projection& proj, const RecordHeader& r, std::uint64_t payload_at, LasFile& file,
                const std::string& path) {
  const std::uint16_t record_id = r.record_id;
  const std::uint64_t length = r.length;
  if (r.user != "LASF_Projection") return;
  if (record_id != 2112 && record_id != 34735 && record_id != kTagGeoDoubleParams) return;
  if (length > kMaxProjectionRecord)
    fail(path, "LASF_Projection record " + str(record_id) + " is " + str(length) + " bytes long, " +
                   kDamaged);
  const std::vector<unsigned char> p = file.readAt(payload_at, static_cast<std::size_t>(length));
  if (record_id == 2112 && !proj.wkt) {
    const auto end = std::find(p.begin(), p.end(), '\0');  // null-terminated, maybe padded
    proj.wkt = std::string(p.begin(), end);
  } else if (record_id == 34735 && !proj.keys) {
    std::vector<std::uint16_t> keys(p.size() / 2);
    for (std::size_t i = 0; i < keys.size(); ++i) keys[i] = u16(p.data() + 2 * i);
    proj.keys = std::move(keys);
  } else if (record_id == kTagGeoDoubleParams && proj.doubles.empty()) {
    for (std::size_t i = 0; i + 8 <= p.size(); i += 8) proj.doubles.push_back(f64(p.data() + i));
  }
}

Projection readProjection(LasFile& file, const Header& h, const std::string& path) {
  Projection proj;
  std::uint64_t pos = h.header_size;
  for (std::uint32_t i = 0; i < h.vlr_count; ++i) {
    if (pos + kVlrHeaderSize > h.offset_to_points)
      fail(path, "VLR " + str(i + 1) + " of " + str(h.vlr_count) +
                     " runs into the point data at byte " + str(h.offset_to_points) + ", " +
                     kDamaged);
    const RecordHeader r = parseRecordHeader(file.readAt(pos, kVlrHeaderSize), false);
    const std::uint64_t length = r.length;
    if (pos + kVlrHeaderSize + length > h.offset_to_points)
      fail(path, "VLR " + str(i + 1) + " of " + str(h.vlr_count) + " (" + str(length) +
                     " bytes) runs into the point data at byte " + str(h.offset_to_points) + ", " +
                     kDamaged);
    keepRecord(proj, r, pos + kVlrHeaderSize, file, path);
    pos += kVlrHeaderSize + length;
  }
  if (h.evlr_count == 0 || h.evlr_start == 0) return proj;
  pos = h.evlr_start;
  for (std::uint32_t i = 0; i < h.evlr_count; ++i) {
    if (pos < h.header_size || pos > file.size() || file.size() - pos < kEvlrHeaderSize)
      fail(path, "EVLR " + str(i + 1) + " of " + str(h.evlr_count) + " at byte " + str(pos) +
                     " lies outside the file (" + str(file.size()) + " bytes), " + kDamaged);
    const RecordHeader r = parseRecordHeader(file.readAt(pos, kEvlrHeaderSize), true);
    const std::uint64_t length = r.length;
    if (length > file.size() - pos - kEvlrHeaderSize)
      fail(path, "EVLR " + str(i + 1) + " of " + str(h.evlr_count) + " (" + str(length) +
                     " bytes) runs past the end of the file, " + kDamaged);
    keepRecord(proj, r, pos + kEvlrHeaderSize, file, path);
    pos += kEvlrHeaderSize + length;
  }
  return proj;
}

/// A linear unit.
struct Unit {
  double to_m{1.0};  // [m per unit]
  std::string name{"metre"};
};

/// Snaps the three common units to their exact factors and names; others keep `name`.
Unit namedUnit(double factor, const std::string& name) {
  const auto near = [factor](double ref) { return std::abs(factor - ref) <= 1e-9 * ref; };
  if (near(1.0)) return {1.0, "metre"};
  if (near(kInternationalFoot)) return {kInternationalFoot, "international foot"};
  if (near(kUsSurveyFoot)) return {kUsSurveyFoot, "US survey foot"};
  return {factor, name};
}

/// One WKT node KEYWORD[values and children, in order] (OGC 01-009 WKT1 and ISO 19162 WKT2).
struct WktNode {
  std::string keyword;              // upper case
  std::vector<std::string> values;  // quoted strings (unquoted) and bare tokens
  std::vector<WktNode> children;
};

/// Recursive-descent parser of one WKT string; errors throw InputError naming the file.
class WktParser {
 public:
  WktParser(const std::string& text, const std::string& path) : s_(text), path_(path) {}

  WktNode parse() {
    skipSpace();
    WktNode root = node(0);
    skipSpace();
    if (i_ != s_.size()) error("text after the closing bracket");
    return root;
  }

 private:
  [[noreturn]] void error(const std::string& what) const {
    fail(path_,
         "WKT (LASF_Projection record 2112) is malformed at character " + str(i_) + " (" + what +
             "), fix its CRS, e.g. `pdal translate x.las y.las --writers.las.a_srs=EPSG:<code>`");
  }
  bool atEnd() const { return i_ >= s_.size(); }
  void skipSpace() {
    while (!atEnd() && std::isspace(static_cast<unsigned char>(s_[i_]))) ++i_;
  }
  static bool isDelimiter(char c) {
    return c == ',' || c == '[' || c == ']' || c == '(' || c == ')' || c == '"' ||
           std::isspace(static_cast<unsigned char>(c));
  }
  std::string quoted() {
    std::string out;
    ++i_;  // opening quote
    while (!atEnd()) {
      if (s_[i_] == '"') {
        if (i_ + 1 < s_.size() && s_[i_ + 1] == '"') {  // "" is an escaped quote
          out += '"';
          i_ += 2;
          continue;
        }
        ++i_;
        return out;
      }
      out += s_[i_++];
    }
    error("unterminated string");
  }
  WktNode node(int depth) {
    if (depth > kMaxWktDepth) error("nested deeper than " + str(kMaxWktDepth) + " levels");
    WktNode n;
    while (!atEnd() && (std::isalnum(static_cast<unsigned char>(s_[i_])) || s_[i_] == '_'))
      n.keyword += static_cast<char>(std::toupper(static_cast<unsigned char>(s_[i_++])));
    if (n.keyword.empty()) error("keyword expected");
    skipSpace();
    if (atEnd() || (s_[i_] != '[' && s_[i_] != '(')) error("'[' expected after " + n.keyword);
    const char close = s_[i_] == '[' ? ']' : ')';
    ++i_;
    for (;;) {
      skipSpace();
      if (atEnd()) error("unterminated " + n.keyword);
      if (s_[i_] == '"') {
        n.values.push_back(quoted());
      } else {
        const std::size_t begin = i_;
        while (!atEnd() && !isDelimiter(s_[i_])) ++i_;
        const std::size_t token_end = i_;
        skipSpace();
        if (!atEnd() && (s_[i_] == '[' || s_[i_] == '(')) {
          i_ = begin;
          n.children.push_back(node(depth + 1));
        } else {
          if (token_end == begin) error("value expected in " + n.keyword);
          n.values.push_back(s_.substr(begin, token_end - begin));
        }
      }
      skipSpace();
      if (atEnd()) error("unterminated " + n.keyword);
      if (s_[i_] == ',') {
        ++i_;
      } else if (s_[i_] == close) {
        ++i_;
        return n;
      } else {
        error("',' or closing bracket expected in " + n.keyword);
      }
    }
  }

  const std::string& s_;
  const std::string& path_;
  std::size_t i_{0};
};

bool isOneOf(const std::string& keyword, std::initializer_list<const char*> names) {
  return std::any_of(names.begin(), names.end(), [&](const char* n) { return keyword == n; });
}

/// The linear unit of a CRS node: the last UNIT / LENGTHUNIT among its direct children
/// or its AXIS children (WKT2 puts it there); nested ones (GEOGCS, PARAMETER) are not it.
std::optional<Unit> crsUnit(const WktNode& crs, const std::string& path) {
  const WktNode* last = nullptr;
  const auto isUnit = [](const WktNode& n) { return isOneOf(n.keyword, {"UNIT", "LENGTHUNIT"}); };
  for (const WktNode& c : crs.children) {
    if (isUnit(c)) last = &c;
    if (c.keyword == "AXIS")
      for (const WktNode& a : c.children)
        if (isUnit(a)) last = &a;
  }
  if (last == nullptr) return std::nullopt;
  const std::string name = last->values.empty() ? "" : last->values[0];
  const std::string factor_text = last->values.size() < 2 ? "" : last->values[1];
  char* end = nullptr;
  const double factor = std::strtod(factor_text.c_str(), &end);
  if (factor_text.empty() || *end != '\0' || !std::isfinite(factor) || factor <= 0.0)
    fail(path,
         "WKT " + crs.keyword + " unit \"" + name + "\" has no valid factor to metres (\"" +
             factor_text +
             "\"), fix its CRS, e.g. `pdal translate x.las y.las --writers.las.a_srs=EPSG:<code>`");
  return namedUnit(factor, name);
}

struct WktUnits {
  std::optional<Unit> horizontal;
  std::optional<Unit> vertical;
};

/// Units of a WKT (a projected CRS, possibly in a compound or bound CRS with a vertical CRS).
WktUnits wktUnits(const std::string& wkt, const std::string& path) {
  WktUnits units;
  if (wkt.find_first_not_of(" \t\r\n") == std::string::npos) return units;  // empty record
  const WktNode root = WktParser(wkt, path).parse();
  std::vector<const WktNode*> todo{&root};
  while (!todo.empty()) {
    const WktNode* n = todo.back();
    todo.pop_back();
    const std::string& k = n->keyword;
    if (isOneOf(k, {"COMPD_CS", "COMPOUNDCRS", "BOUNDCRS", "SOURCECRS"})) {
      for (auto it = n->children.rbegin(); it != n->children.rend(); ++it) todo.push_back(&*it);
    } else if (isOneOf(k, {"PROJCS", "PROJCRS", "PROJECTEDCRS", "LOCAL_CS", "ENGCRS",
                           "ENGINEERINGCRS"})) {
      if (!units.horizontal) units.horizontal = crsUnit(*n, path);
    } else if (isOneOf(k, {"GEOGCS", "GEOGCRS", "GEOGRAPHICCRS", "GEODCRS", "GEODETICCRS"})) {
      fail(path, "its WKT gives a geographic CRS (" + k + ", longitude/latitude in degrees), " +
                     kReproject);
    } else if (isOneOf(k, {"VERT_CS", "VERTCRS", "VERTICALCRS"})) {
      if (!units.vertical) units.vertical = crsUnit(*n, path);
    }
  }
  return units;
}

/// GeoTIFF keys with an inline SHORT value or a value in GeoDoubleParams.
struct GeoKeys {
  std::map<std::uint16_t, std::uint16_t> shorts;
  std::map<std::uint16_t, double> doubles;
};

GeoKeys parseGeoKeys(const std::vector<std::uint16_t>& dir, const std::vector<double>& doubles,
                     const std::string& path) {
  GeoKeys keys;
  if (dir.size() < 4)
    fail(path,
         "GeoKeyDirectory (LASF_Projection record 34735) is shorter than its 8-byte header, " +
             std::string(kDamaged));
  const std::size_t n = dir[3];
  if (4 + 4 * n > dir.size())
    fail(path, "GeoKeyDirectory (LASF_Projection record 34735) lists " + str(n) +
                   " keys but holds " + str((dir.size() - 4) / 4) + ", " + kDamaged);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint16_t* e = dir.data() + 4 + 4 * i;  // {key, tiff_tag_location, count, value}
    if (e[1] == 0)
      keys.shorts[e[0]] = e[3];
    else if (e[1] == kTagGeoDoubleParams && e[3] < doubles.size())
      keys.doubles[e[0]] = doubles[e[3]];
  }
  return keys;
}

/// EPSG linear unit codes used by GeoTIFF keys 3076 and 4099.
std::optional<Unit> epsgUnit(std::uint16_t code) {
  switch (code) {
    case 9001:
      return Unit{1.0, "metre"};
    case 9002:
      return Unit{kInternationalFoot, "international foot"};
    case 9003:
      return Unit{kUsSurveyFoot, "US survey foot"};
    default:
      return std::nullopt;
  }
}

[[noreturn]] void unknownUnitCode(const std::string& path, std::uint16_t key, const char* key_name,
                                  std::uint16_t code) {
  fail(path,
       "GeoTIFF key " + str(key) + " (" + key_name + ") = " + str(code) +
           " is a unit this reader does not know (9001 metre, 9002 international foot, 9003 US "
           "survey foot), " +
           kReproject);
}

/// The file's CRS as PROJ reads it: the WKT of record 2112, else "EPSG:P" from
/// ProjectedCSTypeGeoKey 3072, with "+V" from VerticalCSTypeGeoKey 4096.
void resolveCrs(const Projection& proj, const std::string& path, LasCloud& cloud) {
  if (proj.wkt && proj.wkt->find_first_not_of(" \t\r\n") != std::string::npos) {
    cloud.crs = *proj.wkt;
    while (!cloud.crs.empty() && (cloud.crs.back() == '\0' ||
                                  std::isspace(static_cast<unsigned char>(cloud.crs.back())) != 0))
      cloud.crs.pop_back();
    cloud.crs_source = "LAS WKT record 2112";
    return;
  }
  if (!proj.keys) return;
  const GeoKeys keys = parseGeoKeys(*proj.keys, proj.doubles, path);
  const auto it = keys.shorts.find(kKeyProjectedCsType);
  if (it == keys.shorts.end() || it->second == kUserDefined || it->second == 0) return;
  cloud.crs = "EPSG:" + str(it->second);
  cloud.crs_source = "LAS GeoTIFF key 3072 (ProjectedCSTypeGeoKey)";
  const auto v = keys.shorts.find(kKeyVerticalCsType);
  if (v != keys.shorts.end() && v->second != kUserDefined && v->second != 0) {
    cloud.crs += "+" + str(v->second);
    cloud.crs_source += " and 4096 (VerticalCSTypeGeoKey)";
  }
}

/// Fills the unit fields of `cloud` from the projection records (order in las_reader.h).
void resolveUnits(const Projection& proj, const std::string& path, LasCloud& cloud) {
  const std::string kNone = "none in file (metres assumed)";
  WktUnits wkt;
  if (proj.wkt) wkt = wktUnits(*proj.wkt, path);

  std::optional<Unit> geo_h;
  std::optional<Unit> geo_v;
  std::string geo_h_source = "GeoTIFF key 3076 (ProjLinearUnitsGeoKey)";
  std::string note;
  if (proj.keys && !wkt.horizontal) {
    const GeoKeys keys = parseGeoKeys(*proj.keys, proj.doubles, path);
    const auto shortKey = [&](std::uint16_t key) -> std::optional<std::uint16_t> {
      const auto it = keys.shorts.find(key);
      if (it == keys.shorts.end()) return std::nullopt;
      return it->second;
    };
    if (const auto code = shortKey(kKeyProjLinearUnits)) {
      geo_h = epsgUnit(*code);
      if (!geo_h && *code == kUserDefined && keys.doubles.count(kKeyProjLinearUnitSize) != 0) {
        const double size = keys.doubles.at(kKeyProjLinearUnitSize);
        if (!std::isfinite(size) || size <= 0.0)
          fail(path, "GeoTIFF key 3077 (ProjLinearUnitSizeGeoKey) = " + str(size) +
                         " is not a unit size, " + kReproject);
        geo_h = namedUnit(size, "user-defined unit");
        geo_h_source = "GeoTIFF keys 3076/3077 (user-defined unit size)";
      }
      if (!geo_h) unknownUnitCode(path, kKeyProjLinearUnits, "ProjLinearUnitsGeoKey", *code);
    } else if (shortKey(kKeyModelType) == kModelTypeGeographic) {
      fail(path, std::string("its GeoTIFF keys give a geographic CRS (GTModelTypeGeoKey 1024 = 2, "
                             "longitude/latitude in degrees), ") +
                     kReproject);
    } else if (const auto pcs = shortKey(kKeyProjectedCsType); pcs && *pcs != kUserDefined) {
      note = "; ProjectedCSTypeGeoKey 3072 = EPSG:" + str(*pcs) +
             " implies a unit that was not resolved";
    }
    if (const auto code = shortKey(kKeyVerticalUnits)) {
      geo_v = epsgUnit(*code);
      if (!geo_v) unknownUnitCode(path, kKeyVerticalUnits, "VerticalUnitsGeoKey", *code);
    }
  }

  Unit h;
  if (wkt.horizontal) {
    h = *wkt.horizontal;
    cloud.unit_source = "WKT";
  } else if (geo_h) {
    h = *geo_h;
    cloud.unit_source = geo_h_source;
  } else {
    cloud.unit_source = kNone + note;
  }
  Unit v = h;
  if (wkt.vertical) {
    v = *wkt.vertical;
    cloud.z_unit_source = "WKT VERT_CS";
  } else if (wkt.horizontal) {
    cloud.z_unit_source = "horizontal unit";
  } else if (geo_v) {
    v = *geo_v;
    cloud.z_unit_source = "GeoTIFF key 4099 (VerticalUnitsGeoKey)";
  } else {
    cloud.z_unit_source = geo_h ? "horizontal unit" : kNone;
  }
  cloud.unit_to_m = h.to_m;
  cloud.unit_name = h.name;
  cloud.z_unit_to_m = v.to_m;
  cloud.z_unit_name = v.name;
  resolveCrs(proj, path, cloud);
}

/// Reads the point block in chunks of whole records and hands each chunk's kept points
/// (metres, minus `origin`) and their classes to `sink`; counts the dropped ones.
void readPoints(LasFile& file, const Header& h, const LasOptions& options, const Vec3& origin,
                LasCloud& cloud, const LasChunkSink& sink) {
  std::array<bool, 256> drop{};
  for (const int c : options.drop_classes) drop[static_cast<std::size_t>(c)] = true;
  const bool extended = h.format >= 6;
  const std::size_t len = h.record_length;
  const std::size_t chunk = std::max<std::size_t>(1, kChunkBytes / len);
  // h.count ≤ kMaxPoints and fits in the file (readHeader), so reserving it is safe.
  const auto count = static_cast<std::size_t>(h.count);
  std::vector<unsigned char> buffer(std::min(chunk, count) * len);
  PointList points;
  std::vector<std::uint8_t> classes;
  points.reserve(std::min(chunk, count));
  classes.reserve(std::min(chunk, count));
  const double sx = h.scale[0], sy = h.scale[1], sz = h.scale[2];
  const double ox = h.offset[0], oy = h.offset[1], oz = h.offset[2];
  const double hu = cloud.unit_to_m, vu = cloud.z_unit_to_m;

  file.seek(h.offset_to_points);
  for (std::size_t done = 0; done < count;) {
    const std::size_t n = std::min(chunk, count - done);
    file.read(buffer.data(), n * len);
    points.clear();
    classes.clear();
    for (std::size_t i = 0; i < n; ++i) {
      const unsigned char* r = buffer.data() + i * len;
      const std::uint8_t cls = extended ? r[16] : static_cast<std::uint8_t>(r[15] & 0x1Fu);
      if (drop[cls]) {
        ++cloud.dropped;
        continue;
      }
      points.emplace_back((i32(r) * sx + ox) * hu - origin.x(),
                          (i32(r + 4) * sy + oy) * hu - origin.y(),
                          (i32(r + 8) * sz + oz) * vu - origin.z());
      classes.push_back(cls);
    }
    if (!points.empty()) sink(points, classes);
    done += n;
  }
}

}  // namespace

void LasOptions::validate(const std::string& where) const {
  for (const int c : drop_classes)
    if (c < 0 || c > 255)
      throw InputError(where + ": drop_classes contains " + std::to_string(c) +
                       ", ASPRS classes are 0..255");
}

bool isLasPath(const std::string& path) { return endsWith(lower(path), ".las"); }

LasCloud streamLas(const std::string& path, const LasOptions& options, const LasChunkSink& sink,
                   const std::function<void(const LasCloud&)>& on_header) {
  options.validate(path);
  if (endsWith(lower(path), ".laz"))
    fail(path, "LAZ (LASzip-compressed) files are not read, " + std::string(kDecompress));
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (status.type() == fs::file_type::not_found) fail(path, "no such file, check the path");
  if (ec)
    fail(path, "cannot access the file (" + ec.message() + "), check the path and permissions");
  if (!fs::is_regular_file(status))
    fail(path, "not a regular file (a directory or a device), give a .las file");
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec)
    fail(path, "cannot read the file size (" + ec.message() + "), check the path and permissions");

  LasFile file(path, size);
  const Header h = readHeader(file, path);
  LasCloud cloud;
  cloud.version_major = h.major;
  cloud.version_minor = h.minor;
  cloud.point_format = h.format;
  cloud.point_record_length = static_cast<int>(h.record_length);
  cloud.points_in_file = h.count;
  resolveUnits(readProjection(file, h, path), path, cloud);

  // Origin: centre of the header bounds in metres, rounded (io::recentringOrigin, the
  // rule of every reader); the points' own bounds (one pass more) if the header's are
  // unusable.
  const bool header_bounds = std::isfinite(h.min[0]) && std::isfinite(h.max[0]) &&
                             std::isfinite(h.min[1]) && std::isfinite(h.max[1]) &&
                             h.min[0] <= h.max[0] && h.min[1] <= h.max[1];
  if (header_bounds) {
    const bool z_bounds = std::isfinite(h.min[2]) && std::isfinite(h.max[2]);  // else z is kept
    const Vec3 lo(h.min[0] * cloud.unit_to_m, h.min[1] * cloud.unit_to_m,
                  z_bounds ? h.min[2] * cloud.z_unit_to_m : 0.0);
    const Vec3 hi(h.max[0] * cloud.unit_to_m, h.max[1] * cloud.unit_to_m,
                  z_bounds ? h.max[2] * cloud.z_unit_to_m : 0.0);
    cloud.origin_m = recentringOrigin(lo, hi);
  } else {
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    LasCloud counted = cloud;
    readPoints(file, h, options, Vec3::Zero(), counted,
               [&](const PointList& points, const std::vector<std::uint8_t>&) {
                 for (const Vec3& p : points) {
                   lo = lo.cwiseMin(p);
                   hi = hi.cwiseMax(p);
                 }
               });
    if (lo.allFinite()) cloud.origin_m = recentringOrigin(lo, hi);
  }
  if (on_header) on_header(cloud);
  readPoints(file, h, options, cloud.origin_m, cloud, sink);
  return cloud;
}

LasCloud readLas(const std::string& path, const LasOptions& options) {
  PointList points;
  std::vector<std::uint8_t> classes;
  const auto reserve = [&](const LasCloud& header) {
    // points_in_file ≤ 2^31 and fits in the file (readHeader): reserving it is safe.
    points.reserve(static_cast<std::size_t>(header.points_in_file));
    classes.reserve(static_cast<std::size_t>(header.points_in_file));
  };
  LasCloud cloud = streamLas(
      path, options,
      [&](const PointList& chunk, const std::vector<std::uint8_t>& cls) {
        points.insert(points.end(), chunk.begin(), chunk.end());
        classes.insert(classes.end(), cls.begin(), cls.end());
      },
      reserve);
  cloud.points = std::move(points);
  cloud.classification = std::move(classes);
  return cloud;
}

}  // namespace uavip::io
