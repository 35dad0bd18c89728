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
#include "uavip/planning/flight_planner.h"
#include "uavip/planning/mission_planner.h"
#include "uavip/preprocess/cloud_stats.h"
#include "uavip/preprocess/filters.h"

namespace uavip::app {

/// Progress messages for long work (the CLI shows them on a terminal).
using Progress = std::function<void(const std::string&)>;

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

/// What structure coverage (planStructure) found and reached.
struct StructureSummary {
  int surface_id{0};               ///< id of its entry in missions (above the scene's ids)
  std::size_t points{0};           ///< structure points (the clean cloud without the ground)
  std::size_t ground_points{0};    ///< points of the clean cloud taken as ground
  std::size_t seeds{0};            ///< seed points of the candidates
  std::size_t candidates{0};       ///< candidate poses
  std::size_t free_candidates{0};  ///< free, reachable and within the gimbal limits
  std::size_t imageable{0};        ///< structure points some free candidate images
  std::size_t photos{0};           ///< photos chosen
  double standoff_m{0.0};          ///< viewing distance [m]
  double visible_range_m{0.0};     ///< rule (a)'s range [m]
  double rule_a{0.0};              ///< FC-Planner's pixel rule at the flown stops [0, 1]
  double rule_b{0.0};              ///< our rule (GSD, incidence ≤ 75°, line of sight) [0, 1]
  double select_s{0.0};            ///< wall time of the view selection [s]
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
  std::optional<StructureSummary> structure;  ///< set by planStructure
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
/// inflation radius from every input point.
double safetyClearance(const Scene& scene, const app::Config& config);
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

}  // namespace uavip::app
