#pragma once
/// \file
/// OUT/mission.json (docs/ARCHITECTURE.md): surfaces[] {surface_id, status, reason,
/// stops[] {position, target, yaw_deg, gimbal_pitch_deg, problem}, waypoints,
/// raw_waypoint_count, path_length_m, validation, timings}, flight {…}.
/// This file owns the format: the planner's results are written here, and
/// `export` and `validate` read it back through missionFromJson / loadMission.

#include <cstddef>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "uavip/planning/fleet_types.h"
#include "uavip/planning/types.h"

namespace uavip::io {

/// One surface's mission as JSON.
nlohmann::json surfaceMissionToJson(const planning::SurfaceMission& mission);

/// The ordered flight (`flight` of mission.json): status, reason, home,
/// home_source, order[] {surface_id, reversed}, excluded[] {surface_id, reason},
/// tour_length_m, naive_length_m, lower_bound_m, exact_order, length_m, duration_s,
/// model {…}, sorties[] {sortie (from 1), length_m, duration_s, stops[] {surface_id,
/// stop, waypoint (index in this sortie's waypoints)}, waypoints (home … home),
/// validation}.
nlohmann::json flightToJson(const planning::FlightPlan& flight, const planning::FlightModel& model);

/// The fleet (`fleet` of mission.json, planning/fleet_types.h): status, reason,
/// uav_count, the fleet keys (separation_m, launch_interval_s, slack_s,
/// takeoff_landing_s, battery_swap_s), makespan_s, single_uav_s, speedup,
/// lower_bound_s, work_s, jobs, split_surfaces, waits, fallback_single,
/// closest_approach {nominal_m, at_s, swept_m}, model {…}, uavs[] {uav (from 1), home,
/// home_source, stop_count, wait_s, end_s, sorties[] {sortie (from 1), start_s,
/// duration_s, length_m, stops[], waypoints, times_s (arrival at each waypoint),
/// validation}}.
nlohmann::json fleetToJson(const planning::FleetPlan& fleet);

/// fleetToJson without `uavs` (a site's fleet lists its UAVs' sorties by section).
nlohmann::json fleetSummaryToJson(const planning::FleetPlan& fleet);

/// The whole mission file; `meta` is merged at the top level (version, source,
/// planner, camera…).
nlohmann::json missionToJson(const std::vector<planning::SurfaceMission>& missions,
                             const nlohmann::json& meta);

/// What mission.json holds beside the missions and the flight: how it was planned
/// and how long each stage took.
/// The edits file a plan applied (app/edits.h): mission.json `edits`.
struct EditsSummary {
  std::string file;                  ///< as given
  std::string sha256;                ///< of its bytes
  std::vector<std::string> applied;  ///< one line per applied edit
  std::vector<KeepOut> keep_out;     ///< the volumes planning kept out of (validate does too)
};

struct MissionExtras {
  std::string uavip_version;
  std::string source;               ///< the scenario or scene.json planned
  std::string planner;              ///< planners/registry.h name
  Vec3 cost_weights{Vec3::Ones()};  ///< a1, a2, a3 of the A* step cost (§II-G)
  double inflation_radius_m{0.0};   ///< the UAV's radius [m]
  double overlap_w{0.0};            ///< photo overlap asked, along the rows [0, 1)
  double overlap_h{0.0};            ///< and across them [0, 1)
  /// coverage.purpose; written (meta.purpose) unless it is inspection.
  std::string purpose{"inspection"};
  coverage::Camera camera;     ///< written as `camera_model`
  std::size_t grid_voxels{0};  ///< planning grid (`grid`)
  std::size_t grid_blocked{0};
  double grid_resolution_m{0.0};  ///< [m]
  /// Distance kept from every measured point: the UAV's radius + the safety margin [m].
  double safety_clearance_m{0.0};
  double coverage_s{0.0};                               ///< stage 6 wall time [s]
  double grid_s{0.0};                                   ///< planning grid [s]
  double planning_s{0.0};                               ///< stage 7 [s]
  double flight_s{0.0};                                 ///< order, legs, sorties [s]
  std::optional<planning::StructureSummary> structure;  ///< plan --cover structure
  std::optional<EditsSummary> edits;                    ///< plan --edits, scenario edits:
  /// The aircraft profile planned for (core/aircraft.h; `aircraft` {drone, payload});
  /// empty for `generic`, then not written.
  std::string drone;
  std::string payload;  ///< its camera (`--payload`); empty: the drone's default
  std::optional<planning::FleetPlan> fleet;  ///< several UAVs (planning/fleet.h)
};

/// The text of mission.json: missionToJson with the extras, `flight` and (structure
/// coverage) `structure`. The file's one writer.
std::string missionJsonText(const std::vector<planning::SurfaceMission>& missions,
                            const planning::FlightPlan& flight, const planning::FlightModel& model,
                            const MissionExtras& extras);

// ---- reading back

/// A photo stop as mission.json records it.
struct StopRecord {
  Vec3 position{Vec3::Zero()};   ///< [m], local ENU
  std::optional<Vec3> target;    ///< the surface point it aims at [m]; absent in older files
  double yaw_deg{0.0};           ///< CCW from +x (east) [deg]
  double gimbal_pitch_deg{0.0};  ///< up positive [deg]
  std::string problem{"none"};   ///< "none" when flown; a partial mission skips the others
  bool flown() const { return problem == "none"; }
};

/// One surface's mission as recorded.
struct SurfaceRecord {
  int surface_id{0};
  std::string kind;    ///< "structure" (plan --cover structure), "edge" (a reconstruction's edge
                       ///< link), else "plane"
  std::string status;  ///< ok, partial, blocked, failed, …
  /// The camera's standoff (`camera.standoff_m`) [m]; NaN when absent.
  double standoff_m{std::numeric_limits<double>::quiet_NaN()};
  std::string reason;
  std::vector<StopRecord> stops;
  PointList waypoints;  ///< [m]
  bool flyable() const { return status == "ok" || status == "partial"; }
};

/// A photo stop of a sortie: stop `stop` of surface `surface_id` at waypoint `waypoint`.
struct SortieStopRecord {
  int surface_id{0};
  std::size_t stop{0};
  std::size_t waypoint{0};
};

/// One battery sortie of the ordered flight: home … home.
struct SortieRecord {
  PointList waypoints;  ///< [m]
  std::vector<SortieStopRecord> stops;
};

/// The ordered flight as recorded.
struct FlightRecord {
  std::string status;
  std::string reason;
  std::vector<SortieRecord> sorties;
};

/// One UAV of the fleet as recorded: its home and sorties with their take-off times.
struct FleetUavRecord {
  Vec3 home{Vec3::Zero()};
  std::vector<double> start_s;        ///< take-off of each sortie [s]
  std::vector<SortieRecord> sorties;  ///< home … home
};

/// The fleet as recorded (`fleet`): what `validate` needs to recompute the motion.
struct FleetRecord {
  std::string status;
  planning::FleetOptions options;  ///< uavs and the fleet keys
  planning::FlightModel model;
  double makespan_s{0.0};
  std::vector<FleetUavRecord> uavs;
};

/// Every UAV's motion recomputed from the recorded waypoints, photo stops, take-off
/// times and flight model (planning::sortieMotion over its sorties): what `validate`
/// checks and what the mission page replays.
std::vector<std::vector<planning::MotionPiece>> recordedFleetMotion(const FleetRecord& fleet);

/// A `fleet` block's status, options (through their table), flight model and
/// makespan_s (what fleetSummaryToJson wrote), `where` naming it in errors; uavs left
/// empty. Throws InputError naming `path` and the field.
FleetRecord fleetSettingsFromJson(const nlohmann::json& fleet, const std::string& path,
                                  const std::string& where = "fleet");

/// A mission.json read back.
struct MissionRecord {
  double inflation_radius_m{std::numeric_limits<double>::quiet_NaN()};  ///< NaN when absent [m]
  std::string source;  ///< the scenario or scene.json planned (`source`; "" when absent)
  /// The camera planned with (`camera_model`: footprint, sensor or pinhole); absent in older files.
  std::optional<coverage::Camera> camera;
  std::vector<SurfaceRecord> surfaces;
  std::optional<FlightRecord> flight;  ///< absent in files of older versions
  std::optional<FleetRecord> fleet;    ///< only when planned for several UAVs
  /// The keep-out volumes of the edits the plan applied (`edits.keep_out`; none without).
  std::vector<KeepOut> keep_out;
  /// The aircraft profile planned for (`aircraft.drone`, `aircraft.payload`); empty when
  /// the file names none (planned for a generic UAV, or by an older version).
  std::string drone;
  std::string payload;
  /// The surface with `id`, or nullptr.
  const SurfaceRecord* surface(int id) const;
};

/// Reads a mission.json document strictly (io/json_reader.h): every coordinate
/// finite and local, ids whole numbers in [0, 10⁶] and unique, each sortie stop
/// naming a stop of its surface at a later waypoint of its sortie, within 2 mm of
/// the stop's position. Throws InputError naming `path` and the field.
MissionRecord missionFromJson(const nlohmann::json& mission, const std::string& path);

/// Loads and reads `path` (missionFromJson).
MissionRecord loadMission(const std::string& path);

/// site.json's `format` (app::siteJsonText writes it).
inline constexpr const char* kSiteFormat = "uavip site 1";

/// True when `j` is a site.json (an object whose `format` is kSiteFormat).
bool isSiteJson(const nlohmann::json& j);

/// The flown sections of a site.json (`merge` of several sections, at `path`): each
/// section whose flight_status is ok, its mission.json beside site.json (loadMission),
/// by folder. Throws InputError naming the file and field.
std::map<std::string, MissionRecord> siteMissions(const nlohmann::json& site,
                                                  const std::string& path);

/// A site's fleet as recorded (site.json `fleet`, app/site_fleet.h).
struct SiteFleetRecord {
  /// The settings and each UAV's sorties (copied from `missions`) with their take-off times.
  FleetRecord fleet;
  /// Per UAV, per sortie: the section's folder and the sortie's index in its flight (0-based).
  std::vector<std::vector<std::pair<std::string, std::size_t>>> sorties;
};

/// Reads site.json `fleet` against the sections' flights; throws InputError (naming
/// `path` and the field) for a folder that is no flown section or a sortie beyond its
/// flight.
SiteFleetRecord siteFleetFromJson(const nlohmann::json& site, const std::string& path,
                                  const std::map<std::string, MissionRecord>& missions);

/// A stop is the waypoint within this distance of its position (mission.json rounds
/// coordinates to 0.1 mm) [m].
constexpr double kStopMatchM = 2e-3;

}  // namespace uavip::io
