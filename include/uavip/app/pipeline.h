#pragma once
/// \file
/// The whole flow of docs/ARCHITECTURE.md as callable steps: sense (sim) → stage 3
/// (preprocess) → stages 4–5 (perception) → grid (world) → stage 6 (coverage) →
/// stage 7 (planning), with per-stage wall times. The CLI and the benchmark call
/// these; nothing here prints.

#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "uavip/app/config.h"
#include "uavip/app/scenario.h"
#include "uavip/io/cloud_io.h"
#include "uavip/io/mission_json.h"
#include "uavip/io/scene_json.h"
#include "uavip/planning/fleet_types.h"
#include "uavip/planning/flight_planner.h"
#include "uavip/planning/mission_planner.h"
#include "uavip/planning/path_validator.h"
#include "uavip/preprocess/cloud_stats.h"
#include "uavip/preprocess/filters.h"
#include "uavip/world/collision_world.h"
#include "uavip/world/voxel_grid.h"

namespace uavip::app {

/// Progress messages for long work (the CLI shows them on a terminal).
using Progress = std::function<void(const std::string&)>;

/// Hands `message` to `progress` when one is set.
inline void reportProgress(const Progress& progress, const std::string& message) {
  if (progress) progress(message);
}

/// Wall time per stage [s].
struct StageTimes {
  double sense_s{0.0};
  double preprocess_s{0.0};
  double perception_s{0.0};
  double grid_s{0.0};
  double coverage_s{0.0};
  double planning_s{0.0};
  double flight_s{0.0};  ///< ordering, connecting legs, sorties, their validation
  double total_s{0.0};
};

/// Stages 3–5 on a raw cloud.
struct DetectResult {
  ResolvedConfig resolved;  ///< the config the stages ran with (app/config.h)
  preprocess::PreprocessStats preprocess;
  Scene scene;
  StageTimes times;
};

/// Stages 6–7 for the chosen surfaces.
struct PlanResult {
  std::vector<planning::SurfaceMission> missions;
  std::size_t grid_voxels{0};
  double grid_resolution_m{0.0};  ///< voxel edge of the planning grid used [m]
  std::size_t grid_blocked{0};
  /// Distance kept from every measured point and solid [m]: the UAV's inflation
  /// radius plus the safety cloud's margin (safetyClearance).
  double clearance_m{0.0};
  /// One ordered flight over every flyable surface (planning/flight_planner.h).
  planning::FlightPlan flight;
  StageTimes times;
  std::optional<planning::StructureSummary> structure;  ///< set by planStructure
  /// Several UAVs at once (planning/fleet.h): with fleet.uavs > 1 or fleet.homes.
  std::optional<planning::FleetPlan> fleet;
};

/// The raw cloud's kd-tree: built by measure(), searched again by detect()'s
/// outlier removal (core/neighbour_index.h). Refers to the raw cloud.
using CloudIndex = std::shared_ptr<const NeighbourIndex>;

/// Measures the raw cloud (preprocess/cloud_stats.h). With a scenario, its known
/// sampling is used: mode sample gives the lattice spacing, mode scan a lattice
/// after the voxel grid. `index`, if given, receives the kd-tree built on the way
/// (null for fewer than 2 points). Throws InputError for a non-finite point.
preprocess::CloudStats measure(const PointList& raw, const app::Scenario* scenario = nullptr,
                               CloudIndex* index = nullptr);
/// Runs stages 3–5 with the config resolved for `cloud` (app/config.h); `index`
/// (from measure() on this very `raw`) spares stage 3 building its own. Throws
/// InputError for an empty cloud or non-finite points.
DetectResult detect(const PointList& raw, const app::Config& config,
                    const preprocess::CloudStats& cloud, const Progress& progress = {},
                    const CloudIndex& index = nullptr);

/// The config resolved for a scene read back from scene.json: with the cloud
/// numbers it was detected with (scene.measured), else measured on its points.
ResolvedConfig resolveForScene(const Scene& scene, const app::Config& config);
/// The distance planning and its validator keep from the scene's points, surfaces and
/// obstacles [m]: the UAV's inflation radius, plus (when the scene has a safety cloud)
/// its thinning margin and safety.sparse_factor × the measured spacing
/// (preprocess/safety_cloud.h). A flight that keeps it from the safety cloud keeps the
/// inflation radius from every input point. For a mesh input (SafetyCloud::mesh) the
/// inflation radius alone: the world measures to the triangles themselves.
double safetyClearance(const Scene& scene, const app::Config& config);
/// Where stage 7 plans and checks (paper §II-G): the planning grid and the validator.
struct PlanningSpace {
  double clearance_m{0.0};  ///< safetyClearance(scene, config): the grid's inflation [m]
  /// Over the neighbourhood of the positions (6 m around them), not the whole site: on
  /// a large site the grid stays small and fine. Measured points (safetyPoints), the
  /// solids (surface slabs, obstacle solids) and the operator's keep-out volumes are
  /// occupied, so the planner never flies through space the validator calls solid;
  /// inflated by clearance_m (Config::gridOptions). Resolution: grid.resolution_m when
  /// the file gives it, else the auto rule on the region (app/config.h).
  world::VoxelGrid grid;
  /// Sweeps the UAV against every surface slab, obstacle solid and measured point of
  /// the collision world (world/collision_world.h) at clearance_m.
  planning::PathValidator validator;
};

/// The planning space of a scene around `positions` (photo stops, mission.start and
/// mission.home, or a benchmark's leg ends), on `world` (the scene's collision world).
/// app::plan, app::planStructure and `uavip bench` (bench/runner.h) all plan in it.
/// Throws InputError when the grid would exceed grid.max_voxels.
PlanningSpace planningSpace(const Scene& scene,
                            const std::shared_ptr<const world::CollisionWorld>& world,
                            const app::Config& config, const PointList& positions);
/// Parses a surface selection: "all", an id, or a list of ids "0,3,5"; throws
/// InputError naming the valid ids when an id does not exist or is listed twice.
std::vector<int> selectSurfaces(const Scene& scene, const std::string& selection);

/// Runs stages 6–7 for the given surface ids (each must exist).
PlanResult plan(const Scene& scene, const app::Config& config, const std::vector<int>& surface_ids,
                const Progress& progress = {});

/// Structure coverage (coverage/structure_views.h): photos of every part of the
/// structure in one flight, as one mission of kind "structure" whose id is above the
/// scene's surface ids. The structure is the clean cloud without the ground: the
/// horizontal surfaces at the site's lowest level that span at least a quarter of
/// its footprint, and every point below coverage.ground_z_m when set. Viewing
/// distance: coverage.standoff_m when set, else the one the camera's GSD implies.
/// Throws InputError for a bad camera or a viewing distance inside the clearance.
/// A structure with no free viewpoint gives a mission with status blocked.
PlanResult planStructure(const Scene& scene, const app::Config& config,
                         const Progress& progress = {});

/// Senses the scenario's world: mode `sample` samples its surfaces; mode `scan`
/// simulates the raw scans and runs stages 1–2 on them (app/assemble.h, senseScans),
/// returning the merged cloud in scenario coordinates.
PointList sense(const app::Scenario& scenario);

/// Moves a scenario whose world reaches farther than io::kRecentreBeyondM from the
/// origin (io::farFromOrigin on the world's primitives) by −origin, where origin is
/// io::recentringOrigin of their box, the readers' rule for a far cloud: the world,
/// the scan stations, the viewpoints, mission.start and the flight's home and start.
/// Returns origin (zero for a world near the origin; scene.json's source_offset_m).
Vec3 recentreScenario(app::Scenario& scenario);

/// What scene.json records beside the scene (io::sceneJsonText): the resolved
/// parameters, the stage times and, for a cloud file (`read` not null), how it was read.
io::SceneExtras sceneExtras(const DetectResult& detected, const io::CloudReadInfo* read);

/// What mission.json records beside the missions and the flight
/// (io::missionJsonText): how it was planned (`source`: the file planned), the grid,
/// the clearance kept, the stage times and the structure summary.
io::MissionExtras missionExtras(const PlanResult& planned, const app::Config& config,
                                const std::string& source);

}  // namespace uavip::app
