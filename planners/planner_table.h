#pragma once
/// \file
/// The one table of planners: registry name and OMPL class name. The registry's
/// names, the harness's OMPL names, the bench and the help text all read it; it
/// includes no OMPL header, so reading a config links no planner. Adding a planner
/// is one row here and, for an OMPL planner, its factory in ompl_planners.cpp
/// (tests/planners checks that every sampling row builds). Private to planners/.

#include <string>
#include <vector>

namespace uavip::planners {

/// One planner.
struct PlannerInfo {
  std::string name;  ///< registry name, e.g. "rrtconnect" (config `planner`, --planner)
  std::string
      ompl_name;  ///< OMPL's class name, e.g. "RRTConnect" (the bench log's geometric_<ompl_name>)
  /// An OMPL sampling planner (built by ompl_planners.cpp from ompl_name); false for
  /// uavip's own A* (astar, astar-euclid), which the registry builds on the grid itself.
  bool sampling{false};
  bool isSampling() const { return sampling; }
};

/// Every planner, in the order of the registry (the A*s first).
const std::vector<PlannerInfo>& plannerTable();

/// The row of `name`, or nullptr.
const PlannerInfo* findPlanner(const std::string& name);

}  // namespace uavip::planners
