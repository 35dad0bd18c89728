#include "uavip/planning/mission_planner.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

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
  // A gimbal that looks 80-90° up: no pose within 75° of the wall's normal reaches it.
  MissionOptions options;
  options.gimbal = {80.0, 90.0};
  const SurfaceMission m = planSurfaceMission(strategy, grid, validator, *planner, options);
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

/// A horizontal slab of points z = `z`, x, y ∈ [0, 3] (spacing 0.1 m).
PointList slab(double z) {
  PointList cloud;
  for (double x = 0.0; x <= 3.0001; x += 0.1)
    for (double y = 0.0; y <= 3.0001; y += 0.1) cloud.emplace_back(x, y, z);
  return cloud;
}

/// Four stops 1.5 m below the slab's underside, looking straight up (as the flight
/// strategy places them: pitch +90, beyond a gimbal that stops at `max_pitch`).
coverage::FlightStrategy strategyBelow(double z, double max_pitch) {
  coverage::FlightStrategy s;
  s.surface_id = 5;
  s.camera.standoff_m = 1.5;
  s.axis_w = Vec3::UnitX();
  s.axis_h = Vec3::UnitY();
  for (int k = 0; k < 4; ++k) {
    coverage::Stop stop;
    stop.index = k;
    stop.surface_id = 5;
    stop.col = k;
    stop.target = Vec3(0.9 + 0.4 * k, 1.5, z);
    stop.position = stop.target - 1.5 * Vec3::UnitZ();
    stop.gimbal_pitch_deg = 90.0;
    stop.gimbal_ok = 90.0 <= max_pitch;
    s.stops.push_back(stop);
  }
  return s;
}

/// Brute force over a regular lattice of positions (5 cm) around `target`: a pose
/// 1–1.25 × the standoff from it, within 75° of `normal`, free in the grid, in the
/// gimbal's pitch range and with no measured point within 0.15 m of its line of sight
/// (up to 0.4 m before the target). True when one exists.
bool brutePoseExists(const Vec3& target, const Vec3& normal, double standoff,
                     const coverage::GimbalLimits& gimbal, const world::VoxelGrid& grid,
                     const PointList& cloud) {
  const double r = 1.25 * standoff;
  for (double dx = -r; dx <= r; dx += 0.05)
    for (double dy = -r; dy <= r; dy += 0.05)
      for (double dz = -r; dz <= r; dz += 0.05) {
        const Vec3 d(dx, dy, dz);
        const double dist = d.norm();
        if (dist < standoff || dist > r || d.dot(normal) < dist * std::cos(75.0 * kPi / 180.0))
          continue;
        const Vec3 p = target + d;
        const double pitch = std::atan2(-d.z(), d.head<2>().norm()) * 180.0 / kPi;
        if (pitch < gimbal.pitch_min_deg || pitch > gimbal.pitch_max_deg || !grid.isFree(p))
          continue;
        const Vec3 end = target + d * (0.4 / dist);
        const bool seen = std::none_of(cloud.begin(), cloud.end(), [&](const Vec3& q) {
          return pointSegmentDistance(q, p, end) < 0.15;
        });
        if (seen) return true;
      }
  return false;
}

TEST(MissionPlanner, AStopBeyondTheGimbalIsTakenFromAPoseItReaches) {
  const PointList cloud = slab(4.0);
  const auto strategy = strategyBelow(4.0, 35.0);
  const auto grid = gridFor(cloud, strategy);
  const PathValidator validator(cloud, kRadius);
  auto planner = planners::makePlanner("astar", planners::PlannerSettings{});
  MissionOptions options;
  options.gimbal = {-90.0, 35.0};  // the Mavic 3 Enterprise's camera
  const SurfaceMission m = planSurfaceMission(strategy, grid, validator, *planner, options);
  ASSERT_EQ(m.status, SurfaceStatus::Ok) << m.reason;
  EXPECT_EQ(m.gimbal_moved_stops.size(), 4u);
  for (const auto& stop : m.strategy.stops) {
    EXPECT_LE(stop.gimbal_pitch_deg, 35.0 + 1e-6);
    const Vec3 d = stop.position - stop.target;
    EXPECT_GE(d.norm(), 1.5 - 1e-9);
    EXPECT_LE(d.norm(), 1.25 * 1.5 + 1e-9);
    // The camera looks at the target: pitch and yaw recomputed here from the pose.
    const Vec3 look = stop.target - stop.position;
    EXPECT_NEAR(stop.gimbal_pitch_deg, std::atan2(look.z(), look.head<2>().norm()) * 180.0 / kPi,
                1e-9);
    EXPECT_NEAR(std::remainder(stop.yaw_deg - std::atan2(look.y(), look.x()) * 180.0 / kPi, 360.0),
                0.0, 1e-9);
    // Within 75° of the underside's normal (−z).
    EXPECT_GE(-d.z(), d.norm() * std::cos(75.0 * kPi / 180.0));
  }
  EXPECT_TRUE(m.validation.collision_free);
  expectStopsInOrderAndSafe(m, cloud);
}

TEST(MissionPlanner, AStopIsDroppedForTheGimbalOnlyWhenBruteForceFindsNoPose) {
  // A gimbal that looks 80-90° down cannot see an underside: every pose within 75° of
  // its normal lies below it.
  const PointList cloud = slab(4.0);
  const auto strategy = strategyBelow(4.0, -80.0);
  const auto grid = gridFor(cloud, strategy);
  const PathValidator validator(cloud, kRadius);
  auto planner = planners::makePlanner("astar", planners::PlannerSettings{});
  MissionOptions options;
  options.gimbal = {-90.0, -80.0};
  const SurfaceMission m = planSurfaceMission(strategy, grid, validator, *planner, options);
  for (std::size_t i = 0; i < strategy.stops.size(); ++i) {
    const auto& s = strategy.stops[i];
    EXPECT_FALSE(brutePoseExists(s.target, -Vec3::UnitZ(), 1.5, options.gimbal, grid, cloud));
    EXPECT_EQ(m.stop_problems[i], StopProblem::GimbalLimit);
  }
  EXPECT_TRUE(m.gimbal_moved_stops.empty());
  // With the Mavic's limits the same brute force finds a pose for each, and so does
  // the planner (previous test).
  const coverage::GimbalLimits m3e{-90.0, 35.0};
  for (const auto& s : strategy.stops)
    EXPECT_TRUE(brutePoseExists(s.target, -Vec3::UnitZ(), 1.5, m3e, grid, cloud));
}

/// Whether a pose square to the wall (normal +x) at `standoff` from a target slid by at
/// most (`slide_w`, `slide_h`) along (y, z) is free: brute force on a 1 cm lattice.
bool bruteSquarePoseExists(const Vec3& target, double standoff, double slide_w, double slide_h,
                           const world::VoxelGrid& grid) {
  for (double dw = -slide_w; dw <= slide_w + 1e-9; dw += 0.01)
    for (double dh = -slide_h; dh <= slide_h + 1e-9; dh += 0.01)
      if (grid.isFree(target + Vec3(standoff, dw, dh))) return true;
  return false;
}

/// Whether a pose at `standoff` from `target` within `max_deg` of the normal +x is free:
/// brute force over 1° of tilt and 5° of direction.
bool bruteTiltedPoseExists(const Vec3& target, double standoff, double max_deg,
                           const world::VoxelGrid& grid) {
  for (double t = 1.0; t <= max_deg + 1e-9; t += 1.0)
    for (double phi = 0.0; phi < 360.0; phi += 5.0) {
      const double a = t * kPi / 180.0, b = phi * kPi / 180.0;
      const Vec3 d(std::cos(a), std::sin(a) * std::cos(b), std::sin(a) * std::sin(b));
      if (grid.isFree(target + standoff * d)) return true;
    }
  return false;
}

/// A mosaic's row in front of the wall x = 0: stops 1.5 m out at z = 1.5 and the given y,
/// footprint 0.6 × 0.4 m at overlaps 0.6 / 0.3 (spacing 0.24 / 0.28 m), image width along y.
coverage::FlightStrategy mosaicRow(const std::vector<double>& ys) {
  coverage::FlightStrategy strategy;
  strategy.surface_id = 3;
  strategy.camera = {0.6, 0.4, 1.5, 0.0, 0.0};
  strategy.spacing_w_m = 0.24;
  strategy.spacing_h_m = 0.28;
  strategy.axis_w = Vec3::UnitY();
  strategy.axis_h = Vec3::UnitZ();
  for (std::size_t k = 0; k < ys.size(); ++k) {
    coverage::Stop stop;
    stop.index = static_cast<int>(k);
    stop.surface_id = 3;
    stop.col = static_cast<int>(k);
    stop.target = Vec3(0.0, ys[k], 1.5);
    stop.position = stop.target + Vec3(1.5, 0.0, 0.0);
    stop.yaw_deg = 180.0;
    strategy.stops.push_back(stop);
  }
  return strategy;
}

TEST(MissionPlanner, AMosaicStopIsMovedSquareWithinTheOverlap) {
  // A 6 m wall (x = 0), three stops 1.5 m in front at y = 1, 3, 5 (z = 1.5), a mosaic's
  // footprint 0.6 × 0.4 m at overlaps 0.6 / 0.3: slides of up to 0.18 m along y and
  // 0.06 m along z keep half the overlap. One measured point blocks each stop: beside
  // stop 0 (a slide frees it), above stop 1 (only a tilt down frees it), right in front
  // of stop 2 (nothing within 15° does). The stops are 2 m apart: none covers another.
  PointList cloud;
  for (double y = 0.0; y <= 6.0001; y += 0.1)
    for (double z = 0.0; z <= 3.0001; z += 0.1) cloud.emplace_back(0.0, y, z);
  const PointList obstacles = {Vec3(1.5, 1.9, 1.5), Vec3(1.5, 3.0, 2.1), Vec3(1.0, 5.0, 1.5)};
  cloud.insert(cloud.end(), obstacles.begin(), obstacles.end());
  const auto strategy = mosaicRow({1.0, 3.0, 5.0});
  const auto grid = gridFor(cloud, strategy);
  const PathValidator validator(cloud, kRadius);
  auto planner = planners::makePlanner("astar", planners::PlannerSettings{});
  const double slide_w = 0.18, slide_h = 0.06;
  // The set-up, checked by brute force: every stop blocked; stop 0 freed by a slide;
  // stop 1 by a tilt of at most 15° only; stop 2 by neither.
  for (const auto& stop : strategy.stops) ASSERT_FALSE(grid.isFree(stop.position));
  const auto& st = strategy.stops;
  ASSERT_TRUE(bruteSquarePoseExists(st[0].target, 1.5, slide_w, slide_h, grid));
  ASSERT_FALSE(bruteSquarePoseExists(st[1].target, 1.5, slide_w, slide_h, grid));
  ASSERT_TRUE(bruteTiltedPoseExists(st[1].target, 1.5, 15.0, grid));
  ASSERT_FALSE(bruteSquarePoseExists(st[2].target, 1.5, slide_w, slide_h, grid));
  ASSERT_FALSE(bruteTiltedPoseExists(st[2].target, 1.5, 15.0, grid));

  MissionOptions mosaic;
  mosaic.mosaic_repair = true;
  const SurfaceMission m = planSurfaceMission(strategy, grid, validator, *planner, mosaic);
  MissionOptions inspection;
  const SurfaceMission i = planSurfaceMission(strategy, grid, validator, *planner, inspection);
  ASSERT_EQ(m.moved_stops.size(), 3u) << m.reason;
  const auto angle = [](const coverage::Stop& s) {
    const Vec3 d = (s.position - s.target).normalized();
    return std::acos(std::clamp(d.x(), -1.0, 1.0)) * 180.0 / kPi;
  };
  const auto& a = m.strategy.stops;
  for (const auto& s : a) EXPECT_TRUE(grid.isFree(s.position)) << s.index;
  // Stop 0: square, at the standoff, its photo centre slid along the wall within the
  // allowance; inspection's repair tilts it instead.
  EXPECT_NEAR(angle(a[0]), 0.0, 1e-6);
  EXPECT_NEAR((a[0].position - a[0].target).norm(), 1.5, 1e-9);
  EXPECT_NEAR(a[0].target.x(), 0.0, 1e-12);
  EXPECT_LE(std::abs(a[0].target.y() - st[0].target.y()), slide_w + 1e-9);
  EXPECT_LE(std::abs(a[0].target.z() - st[0].target.z()), slide_h + 1e-9);
  EXPECT_GT((a[0].target - st[0].target).norm(), 0.0);
  EXPECT_GE(angle(i.strategy.stops[0]), 15.0 - 1e-6);
  // Stops 1 and 2: no square pose; left to the general repair, as inspection's (a tilt
  // misplaces a photo in OpenCV's affine mosaic, but leaving it out would leave a hole).
  for (const int k : {1, 2}) {
    EXPECT_EQ(a[k].position, i.strategy.stops[k].position) << k;
    EXPECT_EQ(a[k].target, st[k].target) << k;
    EXPECT_GE(angle(a[k]), 15.0 - 1e-6) << k;
  }
  // The reason counts the photos off square (here the two tilted).
  const auto off_square = std::count_if(a.begin(), a.end(), [&](const coverage::Stop& s) {
    return angle(s) > 0.5 || std::abs((s.position - s.target).norm() - 1.5) > 1e-3;
  });
  EXPECT_EQ(off_square, 2);
  EXPECT_NE(m.reason.find("2 of 3 photos off square"), std::string::npos) << m.reason;
  EXPECT_EQ(i.reason.find("off square"), std::string::npos) << i.reason;  // inspection: not said
  // Each stop is still photographed from where the camera looks at its target.
  for (const auto& s : a) {
    const Vec3 look = s.target - s.position;
    EXPECT_NEAR(s.gimbal_pitch_deg, std::atan2(look.z(), look.head<2>().norm()) * 180.0 / kPi,
                1e-9);
  }
}

TEST(MissionPlanner, AMosaicLeavesOutOnlyStopsItsNeighboursCover) {
  // One row of nine mosaic stops 0.24 m apart (footprint 0.6 × 0.4 m, overlap 0.6) in
  // front of the wall; a measured point 0.5 m in front of the middle stop blocks several.
  PointList cloud = wall();
  cloud.emplace_back(1.0, 2.0, 1.5);
  const auto strategy = mosaicRow({1.04, 1.28, 1.52, 1.76, 2.0, 2.24, 2.48, 2.72, 2.96});
  const auto grid = gridFor(cloud, strategy);
  const PathValidator validator(cloud, kRadius);
  auto planner = planners::makePlanner("astar", planners::PlannerSettings{});
  MissionOptions options;
  options.mosaic_repair = true;
  const SurfaceMission m = planSurfaceMission(strategy, grid, validator, *planner, options);
  ASSERT_EQ(m.status, SurfaceStatus::Ok) << m.reason;
  std::vector<std::size_t> flown, left_out;
  for (std::size_t i = 0; i < m.stop_problems.size(); ++i) {
    if (m.stop_problems[i] == StopProblem::None) flown.push_back(i);
    if (m.stop_problems[i] == StopProblem::MosaicCovered) left_out.push_back(i);
  }
  ASSERT_FALSE(left_out.empty()) << "the obstacle leaves no stop out: the set-up is wrong";
  EXPECT_EQ(flown.size() + left_out.size(), 9u);
  EXPECT_NE(m.reason.find(std::to_string(left_out.size()) + " of 9 stops left out of the mosaic"),
            std::string::npos)
      << m.reason;
  const auto& a = m.strategy.stops;
  for (const std::size_t i : left_out) {
    // Rightly left out: brute force finds no square pose within the slide allowance, and
    // every 1 cm point of its footprint lies in a flown stop's.
    EXPECT_FALSE(bruteSquarePoseExists(strategy.stops[i].target, 1.5, 0.18, 0.06, grid)) << i;
    for (double dw = -0.3; dw <= 0.3 + 1e-9; dw += 0.01)
      for (double dh = -0.2; dh <= 0.2 + 1e-9; dh += 0.01) {
        const Vec3 q = strategy.stops[i].target + Vec3(0.0, dw, dh);
        EXPECT_TRUE(std::any_of(flown.begin(), flown.end(),
                                [&](std::size_t j) {
                                  return std::abs(q.y() - a[j].target.y()) <= 0.3 + 1e-9 &&
                                         std::abs(q.z() - a[j].target.z()) <= 0.2 + 1e-9;
                                }))
            << "stop " << i << " at (" << dw << ", " << dh << ")";
      }
  }
  for (const std::size_t j : flown) EXPECT_TRUE(grid.isFree(a[j].position)) << j;
  // Inspection keeps every stop (moved, none left out).
  const SurfaceMission i =
      planSurfaceMission(strategy, grid, validator, *planner, MissionOptions{});
  EXPECT_TRUE(std::none_of(i.stop_problems.begin(), i.stop_problems.end(),
                           [](StopProblem p) { return p == StopProblem::MosaicCovered; }));
  EXPECT_STREQ(toString(StopProblem::MosaicCovered), "mosaic_covered");
}

/// Whether a pose `dist_lo`–`dist_hi` [m] from `target` within `max_deg` of the normal
/// +x is free and in clear sight of it (no measured point within 0.1 m of the line of
/// sight up to 0.35 m before the target): brute force over 1° of tilt, 5° of direction
/// and 5 cm of distance.
/// Whether pose `p` is free and in clear sight of `target` (no measured point within
/// 0.1 m of the line of sight up to 0.35 m before the target), by brute force.
bool clearPose(const Vec3& p, const Vec3& target, const world::VoxelGrid& grid,
               const PointList& cloud) {
  const Vec3 end = target + 0.35 * (p - target).normalized();
  return grid.isFree(p) && std::none_of(cloud.begin(), cloud.end(), [&](const Vec3& q) {
           return pointSegmentDistance(q, p, end) < 0.1;
         });
}

bool bruteClearPoseExists(const Vec3& target, double dist_lo, double dist_hi, double max_deg,
                          const world::VoxelGrid& grid, const PointList& cloud) {
  for (double r = dist_lo; r <= dist_hi + 1e-9; r += 0.05)
    for (double t = 0.0; t <= max_deg + 1e-9; t += 1.0)
      for (double phi = 0.0; phi < 360.0; phi += 5.0) {
        const double a = t * kPi / 180.0, b = phi * kPi / 180.0;
        const Vec3 d(std::cos(a), std::sin(a) * std::cos(b), std::sin(a) * std::sin(b));
        if (clearPose(target + r * d, target, grid, cloud)) return true;
      }
  return false;
}

/// A disc of points (5 cm apart) in the plane x = centre.x(), of `radius` [m] about `centre`.
void addDisc(PointList& cloud, const Vec3& centre, double radius) {
  for (double r = 0.0; r <= radius + 1e-4; r += 0.05) {
    const int n = std::max(1, static_cast<int>(std::ceil(2.0 * kPi * r / 0.05)));
    for (int k = 0; k < n; ++k) {
      const double phi = 2.0 * kPi * k / n;
      cloud.push_back(centre + Vec3(0.0, r * std::cos(phi), r * std::sin(phi)));
    }
  }
}

/// Stops `standoff` [m] in front (+x) of the wall x = 0 at `targets`, in that order,
/// surface 3, rows along y.
coverage::FlightStrategy strategyFacingWall(const PointList& targets, double standoff) {
  coverage::FlightStrategy strategy;
  strategy.surface_id = 3;
  strategy.camera.standoff_m = standoff;
  strategy.axis_w = Vec3::UnitY();
  strategy.axis_h = Vec3::UnitZ();
  for (const Vec3& t : targets) {
    coverage::Stop stop;
    stop.index = static_cast<int>(strategy.stops.size());
    stop.surface_id = 3;
    stop.col = stop.index;
    stop.target = t;
    stop.position = t + standoff * Vec3::UnitX();
    stop.yaw_deg = 180.0;
    strategy.stops.push_back(stop);
  }
  return strategy;
}

/// A grid of `resolution` [m] over the cloud and `extra`, inflated by kRadius.
world::VoxelGrid gridOver(const PointList& cloud, const PointList& extra, double resolution) {
  world::GridOptions o;
  o.resolution_m = resolution;
  o.inflation_radius_m = kRadius;
  o.padding_m = 2.0;
  return world::VoxelGrid::build(cloud, extra, o);
}

TEST(MissionPlanner, ARepairedStopTurnsNoMoreThan45DegWhenAFartherPoseAllows) {
  // A wall x = 0, one stop 3 m in front of (0, 2, 1.5). A disc of points (x = 2.8,
  // radius 1.2 m around the normal) blocks the stop and every pose up to 30° at the
  // standoff; a ring (x = 2.33, radius 1.91 m) lies 0.3 m beside the 45° line of sight,
  // blocking the 45° poses at the standoff but not their line of sight nor the 45° poses
  // at 1.25 × the standoff. At the standoff only 60° is free; SIFT leaves such a photo
  // out of the model (docs/photo_purposes.md), so the farther 45° pose must win.
  const Vec3 target(0.0, 2.0, 1.5);
  constexpr double kStandoff = 3.0;
  PointList cloud = wall();
  addDisc(cloud, Vec3(2.8, 2.0, 1.5), 1.2);
  for (int k = 0; k < 240; ++k) {
    const double phi = 2.0 * kPi * k / 240;
    cloud.emplace_back(2.33, 2.0 + 1.91 * std::cos(phi), 1.5 + 1.91 * std::sin(phi));
  }
  const coverage::FlightStrategy strategy = strategyFacingWall({target}, kStandoff);
  const auto grid = gridOver(cloud, {strategy.stops[0].position}, 0.05);
  // The scene does what it says (brute force): nothing within 45° at the standoff,
  // 60° there, and within 45° at 1.25 × the standoff.
  ASSERT_FALSE(bruteClearPoseExists(target, kStandoff, kStandoff, 45.0, grid, cloud));
  ASSERT_TRUE(bruteClearPoseExists(target, kStandoff, kStandoff, 60.0, grid, cloud));
  ASSERT_TRUE(bruteClearPoseExists(target, kStandoff, 1.25 * kStandoff, 45.0, grid, cloud));
  const PathValidator validator(cloud, kRadius);
  auto planner = planners::makePlanner("astar", planners::PlannerSettings{});
  MissionOptions options;  // max_standoff_factor 1.25
  const SurfaceMission m = planSurfaceMission(strategy, grid, validator, *planner, options);
  ASSERT_EQ(m.stop_problems[0], StopProblem::None);
  ASSERT_EQ(m.moved_stops.size(), 1u);
  const Vec3 d = m.strategy.stops[0].position - target;
  EXPECT_LE(std::acos(d.normalized().x()) * 180.0 / kPi, 45.0 + 1e-6) << d.transpose();
  EXPECT_LE(d.norm(), 1.25 * kStandoff + 1e-9);
  EXPECT_GT(d.norm(), kStandoff + 1e-9);
}

/// A pose at `deg` of tilt toward the unit `side` from the normal +x, `factor` × 3 m
/// from `target`.
Vec3 poseAt(const Vec3& target, double deg, const Vec3& side, double factor) {
  const double a = deg * kPi / 180.0;
  return target + 3.0 * factor * (std::cos(a) * Vec3::UnitX() + std::sin(a) * side);
}

TEST(MissionPlanner, ARunOfRepairedStopsKeepsOneSide) {
  // A wall x = 0 and two consecutive stops 3 m in front of (0, 2, 3) and (0, 6, 3).
  // Two discs of points on each stop's normal (inflation 0.5 m) block every pose within
  // 15° at all three distances; a point at each blocks 30° up and down at the standoff,
  // and for the first also 30° toward +y. So the first can only be repaired 30° toward −y, and
  // the second could go 30° toward +y (the side tried first) or −y. The second must keep
  // the first's side: turning to +y would change the viewpoint by 60° between two
  // consecutive photos, which SIFT does not match (docs/photo_purposes.md).
  PointList cloud;
  for (double y = 0.0; y <= 8.0001; y += 0.1)
    for (double z = 0.0; z <= 6.0001; z += 0.1) cloud.emplace_back(0.0, y, z);
  const Vec3 ta(0.0, 2.0, 3.0), tb(0.0, 6.0, 3.0);
  const Vec3 up = Vec3::UnitZ(), side = Vec3::UnitY();
  for (const Vec3& t : {ta, tb}) {
    for (const double x : {3.15, 3.5}) addDisc(cloud, t + Vec3(x, 0.0, 0.0), 1.0);
    cloud.push_back(poseAt(t, 30.0, up, 1.0));
    cloud.push_back(poseAt(t, 30.0, -up, 1.0));
  }
  cloud.push_back(poseAt(ta, 30.0, side, 1.0));
  const coverage::FlightStrategy strategy = strategyFacingWall({ta, tb}, 3.0);
  const auto grid = gridOver(cloud, {poseAt(ta, 0.0, up, 1.25)}, 0.1);
  // The scene does what it says (brute force): nothing free within 15° at any distance
  // for either stop; the second has a free pose in clear sight 30° toward each side.
  const auto clear = [&](const Vec3& p, const Vec3& t) { return clearPose(p, t, grid, cloud); };
  for (const Vec3& t : {ta, tb}) {
    ASSERT_FALSE(bruteClearPoseExists(t, 3.0, 3.75, 15.0, grid, cloud));
    ASSERT_FALSE(clear(poseAt(t, 30.0, up, 1.0), t));
    ASSERT_FALSE(clear(poseAt(t, 30.0, -up, 1.0), t));
  }
  ASSERT_FALSE(clear(poseAt(ta, 30.0, side, 1.0), ta));
  ASSERT_TRUE(clear(poseAt(ta, 30.0, -side, 1.0), ta));
  ASSERT_TRUE(clear(poseAt(tb, 30.0, side, 1.0), tb));
  ASSERT_TRUE(clear(poseAt(tb, 30.0, -side, 1.0), tb));
  const PathValidator validator(cloud, kRadius);
  auto planner = planners::makePlanner("astar", planners::PlannerSettings{});
  const SurfaceMission m =
      planSurfaceMission(strategy, grid, validator, *planner, MissionOptions{});
  ASSERT_EQ(m.stop_problems[0], StopProblem::None);
  ASSERT_EQ(m.stop_problems[1], StopProblem::None);
  const Vec3 da = (m.strategy.stops[0].position - ta).normalized();
  const Vec3 db = (m.strategy.stops[1].position - tb).normalized();
  EXPECT_LT(da.y(), 0.0) << da.transpose();
  EXPECT_LE(std::acos(std::min(1.0, da.dot(db))) * 180.0 / kPi, 20.0 + 1e-6)
      << da.transpose() << " then " << db.transpose();
  EXPECT_LE(std::acos(db.x()) * 180.0 / kPi, 30.0 + 1e-6) << db.transpose();
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
