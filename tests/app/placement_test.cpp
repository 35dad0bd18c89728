// Export's placement (app/placement.h) against independent references: heights at the
// NGA's published EGM96 test points (geoid undulations of the EGM96 model), a UTM CRS
// against GeographicLib's own UTM conversion, and the scene check against a box whose
// geometry the simulator knows.

#include "uavip/app/placement.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <GeographicLib/UTMUPS.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "uavip/app/pipeline.h"
#include "uavip/core/error.h"
#include "uavip/io/atomic_file.h"
#include "uavip/io/scene_json.h"
#include "uavip/sim/surface_sampler.h"
#include "uavip/sim/world_model.h"

namespace {

namespace fs = std::filesystem;
using uavip::InputError;
using uavip::Vec3;
namespace app = uavip::app;
namespace io = uavip::io;

/// A flight of the given local waypoints [m] (sortie 1).
io::Flight flightOf(const std::vector<Vec3>& points) {
  io::Flight f;
  f.sortie = 1;
  f.surface_ids = {0};
  for (const Vec3& p : points) {
    io::FlightWaypoint w;
    w.enu = p;
    f.waypoints.push_back(w);
  }
  return f;
}

class PlacementTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("uavip_placement_test_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  /// scene.json with only a CRS record: what placement reads of it.
  std::string crsScene(const std::string& definition, const std::string& vertical,
                       const Vec3& offset) const {
    std::ofstream(path("scene.json")) << nlohmann::json{
        {"crs", {{"definition", definition}, {"vertical", vertical}, {"source", "test"}}},
        {"source_offset_m",
         {offset.x(), offset.y(),
          offset.z()}}}.dump();
    return path("scene.json");
  }
  fs::path dir_;
};

// NGA's EGM96 test points (lat, lon [deg], N [m]), of the spherical harmonic model: the
// 15' grid PROJ interpolates agrees within a few centimetres over the sea.
struct NgaPoint {
  double lat, lon, n;
};
constexpr NgaPoint kNga[] = {{38.6254730, -0.0005000, 50.066}, {-0.4667440, 0.0023000, 17.329}};

TEST_F(PlacementTest, AnOriginIsAboveEgm96AtTheNgaTestPoints) {
  for (const NgaPoint& q : kNga) {
    app::PlacementRequest r;
    r.mission = path("mission.json");
    char origin[96];
    std::snprintf(origin, sizeof origin, "%.7f,%.7f,100", q.lat, q.lon);
    r.origin = origin;
    const app::MissionPlacement p = app::placeMission(io::MissionRecord{}, {}, r);
    ASSERT_TRUE(p.geo);
    EXPECT_EQ(p.home, Vec3::Zero());  // no flight: the origin is home
    const io::Geodetic g = p.geo->toGeodetic(Vec3::Zero());
    EXPECT_NEAR(g.lat_deg, q.lat, 1e-9);
    EXPECT_NEAR(g.lon_deg, q.lon, 1e-9);
    EXPECT_NEAR(g.h_ellipsoid_m, 100.0 + q.n, 0.05) << origin;
    EXPECT_NEAR(p.geo->egm96Height(g), 100.0, 1e-6);
    EXPECT_TRUE(p.warnings.empty());
  }
}

TEST_F(PlacementTest, AUtmCrsPlacesPointsWhereGeographicLibDoesInTheirVerticalDatum) {
  // NGA test point in Mongolia, UTM zone 48N (EPSG:32648): EGM96 N = -43.575 m.
  const double lat = 46.8743190, lon = 102.4487290, n = -43.575;
  int zone = 0;
  bool north = false;
  double e = 0.0, nn = 0.0;
  GeographicLib::UTMUPS::Forward(lat, lon, zone, north, e, nn, 48);
  ASSERT_EQ(zone, 48);
  const Vec3 local(3.0, -2.0, 10.0);
  const Vec3 offset(e - local.x(), nn - local.y(), 0.0);
  app::PlacementRequest r;
  r.mission = path("mission.json");
  r.scene = crsScene("EPSG:32648", "egm96", offset);

  app::MissionPlacement p = app::placeMission(io::MissionRecord{}, {}, r);
  io::Geodetic g = p.geo->toGeodetic(local);
  EXPECT_NEAR(g.lat_deg, lat, 1e-8);  // 1e-8 deg ≈ 1 mm
  EXPECT_NEAR(g.lon_deg, lon, 1e-8);
  EXPECT_NEAR(g.h_ellipsoid_m, 10.0 + n, 0.05);  // z is an EGM96 height (the scene says so)
  EXPECT_TRUE(p.warnings.empty());

  r.vertical = "ellipsoid";  // the cloud's z measured from the ellipsoid itself
  p = app::placeMission(io::MissionRecord{}, {}, r);
  g = p.geo->toGeodetic(local);
  EXPECT_NEAR(g.h_ellipsoid_m, 10.0, 1e-6);
  EXPECT_TRUE(p.warnings.empty());  // the CRS has no vertical part to override

  // --crs by hand with an EGM96 vertical part: it differs from the scene's, and
  // --vertical ellipsoid overrides its vertical part: both said, the heights as asked.
  r.crs = "EPSG:32648+5773";
  p = app::placeMission(io::MissionRecord{}, {}, r);
  g = p.geo->toGeodetic(local);
  EXPECT_NEAR(g.lat_deg, lat, 1e-8);
  EXPECT_NEAR(g.h_ellipsoid_m, 10.0, 1e-6);
  ASSERT_EQ(p.warnings.size(), 2U);
  EXPECT_NE(p.warnings[0].find("differs from the scene's CRS EPSG:32648"), std::string::npos);
  EXPECT_NE(p.warnings[1].find("overrides the CRS's vertical"), std::string::npos);
  r.vertical.clear();
  p = app::placeMission(io::MissionRecord{}, {}, r);
  EXPECT_NEAR(p.geo->toGeodetic(local).h_ellipsoid_m, 10.0 + n, 0.05);

  // The formats with heights relative to home: the CRS, the offset and home.
  r.crs.clear();
  io::ExportOptions o = app::relativeFrame(r);
  ASSERT_TRUE(o.crs);
  app::placeRelativeHome(o, io::MissionRecord{}, {flightOf({local, local + Vec3(0, 0, 5)})}, r);
  EXPECT_EQ(o.home_m, local);
  EXPECT_EQ(o.source_offset_m, offset);
  const io::GeoPoint home = io::homeGeo(o);
  EXPECT_NEAR(home.lat_deg, lat, 1e-8);
  EXPECT_NEAR(home.lon_deg, lon, 1e-8);
}

TEST_F(PlacementTest, AMissingOrAmbiguousFrameAndAFarWaypointAreRefused) {
  app::PlacementRequest r;
  r.mission = path("mission.json");  // no scene beside it: no CRS recorded
  EXPECT_THROW(app::placeMission(io::MissionRecord{}, {}, r), InputError);
  EXPECT_THROW(app::relativeFrame(r), InputError);
  r.origin = "47.3977,8.5456,488";
  r.crs = "EPSG:32632";
  EXPECT_THROW(app::placeMission(io::MissionRecord{}, {}, r), InputError);
  EXPECT_THROW(app::relativeFrame(r), InputError);
  r.crs.clear();
  const io::Flight far = flightOf({Vec3::Zero(), Vec3(60e3, 0.0, 20.0)});
  EXPECT_THROW(app::placeMission(io::MissionRecord{}, {far}, r), InputError);
  EXPECT_EQ(app::relativeFrame(r).origin.lat_deg, 47.3977);
  EXPECT_THROW(app::requireNearOrigin({far}, r.mission), InputError);
  EXPECT_NO_THROW(app::requireNearOrigin({flightOf({Vec3(49e3, 0.0, 0.0)})}, r.mission));
}

TEST_F(PlacementTest, APathThroughTheBoxIsRefusedAndOneClearOfItPasses) {
  // A 4 x 4 x 3 m box, detected as uavip detect would, scene.json written beside the mission.
  uavip::sim::WorldModel w;
  w.addBox("box", Vec3(0.0, 0.0, 0.0), Vec3(4.0, 4.0, 3.0));
  uavip::sim::SampleOptions so;
  so.spacing_m = 0.05;
  so.seed = 3;
  const uavip::PointList raw = uavip::sim::sampleSurfaces(w, so);
  const app::Config config = app::parseConfig("", "(defaults)");
  const app::DetectResult d = app::detect(raw, config, app::measure(raw));
  io::StagedOutputs outputs;
  const std::string pcd = path("cloud_clean.pcd"), safety = path(io::kSafetyCloudFile);
  outputs.writeWith(pcd,
                    [&](const std::string& t) { io::writeCloudPcdFile(t, d.scene.cloud, pcd); });
  outputs.writeWith(safety, [&](const std::string& t) {
    io::writeCloudPcdFile(t, d.scene.safety->points, safety);
  });
  outputs.write(path("scene.json"), io::sceneJsonText(d.scene, app::sceneExtras(d, nullptr)));
  outputs.commit();

  app::PlacementRequest r;
  r.mission = path("mission.json");
  io::MissionRecord mission;
  EXPECT_THROW(app::sceneValidator(mission, r), InputError);  // no inflation radius recorded
  mission.inflation_radius_m = 0.6;
  const auto validator = app::sceneValidator(mission, r);
  // 3 m off every face of the box, well beyond 0.6 m and the cloud's margins.
  const io::Flight clear =
      flightOf({Vec3(-3.0, -3.0, 1.5), Vec3(7.0, -3.0, 1.5), Vec3(7.0, 7.0, 6.0)});
  EXPECT_NO_THROW(app::requireFlightsClear(*validator, {clear}, r));
  // Straight through the box, and then a leg that grazes its top.
  const io::Flight through = flightOf({Vec3(-3.0, 2.0, 1.5), Vec3(7.0, 2.0, 1.5)});
  try {
    app::requireFlightsClear(*validator, {clear, through}, r);
    ADD_FAILURE() << "a path through the box was accepted";
  } catch (const io::NoMissionError& e) {
    EXPECT_NE(std::string(e.what()).find("mission.json: sortie 1, segment 0 comes"),
              std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find(path("scene.json")), std::string::npos) << e.what();
  }
  const io::Flight grazing = flightOf({Vec3(-3.0, 2.0, 3.3), Vec3(7.0, 2.0, 3.3)});  // 0.3 m above
  EXPECT_THROW(app::requireFlightsClear(*validator, {grazing}, r), io::NoMissionError);
  r.scene = path("nowhere/scene.json");
  EXPECT_THROW(app::sceneValidator(mission, r), InputError);
}

}  // namespace
