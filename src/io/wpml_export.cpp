#include "uavip/io/wpml_export.h"

#include <tinyxml2.h>
#include <unzip.h>
#include <zip.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <sstream>

#include "uavip/core/error.h"
#include "uavip/core/text.h"

namespace uavip::io {
namespace {

constexpr const char* kKmlNamespace = "http://www.opengis.net/kml/2.2";
constexpr const char* kWpmlNamespace = "http://www.dji.com/wpmz/1.0.6";
constexpr const char* kTemplatePath = "wpmz/template.kml";
constexpr const char* kWaylinesPath = "wpmz/waylines.wpml";
/// Coordinates to 1e-9° (0.1 mm), heights to 1 mm: far below the 2 cm round trip.
constexpr int kDegDecimals = 9;
constexpr int kHeightDecimals = 3;

/// A compass heading [0, 360) as WPML's angle in [-180, 180].
double wpmlHeading(double yaw_enu_deg) {
  const double h = headingFromYaw(yaw_enu_deg);
  return h > 180.0 ? h - 360.0 : h;
}

/// Everything of one waypoint the two documents need.
struct Placed {
  Geodetic g;
  double execute_height{0.0};   ///< what the aircraft flies to [m]
  double template_height{0.0};  ///< EGM96 or relative height, for the template [m]
  double heading{0.0};          ///< [-180, 180] [deg]
};

std::vector<Placed> place(const Flight& flight, const Georeference& geo, const Vec3& home,
                          const WpmlOptions& o) {
  const double home_h = geo.toGeodetic(home).h_ellipsoid_m;
  std::vector<Placed> out;
  out.reserve(flight.waypoints.size());
  for (const auto& w : flight.waypoints) {
    Placed p;
    p.g = geo.toGeodetic(w.enu);
    const bool relative = o.height_mode == WpmlHeightMode::Relative;
    p.execute_height = relative ? p.g.h_ellipsoid_m - home_h : p.g.h_ellipsoid_m;
    p.template_height = relative ? p.execute_height : geo.egm96Height(p.g);
    p.heading = wpmlHeading(w.yaw_deg);
    out.push_back(p);
  }
  return out;
}

/// The missionConfig element, the same in both documents.
void missionConfig(std::ostringstream& os, const Flight& flight, const Georeference& geo,
                   const Vec3& home, const WpmlOptions& o) {
  const DjiDrone& d = o.drone;
  os << "    <wpml:missionConfig>\n"
     << "      <wpml:flyToWaylineMode>safely</wpml:flyToWaylineMode>\n"
     << "      <wpml:finishAction>goHome</wpml:finishAction>\n"
     << "      <wpml:exitOnRCLost>executeLostAction</wpml:exitOnRCLost>\n"
     << "      <wpml:executeRCLostAction>goBack</wpml:executeRCLostAction>\n"
     << "      <wpml:takeOffSecurityHeight>" << formatFixed(o.takeoff_security_height_m, 1)
     << "</wpml:takeOffSecurityHeight>\n";
  if (d.take_off_ref_point && !flight.waypoints.empty()) {
    const Geodetic h = geo.toGeodetic(home);
    os << "      <wpml:takeOffRefPoint>" << formatFixed(h.lat_deg, kDegDecimals) << ","
       << formatFixed(h.lon_deg, kDegDecimals) << ","
       << formatFixed(h.h_ellipsoid_m, kHeightDecimals) << "</wpml:takeOffRefPoint>\n";
  }
  os << "      <wpml:globalTransitionalSpeed>" << formatFixed(o.speed_m_s, 2)
     << "</wpml:globalTransitionalSpeed>\n"
     << "      <wpml:droneInfo>\n"
     << "        <wpml:droneEnumValue>" << d.drone_enum << "</wpml:droneEnumValue>\n"
     << "        <wpml:droneSubEnumValue>" << d.drone_sub_enum << "</wpml:droneSubEnumValue>\n"
     << "      </wpml:droneInfo>\n"
     << "      <wpml:payloadInfo>\n"
     << "        <wpml:payloadEnumValue>" << d.payload.payload_enum << "</wpml:payloadEnumValue>\n"
     << "        <wpml:payloadSubEnumValue>0</wpml:payloadSubEnumValue>\n"
     << "        <wpml:payloadPositionIndex>" << d.payload.position_index
     << "</wpml:payloadPositionIndex>\n"
     << "      </wpml:payloadInfo>\n"
     << "    </wpml:missionConfig>\n";
}

/// The heading and turn of a waypoint (both documents): turn smoothly to the
/// waypoint's heading on the way; stop at the point (straight legs).
void headingAndTurn(std::ostringstream& os, double heading) {
  os << "        <wpml:waypointHeadingParam>\n"
     << "          <wpml:waypointHeadingMode>smoothTransition</wpml:waypointHeadingMode>\n"
     << "          <wpml:waypointHeadingAngle>" << formatFixed(heading, 2)
     << "</wpml:waypointHeadingAngle>\n"
     << "          <wpml:waypointPoiPoint>0.000000,0.000000,0.000000</wpml:waypointPoiPoint>\n"
     << "          <wpml:waypointHeadingPathMode>followBadArc</wpml:waypointHeadingPathMode>\n"
     << "        </wpml:waypointHeadingParam>\n"
     << "        <wpml:waypointTurnParam>\n"
     << "          <wpml:waypointTurnMode>toPointAndStopWithDiscontinuityCurvature</"
        "wpml:waypointTurnMode>\n"
     << "          <wpml:waypointTurnDampingDist>0</wpml:waypointTurnDampingDist>\n"
     << "        </wpml:waypointTurnParam>\n";
}

/// One action of an action group.
void action(std::ostringstream& os, int id, const char* func, const std::string& params) {
  os << "          <wpml:action>\n"
     << "            <wpml:actionId>" << id << "</wpml:actionId>\n"
     << "            <wpml:actionActuatorFunc>" << func << "</wpml:actionActuatorFunc>\n"
     << "            <wpml:actionActuatorFuncParam>\n"
     << params << "            </wpml:actionActuatorFuncParam>\n"
     << "          </wpml:action>\n";
}

std::string param(const char* name, const std::string& value) {
  return std::string("              <wpml:") + name + ">" + value + "</wpml:" + name + ">\n";
}

/// The photo stop's action group: yaw, gimbal pitch, hover, photo.
void stopActions(std::ostringstream& os, int group, int index, const FlightWaypoint& w,
                 double heading, double previous_heading, const WpmlOptions& o) {
  double turn = std::fmod(heading - previous_heading, 360.0);
  if (turn > 180.0) turn -= 360.0;
  if (turn <= -180.0) turn += 360.0;
  const std::string position = std::to_string(o.drone.payload.position_index);
  os << "        <wpml:actionGroup>\n"
     << "          <wpml:actionGroupId>" << group << "</wpml:actionGroupId>\n"
     << "          <wpml:actionGroupStartIndex>" << index << "</wpml:actionGroupStartIndex>\n"
     << "          <wpml:actionGroupEndIndex>" << index << "</wpml:actionGroupEndIndex>\n"
     << "          <wpml:actionGroupMode>sequence</wpml:actionGroupMode>\n"
     << "          <wpml:actionTrigger>\n"
     << "            <wpml:actionTriggerType>reachPoint</wpml:actionTriggerType>\n"
     << "          </wpml:actionTrigger>\n";
  action(os, 0, "rotateYaw",
         param("aircraftHeading", formatFixed(heading, 2)) +
             param("aircraftPathMode", turn >= 0.0 ? "clockwise" : "counterClockwise"));
  action(os, 1, "gimbalRotate",
         param("gimbalHeadingYawBase", "aircraft") + param("gimbalRotateMode", "absoluteAngle") +
             param("gimbalPitchRotateEnable", "1") +
             param("gimbalPitchRotateAngle", formatFixed(w.gimbal_pitch_deg, 2)) +
             param("gimbalRollRotateEnable", "0") + param("gimbalRollRotateAngle", "0") +
             param("gimbalYawRotateEnable", "0") + param("gimbalYawRotateAngle", "0") +
             param("gimbalRotateTimeEnable", "0") + param("gimbalRotateTime", "0") +
             param("payloadPositionIndex", position));
  action(os, 2, "hover", param("hoverTime", formatFixed(o.hold_s, 1)));
  action(os, 3, "takePhoto",
         param("payloadPositionIndex", position) + param("fileSuffix", stopId(w)) +
             param("payloadLensIndex", "wide") + param("useGlobalPayloadLensIndex", "0"));
  os << "        </wpml:actionGroup>\n";
}

void header(std::ostringstream& os) {
  os << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
     << "<kml xmlns=\"" << kKmlNamespace << "\" xmlns:wpml=\"" << kWpmlNamespace << "\">\n"
     << "  <Document>\n";
}

/// Pitch within the drone's gimbal, else InputError naming the stop.
void requireReachablePitch(const Flight& flight, const DjiDrone& d) {
  for (const auto& w : flight.waypoints) {
    if (!w.isStop()) continue;
    if (!aircraft::pitchWithin(w.gimbal_pitch_deg, d.payload.pitch_min_deg,
                               d.payload.pitch_max_deg))
      throw InputError("--drone " + d.name + ": photo stop " + stopId(w) + " needs gimbal pitch " +
                       formatFixed(w.gimbal_pitch_deg, 1) + "°, beyond the " + d.model + "'s " +
                       d.payload.model + " (" + formatNumber(d.payload.pitch_min_deg) + "° to " +
                       formatNumber(d.payload.pitch_max_deg) +
                       "°); choose a drone or --payload whose gimbal reaches it, or plan with "
                       "coverage: {gimbal_pitch_deg: [" +
                       formatNumber(d.payload.pitch_min_deg) + ", " +
                       formatNumber(d.payload.pitch_max_deg) + "]} in the config (uavip plan -c)");
  }
}

/// The Point and index of a Placemark (both documents).
void placemarkPoint(std::ostringstream& os, const Placed& p, std::size_t index) {
  os << "      <Placemark>\n"
     << "        <Point>\n"
     << "          <coordinates>" << formatFixed(p.g.lon_deg, kDegDecimals) << ","
     << formatFixed(p.g.lat_deg, kDegDecimals) << "</coordinates>\n"
     << "        </Point>\n"
     << "        <wpml:index>" << index << "</wpml:index>\n";
}

/// template.kml: the waypoint template DJI Pilot 2 shows, with EGM96 (or relative) and
/// ellipsoidal heights.
std::string templateKml(const Flight& flight, const std::vector<Placed>& placed,
                        const Georeference& geo, const Vec3& home, const WpmlOptions& o) {
  const bool relative = o.height_mode == WpmlHeightMode::Relative;
  std::ostringstream os;
  header(os);
  os << "    <wpml:author>uavip</wpml:author>\n";
  missionConfig(os, flight, geo, home, o);
  os << "    <Folder>\n"
     << "      <wpml:templateType>waypoint</wpml:templateType>\n"
     << "      <wpml:templateId>0</wpml:templateId>\n"
     << "      <wpml:waylineCoordinateSysParam>\n"
     << "        <wpml:coordinateMode>WGS84</wpml:coordinateMode>\n"
     << "        <wpml:heightMode>" << (relative ? "relativeToStartPoint" : "EGM96")
     << "</wpml:heightMode>\n"
     << "        <wpml:positioningType>GPS</wpml:positioningType>\n"
     << "      </wpml:waylineCoordinateSysParam>\n"
     << "      <wpml:autoFlightSpeed>" << formatFixed(o.speed_m_s, 2) << "</wpml:autoFlightSpeed>\n"
     << "      <wpml:globalHeight>"
     << formatFixed(placed.empty() ? 0.0 : placed.front().template_height, kHeightDecimals)
     << "</wpml:globalHeight>\n"
     << "      <wpml:gimbalPitchMode>usePointSetting</wpml:gimbalPitchMode>\n"
     << "      <wpml:globalWaypointHeadingParam>\n"
     << "        <wpml:waypointHeadingMode>smoothTransition</wpml:waypointHeadingMode>\n"
     << "        <wpml:waypointHeadingPathMode>followBadArc</wpml:waypointHeadingPathMode>\n"
     << "      </wpml:globalWaypointHeadingParam>\n"
     << "      <wpml:globalWaypointTurnMode>toPointAndStopWithDiscontinuityCurvature</"
        "wpml:globalWaypointTurnMode>\n"
     << "      <wpml:globalUseStraightLine>1</wpml:globalUseStraightLine>\n";
  for (std::size_t i = 0; i < placed.size(); ++i) {
    const Placed& p = placed[i];
    placemarkPoint(os, p, i);
    os << "        <wpml:ellipsoidHeight>" << formatFixed(p.g.h_ellipsoid_m, kHeightDecimals)
       << "</wpml:ellipsoidHeight>\n"
       << "        <wpml:height>" << formatFixed(p.template_height, kHeightDecimals)
       << "</wpml:height>\n"
       << "        <wpml:useGlobalHeight>0</wpml:useGlobalHeight>\n"
       << "        <wpml:useGlobalSpeed>1</wpml:useGlobalSpeed>\n"
       << "        <wpml:useGlobalHeadingParam>0</wpml:useGlobalHeadingParam>\n";
    headingAndTurn(os, p.heading);
    os << "        <wpml:useGlobalTurnParam>0</wpml:useGlobalTurnParam>\n"
       << "        <wpml:gimbalPitchAngle>" << formatFixed(flight.waypoints[i].gimbal_pitch_deg, 2)
       << "</wpml:gimbalPitchAngle>\n"
       << "      </Placemark>\n";
  }
  os << "    </Folder>\n  </Document>\n</kml>\n";
  return os.str();
}

/// waylines.wpml: what the aircraft executes.
std::string waylinesWpml(const Flight& flight, const std::vector<Placed>& placed,
                         const Georeference& geo, const Vec3& home, const WpmlOptions& o) {
  double distance = 0.0;
  for (std::size_t i = 1; i < flight.waypoints.size(); ++i)
    distance += (flight.waypoints[i].enu - flight.waypoints[i - 1].enu).norm();
  const double duration =
      distance / o.speed_m_s + static_cast<double>(flight.stopCount()) * o.hold_s;
  std::ostringstream os;
  header(os);
  missionConfig(os, flight, geo, home, o);
  os << "    <Folder>\n"
     << "      <wpml:templateId>0</wpml:templateId>\n"
     << "      <wpml:executeHeightMode>"
     << (o.height_mode == WpmlHeightMode::Relative ? "relativeToStartPoint" : "WGS84")
     << "</wpml:executeHeightMode>\n"
     << "      <wpml:waylineId>0</wpml:waylineId>\n"
     << "      <wpml:distance>" << formatFixed(distance, 1) << "</wpml:distance>\n"
     << "      <wpml:duration>" << formatFixed(duration, 1) << "</wpml:duration>\n"
     << "      <wpml:autoFlightSpeed>" << formatFixed(o.speed_m_s, 2)
     << "</wpml:autoFlightSpeed>\n";
  int group = 0;
  for (std::size_t i = 0; i < placed.size(); ++i) {
    const Placed& p = placed[i];
    const FlightWaypoint& w = flight.waypoints[i];
    placemarkPoint(os, p, i);
    os << "        <wpml:executeHeight>" << formatFixed(p.execute_height, kHeightDecimals)
       << "</wpml:executeHeight>\n"
       << "        <wpml:waypointSpeed>" << formatFixed(o.speed_m_s, 2)
       << "</wpml:waypointSpeed>\n";
    headingAndTurn(os, p.heading);
    if (w.isStop())
      stopActions(os, group++, static_cast<int>(i), w, p.heading,
                  i > 0 ? placed[i - 1].heading : p.heading, o);
    os << "      </Placemark>\n";
  }
  os << "    </Folder>\n  </Document>\n</kml>\n";
  return os.str();
}

std::string xmlFrom(unzFile z, const std::string& path, const char* entry) {
  if (unzLocateFile(z, entry, 1) != UNZ_OK)
    throw InputError(path + ": no " + entry + " in the KMZ (not a DJI WPML route)");
  unz_file_info64 info{};
  if (unzGetCurrentFileInfo64(z, &info, nullptr, 0, nullptr, 0, nullptr, 0) != UNZ_OK ||
      unzOpenCurrentFile(z) != UNZ_OK)
    throw InputError(path + ": cannot open " + entry + " in the KMZ");
  std::string text(static_cast<std::size_t>(info.uncompressed_size), '\0');
  const int n =
      text.empty() ? 0 : unzReadCurrentFile(z, text.data(), static_cast<unsigned>(text.size()));
  unzCloseCurrentFile(z);
  if (n < 0 || static_cast<std::size_t>(n) != text.size())
    throw InputError(path + ": " + entry + " in the KMZ is damaged");
  return text;
}

const tinyxml2::XMLElement* wpmlChild(const tinyxml2::XMLElement* e, const char* name,
                                      const std::string& path) {
  const tinyxml2::XMLElement* c = e != nullptr ? e->FirstChildElement(name) : nullptr;
  if (c == nullptr)
    throw InputError(path + ": waylines.wpml has no <" + name + "> where a route needs one");
  return c;
}

double wpmlNumber(const tinyxml2::XMLElement* e, const std::string& path) {
  double v = 0.0;
  if (e->QueryDoubleText(&v) != tinyxml2::XML_SUCCESS || !std::isfinite(v))
    throw InputError(path + ": waylines.wpml <" + e->Name() + "> is not a number");
  return v;
}

}  // namespace

std::vector<DjiDrone> djiDrones() {
  std::vector<DjiDrone> out;
  for (const aircraft::Profile& p : aircraft::profiles()) {
    if (p.drone_enum != 0) out.push_back(p);
  }
  return out;
}

std::string djiDroneList() {
  std::string out;
  for (const DjiDrone& d : djiDrones()) {
    out += (out.empty() ? "" : ", ") + d.name + " (" + d.model + ", " + d.payload.model +
           ", pitch " + formatNumber(d.payload.pitch_min_deg) + ".." +
           formatNumber(d.payload.pitch_max_deg) + ")";
  }
  return out;
}

DjiDrone findDjiDrone(const std::string& name, const std::string& payload) {
  DjiDrone d = aircraft::findProfile(name, payload, "--drone");
  if (d.drone_enum == 0) {
    std::string names;
    for (const DjiDrone& k : djiDrones()) names += (names.empty() ? "" : ", ") + k.name;
    throw InputError("--drone: '" + name + "' is not a DJI aircraft; one of " + names);
  }
  return d;
}

WpmlHeightMode parseWpmlHeightMode(const std::string& text) {
  if (text == "relative") return WpmlHeightMode::Relative;
  if (text == "ellipsoid") return WpmlHeightMode::Ellipsoid;
  throw InputError(
      "--height-mode: must be relative (relativeToStartPoint: above home) or ellipsoid (WGS84: "
      "above the WGS84 ellipsoid), got '" +
      text + "'");
}

void WpmlOptions::validate() const {
  requirePositive(speed_m_s, "export", "--speed");
  require(std::isfinite(hold_s) && hold_s >= 0.0, "--hold",
          "must be >= 0 s, got " + formatNumber(hold_s, 12));
  require(std::isfinite(takeoff_security_height_m) && takeoff_security_height_m >= 1.2 &&
              takeoff_security_height_m <= 1500.0,
          "--takeoff-height",
          "must be in [1.2, 1500] m (WPML takeOffSecurityHeight), got " +
              formatNumber(takeoff_security_height_m, 12));
  require(max_waypoints >= 2 && max_waypoints <= kWpmlMaxWaypoints, "--max-waypoints",
          "must be in [2, " + std::to_string(kWpmlMaxWaypoints) +
              "] (wpml:index runs 0..65535), got " + std::to_string(max_waypoints));
}

std::vector<Flight> splitForWpml(const Flight& flight, std::size_t max_waypoints) {
  if (flight.waypoints.size() <= max_waypoints) return {flight};
  std::vector<Flight> parts;
  std::size_t begin = 0;
  while (begin + 1 < flight.waypoints.size()) {
    const std::size_t end = std::min(flight.waypoints.size(), begin + max_waypoints);
    Flight part = flight;
    part.waypoints.assign(flight.waypoints.begin() + static_cast<std::ptrdiff_t>(begin),
                          flight.waypoints.begin() + static_cast<std::ptrdiff_t>(end));
    // The joint waypoint is flown twice (end of one part, start of the next): its
    // photo belongs to the part that ends there.
    if (begin > 0) part.waypoints.front().stop_index = -1;
    parts.push_back(std::move(part));
    begin = end - 1;
  }
  return parts;
}

std::string stopId(const FlightWaypoint& w) {
  std::string stop = std::to_string(w.stop_index);
  if (stop.size() < 3) stop.insert(0, 3 - stop.size(), '0');
  return "s" + std::to_string(w.surface_id) + "_" + stop;
}

WpmlDocuments wpmlDocuments(const Flight& flight, const Georeference& geo, const Vec3& home,
                            const WpmlOptions& o) {
  o.validate();
  requireReachablePitch(flight, o.drone);
  if (flight.waypoints.size() > o.max_waypoints)
    throw InputError("dji-kmz: a route of " + std::to_string(flight.waypoints.size()) +
                     " waypoints is beyond " + std::to_string(o.max_waypoints) +
                     "; split it first (splitForWpml)");
  const std::vector<Placed> placed = place(flight, geo, home, o);
  return {templateKml(flight, placed, geo, home, o), waylinesWpml(flight, placed, geo, home, o)};
}

void writeKmz(const std::string& path, const WpmlDocuments& documents) {
  zipFile z = zipOpen64(path.c_str(), APPEND_STATUS_CREATE);
  if (z == nullptr) throw InputError(path + ": cannot create the KMZ (zip) file");
  bool ok = true;
  for (const auto& [name, text] :
       {std::pair<const char*, const std::string*>{kTemplatePath, &documents.template_kml},
        {kWaylinesPath, &documents.waylines_wpml}}) {
    zip_fileinfo info{};
    info.tmz_date = {0, 0, 0, 1, 0, 2020};  // fixed: the same flight gives the same bytes
    ok = ok && zipOpenNewFileInZip64(z, name, &info, nullptr, 0, nullptr, 0, nullptr, Z_DEFLATED,
                                     Z_DEFAULT_COMPRESSION, 0) == ZIP_OK;
    ok = ok && zipWriteInFileInZip(z, text->data(), static_cast<unsigned>(text->size())) == ZIP_OK;
    ok = ok && zipCloseFileInZip(z) == ZIP_OK;
  }
  ok = zipClose(z, nullptr) == ZIP_OK && ok;
  if (!ok) throw InputError(path + ": could not write the KMZ (disk full?)");
}

WpmlRoute readKmzRoute(const std::string& path) {
  unzFile z = unzOpen64(path.c_str());
  if (z == nullptr) throw InputError(path + ": not a readable KMZ (zip) file");
  std::string text;
  try {
    text = xmlFrom(z, path, kWaylinesPath);
  } catch (...) {
    unzClose(z);
    throw;
  }
  unzClose(z);
  tinyxml2::XMLDocument doc;
  if (doc.Parse(text.data(), text.size()) != tinyxml2::XML_SUCCESS)
    throw InputError(path + ": waylines.wpml is not well-formed XML (" + doc.ErrorStr() + ")");
  const auto* folder =
      wpmlChild(wpmlChild(doc.FirstChildElement("kml"), "Document", path), "Folder", path);
  WpmlRoute route;
  route.execute_height_mode =
      wpmlChild(folder, "wpml:executeHeightMode", path)->GetText() != nullptr
          ? wpmlChild(folder, "wpml:executeHeightMode", path)->GetText()
          : "";
  for (const auto* pm = folder->FirstChildElement("Placemark"); pm != nullptr;
       pm = pm->NextSiblingElement("Placemark")) {
    WpmlPlacemark p;
    p.index = static_cast<int>(wpmlNumber(wpmlChild(pm, "wpml:index", path), path));
    p.execute_height_m = wpmlNumber(wpmlChild(pm, "wpml:executeHeight", path), path);
    const char* coords = wpmlChild(wpmlChild(pm, "Point", path), "coordinates", path)->GetText();
    if (coords == nullptr || std::sscanf(coords, " %lf , %lf", &p.lon_deg, &p.lat_deg) != 2)
      throw InputError(path + ": Placemark " + std::to_string(p.index) +
                       " has no 'longitude,latitude' coordinates");
    route.placemarks.push_back(p);
  }
  return route;
}

PointList routeToLocal(const WpmlRoute& route, const Georeference& geo, const Vec3& home) {
  const bool relative = route.execute_height_mode == "relativeToStartPoint";
  if (!relative && route.execute_height_mode != "WGS84")
    throw InputError("waylines.wpml: executeHeightMode '" + route.execute_height_mode +
                     "' is neither relativeToStartPoint nor WGS84");
  const double home_h = geo.toGeodetic(home).h_ellipsoid_m;
  PointList out;
  out.reserve(route.placemarks.size());
  for (const WpmlPlacemark& p : route.placemarks) {
    const double h = relative ? p.execute_height_m + home_h : p.execute_height_m;
    out.push_back(geo.toLocal({p.lat_deg, p.lon_deg, h}));
  }
  return out;
}

}  // namespace uavip::io
