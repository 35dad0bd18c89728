#include "uavip/planning/mission_planner.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "planners/registry.h"
#include "uavip/core/error.h"
#include "uavip/core/geometry.h"

namespace uavip::planning {
namespace {

constexpr double kRadius = 0.5;

/// A wall of points x = 0, y ∈ [0, 4], z ∈ [0, 3] (spacing 0.1 m).
PointList wall() {
  PointList cloud;
  for (double y = 0.0; y <= 4.0001; y += 0.1)
    for (double z = 0.0; z <= 3.0001; z += 0.1) cloud.emplace_back(0.0, y, z);
  return cloud;
}

/// Six stops 1.5 m in front of the wall, boustrophedon over 2 rows × 3 columns.
coverage::FlightStrategy strategyInFront(double x = 1.5) {
  coverage::FlightStrategy s;
  s.surface_id = 3;
  int index = 0;
  for (int row = 0; row < 2; ++row) {
    for (int k = 0; k < 3; ++k) {
      const int col = row % 2 == 0 ? k : 2 - k;
      coverage::Stop stop;
      stop.index = index++;
      stop.surface_id = 3;
      stop.row = row;
      stop.col = col;
      stop.target = Vec3(0.0, 1.0 + col, 1.0 + row);
      stop.position = Vec3(x, 1.0 + col, 1.0 + row);
      stop.yaw_deg = 180.0;
      s.stops.push_back(stop);
    }
  }
  return s;
}

world::VoxelGrid gridFor(const PointList& cloud, const coverage::FlightStrategy& s,
                         const PointList& more = {}) {
  PointList extra = more;
  for (const auto& stop : s.stops) extra.push_back(stop.position);
  world::GridOptions o;
  o.resolution_m = 0.2;
  o.inflation_radius_m = kRadius;
  o.padding_m = 2.0;
  return world::VoxelGrid::build(cloud, extra, o);
}

double bruteClearance(const PointList& cloud, const Vec3& a, const Vec3& b) {
  double d = std::numeric_limits<double>::infinity();
  for (const auto& p : cloud) d = std::min(d, pointSegmentDistance(p, a, b));
  return d;
}

void expectStopsInOrderAndSafe(const SurfaceMission& m, const PointList& cloud) {
  std::size_t pos = 0;
  for (const auto& stop : m.strategy.stops) {
    while (pos < m.waypoints.size() && m.waypoints[pos] != stop.position) ++pos;
    ASSERT_LT(pos, m.waypoints.size()) << "stop " << stop.index << " missing or out of order";
  }
  for (std::size_t i = 0; i + 1 < m.waypoints.size(); ++i) {
    EXPECT_GE(bruteClearance(cloud, m.waypoints[i], m.waypoints[i + 1]), kRadius)
        << "segment " << i;
  }
  for (std::size_t i = 0; i + 1 < m.raw_path.size(); ++i) {
    EXPECT_GE(bruteClearance(cloud, m.raw_path[i], m.raw_path[i + 1]), kRadius)
        << "raw segment " << i;
  }
}

TEST(MissionPlanner, PlansEveryStopInOrderWithClearance) {
  const PointList cloud = wall();
  const auto strategy = strategyInFront();
  const auto grid = gridFor(cloud, strategy);
  const PathValidator validator(cloud, kRadius);
  for (const std::string name : {"astar", "astar-euclid"}) {
    for (bool simplify : {true, false}) {
      auto planner = planners::makePlanner(name, planners::PlannerSettings{});
      MissionOptions options;
      options.simplify = simplify;
      const SurfaceMission m = planSurfaceMission(strategy, grid, validator, *planner, options);
      ASSERT_EQ(m.status, SurfaceStatus::Ok) << m.reason;
      EXPECT_TRUE(m.reason.empty());
      EXPECT_EQ(m.surface_id, 3);
      EXPECT_EQ(m.legs.size(), 5u);
      EXPECT_EQ(m.stop_problems, std::vector<StopProblem>(6, StopProblem::None));
      EXPECT_EQ(m.waypoints.front(), strategy.stops.front().position);
      EXPECT_EQ(m.waypoints.back(), strategy.stops.back().position);
      EXPECT_EQ(m.raw_waypoint_count, m.raw_path.size());
      EXPECT_NEAR(m.raw_length_m, polylineLength(m.raw_path), 1e-12);
      EXPECT_NEAR(m.path_length_m, polylineLength(m.waypoints), 1e-12);
      EXPECT_LE(m.path_length_m, m.raw_length_m + 1e-9);
      // Consecutive stops are 1 m apart: no path is shorter than that.
      EXPECT_GE(m.path_length_m, 5.0 - 1e-9);
      if (!simplify) {
        EXPECT_EQ(m.waypoints, m.raw_path);
      }
      EXPECT_TRUE(m.validation.collision_free);
      EXPECT_GE(m.validation.min_clearance_m, kRadius);
      expectStopsInOrderAndSafe(m, cloud);
    }
  }
}

TEST(MissionPlanner, StartBehindTheWallGoesAround) {
  const PointList cloud = wall();
  const auto strategy = strategyInFront();
  const Vec3 start(-1.5, 2.0, 1.5);
  const auto grid = gridFor(cloud, strategy, {start});
  const PathValidator validator(cloud, kRadius);
  auto planner = planners::makePlanner("astar", planners::PlannerSettings{});
  MissionOptions options;
  options.start = start;
  const SurfaceMission m = planSurfaceMission(strategy, grid, validator, *planner, options);
  ASSERT_EQ(m.status, SurfaceStatus::Ok) << m.reason;
  ASSERT_EQ(m.legs.size(), 6u);
  EXPECT_EQ(m.legs[0].from_stop, -1);
  EXPECT_EQ(m.legs[0].to_stop, 0);
  EXPECT_EQ(m.legs[5].from_stop, 4);
  EXPECT_EQ(m.waypoints.front(), start);
  // Around the wall: at least to its nearest edge (y = 0, z = 3 or y = 4) and back.
  EXPECT_GT(m.legs[0].length_m, 3.0);
  expectStopsInOrderAndSafe(m, cloud);
}

TEST(MissionPlanner, StopInsideInflationBlocksTheSurface) {
  const PointList cloud = wall();
  auto strategy = strategyInFront();
  strategy.stops[2].position.x() = 0.4;  // closer than r to the wall
  strategy.stops[4].gimbal_ok = false;
  const auto grid = gridFor(cloud, strategy);
  const PathValidator validator(cloud, kRadius);
  auto planner = planners::makePlanner("astar", planners::PlannerSettings{});
  const SurfaceMission m =
      planSurfaceMission(strategy, grid, validator, *planner, MissionOptions{});
  EXPECT_EQ(m.status, SurfaceStatus::Blocked);
  EXPECT_TRUE(m.waypoints.empty());
  EXPECT_TRUE(m.legs.empty());
  EXPECT_EQ(m.stop_problems[2], StopProblem::InObstacleSpace);
  EXPECT_EQ(m.stop_problems[4], StopProblem::GimbalLimit);
  EXPECT_EQ(m.stop_problems[0], StopProblem::None);
  EXPECT_NE(m.reason.find("2 of 6 stops"), std::string::npos) << m.reason;
  EXPECT_NE(m.reason.find("1 inside the inflated obstacle space"), std::string::npos) << m.reason;
  EXPECT_NE(m.reason.find("1 outside the gimbal"), std::string::npos) << m.reason;
  EXPECT_EQ(m.reason.find("does not fit"), std::string::npos)
      << m.reason;  // not mostly a tight space
  EXPECT_STREQ(toString(m.status), "blocked");
}

TEST(MissionPlanner, EnclosedStopIsUnreachable) {
  PointList cloud = wall();
  // A closed box of points around (7, 2, 1.5), half-size 1.5 m, spacing 0.1 m.
  const Vec3 c(7.0, 2.0, 1.5);
  for (double u = -1.5; u <= 1.5001; u += 0.1) {
    for (double v = -1.5; v <= 1.5001; v += 0.1) {
      for (double s : {-1.5, 1.5}) {
        cloud.push_back(c + Vec3(s, u, v));
        cloud.push_back(c + Vec3(u, s, v));
        cloud.push_back(c + Vec3(u, v, s));
      }
    }
  }
  auto strategy = strategyInFront();
  strategy.stops[3].position = c;
  const auto grid = gridFor(cloud, strategy);
  ASSERT_TRUE(grid.isFree(c));
  const PathValidator validator(cloud, kRadius);
  auto planner = planners::makePlanner("astar", planners::PlannerSettings{});
  // 1 of 6 stops (17 %) is within the default 25 %: skipped and reported.
  const SurfaceMission m =
      planSurfaceMission(strategy, grid, validator, *planner, MissionOptions{});
  EXPECT_EQ(m.status, SurfaceStatus::Partial);
  EXPECT_STREQ(toString(m.status), "partial");
  EXPECT_EQ(m.stop_problems[3], StopProblem::Unreachable);
  EXPECT_NE(m.reason.find("1 of 6 stops infeasible: 1 unreachable"), std::string::npos) << m.reason;
  EXPECT_TRUE(m.validation.collision_free);
  for (std::size_t i = 0; i < strategy.stops.size(); ++i) {
    const bool visited = std::find(m.waypoints.begin(), m.waypoints.end(),
                                   strategy.stops[i].position) != m.waypoints.end();
    EXPECT_EQ(visited, i != 3) << "stop " << i;
  }
  for (std::size_t i = 0; i + 1 < m.waypoints.size(); ++i) {
    EXPECT_GE(bruteClearance(cloud, m.waypoints[i], m.waypoints[i + 1]), kRadius);
  }
  // With no tolerance the same stop blocks the surface.
  MissionOptions strict;
  strict.max_skipped_fraction = 0.0;
  const SurfaceMission b = planSurfaceMission(strategy, grid, validator, *planner, strict);
  EXPECT_EQ(b.status, SurfaceStatus::Blocked);
  EXPECT_TRUE(b.waypoints.empty());
}

TEST(MissionPlanner, MostStopsInsideInflationSayWhatToChange) {
  const PointList cloud = wall();
  auto strategy = strategyInFront();
  for (const std::size_t i : {1u, 2u, 3u})
    strategy.stops[i].position.x() = 0.4;  // closer than r to the wall
  const auto grid = gridFor(cloud, strategy);
  const PathValidator validator(cloud, kRadius);
  auto planner = planners::makePlanner("astar", planners::PlannerSettings{});
  const SurfaceMission m =
      planSurfaceMission(strategy, grid, validator, *planner, MissionOptions{});
  ASSERT_EQ(m.status, SurfaceStatus::Blocked);
  EXPECT_NE(m.reason.find("3 inside the inflated obstacle space"), std::string::npos) << m.reason;
  EXPECT_NE(
      m.reason.find("does not fit at the standoff here: try a smaller uav.inflation_radius_m"),
      std::string::npos)
      << m.reason;
}

TEST(MissionPlanner, StartInObstacleSpaceThrowsAndNoStops) {
  const PointList cloud = wall();
  const auto strategy = strategyInFront();
  const auto grid = gridFor(cloud, strategy);
  const PathValidator validator(cloud, kRadius);
  auto planner = planners::makePlanner("astar", planners::PlannerSettings{});
  MissionOptions options;
  options.start = Vec3(0.2, 2.0, 1.5);
  try {
    planSurfaceMission(strategy, grid, validator, *planner, options);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("inside obstacle space"), std::string::npos) << e.what();
  }
  coverage::FlightStrategy empty;
  empty.surface_id = 9;
  const SurfaceMission m = planSurfaceMission(empty, grid, validator, *planner, MissionOptions{});
  EXPECT_EQ(m.status, SurfaceStatus::NoStops);
  EXPECT_FALSE(m.reason.empty());
  EXPECT_TRUE(m.waypoints.empty());
}

TEST(MissionPlanner, FailedLegOrValidationFailsTheSurface) {
  const PointList cloud = wall();
  const auto strategy = strategyInFront();
  const auto grid = gridFor(cloud, strategy);
  const PathValidator validator(cloud, kRadius);
  planners::PlannerSettings tight;
  tight.astar.max_expansions = 1;  // legs between stops 1 m apart need more
  auto starved = planners::makePlanner("astar", tight);
  const SurfaceMission m =
      planSurfaceMission(strategy, grid, validator, *starved, MissionOptions{});
  EXPECT_EQ(m.status, SurfaceStatus::Failed);
  EXPECT_NE(m.reason.find("leg 0"), std::string::npos) << m.reason;
  EXPECT_NE(m.reason.find("timeout"), std::string::npos) << m.reason;
  ASSERT_EQ(m.legs.size(), 1u);
  EXPECT_EQ(m.legs[0].status, PathStatus::Timeout);
  EXPECT_TRUE(m.waypoints.empty());

  // The validator is independent of the grid: ask for more clearance than the
  // grid's inflation gives (stops are 1.5 m from the wall).
  const PathValidator strict(cloud, 2.0);
  auto planner = planners::makePlanner("astar", planners::PlannerSettings{});
  const SurfaceMission v = planSurfaceMission(strategy, grid, strict, *planner, MissionOptions{});
  EXPECT_EQ(v.status, SurfaceStatus::Failed);
  EXPECT_FALSE(v.validation.collision_free);
  EXPECT_EQ(v.validation.first_violation_segment, 0);
  EXPECT_NEAR(v.validation.min_clearance_m, 1.5, 1e-9);
  EXPECT_NE(v.reason.find("validation failed"), std::string::npos) << v.reason;
}

TEST(MissionPlanner, OptionsBuiltInCodeAreValidatedToo) {
  // Options that never passed through a config file are checked by the planner.
  const PointList cloud = wall();
  const auto strategy = strategyInFront();
  const auto grid = gridFor(cloud, strategy);
  const PathValidator validator(cloud, kRadius);
  auto planner = planners::makePlanner("astar", planners::PlannerSettings{});
  MissionOptions bad;
  bad.max_skipped_fraction = 1.5;
  EXPECT_THROW(planSurfaceMission(strategy, grid, validator, *planner, bad), InputError);
  bad = MissionOptions{};
  bad.min_coverage = -0.1;
  EXPECT_THROW(bad.validate("mission"), InputError);
  bad = MissionOptions{};
  bad.start = Vec3(0.0, std::nan(""), 1.0);
  EXPECT_THROW(bad.validate("mission"), InputError);
  EXPECT_NO_THROW(MissionOptions{}.validate("mission"));
}

TEST(MissionPlanner, StatusNames) {
  EXPECT_STREQ(toString(SurfaceStatus::Ok), "ok");
  EXPECT_STREQ(toString(SurfaceStatus::NoStops), "no_stops");
  EXPECT_STREQ(toString(SurfaceStatus::Failed), "failed");
  EXPECT_STREQ(toString(PathStatus::NoPath), "no_path");
  EXPECT_STREQ(toString(StopProblem::Unreachable), "unreachable");
}

}  // namespace
}  // namespace uavip::planning
