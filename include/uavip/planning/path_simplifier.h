#pragma once
/// \file
/// Line-of-sight shortcuts of a raw voxel path that keep the grid's clearance.

#include "uavip/core/types.h"
#include "uavip/world/voxel_grid.h"

namespace uavip::planning {

/// Greedy shortcutting: from each kept waypoint jump to the farthest later waypoint
/// reachable by a free segment (VoxelGrid::segmentFree). Keeps the first and last
/// points; never longer than the input; deterministic.
PointList simplifyPath(const PointList& raw, const world::VoxelGrid& grid);

}  // namespace uavip::planning
