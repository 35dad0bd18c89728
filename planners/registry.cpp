#include "planners/registry.h"

#include "planners/ompl_planners.h"

namespace uavip::planners {

// PlannerSettings::validate, plannerNames, requireKnownPlanner and isDeterministic
// read only the table: planner_table.cpp.

std::unique_ptr<planning::Planner> makePlanner(const std::string& name,
                                               const PlannerSettings& settings) {
  settings.validate("planner");
  requireKnownPlanner(name);
  if (isOmplPlanner(name)) return std::make_unique<OmplPlanner>(name, settings);
  AStarOptions options = settings.astar;
  if (name == "astar" || name == "astar-coarse") {
    options.cost = AStarCost::Paper;
    if (name == "astar-coarse" && options.coarse_factor == 0) options.coarse_factor = 4;
  } else {
    options.cost = AStarCost::Euclidean;  // "astar-euclid"
  }
  return std::make_unique<AStarPlanner>(options);
}

}  // namespace uavip::planners
