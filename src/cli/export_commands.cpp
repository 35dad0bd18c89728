// uavip export: a mission.json as a QGroundControl .plan, a QGC WPL 110 file or a
// CSV (io/mission_export.h has the item layout and the heading convention).

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>

#include "src/cli/commands.h"
#include "uavip/core/error.h"
#include "uavip/core/text.h"
#include "uavip/io/atomic_file.h"
#include "uavip/io/cloud_io.h"
#include "uavip/io/json_reader.h"
#include "uavip/io/mission_export.h"
#include "uavip/io/scene_json.h"
#include "uavip/planning/path_validator.h"
#include "uavip/world/collision_world.h"

namespace uavip::cli {
namespace {

namespace fs = std::filesystem;

/// Farthest waypoint from the origin (home) that export converts [m]: local ENU is a
/// flat-earth frame, and no inspection flight goes farther.
constexpr double kMaxDistanceFromOriginM = 50e3;

/// Options of export, kept alive until dispatch.
struct ExportArgs {
  std::string mission, format, origin, crs, out, surface, autopilot{"px4"}, scene;
  int sortie{0};
  double hold_s{1.0}, acceptance_m{0.3}, speed_m_s{2.0};
};

/// The scene.json export checks against: --scene, else the one beside the mission.
std::string sceneFor(const ExportArgs& a) {
  return a.scene.empty() ? (fs::path(a.mission).parent_path() / "scene.json").string() : a.scene;
}

/// Local ENU is a flat-earth frame about the origin: a waypoint beyond
/// kMaxDistanceFromOriginM is refused, naming it.
void requireNearOrigin(const std::vector<io::Flight>& flights, const std::string& mission) {
  for (const auto& f : flights) {
    for (const auto& w : f.waypoints) {
      if (w.enu.norm() > kMaxDistanceFromOriginM)
        throw InputError(mission + ": waypoint " + formatPoint(w.enu) + " lies " +
                         formatFixed(w.enu.norm() / 1e3, 1) +
                         " km from the origin; export converts flights within " +
                         formatNumber(kMaxDistanceFromOriginM / 1e3) +
                         " km of --origin (local metres about it)");
    }
  }
}

/// Every exported path is checked again against the scene with the FCL validator:
/// a mission.json changed by hand, or paired with another scene, is refused (exit 3).
void checkAgainstScene(const std::vector<io::Flight>& flights, const io::MissionRecord& mission,
                       const ExportArgs& a) {
  const std::string scene_path = sceneFor(a);
  if (!fs::is_regular_file(scene_path))
    throw InputError("--scene: " + scene_path +
                     " not found; export checks every leg against the scene the mission " +
                     "was planned in: pass --scene OUT/scene.json");
  if (std::isnan(mission.inflation_radius_m))
    throw InputError(a.mission +
                     ": inflation_radius_m is missing (not a mission.json of uavip run or plan)");
  const Scene scene = io::loadScene(scene_path);
  const planning::PathValidator validator(std::make_shared<const world::CollisionWorld>(scene),
                                          mission.inflation_radius_m);
  for (const auto& f : flights) {
    PointList path;
    for (const auto& w : f.waypoints) path.push_back(w.enu);
    const planning::ValidationResult v = validator.validate(path);
    if (v.collision_free) continue;
    std::ostringstream os;
    os << std::fixed << std::setprecision(3) << a.mission << ": "
       << (f.sortie > 0 ? "sortie " + std::to_string(f.sortie)
                        : "surface " + std::to_string(f.surface_ids.front()))
       << ", segment " << v.first_violation_segment << " comes "
       << v.segment_clearance_m[static_cast<std::size_t>(v.first_violation_segment)] << " m from "
       << v.violation_object << " of " << scene_path << " (required "
       << validator.requiredClearance() << " m); not exported: re-run uavip plan";
    throw io::NoMissionError(os.str());
  }
}

/// --crs: scene.json's source_offset_m, the cloud's file coordinates of the local
/// origin. A scene without one (a cloud within 10 km of its own origin) cannot be
/// placed by a CRS.
Vec3 sourceOffset(const ExportArgs& a) {
  const std::string path = sceneFor(a);
  if (!fs::is_regular_file(path))
    throw InputError(
        "--crs: " + path +
        " not found; the scene gives the cloud's offset in its CRS: pass --scene OUT/scene.json");
  const io::JsonReader reader(path);
  const nlohmann::json scene = reader.load();
  if (!scene.is_object() || !scene.contains("source_offset_m"))
    throw InputError("--crs " + a.crs + ": " + path +
                     " has no source_offset_m: its cloud lies within " +
                     formatNumber(io::kRecentreBeyondM / 1e3) +
                     " km of its own origin, so it is not in a projected "
                     "CRS; pass --origin LAT,LON,ALT instead");
  return reader.vec3(scene.at("source_offset_m"), "source_offset_m", false);
}

/// The export options of the command line (one of --origin and --crs), validated.
io::ExportOptions exportOptions(const ExportArgs& a) {
  if (!a.origin.empty() && !a.crs.empty())
    throw InputError(
        "--origin and --crs: choose one (--crs places the flight by the cloud's own CRS, --origin "
        "by a "
        "WGS84 position of the local origin)");
  if (a.origin.empty() && a.crs.empty())
    throw InputError(
        "--origin: missing; pass --origin LAT,LON,ALT, the WGS84 position (degrees, degrees, "
        "metres above "
        "sea level) of the local frame's origin (0, 0, 0), which is also home; or --crs EPSG:CODE, "
        "the "
        "projected CRS of a georeferenced cloud (e.g. EPSG:32631 for UTM zone 31N)");
  io::ExportOptions options;
  if (!a.origin.empty()) options.origin = io::parseOrigin(a.origin);
  if (!a.crs.empty()) options.crs = std::make_shared<const io::CrsTransform>(a.crs);
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
    return flights;
  }
  return {io::flightFromMission(mission, a.mission, a.surface)};
}

/// Home in local coordinates: the ordered flight's (every sortie starts there), else
/// the first flight's first waypoint, else the origin.
Vec3 homeOf(const io::MissionRecord& mission, const std::vector<io::Flight>& flights) {
  return mission.flight && !mission.flight->sorties.empty() &&
                 !mission.flight->sorties[0].waypoints.empty()
             ? mission.flight->sorties[0].waypoints.front()
         : !flights.empty() && !flights.front().waypoints.empty()
             ? flights.front().waypoints.front().enu
             : Vec3::Zero();
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
/// with _sortieN before the extension.
std::vector<std::string> outputPaths(const std::vector<io::Flight>& flights,
                                     const std::string& out_arg) {
  std::vector<std::string> paths;
  for (const auto& f : flights) {
    if (flights.size() == 1) {
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

int exportCommand(const ExportArgs& a, const Verbosity& v) {
  io::ExportOptions options = exportOptions(a);
  const io::ExportFormat format = io::parseExportFormat(a.format);
  const io::MissionRecord mission = io::loadMission(a.mission);
  std::vector<io::Flight> flights;
  try {
    flights = flightsToExport(mission, a);
    if (!options.crs)
      requireNearOrigin(flights, a.mission);  // --crs: PROJ places every point, no flat earth
    checkAgainstScene(flights, mission, a);
  } catch (const io::NoMissionError& e) {
    std::cerr << "uavip: " << escapeControl(e.what()) << "\n";
    return kExitNoMission;
  }
  if (options.crs) {
    options.source_offset_m = sourceOffset(a);
    options.home_m = homeOf(mission, flights);
  }
  if (!v.quiet) warnBelowHome(flights, options);
  const std::vector<std::string> paths = outputPaths(flights, a.out);
  io::requireDistinctOutputs({a.mission, sceneFor(a)}, paths);
  io::StagedOutputs outputs;  // every sortie's file, or none
  for (std::size_t i = 0; i < flights.size(); ++i)
    outputs.write(paths[i], io::exportFlight(flights[i], format, options));
  outputs.commit();
  if (!v.quiet) reportExport(a, options, format, flights, paths);
  return kExitOk;
}

}  // namespace

void addExportCommands(CLI::App& cli, CommandRegistry& registry) {
  const auto [ex, a] = missionCommand<ExportArgs>(
      cli, "export",
      "Write a mission.json as a QGroundControl .plan, QGC WPL 110 or CSV file. Local ENU -> WGS84 "
      "about --origin, or by the cloud's CRS (--crs); "
      "headings are compass (0 = north, clockwise) = 90 - ENU yaw; altitudes relative to home");
  const Verbosity& v = registry.verbosity();
  ex->add_option("--format", a->format, "qgc-plan, wpl or csv")->required();
  ex->add_option("--origin", a->origin,
                 "LAT,LON,ALT of the local origin (0,0,0) = home [deg, deg, m above sea level]");
  ex->add_option("--crs", a->crs,
                 "The cloud's projected CRS (e.g. EPSG:32631, UTM 31N): waypoint + the scene's "
                 "source_offset_m -> WGS84 "
                 "by PROJ; home is the flight's first waypoint. Instead of --origin");
  ex->add_option("-o,--out", a->out, "Output file")->required();
  ex->add_option("--surface", a->surface,
                 "Surface id (its own path), or 'all' (the ordered flight's sorties, one file each "
                 "when several); "
                 "default: the only surface with a mission");
  ex->add_option("--sortie", a->sortie, "Only this sortie of the ordered flight (from 1)");
  ex->add_option("--scene", a->scene,
                 "scene.json the mission was planned in (default: beside the mission); every "
                 "exported leg is checked against it");
  ex->add_option("--autopilot", a->autopilot,
                 "px4 (heading in NAV_WAYPOINT) or ardupilot (adds CONDITION_YAW)")
      ->capture_default_str();
  ex->add_option("--hold", a->hold_s, "Hover time at each photo stop [s]")->capture_default_str();
  ex->add_option("--acceptance", a->acceptance_m, "Waypoint acceptance radius [m]")
      ->capture_default_str();
  ex->add_option("--speed", a->speed_m_s, "Flight speed (hoverSpeed of the .plan) [m/s]")
      ->capture_default_str();
  registry.add(ex, [a = a, &v] { return exportCommand(*a, v); });
}

}  // namespace uavip::cli
