#pragma once
/// \file
/// One planning run through the ompl::base::Planner interface for any registered
/// planner (the grid A* included), without exposing OMPL types: the benchmark
/// (uavip bench, bench/runner.h) uses it so every planner runs in the same harness.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "planners/registry.h"
#include "uavip/core/types.h"
#include "uavip/planning/planner.h"
#include "uavip/world/voxel_grid.h"

namespace uavip::planners {

/// Measurements of one run, in OMPL's benchmark terms.
struct HarnessRun {
  std::string ompl_name;  ///< OMPL planner name, e.g. "RRTConnect", "AStar"
  int status{0};          ///< index into plannerStatusNames()
  planning::PathStatus path_status{planning::PathStatus::NoPath};
  bool solved{false};           ///< exact solution
  bool approximate{false};      ///< OMPL returned an approximate solution only
  double time_s{0.0};           ///< solve() wall time [s]
  double simplify_time_s{0.0};  ///< simplification wall time [s] (0 without)
  PointList raw_path;           ///< the planner's path (empty unless solved) [m]
  PointList path;               ///< simplified path (or raw_path without simplification) [m]
  double raw_length_m{0.0};
  double length_m{0.0};
  std::size_t graph_states{0};
  std::size_t graph_motions{0};
};

/// Seeds OMPL's global RNG (ompl::RNG::setSeed) once per process, before the first
/// OMPL planner is created, and sets OMPL's log level to errors only. OMPL cannot be
/// re-seeded once sampling started, so only the first seed given takes effect (0 is
/// used as 1). Returns true if OMPL runs with `seed`. makePlanner, makeOmplPlanner and
/// runPlannerOnce call it with their settings' seed.
bool seedOmpl(std::uint32_t seed);

/// The values of the `status` enum of the OMPL benchmark log, in PlannerStatus order
/// (OMPL's texts, with ABORT named "Abort": OMPL 1.5.2 calls it "Unknown status").
std::vector<std::string> plannerStatusNames();

/// OMPL's name for a registry name (e.g. "rrtconnect" → "RRTConnect"); throws
/// InputError for an unknown name.
std::string omplName(const std::string& name);

/// The OMPL version the planners are built with, e.g. "1.5.2".
std::string omplVersion();

/// Plans start → goal once with planner `name` (a fresh planner, budget
/// settings.time_limit_s, path-length objective; simplified when settings.simplify).
/// An end outside the free space gives status Invalid start / Invalid goal without
/// running the planner. Never throws for a registered name and finite points.
HarnessRun runPlannerOnce(const std::string& name, const world::VoxelGrid& grid, const Vec3& start,
                          const Vec3& goal, const PlannerSettings& settings);

}  // namespace uavip::planners
