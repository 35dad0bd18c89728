#include "planners/astar_ompl.h"

#include <ompl/base/PlannerData.h>
#include <ompl/base/ScopedState.h>
#include <ompl/base/goals/GoalSampleableRegion.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/geometric/PathGeometric.h>

#include "planners/ompl_planners.h"

namespace uavip::planners {
namespace {

namespace ob = ompl::base;
namespace og = ompl::geometric;

void setPoint(ob::State* state, const Vec3& p) {
  auto* s = state->as<ob::RealVectorStateSpace::StateType>();
  for (unsigned int i = 0; i < 3; ++i) s->values[i] = p[static_cast<int>(i)];
}

}  // namespace

AStarOmplPlanner::AStarOmplPlanner(const ob::SpaceInformationPtr& si, const world::VoxelGrid& grid,
                                   AStarOptions options, const std::string& name)
    : ob::Planner(si, name), grid_(grid), astar_(options, name) {
  specs_.approximateSolutions = false;
  specs_.optimizingPaths = false;  // optimal for its own grid cost, not for the OMPL objective
  specs_.directed = true;
}

ob::PlannerStatus AStarOmplPlanner::solve(const ob::PlannerTerminationCondition& ptc) {
  checkValidity();
  last_ = {};
  path_.reset();
  const ob::State* start = pis_.nextStart();
  if (start == nullptr) {
    last_.status = planning::PathStatus::InvalidStart;
    return ob::PlannerStatus::INVALID_START;
  }
  if (dynamic_cast<const ob::GoalSampleableRegion*>(pdef_->getGoal().get()) == nullptr) {
    return ob::PlannerStatus::UNRECOGNIZED_GOAL_TYPE;
  }
  const ob::State* goal = pis_.nextGoal(ptc);
  if (goal == nullptr) {
    last_.status = planning::PathStatus::InvalidGoal;
    return ob::PlannerStatus::INVALID_GOAL;
  }
  last_ = astar_.plan(grid_, toVec3(start), toVec3(goal));
  switch (last_.status) {
    case planning::PathStatus::Solved: {
      auto path = std::make_shared<og::PathGeometric>(si_);
      ob::ScopedState<> s(si_);
      for (const Vec3& p : last_.path) {
        setPoint(s.get(), p);
        path->append(s.get());
      }
      path_ = path;
      pdef_->addSolutionPath(path, false, 0.0, getName());
      return ob::PlannerStatus::EXACT_SOLUTION;
    }
    case planning::PathStatus::InvalidStart:
      return ob::PlannerStatus::INVALID_START;
    case planning::PathStatus::InvalidGoal:
      return ob::PlannerStatus::INVALID_GOAL;
    case planning::PathStatus::Timeout:
      return ob::PlannerStatus::TIMEOUT;
    case planning::PathStatus::NoPath:
      break;
  }
  return ob::PlannerStatus::ABORT;
}

void AStarOmplPlanner::clear() {
  ob::Planner::clear();
  last_ = {};
  path_.reset();
}

void AStarOmplPlanner::getPlannerData(ob::PlannerData& data) const {
  ob::Planner::getPlannerData(data);
  if (!path_ || path_->getStateCount() == 0) return;
  // PlannerData keeps pointers: the states belong to path_, alive until the next solve.
  const std::size_t n = path_->getStateCount();
  data.addStartVertex(ob::PlannerDataVertex(path_->getState(0)));
  if (n > 1) data.addGoalVertex(ob::PlannerDataVertex(path_->getState(n - 1)));
  for (std::size_t i = 0; i + 1 < n; ++i) {
    data.addEdge(ob::PlannerDataVertex(path_->getState(i)),
                 ob::PlannerDataVertex(path_->getState(i + 1)));
  }
}

}  // namespace uavip::planners
