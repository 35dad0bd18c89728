#include "planners/harness.h"

#include <ompl/base/PlannerData.h>
#include <ompl/base/PlannerStatus.h>
#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/ScopedState.h>
#include <ompl/base/objectives/PathLengthOptimizationObjective.h>
#include <ompl/geometric/PathGeometric.h>
#include <ompl/geometric/planners/prm/LazyPRM.h>
#include <ompl/geometric/planners/prm/PRM.h>
#include <ompl/util/Exception.h>

#include <exception>
#include <utility>

#include "planners/astar_ompl.h"
#include "planners/ompl_planners.h"
#include "uavip/core/error.h"
#include "uavip/core/stopwatch.h"

#ifndef UAVIP_OMPL_VERSION
#define UAVIP_OMPL_VERSION "unknown"
#endif

namespace uavip::planners {
namespace {

namespace ob = ompl::base;
namespace og = ompl::geometric;

void setState(ob::ScopedState<>& s, const Vec3& p) {
  for (unsigned int i = 0; i < 3; ++i) s[i] = p[static_cast<int>(i)];
}

/// Sets run.graph_states and run.graph_motions. With `planner_data`, as OMPL's
/// benchmark counts them (its PlannerData); otherwise a roadmap (PRM*, LazyPRM*) is
/// counted directly, milestones and edges: the PlannerData of a roadmap kept over many
/// legs (50,000 states) takes longer to build than a leg's budget.
void countGraph(const ob::Planner& planner, const ob::SpaceInformationPtr& si, bool planner_data,
                HarnessRun& run) {
  if (!planner_data) {
    if (const auto* prm = dynamic_cast<const og::PRM*>(&planner)) {
      run.graph_states = prm->milestoneCount();
      run.graph_motions = prm->edgeCount();
      return;
    }
    if (const auto* lazy = dynamic_cast<const og::LazyPRM*>(&planner)) {
      run.graph_states = lazy->milestoneCount();
      run.graph_motions = lazy->edgeCount();
      return;
    }
  }
  try {
    ob::PlannerData data(si);
    planner.getPlannerData(data);
    run.graph_states = data.numVertices();
    run.graph_motions = data.numEdges();
  } catch (const std::exception&) {
    // Statistics only: leave them at 0.
  }
}

}  // namespace

std::vector<std::string> plannerStatusNames() {
  std::vector<std::string> names;
  names.reserve(ob::PlannerStatus::TYPE_COUNT);
  for (int i = 0; i < ob::PlannerStatus::TYPE_COUNT; ++i) {
    names.push_back(ob::PlannerStatus(static_cast<ob::PlannerStatus::StatusType>(i)).asString());
  }
  // OMPL 1.5.2 names ABORT "Unknown status" like UNKNOWN; the enum needs distinct values.
  names[ob::PlannerStatus::ABORT] = "Abort";
  return names;
}

std::string omplName(const std::string& name) { return planning::plannerSpec(name).ompl_name; }

std::string omplVersion() { return UAVIP_OMPL_VERSION; }

HarnessRun runPlannerOnce(const std::string& name, const world::VoxelGrid& grid, const Vec3& start,
                          const Vec3& goal, const PlannerSettings& settings) {
  HarnessRun run;
  run.ompl_name = omplName(name);
  seedOmpl(settings.seed);
  if (!start.allFinite() || !grid.isFree(start)) {
    run.status = ob::PlannerStatus::INVALID_START;
    run.path_status = planning::PathStatus::InvalidStart;
    return run;
  }
  if (!goal.allFinite() || !grid.isFree(goal)) {
    run.status = ob::PlannerStatus::INVALID_GOAL;
    run.path_status = planning::PathStatus::InvalidGoal;
    return run;
  }

  const ob::SpaceInformationPtr si = makeSpaceInformation(grid);
  return solveQuery(makeOmplPlanner(name, si, grid, settings), si, start, goal, settings, true);
}

HarnessRun solveQuery(const ob::PlannerPtr& planner, const ob::SpaceInformationPtr& si,
                      const Vec3& start, const Vec3& goal, const PlannerSettings& settings,
                      bool planner_data) {
  HarnessRun run;
  run.ompl_name = planner->getName();
  auto pdef = std::make_shared<ob::ProblemDefinition>(si);
  ob::ScopedState<> s(si);
  ob::ScopedState<> g(si);
  setState(s, start);
  setState(g, goal);
  pdef->setStartAndGoalStates(s, g);
  pdef->setOptimizationObjective(std::make_shared<ob::PathLengthOptimizationObjective>(si));
  planner->setProblemDefinition(pdef);

  ob::PlannerStatus status = ob::PlannerStatus::UNKNOWN;
  const auto t0 = SteadyClock::now();
  try {
    planner->setup();
    status = planner->solve(settings.time_limit_s);
  } catch (const std::exception&) {
    status = ob::PlannerStatus::CRASH;
  }
  run.time_s = secondsSince(t0);
  run.status = static_cast<ob::PlannerStatus::StatusType>(status);

  countGraph(*planner, si, planner_data, run);

  run.solved = status == ob::PlannerStatus::EXACT_SOLUTION && pdef->hasExactSolution();
  run.approximate = status == ob::PlannerStatus::APPROXIMATE_SOLUTION;
  if (run.solved) {
    run.path_status = planning::PathStatus::Solved;
    og::PathGeometric path(*pdef->getSolutionPath()->as<og::PathGeometric>());
    run.raw_path = toPoints(path);
    run.raw_length_m = path.length();
    if (settings.simplify) run.simplify_time_s = simplifyOmplPath(path, si);
    run.path = toPoints(path);
    run.length_m = path.length();
  } else if (const auto* astar = dynamic_cast<const AStarOmplPlanner*>(planner.get())) {
    run.path_status = astar->lastResult().status;
  } else if (status == ob::PlannerStatus::TIMEOUT ||
             status == ob::PlannerStatus::APPROXIMATE_SOLUTION) {
    run.path_status = planning::PathStatus::Timeout;
  } else {
    run.path_status = planning::PathStatus::NoPath;
  }
  return run;
}

}  // namespace uavip::planners
