#include "planners/planner_table.h"

#include <ompl/geometric/planners/fmt/FMT.h>
#include <ompl/geometric/planners/informedtrees/ABITstar.h>
#include <ompl/geometric/planners/informedtrees/AITstar.h>
#include <ompl/geometric/planners/informedtrees/BITstar.h>
#include <ompl/geometric/planners/prm/LazyPRMstar.h>
#include <ompl/geometric/planners/prm/PRMstar.h>
#include <ompl/geometric/planners/rrt/InformedRRTstar.h>
#include <ompl/geometric/planners/rrt/RRTConnect.h>
#include <ompl/geometric/planners/rrt/RRTstar.h>

#include <memory>

namespace uavip::planners {
namespace {

namespace ob = ompl::base;
namespace og = ompl::geometric;

template <class P>
ob::PlannerPtr make(const ob::SpaceInformationPtr& si) {
  return std::make_shared<P>(si);
}

}  // namespace

const std::vector<PlannerInfo>& plannerTable() {
  static const std::vector<PlannerInfo> table{
      {"astar", "AStar", nullptr},
      {"astar-euclid", "AStarEuclid", nullptr},
      {"rrtconnect", "RRTConnect", &make<og::RRTConnect>},
      {"rrtstar", "RRTstar", &make<og::RRTstar>},
      {"informed-rrtstar", "InformedRRTstar", &make<og::InformedRRTstar>},
      {"bitstar", "BITstar", &make<og::BITstar>},
      {"abitstar", "ABITstar", &make<og::ABITstar>},
      {"aitstar", "AITstar", &make<og::AITstar>},
      {"prmstar", "PRMstar", &make<og::PRMstar>},
      {"lazyprmstar", "LazyPRMstar", &make<og::LazyPRMstar>},
      {"fmtstar", "FMT", &make<og::FMT>},
  };
  return table;
}

const PlannerInfo* findPlanner(const std::string& name) {
  for (const auto& p : plannerTable()) {
    if (p.name == name) return &p;
  }
  return nullptr;
}

}  // namespace uavip::planners
