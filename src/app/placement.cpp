#include "uavip/app/placement.h"

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <optional>
#include <sstream>

#include "uavip/core/error.h"
#include "uavip/core/text.h"
#include "uavip/io/cloud_io.h"
#include "uavip/io/json_reader.h"
#include "uavip/io/scene_json.h"
#include "uavip/world/collision_world.h"

namespace uavip::app {
namespace {

/// The CRS scene.json records, if the scene is there and has one.
std::optional<io::SceneCrsRecord> recordedCrs(const PlacementRequest& r) {
  const std::string path = r.scenePath();
  if (!std::filesystem::is_regular_file(path)) return std::nullopt;
  return io::sceneCrsFromJson(io::JsonReader(path).load(), path);
}

/// --crs: scene.json's source_offset_m, the cloud's file coordinates of the local
/// origin. A scene without one (a cloud within 10 km of its own origin) cannot be
/// placed by a CRS.
Vec3 sceneSourceOffset(const PlacementRequest& r) {
  const std::string path = r.scenePath();
  if (!std::filesystem::is_regular_file(path))
    throw InputError(
        "--crs: " + path +
        " not found; the scene gives the cloud's offset in its CRS: pass --scene OUT/scene.json");
  const io::JsonReader reader(path);
  const nlohmann::json scene = reader.load();
  if (!scene.is_object() || !scene.contains("source_offset_m"))
    throw InputError("--crs " + r.crs + ": " + path +
                     " has no source_offset_m: its cloud lies within " +
                     formatNumber(io::kRecentreBeyondM / 1e3) +
                     " km of its own origin, so it is not in a projected "
                     "CRS; pass --origin LAT,LON,ALT instead");
  return reader.vec3(scene.at("source_offset_m"), "source_offset_m", false);
}

/// The vertical datum of the cloud's heights: --vertical, else scene.json's record,
/// else the compound CRS's vertical part, else EGM96 (docs/formats.md). A --vertical
/// that overrides the CRS's own vertical part adds a warning.
io::VerticalDatum heightDatum(const PlacementRequest& r, const io::CrsTransform& crs,
                              const std::optional<io::SceneCrsRecord>& scene,
                              std::vector<std::string>& warnings) {
  const std::optional<io::VerticalDatum> of_crs = io::verticalDatumOfEpsg(crs.verticalEpsg());
  if (!r.vertical.empty()) {
    const io::VerticalDatum d = io::parseVerticalDatum(r.vertical);
    if (!crs.verticalName().empty() && (!of_crs || *of_crs != d))
      warnings.push_back("--vertical " + r.vertical + " overrides the CRS's vertical " +
                         crs.verticalName() + " (EPSG:" + std::to_string(crs.verticalEpsg()) + ")");
    return d;
  }
  return io::defaultVerticalDatum(crs, scene ? scene->vertical : "", r.scenePath());
}

}  // namespace

std::string PlacementRequest::scenePath() const {
  return scene.empty() ? (std::filesystem::path(mission).parent_path() / "scene.json").string()
                       : scene;
}

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

std::string flightLabel(const io::Flight& flight, const std::string& mission) {
  return mission + ": " +
         (flight.sortie > 0 ? "sortie " + std::to_string(flight.sortie)
                            : "surface " + std::to_string(flight.surface_ids.front()));
}

std::unique_ptr<planning::PathValidator> sceneValidator(const io::MissionRecord& mission,
                                                        const PlacementRequest& request) {
  const std::string scene_path = request.scenePath();
  if (!std::filesystem::is_regular_file(scene_path))
    throw InputError("--scene: " + scene_path +
                     " not found; export checks every leg against the scene the mission " +
                     "was planned in: pass --scene OUT/scene.json");
  if (std::isnan(mission.inflation_radius_m))
    throw InputError(request.mission +
                     ": inflation_radius_m is missing (not a mission.json of uavip run or plan)");
  const Scene scene = io::loadScene(scene_path);
  return std::make_unique<planning::PathValidator>(
      std::make_shared<const world::CollisionWorld>(scene), mission.inflation_radius_m);
}

void requireClear(const planning::PathValidator& validator, const PointList& path,
                  const std::string& what, const PlacementRequest& request) {
  const planning::ValidationResult v = validator.validate(path);
  if (v.collision_free) return;
  std::ostringstream os;
  os << std::fixed << std::setprecision(3) << what << ", segment " << v.first_violation_segment
     << " comes " << v.segment_clearance_m[static_cast<std::size_t>(v.first_violation_segment)]
     << " m from " << v.violation_object << " of " << request.scenePath() << " (required "
     << validator.requiredClearance() << " m); not exported: re-run uavip plan";
  throw io::NoMissionError(os.str());
}

void requireFlightsClear(const planning::PathValidator& validator,
                         const std::vector<io::Flight>& flights, const PlacementRequest& request) {
  for (const auto& f : flights) {
    PointList path;
    for (const auto& w : f.waypoints) path.push_back(w.enu);
    requireClear(validator, path, flightLabel(f, request.mission), request);
  }
}

Vec3 missionHome(const io::MissionRecord& mission, const std::vector<io::Flight>& flights) {
  return mission.flight && !mission.flight->sorties.empty() &&
                 !mission.flight->sorties[0].waypoints.empty()
             ? mission.flight->sorties[0].waypoints.front()
         : !flights.empty() && !flights.front().waypoints.empty()
             ? flights.front().waypoints.front().enu
             : Vec3::Zero();
}

MissionPlacement placeMission(const io::MissionRecord& mission,
                              const std::vector<io::Flight>& flights,
                              const PlacementRequest& request) {
  if (!request.origin.empty() && !request.crs.empty())
    throw InputError(
        "--origin and --crs: choose one (--crs places the flight by the cloud's own "
        "CRS, --origin by a WGS84 position of the local origin)");
  MissionPlacement p;
  // Home is the take-off and landing point of every sortie (mission.home): relative
  // heights are above it, with --origin too.
  p.home = missionHome(mission, flights);
  if (!request.origin.empty()) {
    requireNearOrigin(flights, request.mission);
    p.geo = std::make_unique<io::Georeference>(io::parseOrigin(request.origin));
    return p;
  }
  const std::optional<io::SceneCrsRecord> scene = recordedCrs(request);
  std::string definition = request.crs;
  if (definition.empty()) {
    if (!scene)
      throw InputError(
          "--origin: missing, and " + request.scenePath() +
          " records no CRS (the cloud did not state one, and detect had no --crs); pass --origin "
          "LAT,LON,ALT (ALT above mean sea level) or --crs EPSG:CODE (the cloud's projected CRS)");
    definition = scene->definition;
  } else if (scene && scene->definition != definition) {
    p.warnings.push_back("--crs " + definition + " differs from the scene's CRS " +
                         scene->definition + " (from " + scene->source + "); using --crs " +
                         definition);
  }
  const auto crs = std::make_shared<const io::CrsTransform>(
      definition, request.crs.empty() ? request.scenePath() + ": crs" : "--crs");
  const io::VerticalDatum vertical = heightDatum(request, *crs, scene, p.warnings);
  // A CRS the scene records comes with its offset (zero when the cloud was not
  // recentred); a --crs given by hand needs the scene's offset (sceneSourceOffset says
  // why).
  const Vec3 offset = request.crs.empty() ? scene->source_offset_m : sceneSourceOffset(request);
  p.geo = std::make_unique<io::Georeference>(crs, offset, vertical);
  return p;
}

io::ExportOptions relativeFrame(const PlacementRequest& request) {
  if (!request.origin.empty() && !request.crs.empty())
    throw InputError(
        "--origin and --crs: choose one (--crs places the flight by the cloud's own CRS, --origin "
        "by a WGS84 position of the local origin)");
  io::ExportOptions options;
  if (!request.origin.empty()) {
    options.origin = io::parseOrigin(request.origin);
  } else if (!request.crs.empty()) {
    options.crs = std::make_shared<const io::CrsTransform>(request.crs);
  } else if (const std::optional<io::SceneCrsRecord> scene = recordedCrs(request)) {
    options.crs =
        std::make_shared<const io::CrsTransform>(scene->definition, request.scenePath() + ": crs");
  } else {
    throw InputError(
        "--origin: missing, and " + request.scenePath() +
        " records no CRS; pass --origin LAT,LON,ALT, the WGS84 position (degrees, degrees, metres "
        "above sea level) of the local frame's origin (0, 0, 0), which is also home; or --crs "
        "EPSG:CODE, the projected CRS of a georeferenced cloud (e.g. EPSG:32631 for UTM zone 31N)");
  }
  return options;
}

void placeRelativeHome(io::ExportOptions& options, const io::MissionRecord& mission,
                       const std::vector<io::Flight>& flights, const PlacementRequest& request) {
  if (!options.crs) return;
  options.source_offset_m = sceneSourceOffset(request);
  options.home_m = missionHome(mission, flights);
}

}  // namespace uavip::app
