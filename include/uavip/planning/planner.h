#pragma once
/// \file
/// The point-to-point planner interface of stage 7. Implementations live in
/// planners/ (the paper's A* first; OMPL planners behind the same interface).

#include <cstddef>
#include <string>

#include "uavip/core/stopwatch.h"
#include "uavip/core/types.h"
#include "uavip/planning/types.h"
#include "uavip/world/free_space.h"
#include "uavip/world/voxel_grid.h"

namespace uavip::planning {

/// Result of planning one leg.
struct PathResult {
  PathStatus status{PathStatus::NoPath};
  PointList path;  ///< start … goal; for grid planners the voxel centres of every step, with the
                   ///< exact start and goal at the ends [m]
  double cost{0.0};             ///< in the planner's own cost units
  std::size_t expansions{0};    ///< nodes expanded (grid searches; 0 for sampling planners)
  std::size_t graph_states{0};  ///< states in the planner's graph after the leg (a PRM roadmap's
                                ///< milestones; 0 for grid searches)
  double seconds{0.0};          ///< wall time
  bool solved() const { return status == PathStatus::Solved; }
};

/// The check every planner makes before searching: InvalidStart / InvalidGoal when
/// that end is not finite or not free, else Solved (the ends are usable).
inline PathStatus checkEndpoints(const world::FreeSpace& space, const Vec3& start,
                                 const Vec3& goal) {
  if (!start.allFinite() || !space.isFree(start)) return PathStatus::InvalidStart;
  if (!goal.allFinite() || !space.isFree(goal)) return PathStatus::InvalidGoal;
  return PathStatus::Solved;
}

/// The frame of every planner's plan(): checks the ends (checkEndpoints), lets
/// `search(result)` fill the result when they are usable (its status is Solved on
/// entry), and times the whole call into result.seconds.
template <typename Search>
PathResult timedPlan(const world::FreeSpace& space, const Vec3& start, const Vec3& goal,
                     Search&& search) {
  const auto t0 = SteadyClock::now();
  PathResult out;
  out.status = checkEndpoints(space, start, goal);
  if (out.status == PathStatus::Solved) search(out);
  out.seconds = secondsSince(t0);
  return out;
}

/// Plans collision-free paths on a VoxelGrid. The grid A* searches the grid's
/// lattice; the OMPL planners see it only as a world::FreeSpace (isFree,
/// segmentFree, bounds), and keep one OMPL SpaceInformation and planner per grid
/// (world::FreeSpace::contentId), cleared between legs. plan() is not thread-safe (a
/// planner keeps scratch memory); use one instance per thread.
class Planner {
 public:
  virtual ~Planner() = default;
  /// Registry name, e.g. "astar".
  virtual std::string name() const = 0;
  /// Plans from start to goal; both must lie in free voxels, otherwise the status
  /// says which end is invalid. Never throws for in-range inputs.
  virtual PathResult plan(const world::VoxelGrid& grid, const Vec3& start, const Vec3& goal) = 0;
};

}  // namespace uavip::planning
