#include "planners/ompl_planners.h"

#include <gtest/gtest.h>
#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/ScopedState.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/geometric/PathGeometric.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <random>

#include "planners/astar_ompl.h"
#include "planners/harness.h"
#include "planners/registry.h"
#include "uavip/core/error.h"
#include "uavip/core/geometry.h"

namespace uavip::planners {
namespace {

using world::GridOptions;
using world::VoxelGrid;

constexpr double kRadius = 0.3;  // UAV inflation radius r of these worlds [m]

/// Points of the axis-aligned rectangle {x = x0} × [y0, y1] × [z0, z1], spaced `step`.
void addWallX(PointList& cloud, double x0, double y0, double y1, double z0, double z1,
              double step) {
  for (double y = y0; y <= y1 + 1e-9; y += step)
    for (double z = z0; z <= z1 + 1e-9; z += step) cloud.emplace_back(x0, y, z);
}

/// Points on the six faces of the box [lo, hi]³ (a sealed hollow box), spaced `step`.
PointList sealedBox(double lo, double hi, double step) {
  PointList cloud;
  for (double u = lo; u <= hi + 1e-9; u += step)
    for (double v = lo; v <= hi + 1e-9; v += step) {
      cloud.emplace_back(lo, u, v);
      cloud.emplace_back(hi, u, v);
      cloud.emplace_back(u, lo, v);
      cloud.emplace_back(u, hi, v);
      cloud.emplace_back(u, v, lo);
      cloud.emplace_back(u, v, hi);
    }
  return cloud;
}

GridOptions gridOptions() {
  GridOptions o;
  o.resolution_m = 0.2;
  o.inflation_radius_m = kRadius;
  o.padding_m = 1.0;
  return o;
}

/// A 2 m × 2 m wall at x = 3 between the start (1.5, 2, 1) and the goal (4.5, 2, 1).
struct WallWorld {
  PointList cloud;
  VoxelGrid grid;
  Vec3 start{1.5, 2.0, 1.0};
  Vec3 goal{4.5, 2.0, 1.0};
};

WallWorld wallWorld() {
  PointList cloud;
  addWallX(cloud, 3.0, 1.0, 3.0, 0.0, 2.0, 0.05);
  const PointList extra = {Vec3(0.0, 0.0, 0.0), Vec3(6.0, 4.0, 2.0)};
  VoxelGrid grid = VoxelGrid::build(cloud, extra, gridOptions());
  return {cloud, std::move(grid)};
}

/// wallWorld()'s wall widened to the whole grid, under a higher ceiling: the ways
/// around its sides, wallWorld()'s shortest, are closed; the way over it is open.
WallWorld wideWallWorld() {
  PointList cloud;
  addWallX(cloud, 3.0, -1.0, 5.0, 0.0, 2.0, 0.05);
  const PointList extra = {Vec3(0.0, 0.0, 0.0), Vec3(6.0, 4.0, 3.0)};
  VoxelGrid grid = VoxelGrid::build(cloud, extra, gridOptions());
  return {cloud, std::move(grid)};
}

/// Brute-force clearance of a polyline: the smallest distance from any segment to any
/// cloud point.
double bruteClearance(const PointList& path, const PointList& cloud) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i + 1 < path.size(); ++i)
    for (const Vec3& p : cloud)
      best = std::min(best, pointSegmentDistance(p, path[i], path[i + 1]));
  return best;
}

/// True if a→b lies on the raw polyline (pieces of raw steps that reduceVertices
/// merged, or that shortcutPath cut at interpolated states): every 1 cm sample of it
/// is within 1e-6 m of a raw segment.
bool onRawPath(const Vec3& a, const Vec3& b, const PointList* raw) {
  if (!raw) return false;
  const int n = std::max(1, static_cast<int>((b - a).norm() / 0.01));
  for (int k = 0; k <= n; ++k) {
    const Vec3 p = a + (b - a) * (static_cast<double>(k) / n);
    bool on = false;
    for (std::size_t i = 0; i + 1 < raw->size() && !on; ++i)
      on = pointSegmentDistance(p, (*raw)[i], (*raw)[i + 1]) < 1e-6;
    if (!on) return false;
  }
  return true;
}

void expectValidPath(const PointList& path, const WallWorld& w, const std::string& who,
                     const PointList* raw = nullptr) {
  ASSERT_GE(path.size(), 2u) << who;
  EXPECT_LT((path.front() - w.start).norm(), 1e-9) << who;
  EXPECT_LT((path.back() - w.goal).norm(), 1e-9) << who;
  // Every segment crosses free voxels only, or is a 26-neighbour step between free
  // voxels (the A*'s steps, which may touch a blocked voxel's edge; voxel_grid.h), or
  // lies on such steps of the raw path.
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    const world::Index3 a = w.grid.indexOf(path[i]);
    const world::Index3 b = w.grid.indexOf(path[i + 1]);
    const bool step = w.grid.isFree(a) && w.grid.isFree(b) && std::abs(a.x - b.x) <= 1 &&
                      std::abs(a.y - b.y) <= 1 && std::abs(a.z - b.z) <= 1;
    EXPECT_TRUE(step || w.grid.segmentFree(path[i], path[i + 1]) ||
                onRawPath(path[i], path[i + 1], raw))
        << who << " segment " << i << ": (" << path[i].transpose() << ") -> ("
        << path[i + 1].transpose() << ")";
  }
  EXPECT_GE(bruteClearance(path, w.cloud), kRadius) << who;
  // The wall is in the way: no path is shorter than the straight line, and a
  // valid one must be longer.
  EXPECT_GT(polylineLength(path), (w.goal - w.start).norm()) << who;
}

PlannerSettings fastSettings() {
  PlannerSettings s;
  s.time_limit_s = 0.25;
  return s;
}

TEST(OmplPlanners, RegistryHasEveryRequiredPlanner) {
  const auto names = plannerNames();
  for (const char* required :
       {"astar", "astar-euclid", "rrtconnect", "rrtstar", "informed-rrtstar", "bitstar", "abitstar",
        "aitstar", "prmstar", "lazyprmstar", "fmtstar"}) {
    EXPECT_NE(std::find(names.begin(), names.end(), required), names.end()) << required;
  }
  for (const auto& n : names) {
    EXPECT_EQ(makePlanner(n, fastSettings())->name(), n);
  }
}

TEST(OmplPlanners, OmplNamesMatchTheOmplPlannerObjects) {
  const WallWorld w = wallWorld();
  const auto si = makeSpaceInformation(w.grid);
  for (const auto& n : plannerNames()) {
    EXPECT_EQ(makeOmplPlanner(n, si, w.grid, fastSettings())->getName(), omplName(n)) << n;
  }
  EXPECT_THROW(omplName("rrt"), InputError);
}

TEST(OmplPlanners, BadSettingsAreRejected) {
  PlannerSettings s;
  s.time_limit_s = 0.0;
  EXPECT_THROW(makePlanner("rrtconnect", s), InputError);
  s.time_limit_s = std::nan("");
  EXPECT_THROW(makePlanner("bitstar", s), InputError);
}

TEST(OmplPlanners, SeedIsGlobalAndSetOnce) {
  EXPECT_TRUE(seedOmpl(PlannerSettings{}.seed));
  EXPECT_FALSE(seedOmpl(PlannerSettings{}.seed + 1));
}

TEST(OmplPlanners, EveryPlannerSolvesALegAroundAWall) {
  const WallWorld w = wallWorld();
  ASSERT_TRUE(w.grid.isFree(w.start));
  ASSERT_TRUE(w.grid.isFree(w.goal));
  ASSERT_FALSE(w.grid.segmentFree(w.start, w.goal));
  for (const auto& n : plannerNames()) {
    auto planner = makePlanner(n, fastSettings());
    const auto r = planner->plan(w.grid, w.start, w.goal);
    ASSERT_TRUE(r.solved()) << n << ": " << planning::toString(r.status);
    expectValidPath(r.path, w, n);
    // A sampling planner's graph size is not a count of expanded nodes.
    const bool grid_search = isDeterministic(n);
    EXPECT_EQ(r.graph_states > 0u, !grid_search) << n;
    EXPECT_EQ(r.expansions > 0u, grid_search) << n;
  }
}

TEST(OmplPlanners, OnePlannerPlansLegAfterLegAndStartsAfreshOnANewGrid) {
  for (const auto& n : omplPlannerNames()) {
    auto planner = makePlanner(n, fastSettings());
    std::optional<WallWorld> w;
    w.emplace(wallWorld());
    const VoxelGrid* address = &w->grid;
    const auto there = planner->plan(w->grid, w->start, w->goal);
    ASSERT_TRUE(there.solved()) << n;
    expectValidPath(there.path, *w, n + " leg 1");
    auto back = planner->plan(w->grid, w->goal, w->start);
    ASSERT_TRUE(back.solved()) << n;
    std::reverse(back.path.begin(), back.path.end());
    expectValidPath(back.path, *w, n + " leg 2");
    // PRM* keeps its roadmap between legs on one grid, and grows it.
    if (n == "prmstar") {
      EXPECT_GE(back.graph_states, there.graph_states);
    }

    // A new grid at the same address, closed where the first grid's shortest ways
    // went round the wall's sides: a kept roadmap would cross the new wall there.
    w.reset();
    w.emplace(wideWallWorld());
    ASSERT_EQ(&w->grid, address);
    ASSERT_TRUE(w->grid.isFree(w->start) && w->grid.isFree(w->goal));
    const auto over = planner->plan(w->grid, w->start, w->goal);
    ASSERT_TRUE(over.solved()) << n;
    expectValidPath(over.path, *w, n + " on the new grid");
  }
}

TEST(OmplPlanners, HarnessRunsAreValidAndSimplificationNeverLengthens) {
  const WallWorld w = wallWorld();
  for (const auto& n : plannerNames()) {
    const HarnessRun r = runPlannerOnce(n, w.grid, w.start, w.goal, fastSettings());
    ASSERT_TRUE(r.solved) << n << ": " << plannerStatusNames()[static_cast<std::size_t>(r.status)];
    EXPECT_EQ(plannerStatusNames()[static_cast<std::size_t>(r.status)], "Exact solution") << n;
    expectValidPath(r.raw_path, w, n + " raw");
    expectValidPath(r.path, w, n + " simplified", &r.raw_path);
    EXPECT_NEAR(r.raw_length_m, polylineLength(r.raw_path), 1e-9) << n;
    EXPECT_NEAR(r.length_m, polylineLength(r.path), 1e-9) << n;
    EXPECT_LE(r.length_m, r.raw_length_m + 1e-9) << n;
    EXPECT_GT(r.graph_states, 0u) << n;
  }
}

TEST(OmplPlanners, SealedBoxGivesAStatusForEveryPlanner) {
  const PointList cloud = sealedBox(0.0, 3.0, 0.1);
  const VoxelGrid grid = VoxelGrid::build(cloud, {}, gridOptions());
  const Vec3 outside(-0.8, 1.5, 1.5);
  const Vec3 inside(1.5, 1.5, 1.5);
  ASSERT_TRUE(grid.isFree(outside));
  ASSERT_TRUE(grid.isFree(inside));
  PlannerSettings s;
  s.time_limit_s = 0.2;
  for (const auto& n : plannerNames()) {
    const auto r = makePlanner(n, s)->plan(grid, outside, inside);
    EXPECT_FALSE(r.solved()) << n;
    const auto expected =
        isOmplPlanner(n) ? planning::PathStatus::Timeout : planning::PathStatus::NoPath;
    EXPECT_EQ(r.status, expected) << n << ": " << planning::toString(r.status);
    EXPECT_TRUE(r.path.empty()) << n;
  }
  // The same through the harness (OMPL statuses).
  const HarnessRun a = runPlannerOnce("astar", grid, outside, inside, s);
  EXPECT_EQ(plannerStatusNames()[static_cast<std::size_t>(a.status)], "Abort");
  EXPECT_EQ(a.path_status, planning::PathStatus::NoPath);
  const HarnessRun b = runPlannerOnce("rrtconnect", grid, outside, inside, s);
  EXPECT_FALSE(b.solved);
  EXPECT_EQ(b.path_status, planning::PathStatus::Timeout);
}

TEST(OmplPlanners, BlockedEndsGiveInvalidStatuses) {
  const WallWorld w = wallWorld();
  const Vec3 in_wall(3.0, 2.0, 1.0);
  ASSERT_FALSE(w.grid.isFree(in_wall));
  auto planner = makePlanner("rrtconnect", fastSettings());
  EXPECT_EQ(planner->plan(w.grid, in_wall, w.goal).status, planning::PathStatus::InvalidStart);
  EXPECT_EQ(planner->plan(w.grid, w.start, in_wall).status, planning::PathStatus::InvalidGoal);
  EXPECT_EQ(runPlannerOnce("bitstar", w.grid, w.start, in_wall, fastSettings()).path_status,
            planning::PathStatus::InvalidGoal);
}

TEST(OmplPlanners, AStarThroughOmplMatchesAStarSearch) {
  const WallWorld w = wallWorld();
  for (const AStarCost cost : {AStarCost::Paper, AStarCost::Euclidean}) {
    AStarOptions o;
    o.cost = cost;
    o.a3 = 2.0;
    const auto si = makeSpaceInformation(w.grid);
    auto pdef = std::make_shared<ompl::base::ProblemDefinition>(si);
    ompl::base::ScopedState<> s(si), g(si);
    for (unsigned int i = 0; i < 3; ++i) {
      s[i] = w.start[static_cast<int>(i)];
      g[i] = w.goal[static_cast<int>(i)];
    }
    pdef->setStartAndGoalStates(s, g);
    auto planner = std::make_shared<AStarOmplPlanner>(si, w.grid, o);
    planner->setProblemDefinition(pdef);
    planner->setup();
    ASSERT_EQ(planner->solve(1.0), ompl::base::PlannerStatus::EXACT_SOLUTION);
    const GridSearchResult ref =
        astarSearch(w.grid, w.grid.indexOf(w.start), w.grid.indexOf(w.goal), o);
    ASSERT_TRUE(ref.found);
    EXPECT_DOUBLE_EQ(planner->lastResult().cost, ref.cost);
    // The solution path is the grid path: exact ends, and one voxel centre per step.
    const PointList path = toPoints(*pdef->getSolutionPath()->as<ompl::geometric::PathGeometric>());
    EXPECT_EQ(path, AStarPlanner(o).plan(w.grid, w.start, w.goal).path);
    EXPECT_GE(path.size(), ref.cells.size());
    EXPECT_LE(path.size(), ref.cells.size() + 2);
  }
}

/// The paper's step cost (§II-G) of a grid path, summed over its voxel steps: an
/// independent recount of what the A* reports as its cost.
double paperCostOfSteps(const VoxelGrid& grid, const PointList& path, const AStarOptions& o) {
  double cost = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i) {
    const world::Index3 a = grid.indexOf(path[i - 1]);
    const world::Index3 b = grid.indexOf(path[i]);
    const int dx = b.x - a.x, dy = b.y - a.y, dz = b.z - a.z;
    EXPECT_LE(std::max({std::abs(dx), std::abs(dy), std::abs(dz)}), 1) << "not a voxel step";
    cost += o.a1 * dx * dx + o.a2 * dy * dy + o.a3 * dz * dz;
  }
  return cost;
}

TEST(OmplPlanners, HarnessAndRegistryBuildEveryRowAlike) {
  const WallWorld w = wallWorld();
  const auto si = makeSpaceInformation(w.grid);
  PlannerSettings s = fastSettings();
  s.astar.a3 = 2.0;
  s.simplify = false;
  for (const auto& n : plannerNames()) {
    SCOPED_TRACE(n);
    const auto mine = makePlanner(n, s);
    const auto bench = makeOmplPlanner(n, si, w.grid, s);
    EXPECT_EQ(mine->name(), n);
    EXPECT_EQ(bench->getName(), omplName(n));
    const auto* grid_a = dynamic_cast<const AStarPlanner*>(mine.get());
    const auto* bench_a = dynamic_cast<const AStarOmplPlanner*>(bench.get());
    ASSERT_EQ(grid_a != nullptr, isDeterministic(n));
    ASSERT_EQ(bench_a != nullptr, isDeterministic(n));
    if (grid_a == nullptr) continue;
    const AStarOptions& a = grid_a->options();
    const AStarOptions& b = bench_a->options();
    EXPECT_EQ(a.cost, b.cost);
    EXPECT_EQ(a.coarse_factor, b.coarse_factor);
    EXPECT_EQ(a.max_expansions, b.max_expansions);
    EXPECT_EQ(Vec3(a.a1, a.a2, a.a3), Vec3(b.a1, b.a2, b.a3));
    // The same leg through both: the same path at the same cost.
    const planning::PathResult flown = mine->plan(w.grid, w.start, w.goal);
    const HarnessRun run = solveQuery(bench, si, w.start, w.goal, s, true);
    ASSERT_TRUE(flown.solved());
    ASSERT_TRUE(run.solved);
    EXPECT_EQ(run.raw_path, flown.path);
    EXPECT_DOUBLE_EQ(bench_a->lastResult().cost, flown.cost);
  }
  // The default planner is the paper's cost on blocks of 4 voxels (README, planner.name),
  // in the benchmark too; its reported cost is the paper's cost of its voxel steps.
  const auto coarse = makeOmplPlanner("astar-coarse", si, w.grid, s);
  const auto& options = dynamic_cast<const AStarOmplPlanner&>(*coarse).options();
  EXPECT_EQ(options.cost, AStarCost::Paper);
  EXPECT_EQ(options.coarse_factor, 4);
  const HarnessRun run = solveQuery(coarse, si, w.start, w.goal, s, true);
  ASSERT_TRUE(run.solved);
  const double cost = dynamic_cast<const AStarOmplPlanner&>(*coarse).lastResult().cost;
  EXPECT_NEAR(paperCostOfSteps(w.grid, run.raw_path, options), cost, 1e-9);
  AStarOptions whole = options;
  whole.coarse_factor = 0;
  const GridSearchResult best =
      astarSearch(w.grid, w.grid.indexOf(w.start), w.grid.indexOf(w.goal), whole);
  ASSERT_TRUE(best.found);
  EXPECT_GE(cost, best.cost - 1e-9);  // the corridor's path is never cheaper than the optimum
}

TEST(OmplPlanners, MotionValidatorKeepsClearanceAndFindsLastValidState) {
  const WallWorld w = wallWorld();
  const auto si = makeSpaceInformation(w.grid);
  const auto mv = si->getMotionValidator();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> ux(0.0, 6.0), uy(0.0, 4.0), uz(0.0, 2.0);
  ompl::base::ScopedState<> a(si), b(si), last(si);
  int valid = 0, invalid = 0;
  for (int k = 0; k < 300; ++k) {
    const Vec3 p(ux(rng), uy(rng), uz(rng));
    const Vec3 q(ux(rng), uy(rng), uz(rng));
    if (!w.grid.isFree(p)) continue;
    for (unsigned int i = 0; i < 3; ++i) {
      a[i] = p[static_cast<int>(i)];
      b[i] = q[static_cast<int>(i)];
    }
    std::pair<ompl::base::State*, double> lv{last.get(), -1.0};
    const bool ok = mv->checkMotion(a.get(), b.get());
    EXPECT_EQ(ok, mv->checkMotion(a.get(), b.get(), lv));
    if (ok) {
      ++valid;
      EXPECT_GE(bruteClearance({p, q}, w.cloud), kRadius);
    } else {
      ++invalid;
      ASSERT_GE(lv.second, 0.0);
      ASSERT_LT(lv.second, 1.0);
      const Vec3 l = toVec3(last.get());
      EXPECT_LT((l - (p + lv.second * (q - p))).norm(), 1e-9);
      EXPECT_GE(bruteClearance({p, l}, w.cloud), kRadius);
      // A quarter voxel further the motion is no longer valid.
      const Vec3 beyond =
          p + std::min(1.0, lv.second + 0.25 * 0.2 / (q - p).norm() + 1e-9) * (q - p);
      EXPECT_FALSE(w.grid.segmentFree(p, beyond));
    }
  }
  EXPECT_GT(valid, 10);
  EXPECT_GT(invalid, 10);
}

}  // namespace
}  // namespace uavip::planners
