#include "planners/registry.h"

#include "planners/ompl_planners.h"
#include "planners/planner_table.h"
#include "uavip/core/error.h"

#include <algorithm>


namespace uavip::planners {

void PlannerSettings::validate(const std::string& where) const {
  astar.validate(where);
  requirePositive(time_limit_s, where, "time_limit_s");
}

std::vector<std::string> plannerNames() {
  std::vector<std::string> names;
  for (const auto& p : plannerTable()) names.push_back(p.name);
  return names;
}

void requireKnownPlanner(const std::string& name) {
  const std::vector<std::string> names = plannerNames();
  if (std::find(names.begin(), names.end(), name) != names.end()) return;
  std::string valid;
  for (const auto& n : names) valid += (valid.empty() ? "" : ", ") + n;
  throw InputError("planner: unknown planner '" + name + "'; valid names: " + valid);
}

bool isDeterministic(const std::string& name) {
  const PlannerInfo* row = findPlanner(name);
  return row != nullptr && !row->isSampling();
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
