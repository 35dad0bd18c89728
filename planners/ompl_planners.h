#pragma once
/// \file
/// OMPL geometric planners on R³ over the planning grid (ARCHITECTURE.md, planners/;
/// issue 4). The state space is ompl::base::RealVectorStateSpace(3) bounded by the
/// VoxelGrid's box; a state is valid iff VoxelGrid::isFree(point) (the same test as
/// the paper's A*, §II-G), and a motion is valid iff VoxelGrid::segmentFree(a, b):
/// the exact voxel traversal, not OMPL's default discrete checker, so an OMPL path
/// keeps the grid's clearance guarantee (every segment crosses free voxels only, hence
/// stays ≥ r from every measured point; voxel_grid.h).
///
/// This header includes OMPL; link uavip_ompl to use it. Code that must not see OMPL
/// uses planners/registry.h (makePlanner) and planners/harness.h instead.
///
/// Randomness: OMPL draws every planner's seed from one global generator. seedOmpl()
/// (harness.h)
/// calls ompl::RNG::setSeed once per process, before the first planner is created,
/// with the first seed it is given; later calls with another seed have no effect (OMPL
/// cannot re-seed once sampling has started). Runs are reproducible only as far as a
/// time budget allows: an anytime planner's number of iterations depends on speed.

#include "planners/astar.h"
#include "planners/harness.h"
#include "planners/registry.h"
#include "uavip/core/types.h"
#include "uavip/planning/planner.h"
#include "uavip/world/voxel_grid.h"

#include <ompl/base/MotionValidator.h>
#include <ompl/base/Planner.h>
#include <ompl/base/SpaceInformation.h>
#include <ompl/geometric/PathGeometric.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace uavip::planners {

/// Motion validity on the grid: a → b is valid iff VoxelGrid::segmentFree(a, b).
/// Keeps a reference to the grid, which must outlive it.
class GridMotionValidator : public ompl::base::MotionValidator {
 public:
  GridMotionValidator(const ompl::base::SpaceInformationPtr& si, const world::VoxelGrid& grid);
  bool checkMotion(const ompl::base::State* s1, const ompl::base::State* s2) const override;
  /// Also reports the last valid state and its fraction of a → b (found along
  /// sub-segments no longer than a quarter voxel).
  bool checkMotion(const ompl::base::State* s1, const ompl::base::State* s2,
                   std::pair<ompl::base::State*, double>& last_valid) const override;

 private:
  const world::VoxelGrid& grid_;
};

/// R³ space over the grid's box with the grid validity checker and GridMotionValidator,
/// set up. The grid must outlive the returned object.
ompl::base::SpaceInformationPtr makeGridSpace(const world::VoxelGrid& grid);

/// Point of an R³ state [m].
Vec3 toVec3(const ompl::base::State* state);
/// Polyline of a geometric path [m].
PointList toPoints(const ompl::geometric::PathGeometric& path);

/// Registry names of the OMPL sampling planners (astar and astar-euclid excluded).
std::vector<std::string> omplPlannerNames();
/// True for a name of omplPlannerNames().
bool isOmplPlanner(const std::string& name);

/// The ompl::base::Planner for any registry name, the grid A* (AStarOmplPlanner) too.
/// Seeds OMPL first (seedOmpl(settings.seed)). Throws InputError for an unknown name.
ompl::base::PlannerPtr makeOmplPlanner(const std::string& name, const ompl::base::SpaceInformationPtr& si,
                                       const world::VoxelGrid& grid, const PlannerSettings& settings);

/// PathSimplifier::reduceVertices then shortcutPath, repeated while the length drops
/// (at most 5 rounds; no B-spline smoothing), through the space's motion validator.
/// Returns the wall time [s].
double simplifyOmplPath(ompl::geometric::PathGeometric& path, const ompl::base::SpaceInformationPtr& si);

/// planning::Planner adapter for an OMPL sampling planner: a fresh OMPL planner per
/// leg with settings.time_limit_s as budget, the path length as objective, and the
/// simplification of simplifyOmplPath when settings.simplify. A leg whose straight
/// segment is free is returned as that segment (every planner's optimum) without
/// running OMPL. No exact solution in the budget gives PathStatus::Timeout; it never
/// throws for in-range inputs.
class OmplPlanner : public planning::Planner {
 public:
  /// `name` must be one of omplPlannerNames(); throws InputError otherwise.
  OmplPlanner(std::string name, PlannerSettings settings);
  std::string name() const override { return name_; }
  planning::PathResult plan(const world::VoxelGrid& grid, const Vec3& start, const Vec3& goal) override;

 private:
  std::string name_;
  PlannerSettings settings_;
};

}  // namespace uavip::planners
