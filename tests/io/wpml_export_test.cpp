// io/wpml_export.h and io/map_export.h against independent references: every KMZ is
// opened here with minizip and parsed with TinyXML-2 (not io::readKmzRoute), each
// waypoint is converted back with GeographicLib's LocalCartesian about an origin whose
// geoid height is NGA's published EGM96 value, and compared with the flight (≤ 2 cm);
// the WPML elements a route needs are checked against the enumerations DJI documents.

#include "uavip/io/wpml_export.h"

#include <gtest/gtest.h>
#include <tinyxml2.h>
#include <unistd.h>
#include <unzip.h>

#include <GeographicLib/LocalCartesian.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "uavip/core/error.h"
#include "uavip/io/map_export.h"

namespace {

namespace fs = std::filesystem;
namespace io = uavip::io;
using tinyxml2::XMLElement;
using uavip::Vec3;

// NGA's first EGM96 check point and its published geoid height [m].
constexpr double kLat0 = 38.6281550, kLon0 = 269.7791550 - 360.0, kN0 = -31.628;
constexpr double kAltMsl = 150.0;

/// A flight of a few legs: home, three photo stops (one looking down), a leg between, home.
io::Flight sampleFlight() {
  io::Flight f;
  f.sortie = 1;
  f.surface_ids = {3};
  const auto wp = [](Vec3 p, int stop, double yaw, double pitch) {
    io::FlightWaypoint w;
    w.surface_id = 3;
    w.stop_index = stop;
    w.enu = p;
    w.yaw_deg = yaw;
    w.gimbal_pitch_deg = pitch;
    return w;
  };
  f.waypoints = {wp({0, 0, 2}, -1, 90, 0),        wp({20, 5, 12.5}, 0, 180, 0),
                 wp({20, 8, 12.5}, 1, 180, -30),  wp({35.5, -40, 30}, -1, -90, -90),
                 wp({36, -41, 30}, 12, -90, -90), wp({0, 0, 2}, -1, 90, 0)};
  return f;
}

std::string tempPath(const std::string& name) {
  return (fs::temp_directory_path() / ("uavip_wpml_" + std::to_string(::getpid()) + "_" + name))
      .string();
}

/// The entries of a zip, read with minizip here.
std::map<std::string, std::string> unzipAll(const std::string& path) {
  std::map<std::string, std::string> out;
  unzFile z = unzOpen64(path.c_str());
  EXPECT_NE(z, nullptr) << path;
  if (z == nullptr) return out;
  for (int r = unzGoToFirstFile(z); r == UNZ_OK; r = unzGoToNextFile(z)) {
    char name[256];
    unz_file_info64 info{};
    unzGetCurrentFileInfo64(z, &info, name, sizeof name, nullptr, 0, nullptr, 0);
    std::string text(static_cast<std::size_t>(info.uncompressed_size), '\0');
    unzOpenCurrentFile(z);
    unzReadCurrentFile(z, text.data(), static_cast<unsigned>(text.size()));
    unzCloseCurrentFile(z);
    out[name] = text;
  }
  unzClose(z);
  return out;
}

const XMLElement* need(const XMLElement* e, const char* name) {
  const XMLElement* c = e != nullptr ? e->FirstChildElement(name) : nullptr;
  EXPECT_NE(c, nullptr) << "missing <" << name << ">";
  return c;
}

std::string text(const XMLElement* e, const char* name) {
  const XMLElement* c = need(e, name);
  return c != nullptr && c->GetText() != nullptr ? c->GetText() : "";
}

double num(const XMLElement* e, const char* name) { return std::stod(text(e, name)); }

bool oneOf(const std::string& v, const std::set<std::string>& legal) { return legal.count(v) != 0; }

/// The missionConfig elements DJI marks required, with legal values.
void checkMissionConfig(const XMLElement* doc, const io::DjiDrone& d) {
  const XMLElement* mc = need(doc, "wpml:missionConfig");
  EXPECT_TRUE(oneOf(text(mc, "wpml:flyToWaylineMode"), {"safely", "pointToPoint"}));
  EXPECT_TRUE(oneOf(text(mc, "wpml:finishAction"),
                    {"goHome", "noAction", "autoLand", "gotoFirstWaypoint"}));
  EXPECT_TRUE(oneOf(text(mc, "wpml:exitOnRCLost"), {"goContinue", "executeLostAction"}));
  EXPECT_TRUE(oneOf(text(mc, "wpml:executeRCLostAction"), {"goBack", "landing", "hover"}));
  const double security = num(mc, "wpml:takeOffSecurityHeight");
  EXPECT_GE(security, 1.2);
  EXPECT_LE(security, 1500.0);
  EXPECT_GT(num(mc, "wpml:globalTransitionalSpeed"), 0.0);
  EXPECT_EQ(num(need(mc, "wpml:droneInfo"), "wpml:droneEnumValue"), d.drone_enum);
  EXPECT_EQ(num(need(mc, "wpml:droneInfo"), "wpml:droneSubEnumValue"), d.drone_sub_enum);
  EXPECT_EQ(num(need(mc, "wpml:payloadInfo"), "wpml:payloadEnumValue"), d.payload.payload_enum);
  EXPECT_EQ(num(need(mc, "wpml:payloadInfo"), "wpml:payloadPositionIndex"),
            d.payload.position_index);
}

struct ReadBack {
  std::string height_mode;
  std::vector<Vec3> local;  ///< each Placemark converted back by GeographicLib here
};

/// Checks waylines.wpml element by element and converts its waypoints back.
ReadBack checkWaylines(const std::string& xml, const io::Flight& f, const io::DjiDrone& d,
                       const GeographicLib::LocalCartesian& lc, double home_h) {
  tinyxml2::XMLDocument doc;
  EXPECT_EQ(doc.Parse(xml.c_str()), tinyxml2::XML_SUCCESS);
  const XMLElement* kml = doc.FirstChildElement("kml");
  EXPECT_STREQ(kml->Attribute("xmlns"), "http://www.opengis.net/kml/2.2");
  EXPECT_STREQ(kml->Attribute("xmlns:wpml"), "http://www.dji.com/wpmz/1.0.6");
  const XMLElement* document = need(kml, "Document");
  checkMissionConfig(document, d);
  const XMLElement* folder = need(document, "Folder");
  ReadBack out;
  out.height_mode = text(folder, "wpml:executeHeightMode");
  EXPECT_TRUE(oneOf(out.height_mode, {"WGS84", "relativeToStartPoint"}));
  EXPECT_EQ(num(folder, "wpml:templateId"), 0);
  EXPECT_EQ(num(folder, "wpml:waylineId"), 0);
  EXPECT_GT(num(folder, "wpml:autoFlightSpeed"), 0.0);
  int index = 0;
  for (const XMLElement* pm = folder->FirstChildElement("Placemark"); pm != nullptr;
       pm = pm->NextSiblingElement("Placemark"), ++index) {
    EXPECT_EQ(num(pm, "wpml:index"), index);  // consecutive from 0
    double lon = 0.0, lat = 0.0;
    EXPECT_EQ(std::sscanf(text(need(pm, "Point"), "coordinates").c_str(), "%lf,%lf", &lon, &lat),
              2);
    const double h =
        num(pm, "wpml:executeHeight") + (out.height_mode == "relativeToStartPoint" ? home_h : 0.0);
    Vec3 p;
    lc.Forward(lat, lon, h, p.x(), p.y(), p.z());
    out.local.push_back(p);
    EXPECT_GT(num(pm, "wpml:waypointSpeed"), 0.0);
    const XMLElement* heading = need(pm, "wpml:waypointHeadingParam");
    EXPECT_TRUE(oneOf(text(heading, "wpml:waypointHeadingMode"),
                      {"followWayline", "manually", "fixed", "smoothTransition", "towardPOI"}));
    const double angle = num(heading, "wpml:waypointHeadingAngle");
    EXPECT_GE(angle, -180.0);
    EXPECT_LE(angle, 180.0);
    // Every waypoint stops, legs straight: flown as validated.
    EXPECT_EQ(text(need(pm, "wpml:waypointTurnParam"), "wpml:waypointTurnMode"),
              "toPointAndStopWithDiscontinuityCurvature");
    const io::FlightWaypoint& w = f.waypoints[static_cast<std::size_t>(index)];
    const XMLElement* group = pm->FirstChildElement("wpml:actionGroup");
    EXPECT_EQ(group != nullptr, w.isStop()) << "waypoint " << index;
    if (group == nullptr) continue;
    EXPECT_EQ(num(group, "wpml:actionGroupStartIndex"), index);
    EXPECT_EQ(num(group, "wpml:actionGroupEndIndex"), index);
    EXPECT_EQ(text(need(group, "wpml:actionTrigger"), "wpml:actionTriggerType"), "reachPoint");
    std::vector<std::string> funcs;
    for (const XMLElement* a = group->FirstChildElement("wpml:action"); a != nullptr;
         a = a->NextSiblingElement("wpml:action")) {
      funcs.push_back(text(a, "wpml:actionActuatorFunc"));
      const XMLElement* p = need(a, "wpml:actionActuatorFuncParam");
      if (funcs.back() == "rotateYaw") {
        // The compass heading of the stop: 90 - ENU yaw, in [-180, 180].
        double want = std::fmod(90.0 - w.yaw_deg + 720.0, 360.0);
        if (want > 180.0) want -= 360.0;
        EXPECT_NEAR(num(p, "wpml:aircraftHeading"), want, 0.01);
        EXPECT_TRUE(oneOf(text(p, "wpml:aircraftPathMode"), {"clockwise", "counterClockwise"}));
      } else if (funcs.back() == "gimbalRotate") {
        const double pitch = num(p, "wpml:gimbalPitchRotateAngle");
        EXPECT_NEAR(pitch, w.gimbal_pitch_deg, 0.01);
        EXPECT_GE(pitch, d.payload.pitch_min_deg);
        EXPECT_LE(pitch, d.payload.pitch_max_deg);
        EXPECT_EQ(text(p, "wpml:gimbalRotateMode"), "absoluteAngle");
      } else if (funcs.back() == "takePhoto") {
        EXPECT_EQ(text(p, "wpml:fileSuffix"), io::stopId(w));
      } else if (funcs.back() == "hover") {
        EXPECT_GT(num(p, "wpml:hoverTime"), 0.0);
      }
    }
    EXPECT_EQ(funcs, (std::vector<std::string>{"rotateYaw", "gimbalRotate", "hover", "takePhoto"}));
  }
  EXPECT_EQ(static_cast<std::size_t>(index), f.waypoints.size());
  return out;
}

class Wpml : public ::testing::TestWithParam<const char*> {};

TEST_P(Wpml, EveryWaypointReadsBackWithin2CmInBothHeightModes) {
  const io::DjiDrone drone = io::findDjiDrone(GetParam());
  const io::Georeference geo(io::GeoOrigin{kLat0, kLon0, kAltMsl});
  // The origin's ellipsoidal height from NGA's published geoid height, not from uavip.
  const double h0 = kAltMsl + kN0;
  const GeographicLib::LocalCartesian lc(kLat0, kLon0, h0);
  const io::Flight f = sampleFlight();
  for (const auto mode : {io::WpmlHeightMode::Relative, io::WpmlHeightMode::Ellipsoid}) {
    io::WpmlOptions o;
    o.drone = drone;
    o.height_mode = mode;
    const std::string path = tempPath(drone.name + ".kmz");
    io::writeKmz(path, io::wpmlDocuments(f, geo, Vec3::Zero(), o));
    const auto entries = unzipAll(path);
    ASSERT_EQ(entries.size(), 2u);
    ASSERT_TRUE(entries.count("wpmz/template.kml"));
    ASSERT_TRUE(entries.count("wpmz/waylines.wpml"));
    const ReadBack back = checkWaylines(entries.at("wpmz/waylines.wpml"), f, drone, lc, h0);
    EXPECT_EQ(back.height_mode,
              mode == io::WpmlHeightMode::Relative ? "relativeToStartPoint" : "WGS84");
    ASSERT_EQ(back.local.size(), f.waypoints.size());
    for (std::size_t i = 0; i < back.local.size(); ++i) {
      const Vec3 d = back.local[i] - f.waypoints[i].enu;
      EXPECT_LE(d.head<2>().norm(), 0.02) << "horizontal, waypoint " << i;
      EXPECT_LE(std::abs(d.z()), 0.02) << "vertical, waypoint " << i;
    }
    // uavip's own reader agrees with this one.
    const uavip::PointList own = io::routeToLocal(io::readKmzRoute(path), geo, Vec3::Zero());
    for (std::size_t i = 0; i < own.size(); ++i) EXPECT_LT((own[i] - back.local[i]).norm(), 0.05);
    // template.kml: a waypoint template with both heights of each waypoint.
    tinyxml2::XMLDocument t;
    ASSERT_EQ(t.Parse(entries.at("wpmz/template.kml").c_str()), tinyxml2::XML_SUCCESS);
    const XMLElement* folder = need(need(t.FirstChildElement("kml"), "Document"), "Folder");
    EXPECT_EQ(text(folder, "wpml:templateType"), "waypoint");
    EXPECT_EQ(text(need(folder, "wpml:waylineCoordinateSysParam"), "wpml:heightMode"),
              mode == io::WpmlHeightMode::Relative ? "relativeToStartPoint" : "EGM96");
    int n = 0;
    for (const XMLElement* pm = folder->FirstChildElement("Placemark"); pm != nullptr;
         pm = pm->NextSiblingElement("Placemark"), ++n) {
      const double h_ell = num(pm, "wpml:ellipsoidHeight");
      const double h = num(pm, "wpml:height");
      // EGM96 height = ellipsoidal − N (NGA's N at the origin; the site spans 100 m).
      EXPECT_NEAR(mode == io::WpmlHeightMode::Relative ? h + h0 : h + kN0, h_ell, 0.05);
    }
    EXPECT_EQ(static_cast<std::size_t>(n), f.waypoints.size());
    fs::remove(path);
  }
}

INSTANTIATE_TEST_SUITE_P(EveryDrone, Wpml,
                         ::testing::Values("m300", "m350", "m30", "m30t", "m3e", "m3t", "m4e",
                                           "m4t"));

TEST(WpmlLimits, APitchBeyondTheGimbalAnUnknownDroneAndBadOptionsAreRefused) {
  const io::Georeference geo(io::GeoOrigin{kLat0, kLon0, kAltMsl});
  io::Flight f = sampleFlight();
  f.waypoints[2].gimbal_pitch_deg = -100.0;  // the Mavic 3E reaches -90
  io::WpmlOptions o;
  o.drone = io::findDjiDrone("m3e");
  try {
    io::wpmlDocuments(f, geo, Vec3::Zero(), o);
    ADD_FAILURE() << "a pitch of -100 was written for the M3E";
  } catch (const uavip::InputError& e) {
    EXPECT_NE(std::string(e.what()).find(io::stopId(f.waypoints[2])), std::string::npos)
        << e.what();
  }
  o.drone = io::findDjiDrone("m350");  // the H20 reaches -120
  EXPECT_NO_THROW(io::wpmlDocuments(f, geo, Vec3::Zero(), o));
  try {
    io::findDjiDrone("phantom4");
    ADD_FAILURE();
  } catch (const uavip::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("m4t"), std::string::npos) << e.what();
  }
  // An M350 with the H30 reaches +60, the H20T only +30 (PSDK gimbal limits).
  f.waypoints[2].gimbal_pitch_deg = 50.0;
  o.drone = io::findDjiDrone("m350", "h30");
  EXPECT_EQ(o.drone.payload.payload_enum, 82);
  EXPECT_NO_THROW(io::wpmlDocuments(f, geo, Vec3::Zero(), o));
  o.drone = io::findDjiDrone("m350", "h20t");
  EXPECT_THROW(io::wpmlDocuments(f, geo, Vec3::Zero(), o), uavip::InputError);
  EXPECT_THROW(io::findDjiDrone("m3e", "h30"), uavip::InputError);
  EXPECT_THROW(io::findDjiDrone("m300", "p1"), uavip::InputError);
  o.takeoff_security_height_m = 0.5;
  EXPECT_THROW(o.validate(), uavip::InputError);
}

TEST(WpmlLimits, ALongFlightIsSplitIntoRoutesThatJoinWithoutLosingAStop) {
  io::Flight f;
  f.sortie = 2;
  for (int i = 0; i < 11; ++i) {
    io::FlightWaypoint w;
    w.enu = Vec3(i, 0.0, 5.0);
    w.stop_index = i % 2 == 1 ? i : -1;
    f.waypoints.push_back(w);
  }
  const std::vector<io::Flight> parts = io::splitForWpml(f, 4);
  ASSERT_EQ(parts.size(), 4u);  // 0-3, 3-6, 6-9, 9-10
  std::size_t stops = 0;
  for (std::size_t k = 0; k < parts.size(); ++k) {
    EXPECT_LE(parts[k].waypoints.size(), 4u);
    if (k > 0) {
      EXPECT_EQ(parts[k].waypoints.front().enu, parts[k - 1].waypoints.back().enu);  // joined
    }
    stops += parts[k].stopCount();
  }
  EXPECT_EQ(stops, f.stopCount());  // each photo once
  EXPECT_EQ(parts.back().waypoints.back().enu, f.waypoints.back().enu);
  EXPECT_EQ(io::splitForWpml(f, 11).size(), 1u);
}

TEST(WpmlLimits, TheSameFlightGivesTheSameBytes) {
  const io::Georeference geo(io::GeoOrigin{kLat0, kLon0, kAltMsl});
  io::WpmlOptions o;
  o.drone = io::findDjiDrone("m30t");
  const auto docs = io::wpmlDocuments(sampleFlight(), geo, Vec3::Zero(), o);
  const std::string a = tempPath("a.kmz"), b = tempPath("b.kmz");
  io::writeKmz(a, docs);
  io::writeKmz(b, docs);
  std::ifstream fa(a, std::ios::binary), fb(b, std::ios::binary);
  const std::string sa((std::istreambuf_iterator<char>(fa)), {});
  const std::string sb((std::istreambuf_iterator<char>(fb)), {});
  EXPECT_FALSE(sa.empty());
  EXPECT_EQ(sa, sb);
  fs::remove(a);
  fs::remove(b);
}

TEST(MapExport, KmlAndGeoJsonParseAndPutEveryWaypointWhereItIs) {
  const io::Georeference geo(io::GeoOrigin{kLat0, kLon0, kAltMsl});
  const double h0 = kAltMsl + kN0;
  const GeographicLib::LocalCartesian lc(kLat0, kLon0, h0);
  const std::vector<io::Flight> flights = {sampleFlight()};
  // GeoJSON: [lon, lat, h above the ellipsoid] (RFC 7946 §4).
  const nlohmann::json gj =
      nlohmann::json::parse(io::flightsGeoJson(flights, geo, Vec3::Zero(), "site").dump());
  EXPECT_EQ(gj["type"], "FeatureCollection");
  std::size_t lines = 0, stops = 0;
  for (const auto& feature : gj["features"]) {
    const auto& g = feature["geometry"];
    if (g["type"] == "LineString") {
      ++lines;
      ASSERT_EQ(g["coordinates"].size(), flights[0].waypoints.size());
      for (std::size_t i = 0; i < g["coordinates"].size(); ++i) {
        const auto& c = g["coordinates"][i];
        Vec3 p;
        lc.Forward(c[1].get<double>(), c[0].get<double>(), c[2].get<double>(), p.x(), p.y(), p.z());
        EXPECT_LT((p - flights[0].waypoints[i].enu).norm(), 0.05) << i;
      }
    } else if (feature["properties"]["kind"] == "stop") {
      ++stops;
      EXPECT_TRUE(feature["properties"].contains("heading_deg"));
      EXPECT_TRUE(feature["properties"].contains("gimbal_pitch_deg"));
      EXPECT_EQ(g["coordinates"].size(), 3u);
    }
  }
  EXPECT_EQ(lines, 1u);
  EXPECT_EQ(stops, flights[0].stopCount());
  // KML: absolute altitudes above EGM96 = h_ellipsoid − N.
  tinyxml2::XMLDocument kml;
  ASSERT_EQ(kml.Parse(io::flightsKml(flights, geo, Vec3::Zero(), "site").c_str()),
            tinyxml2::XML_SUCCESS);
  const XMLElement* folder = need(need(kml.FirstChildElement("kml"), "Document"), "Folder");
  const XMLElement* line = need(need(folder, "Placemark"), "LineString");
  EXPECT_EQ(text(line, "altitudeMode"), "absolute");
  std::istringstream coords(text(line, "coordinates"));
  std::size_t i = 0;
  for (std::string tuple; coords >> tuple; ++i) {
    double lon = 0.0, lat = 0.0, alt = 0.0;
    ASSERT_EQ(std::sscanf(tuple.c_str(), "%lf,%lf,%lf", &lon, &lat, &alt), 3);
    Vec3 p;
    lc.Forward(lat, lon, alt + kN0, p.x(), p.y(), p.z());
    EXPECT_LT((p - flights[0].waypoints[i].enu).norm(), 0.05) << i;
  }
  EXPECT_EQ(i, flights[0].waypoints.size());
}

}  // namespace
