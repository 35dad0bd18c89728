#pragma once
/// \file
/// Stage 7 for one surface (paper §II-G): check every photo stop against the
/// inflated grid, then join consecutive stops by legs planned with a Planner, then
/// simplify and validate the whole path.

#include <optional>
#include <string>
#include <vector>

#include "uavip/core/types.h"
#include "uavip/coverage/flight_strategy.h"
#include "uavip/planning/path_validator.h"
#include "uavip/planning/planner.h"
#include "uavip/world/voxel_grid.h"

namespace uavip::planning {

/// Outcome for a surface. `Blocked` is a result (exit 0), not an error.
enum class SurfaceStatus {
  Ok,       ///< every stop visited by a validated path
  Partial,  ///< the usable stops visited by a validated path; the skipped ones are reported
  Blocked,  ///< too many stops cannot be reached safely: no waypoints (paper: crossed planes)
  NoStops,  ///< the flight strategy produced no stop
  Failed,   ///< a leg failed or the validator rejected the path
};

/// True when the surface has a validated path to fly (Ok or Partial).
inline bool flyable(SurfaceStatus status) {
  return status == SurfaceStatus::Ok || status == SurfaceStatus::Partial;
}

/// Text of a status ("ok", "partial", "blocked", "no_stops", "failed").
const char* toString(SurfaceStatus status);

/// Why a stop cannot be used.
enum class StopProblem { None, GimbalLimit, InObstacleSpace, Unreachable };
const char* toString(StopProblem problem);

/// Options of mission planning.
struct MissionOptions {
  bool simplify{true};  ///< shortcut the raw voxel path (line of sight on the grid)
  /// Unusable stops (gimbal limit, obstacle space, unreachable) are skipped and
  /// reported while they are at most this fraction of the surface's stops (status
  /// Partial); above it the surface is Blocked. 0 = any unusable stop blocks.
  double max_skipped_fraction{0.25};
  std::optional<Vec3> start;  ///< take-off / entry point; must be free. Default: the first stop
  /// Stop repair: a stop inside the inflated obstacle space is moved to a nearby
  /// free pose that still looks at its photo centre with a clear line of sight:
  /// tilted from above, below or the sides by 15–60° at the same distance, or
  /// farther out up to max_standoff_factor × the standoff (footprint and GSD grow
  /// by that factor). Moved stops are counted and listed.
  bool repair_stops{true};
  double max_standoff_factor{1.25};  ///< farthest repaired stop, × standoff (GSD allowance)
  /// A flyable surface whose measured coverage is below this is `partial` [0, 1].
  double min_coverage{0.95};
  coverage::GimbalLimits gimbal;  ///< pitch limits a repaired stop must respect (the camera's)
  /// Fly a leg straight when its segment crosses free voxels only, or through one
  /// point beside its midpoint when both halves do, and ask the planner only for the
  /// others (structure coverage: most legs are short hops).
  bool direct_legs{false};

  /// Throws InputError "<where>: <key> must be …, got …" for a value out of range
  /// (max_skipped_fraction and min_coverage in [0, 1], max_standoff_factor in [1, 3],
  /// a finite start, valid gimbal limits). planSurfaceMission calls it.
  void validate(const std::string& where) const;
};

/// What structure coverage (app::planStructure; coverage/structure_views.h) found and reached.
struct StructureSummary {
  int surface_id{0};               ///< id of its entry in missions (above the scene's ids)
  std::size_t points{0};           ///< structure points (the clean cloud without the ground)
  std::size_t ground_points{0};    ///< points of the clean cloud taken as ground
  std::size_t seeds{0};            ///< seed points of the candidates
  std::size_t candidates{0};       ///< candidate poses
  std::size_t free_candidates{0};  ///< kept: free, reachable, within the gimbal limits, and per
                                   ///< seed and direction the nearest such
  std::size_t imageable{0};        ///< structure points some free candidate images
  std::size_t photos{0};           ///< photos chosen
  double standoff_m{0.0};          ///< viewing distance [m]
  double visible_range_m{0.0};     ///< rule (a)'s range [m]
  double rule_a{0.0};              ///< FC-Planner's pixel rule at the flown stops [0, 1]
  double rule_b{0.0};              ///< our rule (GSD, incidence ≤ 75°, line of sight) [0, 1]
  double prepare_s{0.0};  ///< grid components, line-of-sight index, normals' orientation [s]
  double select_s{0.0};   ///< wall time of the view selection [s]
  double order_s{0.0};    ///< ordering the photos into one open path [s]
  double legs_s{0.0};     ///< the legs between consecutive photos [s]
  double score_s{0.0};    ///< rules (a) and (b) at the flown stops [s]
};

/// A planned leg between two consecutive path points.
struct Leg {
  int from_stop{-1};  ///< −1 for the start point
  int to_stop{0};
  PathStatus status{PathStatus::NoPath};
  std::size_t raw_steps{0};
  double length_m{0.0};  ///< raw voxel path length [m]
  double seconds{0.0};
};

/// The mission of one surface.
struct SurfaceMission {
  int surface_id{0};
  /// "plane": a detected surface's rows (§II-F); "structure": the photos of the
  /// whole structure (coverage/structure_views.h).
  std::string kind{"plane"};
  SurfaceStatus status{SurfaceStatus::NoStops};
  std::string reason;  ///< one sentence; empty when ok
  coverage::FlightStrategy strategy;
  std::vector<StopProblem> stop_problems;  ///< one per stop of the strategy
  std::vector<int> moved_stops;  ///< stops moved by repair (strategy.stops holds the new pose)
  /// Share of the surface's points some flown photo images (coverage_evaluator.h),
  /// filled by the caller that knows the surface's points (app::plan).
  struct Coverage {
    bool evaluated{false};
    double fraction{0.0};
    std::size_t points{0};
    std::size_t uncovered{0};
    PointList uncovered_points;  ///< [m], for the overview
  } coverage;
  std::vector<Leg> legs;
  PointList raw_path;   ///< every voxel step (the paper's waypoint count) [m]
  PointList waypoints;  ///< simplified (or raw) path through every stop [m]
  std::size_t raw_waypoint_count{0};
  double raw_length_m{0.0};
  double path_length_m{0.0};
  ValidationResult validation;
  double seconds{0.0};  ///< wall time of stage 7 for this surface
};

/// A leg of one or two straight segments on free voxels: the direct segment, else a
/// detour through one point beside the midpoint (up, down or to either side, offset
/// by ¼, ½ or 1 × the leg's length; the nearest offset that works, the shorter
/// direction). Empty when none is free: then a planner must search.
PointList straightOrDetour(const world::VoxelGrid& grid, const Vec3& a, const Vec3& b);

/// Plans the mission of one surface with the given strategy. Stops in the inflated
/// obstacle space, outside the gimbal limits, or not 26-connected to the first
/// usable stop are counted by cause in the reason; above max_skipped_fraction the
/// surface is Blocked (no waypoints), otherwise they are skipped (Partial).
/// Throws InputError if options.start is given and not free ("start … inside
/// obstacle space").
SurfaceMission planSurfaceMission(const coverage::FlightStrategy& strategy,
                                  const world::VoxelGrid& grid, const PathValidator& validator,
                                  Planner& planner, const MissionOptions& options);

}  // namespace uavip::planning
