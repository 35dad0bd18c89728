// The planner table and its lookups (planning/planner_table.h): plain data, no OMPL,
// so reading and checking a config links no planner.
#include "uavip/planning/planner_table.h"

#include "uavip/core/error.h"

namespace uavip::planning {

const std::vector<PlannerSpec>& plannerTable() {
  using F = PlannerFactory;
  static const std::vector<PlannerSpec> table{
      {kPaperPlanner, "AStar", F::GridAStar, AStarCost::Paper, 0},
      {"astar-euclid", "AStarEuclid", F::GridAStar, AStarCost::Euclidean, 0},
      // The default: the paper's cost searched coarse to fine on blocks of 4 voxels first.
      {"astar-coarse", "AStarCoarse", F::GridAStar, AStarCost::Paper, 4},
      {"rrtconnect", "RRTConnect", F::RRTConnect},
      {"rrtstar", "RRTstar", F::RRTstar},
      {"informed-rrtstar", "InformedRRTstar", F::InformedRRTstar},
      {"bitstar", "BITstar", F::BITstar},
      {"abitstar", "ABITstar", F::ABITstar},
      {"aitstar", "AITstar", F::AITstar},
      {"prmstar", "PRMstar", F::PRMstar},
      {"lazyprmstar", "LazyPRMstar", F::LazyPRMstar},
      {"fmtstar", "FMT", F::FMT},
  };
  return table;
}

AStarOptions PlannerSpec::astarOptions(const PlannerSettings& settings) const {
  AStarOptions options = settings.astar;
  options.cost = cost;
  if (options.coarse_factor == 0) options.coarse_factor = coarse_factor;
  return options;
}

const PlannerSpec* findPlanner(const std::string& name) {
  for (const auto& p : plannerTable()) {
    if (p.name == name) return &p;
  }
  return nullptr;
}

const PlannerSpec& plannerSpec(const std::string& name) {
  if (const PlannerSpec* p = findPlanner(name)) return *p;
  std::string valid;
  for (const auto& p : plannerTable()) valid += (valid.empty() ? "" : ", ") + p.name;
  throw InputError("planner: unknown planner '" + name + "'; valid names: " + valid);
}

std::vector<std::string> plannerNames() {
  std::vector<std::string> names;
  for (const auto& p : plannerTable()) names.push_back(p.name);
  return names;
}

void requireKnownPlanner(const std::string& name) { plannerSpec(name); }

bool isDeterministic(const std::string& name) {
  const PlannerSpec* p = findPlanner(name);
  return p != nullptr && p->deterministic();
}

void AStarOptions::validate(const std::string& where) const {
  requirePositive(a1, where, "a1");
  requirePositive(a2, where, "a2");
  requirePositive(a3, where, "a3");
  requireThat(coarse_factor == 0 || (coarse_factor >= 2 && coarse_factor <= 16), where,
              "coarse_factor", "0 or in [2, 16]", coarse_factor);
}

void PlannerSettings::validate(const std::string& where) const {
  astar.validate(where);
  requirePositive(time_limit_s, where, "time_limit_s");
}

}  // namespace uavip::planning
