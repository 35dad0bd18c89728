#pragma once
/// \file
/// One flight for the whole structure: the surfaces' missions (mission_planner.h)
/// ordered into a tour from home and back, every connecting leg planned on the
/// shared grid, the tour split into battery sorties, each validated as one path.
///
/// Order (the paper's follow-up: a travelling-salesman order on A* distances):
/// each flyable surface keeps its boustrophedon rows and is flown forward or
/// reversed (entry at its first or its last stop); the order and directions solve a
/// generalised TSP (planning/tour.h). Leg costs are lengths [m]: the straight line
/// when it is free on the grid, else the planner's simplified path, planned lazily —
/// the solver first sees the straight-line length as a lower bound, the legs its
/// tour uses are planned, and it solves again until every leg of its tour is exact.
///
/// Sorties: the ordered stops are cut greedily so that each sortie, home → first
/// stop → … → last stop → home, lasts at most the usable endurance of the flight
/// model (FlightModel), counting flight time, hover and settle time per photo.
///
/// Validation: every segment of every sortie has the validator's clearance. A
/// segment of a surface's own path keeps the clearance its surface's validation
/// measured (same validator, same segment); connecting, outbound and return legs are
/// validated here. Its types (FlightPlan, FlightOptions, FlightModel) are plain data in
/// planning/types.h.

#include <optional>
#include <string>
#include <vector>

#include "uavip/core/types.h"
#include "uavip/planning/mission_planner.h"
#include "uavip/planning/path_validator.h"
#include "uavip/planning/planner.h"
#include "uavip/planning/types.h"
#include "uavip/world/voxel_grid.h"

namespace uavip::planning {

/// Orders, connects, splits and validates. Throws InputError when options.home is
/// given and not free. Surfaces whose mission is not flyable, or that home cannot
/// reach, are listed in `excluded`. Status Failed when a leg cannot be planned, a
/// stop cannot be flown within one battery, or a sortie fails validation (reason
/// names the sortie and segment).
FlightPlan planFlight(const std::vector<SurfaceMission>& missions, const world::VoxelGrid& grid,
                      const PathValidator& validator, Planner& planner,
                      const FlightOptions& options);

}  // namespace uavip::planning
