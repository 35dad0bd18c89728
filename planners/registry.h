#pragma once
/// \file
/// Planners by name (docs/ARCHITECTURE.md, planners/).

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "planners/astar.h"
#include "uavip/planning/planner.h"

namespace uavip::planners {

/// Settings shared by the registered planners.
struct PlannerSettings {
  AStarOptions astar;        ///< weights and budget of the grid A*
  double time_limit_s{1.0};  ///< budget of an OMPL planner per leg [s]
  /// Seed of OMPL's global RNG; only the first seed of a process takes effect
  /// (harness.h, seedOmpl).
  std::uint32_t seed{1};
  /// Simplify OMPL paths (PathSimplifier reduceVertices + shortcutPath, validated with
  /// the grid's motion validator; no B-spline).
  bool simplify{true};

  /// Throws InputError naming the bad field (prefix `where`).
  void validate(const std::string& where = "planner") const;
};

/// Names accepted by makePlanner, in a stable order: the grid A* ("astar",
/// "astar-euclid", "astar-coarse") first, then the OMPL planners of ompl_planners.h ("rrtconnect",
/// "rrtstar", "informed-rrtstar", "bitstar", "abitstar", "aitstar", "prmstar",
/// "lazyprmstar", "fmtstar").
std::vector<std::string> plannerNames();

/// Throws InputError listing the valid names unless `name` is one of plannerNames().
/// Creates nothing: validating a config must not seed OMPL (harness.h, seedOmpl).
void requireKnownPlanner(const std::string& name);

/// True for the planners whose paths do not depend on a random stream (the grid
/// A*s): instances may plan in parallel and the mission stays reproducible. OMPL's
/// planners draw from one process-wide stream (seedOmpl), so they plan in order.
bool isDeterministic(const std::string& name);

/// Creates the planner `name`; throws InputError listing the valid names otherwise.
std::unique_ptr<planning::Planner> makePlanner(const std::string& name,
                                               const PlannerSettings& settings);

}  // namespace uavip::planners
