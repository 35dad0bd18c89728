#pragma once
/// \file
/// The one table of planners: registry name, OMPL class name and factory. The
/// registry's names, the harness's OMPL names, the OMPL factory, the bench and the
/// help text all read it; adding a planner is one row here. Private to planners/.

#include <ompl/base/Planner.h>
#include <ompl/base/SpaceInformation.h>

#include <string>
#include <vector>

namespace uavip::planners {

/// One planner.
struct PlannerInfo {
  std::string name;       ///< registry name, e.g. "rrtconnect" (config `planner`, --planner)
  std::string ompl_name;  ///< OMPL's class name, e.g. "RRTConnect" (the bench log's geometric_<ompl_name>)
  /// Builds the OMPL planner on `si`; empty for uavip's own A* (astar, astar-euclid),
  /// which the registry builds on the grid itself.
  ompl::base::PlannerPtr (*make)(const ompl::base::SpaceInformationPtr& si);
  bool isSampling() const { return make != nullptr; }
};

/// Every planner, in the order of the registry (the A*s first).
const std::vector<PlannerInfo>& plannerTable();

/// The row of `name`, or nullptr.
const PlannerInfo* findPlanner(const std::string& name);

}  // namespace uavip::planners
