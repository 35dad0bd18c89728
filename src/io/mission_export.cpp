#include "uavip/io/mission_export.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <map>
#include <sstream>

#include "uavip/core/error.h"
#include "uavip/core/text.h"
#include "uavip/io/mission_json.h"

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

/// The waypoints of one flyable surface, its flown stops marked and oriented; each
/// flown stop must be a waypoint, in order.
std::vector<FlightWaypoint> surfaceFlight(const SurfaceRecord& s, const std::string& path,
                                          const std::string& where) {
  std::vector<FlightWaypoint> out;
  std::size_t k = 0;  // the next stop to find
  const auto skipUnflown = [&] {
    while (k < s.stops.size() && !s.stops[k].flown())
      ++k;  // a "partial" surface skips stops it cannot reach
  };
  skipUnflown();
  for (const Vec3& p : s.waypoints) {
    FlightWaypoint w;
    w.surface_id = s.surface_id;
    w.enu = p;
    if (k < s.stops.size() && (p - s.stops[k].position).norm() <= kStopMatchM) {
      w.stop_index = static_cast<int>(k);
      w.yaw_deg = s.stops[k].yaw_deg;
      w.gimbal_pitch_deg = s.stops[k].gimbal_pitch_deg;
      ++k;
      skipUnflown();
    }
    out.push_back(w);
  }
  if (k < s.stops.size())
    throw InputError(
        path + ": " + where + ".stops[" + std::to_string(k) +
        "] is not on the waypoint path (in order); the file was changed or is not a uavip mission");
  orientBetweenStops(out);
  return out;
}

std::string describe(const SurfaceRecord& s) {
  return "status " + s.status + (s.reason.empty() ? "" : ": " + s.reason);
}

}  // namespace

GeoPoint waypointGeo(const ExportOptions& options, const Vec3& enu) {
  if (options.crs) {
    const Vec3 p = enu + options.source_offset_m;
    GeoPoint g = options.crs->toWgs84(p.x(), p.y());
    g.alt_m = enu.z() - options.home_m.z();
    return g;
  }
  GeoPoint g = enuToGeodetic(options.origin, enu);
  g.alt_m -= options.origin.alt_m;
  return g;
}

GeoPoint homeGeo(const ExportOptions& options) {
  if (options.crs) {
    const Vec3 p = options.home_m + options.source_offset_m;
    GeoPoint g = options.crs->toWgs84(p.x(), p.y());
    g.alt_m = p.z();
    return g;
  }
  return {options.origin.lat_deg, options.origin.lon_deg, options.origin.alt_m};
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
  throw InputError("--format: must be dji-kmz, qgc-plan, wpl, csv, kml or geojson, got '" + text +
                   "'");
}

Autopilot parseAutopilot(const std::string& text) {
  if (text == "px4") return Autopilot::Px4;
  if (text == "ardupilot") return Autopilot::ArduPilot;
  throw InputError("--autopilot: must be px4 or ardupilot, got '" + text + "'");
}

void ExportOptions::validate() const {
  require(std::isfinite(hold_s) && hold_s >= 0.0, "--hold",
          "must be >= 0 s, got " + formatNumber(hold_s, 12));
  requirePositive(acceptance_m, "export", "--acceptance");
  requirePositive(speed_m_s, "export", "--speed");
}

std::size_t Flight::stopCount() const {
  std::size_t n = 0;
  for (const auto& w : waypoints) n += w.isStop();
  return n;
}

Flight flightFromMission(const MissionRecord& mission, const std::string& path,
                         const std::string& surface) {
  if (surface == "all")
    throw InputError("--surface all: the surfaces are flown as the ordered, validated flight of " +
                     path + " (its sorties), not joined here");
  std::vector<std::size_t> chosen;
  if (surface.empty()) {
    std::string ids, why;
    for (std::size_t i = 0; i < mission.surfaces.size(); ++i) {
      const SurfaceRecord& s = mission.surfaces[i];
      if (s.flyable()) {
        chosen.push_back(i);
        ids += (ids.empty() ? "" : ", ") + std::to_string(s.surface_id);
      }
      why += (why.empty() ? "" : "; ") +
             ("surface " + std::to_string(s.surface_id) + " " + describe(s));
    }
    if (chosen.empty())
      throw NoMissionError(path + ": no surface has a flyable mission" +
                           (why.empty() ? " (no surfaces)" : " (" + why + ")"));
    if (chosen.size() > 1)
      throw InputError(
          path + ": " + std::to_string(chosen.size()) + " surfaces have a mission (" + ids +
          "): pass --surface ID for one of them, or --surface all for the ordered flight over all");
  } else {
    char* end = nullptr;
    const long want = std::strtol(surface.c_str(), &end, 10);
    if (end == surface.c_str() || *end != '\0')
      throw InputError("--surface: expected a surface id or 'all', got '" + surface + "'");
    std::string all_ids;
    for (std::size_t i = 0; i < mission.surfaces.size(); ++i) {
      const SurfaceRecord& s = mission.surfaces[i];
      all_ids += (all_ids.empty() ? "" : ", ") + std::to_string(s.surface_id);
      if (s.surface_id != want) continue;
      if (!s.flyable())
        throw NoMissionError(path + ": surface " + surface + " has no flyable mission (" +
                             describe(s) + ")");
      chosen.push_back(i);
    }
    if (chosen.empty())
      throw InputError(path + ": no surface with id " + surface +
                       " (ids: " + (all_ids.empty() ? "none" : all_ids) + ")");
  }
  Flight f;
  for (auto i : chosen) {
    const SurfaceRecord& s = mission.surfaces[i];
    f.surface_ids.push_back(s.surface_id);
    auto w = surfaceFlight(s, path, "surfaces[" + std::to_string(i) + "]");
    f.waypoints.insert(f.waypoints.end(), w.begin(), w.end());
  }
  return f;
}

std::vector<Flight> sortiesFromMission(const MissionRecord& mission, const std::string& path) {
  if (!mission.flight)
    throw InputError(
        path +
        ": has no ordered flight (written by an older uavip); re-run uavip plan --surface all");
  const FlightRecord& flight = *mission.flight;
  if (flight.status != "ok")
    throw NoMissionError(path + ": the flight has status \"" + flight.status + "\"" +
                         (flight.reason.empty() ? "" : ": " + flight.reason));
  if (flight.sorties.empty()) throw InputError(path + ": flight.sorties must be a non-empty list");
  std::vector<Flight> out;
  for (std::size_t i = 0; i < flight.sorties.size(); ++i) {
    const SortieRecord& sortie = flight.sorties[i];
    Flight f;
    f.sortie = static_cast<int>(i + 1);
    for (const Vec3& p : sortie.waypoints) {
      FlightWaypoint w;
      w.enu = p;
      f.waypoints.push_back(w);
    }
    for (const SortieStopRecord& st : sortie.stops) {  // consistency checked by missionFromJson
      const StopRecord& stop = mission.surface(st.surface_id)->stops[st.stop];
      FlightWaypoint& w = f.waypoints[st.waypoint];
      w.surface_id = st.surface_id;
      w.stop_index = static_cast<int>(st.stop);
      w.yaw_deg = stop.yaw_deg;
      w.gimbal_pitch_deg = stop.gimbal_pitch_deg;
      if (std::find(f.surface_ids.begin(), f.surface_ids.end(), w.surface_id) ==
          f.surface_ids.end())
        f.surface_ids.push_back(w.surface_id);
    }
    orientBetweenStops(f.waypoints);
    out.push_back(std::move(f));
  }
  return out;
}

std::vector<MissionItem> missionItems(const Flight& flight, const ExportOptions& options) {
  std::vector<MissionItem> items;
  int photo = 0;
  for (const auto& w : flight.waypoints) {
    const GeoPoint g = waypointGeo(options, w.enu);
    const double heading = headingFromYaw(w.yaw_deg);
    if (w.isStop()) {
      if (options.autopilot == Autopilot::ArduPilot)
        items.push_back({kCmdConditionYaw, kFrameMission, {heading, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0}});
      items.push_back({kCmdGimbalPitchYaw,
                       kFrameMission,
                       {w.gimbal_pitch_deg, 0.0, 0.0, 0.0, kGimbalFlagsRollPitchLock, 0.0, 0.0}});
    }
    items.push_back({kCmdWaypoint,
                     kFrameGlobalRelativeAlt,
                     {w.isStop() ? options.hold_s : 0.0, options.acceptance_m, 0.0, heading,
                      g.lat_deg, g.lon_deg, g.alt_m}});
    if (w.isStop())
      items.push_back({kCmdImageStartCapture,
                       kFrameMission,
                       {0.0, 0.0, 1.0, static_cast<double>(++photo), 0.0, 0.0, 0.0}});
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
  const GeoPoint o = homeGeo(options);
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
  const GeoPoint o = homeGeo(options);
  std::ostringstream os;
  os << "QGC WPL 110\n";
  os << "0\t1\t" << kFrameGlobal << "\t" << kCmdWaypoint << "\t0\t0\t0\t0\t"
     << formatNumber(o.lat_deg, 12) << "\t" << formatNumber(o.lon_deg, 12) << "\t"
     << formatNumber(o.alt_m, 12) << "\t1\n";
  int index = 0;
  for (const auto& it : missionItems(flight, options)) {
    os << ++index << "\t0\t" << it.frame << "\t" << it.command;
    for (double p : it.params) os << "\t" << formatNumber(p, 12);
    os << "\t1\n";
  }
  return os.str();
}

std::string toCsv(const Flight& flight, const ExportOptions& options) {
  std::ostringstream os;
  os << "index,surface_id,stop_index,is_stop,east_m,north_m,up_m,lat_deg,lon_deg,alt_rel_home_m,"
        "yaw_enu_deg,"
        "heading_deg,gimbal_pitch_deg\n";
  for (std::size_t i = 0; i < flight.waypoints.size(); ++i) {
    const auto& w = flight.waypoints[i];
    const GeoPoint g = waypointGeo(options, w.enu);
    os << i << "," << w.surface_id << "," << w.stop_index << "," << (w.isStop() ? 1 : 0) << ","
       << formatFixed(w.enu.x(), 4) << "," << formatFixed(w.enu.y(), 4) << ","
       << formatFixed(w.enu.z(), 4) << "," << formatFixed(g.lat_deg, 9) << ","
       << formatFixed(g.lon_deg, 9) << "," << formatFixed(g.alt_m, 4) << ","
       << formatFixed(w.yaw_deg, 4) << "," << formatFixed(headingFromYaw(w.yaw_deg), 4) << ","
       << formatFixed(w.gimbal_pitch_deg, 4) << "\n";
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
