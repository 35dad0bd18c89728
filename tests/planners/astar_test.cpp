#include "planners/astar.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <random>

#include "planners/registry.h"
#include "uavip/core/error.h"

namespace uavip::planners {
namespace {

using world::GridOptions;
using world::Index3;
using world::VoxelGrid;

/// A grid of nx × ny × nz unit voxels (origin 0) with measured points at the
/// centres of `obstacles`; inflation radius 0 (the grid still blocks √3 voxels).
VoxelGrid unitGrid(int nx, int ny, int nz, const std::vector<Index3>& obstacles) {
  PointList cloud;
  for (const auto& o : obstacles) cloud.emplace_back(o.x + 0.5, o.y + 0.5, o.z + 0.5);
  GridOptions opt;
  opt.resolution_m = 1.0;
  opt.inflation_radius_m = 0.0;
  opt.padding_m = 0.0;
  const PointList corners = {Vec3(0.0, 0.0, 0.0), Vec3(nx - 0.01, ny - 0.01, nz - 0.01)};
  VoxelGrid g = VoxelGrid::build(cloud, corners, opt);
  EXPECT_EQ(g.dims()[0], nx);
  EXPECT_EQ(g.dims()[2], nz);
  return g;
}

/// Independent reference: Bellman-Ford style relaxation to a fixed point over all
/// free voxels with the 26 moves (no heuristic, no heap).
double referenceCost(const VoxelGrid& g, const Index3& s, const Index3& t, const AStarOptions& o) {
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> d(g.voxelCount(), inf);
  d[g.linear(s)] = 0.0;
  bool changed = true;
  while (changed) {
    changed = false;
    for (int z = 0; z < g.dims()[2]; ++z)
      for (int y = 0; y < g.dims()[1]; ++y)
        for (int x = 0; x < g.dims()[0]; ++x) {
          const Index3 c{x, y, z};
          if (g.isBlocked(c) || d[g.linear(c)] == inf) continue;
          for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
              for (int dx = -1; dx <= 1; ++dx) {
                if (!dx && !dy && !dz) continue;
                const Index3 n{x + dx, y + dy, z + dz};
                if (g.isBlocked(n)) continue;
                const double w =
                    o.cost == AStarCost::Paper
                        ? o.a1 * std::abs(dx) + o.a2 * std::abs(dy) + o.a3 * std::abs(dz)
                        : std::sqrt(o.a1 * dx * dx + o.a2 * dy * dy + o.a3 * dz * dz);
                const double nd = d[g.linear(c)] + w;
                if (nd < d[g.linear(n)] - 1e-12) {
                  d[g.linear(n)] = nd;
                  changed = true;
                }
              }
        }
  }
  return d[g.linear(t)];
}

/// Every free voxel of g, in z, y, x order.
std::vector<Index3> freeCells(const VoxelGrid& g) {
  std::vector<Index3> cells;
  for (int z = 0; z < g.dims()[2]; ++z)
    for (int y = 0; y < g.dims()[1]; ++y)
      for (int x = 0; x < g.dims()[0]; ++x)
        if (g.isFree(Index3{x, y, z})) cells.push_back({x, y, z});
  return cells;
}

void expectValidPath(const VoxelGrid& g, const GridSearchResult& r, const Index3& s,
                     const Index3& t, const AStarOptions& o) {
  ASSERT_FALSE(r.cells.empty());
  EXPECT_EQ(r.cells.front(), s);
  EXPECT_EQ(r.cells.back(), t);
  double cost = 0.0;
  for (std::size_t i = 0; i < r.cells.size(); ++i) {
    EXPECT_TRUE(g.isFree(r.cells[i]));
    if (i == 0) continue;
    const int dx = r.cells[i].x - r.cells[i - 1].x;
    const int dy = r.cells[i].y - r.cells[i - 1].y;
    const int dz = r.cells[i].z - r.cells[i - 1].z;
    EXPECT_LE(std::max({std::abs(dx), std::abs(dy), std::abs(dz)}), 1);
    EXPECT_FALSE(dx == 0 && dy == 0 && dz == 0);
    cost += stepCost(dx, dy, dz, o);
  }
  EXPECT_NEAR(cost, r.cost, 1e-9);
}

TEST(AStar, StepCostFollowsThePaper) {
  AStarOptions o;
  o.a1 = 2.0;
  o.a2 = 3.0;
  o.a3 = 5.0;
  EXPECT_DOUBLE_EQ(stepCost(1, 0, 0, o), 2.0);
  EXPECT_DOUBLE_EQ(stepCost(-1, 1, 0, o), 5.0);
  EXPECT_DOUBLE_EQ(stepCost(1, -1, -1, o), 10.0);
  o.cost = AStarCost::Euclidean;
  EXPECT_DOUBLE_EQ(stepCost(1, -1, -1, o), std::sqrt(10.0));
  EXPECT_DOUBLE_EQ(stepCost(0, 0, 1, o), std::sqrt(5.0));
}

TEST(AStar, OptimalAgainstExhaustiveSearchOnRandomGrids) {
  std::mt19937 rng(42);
  const std::vector<std::array<double, 3>> weights = {
      {1.0, 1.0, 1.0}, {1.0, 2.0, 3.0}, {2.5, 1.0, 0.7}};
  int compared = 0, unreachable = 0;
  for (int trial = 0; trial < 12; ++trial) {
    std::vector<Index3> obstacles;
    const int n_obs = 2 + static_cast<int>(rng() % 3);
    obstacles.reserve(static_cast<std::size_t>(n_obs));
    for (int k = 0; k < n_obs; ++k)
      obstacles.push_back(
          {static_cast<int>(rng() % 8), static_cast<int>(rng() % 8), static_cast<int>(rng() % 6)});
    const VoxelGrid g = unitGrid(8, 8, 6, obstacles);
    const std::vector<Index3> free_cells = freeCells(g);
    ASSERT_GE(free_cells.size(), 2u);
    for (int pair = 0; pair < 3; ++pair) {
      const Index3 s = free_cells[rng() % free_cells.size()];
      const Index3 t = free_cells[rng() % free_cells.size()];
      for (const auto& w : weights) {
        for (AStarCost mode : {AStarCost::Paper, AStarCost::Euclidean}) {
          AStarOptions o;
          o.cost = mode;
          o.a1 = w[0];
          o.a2 = w[1];
          o.a3 = w[2];
          const double ref = referenceCost(g, s, t, o);
          const GridSearchResult r = astarSearch(g, s, t, o);
          if (std::isinf(ref)) {
            EXPECT_FALSE(r.found);
            ++unreachable;
            continue;
          }
          ASSERT_TRUE(r.found);
          EXPECT_NEAR(r.cost, ref, 1e-9);
          expectValidPath(g, r, s, t, o);
          ++compared;
        }
      }
    }
  }
  EXPECT_GT(compared, 100);
  (void)unreachable;
}

// The search state is laid out in tiles of 8³ voxels: grids whose sides are no
// multiple of 8 (partial tiles on every axis), searched with the scratch kept and
// after it is freed (releaseSearchScratch), give the exhaustive optimum each time.
TEST(AStar, OptimalOnPartialTilesAndAfterTheScratchIsFreed) {
  std::mt19937 rng(7);
  const VoxelGrid g = unitGrid(11, 9, 13, {{5, 4, 6}, {5, 5, 6}, {2, 7, 3}, {9, 1, 10}});
  const std::vector<Index3> free_cells = freeCells(g);
  ASSERT_GE(free_cells.size(), 2u);
  AStarOptions o;
  o.cost = AStarCost::Euclidean;
  o.a2 = 1.5;
  for (int pair = 0; pair < 8; ++pair) {
    const Index3 s = free_cells[rng() % free_cells.size()];
    const Index3 t = free_cells[rng() % free_cells.size()];
    const double ref = referenceCost(g, s, t, o);
    ASSERT_TRUE(std::isfinite(ref));
    for (int round = 0; round < 2; ++round) {
      const GridSearchResult r = astarSearch(g, s, t, o);
      ASSERT_TRUE(r.found);
      EXPECT_NEAR(r.cost, ref, 1e-9);
      expectValidPath(g, r, s, t, o);
      if (round == 0) releaseSearchScratch();
    }
  }
}

TEST(AStar, PaperCostInFreeSpaceIsWeightedL1) {
  const VoxelGrid g = unitGrid(10, 9, 7, {});
  std::mt19937 rng(3);
  AStarOptions o;
  o.a1 = 1.5;
  o.a2 = 0.5;
  o.a3 = 4.0;
  for (int k = 0; k < 20; ++k) {
    const Index3 s{static_cast<int>(rng() % 10), static_cast<int>(rng() % 9),
                   static_cast<int>(rng() % 7)};
    const Index3 t{static_cast<int>(rng() % 10), static_cast<int>(rng() % 9),
                   static_cast<int>(rng() % 7)};
    const GridSearchResult r = astarSearch(g, s, t, o);
    ASSERT_TRUE(r.found);
    EXPECT_NEAR(r.cost,
                1.5 * std::abs(s.x - t.x) + 0.5 * std::abs(s.y - t.y) + 4.0 * std::abs(s.z - t.z),
                1e-12);
    expectValidPath(g, r, s, t, o);
  }
}

/// Closed form of the unit-weight Euclidean 26-neighbour distance: with sorted
/// |Δ| = a ≥ b ≥ c, c diagonal-3 moves, b − c diagonal-2 moves, a − b straight moves.
double octileDistance(const Index3& s, const Index3& t) {
  std::array<int, 3> d{{std::abs(s.x - t.x), std::abs(s.y - t.y), std::abs(s.z - t.z)}};
  std::sort(d.begin(), d.end());
  return d[0] * std::sqrt(3.0) + (d[1] - d[0]) * std::sqrt(2.0) + (d[2] - d[1]);
}

TEST(AStar, EuclideanCostInFreeSpaceMatchesClosedForm) {
  // The small grid uses the dense scratch, the large one (> 6 M voxels) the hash map.
  for (const auto& dims : {std::array<int, 3>{{12, 11, 9}}, std::array<int, 3>{{200, 200, 160}}}) {
    const VoxelGrid g = unitGrid(dims[0], dims[1], dims[2], {});
    AStarOptions o;
    o.cost = AStarCost::Euclidean;
    std::mt19937 rng(8);
    for (int k = 0; k < 6; ++k) {
      auto pick = [&](int n) {
        return static_cast<int>(rng() % static_cast<unsigned>(std::min(n, 12)));
      };
      const Index3 s{pick(dims[0]), pick(dims[1]), pick(dims[2])};
      const Index3 t{pick(dims[0]), pick(dims[1]), pick(dims[2])};
      const GridSearchResult r = astarSearch(g, s, t, o);
      ASSERT_TRUE(r.found);
      EXPECT_NEAR(r.cost, octileDistance(s, t), 1e-9);
      expectValidPath(g, r, s, t, o);
    }
  }
}

/// A grid of nx × ny × nz with a wall of points across x = wall_x (every y, z) but a
/// 5 × 5 square around (hole_y, hole_z) when hole_y ≥ 0, plus `extra` obstacles. The
/// grid blocks √3 voxels around a point, so the opening is about 3 voxels wide.
VoxelGrid walledGrid(int nx, int ny, int nz, int wall_x, int hole_y, int hole_z,
                     std::vector<Index3> extra) {
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      if (hole_y < 0 || std::abs(y - hole_y) > 2 || std::abs(z - hole_z) > 2)
        extra.push_back({wall_x, y, z});
  return unitGrid(nx, ny, nz, extra);
}

TEST(AStar, CoarseToFineFindsAPathExactlyWhenTheWholeGridHasOne) {
  // Against the exhaustive reference: found ⇔ a path exists; a valid path; its cost
  // never below the optimum, equal to it in free space. Grids with random clutter,
  // and walls whose only opening is narrower than a block (the levels fall back).
  std::mt19937 rng(7);
  int compared = 0, unreachable = 0, exact = 0;
  for (int trial = 0; trial < 16; ++trial) {
    std::vector<Index3> obstacles;
    const int n_obs = 3 + static_cast<int>(rng() % 10);
    obstacles.reserve(static_cast<std::size_t>(n_obs));
    for (int k = 0; k < n_obs; ++k)
      obstacles.push_back({static_cast<int>(rng() % 16), static_cast<int>(rng() % 12),
                           static_cast<int>(rng() % 8)});
    // Odd trials: a wall at x = 8 (with an opening on trials 1 mod 4, none on 3 mod 4).
    const VoxelGrid g = trial % 2 == 0 ? unitGrid(16, 12, 8, obstacles)
                                       : walledGrid(16, 12, 8, 8, trial % 4 == 1 ? 5 : -1,
                                                    trial % 4 == 1 ? 4 : -1, obstacles);
    const std::vector<Index3> free_cells = freeCells(g);
    ASSERT_GE(free_cells.size(), 2u);
    for (int pair = 0; pair < 3; ++pair) {
      const Index3 s = free_cells[rng() % free_cells.size()];
      const Index3 t = free_cells[rng() % free_cells.size()];
      for (const int factor : {2, 4}) {
        AStarOptions o;
        o.coarse_factor = factor;
        const double ref = referenceCost(g, s, t, o);
        const GridSearchResult r = astarSearch(g, s, t, o);
        if (std::isinf(ref)) {
          EXPECT_FALSE(r.found);
          ++unreachable;
          continue;
        }
        ASSERT_TRUE(r.found) << "trial " << trial << " factor " << factor;
        EXPECT_GE(r.cost, ref - 1e-9);
        expectValidPath(g, r, s, t, o);
        exact += std::abs(r.cost - ref) < 1e-9 ? 1 : 0;
        ++compared;
      }
    }
  }
  EXPECT_GT(compared, 40);
  EXPECT_GT(unreachable, 0);  // the closed walls
  EXPECT_GT(exact, compared / 2);
  // Free space: the corridor holds a monotone path, so the cost is the optimum.
  const VoxelGrid open = unitGrid(20, 14, 9, {});
  AStarOptions o;
  o.coarse_factor = 4;
  const GridSearchResult r = astarSearch(open, Index3{1, 2, 0}, Index3{18, 11, 8}, o);
  ASSERT_TRUE(r.found);
  EXPECT_DOUBLE_EQ(r.cost, referenceCost(open, Index3{1, 2, 0}, Index3{18, 11, 8}, o));
}

/// Coarse to fine (blocks of 4) from s to t, where the exhaustive reference `ref`
/// finds a path: the search finds one too, valid, costing no less than the optimum.
GridSearchResult expectCoarseToFinePath(const VoxelGrid& g, const Index3& s, const Index3& t,
                                        double& ref) {
  AStarOptions o;
  o.coarse_factor = 4;
  ref = referenceCost(g, s, t, o);
  EXPECT_FALSE(std::isinf(ref));
  GridSearchResult r = astarSearch(g, s, t, o);
  EXPECT_TRUE(r.found);
  if (r.found) expectValidPath(g, r, s, t, o);
  EXPECT_GE(r.cost, ref - 1e-9);
  return r;
}

TEST(AStar, CoarseToFineThroughANarrowOpening) {
  // The only way through the wall is an opening about 3 voxels wide, which no free
  // block of 4 passes: a finer level or the whole grid finds the way.
  const VoxelGrid g = walledGrid(16, 12, 8, 8, 5, 4, {});
  const Index3 s{1, 1, 1}, t{14, 10, 6};
  ASSERT_TRUE(g.isFree(s) && g.isFree(t));
  double ref = 0.0;
  const GridSearchResult r = expectCoarseToFinePath(g, s, t, ref);
  EXPECT_LE(r.cost, 1.25 * ref);
}

TEST(AStar, CoarseToFineThroughAOneVoxelHole) {
  // The wall's only opening leaves one free voxel once inflated (√3 voxels): no
  // block of 4 or 2 is free across it (the blocks that count as free when any voxel
  // is are made for this); the path found must pass through that voxel.
  std::vector<Index3> wall;
  for (int z = 0; z < 8; ++z)
    for (int y = 0; y < 12; ++y)
      if (std::abs(y - 5) > 1 || std::abs(z - 4) > 1) wall.push_back({8, y, z});
  const VoxelGrid g = unitGrid(16, 12, 8, wall);
  ASSERT_TRUE(g.isFree(Index3{8, 5, 4}));
  ASSERT_TRUE(g.isBlocked(Index3{8, 6, 4}) && g.isBlocked(Index3{8, 5, 5}));
  double ref = 0.0;
  const GridSearchResult r = expectCoarseToFinePath(g, Index3{1, 1, 1}, Index3{14, 10, 6}, ref);
  EXPECT_NE(std::find(r.cells.begin(), r.cells.end(), Index3{8, 5, 4}), r.cells.end());
}

TEST(AStar, WalledOffGoalHasNoPath) {
  // A closed shell of points on the surface of the cube [2, 6]^3 (voxel indices).
  std::vector<Index3> shell;
  for (int z = 2; z <= 6; ++z)
    for (int y = 2; y <= 6; ++y)
      for (int x = 2; x <= 6; ++x)
        if (x == 2 || x == 6 || y == 2 || y == 6 || z == 2 || z == 6) shell.push_back({x, y, z});
  const VoxelGrid g = unitGrid(9, 9, 9, shell);
  const Index3 inside{4, 4, 4};
  const Index3 outside{0, 0, 0};
  ASSERT_TRUE(g.isFree(inside));
  ASSERT_TRUE(g.isFree(outside));
  const GridSearchResult r = astarSearch(g, outside, inside, AStarOptions{});
  EXPECT_FALSE(r.found);
  EXPECT_FALSE(r.exhausted_budget);
  EXPECT_GT(r.expansions, 0u);
  // Coarse to fine knows from the grid's components that no path exists: no search.
  AStarOptions coarse;
  coarse.coarse_factor = 4;
  const GridSearchResult rc = astarSearch(g, outside, inside, coarse);
  EXPECT_FALSE(rc.found);
  EXPECT_FALSE(rc.exhausted_budget);
  EXPECT_EQ(rc.expansions, 0u);
  AStarPlanner planner(AStarOptions{});
  const auto pr = planner.plan(g, Vec3(0.5, 0.5, 0.5), Vec3(4.5, 4.5, 4.5));
  EXPECT_EQ(pr.status, planning::PathStatus::NoPath);
  EXPECT_TRUE(pr.path.empty());
}

TEST(AStar, BudgetGivesTimeout) {
  const VoxelGrid g = unitGrid(10, 10, 10, {});
  AStarOptions o;
  o.cost = AStarCost::Euclidean;
  o.max_expansions = 2;
  const GridSearchResult r = astarSearch(g, Index3{0, 0, 0}, Index3{9, 9, 9}, o);
  EXPECT_FALSE(r.found);
  EXPECT_TRUE(r.exhausted_budget);
  AStarPlanner planner(o);
  EXPECT_EQ(planner.plan(g, Vec3(0.5, 0.5, 0.5), Vec3(9.5, 9.5, 9.5)).status,
            planning::PathStatus::Timeout);
  // Coarse to fine: the budget counts every level's expansions, and a budget the
  // block search used up is not an unlimited one for the corridor.
  AStarOptions coarse;
  coarse.coarse_factor = 4;
  coarse.max_expansions = 2;
  const GridSearchResult rc = astarSearch(g, Index3{0, 0, 0}, Index3{9, 9, 9}, coarse);
  EXPECT_FALSE(rc.found);
  EXPECT_TRUE(rc.exhausted_budget);
  coarse.max_expansions = 0;
  EXPECT_TRUE(astarSearch(g, Index3{0, 0, 0}, Index3{9, 9, 9}, coarse).found);
}

TEST(AStar, PlannerEndsAndInvalidEnds) {
  const VoxelGrid g = unitGrid(10, 10, 6, {Index3{5, 5, 3}});
  AStarPlanner planner(AStarOptions{});
  EXPECT_EQ(planner.name(), "astar");
  EXPECT_EQ(planner.plan(g, Vec3(5.5, 5.5, 3.5), Vec3(0.5, 0.5, 0.5)).status,
            planning::PathStatus::InvalidStart);
  EXPECT_EQ(planner.plan(g, Vec3(0.5, 0.5, 0.5), Vec3(5.2, 5.9, 3.1)).status,
            planning::PathStatus::InvalidGoal);
  EXPECT_EQ(planner.plan(g, Vec3(-3.0, 0.5, 0.5), Vec3(0.5, 0.5, 0.5)).status,
            planning::PathStatus::InvalidStart);

  const Vec3 s(0.3, 0.6, 0.2), t(9.7, 9.1, 5.4);
  const auto r = planner.plan(g, s, t);
  ASSERT_TRUE(r.solved());
  ASSERT_GE(r.path.size(), 3u);
  EXPECT_EQ(r.path.front(), s);
  EXPECT_EQ(r.path.back(), t);
  for (std::size_t i = 1; i + 1 < r.path.size(); ++i) {
    // Interior points are voxel centres of free voxels.
    EXPECT_TRUE(g.isFree(r.path[i]));
    EXPECT_LT((r.path[i] - g.centreOf(g.indexOf(r.path[i]))).norm(), 1e-12);
  }
  // Deterministic.
  const auto again = planner.plan(g, s, t);
  EXPECT_EQ(again.path, r.path);

  const auto same = planner.plan(g, Vec3(0.2, 0.2, 0.2), Vec3(0.8, 0.7, 0.6));
  ASSERT_TRUE(same.solved());
  EXPECT_EQ(same.path, (PointList{Vec3(0.2, 0.2, 0.2), Vec3(0.8, 0.7, 0.6)}));
}

TEST(Registry, NamesAndUnknownName) {
  const auto names = plannerNames();
  ASSERT_GE(names.size(), 2u);
  EXPECT_EQ(names[0], "astar");
  EXPECT_EQ(names[1], "astar-euclid");
  PlannerSettings settings;
  settings.astar.a3 = 2.0;
  EXPECT_EQ(makePlanner("astar", settings)->name(), "astar");
  EXPECT_EQ(makePlanner("astar-euclid", settings)->name(), "astar-euclid");
  EXPECT_EQ(makePlanner("astar-coarse", settings)->name(), "astar-coarse");
  settings.astar.coarse_factor = 1;
  EXPECT_THROW(makePlanner("astar-coarse", settings), InputError);
  settings.astar.coarse_factor = 0;
  try {
    makePlanner("rrt", settings);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("rrt"), std::string::npos);
    EXPECT_NE(msg.find("astar-euclid"), std::string::npos);
  }
  settings.astar.a1 = -1.0;
  EXPECT_THROW(makePlanner("astar", settings), InputError);
}

}  // namespace
}  // namespace uavip::planners
