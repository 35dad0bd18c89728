#pragma once
/// \file
/// The paper's grid A* (§II-G) as an ompl::base::Planner, so one harness runs it beside
/// the OMPL planners. solve() reads the start and the goal from the problem
/// definition, runs the A* of planners/astar.h on the grid and adds the path (exact
/// start, voxel centres, exact goal) with pdef_->addSolutionPath. The search ignores
/// the termination condition; its budget is AStarOptions::max_expansions.
/// Statuses: EXACT_SOLUTION, INVALID_START / INVALID_GOAL (not in a free voxel),
/// TIMEOUT (expansion budget exhausted), ABORT (the grid search exhausted the free
/// space: no path exists on the grid).

#include <ompl/base/Planner.h>
#include <ompl/geometric/PathGeometric.h>

#include <memory>
#include <string>

#include "planners/astar.h"
#include "uavip/planning/planner.h"
#include "uavip/world/voxel_grid.h"

namespace uavip::planners {

/// Grid A* behind the OMPL planner interface. The space must be an R³ space (e.g.
/// makeSpaceInformation); the grid must outlive the planner. makeOmplPlanner names it
/// by its planner table row ("AStar", "AStarEuclid", "AStarCoarse"); `name` is the
/// row's registry name, which its A* reports.
class AStarOmplPlanner : public ompl::base::Planner {
 public:
  AStarOmplPlanner(const ompl::base::SpaceInformationPtr& si, const world::VoxelGrid& grid,
                   AStarOptions options, const std::string& name = planning::kPaperPlanner);

  using ompl::base::Planner::solve;  // solve(seconds) too
  ompl::base::PlannerStatus solve(const ompl::base::PlannerTerminationCondition& ptc) override;
  void clear() override;
  /// The vertices and edges of the last path.
  void getPlannerData(ompl::base::PlannerData& data) const override;

  /// The last search's result (status, grid cost, expansions, path).
  const planning::PathResult& lastResult() const { return last_; }
  /// The options its A* searches with.
  const AStarOptions& options() const { return astar_.options(); }

 private:
  const world::VoxelGrid& grid_;
  AStarPlanner astar_;
  planning::PathResult last_;
  std::shared_ptr<ompl::geometric::PathGeometric>
      path_;  ///< last solution (owns the states of getPlannerData)
};

}  // namespace uavip::planners
