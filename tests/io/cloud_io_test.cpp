#include "uavip/io/cloud_io.h"

#include <gtest/gtest.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_types.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "uavip/core/error.h"

namespace uavip::io {
namespace {

namespace fs = std::filesystem;

class CloudIo : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("uavip_cloud_io_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string file(const std::string& name, const std::string& text) const {
    std::string p = (dir_ / name).string();
    std::ofstream(p) << text;
    return p;
  }
  fs::path dir_;
};

void expectError(const std::string& path, const std::string& fragment) {
  try {
    loadCloud(path);
    FAIL() << path;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

TEST_F(CloudIo, XyzIsRead) {
  const PointList p = loadCloud(file("a.xyz", "# x y z\n1 2 3\n\n4.5,5,6 99\n"));
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(p[1], Vec3(4.5, 5, 6));
}

TEST_F(CloudIo, CsvAndHeaderLinesOfColumnNamesAreRead) {
  const PointList spreadsheet = loadCloud(file("a.csv", "x,y,z\n1,2,3\n4.5,5,6\n"));
  ASSERT_EQ(spreadsheet.size(), 2u);
  EXPECT_EQ(spreadsheet[1], Vec3(4.5, 5, 6));
  const PointList cloudcompare = loadCloud(file("b.txt", "//X,Y,Z,R,G,B\n1,2,3,255,0,0\n"));
  ASSERT_EQ(cloudcompare.size(), 1u);
  EXPECT_EQ(cloudcompare[0], Vec3(1, 2, 3));
  // Only before the first point: a word later is an error with its line.
  expectError(file("late.csv", "1,2,3\nx,y,z\n"), ":2: not a number");
}

TEST_F(CloudIo, ScaleConvertsToMetresAndIsNoted) {
  CloudReadOptions mm;
  mm.scale = 0.001;
  CloudReadInfo info;
  const PointList p = loadCloud(file("mm.xyz", "1000 2500 -300\n"), mm, &info);
  ASSERT_EQ(p.size(), 1u);
  EXPECT_NEAR((p[0] - Vec3(1.0, 2.5, -0.3)).norm(), 0.0, 1e-12);
  EXPECT_NE(info.note.find("input.scale 0.001"), std::string::npos) << info.note;
  for (const double bad : {0.0, -1.0, std::nan("")}) {
    CloudReadOptions o;
    o.scale = bad;
    EXPECT_THROW(loadCloud(file("ok.xyz", "1 2 3\n"), o), InputError) << bad;
  }
}

TEST_F(CloudIo, PcdRoundTripKeepsFloatPrecision) {
  const PointList in = {{0.1, -2.5, 3.25}, {10.0, 20.0, -0.001}};
  const std::string p = (dir_ / "c.pcd").string();
  saveCloudPcd(p, in);
  const PointList out = loadCloud(p);
  ASSERT_EQ(out.size(), in.size());
  for (std::size_t i = 0; i < in.size(); ++i) EXPECT_LT((out[i] - in[i]).norm(), 1e-5);
  EXPECT_FALSE(fs::exists(p + ".tmp" + std::to_string(::getpid())));
}

TEST_F(CloudIo, DoubleAndIntegerFieldsAreReadAsNumbers) {
  // PCL's PointXYZ conversion copies a double's bytes as a float: these read as
  // zeros before. Geo-referenced values (5e5 m) need the double.
  const auto pcd = [](const std::string& size, const std::string& type, const std::string& data) {
    return "VERSION .7\nFIELDS x y z\nSIZE " + size + "\nTYPE " + type +
           "\nCOUNT 1 1 1\nWIDTH 2\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA ascii\n" +
           data;
  };
  CloudReadInfo info;
  const PointList d = loadCloud(
      file("d.pcd", pcd("8 8 8", "F F F", "500000.125 4000000.5 12.25\n500003.5 4000002 3\n")), {},
      &info);
  ASSERT_EQ(d.size(), 2u);
  EXPECT_EQ(info.origin_m, Vec3(500002.0, 4000001.0, 0.0));  // recentred: the box's centre, rounded
  EXPECT_DOUBLE_EQ(d[0].x() + info.origin_m.x(), 500000.125);
  EXPECT_DOUBLE_EQ(d[0].y() + info.origin_m.y(), 4000000.5);
  EXPECT_DOUBLE_EQ(d[1].z(), 3.0);
  const PointList i = loadCloud(file("i.pcd", pcd("4 4 2", "I I U", "-7 8 9\n1 2 3\n")));
  ASSERT_EQ(i.size(), 2u);
  EXPECT_DOUBLE_EQ(i[0].x(), -7.0);
  EXPECT_DOUBLE_EQ(i[0].z(), 9.0);
  const PointList ply =
      loadCloud(file("d.ply",
                     "ply\nformat ascii 1.0\nelement vertex 1\nproperty double x\n"
                     "property double y\nproperty double z\nend_header\n1.25 -2.5 700000.75\n"));
  ASSERT_EQ(ply.size(), 1u);
  EXPECT_DOUBLE_EQ(ply[0].z(),
                   -0.25);  // z far from the origin too: recentred by its rounded value 700001
}

/// The origin the readers promise (cloud_io.h), computed from the points here.
Vec3 expectedOrigin(const PointList& file_points) {
  Vec3 lo = file_points.front(), hi = lo;
  for (const auto& p : file_points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const Vec3 c = 0.5 * (lo + hi);
  return {std::round(c.x()), std::round(c.y()),
          std::max(std::abs(lo.z()), std::abs(hi.z())) > 1e4 ? std::round(c.z()) : 0.0};
}

TEST_F(CloudIo, EveryReaderRecentresAGeoreferencedCloudInDouble) {
  // UTM 31N coordinates with millimetres: recentring must keep every digit.
  const PointList utm = {{500123.371, 5400456.812, 101.25},
                         {500126.374, 5400459.813, 104.5},
                         {500124.001, 5400457.5, 102.0}};
  std::string xyz, csv = "x,y,z\n";
  for (const auto& p : utm) {
    std::ostringstream l;
    l << std::setprecision(12) << p.x() << " " << p.y() << " " << p.z() << "\n";
    xyz += l.str();
    std::string c = l.str();
    std::replace(c.begin(), c.end(), ' ', ',');
    csv += c;
  }
  const std::string pcd =
      "VERSION .7\nFIELDS x y z\nSIZE 8 8 8\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 3\nHEIGHT 1\n"
      "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\nDATA ascii\n" +
      xyz;
  const std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
      "property double z\nend_header\n" +
      xyz;
  const Vec3 origin = expectedOrigin(utm);
  EXPECT_EQ(origin, Vec3(500125.0, 5400458.0, 0.0));
  for (const auto& [name, text] : std::vector<std::pair<std::string, std::string>>{
           {"u.xyz", xyz}, {"u.txt", xyz}, {"u.csv", csv}, {"u.pcd", pcd}, {"u.ply", ply}}) {
    CloudReadInfo info;
    const PointList p = loadCloud(file(name, text), {}, &info);
    ASSERT_EQ(p.size(), utm.size()) << name;
    EXPECT_EQ(info.origin_m, origin) << name;
    EXPECT_NE(info.note.find("recentred by (500125, 5400458, 0) m"), std::string::npos)
        << name << ": " << info.note;
    for (std::size_t i = 0; i < p.size(); ++i) {
      EXPECT_LT(p[i].head<2>().norm(), 10.0) << name;  // x, y recentred; z kept
      EXPECT_NEAR((p[i] + info.origin_m - utm[i]).norm(), 0.0, 1e-9) << name << " point " << i;
    }
  }
  // input.scale first, then the recentring, in metres: a cloud in millimetres.
  CloudReadOptions mm;
  mm.scale = 0.001;
  CloudReadInfo info;
  const PointList p = loadCloud(
      file("mm.xyz", "500123371 5400456812 101250\n500126374 5400459813 104500\n"), mm, &info);
  EXPECT_EQ(info.origin_m, Vec3(500125.0, 5400458.0, 0.0));
  EXPECT_NEAR((p[0] + info.origin_m - utm[0]).norm(), 0.0, 1e-6);
  // A cloud near its origin is left where it is.
  CloudReadInfo local;
  const PointList q = loadCloud(file("local.xyz", "9999 -9999 5\n9990 -9990 3\n"), {}, &local);
  EXPECT_EQ(local.origin_m, Vec3::Zero());
  EXPECT_EQ(q[0], Vec3(9999, -9999, 5));
  EXPECT_TRUE(local.note.empty()) << local.note;
}

TEST_F(CloudIo, ACloudBeyondPhysicalSenseNamesItsStrayPoint) {
  // One point at 1e308 among a wall's: the cloud cannot be recentred into any frame.
  std::string wall;
  for (int i = 0; i < 20; ++i)
    wall += std::to_string(i * 0.1) + " 0 " + std::to_string(i * 0.05) + "\n";
  expectError(file("far.xyz", wall + "1e308 0 0\n" + wall), "point 20 (1e+308, 0, 0)");
  expectError(file("far_neg.csv", "x,y,z\n" + wall + "0 -1e308 0\n"), "point 20 (0, -1e+308, 0)");
  // A wall in the wrong unit (or scaled by 1e12): 4e12 m across is no structure.
  std::string huge;
  for (int i = 0; i <= 40; ++i)
    huge += std::to_string(i * 1e11) + " 0 " + std::to_string((i % 7) * 1e11) + "\n";
  expectError(file("huge.xyz", huge), "spans 4e+12 m");
  CloudReadOptions scale;
  scale.scale = 1e12;
  EXPECT_THROW(loadCloud(file("scaled.xyz", wall), scale), InputError);
  // A lone point at 1e308 (found by fuzz_cloud): no extent, but on no map of the earth.
  expectError(file("lone.xyz", "\n1e308 0 0\n"), "point 0 (1e+308, 0, 0) lies beyond 100000 km");
  expectError(file("lone_mm.xyz", wall + "0 2e8 0\n"), "point 20 (0, 2e+08, 0)");
  // 90 km across is a large site, still read.
  EXPECT_NO_THROW(loadCloud(file("wide.xyz", "0 0 0\n90000 0 0\n")));
}

TEST_F(CloudIo, OrganizedFrameSkipsItsMissingReturns) {
  // A sensor frame (HEIGHT > 1) marks beams without a return by NaN.
  const PointList p =
      loadCloud(file("o.pcd",
                     "VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
                     "WIDTH 2\nHEIGHT 2\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 4\nDATA ascii\n"
                     "1 2 3\nnan nan nan\n4 5 6\n7 8 9\n"));
  ASSERT_EQ(p.size(), 3u);
  EXPECT_DOUBLE_EQ(p[2].x(), 7.0);
}

TEST_F(CloudIo, BadCloudsAreOneLineErrors) {
  expectError((dir_ / "missing.pcd").string(), "no such file");
  expectError(file("empty.xyz", "# nothing\n"), "no points");
  expectError(file("nan.xyz", "1 2 3\nnan 0 0\n"), ":2:");
  expectError(file("inf.xyz", "1 2 inf\n"), "not finite");
  expectError(file("text.xyz", "1 2 three\n"), "not a number");
  expectError(file("short.xyz", "1 2\n"), "expected 'x y z'");
  expectError(file("a.e57", "x"), "unknown cloud extension");
  expectError(file("b.las", "x"), "b.las");
  expectError(file("c.laz", "x"), "laszip");
  expectError(file("bad.pcd", "garbage"), "not a PCD file");
  expectError(file("nofields.pcd", "VERSION 0.7\nFIELDS a b c\nPOINTS 1\nDATA ascii\n1 2 3\n"),
              "x y z");
  // Headers PCL's reader crashes on (found by tests/fuzz/fuzz_cloud) are refused first.
  const std::string body = "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n";
  expectError(file("noversion.pcd", body + "WIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA ascii\n1 2 3\n"),
              "VERSION");
  expectError(
      file("nowidth.pcd", "VERSION 0.7\n" + body + "HEIGHT 1\nPOINTS 1\nDATA ascii\n1 2 3\n"),
      "WIDTH");
  expectError(file("key.pcd",
                   "VERSION 0.7\n" + body + "WIDT\xfe\xff HEIGHT 1\nPOINTS 1\nDATA ascii\n1 2 3\n"),
              "header line 6");
  expectError(file("twice.pcd", "VERSION 0.7\n" + body +
                                    "WIDTH 1\nWIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA ascii\n1 2 3\n"),
              "WIDTH twice");
  expectError(
      file("claims.pcd", "VERSION 0.7\n" + body + "WIDTH 100\nHEIGHT 1\nPOINTS 100\nDATA binary\n" +
                             std::string(12, '\0')),
      "claims 100 points");
  expectError(file("bad.ply", "garbage"), "not a PLY file");
  expectError(file("claims.ply",
                   "ply\nformat binary_little_endian 1.0\nelement vertex 9\nproperty float x\n"
                   "property float y\nproperty float z\nend_header\n" +
                       std::string(12, '\0')),
              "claims 9 points");
  expectError(file("novertex.ply", "ply\nformat ascii 1.0\nend_header\n"), "no vertex");
}

TEST(CloudIoReal, RoomScanLoads) {
  const PointList p = loadCloud(std::string(UAVIP_SOURCE_DIR) + "/tests/data/room_scan1.pcd");
  EXPECT_GT(p.size(), 100000u);
}

// uavip reads PCD itself (PCL's reader crashes on some damaged files): every layout
// PCL writes must read back point for point as PCL reads it.
TEST(CloudIoPcd, OwnReaderMatchesPclOnEveryDataLayout) {
  pcl::PointCloud<pcl::PointXYZRGB> cloud;  // x y z and a packed rgb field after them
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-50.0f, 50.0f);
  for (int i = 0; i < 5000; ++i) {
    pcl::PointXYZRGB p;
    p.x = u(rng);
    p.y = u(rng);
    p.z = std::round(u(rng));  // runs of equal bytes: LZF back references
    p.r = static_cast<std::uint8_t>(i);
    cloud.push_back(p);
  }
  const auto dir =
      std::filesystem::temp_directory_path() / ("uavip_pcd_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string ascii = (dir / "a.pcd").string(), binary = (dir / "b.pcd").string(),
                    compressed = (dir / "c.pcd").string();
  pcl::io::savePCDFileASCII(ascii, cloud);
  pcl::io::savePCDFileBinary(binary, cloud);
  pcl::io::savePCDFileBinaryCompressed(compressed, cloud);
  std::vector<std::string> files = {
      ascii, binary, compressed, std::string(UAVIP_SOURCE_DIR) + "/tests/data/room_scan1.pcd",
      std::string(UAVIP_SOURCE_DIR) + "/tests/data/fcplanner_MBS.pcd"};
  for (const auto& f : files) {
    pcl::PointCloud<pcl::PointXYZ> reference;
    ASSERT_EQ(pcl::io::loadPCDFile(f, reference), 0) << f;
    const PointList ours = loadCloud(f);
    ASSERT_EQ(ours.size(), reference.size()) << f;
    for (std::size_t i = 0; i < ours.size(); ++i) {
      ASSERT_EQ(ours[i], reference[i].getVector3fMap().cast<double>()) << f << " point " << i;
    }
  }
  // A damaged LZF stream or size is refused by name, not a crash.
  std::string bytes;
  {
    std::ifstream in(compressed, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  const std::size_t data = bytes.find("DATA binary_compressed\n") + 23;
  std::string damaged = bytes;
  damaged[data + 8] =
      static_cast<char>(0xff);  // the first control byte: a back reference before the start
  std::ofstream(dir / "d.pcd", std::ios::binary) << damaged;
  EXPECT_THROW(loadCloud((dir / "d.pcd").string()), InputError);
  damaged = bytes;
  damaged[data + 4] = static_cast<char>(damaged[data + 4] + 1);  // uncompressed size off by one
  std::ofstream(dir / "e.pcd", std::ios::binary) << damaged;
  EXPECT_THROW(loadCloud((dir / "e.pcd").string()), InputError);
  std::filesystem::remove_all(dir);
}

/// Every point streamCloud hands on, in order.
PointList streamed(const std::string& path, std::size_t chunk) {
  PointList out;
  streamCloud(path, CloudReadOptions{}, chunk, [&](const PointList& points) {
    EXPECT_LE(points.size(), chunk);
    out.insert(out.end(), points.begin(), points.end());
  });
  return out;
}

// ascii and binary PCD are streamed a chunk at a time: the same points as loadCloud
// (which reads the whole file), organized clouds' missing returns skipped alike, a
// bad point named by its index in the file; binary_compressed is read whole.
TEST(CloudIoPcd, StreamedAsLoadedChunkByChunk) {
  pcl::PointCloud<pcl::PointXYZ> organized(60, 40);  // a sensor frame with missing returns
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-20.0f, 20.0f);
  for (std::size_t i = 0; i < organized.size(); ++i) {
    organized[i].getVector3fMap() = Eigen::Vector3f(u(rng), u(rng), u(rng));
    if (i % 7 == 3) organized[i].x = std::numeric_limits<float>::quiet_NaN();
  }
  pcl::PointCloud<pcl::PointXYZ> flat;
  for (int i = 0; i < 3000; ++i) flat.push_back(pcl::PointXYZ(u(rng), u(rng), u(rng)));
  const auto dir =
      std::filesystem::temp_directory_path() / ("uavip_pcd_stream_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto at = [&](const std::string& name) { return (dir / name).string(); };
  pcl::io::savePCDFileASCII(at("a.pcd"), flat);
  pcl::io::savePCDFileBinary(at("b.pcd"), flat);
  pcl::io::savePCDFileBinaryCompressed(at("c.pcd"), flat);
  pcl::io::savePCDFileBinary(at("o.pcd"), organized);
  pcl::io::savePCDFileASCII(at("oa.pcd"), organized);
  for (const std::string& f : {at("a.pcd"), at("b.pcd"), at("c.pcd"), at("o.pcd"), at("oa.pcd"),
                               std::string(UAVIP_SOURCE_DIR) + "/tests/data/room_scan1.pcd",
                               std::string(UAVIP_SOURCE_DIR) + "/tests/data/fcplanner_MBS.pcd"}) {
    const PointList whole = loadCloud(f);
    if (f.rfind(dir.string(), 0) == 0) {  // written here: all but c.pcd stream
      EXPECT_EQ(streamsInBoundedMemory(f), f != at("c.pcd")) << f;
    }
    for (const std::size_t chunk : {std::size_t{1}, std::size_t{777}, std::size_t{1} << 20}) {
      if (chunk == 1 && whole.size() > 20000) continue;
      EXPECT_EQ(streamed(f, chunk), whole) << f << ", chunks of " << chunk;
    }
  }
  EXPECT_EQ(loadCloud(at("o.pcd")).size(), organized.size() - (organized.size() + 3) / 7);
  // A non-finite point of an unorganized cloud: the same message, naming point 2345.
  flat[2345].z = std::numeric_limits<float>::infinity();
  pcl::io::savePCDFileBinary(at("bad.pcd"), flat);
  std::string loaded, streamed_error;
  try {
    loadCloud(at("bad.pcd"));
  } catch (const InputError& e) {
    loaded = e.what();
  }
  try {
    streamed(at("bad.pcd"), 1000);
  } catch (const InputError& e) {
    streamed_error = e.what();
  }
  EXPECT_NE(loaded.find("point 2345 "), std::string::npos) << loaded;
  EXPECT_EQ(streamed_error, loaded);
  std::filesystem::remove_all(dir);
}

// PLY files as PCL writes them (ascii and binary_little_endian, a camera element after
// the vertices) are streamed a chunk at a time: the same points as loadCloud (PCL's
// reader); a sensor frame (the camera's viewport has rows) is read whole, its missing
// returns skipped.
TEST(CloudIoPly, StreamedAsLoadedChunkByChunk) {
  pcl::PointCloud<pcl::PointXYZ> flat;
  std::mt19937 rng(8);
  std::uniform_real_distribution<float> u(-30.0f, 30.0f);
  for (int i = 0; i < 2500; ++i) flat.push_back(pcl::PointXYZ(u(rng), u(rng), u(rng)));
  pcl::PointCloud<pcl::PointXYZ> organized(50, 30);
  for (std::size_t i = 0; i < organized.size(); ++i) {
    organized[i].getVector3fMap() = Eigen::Vector3f(u(rng), u(rng), u(rng));
    if (i % 5 == 1) organized[i].z = std::numeric_limits<float>::quiet_NaN();
  }
  const auto dir =
      std::filesystem::temp_directory_path() / ("uavip_ply_stream_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto at = [&](const std::string& name) { return (dir / name).string(); };
  ASSERT_EQ(pcl::io::savePLYFileASCII(at("a.ply"), flat), 0);
  ASSERT_EQ(pcl::io::savePLYFileBinary(at("b.ply"), flat), 0);
  ASSERT_EQ(pcl::io::savePLYFileBinary(at("o.ply"), organized), 0);
  for (const std::string& f : {at("a.ply"), at("b.ply"), at("o.ply")}) {
    const PointList whole = loadCloud(f);
    EXPECT_EQ(whole.size(),
              f == at("o.ply") ? organized.size() - (organized.size() + 3) / 5 : flat.size())
        << f;
    for (const std::size_t chunk : {std::size_t{1}, std::size_t{777}, std::size_t{1} << 20})
      EXPECT_EQ(streamed(f, chunk), whole) << f << ", chunks of " << chunk;
  }
  EXPECT_FALSE(streamsInBoundedMemory(at("o.ply")));  // a sensor frame: read whole
  EXPECT_TRUE(streamsInBoundedMemory(at("a.ply")));
  EXPECT_TRUE(streamsInBoundedMemory(at("b.ply")));
  // A truncated binary file is refused naming the file, not a crash.
  std::string bytes;
  {
    std::ifstream in(at("b.ply"), std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  const std::size_t body = bytes.find("end_header\n") + 11;
  std::ofstream(at("t.ply"), std::ios::binary)
      << bytes.substr(0, body + std::size_t{12} * 1000 + 5);
  try {
    streamed(at("t.ply"), 300);
    ADD_FAILURE() << "a truncated PLY was streamed";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(at("t.ply")), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace uavip::io
