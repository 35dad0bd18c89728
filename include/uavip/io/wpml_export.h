#pragma once
/// \file
/// `uavip export --format dji-kmz`: a flight as DJI WPML, the route format DJI Pilot 2
/// and FlightHub 2 import (docs/formats.md, "DJI WPML"; DJI Cloud API, "DJI WPML":
/// overview, template.kml, waylines.wpml, common elements; product enumerations).
///
/// A KMZ is a zip holding `wpmz/template.kml` (what Pilot 2 shows and edits) and
/// `wpmz/waylines.wpml` (what the aircraft executes), both KML 2.2 with the WPML
/// namespace http://www.dji.com/wpmz/1.0.6. One Placemark per flown waypoint,
/// `wpml:index` from 0; every waypoint stops (`toPointAndStopWithDiscontinuityCurvature`:
/// straight legs, as validated); the heading turns smoothly to the waypoint's heading;
/// at each photo stop one action group (trigger `reachPoint`): rotateYaw to the stop's
/// heading, gimbalRotate to its pitch, hover, takePhoto with fileSuffix = the stop id.
///
/// Heights (`executeHeightMode`): `relativeToStartPoint`, metres above home (the
/// ellipsoidal height difference), or `WGS84`, metres above the WGS84 ellipsoid. The
/// template shows EGM96 (or relative) heights with the ellipsoidal ones beside them.
///
/// Thread safety: functions are re-entrant; a Georeference is not (one per thread).

#include <cstddef>
#include <string>
#include <vector>

#include "uavip/core/aircraft.h"
#include "uavip/io/geodesy.h"
#include "uavip/io/mission_export.h"

namespace uavip::io {

/// A DJI aircraft and its camera (core/aircraft.h: WPML's droneInfo and payloadInfo
/// enumerations, the gimbal pitch its camera reaches).
using DjiDrone = aircraft::Profile;

/// Every DJI profile `--drone` takes (all of aircraft::profiles() but `generic`).
std::vector<DjiDrone> djiDrones();
/// The DJI aircraft `name` with `payload` ("" keeps its default camera); throws
/// InputError naming the value and listing the names.
DjiDrone findDjiDrone(const std::string& name, const std::string& payload = "");
/// "m300 (Matrice 300 RTK, Zenmuse H20, pitch -120..45), …": for --help and errors.
std::string djiDroneList();

/// What the route's heights are measured from.
enum class WpmlHeightMode { Relative, Ellipsoid };
/// Parses "relative" or "ellipsoid"; throws InputError naming the value.
WpmlHeightMode parseWpmlHeightMode(const std::string& text);

/// The largest number of waypoints in one WPML route: wpml:index runs 0…65535.
constexpr std::size_t kWpmlMaxWaypoints = 65536;

/// Options of the DJI export.
struct WpmlOptions {
  DjiDrone drone;
  WpmlHeightMode height_mode{WpmlHeightMode::Relative};
  double speed_m_s{2.0};  ///< autoFlightSpeed, globalTransitionalSpeed and each waypoint's [m/s]
  double hold_s{1.0};     ///< hover at a photo stop before the photo [s]
  /// wpml:takeOffSecurityHeight [m, 1.2…1500]: the climb after take-off, above home.
  double takeoff_security_height_m{20.0};
  /// Waypoints per route; a longer flight is split into parts (≤ kWpmlMaxWaypoints).
  std::size_t max_waypoints{kWpmlMaxWaypoints};
  /// Throws InputError naming the bad option.
  void validate() const;
};

/// The flight split into routes of at most options.max_waypoints waypoints; each part
/// after the first starts at the last waypoint of the one before (nothing unflown).
std::vector<Flight> splitForWpml(const Flight& flight, std::size_t max_waypoints);

/// The stop id a photo is named by (wpml:fileSuffix): "s<surface>_<stop>", e.g. "s3_017".
std::string stopId(const FlightWaypoint& w);

/// The two documents of one route. `home`: the local point heights are relative to
/// (the take-off point). Throws InputError naming the stop when its pitch is beyond
/// the drone's gimbal.
struct WpmlDocuments {
  std::string template_kml;
  std::string waylines_wpml;
};
WpmlDocuments wpmlDocuments(const Flight& flight, const Georeference& geo, const Vec3& home,
                            const WpmlOptions& options);

/// Writes the KMZ (zip, deflate) of the documents to `path`; fixed timestamps, so
/// the same flight gives the same bytes. Throws InputError naming the path.
void writeKmz(const std::string& path, const WpmlDocuments& documents);

/// One Placemark of a waylines.wpml as read back.
struct WpmlPlacemark {
  int index{0};
  double lon_deg{0.0};
  double lat_deg{0.0};
  double execute_height_m{0.0};  ///< wpml:executeHeight [m]
};
/// A KMZ's route as the aircraft reads it.
struct WpmlRoute {
  std::string execute_height_mode;  ///< "relativeToStartPoint" or "WGS84"
  std::vector<WpmlPlacemark> placemarks;
};
/// Reads `wpmz/waylines.wpml` of a KMZ back (minizip, TinyXML-2). Throws InputError
/// naming the file and what is missing or malformed.
WpmlRoute readKmzRoute(const std::string& path);

/// The local points [m] of a route read back: the inverse of what wpmlDocuments wrote.
PointList routeToLocal(const WpmlRoute& route, const Georeference& geo, const Vec3& home);

}  // namespace uavip::io
