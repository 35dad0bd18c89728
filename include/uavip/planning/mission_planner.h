#pragma once
/// \file
/// Stage 7 for one surface (paper §II-G): check every photo stop against the
/// inflated grid, then join consecutive stops by legs planned with a Planner, then
/// simplify and validate the whole path.

#include "uavip/core/types.h"
#include "uavip/coverage/flight_strategy.h"
#include "uavip/planning/path_validator.h"
#include "uavip/planning/planner.h"
#include "uavip/world/voxel_grid.h"

#include <optional>
#include <string>
#include <vector>

namespace uavip::planning {

/// Outcome for a surface. `Blocked` is a result (exit 0), not an error.
enum class SurfaceStatus {
  Ok,       ///< every stop visited by a validated path
  Blocked,  ///< some stops cannot be reached safely: no waypoints (paper: crossed planes)
  NoStops,  ///< the flight strategy produced no stop
  Failed,   ///< a leg failed or the validator rejected the path
};

/// Text of a status ("ok", "blocked", "no_stops", "failed").
const char* toString(SurfaceStatus status);

/// Why a stop cannot be used.
enum class StopProblem { None, GimbalLimit, InObstacleSpace, Unreachable };
const char* toString(StopProblem problem);

/// Options of mission planning.
struct MissionOptions {
  bool simplify{true};          ///< shortcut the raw voxel path (line of sight on the grid)
  std::optional<Vec3> start;    ///< take-off / entry point; must be free. Default: the first stop
};

/// A planned leg between two consecutive path points.
struct Leg {
  int from_stop{-1};  ///< −1 for the start point
  int to_stop{0};
  PathStatus status{PathStatus::NoPath};
  std::size_t raw_steps{0};
  double length_m{0.0};   ///< raw voxel path length [m]
  double seconds{0.0};
};

/// The mission of one surface.
struct SurfaceMission {
  int surface_id{0};
  SurfaceStatus status{SurfaceStatus::NoStops};
  std::string reason;                     ///< one sentence; empty when ok
  coverage::FlightStrategy strategy;
  std::vector<StopProblem> stop_problems; ///< one per stop of the strategy
  std::vector<Leg> legs;
  PointList raw_path;                     ///< every voxel step (the paper's waypoint count) [m]
  PointList waypoints;                    ///< simplified (or raw) path through every stop [m]
  std::size_t raw_waypoint_count{0};
  double raw_length_m{0.0};
  double path_length_m{0.0};
  ValidationResult validation;
  double seconds{0.0};                    ///< wall time of stage 7 for this surface
};

/// Plans the mission of one surface with the given strategy. Stops in the inflated
/// obstacle space, outside the gimbal limits, or not 26-connected to the first
/// usable stop make the surface Blocked with a reason that counts them by cause.
/// Throws InputError if options.start is given and not free ("start … inside
/// obstacle space").
SurfaceMission planSurfaceMission(const coverage::FlightStrategy& strategy,
                                  const world::VoxelGrid& grid, const PathValidator& validator,
                                  Planner& planner, const MissionOptions& options);

}  // namespace uavip::planning
