#pragma once
/// \file
/// `uavip export`: a mission.json (local ENU metres) as a file a ground station
/// flies (docs/ARCHITECTURE.md, "CLI contract"; facts in docs/formats.md):
///  - QGroundControl `.plan` (JSON) with flat SimpleItems only (MAVSDK cannot read
///    complex items),
///  - QGC WPL 110 text (12 tab-separated fields, line 0 = home),
///  - CSV with local ENU and geographic columns.
///
/// Geography, one of two ways:
///  - `--origin LAT,LON,ALT`: local ENU (x east, y north, z up) → WGS84 with
///    GeographicLib's LocalCartesian(lat0, lon0, h0).Reverse(E, N, U). Altitudes of
///    mission items are relative to home (MAV_FRAME_GLOBAL_RELATIVE_ALT = 3):
///    alt = h − h0, where home is the origin.
///  - `--crs EPSG:…`: the cloud's own projected CRS. A local point plus scene.json's
///    source_offset_m is a point of the CRS, which PROJ transforms to WGS84
///    latitude and longitude. Home is the flight's first waypoint (the ordered
///    flight's home); altitudes stay relative to it (alt = z − z_home), as QGC
///    expects, and the home position's altitude is z_home + the offset's z, in the
///    vertical datum of the cloud's z.
///
/// Headings: mission.json gives yaw counter-clockwise from +x (east), the ENU
/// convention of the planner; QGC and MAVLink use a compass heading, clockwise from
/// north. heading = 90° − yaw, wrapped to [0°, 360°). Gimbal pitch is up-positive
/// in both (0 = horizontal, −90 = straight down).
///
/// Mission items (MAVLink common.xml ids) for each waypoint of the path, in order;
/// a waypoint that is a photo stop (paper §II-F) gets the camera orientation:
///   [ArduPilot only: 115 CONDITION_YAW (p1 heading, p2 0 = default rate, p3 0 =
///    shortest way, p4 0 = absolute)]
///   1000 DO_GIMBAL_MANAGER_PITCHYAW (p1 pitch deg, p2 yaw 0 = straight ahead,
///        p3 p4 rates 0, p5 flags 12 = roll and pitch locked to the horizon, p7 0 =
///        all gimbals) — before the stop's waypoint, so the camera turns on the way
///   16 NAV_WAYPOINT (p1 hold s, p2 acceptance radius m, p3 0, p4 heading deg,
///        p5 lat, p6 lon, p7 alt relative to home)
///   2000 IMAGE_START_CAPTURE (p1 camera id 0 = all, p2 interval 0, p3 total 1,
///        p4 sequence number from 1)
/// A waypoint between stops is a NAV_WAYPOINT with hold 0 and the heading of the
/// next stop. PX4 reads the heading from NAV_WAYPOINT p4; ArduPilot copters ignore
/// it and need CONDITION_YAW. No take-off or landing item is added: the vehicle
/// takes off and lands as its ground station or autopilot is set up to do.

#include <array>
#include <cstddef>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "uavip/core/types.h"
#include "uavip/io/geodesy.h"
#include "uavip/io/mission_json.h"

namespace uavip::io {

/// Compass heading [deg, 0 = north, clockwise, in [0, 360)] of an ENU yaw [deg,
/// counter-clockwise from east]: 90 − yaw, wrapped.
double headingFromYaw(double yaw_enu_deg);

/// Output formats.
enum class ExportFormat { QgcPlan, Wpl, Csv };
/// Parses "qgc-plan", "wpl" or "csv"; throws InputError naming the value.
ExportFormat parseExportFormat(const std::string& text);

/// Which autopilot reads the mission (firmwareType of the .plan; CONDITION_YAW).
enum class Autopilot { Px4, ArduPilot };
/// Parses "px4" or "ardupilot"; throws InputError naming the value.
Autopilot parseAutopilot(const std::string& text);

/// Options of the export. Where the local frame lies: `origin` (--origin: the local
/// (0, 0, 0) is home at that WGS84 position), or, when `crs` is set (--crs), the
/// local point p is the CRS point p + source_offset_m and home is `home_m`.
struct ExportOptions {
  GeoOrigin origin;
  /// --crs: the cloud's CRS; null for --origin.
  std::shared_ptr<const CrsTransform> crs;
  /// --crs: scene.json's source_offset_m, added to every local point [m].
  Vec3 source_offset_m{Vec3::Zero()};
  /// --crs: home in the local frame (the flight's first waypoint) [m]; altitudes are relative to
  /// its z.
  Vec3 home_m{Vec3::Zero()};
  Autopilot autopilot{Autopilot::Px4};
  double hold_s{1.0};        ///< hover time at a photo stop before the photo [s]
  double acceptance_m{0.3};  ///< waypoint acceptance radius [m]
  double speed_m_s{2.0};     ///< hoverSpeed of the .plan [m/s]
  /// Throws InputError naming the bad field.
  void validate() const;
};

/// Where a local point [m] lies: WGS84 latitude and longitude, and alt_m its altitude
/// relative to home (−origin.alt_m with --origin; − home_m.z with --crs) [m].
GeoPoint waypointGeo(const ExportOptions& options, const Vec3& enu);
/// Home: WGS84 latitude, longitude and altitude above the datum of the cloud's z
/// (--crs: home_m.z + source_offset_m.z) or --origin's altitude [m].
GeoPoint homeGeo(const ExportOptions& options);

/// One waypoint of the flight, in flight order.
struct FlightWaypoint {
  int surface_id{0};
  int stop_index{-1};      ///< index of the photo stop in its surface's stops[], −1 between stops
  Vec3 enu{Vec3::Zero()};  ///< [m]
  double yaw_deg{0.0};     ///< ENU yaw (CCW from east) of the stop, or of the next stop [deg]
  double gimbal_pitch_deg{0.0};  ///< up positive [deg]; of the stop, or of the next stop
  bool isStop() const { return stop_index >= 0; }
};

/// What is flown: one surface's path, or one sortie of the ordered flight.
struct Flight {
  int sortie{0};  ///< sortie number (from 1) of the ordered flight; 0 for one surface's path
  int uav{0};     ///< UAV number (from 1) of a fleet's flight; 0 for a single UAV
  std::vector<int> surface_ids;
  std::vector<FlightWaypoint> waypoints;
  std::size_t stopCount() const;
};

/// One surface's path of a mission (`path` names its file in messages).
/// `surface`: an id, or "" (the only surface with status ok or partial). Several
/// surfaces are flown by the ordered flight (sortiesFromMission), never joined
/// here; "all" throws InputError saying so.
/// Stops with a problem other than "none" (skipped by a partial mission) are not
/// flown; every other stop must lie on the waypoint path, in order.
/// Throws InputError naming the file when a stop is not on the waypoint path, the
/// id does not exist, "" is ambiguous (lists the ids), or NoMissionError when the
/// chosen surface has no flyable mission (names its status and reason; the CLI
/// exits 3 for that).
Flight flightFromMission(const MissionRecord& mission, const std::string& path,
                         const std::string& surface);

/// The sorties of the ordered flight, each home → stops → home, stops oriented from
/// their surface's stops. Throws InputError when the flight is missing (an older
/// file), NoMissionError when its status is not ok.
std::vector<Flight> sortiesFromMission(const MissionRecord& mission, const std::string& path);

/// The same from a mission.json document (read with missionFromJson).
inline Flight flightFromMissionJson(const nlohmann::json& mission, const std::string& path,
                                    const std::string& surface) {
  return flightFromMission(missionFromJson(mission, path), path, surface);
}
inline std::vector<Flight> sortiesFromMissionJson(const nlohmann::json& mission,
                                                  const std::string& path) {
  return sortiesFromMission(missionFromJson(mission, path), path);
}

/// The chosen surface exists but has no collision-free mission (CLI exit code 3).
class NoMissionError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// One MAVLink mission item.
struct MissionItem {
  int command{16};
  int frame{3};  ///< 3 = global, altitude relative to home; 2 = mission (no position)
  std::array<double, 7> params{};  ///< p1…p7; p5–p7 are lat, lon, alt for NAV_WAYPOINT
};

/// The mission items of a flight (see the file comment for their order).
std::vector<MissionItem> missionItems(const Flight& flight, const ExportOptions& options);

/// The QGroundControl .plan document.
nlohmann::json toQgcPlan(const Flight& flight, const ExportOptions& options);
/// QGC WPL 110 text.
std::string toWpl(const Flight& flight, const ExportOptions& options);
/// CSV: one row per waypoint; columns in the header line.
std::string toCsv(const Flight& flight, const ExportOptions& options);
/// The file text of `format`.
std::string exportFlight(const Flight& flight, ExportFormat format, const ExportOptions& options);

}  // namespace uavip::io
