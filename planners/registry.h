#pragma once
/// \file
/// Planners by name (docs/ARCHITECTURE.md, planners/): makePlanner builds the planner of
/// a row of the planner table (planning/planner_table.h), whose names, settings and
/// lookups are re-exported here under planners::.

#include <memory>
#include <string>

#include "planners/astar.h"
#include "uavip/planning/planner.h"
#include "uavip/planning/planner_table.h"

namespace uavip::planners {

using planning::isDeterministic;
using planning::plannerNames;
using planning::PlannerSettings;
using planning::requireKnownPlanner;

/// Creates the planner of row `name` (planning::plannerSpec): the grid A* with the row's
/// options (PlannerSpec::astarOptions), or an OmplPlanner (ompl_planners.h); throws
/// InputError listing the valid names for an unknown name, or naming a bad setting.
std::unique_ptr<planning::Planner> makePlanner(const std::string& name,
                                               const PlannerSettings& settings);

}  // namespace uavip::planners
