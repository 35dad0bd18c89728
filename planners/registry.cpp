#include "planners/registry.h"

#include "planners/ompl_planners.h"

namespace uavip::planners {

std::unique_ptr<planning::Planner> makePlanner(const std::string& name,
                                               const PlannerSettings& settings) {
  settings.validate("planner");
  const planning::PlannerSpec& spec = planning::plannerSpec(name);
  if (!spec.gridSearch()) return std::make_unique<OmplPlanner>(spec.name, settings);
  return std::make_unique<AStarPlanner>(spec.astarOptions(settings), spec.name);
}

}  // namespace uavip::planners
