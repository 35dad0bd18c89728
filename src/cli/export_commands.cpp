// uavip export: a mission.json as a QGroundControl .plan, a QGC WPL 110 file, a CSV, a
// DJI WPML route, KML or GeoJSON (io/mission_export.h has the item layout and the heading
// convention). Where the flight lies and the check against its scene are app/placement.h's;
// here the options are parsed, the files staged and the result printed.

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

#include "src/cli/commands.h"
#include "uavip/app/placement.h"
#include "uavip/core/error.h"
#include "uavip/core/text.h"
#include "uavip/io/atomic_file.h"
#include "uavip/io/geodesy.h"
#include "uavip/io/json_reader.h"
#include "uavip/io/map_export.h"
#include "uavip/io/mission_export.h"
#include "uavip/io/wpml_export.h"
#include "uavip/planning/path_validator.h"

namespace uavip::cli {
namespace {

namespace fs = std::filesystem;

/// Options of export, kept alive until dispatch.
struct ExportArgs {
  std::string mission, format, origin, crs, out, surface, autopilot{"px4"}, scene;
  std::string drone, payload, height_mode{"relative"}, vertical;
  int sortie{0};
  int uav{0};  ///< --uav: only this UAV of a fleet (from 1); 0 = every UAV
  /// Set per UAV of a fleet: file names get _uavN_sortieM, flights carry the UAV.
  int fleet_uav{0};
  /// Set per sortie of a site's fleet (its number in the UAV's run, from 1): the one
  /// sortie exported gets this number, and kml / geojson a file per sortie too.
  int uav_sortie{0};
  double hold_s{1.0}, acceptance_m{0.3}, speed_m_s{2.0}, takeoff_height_m{20.0};
  std::size_t max_waypoints{io::kWpmlMaxWaypoints};
  /// Where the flight lies and the scene it is checked against (app/placement.h).
  app::PlacementRequest placement() const { return {mission, scene, origin, crs, vertical}; }
};

/// The formats placed on the Earth with true heights (io/geodesy.h): one file per
/// sortie (dji-kmz) or one for the whole flight (kml, geojson).
bool isGeographicFormat(const std::string& format) {
  return format == "dji-kmz" || format == "kml" || format == "geojson";
}

/// The export options of the command line (one of --origin and --crs, else the CRS
/// scene.json records: app::relativeFrame), validated.
io::ExportOptions exportOptions(const ExportArgs& a) {
  io::ExportOptions options = app::relativeFrame(a.placement());
  options.autopilot = io::parseAutopilot(a.autopilot);
  options.hold_s = a.hold_s;
  options.acceptance_m = a.acceptance_m;
  options.speed_m_s = a.speed_m_s;
  options.validate();
  return options;
}

/// The flights to export: one surface's path, or the ordered flight's sorties (all,
/// or --sortie's).
std::vector<io::Flight> flightsToExport(const io::MissionRecord& mission, const ExportArgs& a) {
  if (a.surface == "all" || a.sortie != 0) {
    if (!a.surface.empty() && a.surface != "all")
      throw InputError("--sortie: sorties belong to the flight over all surfaces; drop --surface " +
                       a.surface);
    std::vector<io::Flight> flights = io::sortiesFromMission(mission, a.mission);
    if (a.sortie < 0 || a.sortie > static_cast<int>(flights.size()))
      throw InputError("--sortie: " + std::to_string(a.sortie) + " does not exist; " + a.mission +
                       " has " + std::to_string(flights.size()) + " sortie(s), numbered from 1");
    if (a.sortie > 0) flights = {flights[static_cast<std::size_t>(a.sortie - 1)]};
    for (auto& f : flights) {
      f.uav = a.fleet_uav;
      if (a.uav_sortie > 0) f.sortie = a.uav_sortie;
    }
    return flights;
  }
  return {io::flightFromMission(mission, a.mission, a.surface)};
}

/// Warns on stderr when a waypoint lies below home.
void warnBelowHome(const std::vector<io::Flight>& flights, const io::ExportOptions& options) {
  double min_up = 0.0;
  for (const auto& f : flights) {
    for (const auto& w : f.waypoints) min_up = std::min(min_up, w.enu.z() - options.home_m.z());
  }
  if (min_up < 0.0) {
    std::cerr
        << "uavip: warning: the lowest waypoint is " << std::fixed << std::setprecision(2)
        << -min_up
        << (options.crs
                ? " m below home; QGroundControl altitudes are relative to home: take off there\n"
                : " m below the origin (home); check that the origin's altitude is that of the "
                  "ground or lower\n");
  }
}

/// The output file of each flight: OUT, or for several sorties one file each, OUT
/// with _sortieN before the extension (a fleet's UAV: always _uavN_sortieM).
std::vector<std::string> outputPaths(const std::vector<io::Flight>& flights,
                                     const std::string& out_arg) {
  std::vector<std::string> paths;
  for (const auto& f : flights) {
    if (f.uav > 0) {
      const fs::path out(out_arg);
      paths.push_back(
          (out.parent_path() / (out.stem().string() + "_uav" + std::to_string(f.uav) + "_sortie" +
                                std::to_string(f.sortie) + out.extension().string()))
              .string());
    } else if (flights.size() == 1) {
      paths.push_back(out_arg);
    } else {
      const fs::path out(out_arg);
      paths.push_back((out.parent_path() / (out.stem().string() + "_sortie" +
                                            std::to_string(f.sortie) + out.extension().string()))
                          .string());
    }
  }
  return paths;
}

/// What was written: the georeference (--crs) and a line per file.
void reportExport(const ExportArgs& a, const io::ExportOptions& options, io::ExportFormat format,
                  const std::vector<io::Flight>& flights, const std::vector<std::string>& paths) {
  if (options.crs) {
    const io::GeoPoint home = io::homeGeo(options);
    std::cout << "georeferenced by " << options.crs->name() << " (" << a.crs
              << ") with the scene's source_offset_m ("
              << formatFixed(options.source_offset_m.x(), 3) << ", "
              << formatFixed(options.source_offset_m.y(), 3) << ", "
              << formatFixed(options.source_offset_m.z(), 3) << ") m; home "
              << formatPoint(options.home_m) << " local = " << formatFixed(home.lat_deg, 8) << ", "
              << formatFixed(home.lon_deg, 8) << ", " << formatFixed(home.alt_m, 2)
              << " m (the cloud's height datum); waypoint altitudes are relative to "
                 "home, as QGroundControl expects\n";
  }
  for (std::size_t i = 0; i < flights.size(); ++i) {
    const io::Flight& f = flights[i];
    std::string ids;
    for (int id : f.surface_ids) ids += (ids.empty() ? "" : ", ") + std::to_string(id);
    const std::size_t items =
        format == io::ExportFormat::Csv ? f.waypoints.size() : io::missionItems(f, options).size();
    std::cout << "exported "
              << (f.sortie > 0 ? "sortie " + std::to_string(f.sortie) + " (surfaces " : "surface ")
              << ids << (f.sortie > 0 ? ")" : "") << ": " << f.waypoints.size() << " waypoints, "
              << f.stopCount() << " photo stops, " << items
              << (format == io::ExportFormat::Csv ? " rows" : " mission items")
              << ", validated against the scene -> " << paths[i] << "\n";
  }
}

/// OUT with _partK before the extension, when a flight is split into several routes.
std::string partPath(const std::string& path, std::size_t k, std::size_t parts) {
  if (parts == 1) return path;
  const fs::path p(path);
  return (p.parent_path() /
          (p.stem().string() + "_part" + std::to_string(k + 1) + p.extension().string()))
      .string();
}

/// --format kml|geojson: the whole flight in one file (a fleet's UAV: OUT with _uavN).
int mapExport(const ExportArgs& a, const Verbosity& v, const std::vector<io::Flight>& flights,
              const app::MissionPlacement& place) {
  std::string path = a.out;
  if (a.fleet_uav > 0) {
    const fs::path out(a.out);
    const std::string sortie =
        a.uav_sortie > 0 ? "_sortie" + std::to_string(a.uav_sortie) : std::string();
    path = (out.parent_path() / (out.stem().string() + "_uav" + std::to_string(a.fleet_uav) +
                                 sortie + out.extension().string()))
               .string();
  }
  const std::string name = fs::path(path).stem().string();
  io::requireDistinctOutputs({a.mission, a.placement().scenePath()}, {path});
  io::StagedOutputs outputs;
  outputs.write(path,
                a.format == "kml"
                    ? io::flightsKml(flights, *place.geo, place.home, name)
                    : io::flightsGeoJson(flights, *place.geo, place.home, name).dump(1) + "\n");
  outputs.commit();
  if (!v.quiet)
    std::cout << "exported " << flights.size() << " flight(s) as " << a.format << " ("
              << place.geo->describe() << ") -> " << path << "\n";
  return kExitOk;
}

/// The aircraft without --drone: the one mission.json was planned for, else the M350.
constexpr const char* kDefaultDrone = "m350";

/// The DJI options of the command line, validated; the aircraft is the mission's
/// (mission.json `aircraft`) unless --drone names another (a warning says so).
io::WpmlOptions wpmlOptions(const ExportArgs& a, const io::MissionRecord& mission,
                            const Verbosity& v) {
  io::WpmlOptions o;
  const bool planned_dji = !mission.drone.empty() && mission.drone != "generic";
  if (a.drone.empty()) {
    o.drone = planned_dji
                  ? io::findDjiDrone(mission.drone, a.payload.empty() ? mission.payload : a.payload)
                  : io::findDjiDrone(kDefaultDrone, a.payload);
  } else {
    o.drone = io::findDjiDrone(a.drone, a.payload);
    if (planned_dji &&
        (a.drone != mission.drone || (!a.payload.empty() && a.payload != mission.payload)) &&
        !v.quiet)
      std::cerr << "uavip: warning: " << a.mission << " was planned for the " << mission.drone
                << (mission.payload.empty() ? "" : " with the " + mission.payload)
                << "; exporting for the " << o.drone.name
                << ": its camera, gimbal and speed may not fly the plan as planned\n";
  }
  o.height_mode = io::parseWpmlHeightMode(a.height_mode);
  o.speed_m_s = a.speed_m_s;
  o.hold_s = a.hold_s;
  o.takeoff_security_height_m = a.takeoff_height_m;
  o.max_waypoints = a.max_waypoints;
  o.validate();
  return o;
}

/// Stages one route's KMZ at `path`: written, read back, converted to the local frame
/// and validated as the aircraft will fly it. Returns the report line.
std::string stageRoute(io::StagedOutputs& outputs, const std::string& path, const io::Flight& route,
                       const app::MissionPlacement& place, const io::WpmlOptions& o,
                       const planning::PathValidator& validator, const ExportArgs& a) {
  const io::WpmlDocuments docs = io::wpmlDocuments(route, *place.geo, place.home, o);
  double worst = 0.0;
  outputs.writeWith(path, [&](const std::string& tmp) {
    io::writeKmz(tmp, docs);
    const PointList flown = io::routeToLocal(io::readKmzRoute(tmp), *place.geo, place.home);
    if (flown.size() != route.waypoints.size())
      throw InputError(path + ": read back " + std::to_string(flown.size()) + " waypoints of " +
                       std::to_string(route.waypoints.size()));
    for (std::size_t j = 0; j < flown.size(); ++j)
      worst = std::max(worst, (flown[j] - route.waypoints[j].enu).norm());
    app::requireClear(validator, flown,
                      app::flightLabel(route, a.mission) + " as written in " + path, a.placement());
  });
  return "exported " + app::flightLabel(route, a.mission) + ": " +
         std::to_string(route.waypoints.size()) + " waypoints, " +
         std::to_string(route.stopCount()) + " photo stops -> " + path +
         "; read back (largest difference " + formatFixed(worst * 1000.0, 2) +
         " mm) and validated against the scene as flown";
}

/// --format dji-kmz: one KMZ per sortie (and per part of a sortie too long for WPML).
int djiExport(const ExportArgs& a, const Verbosity& v, const io::MissionRecord& mission,
              const std::vector<io::Flight>& flights, const app::MissionPlacement& place,
              const planning::PathValidator& validator) {
  const io::WpmlOptions o = wpmlOptions(a, mission, v);
  const std::vector<std::string> paths = outputPaths(flights, a.out);
  io::StagedOutputs outputs;
  std::vector<std::string> lines;  // the report, printed once everything is in place
  try {
    std::vector<std::string> all_paths;
    for (std::size_t i = 0; i < flights.size(); ++i) {
      const std::vector<io::Flight> parts = io::splitForWpml(flights[i], o.max_waypoints);
      if (parts.size() > 1 && !v.quiet)
        std::cerr << "uavip: " << app::flightLabel(flights[i], a.mission) << " has "
                  << flights[i].waypoints.size() << " waypoints, more than " << o.max_waypoints
                  << " per WPML route: split into " << parts.size()
                  << " routes flown one after another\n";
      for (std::size_t k = 0; k < parts.size(); ++k) {
        all_paths.push_back(partPath(paths[i], k, parts.size()));
        io::requireDistinctOutputs({a.mission, a.placement().scenePath()}, all_paths);
        lines.push_back(stageRoute(outputs, all_paths.back(), parts[k], place, o, validator, a));
      }
    }
  } catch (const io::NoMissionError& e) {
    std::cerr << "uavip: " << escapeControl(e.what()) << "\n";
    return kExitNoMission;
  }
  outputs.commit();
  if (!v.quiet) {
    const io::Geodetic home = place.geo->toGeodetic(place.home);
    std::cout << "DJI WPML for the " << o.drone.model << " (" << o.drone.payload.model
              << "), heights "
              << (o.height_mode == io::WpmlHeightMode::Relative
                      ? "relativeToStartPoint (above home: take off there)"
                      : "WGS84 (above the ellipsoid)")
              << "; home " << formatPoint(place.home) << " local = " << formatFixed(home.lat_deg, 8)
              << ", " << formatFixed(home.lon_deg, 8) << ", "
              << formatFixed(place.geo->egm96Height(home), 2) << " m above EGM96; "
              << place.geo->describe() << "\n";
    for (const auto& line : lines) std::cout << line << "\n";
  }
  return kExitOk;
}

/// export --format dji-kmz|kml|geojson: placed on the Earth with true heights; each
/// KMZ is read back, converted to the local frame and validated as the aircraft will
/// fly it before anything is renamed into place.
int geographicExport(const ExportArgs& a, const Verbosity& v, const io::MissionRecord& mission) {
  std::vector<io::Flight> flights;
  std::unique_ptr<planning::PathValidator> validator;
  try {
    flights = flightsToExport(mission, a);
    validator = app::sceneValidator(mission, a.placement());
    app::requireFlightsClear(*validator, flights, a.placement());
  } catch (const io::NoMissionError& e) {
    std::cerr << "uavip: " << escapeControl(e.what()) << "\n";
    return kExitNoMission;
  }
  const app::MissionPlacement place = app::placeMission(mission, flights, a.placement());
  if (!v.quiet)
    for (const auto& w : place.warnings) std::cerr << "uavip: warning: " << w << "\n";
  return a.format == "dji-kmz" ? djiExport(a, v, mission, flights, place, *validator)
                               : mapExport(a, v, flights, place);
}

int exportOne(const ExportArgs& a, const Verbosity& v, const io::MissionRecord& mission) {
  if (isGeographicFormat(a.format)) return geographicExport(a, v, mission);
  io::ExportOptions options = exportOptions(a);
  const io::ExportFormat format = io::parseExportFormat(a.format);
  std::vector<io::Flight> flights;
  try {
    flights = flightsToExport(mission, a);
    if (!options.crs)
      app::requireNearOrigin(flights, a.mission);  // --crs: PROJ places every point, no flat earth
    app::requireFlightsClear(*app::sceneValidator(mission, a.placement()), flights, a.placement());
  } catch (const io::NoMissionError& e) {
    std::cerr << "uavip: " << escapeControl(e.what()) << "\n";
    return kExitNoMission;
  }
  app::placeRelativeHome(options, mission, flights, a.placement());
  if (!v.quiet) warnBelowHome(flights, options);
  const std::vector<std::string> paths = outputPaths(flights, a.out);
  io::requireDistinctOutputs({a.mission, a.placement().scenePath()}, paths);
  io::StagedOutputs outputs;  // every sortie's file, or none
  for (std::size_t i = 0; i < flights.size(); ++i)
    outputs.write(paths[i], io::exportFlight(flights[i], format, options));
  outputs.commit();
  if (!v.quiet) reportExport(a, options, format, flights, paths);
  return kExitOk;
}

/// A fleet's flights (mission.json `fleet`, --surface all or --sortie or --uav): each
/// UAV's sorties exported from its own home, after a line with its take-off times.
int exportFleet(const ExportArgs& a, const Verbosity& v, const io::MissionRecord& mission) {
  const io::FleetRecord& fleet = *mission.fleet;
  if (a.uav < 0 || a.uav > static_cast<int>(fleet.uavs.size()))
    throw InputError("--uav: " + std::to_string(a.uav) + " does not exist; " + a.mission + " has " +
                     std::to_string(fleet.uavs.size()) + " UAVs, numbered from 1");
  for (std::size_t u = 0; u < fleet.uavs.size(); ++u) {
    if (a.uav > 0 && static_cast<int>(u) + 1 != a.uav) continue;
    const io::FleetUavRecord& rec = fleet.uavs[u];
    if (!v.quiet) {
      std::cout << "uav " << u + 1 << ": home " << formatPoint(rec.home) << ", "
                << rec.sorties.size() << " sorties, take-off at";
      for (const double t : rec.start_s) std::cout << " +" << formatFixed(t, 1) << " s";
      std::cout << (rec.sorties.empty() ? " - (stays on the ground)" : "") << "\n";
    }
    if (rec.sorties.empty()) continue;
    io::MissionRecord own = mission;
    own.flight = io::FlightRecord{fleet.status, "", rec.sorties};
    ExportArgs b = a;
    b.fleet_uav = static_cast<int>(u) + 1;
    b.surface = "all";
    const int code = exportOne(b, v, own);
    if (code != kExitOk) return code;
  }
  return kExitOk;
}

/// A site's fleet (site.json of `merge --uavs K` over several sections,
/// app/site_fleet.h; every UAV, or --uav's): each UAV's sorties in its order, each
/// exported from its own section's mission.json (its home, scene and frame) as
/// OUT_uavN_sortieM, after a line per UAV with its take-off times.
int exportSite(const ExportArgs& a, const Verbosity& v, const nlohmann::json& site) {
  if (!site.contains("fleet"))
    throw InputError(a.mission + ": a site without a fleet; export each section: uavip export " +
                     (fs::path(a.mission).parent_path() / "section_NNN" / "mission.json").string() +
                     " --surface all ...");
  if (a.sortie != 0 || (!a.surface.empty() && a.surface != "all"))
    throw InputError("--sortie / --surface: a site's fleet is exported by UAV (--uav N) or whole");
  if (!a.scene.empty())
    throw InputError("--scene: each sortie of a site is checked against its own section's scene");
  const auto missions = io::siteMissions(site, a.mission);
  const io::SiteFleetRecord record = io::siteFleetFromJson(site, a.mission, missions);
  const auto uavs = static_cast<int>(record.sorties.size());
  if (a.uav < 0 || a.uav > uavs)
    throw InputError("--uav: " + std::to_string(a.uav) + " does not exist; " + a.mission + " has " +
                     std::to_string(uavs) + " UAVs, numbered from 1");
  for (int u = 0; u < uavs; ++u) {
    if (a.uav > 0 && u + 1 != a.uav) continue;
    const auto& run = record.sorties[static_cast<std::size_t>(u)];
    const io::FleetUavRecord& rec = record.fleet.uavs[static_cast<std::size_t>(u)];
    if (!v.quiet) {
      std::cout << "uav " << u + 1 << ": " << run.size() << " sorties, take-off at";
      for (std::size_t k = 0; k < run.size(); ++k)
        std::cout << " +" << formatFixed(rec.start_s[k], 1) << " s (" << run[k].first << " sortie "
                  << run[k].second + 1 << ")";
      std::cout << (run.empty() ? " - (stays on the ground)" : "") << "\n";
    }
    for (std::size_t k = 0; k < run.size(); ++k) {
      io::MissionRecord own = missions.at(run[k].first);
      own.flight = io::FlightRecord{"ok", "", {rec.sorties[k]}};
      ExportArgs b = a;
      b.mission = (fs::path(a.mission).parent_path() / run[k].first / "mission.json").string();
      b.fleet_uav = u + 1;
      b.uav_sortie = static_cast<int>(k) + 1;
      b.surface = "all";
      const int code = exportOne(b, v, own);
      if (code != kExitOk) return code;
    }
  }
  return kExitOk;
}

int exportCommand(const ExportArgs& a, const Verbosity& v) {
  const nlohmann::json j = io::JsonReader(a.mission).load();
  if (io::isSiteJson(j)) return exportSite(a, v, j);
  const io::MissionRecord mission = io::missionFromJson(j, a.mission);
  if (mission.fleet && (a.surface == "all" || a.sortie != 0 || a.uav != 0))
    return exportFleet(a, v, mission);
  if (a.uav != 0) throw InputError("--uav: " + a.mission + " has no fleet (plan with --uavs K)");
  return exportOne(a, v, mission);
}

}  // namespace

void addExportCommands(CLI::App& cli, CommandRegistry& registry) {
  const auto [ex, a] = missionCommand<ExportArgs>(
      cli, "export",
      "Write a mission.json as a DJI WPML route (KMZ for DJI Pilot 2 / FlightHub 2), a "
      "QGroundControl .plan, QGC WPL 110, CSV, or KML / GeoJSON to check it on a map. Local ENU -> "
      "WGS84 about --origin, or by the cloud's CRS (--crs, else the one scene.json records); "
      "headings are compass (0 = north, clockwise) = 90 - ENU yaw");
  const Verbosity& v = registry.verbosity();
  ex->add_option("--format", a->format,
                 "dji-kmz (one .kmz per sortie), qgc-plan, wpl, csv, kml (Google Earth) or geojson")
      ->required();
  ex->add_option("--origin", a->origin,
                 "LAT,LON,ALT of the local origin (0,0,0) = home [deg, deg, m above mean sea "
                 "level (EGM96)]");
  ex->add_option("--crs", a->crs,
                 "The cloud's projected CRS (e.g. EPSG:32631, UTM 31N; EPSG:32650+5773 with EGM96 "
                 "heights): waypoint + the scene's source_offset_m -> WGS84 by PROJ; home is the "
                 "flight's first waypoint. Default: the CRS scene.json records (detect reads it "
                 "from a LAS file or takes detect --crs)");
  ex->add_option("--vertical", a->vertical,
                 "What the cloud's z is measured from: egm96, egm2008 or ellipsoid (default: the "
                 "CRS's vertical part, else egm96); dji-kmz, kml, geojson");
  ex->add_option("--drone", a->drone,
                 "dji-kmz: the DJI model (default: the one mission.json was planned for, else "
                 "m350): " +
                     io::djiDroneList());
  ex->add_option(
      "--payload", a->payload,
      "dji-kmz, m300/m350 only: the Zenmuse camera (default: the mission's, else h20): " +
          aircraft::payloadList() + " (each its own enum value and gimbal pitch range)");
  ex->add_option("--height-mode", a->height_mode,
                 "dji-kmz: relative (relativeToStartPoint: metres above home, take off there) or "
                 "ellipsoid (WGS84: metres above the WGS84 ellipsoid; needs RTK-grade heights)")
      ->capture_default_str();
  ex->add_option("--takeoff-height", a->takeoff_height_m,
                 "dji-kmz: takeOffSecurityHeight, the climb after take-off [m, 1.2-1500]")
      ->capture_default_str();
  ex->add_option("--max-waypoints", a->max_waypoints,
                 "dji-kmz: waypoints per route; a longer sortie is split into _partK files")
      ->capture_default_str();
  ex->add_option("-o,--out", a->out, "Output file")->required();
  ex->add_option("--surface", a->surface,
                 "Surface id (its own path), or 'all' (the ordered flight's sorties, one file each "
                 "when several); "
                 "default: the only surface with a mission");
  ex->add_option("--sortie", a->sortie, "Only this sortie of the ordered flight (from 1)");
  ex->add_option("--uav", a->uav,
                 "A fleet (plan --uavs K): only this UAV's sorties (from 1); default: every UAV's, "
                 "one file per UAV and sortie (OUT_uavN_sortieM). Given a site.json of merge "
                 "--uavs K, each UAV's sorties across the sections, one file each");
  ex->add_option("--scene", a->scene,
                 "scene.json the mission was planned in (default: beside the mission); every "
                 "exported leg is checked against it");
  ex->add_option("--autopilot", a->autopilot,
                 "px4 (heading in NAV_WAYPOINT) or ardupilot (adds CONDITION_YAW)")
      ->capture_default_str();
  ex->add_option("--hold", a->hold_s, "Hover time at each photo stop [s]")->capture_default_str();
  ex->add_option("--acceptance", a->acceptance_m, "Waypoint acceptance radius [m]")
      ->capture_default_str();
  ex->add_option("--speed", a->speed_m_s,
                 "Flight speed (hoverSpeed of the .plan; every waypoint's of a KMZ) [m/s]")
      ->capture_default_str();
  registry.add(ex, [a = a, &v] { return exportCommand(*a, v); });
}

}  // namespace uavip::cli
