#include "uavip/io/las_reader.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "uavip/core/error.h"
#include "uavip/io/cloud_io.h"
#include "uavip/io/geodesy.h"

#ifndef UAVIP_SOURCE_DIR
#define UAVIP_SOURCE_DIR "."  // standalone build from the repository root
#endif

namespace uavip::io {
namespace {

namespace fs = std::filesystem;

constexpr double kFoot = 0.3048;
constexpr double kUsFoot = 1200.0 / 3937.0;
constexpr std::array<int, 11> kRecordLength{20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};

// ---------------------------------------------------------------------------------------
// A tiny LAS writer, written from the ASPRS LAS 1.4 R15 tables independently of the reader.

struct TestPoint {
  std::int32_t x{0}, y{0}, z{0};  // stored integers
  std::uint8_t cls{0};            // ASPRS class
};

struct Record {  // a VLR or EVLR
  std::string user{"LASF_Projection"};
  std::uint16_t id{0};
  std::string data;
};

struct LasSpec {
  int minor{2};
  int format{0};
  int extra_bytes{0};  // per point, after the format's fields
  std::array<double, 3> scale{0.01, 0.01, 0.01};
  std::array<double, 3> offset{0.0, 0.0, 0.0};
  std::vector<TestPoint> points;
  std::vector<Record> vlrs;
  std::vector<Record> evlrs;           // LAS 1.4 only
  std::optional<int> header_size;      // override
  std::optional<int> format_byte;      // override of byte 104
  std::optional<int> record_length;    // override
  std::optional<std::uint64_t> count;  // override of the point count (legacy and 64-bit)
  bool write_legacy_count{true};       // LAS 1.4 formats 0-5: also fill the 32-bit count
  std::optional<std::array<double, 3>> scale_raw;  // written instead of scale (for bad values)
};

void putU(std::string& b, std::size_t at, std::uint64_t v, int bytes) {
  for (int i = 0; i < bytes; ++i)
    b[at + static_cast<std::size_t>(i)] = static_cast<char>((v >> (8 * i)) & 0xFFu);
}
void putD(std::string& b, std::size_t at, double d) {
  std::uint64_t u = 0;
  std::memcpy(&u, &d, sizeof u);
  putU(b, at, u, 8);
}
void putI32(std::string& b, std::size_t at, std::int32_t v) {
  putU(b, at, static_cast<std::uint32_t>(v), 4);
}

std::string recordHeader(const Record& r, bool extended) {
  std::string h(extended ? 60 : 54, '\0');
  std::memcpy(&h[2], r.user.data(), std::min<std::size_t>(16, r.user.size()));
  putU(h, 18, r.id, 2);
  putU(h, 20, r.data.size(), extended ? 8 : 2);
  return h + r.data;
}

double coord(const LasSpec& s, const TestPoint& p, int k) {
  const std::int32_t v = k == 0 ? p.x : k == 1 ? p.y : p.z;
  return v * s.scale[static_cast<std::size_t>(k)] + s.offset[static_cast<std::size_t>(k)];
}

std::string lasBytes(const LasSpec& s) {
  const int header_size = s.minor <= 2 ? 227 : s.minor == 3 ? 235 : 375;
  std::string vlr_block;
  for (const Record& r : s.vlrs) vlr_block += recordHeader(r, false);
  const int record_length =
      s.record_length.value_or(kRecordLength[static_cast<std::size_t>(s.format)] + s.extra_bytes);
  const std::uint64_t count = s.count.value_or(s.points.size());

  std::string h(static_cast<std::size_t>(header_size), '\0');
  std::memcpy(&h[0], "LASF", 4);
  h[24] = 1;
  h[25] = static_cast<char>(s.minor);
  putU(h, 94, static_cast<std::uint64_t>(s.header_size.value_or(header_size)), 2);
  const std::uint64_t offset_to_points = static_cast<std::uint64_t>(header_size) + vlr_block.size();
  putU(h, 96, offset_to_points, 4);
  putU(h, 100, s.vlrs.size(), 4);
  h[104] = static_cast<char>(s.format_byte.value_or(s.format));
  putU(h, 105, static_cast<std::uint64_t>(record_length), 2);
  const bool legacy = s.minor < 4 || (s.format < 6 && s.write_legacy_count);
  if (legacy) putU(h, 107, std::min<std::uint64_t>(count, 0xFFFFFFFFu), 4);
  for (std::size_t k = 0; k < 3; ++k) {
    putD(h, 131 + 8 * k, s.scale_raw ? (*s.scale_raw)[k] : s.scale[k]);
    putD(h, 155 + 8 * k, s.offset[k]);
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const TestPoint& p : s.points) {
      lo = std::min(lo, coord(s, p, static_cast<int>(k)));
      hi = std::max(hi, coord(s, p, static_cast<int>(k)));
    }
    if (s.points.empty()) lo = hi = 0.0;
    putD(h, 179 + 16 * k, hi);
    putD(h, 187 + 16 * k, lo);
  }

  std::string pts;
  for (const TestPoint& p : s.points) {
    std::string r(static_cast<std::size_t>(record_length), '\x5A');  // filler in the unused fields
    putI32(r, 0, p.x);
    putI32(r, 4, p.y);
    putI32(r, 8, p.z);
    putU(r, 12, 1000, 2);  // intensity
    r[14] = 0x11;          // return 1 of 1
    if (s.format < 6) {
      r[15] = static_cast<char>(p.cls | 0xE0);  // synthetic, key-point, withheld flags set
    } else {
      r[15] =
          static_cast<char>(0xFF);  // classification flags, scanner channel, scan direction, edge
      r[16] = static_cast<char>(p.cls);
    }
    pts += r;
  }

  std::string evlr_block;
  for (const Record& r : s.evlrs) evlr_block += recordHeader(r, true);
  if (s.minor >= 4) {
    if (!s.evlrs.empty()) putU(h, 235, offset_to_points + pts.size(), 8);
    putU(h, 243, s.evlrs.size(), 4);
    putU(h, 247, count, 8);
  }
  return h + vlr_block + pts + evlr_block;
}

std::string geoKeys(const std::vector<std::array<std::uint16_t, 4>>& entries) {
  std::string b(8 + 8 * entries.size(), '\0');
  putU(b, 0, 1, 2);
  putU(b, 2, 1, 2);
  putU(b, 4, 0, 2);
  putU(b, 6, entries.size(), 2);
  for (std::size_t i = 0; i < entries.size(); ++i)
    for (std::size_t j = 0; j < 4; ++j) putU(b, 8 + 8 * i + 2 * j, entries[i][j], 2);
  return b;
}

std::string wktRecord(const std::string& wkt) { return wkt + std::string(1, '\0'); }

const std::string kWktUtmMetre =
    R"w(PROJCS["WGS 84 / UTM zone 32N",GEOGCS["WGS 84",DATUM["WGS_1984",SPHEROID["WGS 84",6378137,298.257223563,)w"
    R"w(AUTHORITY["EPSG","7030"]],AUTHORITY["EPSG","6326"]],PRIMEM["Greenwich",0],UNIT["degree",0.0174532925199433]],)w"
    R"w(PROJECTION["Transverse_Mercator"],PARAMETER["latitude_of_origin",0],PARAMETER["central_meridian",9],)w"
    R"w(PARAMETER["scale_factor",0.9996],PARAMETER["false_easting",500000],PARAMETER["false_northing",0],)w"
    R"w(UNIT["metre",1,AUTHORITY["EPSG","9001"]],AXIS["Easting",EAST],AXIS["Northing",NORTH],AUTHORITY["EPSG","32632"]])w";

std::vector<TestPoint> samplePoints(int format) {
  const std::uint8_t big = format >= 6 ? 200 : 31;  // 8-bit class field only in formats 6-10
  return {
      {1234567, -7654321, 98765, 2},
      {std::numeric_limits<std::int32_t>::min(), std::numeric_limits<std::int32_t>::max(), -5, big},
      {0, 0, 0, 0}};
}

/// Expected point [m]: (X × scale + offset) × unit − origin, origin from the header bounds.
Vec3 expected(const LasSpec& s, const TestPoint& p, double unit_xy, double unit_z) {
  std::array<double, 2> centre{};
  for (int k = 0; k < 2; ++k) {
    double lo = coord(s, s.points[0], k), hi = lo;
    for (const TestPoint& q : s.points) {
      lo = std::min(lo, coord(s, q, k));
      hi = std::max(hi, coord(s, q, k));
    }
    centre[static_cast<std::size_t>(k)] = std::round(0.5 * (lo + hi) * unit_xy);
  }
  return {coord(s, p, 0) * unit_xy - centre[0], coord(s, p, 1) * unit_xy - centre[1],
          coord(s, p, 2) * unit_z};
}

class LasReader : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("uavip_las_reader_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& bytes) const {
    std::string p = (dir_ / name).string();
    std::ofstream(p, std::ios::binary) << bytes;
    return p;
  }
  std::string write(const std::string& name, const LasSpec& spec) const {
    return write(name, lasBytes(spec));
  }

  /// Expects readLas to throw a one-line InputError naming the file and containing `fragment`.
  static void expectError(const std::string& path, const std::string& fragment,
                          const LasOptions& options = {}) {
    try {
      readLas(path, options);
      ADD_FAILURE() << "no error for " << path;
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(fragment), std::string::npos) << what;
      EXPECT_EQ(what.rfind(path + ": ", 0), 0u) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
  }

  fs::path dir_;
};

// ---------------------------------------------------------------------------------------

TEST_F(LasReader, EveryPointFormatReadsBackExactly) {
  const std::vector<std::pair<int, int>> cases{
      {0, 0}, {0, 1}, {1, 1}, {2, 0}, {2, 1}, {2, 2}, {2, 3}, {3, 4}, {3, 5}, {4, 0},
      {4, 1}, {4, 2}, {4, 3}, {4, 4}, {4, 5}, {4, 6}, {4, 7}, {4, 8}, {4, 9}, {4, 10}};
  for (const auto& [minor, format] : cases) {
    for (const int extra : {0, 3}) {
      SCOPED_TRACE("LAS 1." + std::to_string(minor) + " format " + std::to_string(format) +
                   " extra " + std::to_string(extra));
      LasSpec s;
      s.minor = minor;
      s.format = format;
      s.extra_bytes = extra;
      s.scale = {0.001, 0.0025, 0.01};
      s.offset = {500000.0, 5300000.0, -20.0};
      s.points = samplePoints(format);
      const LasCloud c = readLas(write("f.las", s));
      EXPECT_EQ(c.version_major, 1);
      EXPECT_EQ(c.version_minor, minor);
      EXPECT_EQ(c.point_format, format);
      EXPECT_EQ(c.point_record_length, kRecordLength[static_cast<std::size_t>(format)] + extra);
      EXPECT_EQ(c.points_in_file, s.points.size());
      EXPECT_EQ(c.dropped, 0u);
      EXPECT_EQ(c.unit_to_m, 1.0);
      EXPECT_EQ(c.unit_source, "none in file (metres assumed)");
      ASSERT_EQ(c.points.size(), s.points.size());
      ASSERT_EQ(c.classification.size(), s.points.size());
      for (std::size_t i = 0; i < s.points.size(); ++i) {
        const Vec3 e = expected(s, s.points[i], 1.0, 1.0);
        EXPECT_NEAR(c.points[i].x(), e.x(), 1e-9) << i;
        EXPECT_NEAR(c.points[i].y(), e.y(), 1e-9) << i;
        EXPECT_NEAR(c.points[i].z(), e.z(), 1e-9) << i;
        EXPECT_EQ(c.classification[i], s.points[i].cls) << i;
      }
      EXPECT_EQ(c.origin_m.z(), 0.0);
      EXPECT_EQ(c.origin_m.x(), std::round(c.origin_m.x()));
    }
  }
}

TEST_F(LasReader, Las14TakesTheSixtyFourBitCountWhenTheLegacyCountIsZero) {
  LasSpec s;
  s.minor = 4;
  s.format = 1;
  s.write_legacy_count = false;
  s.points = samplePoints(1);
  const LasCloud c = readLas(write("c.las", s));
  EXPECT_EQ(c.points_in_file, 3u);
  EXPECT_EQ(c.points.size(), 3u);
}

TEST_F(LasReader, GeoTiffUsSurveyFeet) {
  LasSpec s;
  s.points = samplePoints(0);
  s.offset = {2000000.0, 600000.0, 300.0};
  s.vlrs.push_back({"LASF_Projection", 34735,
                    geoKeys({{1024, 0, 1, 1}, {3072, 0, 1, 2285}, {3076, 0, 1, 9003}})});
  const LasCloud c = readLas(write("usft.las", s));
  EXPECT_DOUBLE_EQ(c.unit_to_m, kUsFoot);
  EXPECT_EQ(c.unit_name, "US survey foot");
  EXPECT_EQ(c.unit_source, "GeoTIFF key 3076 (ProjLinearUnitsGeoKey)");
  EXPECT_DOUBLE_EQ(c.z_unit_to_m, kUsFoot);
  EXPECT_EQ(c.z_unit_source, "horizontal unit");
  EXPECT_EQ(c.crs, "EPSG:2285");  // ProjectedCSTypeGeoKey, for export's CRS
  EXPECT_EQ(c.crs_source, "LAS GeoTIFF key 3072 (ProjectedCSTypeGeoKey)");
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    const Vec3 e = expected(s, s.points[i], kUsFoot, kUsFoot);
    EXPECT_NEAR((c.points[i] - e).norm(), 0.0, 1e-8) << i;
  }
}

TEST_F(LasReader, GeoTiffVerticalUnitAppliesToZOnly) {
  LasSpec s;
  s.points = samplePoints(0);
  s.vlrs.push_back({"LASF_Projection", 34735, geoKeys({{3076, 0, 1, 9001}, {4099, 0, 1, 9002}})});
  const LasCloud c = readLas(write("v.las", s));
  EXPECT_EQ(c.unit_to_m, 1.0);
  EXPECT_EQ(c.z_unit_to_m, kFoot);
  EXPECT_EQ(c.z_unit_name, "international foot");
  EXPECT_EQ(c.z_unit_source, "GeoTIFF key 4099 (VerticalUnitsGeoKey)");
  EXPECT_NEAR(c.points[0].z(), (98765 * 0.01) * kFoot, 1e-9);
}

TEST_F(LasReader, GeoTiffProjectedAndVerticalCrsKeysGiveACompoundCrs) {
  LasSpec s;
  s.points = samplePoints(0);
  s.vlrs.push_back({"LASF_Projection", 34735,
                    geoKeys({{1024, 0, 1, 1}, {3072, 0, 1, 32650}, {4096, 0, 1, 5773}})});
  const LasCloud c = readLas(write("compound.las", s));
  EXPECT_EQ(c.crs, "EPSG:32650+5773");
  EXPECT_NE(c.crs_source.find("4096"), std::string::npos) << c.crs_source;
  const CrsTransform t(c.crs);  // PROJ reads what the reader records
  EXPECT_EQ(t.verticalEpsg(), 5773);
  LasSpec none;
  none.points = samplePoints(0);
  EXPECT_EQ(readLas(write("nocrs.las", none)).crs, "");
}

TEST_F(LasReader, GeoTiffUserDefinedUnitSize) {
  LasSpec s;
  s.points = samplePoints(0);
  std::string doubles(16, '\0');
  putD(doubles, 0, 7.0);
  putD(doubles, 8, 0.5);  // index 1: half a metre per unit
  s.vlrs.push_back({"LASF_Projection", 34735, geoKeys({{3076, 0, 1, 32767}, {3077, 34736, 1, 1}})});
  s.vlrs.push_back({"LASF_Projection", 34736, doubles});
  const LasCloud c = readLas(write("user.las", s));
  EXPECT_EQ(c.unit_to_m, 0.5);
  EXPECT_EQ(c.unit_source, "GeoTIFF keys 3076/3077 (user-defined unit size)");
}

TEST_F(LasReader, UnknownGeoTiffUnitCodeIsRejected) {
  LasSpec s;
  s.points = samplePoints(0);
  s.vlrs.push_back({"LASF_Projection", 34735, geoKeys({{3076, 0, 1, 9036}})});
  expectError(write("km.las", s), "9036");
}

TEST_F(LasReader, WktInMetresIsPreferredOverGeoTiffKeys) {
  LasSpec s;
  s.points = samplePoints(0);
  s.vlrs.push_back(
      {"LASF_Projection", 34735, geoKeys({{3076, 0, 1, 9002}})});  // contradicts the WKT
  s.vlrs.push_back({"LASF_Projection", 2112, wktRecord(kWktUtmMetre)});
  const LasCloud c = readLas(write("wkt.las", s));
  EXPECT_EQ(c.unit_to_m, 1.0);
  EXPECT_EQ(c.unit_name, "metre");
  EXPECT_EQ(c.unit_source, "WKT");
  EXPECT_EQ(c.z_unit_to_m, 1.0);
  EXPECT_EQ(c.crs, kWktUtmMetre);  // the WKT wins over the keys for the CRS too
  EXPECT_EQ(c.crs_source, "LAS WKT record 2112");
  for (std::size_t i = 0; i < s.points.size(); ++i)
    EXPECT_NEAR((c.points[i] - expected(s, s.points[i], 1.0, 1.0)).norm(), 0.0, 1e-9) << i;
}

TEST_F(LasReader, WktCompoundCrsGivesTheVerticalUnit) {
  const std::string wkt =
      R"w(COMPD_CS["NAD83(2011) / Oregon North (ftUS) + NAVD88 height",)w"
      R"w(PROJCS["NAD83(2011) / Oregon North (ftUS)",GEOGCS["NAD83(2011)",DATUM["NAD83_National_Spatial_Reference_System_2011",)w"
      R"w(SPHEROID["GRS 1980",6378137,298.257222101]],PRIMEM["Greenwich",0],UNIT["degree",0.0174532925199433]],)w"
      R"w(PROJECTION["Lambert_Conformal_Conic_2SP"],PARAMETER["false_easting",8202083.333],)w"
      R"w(UNIT["US survey foot",0.304800609601219,AUTHORITY["EPSG","9003"]],AXIS["Easting",EAST],AXIS["Northing",NORTH]],)w"
      R"w(VERT_CS["NAVD88 height",VERT_DATUM["North American Vertical Datum 1988",2005],UNIT["metre",1],AXIS["Up",UP]]])w";
  LasSpec s;
  s.points = samplePoints(0);
  s.vlrs.push_back({"LASF_Projection", 2112, wktRecord(wkt)});
  const LasCloud c = readLas(write("compd.las", s));
  EXPECT_DOUBLE_EQ(c.unit_to_m, kUsFoot);
  EXPECT_EQ(c.unit_name, "US survey foot");
  EXPECT_EQ(c.z_unit_to_m, 1.0);
  EXPECT_EQ(c.z_unit_source, "WKT VERT_CS");
  EXPECT_NEAR(c.points[0].z(), 98765 * 0.01, 1e-9);
}

TEST_F(LasReader, Wkt2UnitIsTheAxisUnitNotAParameterUnit) {
  const std::string wkt =
      R"w(PROJCRS["local grid",BASEGEOGCRS["WGS 84",DATUM["World Geodetic System 1984",ELLIPSOID["WGS 84",6378137,)w"
      R"w(298.257223563,LENGTHUNIT["metre",1]]],PRIMEM["Greenwich",0,ANGLEUNIT["degree",0.0174532925199433]]],)w"
      R"w(CONVERSION["grid",METHOD["Transverse Mercator"],PARAMETER["False easting",500000,LENGTHUNIT["metre",1]]],)w"
      R"w(CS[Cartesian,2],AXIS["easting (X)",east,ORDER[1],LENGTHUNIT["foot",0.3048]],)w"
      R"w(AXIS["northing (Y)",north,ORDER[2],LENGTHUNIT["foot",0.3048]]])w";
  LasSpec s;
  s.minor = 4;
  s.format = 6;
  s.points = samplePoints(6);
  s.evlrs.push_back({"LASF_Projection", 2112, wktRecord(wkt)});  // LAS 1.4: the WKT may be an EVLR
  const LasCloud c = readLas(write("wkt2.las", s));
  EXPECT_EQ(c.unit_to_m, kFoot);
  EXPECT_EQ(c.unit_name, "international foot");
  EXPECT_EQ(c.unit_source, "WKT");
  EXPECT_EQ(c.z_unit_to_m, kFoot);
}

TEST_F(LasReader, GeographicCrsIsRejected) {
  LasSpec s;
  s.points = samplePoints(0);
  s.vlrs.push_back(
      {"LASF_Projection", 2112,
       wktRecord(R"w(GEOGCS["WGS 84",DATUM["WGS_1984",SPHEROID["WGS 84",6378137,298.257223563]],)w"
                 R"w(PRIMEM["Greenwich",0],UNIT["degree",0.0174532925199433]])w")});
  expectError(write("geo.las", s), "geographic");
  LasSpec k;
  k.points = samplePoints(0);
  k.vlrs.push_back({"LASF_Projection", 34735, geoKeys({{1024, 0, 1, 2}, {2048, 0, 1, 4326}})});
  expectError(write("geokeys.las", k), "geographic");
}

TEST_F(LasReader, MalformedWktIsRejected) {
  LasSpec s;
  s.points = samplePoints(0);
  s.vlrs.push_back({"LASF_Projection", 2112, wktRecord(R"w(PROJCS["x",UNIT["metre",1])w")});
  expectError(write("bad_wkt.las", s), "WKT");
}

TEST_F(LasReader, DropClasses) {
  LasSpec s;
  s.minor = 4;
  s.format = 6;
  s.points = {{0, 0, 0, 2}, {1, 1, 1, 5}, {2, 2, 2, 7}, {3, 3, 3, 2}, {4, 4, 4, 1}, {5, 5, 5, 200}};
  LasOptions o;
  o.drop_classes = {5, 7, 200};
  const LasCloud c = readLas(write("drop.las", s), o);
  EXPECT_EQ(c.points_in_file, 6u);
  EXPECT_EQ(c.dropped, 3u);
  EXPECT_EQ(c.classification, (std::vector<std::uint8_t>{2, 2, 1}));
  ASSERT_EQ(c.points.size(), 3u);
  EXPECT_NEAR(c.points[1].z(), 0.03, 1e-12);
  o.drop_classes = {300};
  expectError(write("drop.las", s), "drop_classes", o);
}

TEST_F(LasReader, LoadCloudDropsOnlyTheNoiseClassesByDefaultAndSaysSo) {
  LasSpec s;
  s.minor = 4;
  s.format = 6;
  s.points = {{0, 0, 0, 2}, {1, 1, 1, 7}, {2, 2, 2, 18}, {3, 3, 3, 1}, {4, 4, 4, 5}};
  const std::string file = write("noise.las", s);
  io::CloudReadInfo info;
  EXPECT_EQ(io::loadCloud(file, {}, &info).size(), 3u);  // 7 and 18 dropped; vegetation (5) kept
  EXPECT_NE(info.note.find("2 dropped: input.drop_classes 7 18, the classes LAS flags as noise"),
            std::string::npos)
      << info.note;
  io::CloudReadOptions keep;
  keep.drop_classes.clear();
  EXPECT_EQ(io::loadCloud(file, keep, &info).size(), 5u);
}

TEST_F(LasReader, WrongHeaderSizeIsRejected) {
  LasSpec s;
  s.points = samplePoints(0);
  s.header_size = 200;
  expectError(write("h12.las", s), "header size 200");
  LasSpec t;
  t.minor = 4;
  t.points = samplePoints(0);
  t.header_size = 227;  // a 1.2 header in a 1.4 file
  expectError(write("h14.las", t), "375");
}

TEST_F(LasReader, PointCountBeyondTheFileIsRejectedBeforeAllocating) {
  LasSpec s;
  s.points = samplePoints(3);
  s.format = 3;
  s.count = 4;  // one more than written
  expectError(write("short.las", s), "truncated");
  s.count = 0xFFFFFFFFu;
  expectError(write("huge32.las", s), "truncated");
  LasSpec t;
  t.minor = 4;
  t.format = 6;
  t.points = samplePoints(6);
  t.count = std::uint64_t{1} << 62;  // would be exabytes if allocated
  expectError(write("huge64.las", t), "truncated");
}

TEST_F(LasReader, CompressedFormatIsRejected) {
  LasSpec s;
  s.format = 3;
  s.points = samplePoints(3);
  s.format_byte = 3 | 0x80;
  expectError(write("laz_inside.las", s), "laszip");
  s.format_byte = 3 | 0x40;
  expectError(write("laz_bit6.las", s), "pdal translate");
}

TEST_F(LasReader, LazPathIsRejected) {
  expectError((dir_ / "x.laz").string(), "laszip");
  expectError((dir_ / "X.LAZ").string(), "laszip");
}

TEST_F(LasReader, ZeroPointsIsRejected) {
  LasSpec s;
  expectError(write("empty.las", s), "no points");
  s.minor = 4;
  s.format = 7;
  expectError(write("empty14.las", s), "no points");
}

TEST_F(LasReader, DamagedHeadersAreRejected) {
  LasSpec s;
  s.points = samplePoints(0);
  std::string bytes = lasBytes(s);
  bytes[0] = 'X';
  expectError(write("sig.las", bytes), "LASF");
  expectError(write("tiny.las", std::string("LASF")), "227");

  LasSpec f = s;
  f.format_byte = 11;
  f.record_length = 40;
  expectError(write("fmt.las", f), "unknown point data format 11");

  LasSpec r = s;
  r.format = 3;
  r.record_length = 28;
  expectError(write("len.las", r), "shorter than the 34 bytes");

  LasSpec z = s;
  z.scale_raw = std::array<double, 3>{0.01, 0.0, 0.01};
  expectError(write("scale0.las", z), "y scale factor");
  z.scale_raw = std::array<double, 3>{std::nan(""), 0.01, 0.01};
  expectError(write("scalenan.las", z), "x scale factor");

  LasSpec v = s;
  v.minor = 5;
  expectError(write("v15.las", v), "version 1.5");

  LasSpec vl = s;
  vl.vlrs.push_back({"LASF_Projection", 34735, geoKeys({{3076, 0, 1, 9001}})});
  bytes = lasBytes(vl);
  putU(bytes, 100, 2, 4);  // two VLRs claimed, one present
  expectError(write("vlr.las", bytes), "VLR 2 of 2");
}

TEST_F(LasReader, MissingFileAndDirectoryAreRejected) {
  expectError((dir_ / "missing.las").string(), "no such file");
  fs::create_directories(dir_ / "d.las");
  expectError((dir_ / "d.las").string(), "not a regular file");
}

TEST(LasPath, IsLasPathIgnoresCase) {
  EXPECT_TRUE(isLasPath("a/b/scan.las"));
  EXPECT_TRUE(isLasPath("SCAN.LAS"));
  EXPECT_TRUE(isLasPath("x.LaS"));
  EXPECT_FALSE(isLasPath("scan.laz"));
  EXPECT_FALSE(isLasPath("scan.pcd"));
  EXPECT_FALSE(isLasPath("las"));
  EXPECT_FALSE(isLasPath(""));
}

// Real data: PDAL's autzen_trim.las (tests/data/README.md). Reference values from the
// header bounds; class counts from a separate decode of the file (Python struct, 34-byte records).
TEST(LasAutzen, RealAirborneScanInInternationalFeet) {
  const LasCloud c = readLas(std::string(UAVIP_SOURCE_DIR) + "/tests/data/autzen_trim.las");
  EXPECT_EQ(c.version_major, 1);
  EXPECT_EQ(c.version_minor, 2);
  EXPECT_EQ(c.point_format, 3);
  EXPECT_EQ(c.points_in_file, 110000u);
  ASSERT_EQ(c.points.size(), 110000u);
  EXPECT_EQ(c.unit_name, "international foot");
  EXPECT_EQ(c.unit_to_m, kFoot);
  EXPECT_EQ(c.unit_source, "WKT");
  EXPECT_EQ(c.z_unit_to_m, kFoot);

  std::map<int, std::size_t> classes;
  for (const std::uint8_t k : c.classification) ++classes[k];
  EXPECT_EQ(classes, (std::map<int, std::size_t>{{1, 83893}, {2, 26107}}));

  Vec3 lo = c.points.front(), hi = c.points.front();
  for (const Vec3& p : c.points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const Vec3 extent_ft(637179.22 - 636001.76, 849497.90 - 848935.20,
                       520.51 - 406.26);  // header bounds
  const Vec3 extent_m = hi - lo;
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(extent_m[k], extent_ft[k] * kFoot, 0.01 * extent_ft[k] * kFoot) << k;
  EXPECT_NEAR(extent_m.x(), 359.0, 1.0);
  EXPECT_NEAR(extent_m.y(), 172.0, 1.0);
  EXPECT_NEAR(extent_m.z(), 35.0, 1.0);
  // Recentred on whole metres; elevations kept.
  EXPECT_EQ(c.origin_m, Vec3(194033.0, 258841.0, 0.0));
  // Its WKT (Oregon Lambert, NAD83 HARN, feet) places the centre on Autzen Stadium,
  // Eugene, Oregon (44.058 N, 123.069 W).
  EXPECT_EQ(c.crs_source, "LAS WKT record 2112");
  const CrsTransform crs(c.crs);
  const GeoPoint centre = crs.toWgs84(c.origin_m.x(), c.origin_m.y());
  EXPECT_NEAR(centre.lat_deg, 44.058, 0.01);
  EXPECT_NEAR(centre.lon_deg, -123.069, 0.01);
  EXPECT_NEAR(lo.z(), 406.26 * kFoot, 1e-6);
  EXPECT_LT(lo.head<2>().cwiseAbs().maxCoeff(), 200.0);

  LasOptions ground_only;
  ground_only.drop_classes = {1};
  const LasCloud g =
      readLas(std::string(UAVIP_SOURCE_DIR) + "/tests/data/autzen_trim.las", ground_only);
  EXPECT_EQ(g.points.size(), 26107u);
  EXPECT_EQ(g.dropped, 83893u);
}

}  // namespace
}  // namespace uavip::io
