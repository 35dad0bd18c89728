#pragma once
/// \file
/// Stage 7 for one surface (paper §II-G): check every photo stop against the
/// inflated grid, then join consecutive stops by legs planned with a Planner, then
/// simplify and validate the whole path. Its types (SurfaceMission, MissionOptions, the
/// statuses) are plain data in planning/types.h.

#include <optional>
#include <string>
#include <vector>

#include "uavip/core/types.h"
#include "uavip/coverage/flight_strategy.h"
#include "uavip/planning/path_validator.h"
#include "uavip/planning/planner.h"
#include "uavip/planning/types.h"
#include "uavip/world/voxel_grid.h"

namespace uavip::planning {

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
