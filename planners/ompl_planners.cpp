#include "planners/ompl_planners.h"

#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/geometric/PathSimplifier.h>
#include <ompl/geometric/planners/fmt/FMT.h>
#include <ompl/geometric/planners/informedtrees/ABITstar.h>
#include <ompl/geometric/planners/informedtrees/AITstar.h>
#include <ompl/geometric/planners/informedtrees/BITstar.h>
#include <ompl/geometric/planners/prm/LazyPRMstar.h>
#include <ompl/geometric/planners/prm/PRMstar.h>
#include <ompl/geometric/planners/rrt/InformedRRTstar.h>
#include <ompl/geometric/planners/rrt/RRTConnect.h>
#include <ompl/geometric/planners/rrt/RRTstar.h>
#include <ompl/util/Console.h>
#include <ompl/util/RandomNumbers.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>
#include <stdexcept>

#include "planners/astar_ompl.h"
#include "planners/harness.h"
#include "uavip/core/error.h"
#include "uavip/core/geometry.h"
#include "uavip/core/stopwatch.h"

namespace uavip::planners {
namespace {

namespace ob = ompl::base;
namespace og = ompl::geometric;

/// Builds the OMPL sampling planner of a table row (planning/planner_table.h): the one
/// place a row's factory becomes an OMPL class.
ob::PlannerPtr makeSampling(planning::PlannerFactory factory, const ob::SpaceInformationPtr& si) {
  using F = planning::PlannerFactory;
  switch (factory) {
    case F::RRTConnect:
      return std::make_shared<og::RRTConnect>(si);
    case F::RRTstar:
      return std::make_shared<og::RRTstar>(si);
    case F::InformedRRTstar:
      return std::make_shared<og::InformedRRTstar>(si);
    case F::BITstar:
      return std::make_shared<og::BITstar>(si);
    case F::ABITstar:
      return std::make_shared<og::ABITstar>(si);
    case F::AITstar:
      return std::make_shared<og::AITstar>(si);
    case F::PRMstar:
      return std::make_shared<og::PRMstar>(si);
    case F::LazyPRMstar:
      return std::make_shared<og::LazyPRMstar>(si);
    case F::FMT:
      return std::make_shared<og::FMT>(si);
    case F::GridAStar:
      break;
  }
  throw std::logic_error("planner table: a grid A* row has no OMPL sampling planner");
}

}  // namespace

FreeSpaceMotionValidator::FreeSpaceMotionValidator(const ob::SpaceInformationPtr& si,
                                                   const world::FreeSpace& space)
    : ob::MotionValidator(si), space_(space) {}

bool FreeSpaceMotionValidator::checkMotion(const ob::State* s1, const ob::State* s2) const {
  if (space_.segmentFree(toVec3(s1), toVec3(s2))) {
    ++valid_;
    return true;
  }
  ++invalid_;
  return false;
}

bool FreeSpaceMotionValidator::checkMotion(const ob::State* s1, const ob::State* s2,
                                           std::pair<ob::State*, double>& last_valid) const {
  const Vec3 a = toVec3(s1);
  const Vec3 b = toVec3(s2);
  const double step = 0.25 * space_.resolution();
  const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / step)));
  Vec3 prev = a;
  for (int k = 1; k <= n; ++k) {
    const double t = static_cast<double>(k) / n;
    const Vec3 p = a + t * (b - a);
    if (!space_.segmentFree(prev, p)) {
      last_valid.second = static_cast<double>(k - 1) / n;
      if (last_valid.first != nullptr) {
        si_->getStateSpace()->interpolate(s1, s2, last_valid.second, last_valid.first);
      }
      ++invalid_;
      return false;
    }
    prev = p;
  }
  ++valid_;
  return true;
}

ob::SpaceInformationPtr makeSpaceInformation(const world::FreeSpace& free_space) {
  auto space = std::make_shared<ob::RealVectorStateSpace>(3);
  const Aabb box = free_space.bounds();
  ob::RealVectorBounds bounds(3);
  for (int i = 0; i < 3; ++i) {
    bounds.setLow(static_cast<unsigned int>(i), box.min[i]);
    bounds.setHigh(static_cast<unsigned int>(i), box.max[i]);
  }
  space->setBounds(bounds);
  auto si = std::make_shared<ob::SpaceInformation>(space);
  const world::FreeSpace* f = &free_space;
  si->setStateValidityChecker([f](const ob::State* s) { return f->isFree(toVec3(s)); });
  si->setMotionValidator(std::make_shared<FreeSpaceMotionValidator>(si, free_space));
  si->setup();
  return si;
}

Vec3 toVec3(const ob::State* state) {
  const auto* s = state->as<ob::RealVectorStateSpace::StateType>();
  return {s->values[0], s->values[1], s->values[2]};
}

PointList toPoints(const og::PathGeometric& path) {
  PointList out;
  out.reserve(path.getStateCount());
  for (std::size_t i = 0; i < path.getStateCount(); ++i) out.push_back(toVec3(path.getState(i)));
  return out;
}

std::vector<std::string> omplPlannerNames() {
  std::vector<std::string> names;
  for (const auto& p : planning::plannerTable()) {
    if (!p.gridSearch()) names.push_back(p.name);
  }
  return names;
}

bool isOmplPlanner(const std::string& name) {
  const planning::PlannerSpec* p = planning::findPlanner(name);
  return p != nullptr && !p->gridSearch();
}

bool seedOmpl(std::uint32_t seed) {
  static std::once_flag once;
  static std::uint32_t used = 0;
  std::call_once(once, [seed] {
    ompl::msg::setLogLevel(ompl::msg::LOG_ERROR);
    ompl::RNG::setSeed(seed == 0 ? 1 : seed);  // OMPL refuses seed 0
    used = seed;
  });
  return used == seed;
}

ob::PlannerPtr makeOmplPlanner(const std::string& name, const ob::SpaceInformationPtr& si,
                               const world::VoxelGrid& grid, const PlannerSettings& settings) {
  const planning::PlannerSpec& spec = planning::plannerSpec(name);  // throws for an unknown name
  seedOmpl(settings.seed);
  // The grid A* rows: uavip's A* behind OMPL's interface, with the options makePlanner uses.
  ob::PlannerPtr p = spec.gridSearch() ? std::make_shared<AStarOmplPlanner>(
                                             si, grid, spec.astarOptions(settings), spec.name)
                                       : makeSampling(spec.factory, si);
  p->setName(spec.ompl_name);
  return p;
}

double simplifyOmplPath(og::PathGeometric& path, const ob::SpaceInformationPtr& si) {
  const auto t0 = SteadyClock::now();
  og::PathSimplifier simplifier(si);
  double length = path.length();
  for (int round = 0; round < 5; ++round) {
    simplifier.reduceVertices(path);
    simplifier.shortcutPath(path);
    const double now = path.length();
    if (!(now < length - 1e-9)) break;
    length = now;
  }
  return secondsSince(t0);
}

OmplPlanner::OmplPlanner(std::string name, PlannerSettings settings)
    : name_(std::move(name)), settings_(settings) {
  if (!isOmplPlanner(name_)) throw InputError("planner: '" + name_ + "' is not an OMPL planner");
  settings_.validate("planner");
  seedOmpl(settings_.seed);
}

bool OmplPlanner::bindTo(const world::VoxelGrid& grid) {
  if (planner_ && space_ == &grid && space_id_ == grid.contentId()) return false;
  si_ = makeSpaceInformation(grid);
  planner_ = makeOmplPlanner(name_, si_, grid, settings_);
  space_ = &grid;
  space_id_ = grid.contentId();
  return true;
}

planning::PathResult OmplPlanner::plan(const world::VoxelGrid& grid, const Vec3& start,
                                       const Vec3& goal) {
  return planning::timedPlan(grid, start, goal, [&](planning::PathResult& out) {
    if (grid.segmentFree(start, goal)) {
      out.path = {start, goal};
      out.cost = (goal - start).norm();
      return;
    }
    // Only a planner that has solved is cleared: OMPL 1.5.2's AITstar::clear() crashes
    // before its first setup().
    if (!bindTo(grid)) planner_->clearQuery();
    const HarnessRun run = solveQuery(planner_, si_, start, goal, settings_, false);
    out.status = run.path_status;
    out.graph_states = run.graph_states;
    if (run.solved) {
      out.path = run.path;
      out.cost = run.length_m;
    }
  });
}

}  // namespace uavip::planners
