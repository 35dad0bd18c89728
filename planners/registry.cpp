#include "planners/registry.h"

#include "uavip/core/error.h"

namespace uavip::planners {

std::vector<std::string> plannerNames() { return {"astar", "astar-euclid"}; }

std::unique_ptr<planning::Planner> makePlanner(const std::string& name, const PlannerSettings& settings) {
  AStarOptions options = settings.astar;
  if (name == "astar") {
    options.cost = AStarCost::Paper;
  } else if (name == "astar-euclid") {
    options.cost = AStarCost::Euclidean;
  } else {
    std::string valid;
    for (const auto& n : plannerNames()) valid += (valid.empty() ? "" : ", ") + n;
    throw InputError("planner: unknown planner '" + name + "'; valid names: " + valid);
  }
  options.validate("planner");
  return std::make_unique<AStarPlanner>(options);
}

}  // namespace uavip::planners
