// Georeferenced clouds through the whole command line: a cube written in UTM zone
// 31N coordinates (x ≈ 5e5, y ≈ 5.4e6 m) as .xyz and as .csv with a header line is
// recentred by the reader, detected, planned, validated and exported with defaults;
// with --crs EPSG:32631 every waypoint lands where GeographicLib's own UTM
// conversion (an independent implementation of the same projection) puts it.

#include <gtest/gtest.h>
#include <tinyxml2.h>
#include <unistd.h>
#include <unzip.h>

#include <GeographicLib/UTMUPS.hpp>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "tests/cli/cli_runner.h"

namespace {

namespace fs = std::filesystem;

using uavip::cli_test::Result;
using uavip::cli_test::slurp;
using uavip::cli_test::uavip;

// The cube's corner in UTM 31N [m]: east, north, and a ground height of 101.25 m.
constexpr double kEast = 500123.37, kNorth = 5400456.81, kHeight = 101.25;
constexpr double kSide = 3.0, kStep = 0.05;

/// A 3 m cube standing on the ground (its top and four sides, every 5 cm; the bottom
/// is not scanned), as text lines "e<sep>n<sep>h" with millimetres.
std::string cubeText(char sep) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(3);
  const int n = static_cast<int>(std::lround(kSide / kStep));
  const double z0 = kHeight;
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j <= n; ++j) {
      const double a = i * kStep, b = j * kStep;
      const double pts[5][3] = {
          {a, b, kSide}, {a, 0.0, b}, {a, kSide, b}, {0.0, a, b}, {kSide, a, b}};
      for (const auto& p : pts)
        os << kEast + p[0] << sep << kNorth + p[1] << sep << z0 + p[2] << "\n";
    }
  }
  return os.str();
}

/// Splits a CSV line.
std::vector<std::string> fields(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  for (std::string f; std::getline(ss, f, ',');) out.push_back(f);
  return out;
}

class GeorefCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("uavip_georef_cli_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

TEST_F(GeorefCli, AUtmCubeDetectsPlansValidatesAndExportsAtItsTrueLatitudeAndLongitude) {
  // The offset the readers pick (io::recentringOrigin), computed here from the box:
  // x, y the rounded centre, z kept (101 m is near the origin).
  const double off_e = std::round(kEast + 0.5 * kSide), off_n = std::round(kNorth + 0.5 * kSide);
  for (const std::string name : {"cube.xyz", "cube.csv"}) {
    SCOPED_TRACE(name);
    const bool csv = name == "cube.csv";
    std::ofstream(path(name)) << (csv ? "easting,northing,height\n" : "")
                              << cubeText(csv ? ',' : ' ');
    const std::string out = path(name + "_out");

    Result r = uavip("detect " + path(name) + " -o " + out);
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("recentred by"), std::string::npos) << r.out;
    const auto scene = nlohmann::json::parse(slurp(fs::path(out) / "scene.json"));
    ASSERT_TRUE(scene.contains("source_offset_m")) << r.out;
    EXPECT_DOUBLE_EQ(scene["source_offset_m"][0].get<double>(), off_e);
    EXPECT_DOUBLE_EQ(scene["source_offset_m"][1].get<double>(), off_n);
    EXPECT_DOUBLE_EQ(scene["source_offset_m"][2].get<double>(), 0.0);
    EXPECT_EQ(scene["surfaces"].size(), 5u) << r.out;

    r = uavip("plan " + out + "/scene.json --surface all -o " + out);
    ASSERT_EQ(r.code, 0) << r.out;
    r = uavip("validate " + out + "/mission.json");
    ASSERT_EQ(r.code, 0) << r.out;

    // --origin still works on such a scene (local metres about the given point).
    r = uavip("export " + out +
              "/mission.json --surface all --format csv --origin 48.75,3.0,150 -o " +
              path("o.csv"));
    ASSERT_EQ(r.code, 0) << r.out;

    r = uavip("export " + out +
              "/mission.json --surface all --sortie 1 --format csv --crs EPSG:32631 -o " +
              path("g.csv"));
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("relative to home"), std::string::npos) << r.out;
    const auto mission = nlohmann::json::parse(slurp(fs::path(out) / "mission.json"));
    ASSERT_EQ(mission["flight"]["status"], "ok");
    const auto& home = mission["flight"]["sorties"][0]["waypoints"][0];
    const double home_z = home[2].get<double>();

    std::istringstream rows(slurp(path("g.csv")));
    std::string line;
    std::getline(rows, line);
    const std::vector<std::string> header = fields(line);
    const auto column = [&](const std::string& c) {
      return static_cast<std::size_t>(std::find(header.begin(), header.end(), c) - header.begin());
    };
    const std::size_t ce = column("east_m"), cn = column("north_m"), cu = column("up_m"),
                      clat = column("lat_deg"), clon = column("lon_deg"),
                      calt = column("alt_rel_home_m");
    ASSERT_LT(calt, header.size()) << line;
    int checked = 0;
    while (std::getline(rows, line)) {
      const std::vector<std::string> f = fields(line);
      ASSERT_EQ(f.size(), header.size()) << line;
      // GeographicLib: UTM zone 31, northern hemisphere, of the file's coordinates.
      double lat = 0.0, lon = 0.0;
      GeographicLib::UTMUPS::Reverse(31, true, std::stod(f[ce]) + off_e, std::stod(f[cn]) + off_n,
                                     lat, lon);
      EXPECT_NEAR(std::stod(f[clat]), lat, 1e-8) << line;  // 1e-8 deg ≈ 1 mm
      EXPECT_NEAR(std::stod(f[clon]), lon, 1e-8) << line;
      EXPECT_NEAR(std::stod(f[calt]), std::stod(f[cu]) - home_z, 1e-3) << line;
      EXPECT_GT(lat, 48.7);  // the cube lies at about 48.75 N, 3.0 E
      EXPECT_LT(lat, 48.8);
      EXPECT_NEAR(lon, 3.0, 0.05);
      ++checked;
    }
    EXPECT_GT(checked, 10);

    // The .plan's home is the flight's home, at its height in the cloud's datum.
    r = uavip("export " + out +
              "/mission.json --surface all --sortie 1 --format qgc-plan --crs EPSG:32631 -o " +
              path("g.plan"));
    ASSERT_EQ(r.code, 0) << r.out;
    const auto plan = nlohmann::json::parse(slurp(path("g.plan")));
    double lat = 0.0, lon = 0.0;
    GeographicLib::UTMUPS::Reverse(31, true, home[0].get<double>() + off_e,
                                   home[1].get<double>() + off_n, lat, lon);
    EXPECT_NEAR(plan["mission"]["plannedHomePosition"][0].get<double>(), lat, 1e-8);
    EXPECT_NEAR(plan["mission"]["plannedHomePosition"][1].get<double>(), lon, 1e-8);
    EXPECT_NEAR(plan["mission"]["plannedHomePosition"][2].get<double>(), home_z, 1e-6);
  }
}

/// The entries of a KMZ (minizip, read here).
std::string unzipEntry(const std::string& kmz, const char* entry) {
  unzFile z = unzOpen64(kmz.c_str());
  if (z == nullptr || unzLocateFile(z, entry, 1) != UNZ_OK) {
    if (z != nullptr) unzClose(z);
    return "";
  }
  unz_file_info64 info{};
  unzGetCurrentFileInfo64(z, &info, nullptr, 0, nullptr, 0, nullptr, 0);
  std::string text(static_cast<std::size_t>(info.uncompressed_size), '\0');
  unzOpenCurrentFile(z);
  unzReadCurrentFile(z, text.data(), static_cast<unsigned>(text.size()));
  unzCloseCurrentFile(z);
  unzClose(z);
  return text;
}

/// lon, lat and the named height of each Placemark of a WPML document.
std::vector<std::array<double, 3>> placemarks(const std::string& xml, const char* height) {
  tinyxml2::XMLDocument doc;
  std::vector<std::array<double, 3>> out;
  if (doc.Parse(xml.c_str()) != tinyxml2::XML_SUCCESS) return out;
  const auto* folder =
      doc.FirstChildElement("kml")->FirstChildElement("Document")->FirstChildElement("Folder");
  for (const auto* pm = folder->FirstChildElement("Placemark"); pm != nullptr;
       pm = pm->NextSiblingElement("Placemark")) {
    std::array<double, 3> p{};
    std::sscanf(pm->FirstChildElement("Point")->FirstChildElement("coordinates")->GetText(),
                " %lf,%lf", &p[0], &p[1]);
    p[2] = std::stod(pm->FirstChildElement(height)->GetText());
    out.push_back(p);
  }
  return out;
}

TEST_F(GeorefCli, DetectRecordsTheCrsAndADjiRouteNeedsNoCrsOrOriginAfterIt) {
  const double off_e = std::round(kEast + 0.5 * kSide), off_n = std::round(kNorth + 0.5 * kSide);
  std::ofstream(path("cube.xyz")) << cubeText(' ');
  Result r = uavip("detect " + path("cube.xyz") + " --crs EPSG:32631+5773 -o " + path("d"));
  ASSERT_EQ(r.code, 0) << r.out;
  const auto scene = nlohmann::json::parse(slurp(path("d/scene.json")));
  EXPECT_EQ(scene["crs"]["definition"], "EPSG:32631+5773");
  EXPECT_EQ(scene["crs"]["vertical"], "egm96");  // from the compound CRS's vertical part
  EXPECT_EQ(scene["crs"]["source"], "detect --crs");
  ASSERT_EQ(uavip("plan " + path("d/scene.json") + " --surface all -o " + path("d")).code, 0);
  r = uavip("export " + path("d/mission.json") +
            " --surface all --sortie 1 --format dji-kmz --height-mode ellipsoid -o " +
            path("site.kmz"));
  ASSERT_EQ(r.code, 0) << r.out;
  const auto mission = nlohmann::json::parse(slurp(path("d/mission.json")));
  const auto& wps = mission["flight"]["sorties"][0]["waypoints"];
  const auto flown = placemarks(unzipEntry(path("site.kmz"), "wpmz/waylines.wpml"),
                                "wpml:executeHeight");  // above the ellipsoid
  const auto shown = placemarks(unzipEntry(path("site.kmz"), "wpmz/template.kml"),
                                "wpml:height");  // above EGM96, as Pilot 2 shows them
  ASSERT_EQ(flown.size(), wps.size());
  ASSERT_EQ(shown.size(), wps.size());
  double undulation = 0.0;
  for (std::size_t i = 0; i < wps.size(); ++i) {
    double lat = 0.0, lon = 0.0;
    GeographicLib::UTMUPS::Reverse(31, true, wps[i][0].get<double>() + off_e,
                                   wps[i][1].get<double>() + off_n, lat, lon);
    EXPECT_NEAR(flown[i][0], lon, 2e-9) << i;  // ≈ 0.2 mm
    EXPECT_NEAR(flown[i][1], lat, 2e-9) << i;
    // The cloud's heights are EGM96 heights (EPSG:5773): the template gives them back.
    EXPECT_NEAR(shown[i][2], wps[i][2].get<double>(), 1e-3) << i;
    // Ellipsoidal = EGM96 + N, the same N over a 10 m site.
    if (i == 0) undulation = flown[0][2] - shown[0][2];
    EXPECT_NEAR(flown[i][2] - shown[i][2], undulation, 0.01) << i;
  }
  EXPECT_GT(std::abs(undulation), 1.0);  // N is tens of metres in Europe, never silently 0
  // mission.html carries the CRS in closed form: a picked point shows where it is.
  const std::string html = slurp(path("d/mission.html"));
  const std::string open = "<script type=\"application/json\" id=\"uavip-geo\">";
  const auto at = html.find(open);
  ASSERT_NE(at, std::string::npos);
  const auto geo = nlohmann::json::parse(
      html.substr(at + open.size(), html.find("</script>", at) - at - open.size()));
  EXPECT_LT(geo["max_error_m"].get<double>(), 0.01);
  for (std::size_t i = 0; i < wps.size(); i += 7) {  // the page's polynomial, evaluated here
    std::array<double, 3> q{};
    for (int k = 0; k < 3; ++k)
      q[k] =
          (wps[i][k].get<double>() - geo["centre"][k].get<double>()) / geo["half"][k].get<double>();
    const std::array<double, 10> b = {1.0,         q[0],        q[1],        q[2],
                                      q[0] * q[0], q[1] * q[1], q[2] * q[2], q[0] * q[1],
                                      q[0] * q[2], q[1] * q[2]};
    double lat = 0.0, lon = 0.0, h = 0.0;
    for (std::size_t k = 0; k < 10; ++k) {
      lat += geo["lat"][k].get<double>() * b[k];
      lon += geo["lon"][k].get<double>() * b[k];
      h += geo["h"][k].get<double>() * b[k];
    }
    EXPECT_NEAR(lon, flown[i][0], 1e-7) << i;  // 1e-7 deg ≈ 1 cm
    EXPECT_NEAR(lat, flown[i][1], 1e-7) << i;
    EXPECT_NEAR(h, flown[i][2], 0.01) << i;
  }
  // A --crs that contradicts the scene's is a warning naming both.
  r = uavip("export " + path("d/mission.json") +
            " --surface all --sortie 1 --format geojson --crs EPSG:32631 -o " + path("g.json"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("warning: --crs EPSG:32631 differs from the scene's CRS EPSG:32631+5773"),
            std::string::npos)
      << r.out;
  // A CRS PROJ does not know is refused at detect.
  r = uavip("detect " + path("cube.xyz") + " --crs EPSG:99999 -o " + path("e"));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("EPSG:99999"), std::string::npos) << r.out;
}

TEST_F(GeorefCli, CrsMistakesAreOneLineAndExit2) {
  std::ofstream(path("cube.xyz")) << cubeText(' ');
  ASSERT_EQ(uavip("detect " + path("cube.xyz") + " -o " + path("d")).code, 0);
  ASSERT_EQ(uavip("plan " + path("d/scene.json") + " --surface 0 -o " + path("d")).code, 0);
  const std::string exp =
      "export " + path("d/mission.json") + " --surface 0 --format wpl -o " + path("x.wpl") + " ";
  const struct {
    std::string args, fragment;
  } cases[] = {
      {"--crs EPSG:32631 --origin 48,3,100", "choose one"},
      {"--crs EPSG:99999", "EPSG:99999"},
      {"--crs EPSG:4326", "not a projected CRS"},
      {"--crs 'not a crs'", "not a crs"},
  };
  for (const auto& c : cases) {
    const Result r = uavip(exp + c.args);
    EXPECT_EQ(r.code, 2) << c.args << "\n" << r.out;
    EXPECT_NE(r.out.find(c.fragment), std::string::npos) << c.args << "\n" << r.out;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << c.args << "\n" << r.out;
  }
  EXPECT_FALSE(fs::exists(path("x.wpl")));
  // A scene near its own origin has no offset: --crs cannot place it.
  ASSERT_EQ(uavip("run " + std::string(UAVIP_SOURCE_DIR) + "/scenarios/single_plane.yaml -o " +
                  path("local"))
                .code,
            0);
  const Result r = uavip("export " + path("local/mission.json") +
                         " --format wpl --crs EPSG:32631 -o " + path("x.wpl"));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("source_offset_m"), std::string::npos) << r.out;
}

}  // namespace
