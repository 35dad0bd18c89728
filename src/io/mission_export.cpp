#include "uavip/io/mission_export.h"

#include "uavip/core/error.h"

#include <GeographicLib/LocalCartesian.hpp>

#include <cerrno>
#include <cmath>
#include <algorithm>
#include <cstdlib>
#include <map>
#include <iomanip>
#include <sstream>

namespace uavip::io {
namespace {

using nlohmann::json;

constexpr int kCmdWaypoint = 16;
constexpr int kCmdConditionYaw = 115;
constexpr int kCmdGimbalPitchYaw = 1000;
constexpr int kCmdImageStartCapture = 2000;
constexpr int kFrameGlobal = 0;
constexpr int kFrameMission = 2;
constexpr int kFrameGlobalRelativeAlt = 3;
constexpr double kGimbalFlagsRollPitchLock = 4 + 8;  // GIMBAL_MANAGER_FLAGS_ROLL_LOCK | PITCH_LOCK
/// A stop is the waypoint within this distance of its position (mission.json rounds to 0.1 mm) [m].
constexpr double kStopMatchM = 2e-3;

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  const auto e = s.find_last_not_of(" \t");
  return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}

bool parseDouble(const std::string& text, double& out) {
  const std::string t = trim(text);
  if (t.empty()) return false;
  char* end = nullptr;
  errno = 0;
  out = std::strtod(t.c_str(), &end);
  return errno == 0 && end == t.c_str() + t.size() && std::isfinite(out);
}

std::string num(double v) {
  std::ostringstream os;
  os << std::setprecision(12) << v;
  return os.str();
}

std::string fixed(double v, int digits) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(digits) << v;
  return os.str();
}

// ---- mission.json access with messages naming the file and the field

const json& field(const json& j, const char* key, const std::string& path, const std::string& where) {
  if (!j.is_object() || !j.contains(key))
    throw InputError(path + ": " + where + (where.empty() ? "" : ".") + key + " is missing (not a uavip mission.json?)");
  return j.at(key);
}

Vec3 vec3(const json& j, const std::string& path, const std::string& where) {
  if (!j.is_array() || j.size() != 3 || !j[0].is_number() || !j[1].is_number() || !j[2].is_number())
    throw InputError(path + ": " + where + " must be an array of 3 numbers, got " + j.dump());
  return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
}

double number(const json& j, const std::string& path, const std::string& where) {
  if (!j.is_number()) throw InputError(path + ": " + where + " must be a number, got " + j.dump());
  return j.get<double>();
}

/// Between stops a waypoint takes the surface and orientation of the next stop
/// (after the last stop: of the last).
void orientBetweenStops(std::vector<FlightWaypoint>& out) {
  const FlightWaypoint* next = nullptr;  // the next stop, else the last
  for (const auto& w : out) {
    if (w.isStop()) next = &w;
  }
  if (next == nullptr) return;
  for (std::size_t i = out.size(); i-- > 0;) {
    if (out[i].isStop()) {
      next = &out[i];
    } else {
      out[i].surface_id = next->surface_id;
      out[i].yaw_deg = next->yaw_deg;
      out[i].gimbal_pitch_deg = next->gimbal_pitch_deg;
    }
  }
}

/// The waypoints of one surface with status ok, stops marked.
std::vector<FlightWaypoint> surfaceFlight(const json& s, int id, const std::string& path, const std::string& where) {
  const json& stops = field(s, "stops", path, where);
  const json& wps = field(s, "waypoints", path, where);
  if (!stops.is_array() || !wps.is_array()) throw InputError(path + ": " + where + ".stops and .waypoints must be arrays");
  struct StopInfo {
    int index;
    Vec3 p;
    double yaw, pitch;
  };
  std::vector<StopInfo> st;  // the stops that are flown (problem "none"), in order
  for (std::size_t k = 0; k < stops.size(); ++k) {
    const std::string w = where + ".stops[" + std::to_string(k) + "]";
    const bool skipped = stops[k].contains("problem") && stops[k]["problem"] != "none";
    if (skipped) continue;  // a "partial" surface skips stops it cannot reach safely
    st.push_back({static_cast<int>(k), vec3(field(stops[k], "position", path, w), path, w + ".position"),
                  number(field(stops[k], "yaw_deg", path, w), path, w + ".yaw_deg"),
                  number(field(stops[k], "gimbal_pitch_deg", path, w), path, w + ".gimbal_pitch_deg")});
  }
  std::vector<FlightWaypoint> out;
  std::size_t k = 0;
  for (std::size_t i = 0; i < wps.size(); ++i) {
    FlightWaypoint w;
    w.surface_id = id;
    w.enu = vec3(wps[i], path, where + ".waypoints[" + std::to_string(i) + "]");
    if (k < st.size() && (w.enu - st[k].p).norm() <= kStopMatchM) {
      w.stop_index = st[k].index;
      w.yaw_deg = st[k].yaw;
      w.gimbal_pitch_deg = st[k].pitch;
      ++k;
    }
    out.push_back(w);
  }
  if (k < st.size())
    throw InputError(path + ": " + where + ".stops[" + std::to_string(st[k].index) +
                     "] is not on the waypoint path (in order); the file was changed or is not a uavip mission");
  orientBetweenStops(out);
  return out;
}

std::string describe(const json& s) {
  const std::string status = s.contains("status") && s["status"].is_string() ? s["status"].get<std::string>() : "?";
  const std::string reason = s.contains("reason") && s["reason"].is_string() ? s["reason"].get<std::string>() : "";
  return "status " + status + (reason.empty() ? "" : ": " + reason);
}

}  // namespace

GeoOrigin parseOrigin(const std::string& text, const std::string& where) {
  const std::string shown = "got '" + text + "'";
  std::vector<std::string> parts;
  std::string cur;
  for (char c : text) {
    if (c == ',') {
      parts.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  parts.push_back(cur);
  GeoOrigin o;
  if (parts.size() != 3 || !parseDouble(parts[0], o.lat_deg) || !parseDouble(parts[1], o.lon_deg) ||
      !parseDouble(parts[2], o.alt_m))
    throw InputError(where + ": expected LAT,LON,ALT (degrees, degrees, metres above sea level, e.g. "
                             "47.3977,8.5456,488), " + shown);
  require(o.lat_deg >= -90.0 && o.lat_deg <= 90.0, where, "latitude must be in [-90, 90] degrees, " + shown);
  require(o.lon_deg >= -180.0 && o.lon_deg <= 180.0, where, "longitude must be in [-180, 180] degrees, " + shown);
  require(o.alt_m >= -500.0 && o.alt_m <= 9000.0, where, "altitude must be in [-500, 9000] m, " + shown);
  return o;
}

GeoPoint enuToGeodetic(const GeoOrigin& origin, const Vec3& enu) {
  const GeographicLib::LocalCartesian lc(origin.lat_deg, origin.lon_deg, origin.alt_m);
  GeoPoint g;
  lc.Reverse(enu.x(), enu.y(), enu.z(), g.lat_deg, g.lon_deg, g.alt_m);
  return g;
}

double headingFromYaw(double yaw_enu_deg) {
  double h = std::fmod(90.0 - yaw_enu_deg, 360.0);
  if (h < 0.0) h += 360.0;
  if (h >= 360.0) h -= 360.0;  // fmod of a tiny negative + 360 rounds to 360
  return h;
}

ExportFormat parseExportFormat(const std::string& text) {
  if (text == "qgc-plan") return ExportFormat::QgcPlan;
  if (text == "wpl") return ExportFormat::Wpl;
  if (text == "csv") return ExportFormat::Csv;
  throw InputError("--format: must be qgc-plan, wpl or csv, got '" + text + "'");
}

Autopilot parseAutopilot(const std::string& text) {
  if (text == "px4") return Autopilot::Px4;
  if (text == "ardupilot") return Autopilot::ArduPilot;
  throw InputError("--autopilot: must be px4 or ardupilot, got '" + text + "'");
}

void ExportOptions::validate() const {
  require(std::isfinite(hold_s) && hold_s >= 0.0, "--hold", "must be >= 0 s, got " + num(hold_s));
  requirePositive(acceptance_m, "export", "--acceptance");
  requirePositive(speed_m_s, "export", "--speed");
}

std::size_t Flight::stopCount() const {
  std::size_t n = 0;
  for (const auto& w : waypoints) n += w.isStop();
  return n;
}

Flight flightFromMissionJson(const json& mission, const std::string& path, const std::string& surface) {
  const json& surfaces = field(mission, "surfaces", path, "");
  if (!surfaces.is_array()) throw InputError(path + ": surfaces must be an array");
  std::vector<std::size_t> ok;
  std::string all_ids;
  for (std::size_t i = 0; i < surfaces.size(); ++i) {
    const std::string where = "surfaces[" + std::to_string(i) + "]";
    const json& id = field(surfaces[i], "surface_id", path, where);
    if (!id.is_number_integer()) throw InputError(path + ": " + where + ".surface_id must be an integer");
    all_ids += (all_ids.empty() ? "" : ", ") + std::to_string(id.get<int>());
    const json& status = field(surfaces[i], "status", path, where);
    if (status == "ok" || status == "partial") ok.push_back(i);
  }

  std::vector<std::size_t> chosen;
  if (surface == "all")
    throw InputError("--surface all: the surfaces are flown as the ordered, validated flight of " + path +
                     " (its sorties), not joined here");
  if (surface.empty()) {
    if (ok.empty()) {
      std::string why;
      for (const auto& s : surfaces)
        why += (why.empty() ? "" : "; ") + ("surface " + std::to_string(s["surface_id"].get<int>()) + " " + describe(s));
      throw NoMissionError(path + ": no surface has a flyable mission" + (why.empty() ? " (no surfaces)" : " (" + why + ")"));
    }
    if (ok.size() > 1) {
      std::string ids;
      for (auto i : ok) ids += (ids.empty() ? "" : ", ") + std::to_string(surfaces[i]["surface_id"].get<int>());
      throw InputError(path + ": " + std::to_string(ok.size()) + " surfaces have a mission (" + ids +
                       "): pass --surface ID for one of them, or --surface all for the ordered flight over all");
    }
    chosen = ok;
  } else {
    char* end = nullptr;
    const long want = std::strtol(surface.c_str(), &end, 10);
    if (end == surface.c_str() || *end != '\0')
      throw InputError("--surface: expected a surface id or 'all', got '" + surface + "'");
    bool found = false;
    for (std::size_t i = 0; i < surfaces.size(); ++i) {
      if (surfaces[i]["surface_id"].get<long>() != want) continue;
      found = true;
      if (surfaces[i]["status"] != "ok" && surfaces[i]["status"] != "partial")
        throw NoMissionError(path + ": surface " + surface + " has no flyable mission (" + describe(surfaces[i]) + ")");
      chosen.push_back(i);
    }
    if (!found)
      throw InputError(path + ": no surface with id " + surface + " (ids: " + (all_ids.empty() ? "none" : all_ids) + ")");
  }

  Flight f;
  for (auto i : chosen) {
    const int id = surfaces[i]["surface_id"].get<int>();
    f.surface_ids.push_back(id);
    auto w = surfaceFlight(surfaces[i], id, path, "surfaces[" + std::to_string(i) + "]");
    f.waypoints.insert(f.waypoints.end(), w.begin(), w.end());
  }
  return f;
}

std::vector<Flight> sortiesFromMissionJson(const json& mission, const std::string& path) {
  if (!mission.is_object() || !mission.contains("flight"))
    throw InputError(path + ": has no ordered flight (written by an older uavip); re-run uavip plan --surface all");
  const json& flight = mission.at("flight");
  const json& status = field(flight, "status", path, "flight");
  if (status != "ok") {
    const std::string reason = flight.contains("reason") && flight["reason"].is_string() ? flight["reason"].get<std::string>() : "";
    throw NoMissionError(path + ": the flight has status " + status.dump() + (reason.empty() ? "" : ": " + reason));
  }
  // Stops of each surface by id, for their orientation.
  std::map<long, const json*> stops_of;
  const json& surfaces = field(mission, "surfaces", path, "");
  if (!surfaces.is_array()) throw InputError(path + ": surfaces must be a list");
  for (const auto& s : surfaces) {
    const json& id = field(s, "surface_id", path, "surfaces[]");
    if (!id.is_number_integer()) throw InputError(path + ": surfaces[].surface_id must be an integer");
    const json& stops = field(s, "stops", path, "surfaces[]");
    if (!stops.is_array()) throw InputError(path + ": surfaces[].stops must be a list");
    stops_of[id.get<long>()] = &stops;
  }
  const json& sorties = field(flight, "sorties", path, "flight");
  if (!sorties.is_array() || sorties.empty()) throw InputError(path + ": flight.sorties must be a non-empty list");
  std::vector<Flight> out;
  for (std::size_t i = 0; i < sorties.size(); ++i) {
    const std::string where = "flight.sorties[" + std::to_string(i) + "]";
    Flight f;
    f.sortie = static_cast<int>(i + 1);
    const json& wps = field(sorties[i], "waypoints", path, where);
    const json& st = field(sorties[i], "stops", path, where);
    if (!wps.is_array() || wps.size() < 2 || !st.is_array())
      throw InputError(path + ": " + where + ".waypoints must list home ... home and .stops must be a list");
    for (std::size_t k = 0; k < wps.size(); ++k) {
      FlightWaypoint w;
      w.enu = vec3(wps[k], path, where + ".waypoints[" + std::to_string(k) + "]");
      f.waypoints.push_back(w);
    }
    long previous = -1;
    for (std::size_t k = 0; k < st.size(); ++k) {
      const std::string ws = where + ".stops[" + std::to_string(k) + "]";
      const json& sid = field(st[k], "surface_id", path, ws);
      const json& stop = field(st[k], "stop", path, ws);
      const json& at = field(st[k], "waypoint", path, ws);
      if (!sid.is_number_integer() || !stop.is_number_integer() || !at.is_number_integer())
        throw InputError(path + ": " + ws + " must hold integers surface_id, stop and waypoint");
      const auto it = stops_of.find(sid.get<long>());
      const long a = at.get<long>();
      if (it == stops_of.end() || stop.get<long>() < 0 || stop.get<std::size_t>() >= it->second->size() || a <= previous ||
          a >= static_cast<long>(f.waypoints.size()))
        throw InputError(path + ": " + ws + " names no stop of the mission or no later waypoint of the sortie");
      previous = a;
      const json& s = (*it->second)[stop.get<std::size_t>()];
      FlightWaypoint& w = f.waypoints[static_cast<std::size_t>(a)];
      if ((w.enu - vec3(field(s, "position", path, ws), path, ws + ".position")).norm() > kStopMatchM)
        throw InputError(path + ": " + ws + " is not at its waypoint; the file was changed or is not a uavip mission");
      w.surface_id = sid.get<int>();
      w.stop_index = stop.get<int>();
      w.yaw_deg = number(field(s, "yaw_deg", path, ws), path, ws + ".yaw_deg");
      w.gimbal_pitch_deg = number(field(s, "gimbal_pitch_deg", path, ws), path, ws + ".gimbal_pitch_deg");
      if (std::find(f.surface_ids.begin(), f.surface_ids.end(), w.surface_id) == f.surface_ids.end())
        f.surface_ids.push_back(w.surface_id);
    }
    orientBetweenStops(f.waypoints);
    out.push_back(std::move(f));
  }
  return out;
}

std::vector<MissionItem> missionItems(const Flight& flight, const ExportOptions& options) {
  const GeographicLib::LocalCartesian lc(options.origin.lat_deg, options.origin.lon_deg, options.origin.alt_m);
  std::vector<MissionItem> items;
  int photo = 0;
  for (const auto& w : flight.waypoints) {
    double lat = 0.0, lon = 0.0, h = 0.0;
    lc.Reverse(w.enu.x(), w.enu.y(), w.enu.z(), lat, lon, h);
    const double heading = headingFromYaw(w.yaw_deg);
    if (w.isStop()) {
      if (options.autopilot == Autopilot::ArduPilot)
        items.push_back({kCmdConditionYaw, kFrameMission, {heading, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0}});
      items.push_back({kCmdGimbalPitchYaw, kFrameMission,
                       {w.gimbal_pitch_deg, 0.0, 0.0, 0.0, kGimbalFlagsRollPitchLock, 0.0, 0.0}});
    }
    items.push_back({kCmdWaypoint,
                     kFrameGlobalRelativeAlt,
                     {w.isStop() ? options.hold_s : 0.0, options.acceptance_m, 0.0, heading, lat, lon,
                      h - options.origin.alt_m}});
    if (w.isStop())
      items.push_back({kCmdImageStartCapture, kFrameMission, {0.0, 0.0, 1.0, static_cast<double>(++photo), 0.0, 0.0, 0.0}});
  }
  return items;
}

json toQgcPlan(const Flight& flight, const ExportOptions& options) {
  json items = json::array();
  int jump = 0;
  for (const auto& it : missionItems(flight, options)) {
    items.push_back({{"type", "SimpleItem"},
                     {"command", it.command},
                     {"frame", it.frame},
                     {"params", json(std::vector<double>(it.params.begin(), it.params.end()))},
                     {"autoContinue", true},
                     {"doJumpId", ++jump}});
  }
  const auto& o = options.origin;
  return {{"fileType", "Plan"},
          {"version", 1},
          {"groundStation", "QGroundControl"},
          {"mission",
           {{"version", 2},
            {"firmwareType", options.autopilot == Autopilot::Px4 ? 12 : 3},
            {"vehicleType", 2},
            {"cruiseSpeed", options.speed_m_s},
            {"hoverSpeed", options.speed_m_s},
            {"plannedHomePosition", {o.lat_deg, o.lon_deg, o.alt_m}},
            {"items", items}}},
          {"geoFence", {{"circles", json::array()}, {"polygons", json::array()}, {"version", 2}}},
          {"rallyPoints", {{"points", json::array()}, {"version", 2}}}};
}

std::string toWpl(const Flight& flight, const ExportOptions& options) {
  const auto& o = options.origin;
  std::ostringstream os;
  os << "QGC WPL 110\n";
  os << "0\t1\t" << kFrameGlobal << "\t" << kCmdWaypoint << "\t0\t0\t0\t0\t" << num(o.lat_deg) << "\t" << num(o.lon_deg)
     << "\t" << num(o.alt_m) << "\t1\n";
  int index = 0;
  for (const auto& it : missionItems(flight, options)) {
    os << ++index << "\t0\t" << it.frame << "\t" << it.command;
    for (double p : it.params) os << "\t" << num(p);
    os << "\t1\n";
  }
  return os.str();
}

std::string toCsv(const Flight& flight, const ExportOptions& options) {
  const GeographicLib::LocalCartesian lc(options.origin.lat_deg, options.origin.lon_deg, options.origin.alt_m);
  std::ostringstream os;
  os << "index,surface_id,stop_index,is_stop,east_m,north_m,up_m,lat_deg,lon_deg,alt_rel_home_m,yaw_enu_deg,"
        "heading_deg,gimbal_pitch_deg\n";
  for (std::size_t i = 0; i < flight.waypoints.size(); ++i) {
    const auto& w = flight.waypoints[i];
    double lat = 0.0, lon = 0.0, h = 0.0;
    lc.Reverse(w.enu.x(), w.enu.y(), w.enu.z(), lat, lon, h);
    os << i << "," << w.surface_id << "," << w.stop_index << "," << (w.isStop() ? 1 : 0) << "," << fixed(w.enu.x(), 4)
       << "," << fixed(w.enu.y(), 4) << "," << fixed(w.enu.z(), 4) << "," << fixed(lat, 9) << "," << fixed(lon, 9) << ","
       << fixed(h - options.origin.alt_m, 4) << "," << fixed(w.yaw_deg, 4) << "," << fixed(headingFromYaw(w.yaw_deg), 4)
       << "," << fixed(w.gimbal_pitch_deg, 4) << "\n";
  }
  return os.str();
}

std::string exportFlight(const Flight& flight, ExportFormat format, const ExportOptions& options) {
  switch (format) {
    case ExportFormat::QgcPlan:
      return toQgcPlan(flight, options).dump(2) + "\n";
    case ExportFormat::Wpl:
      return toWpl(flight, options);
    case ExportFormat::Csv:
      return toCsv(flight, options);
  }
  return {};
}

}  // namespace uavip::io
