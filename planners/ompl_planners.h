#pragma once
/// \file
/// OMPL geometric planners on R³ (docs/ARCHITECTURE.md, planners/). The state space is
/// ompl::base::RealVectorStateSpace(3) bounded by the world::FreeSpace's box; a state
/// is valid iff FreeSpace::isFree(point) (on the grid, the same test as the paper's
/// A*, §II-G), and a motion is valid iff FreeSpace::segmentFree(a, b): on the grid the
/// exact voxel traversal, not OMPL's default discrete checker, so an OMPL path keeps
/// the grid's clearance guarantee (every segment crosses free voxels only, hence
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

#include <ompl/base/MotionValidator.h>
#include <ompl/base/Planner.h>
#include <ompl/base/SpaceInformation.h>
#include <ompl/geometric/PathGeometric.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "planners/astar.h"
#include "planners/harness.h"
#include "planners/registry.h"
#include "uavip/core/types.h"
#include "uavip/planning/planner.h"
#include "uavip/world/free_space.h"
#include "uavip/world/voxel_grid.h"

namespace uavip::planners {

/// Motion validity: a → b is valid iff FreeSpace::segmentFree(a, b). Keeps a
/// reference to the space, which must outlive it.
class FreeSpaceMotionValidator : public ompl::base::MotionValidator {
 public:
  FreeSpaceMotionValidator(const ompl::base::SpaceInformationPtr& si,
                           const world::FreeSpace& space);
  bool checkMotion(const ompl::base::State* s1, const ompl::base::State* s2) const override;
  /// Also reports the last valid state and its fraction of a → b (found along
  /// sub-segments no longer than a quarter of the space's resolution).
  bool checkMotion(const ompl::base::State* s1, const ompl::base::State* s2,
                   std::pair<ompl::base::State*, double>& last_valid) const override;

 private:
  const world::FreeSpace& space_;
};

/// R³ space over the space's box with FreeSpace::isFree as validity checker and
/// FreeSpaceMotionValidator, set up. The space must outlive the returned object.
ompl::base::SpaceInformationPtr makeSpaceInformation(const world::FreeSpace& space);

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
ompl::base::PlannerPtr makeOmplPlanner(const std::string& name,
                                       const ompl::base::SpaceInformationPtr& si,
                                       const world::VoxelGrid& grid,
                                       const PlannerSettings& settings);

/// PathSimplifier::reduceVertices then shortcutPath, repeated while the length drops
/// (at most 5 rounds; no B-spline smoothing), through the space's motion validator.
/// Returns the wall time [s].
double simplifyOmplPath(ompl::geometric::PathGeometric& path,
                        const ompl::base::SpaceInformationPtr& si);

/// Solves one query start → goal with an existing planner on `si`: a new problem
/// definition (path-length objective), budget settings.time_limit_s, simplified when
/// settings.simplify. The caller has checked both ends are free. runPlannerOnce is
/// this with a fresh space and planner. The graph is counted from OMPL's PlannerData
/// (as OMPL's benchmark does) with `planner_data`; without, a PRM roadmap is counted
/// directly (milestones, edges), which stays cheap when it grows over many legs.
HarnessRun solveQuery(const ompl::base::PlannerPtr& planner,
                      const ompl::base::SpaceInformationPtr& si, const Vec3& start,
                      const Vec3& goal, const PlannerSettings& settings, bool planner_data);

/// planning::Planner adapter for an OMPL sampling planner, as OMPL's own tools use
/// one: one SpaceInformation and one planner per grid (same address and
/// contentId), set up once; between legs the planner's clearQuery(), so the
/// multi-query planners (PRM*, LazyPRM*) keep their roadmap and grow it leg after
/// leg, and the others start afresh (their clearQuery is clear). Each leg gets
/// settings.time_limit_s, the path length as objective, and the simplification of
/// simplifyOmplPath when settings.simplify. A leg whose straight segment is free is
/// returned as that segment (every planner's optimum) without running OMPL. No exact
/// solution in the budget gives PathStatus::Timeout; it never throws for in-range
/// inputs.
class OmplPlanner : public planning::Planner {
 public:
  /// `name` must be one of omplPlannerNames(); throws InputError otherwise.
  OmplPlanner(std::string name, PlannerSettings settings);
  std::string name() const override { return name_; }
  planning::PathResult plan(const world::VoxelGrid& grid, const Vec3& start,
                            const Vec3& goal) override;

 private:
  /// Makes the space and the planner for `grid` unless they are for it already;
  /// true when it made them.
  bool bindTo(const world::VoxelGrid& grid);

  std::string name_;
  PlannerSettings settings_;
  const world::FreeSpace* space_{nullptr};  ///< the space si_ and planner_ were made for
  std::uint64_t space_id_{0};               ///< its contentId then
  ompl::base::SpaceInformationPtr si_;
  ompl::base::PlannerPtr planner_;
};

}  // namespace uavip::planners
