#include "uavip/planning/flight_planner.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <set>

#include "planners/registry.h"
#include "uavip/core/error.h"
#include "uavip/core/geometry.h"
#include "uavip/planning/tour.h"

namespace uavip::planning {
namespace {

constexpr double kRadius = 0.5;

/// A wall of points x = 0, y ∈ [0, 6], z ∈ [0, 3] (spacing 0.1 m).
PointList wall() {
  PointList cloud;
  for (double y = 0.0; y <= 6.0001; y += 0.1)
    for (double z = 0.0; z <= 3.0001; z += 0.1) cloud.emplace_back(0.0, y, z);
  return cloud;
}

/// A boustrophedon of rows × cols stops at x, starting at (y0, z0), 1 m apart.
coverage::FlightStrategy stopsAt(int id, double x, double y0, double z0, int rows, int cols) {
  coverage::FlightStrategy s;
  s.surface_id = id;
  int index = 0;
  for (int row = 0; row < rows; ++row) {
    for (int k = 0; k < cols; ++k) {
      const int col = row % 2 == 0 ? k : cols - 1 - k;
      coverage::Stop stop;
      stop.index = index++;
      stop.surface_id = id;
      stop.row = row;
      stop.col = col;
      stop.position = Vec3(x, y0 + col, z0 + row);
      stop.target = Vec3(0.0, y0 + col, z0 + row);
      stop.yaw_deg = x > 0.0 ? 180.0 : 0.0;
      s.stops.push_back(stop);
    }
  }
  return s;
}

struct World {
  PointList cloud = wall();
  std::vector<coverage::FlightStrategy> strategies;
  world::VoxelGrid grid;
  PathValidator validator{PointList{}, kRadius};
  std::vector<SurfaceMission> missions;
};

/// Surfaces in front of (x > 0) and behind (x < 0) the wall: legs between the two
/// sides must go around or over it.
World twoSidedWall(std::unique_ptr<Planner>& planner) {
  World w;
  w.strategies = {stopsAt(0, 1.5, 1.0, 1.0, 2, 4), stopsAt(1, -1.5, 1.0, 1.0, 2, 4),
                  stopsAt(2, 1.5, 1.0, 4.5, 1, 3), stopsAt(3, -1.5, 4.0, 4.5, 1, 2)};
  PointList extra;
  for (const auto& s : w.strategies)
    for (const auto& stop : s.stops) extra.push_back(stop.position);
  world::GridOptions o;
  o.resolution_m = 0.2;
  o.inflation_radius_m = kRadius;
  o.padding_m = 3.0;
  w.grid = world::VoxelGrid::build(w.cloud, extra, o);
  w.validator = PathValidator(w.cloud, kRadius);
  planner = planners::makePlanner("astar", {});
  MissionOptions mo;
  for (const auto& s : w.strategies)
    w.missions.push_back(planSurfaceMission(s, w.grid, w.validator, *planner, mo));
  for (const auto& m : w.missions) EXPECT_EQ(m.status, SurfaceStatus::Ok) << m.reason;
  return w;
}

double bruteClearance(const PointList& cloud, const PointList& path) {
  double d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i + 1 < path.size(); ++i)
    for (const auto& p : cloud) d = std::min(d, pointSegmentDistance(p, path[i], path[i + 1]));
  return d;
}

/// Every sortie from home to home, every stop of every surface flown exactly once,
/// each stop at its waypoint, and every segment clear of every wall point.
void expectWholeFlight(const FlightPlan& f, const World& w) {
  ASSERT_EQ(f.status, FlightPlan::Status::Ok) << f.reason;
  std::set<std::pair<int, int>> flown;
  for (const auto& s : f.sorties) {
    ASSERT_GE(s.waypoints.size(), 2u);
    EXPECT_EQ(s.waypoints.front(), f.home);
    EXPECT_EQ(s.waypoints.back(), f.home);
    EXPECT_TRUE(s.validation.collision_free);
    EXPECT_GE(bruteClearance(w.cloud, s.waypoints), kRadius - 1e-9);
    // Reused surface clearances give the verdict of validating the whole sortie.
    const ValidationResult whole = w.validator.validate(s.waypoints);
    EXPECT_NEAR(s.validation.min_clearance_m, whole.min_clearance_m, 1e-9);
    ASSERT_EQ(s.validation.segment_clearance_m.size(), whole.segment_clearance_m.size());
    for (std::size_t i = 0; i < whole.segment_clearance_m.size(); ++i)
      EXPECT_NEAR(s.validation.segment_clearance_m[i], whole.segment_clearance_m[i], 1e-9)
          << "segment " << i;
    for (const auto& st : s.stops) {
      EXPECT_TRUE(flown.insert({st.surface_id, st.stop}).second) << "stop flown twice";
      ASSERT_LT(st.waypoint, s.waypoints.size());
      EXPECT_EQ(s.waypoints[st.waypoint],
                w.strategies[static_cast<std::size_t>(st.surface_id)].stops[st.stop].position);
    }
  }
  std::size_t total = 0;
  for (const auto& s : w.strategies) total += s.stops.size();
  EXPECT_EQ(flown.size(), total);
}

TEST(FlightPlanner, OneTourFromHomeOverEverySurface) {
  std::unique_ptr<Planner> planner;
  const World w = twoSidedWall(planner);
  FlightOptions o;
  o.compare_naive = true;
  const FlightPlan f = planFlight(w.missions, w.grid, w.validator, *planner, o);
  expectWholeFlight(f, w);
  EXPECT_EQ(f.sorties.size(), 1u);
  EXPECT_EQ(f.order.size(), 4u);
  // Default home: the lowest stop (z = 1), the first one found.
  EXPECT_DOUBLE_EQ(f.home.z(), 1.0);
  EXPECT_NE(f.home_source.find("lowest photo stop"), std::string::npos);
  // The tour is no shorter than the bound and no longer than surfaces by id; the
  // flight of one sortie is the tour.
  EXPECT_LE(f.lower_bound_m, f.tour_length_m + 1e-6);
  EXPECT_LE(f.tour_length_m, f.naive_length_m + 1e-6);
  EXPECT_NEAR(f.length_m, f.tour_length_m, 1e-6);
  EXPECT_TRUE(f.exact_order);
  // Legs between the sides cross the wall's plane beyond its ends or over its top.
  EXPECT_GT(f.planned_legs, 0u);
}

TEST(FlightPlanner, SortiesFitTheBatteryAndStartAndEndAtHome) {
  std::unique_ptr<Planner> planner;
  const World w = twoSidedWall(planner);
  FlightOptions o;
  o.home = Vec3(4.0, -2.0, 1.0);
  o.model.endurance_s = 40.0;  // 30 s usable: 22 photos of 3 s need at least 3 batteries
  const FlightPlan f = planFlight(w.missions, w.grid, w.validator, *planner, o);
  expectWholeFlight(f, w);
  EXPECT_EQ(f.home_source, "mission.home");
  EXPECT_GE(f.sorties.size(), 3u);
  double total = 0.0;
  for (const auto& s : f.sorties) {
    // Independent duration: flight time of each segment plus the photo time.
    double t = 0.0;
    for (std::size_t i = 1; i < s.waypoints.size(); ++i) {
      const Vec3 d = s.waypoints[i] - s.waypoints[i - 1];
      t += std::max(
          std::hypot(d.x(), d.y()) / o.model.cruise_speed_m_s,
          d.z() > 0 ? d.z() / o.model.climb_speed_m_s : -d.z() / o.model.descent_speed_m_s);
    }
    t += static_cast<double>(s.stops.size()) * (o.model.hover_s + o.model.settle_s);
    EXPECT_NEAR(s.duration_s, t, 1e-9);
    EXPECT_LE(s.duration_s, 30.0 + 1e-9);
    total += s.duration_s;
  }
  EXPECT_NEAR(f.duration_s, total, 1e-9);
}

TEST(FlightPlanner, AStopBeyondOneBatteryFailsTheFlight) {
  std::unique_ptr<Planner> planner;
  const World w = twoSidedWall(planner);
  FlightOptions o;
  o.model.endurance_s = 4.0;  // 3 s usable: not even one photo (3 s) and the way there
  o.home = Vec3(4.0, -2.0, 1.0);
  const FlightPlan f = planFlight(w.missions, w.grid, w.validator, *planner, o);
  EXPECT_EQ(f.status, FlightPlan::Status::Failed);
  EXPECT_NE(f.reason.find("endurance_s"), std::string::npos) << f.reason;
  EXPECT_TRUE(f.sorties.empty());
}

TEST(FlightPlanner, HomeInsideObstacleSpaceIsRefused) {
  std::unique_ptr<Planner> planner;
  const World w = twoSidedWall(planner);
  FlightOptions o;
  o.home = Vec3(0.1, 2.0, 1.0);
  EXPECT_THROW(planFlight(w.missions, w.grid, w.validator, *planner, o), InputError);
}

TEST(FlightPlanner, OptionsBuiltInCodeAreValidated) {
  std::unique_ptr<Planner> planner;
  const World w = twoSidedWall(planner);
  FlightOptions o;
  o.max_rounds = 0;
  EXPECT_THROW(planFlight(w.missions, w.grid, w.validator, *planner, o), InputError);
  o = FlightOptions{};
  o.home = Vec3(std::numeric_limits<double>::infinity(), 0.0, 1.0);
  EXPECT_THROW(o.validate(), InputError);
  o = FlightOptions{};
  o.model.reserve = 1.5;  // FlightModel::validate: a reserve in [0, 1)
  EXPECT_THROW(o.validate(), InputError);
  EXPECT_NO_THROW(FlightOptions{}.validate());
  TourOptions t;
  t.max_passes = -1;
  EXPECT_THROW(t.validate(), InputError);
}

TEST(FlightPlanner, BlockedSurfacesAreListedNotFlown) {
  std::unique_ptr<Planner> planner;
  World w = twoSidedWall(planner);
  w.missions[1].status = SurfaceStatus::Blocked;
  const FlightPlan f = planFlight(w.missions, w.grid, w.validator, *planner, {});
  ASSERT_EQ(f.status, FlightPlan::Status::Ok) << f.reason;
  ASSERT_EQ(f.excluded.size(), 1u);
  EXPECT_EQ(f.excluded[0].surface_id, 1);
  for (const auto& v : f.order) EXPECT_NE(v.surface_id, 1);
  for (const auto& s : f.sorties)
    for (const auto& st : s.stops) EXPECT_NE(st.surface_id, 1);
  w.missions.clear();
  EXPECT_EQ(planFlight(w.missions, w.grid, w.validator, *planner, {}).status,
            FlightPlan::Status::Empty);
}

TEST(FlightModel, TimesAndValidation) {
  FlightModel m;
  EXPECT_DOUBLE_EQ(m.segmentSeconds({0, 0, 0}, {6, 0, 0}), 2.0);  // 3 m/s
  EXPECT_DOUBLE_EQ(m.segmentSeconds({0, 0, 0}, {0, 0, 4}), 2.0);  // climb 2 m/s
  EXPECT_DOUBLE_EQ(m.segmentSeconds({0, 0, 4}, {0, 0, 0}), 4.0 / 1.5);
  EXPECT_DOUBLE_EQ(m.segmentSeconds({0, 0, 0}, {3, 0, 4}), 2.0);  // vertical limits
  EXPECT_DOUBLE_EQ(m.usableSeconds(), 900.0);
  m.reserve = 1.0;
  EXPECT_THROW(m.validate(), InputError);
  m = FlightModel{};
  m.cruise_speed_m_s = 0.0;
  EXPECT_THROW(m.validate(), InputError);
}

}  // namespace
}  // namespace uavip::planning
