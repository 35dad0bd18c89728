#pragma once
/// \file
/// The planners, one row each (OMPL's planner allocators are the model), and the
/// settings every planner reads. Plain data and lookups, no OMPL and no search
/// (library uavip_planning_types): a config names and checks its planner with this
/// header alone; planners/registry.h (makePlanner) and planners/harness.h (the
/// benchmark's runPlannerOnce) build a planner from its row, so both paths build the
/// same planner with the same settings. Adding a planner is one row here and, for an
/// OMPL planner, one case in planners/ompl_planners.cpp's switch over PlannerFactory
/// (a missing case does not compile under -Werror=switch).

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "uavip/core/params.h"

namespace uavip::planning {

/// Step cost model of the grid A* (planners/astar.h, §II-G).
enum class AStarCost { Paper, Euclidean };

/// Options of the grid A* (planners/astar.h).
struct AStarOptions {
  AStarCost cost{AStarCost::Paper};
  double a1{1.0};                 ///< weight of x moves
  double a2{1.0};                 ///< weight of y moves
  double a3{1.0};                 ///< weight of z moves
  std::size_t max_expansions{0};  ///< 0 = unlimited; otherwise status Timeout when exceeded
  int coarse_factor{0};           ///< 0: the whole grid; k in [2, 16]: coarse to fine

  /// Throws InputError naming the bad field (prefix `where`).
  void validate(const std::string& where = "planner") const;
  /// The keys of `planner:` this struct holds (core/params.h).
  static const params::Table<AStarOptions>& table();
};

/// Settings shared by the planners (config section `planner:`).
struct PlannerSettings {
  AStarOptions astar;        ///< weights and budget of the grid A*
  double time_limit_s{1.0};  ///< budget of an OMPL planner per leg [s]
  /// Seed of OMPL's global RNG; only the first seed of a process takes effect
  /// (planners/harness.h, seedOmpl).
  std::uint32_t seed{1};
  /// Simplify OMPL paths (PathSimplifier reduceVertices + shortcutPath, validated with
  /// the grid's motion validator; no B-spline).
  bool simplify{true};

  /// Throws InputError naming the bad field (prefix `where`).
  void validate(const std::string& where = "planner") const;
  /// The keys of `planner:` these settings hold, the grid A*'s included (core/params.h).
  static const params::Table<PlannerSettings>& table();
};

/// What builds a row's planner: uavip's grid A* or one of OMPL's geometric planners.
enum class PlannerFactory {
  GridAStar,
  RRTConnect,
  RRTstar,
  InformedRRTstar,
  BITstar,
  ABITstar,
  AITstar,
  PRMstar,
  LazyPRMstar,
  FMT,
};

/// One planner.
struct PlannerSpec {
  std::string name;       ///< registry name, e.g. "rrtconnect" (config `planner.name`, --planner)
  std::string ompl_name;  ///< OMPL's planner name, e.g. "RRTConnect" (bench log's geometric_<…>)
  PlannerFactory factory{PlannerFactory::GridAStar};
  /// Grid A* rows: the step cost, and the coarse factor used when the settings leave
  /// `coarse_factor` at 0 (0: the whole grid).
  AStarCost cost{AStarCost::Paper};
  int coarse_factor{0};

  /// uavip's grid A* (not an OMPL sampling planner).
  bool gridSearch() const { return factory == PlannerFactory::GridAStar; }
  /// Paths do not depend on a random stream (the grid A*s): instances may plan in
  /// parallel and the mission stays reproducible. OMPL's planners draw from one
  /// process-wide stream (seedOmpl), so they plan in order.
  bool deterministic() const { return gridSearch(); }
  /// The grid A*'s options for this row: `settings.astar` with the row's cost, and the
  /// row's coarse factor when the settings give none. The one place a row's A* is set.
  AStarOptions astarOptions(const PlannerSettings& settings) const;
};

/// The paper's planner (§II-G, the whole-grid A* with its step cost): the reference of
/// the benchmark's "/ A*" ratios, and the name a bare AStarPlanner reports.
inline constexpr const char* kPaperPlanner = "astar";

/// Every planner, in a stable order: the grid A* ("astar", "astar-euclid",
/// "astar-coarse") first, then OMPL's ("rrtconnect", "rrtstar", "informed-rrtstar",
/// "bitstar", "abitstar", "aitstar", "prmstar", "lazyprmstar", "fmtstar").
const std::vector<PlannerSpec>& plannerTable();

/// The row of `name`, or nullptr.
const PlannerSpec* findPlanner(const std::string& name);

/// The row of `name`; throws InputError listing the valid names otherwise.
const PlannerSpec& plannerSpec(const std::string& name);

/// The names of plannerTable(), in its order.
std::vector<std::string> plannerNames();

/// Throws InputError listing the valid names unless `name` is a row's name. Creates
/// nothing: validating a config must not seed OMPL (planners/harness.h, seedOmpl).
void requireKnownPlanner(const std::string& name);

/// PlannerSpec::deterministic of the row `name`; false for an unknown name.
bool isDeterministic(const std::string& name);

}  // namespace uavip::planning
