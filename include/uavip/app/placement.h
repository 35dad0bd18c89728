#pragma once
/// \file
/// Where an exported mission lies on the Earth, and the check that it is still the
/// collision-free mission of its scene (`uavip export`): the local ENU frame placed by a
/// WGS84 origin or by the cloud's CRS (given, or the one scene.json records) with the
/// scene's source offset and the vertical datum of the cloud's heights (io/geodesy.h),
/// home (the take-off point relative heights are measured from), and every exported path
/// checked again with the FCL validator against the scene it was planned in. Nothing
/// here prints: warnings are returned.

#include <memory>
#include <string>
#include <vector>

#include "uavip/core/types.h"
#include "uavip/io/geodesy.h"
#include "uavip/io/mission_export.h"
#include "uavip/io/mission_json.h"
#include "uavip/planning/path_validator.h"

namespace uavip::app {

/// What export's command line says about where the mission lies.
struct PlacementRequest {
  std::string mission;   ///< mission.json (named in messages)
  std::string scene;     ///< --scene: scene.json it was planned in; empty: the one beside it
  std::string origin;    ///< --origin "LAT,LON,ALT" [deg, deg, m above EGM96], or empty
  std::string crs;       ///< --crs: the cloud's projected CRS ("EPSG:32631"), or empty
  std::string vertical;  ///< --vertical: egm96, egm2008 or ellipsoid, or empty
  /// The scene.json: `scene`, else scene.json beside the mission.
  std::string scenePath() const;
};

/// Farthest waypoint from the origin (home) that --origin places [m]: local ENU about a
/// WGS84 point is a flat-earth frame, and no inspection flight goes farther.
constexpr double kMaxDistanceFromOriginM = 50e3;

/// Throws InputError naming the first waypoint beyond kMaxDistanceFromOriginM of the
/// origin (`mission`: the file, named in the message).
void requireNearOrigin(const std::vector<io::Flight>& flights, const std::string& mission);

/// A flight's name in messages: "mission.json: sortie 2" or "mission.json: surface 3".
std::string flightLabel(const io::Flight& flight, const std::string& mission);

/// The FCL validator (surfaces, obstacles, every measured point) of the scene the
/// mission was planned in, at the mission's inflation radius. Throws InputError when
/// the scene is missing or the mission records no inflation radius.
std::unique_ptr<planning::PathValidator> sceneValidator(const io::MissionRecord& mission,
                                                        const PlacementRequest& request);

/// Throws io::NoMissionError (exit 3) naming `what` and its first segment that comes
/// closer to the scene than the validator requires.
void requireClear(const planning::PathValidator& validator, const PointList& path,
                  const std::string& what, const PlacementRequest& request);

/// requireClear for every waypoint path of `flights` (a mission.json changed by hand, or
/// paired with another scene, is refused).
void requireFlightsClear(const planning::PathValidator& validator,
                         const std::vector<io::Flight>& flights, const PlacementRequest& request);

/// Home in local coordinates [m]: the ordered flight's (every sortie starts there),
/// else the first flight's first waypoint, else the origin.
Vec3 missionHome(const io::MissionRecord& mission, const std::vector<io::Flight>& flights);

/// The mission placed with true heights (dji-kmz, kml, geojson).
struct MissionPlacement {
  std::unique_ptr<io::Georeference> geo;  ///< local ENU ↔ WGS84 with ellipsoidal heights
  Vec3 home{Vec3::Zero()};                ///< the take-off point, local [m]
  std::vector<std::string> warnings;      ///< a --crs or --vertical overriding the scene's
};

/// Places the mission: --origin (flights within kMaxDistanceFromOriginM of it), else the
/// CRS of --crs (with the scene's source_offset_m) or the one scene.json records (with
/// its offset), in the vertical datum of --vertical, else scene.json's record, else the
/// compound CRS's vertical part, else EGM96 (io::defaultVerticalDatum). Home: missionHome.
/// Throws InputError for --origin with --crs, neither and no CRS in the scene, a bad
/// origin, CRS or datum, or a missing geoid grid.
MissionPlacement placeMission(const io::MissionRecord& mission,
                              const std::vector<io::Flight>& flights,
                              const PlacementRequest& request);

/// The frame of the formats whose heights are relative to home (qgc-plan, wpl, csv):
/// `origin` from --origin, else `crs` from --crs or the scene's record (the other fields
/// of io::ExportOptions keep their defaults). Read before the mission, so that a
/// missing origin is named first. Throws InputError like placeMission.
io::ExportOptions relativeFrame(const PlacementRequest& request);

/// For a CRS frame: `options.source_offset_m` from scene.json (InputError when it has
/// none: a cloud near its own origin is not in a projected CRS) and `options.home_m`
/// (missionHome). Nothing for an --origin frame.
void placeRelativeHome(io::ExportOptions& options, const io::MissionRecord& mission,
                       const std::vector<io::Flight>& flights, const PlacementRequest& request);

}  // namespace uavip::app
