// The planner table and the registry's lookups that read only it (registry.h:
// PlannerSettings::validate, plannerNames, requireKnownPlanner, isDeterministic):
// no OMPL here, so validating a config links no planner.
#include "planners/planner_table.h"

#include <algorithm>

#include "planners/registry.h"
#include "uavip/core/error.h"

namespace uavip::planners {

const std::vector<PlannerInfo>& plannerTable() {
  static const std::vector<PlannerInfo> table{
      {"astar", "AStar", false},
      {"astar-euclid", "AStarEuclid", false},
      {"astar-coarse", "AStarCoarse", false},
      {"rrtconnect", "RRTConnect", true},
      {"rrtstar", "RRTstar", true},
      {"informed-rrtstar", "InformedRRTstar", true},
      {"bitstar", "BITstar", true},
      {"abitstar", "ABITstar", true},
      {"aitstar", "AITstar", true},
      {"prmstar", "PRMstar", true},
      {"lazyprmstar", "LazyPRMstar", true},
      {"fmtstar", "FMT", true},
  };
  return table;
}

const PlannerInfo* findPlanner(const std::string& name) {
  for (const auto& p : plannerTable()) {
    if (p.name == name) return &p;
  }
  return nullptr;
}

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

}  // namespace uavip::planners
