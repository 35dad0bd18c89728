#pragma once
/// \file
/// The paper's planner (§II-G): A* over the 26-neighbour voxel grid with the step
/// cost C(α,β,γ) = a1·α² + a2·β² + a3·γ², α,β,γ ∈ {−1,0,1}. Since α² = |α| the
/// cost of any path is at least a1|Δx| + a2|Δy| + a3|Δz| (in voxels), which every
/// monotone path attains: this weighted L1 distance is the exact heuristic in free
/// space. The Euclidean mode uses √(a1α² + a2β² + a3γ²) with the weighted Euclidean
/// distance as heuristic (admissible and consistent).
///
/// Coarse to fine (`coarse_factor` k ≥ 2, planner "astar-coarse"): the same search
/// first on a grid of k×k×k blocks, a block free when all its voxels are free (the
/// blocks of the two ends always), then on the fine grid inside a corridor: the
/// blocks of the coarse path and their 26 neighbours. A leg then costs what its
/// corridor holds, not what the grid holds; the path is the cheapest within the
/// corridor (not always the cheapest overall). When the blocks hold no path (only
/// passages narrower than a block) or the corridor holds no fine path, blocks of k/2,
/// … 2 are tried, then the same factors with a block free when any of its voxels is
/// (a passage one voxel wide), then the whole grid, so a path exists exactly when the
/// paper's A* finds one. Ends in different 26-connected components of the grid
/// (VoxelGrid::connected) have no path and cost no search.

#include <cstddef>
#include <string>
#include <vector>

#include "uavip/planning/planner.h"
#include "uavip/planning/planner_table.h"
#include "uavip/world/voxel_grid.h"

namespace uavip::planners {

/// Step cost model and options (plain data, planning/planner_table.h).
using planning::AStarCost;
using planning::AStarOptions;

/// Result of a grid search.
struct GridSearchResult {
  bool found{false};
  std::vector<world::Index3> cells;  ///< start … goal
  double cost{0.0};
  std::size_t expansions{0};
  bool exhausted_budget{false};
};

/// A* between two free voxels. Deterministic: ties on f are broken by larger g,
/// then by linear index. Returns found = false if either end is blocked.
GridSearchResult astarSearch(const world::VoxelGrid& grid, const world::Index3& start,
                             const world::Index3& goal, const AStarOptions& options);

/// Frees the dense search scratches kept for reuse (their pages: up to 12 B a voxel
/// of the grid each, one per thread that searched). For the end of a parallel phase,
/// so that the next phase's one thread does not keep the others' pages resident.
void releaseSearchScratch();

/// Step cost of a move (dx, dy, dz) ∈ {−1,0,1}³ under the options.
double stepCost(int dx, int dy, int dz, const AStarOptions& options);

/// planning::Planner adapter for the grid A* with the given options. makePlanner builds
/// the rows "astar" (paper cost), "astar-euclid" and "astar-coarse" (paper cost, coarse
/// to fine) with their row's options (planning::PlannerSpec::astarOptions) and name.
class AStarPlanner : public planning::Planner {
 public:
  /// `name`: the registry name it reports (its planner table row's).
  explicit AStarPlanner(AStarOptions options, std::string name = planning::kPaperPlanner);
  std::string name() const override { return name_; }
  /// The options it searches with.
  const AStarOptions& options() const { return options_; }
  planning::PathResult plan(const world::VoxelGrid& grid, const Vec3& start,
                            const Vec3& goal) override;

 private:
  AStarOptions options_;
  std::string name_;
};

}  // namespace uavip::planners
