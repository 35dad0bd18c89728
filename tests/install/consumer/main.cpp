// Plans around a scanned wall with the installed uavip: the grid of stage 7, the paper's
// A* from the planner registry, then checks the path with the core geometry. Exit 0 when
// every check holds.
#include <algorithm>
#include <cstdio>
#include <limits>

#include "planners/registry.h"
#include "uavip/core/geometry.h"
#include "uavip/planning/planner.h"
#include "uavip/world/voxel_grid.h"

namespace {

int failures = 0;

void check(bool ok, const char* what) {
  if (!ok) {
    std::fprintf(stderr, "uavip_consumer: FAILED: %s\n", what);
    ++failures;
  }
}

}  // namespace

int main() {
  using uavip::Vec3;
  // A 4 x 4 m wall in the plane x = 5, points every 0.1 m.
  uavip::PointList wall;
  for (int j = 0; j <= 40; ++j) {
    for (int k = 0; k <= 40; ++k) wall.emplace_back(5.0, 0.1 * j, 0.1 * k);
  }
  uavip::world::GridOptions options;
  options.resolution_m = 0.2;
  options.inflation_radius_m = 0.6;
  options.padding_m = 2.5;
  const uavip::world::VoxelGrid grid = uavip::world::VoxelGrid::build(wall, {}, options);

  const auto names = uavip::planners::plannerNames();
  check(std::find(names.begin(), names.end(), "astar") != names.end(),
        "\"astar\" is a registered planner");

  const Vec3 start(3.5, 2.0, 2.0), goal(6.5, 2.0, 2.0);  // either side of the wall
  auto planner = uavip::planners::makePlanner("astar", uavip::planners::PlannerSettings{});
  const uavip::planning::PathResult result = planner->plan(grid, start, goal);
  check(result.solved(), "A* finds a path around the wall");
  if (!result.solved()) return 1;

  double clearance = std::numeric_limits<double>::infinity();
  for (std::size_t i = 1; i < result.path.size(); ++i) {
    check(grid.isFree(result.path[i]), "every path point lies in a free voxel");
    for (const Vec3& p : wall) {
      clearance =
          std::min(clearance, uavip::pointSegmentDistance(p, result.path[i - 1], result.path[i]));
    }
  }
  const double length = uavip::polylineLength(result.path);
  check(result.path.front().isApprox(start) && result.path.back().isApprox(goal),
        "the path joins start and goal");
  check(clearance >= options.inflation_radius_m,
        "the path keeps the inflation radius from every wall point");
  check(length > 3.0 + 2.0, "the path goes around the wall, not through it");
  std::printf(
      "uavip_consumer: %s path of %zu points, %.2f m, clearance %.2f m on a %d x %d x %d grid: "
      "%s\n",
      planner->name().c_str(), result.path.size(), length, clearance, grid.dims()[0],
      grid.dims()[1], grid.dims()[2], failures == 0 ? "ok" : "FAILED");
  return failures == 0 ? 0 : 1;
}
