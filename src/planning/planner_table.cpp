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
  table().check(*this, where);
  requireThat(coarse_factor == 0 || (coarse_factor >= 2 && coarse_factor <= 16), where,
              table().find(*this, &coarse_factor)->key, "0 or in [2, 16]", coarse_factor);
}

const params::Table<AStarOptions>& AStarOptions::table() {
  static const params::Table<AStarOptions> t = [] {
    using O = AStarOptions;
    params::Table<O> p;
    p.add(
         "cost_weights", params::Kind::Numbers,
         [](const O& o) {
           return params::Value{{o.a1, o.a2, o.a3}, {}, true};
         },
         [](O& o, const params::Value& v) {
           o.a1 = v.numbers.at(0);
           o.a2 = v.numbers.at(1);
           o.a3 = v.numbers.at(2);
         },
         "grid A*'s weights [a1, a2, a3] of x, y and z moves (§II-G)")
        .count(3, 3)
        .positive()
        .storedAt([](const O& o) -> const void* { return &o.a1; });
    p.add("max_expansions", &O::max_expansions,
          "grid A*'s budget of expanded voxels per leg (0: unlimited), else status Timeout")
        .atLeast(0);
    p.add("coarse_factor", &O::coarse_factor,
          "grid A*'s coarse block in voxels, 2..16 (0: the planner's own: astar-coarse 4, astar "
          "none)")
        .within(0, 16);
    return p;
  }();
  return t;
}

void PlannerSettings::validate(const std::string& where) const {
  table().check(*this, where);
  astar.validate(where);
}

const params::Table<PlannerSettings>& PlannerSettings::table() {
  static const params::Table<PlannerSettings> t = [] {
    using O = PlannerSettings;
    params::Table<O> p;
    p.add("time_limit_s", &O::time_limit_s, "budget of an OMPL planner per leg")
        .unitIs("s")
        .positive();
    p.add("seed", &O::seed, "seed of OMPL's random stream (the first seed of a process counts)")
        .atLeast(0);
    p.add("simplify", &O::simplify, "simplify OMPL paths (reduce vertices, shortcut)");
    p.include("", &O::astar, AStarOptions::table());
    return p;
  }();
  return t;
}

}  // namespace uavip::planning
