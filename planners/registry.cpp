#include "planners/registry.h"

#include "planners/ompl_planners.h"
#include "uavip/core/error.h"


namespace uavip::planners {

void PlannerSettings::validate(const std::string& where) const {
  astar.validate(where);
  requirePositive(time_limit_s, where, "time_limit_s");
}

std::vector<std::string> plannerNames() {
  std::vector<std::string> names{"astar", "astar-euclid"};
  for (const auto& n : omplPlannerNames()) names.push_back(n);
  return names;
}

std::unique_ptr<planning::Planner> makePlanner(const std::string& name, const PlannerSettings& settings) {
  settings.validate("planner");
  if (isOmplPlanner(name)) return std::make_unique<OmplPlanner>(name, settings);
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
  return std::make_unique<AStarPlanner>(options);
}

}  // namespace uavip::planners
