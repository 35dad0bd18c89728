#pragma once
/// \file
/// Planners by name (ARCHITECTURE.md, planners/).

#include "planners/astar.h"
#include "uavip/planning/planner.h"

#include <memory>
#include <string>
#include <vector>

namespace uavip::planners {

/// Settings shared by the registered planners.
struct PlannerSettings {
  AStarOptions astar;  ///< weights and budget of the grid A*
};

/// Names accepted by makePlanner, in a stable order.
std::vector<std::string> plannerNames();

/// Creates the planner `name`; throws InputError listing the valid names otherwise.
std::unique_ptr<planning::Planner> makePlanner(const std::string& name, const PlannerSettings& settings);

}  // namespace uavip::planners
