// uavip export: each format parsed back and checked against a hand-made mission;
// geography against the WGS84 radii of curvature worked out by hand.

#include <gtest/gtest.h>

#include <GeographicLib/UTMUPS.hpp>
#include <cmath>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "uavip/core/error.h"
#include "uavip/io/mission_export.h"

namespace {

using nlohmann::json;
namespace io = uavip::io;
using uavip::Vec3;

constexpr double kPi = 3.14159265358979323846;
constexpr double kLat0 = 47.0, kLon0 = 8.0, kAlt0 = 500.0;

/// WGS84 meridian (M) and prime-vertical (N) radii of curvature at latitude phi,
/// plus the origin's height (a point kAlt0 above the ellipsoid moves on a larger
/// circle) [m].
void radii(double lat_deg, double& M, double& N) {
  const double a = 6378137.0, f = 1.0 / 298.257223563, e2 = f * (2.0 - f);
  const double s = std::sin(lat_deg * kPi / 180.0);
  const double w = 1.0 - e2 * s * s;
  M = a * (1.0 - e2) / std::pow(w, 1.5) + kAlt0;
  N = a / std::sqrt(w) + kAlt0;
}

json stop(double x, double y, double z, double yaw, double pitch) {
  return {{"position", {x, y, z}},
          {"target", {x, y, z}},
          {"yaw_deg", yaw},
          {"gimbal_pitch_deg", pitch}};
}

/// Surface 0: two stops (100 m north, then 100 m east, 10 m up) with a waypoint
/// between them; surface 1 blocked; surface 2: one stop looking straight down.
json mission() {
  json s0 = {{"surface_id", 0},
             {"status", "ok"},
             {"reason", ""},
             {"stops", {stop(0, 100, 10, 90.0, -10.0), stop(100, 0, 10, 0.0, 5.0)}},
             {"waypoints", {{0, 100, 10}, {50, 50, 12}, {100, 0, 10}}}};
  json s1 = {{"surface_id", 1},
             {"status", "blocked"},
             {"reason", "3 of 3 stops infeasible"},
             {"stops", {stop(1, 1, 1, 0, 0)}},
             {"waypoints", json::array()}};
  json s2 = {{"surface_id", 2},
             {"status", "ok"},
             {"reason", ""},
             {"stops", {stop(0, 0, 5, -90.0, -90.0)}},
             {"waypoints", {{0, 0, 5}}}};
  // The ordered flight: home at surface 0's first stop, surface 0, surface 2, home.
  json sortie = {{"sortie", 1},
                 {"waypoints", {{0, 100, 10}, {50, 50, 12}, {100, 0, 10}, {0, 0, 5}, {0, 100, 10}}},
                 {"stops",
                  {{{"surface_id", 0}, {"stop", 0}, {"waypoint", 0}},
                   {{"surface_id", 0}, {"stop", 1}, {"waypoint", 2}},
                   {{"surface_id", 2}, {"stop", 0}, {"waypoint", 3}}}}};
  json flight = {{"status", "ok"}, {"reason", ""}, {"sorties", {sortie}}};
  return {{"format", "uavip-mission"}, {"surfaces", {s0, s1, s2}}, {"flight", flight}};
}

io::ExportOptions options(io::Autopilot ap = io::Autopilot::Px4) {
  io::ExportOptions o;
  o.origin = {kLat0, kLon0, kAlt0};
  o.autopilot = ap;
  o.hold_s = 2.0;
  return o;
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string cur;
  std::istringstream in(s);
  while (std::getline(in, cur, sep)) out.push_back(cur);
  return out;
}

TEST(Heading, CompassFromEnuYaw) {
  EXPECT_NEAR(io::headingFromYaw(90.0), 0.0, 1e-12);     // north
  EXPECT_NEAR(io::headingFromYaw(0.0), 90.0, 1e-12);     // east
  EXPECT_NEAR(io::headingFromYaw(-90.0), 180.0, 1e-12);  // south
  EXPECT_NEAR(io::headingFromYaw(180.0), 270.0, 1e-12);  // west
  EXPECT_NEAR(io::headingFromYaw(-180.0), 270.0, 1e-12);
  EXPECT_NEAR(io::headingFromYaw(135.0), 315.0, 1e-12);  // north-west
  EXPECT_NEAR(io::headingFromYaw(450.0), 0.0, 1e-12);
  const double h = io::headingFromYaw(90.0 + 1e-14);
  EXPECT_GE(h, 0.0);
  EXPECT_LT(h, 360.0);
}

TEST(Geo, HundredMetresNorthAndEast) {
  double M = 0.0, N = 0.0;
  radii(kLat0, M, N);
  const io::GeoOrigin o{kLat0, kLon0, kAlt0};
  const io::GeoPoint north = io::enuToGeodetic(o, {0.0, 100.0, 0.0});
  EXPECT_NEAR(north.lat_deg - kLat0, 100.0 / M * 180.0 / kPi, 1e-8);
  EXPECT_NEAR(north.lat_deg - kLat0, 0.000899, 2e-6);  // the rule of thumb
  EXPECT_NEAR(north.lon_deg, kLon0, 1e-10);
  const io::GeoPoint east = io::enuToGeodetic(o, {100.0, 0.0, 0.0});
  EXPECT_NEAR(east.lon_deg - kLon0, 100.0 / (N * std::cos(kLat0 * kPi / 180.0)) * 180.0 / kPi,
              1e-8);
  const io::GeoPoint up = io::enuToGeodetic(o, {0.0, 0.0, 10.0});
  EXPECT_NEAR(up.alt_m, kAlt0 + 10.0, 1e-6);
  EXPECT_NEAR(up.lat_deg, kLat0, 1e-10);
}

TEST(Geo, OriginParsing) {
  const io::GeoOrigin o = io::parseOrigin(" 47.5, -8.25 ,488");
  EXPECT_DOUBLE_EQ(o.lat_deg, 47.5);
  EXPECT_DOUBLE_EQ(o.lon_deg, -8.25);
  EXPECT_DOUBLE_EQ(o.alt_m, 488.0);
  for (const std::string bad :
       {"47.5,8", "47.5,8,1,2", "a,b,c", "91,0,0", "0,181,0", "0,0,nan", "", "1,2,3x"}) {
    try {
      io::parseOrigin(bad);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const uavip::InputError& e) {
      EXPECT_NE(std::string(e.what()).find("'" + bad + "'"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("--origin"), std::string::npos) << e.what();
    }
  }
}

TEST(Geo, CrsTransformMatchesGeographicLibsUtm) {
  // PROJ (EPSG:32631, EPSG:32733) against GeographicLib's own UTM (Krüger series).
  const struct {
    const char* crs;
    int zone;
    bool north;
    double e, n;
  } cases[] = {{"EPSG:32631", 31, true, 500123.37, 5400456.81},
               {"EPSG:32631", 31, true, 312345.5, 6712345.25},
               {"EPSG:32733", 33, false, 654321.0, 7654321.0}};
  for (const auto& c : cases) {
    const io::CrsTransform t(c.crs);
    const io::GeoPoint g = t.toWgs84(c.e, c.n);
    double lat = 0.0, lon = 0.0;
    GeographicLib::UTMUPS::Reverse(c.zone, c.north, c.e, c.n, lat, lon);
    EXPECT_NEAR(g.lat_deg, lat, 1e-9) << c.crs;  // 1e-9 deg ≈ 0.1 mm
    EXPECT_NEAR(g.lon_deg, lon, 1e-9) << c.crs;
  }
  EXPECT_EQ(io::CrsTransform("EPSG:32631").name(), "WGS 84 / UTM zone 31N");
  // A CRS in US survey feet: metres in, divided by its unit before PROJ.
  EXPECT_NEAR(io::CrsTransform("EPSG:2263").unitToMetres(), 1200.0 / 3937.0, 1e-12);
  for (const std::string bad : {"EPSG:4326", "EPSG:99999", "no crs", ""}) {
    try {
      io::CrsTransform t(bad);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const uavip::InputError& e) {
      EXPECT_NE(std::string(e.what()).find("--crs"), std::string::npos) << e.what();
    }
  }
}

TEST(Geo, WaypointsByCrsAreRelativeToHome) {
  io::ExportOptions o;
  o.crs = std::make_shared<const io::CrsTransform>("EPSG:32631");
  o.source_offset_m = Vec3(500125.0, 5400458.0, 0.0);
  o.home_m = Vec3(-3.0, 2.0, 101.5);
  const io::GeoPoint w = io::waypointGeo(o, Vec3(1.0, -2.0, 110.0));
  double lat = 0.0, lon = 0.0;
  GeographicLib::UTMUPS::Reverse(31, true, 500126.0, 5400456.0, lat, lon);
  EXPECT_NEAR(w.lat_deg, lat, 1e-9);
  EXPECT_NEAR(w.lon_deg, lon, 1e-9);
  EXPECT_DOUBLE_EQ(w.alt_m, 8.5);  // relative to home
  const io::GeoPoint h = io::homeGeo(o);
  EXPECT_DOUBLE_EQ(h.alt_m, 101.5);  // in the cloud's height datum
  GeographicLib::UTMUPS::Reverse(31, true, 500122.0, 5400460.0, lat, lon);
  EXPECT_NEAR(h.lat_deg, lat, 1e-9);
}

TEST(Flight, SelectionOfSurfaces) {
  const json m = mission();
  // Two surfaces have a mission: no silent choice.
  try {
    io::flightFromMissionJson(m, "m.json", "");
    ADD_FAILURE() << "ambiguous selection accepted";
  } catch (const uavip::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("0, 2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("--surface"), std::string::npos) << e.what();
  }
  const io::Flight f = io::flightFromMissionJson(m, "m.json", "0");
  ASSERT_EQ(f.waypoints.size(), 3u);
  EXPECT_EQ(f.stopCount(), 2u);
  EXPECT_EQ(f.waypoints[0].stop_index, 0);
  EXPECT_EQ(f.waypoints[1].stop_index, -1);
  EXPECT_EQ(f.waypoints[2].stop_index, 1);
  // Between stops: the next stop's orientation.
  EXPECT_DOUBLE_EQ(f.waypoints[1].yaw_deg, 0.0);
  EXPECT_DOUBLE_EQ(f.waypoints[1].gimbal_pitch_deg, 5.0);
  // Several surfaces are flown by the ordered flight only, never joined here.
  EXPECT_THROW(io::flightFromMissionJson(m, "m.json", "all"), uavip::InputError);
  EXPECT_THROW(io::flightFromMissionJson(m, "m.json", "1"), io::NoMissionError);
  EXPECT_THROW(io::flightFromMissionJson(m, "m.json", "7"), uavip::InputError);
  EXPECT_THROW(io::flightFromMissionJson(m, "m.json", "x"), uavip::InputError);
  EXPECT_THROW(io::flightFromMissionJson(json{{"x", 1}}, "m.json", ""), uavip::InputError);
  // A partial surface: the skipped stop (problem set) is not on the path and not flown.
  json partial = m;
  partial["surfaces"][1] = {
      {"surface_id", 1},
      {"status", "partial"},
      {"reason", "1 of 3 stops skipped"},
      {"stops", {stop(0, 0, 1, 0, 0), stop(5, 5, 5, 0, 0), stop(2, 0, 1, 45.0, 0)}},
      {"waypoints", {{0, 0, 1}, {1, -1, 1}, {2, 0, 1}}}};
  partial["surfaces"][1]["stops"][1]["problem"] = "in_obstacle_space";
  const io::Flight pf = io::flightFromMissionJson(partial, "m.json", "1");
  ASSERT_EQ(pf.waypoints.size(), 3u);
  EXPECT_EQ(pf.stopCount(), 2u);
  EXPECT_EQ(pf.waypoints[2].stop_index, 2);
  EXPECT_DOUBLE_EQ(pf.waypoints[1].yaw_deg, 45.0);
  json moved = m;
  moved["surfaces"][0]["waypoints"][2] = {100, 1, 10};  // stop 1 is no longer on the path
  EXPECT_THROW(io::flightFromMissionJson(moved, "m.json", "0"), uavip::InputError);
}

TEST(QgcPlan, RequiredKeysAndItems) {
  const io::Flight f = io::flightFromMissionJson(mission(), "m.json", "0");
  const json plan = json::parse(io::exportFlight(f, io::ExportFormat::QgcPlan, options()));
  EXPECT_EQ(plan["fileType"], "Plan");
  EXPECT_EQ(plan["groundStation"], "QGroundControl");
  EXPECT_TRUE(plan["version"].is_number_integer());
  ASSERT_TRUE(plan["geoFence"].is_object());
  EXPECT_TRUE(plan["geoFence"]["circles"].is_array());
  EXPECT_TRUE(plan["geoFence"]["polygons"].is_array());
  EXPECT_EQ(plan["geoFence"]["version"], 2);
  EXPECT_TRUE(plan["rallyPoints"]["points"].is_array());
  EXPECT_EQ(plan["rallyPoints"]["version"], 2);
  const json& mi = plan["mission"];
  EXPECT_EQ(mi["version"], 2);
  EXPECT_EQ(mi["firmwareType"], 12);
  EXPECT_EQ(mi["vehicleType"], 2);
  EXPECT_TRUE(mi["cruiseSpeed"].is_number());
  EXPECT_TRUE(mi["hoverSpeed"].is_number());
  ASSERT_EQ(mi["plannedHomePosition"].size(), 3u);
  EXPECT_DOUBLE_EQ(mi["plannedHomePosition"][0].get<double>(), kLat0);
  EXPECT_DOUBLE_EQ(mi["plannedHomePosition"][2].get<double>(), kAlt0);

  std::map<int, int> count;
  int jump = 0;
  for (const auto& it : mi["items"]) {
    EXPECT_EQ(it["type"], "SimpleItem");
    EXPECT_TRUE(it["autoContinue"].is_boolean());
    EXPECT_EQ(it["doJumpId"], ++jump);
    ASSERT_EQ(it["params"].size(), 7u);
    for (const auto& p : it["params"]) EXPECT_TRUE(p.is_number());
    EXPECT_FALSE(it.contains("AltitudeMode"));
    ++count[it["command"].get<int>()];
    EXPECT_EQ(it["frame"], it["command"] == 16 ? 3 : 2);
  }
  EXPECT_EQ(count[16], 3);          // every waypoint
  EXPECT_EQ(count[1000], 2);        // gimbal at each stop
  EXPECT_EQ(count[2000], 2);        // one photo per stop
  EXPECT_EQ(count.count(115), 0u);  // PX4: heading in the waypoint
  EXPECT_EQ(count.size(), 3u);

  // Order at stop 0: gimbal, waypoint, photo; values from the mission.
  const json& items = mi["items"];
  EXPECT_EQ(items[0]["command"], 1000);
  EXPECT_DOUBLE_EQ(items[0]["params"][0].get<double>(), -10.0);
  EXPECT_EQ(items[1]["command"], 16);
  const json& wp = items[1]["params"];
  EXPECT_DOUBLE_EQ(wp[0].get<double>(), 2.0);   // hold at a stop
  EXPECT_NEAR(wp[3].get<double>(), 0.0, 1e-9);  // yaw 90 (north) → heading 0
  double M = 0.0, N = 0.0;
  radii(kLat0, M, N);
  EXPECT_NEAR(wp[4].get<double>() - kLat0, 100.0 / M * 180.0 / kPi, 1e-8);
  EXPECT_NEAR(wp[5].get<double>(), kLon0, 1e-9);
  EXPECT_NEAR(wp[6].get<double>(), 10.0, 1e-3);  // relative to home
  EXPECT_EQ(items[2]["command"], 2000);
  EXPECT_DOUBLE_EQ(items[2]["params"][2].get<double>(), 1.0);  // one photo
  EXPECT_DOUBLE_EQ(items[2]["params"][3].get<double>(), 1.0);  // sequence 1
  // The in-between waypoint: no hold, heading of the next stop (yaw 0 → 90).
  EXPECT_EQ(items[3]["command"], 16);
  EXPECT_DOUBLE_EQ(items[3]["params"][0].get<double>(), 0.0);
  EXPECT_NEAR(items[3]["params"][3].get<double>(), 90.0, 1e-9);
  // The second stop is 100 m east.
  EXPECT_NEAR(items[5]["params"][5].get<double>() - kLon0,
              100.0 / (N * std::cos(kLat0 * kPi / 180.0)) * 180.0 / kPi, 1e-8);
  EXPECT_DOUBLE_EQ(items[6]["params"][3].get<double>(), 2.0);  // photo 2
}

TEST(QgcPlan, ArduPilotGetsConditionYaw) {
  const io::Flight f = io::flightFromMissionJson(mission(), "m.json", "2");
  const json plan = io::toQgcPlan(f, options(io::Autopilot::ArduPilot));
  EXPECT_EQ(plan["mission"]["firmwareType"], 3);
  const json& items = plan["mission"]["items"];
  ASSERT_EQ(items.size(), 4u);  // yaw, gimbal, waypoint, photo
  EXPECT_EQ(items[0]["command"], 115);
  EXPECT_NEAR(items[0]["params"][0].get<double>(), 180.0, 1e-9);  // yaw −90 (south)
  EXPECT_DOUBLE_EQ(items[1]["params"][0].get<double>(), -90.0);   // straight down
}

TEST(Wpl, TwelveTabSeparatedFieldsAndHomeFirst) {
  const io::Flight f = io::flightFromMissionJson(mission(), "m.json", "0");
  const auto opts = options();
  const auto lines = split(io::toWpl(f, opts), '\n');
  ASSERT_GE(lines.size(), 2u);
  EXPECT_EQ(lines[0], "QGC WPL 110");
  const auto items = io::missionItems(f, opts);
  ASSERT_EQ(lines.size(), items.size() + 2);  // header + home + items
  std::map<int, int> count;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const auto fields = split(lines[i], '\t');
    ASSERT_EQ(fields.size(), 12u) << lines[i];
    EXPECT_EQ(std::stoi(fields[0]), static_cast<int>(i - 1));
    EXPECT_EQ(fields[11], "1");
    if (i == 1) {  // home: current, absolute frame, origin
      EXPECT_EQ(fields[1], "1");
      EXPECT_EQ(fields[2], "0");
      EXPECT_EQ(fields[3], "16");
      EXPECT_NEAR(std::stod(fields[8]), kLat0, 1e-12);
      EXPECT_NEAR(std::stod(fields[9]), kLon0, 1e-12);
      EXPECT_NEAR(std::stod(fields[10]), kAlt0, 1e-9);
      continue;
    }
    EXPECT_EQ(fields[1], "0");
    ++count[std::stoi(fields[3])];
  }
  EXPECT_EQ(count[16], 3);
  EXPECT_EQ(count[1000], 2);
  EXPECT_EQ(count[2000], 2);
  // The first waypoint (line 3: home, gimbal, waypoint) 100 m north.
  const auto wp = split(lines[3], '\t');
  double M = 0.0, N = 0.0;
  radii(kLat0, M, N);
  EXPECT_EQ(wp[3], "16");
  EXPECT_NEAR(std::stod(wp[8]) - kLat0, 100.0 / M * 180.0 / kPi, 1e-8);
  EXPECT_NEAR(std::stod(wp[10]), 10.0, 1e-3);
}

TEST(Csv, OneRowPerWaypointWithBothFrames) {
  const io::Flight f = io::sortiesFromMissionJson(mission(), "m.json").at(0);
  const auto lines = split(io::toCsv(f, options()), '\n');
  ASSERT_EQ(lines.size(), 1 + f.waypoints.size());
  const auto header = split(lines[0], ',');
  std::map<std::string, std::size_t> col;
  for (std::size_t i = 0; i < header.size(); ++i) col[header[i]] = i;
  for (const char* k : {"east_m", "north_m", "up_m", "lat_deg", "lon_deg", "alt_rel_home_m",
                        "is_stop", "yaw_enu_deg", "heading_deg", "gimbal_pitch_deg", "surface_id"})
    ASSERT_TRUE(col.count(k)) << k;
  int stops = 0;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const auto r = split(lines[i], ',');
    ASSERT_EQ(r.size(), header.size());
    stops += std::stoi(r[col["is_stop"]]);
  }
  EXPECT_EQ(stops, 3);
  const auto first = split(lines[1], ',');
  double M = 0.0, N = 0.0;
  radii(kLat0, M, N);
  EXPECT_NEAR(std::stod(first[col["north_m"]]), 100.0, 1e-9);
  EXPECT_NEAR(std::stod(first[col["lat_deg"]]) - kLat0, 100.0 / M * 180.0 / kPi, 2e-9);
  EXPECT_NEAR(std::stod(first[col["heading_deg"]]), 0.0, 1e-9);
  const auto last = split(lines.back(), ',');
  EXPECT_EQ(last[col["surface_id"]], "2");
  EXPECT_NEAR(std::stod(last[col["heading_deg"]]), 180.0, 1e-9);
  EXPECT_NEAR(std::stod(last[col["gimbal_pitch_deg"]]), -90.0, 1e-9);
}

TEST(Flight, SortiesOfTheOrderedFlight) {
  json m = mission();
  const auto sorties = io::sortiesFromMissionJson(m, "m.json");
  ASSERT_EQ(sorties.size(), 1u);
  const io::Flight& f = sorties[0];
  EXPECT_EQ(f.sortie, 1);
  EXPECT_EQ(f.surface_ids, (std::vector<int>{0, 2}));
  ASSERT_EQ(f.waypoints.size(), 5u);
  EXPECT_EQ(f.stopCount(), 3u);
  EXPECT_EQ(f.waypoints[3].surface_id, 2);
  EXPECT_EQ(f.waypoints[3].stop_index, 0);
  // Between stops: the next stop's orientation; back home: the last stop's.
  EXPECT_DOUBLE_EQ(f.waypoints[1].gimbal_pitch_deg, 5.0);
  EXPECT_DOUBLE_EQ(f.waypoints[4].gimbal_pitch_deg, -90.0);
  // A stop moved off its waypoint, a missing flight, a failed flight.
  json moved = m;
  moved["flight"]["sorties"][0]["waypoints"][2] = {100, 0, 11};
  EXPECT_THROW(io::sortiesFromMissionJson(moved, "m.json"), uavip::InputError);
  json old = m;
  old.erase("flight");
  EXPECT_THROW(io::sortiesFromMissionJson(old, "m.json"), uavip::InputError);
  json failed = m;
  failed["flight"]["status"] = "failed";
  EXPECT_THROW(io::sortiesFromMissionJson(failed, "m.json"), io::NoMissionError);
  json bad = m;
  bad["flight"]["sorties"][0]["stops"][1]["waypoint"] = 0;  // not after the previous stop
  EXPECT_THROW(io::sortiesFromMissionJson(bad, "m.json"), uavip::InputError);
}

TEST(Export, FormatAndOptionsAreChecked) {
  EXPECT_EQ(io::parseExportFormat("wpl"), io::ExportFormat::Wpl);
  EXPECT_THROW(io::parseExportFormat("kml"), uavip::InputError);
  EXPECT_THROW(io::parseAutopilot("inav"), uavip::InputError);
  io::ExportOptions o = options();
  o.speed_m_s = 0.0;
  EXPECT_THROW(o.validate(), uavip::InputError);
  o = options();
  o.hold_s = -1.0;
  EXPECT_THROW(o.validate(), uavip::InputError);
}

}  // namespace
