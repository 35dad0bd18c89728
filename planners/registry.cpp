#include "planners/registry.h"

#include "planners/ompl_planners.h"
#include "uavip/core/error.h"

#include <algorithm>


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

void requireKnownPlanner(const std::string& name) {
  const std::vector<std::string> names = plannerNames();
  if (std::find(names.begin(), names.end(), name) != names.end()) return;
  std::string valid;
  for (const auto& n : names) valid += (valid.empty() ? "" : ", ") + n;
  throw InputError("planner: unknown planner '" + name + "'; valid names: " + valid);
}

std::unique_ptr<planning::Planner> makePlanner(const std::string& name, const PlannerSettings& settings) {
  settings.validate("planner");
  requireKnownPlanner(name);
  if (isOmplPlanner(name)) return std::make_unique<OmplPlanner>(name, settings);
  AStarOptions options = settings.astar;
  if (name == "astar") {
    options.cost = AStarCost::Paper;
  } else {
    options.cost = AStarCost::Euclidean;  // "astar-euclid"
  }
  return std::make_unique<AStarPlanner>(options);
}

}  // namespace uavip::planners
