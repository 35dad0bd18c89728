// Structure coverage through the whole chain (app::planStructure): the paper's
// floating cube and a tank standing on the ground, scored by FC-Planner's pixel rule
// on an independent analytic sampling, with every flown segment measured by brute
// force against every input point.

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <limits>
#include <random>

#include "uavip/app/pipeline.h"
#include "uavip/app/scenario.h"
#include "uavip/core/geometry.h"
#include "uavip/coverage/pixel_coverage.h"

namespace uavip::app {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// Smallest distance from every flown segment to every point (brute force).
double flightClearance(const planning::FlightPlan& f, const PointList& cloud) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& s : f.sorties) {
    for (std::size_t i = 0; i + 1 < s.waypoints.size(); ++i) {
      for (const auto& p : cloud)
        best = std::min(best, pointSegmentDistance(p, s.waypoints[i], s.waypoints[i + 1]));
    }
  }
  return best;
}

std::vector<coverage::ViewPose> flownViews(const PlanResult& p) {
  std::vector<coverage::ViewPose> views;
  for (const auto& sortie : p.flight.sorties) {
    for (const auto& st : sortie.stops) {
      const auto& s = p.missions.at(0).strategy.stops.at(static_cast<std::size_t>(st.stop));
      views.push_back({s.position, s.yaw_deg, s.gimbal_pitch_deg});
    }
  }
  return views;
}

TEST(StructureCoverage, FloatingCubeInOneFlightSafeFromEveryPoint) {
  Scenario sc = loadScenario(std::string(UAVIP_SOURCE_DIR) + "/scenarios/single_cube.yaml");
  const PointList raw = sense(sc);
  const DetectResult d = detect(raw, sc.config, measure(raw, &sc));
  const PlanResult p = planStructure(d.scene, d.resolved.config);
  ASSERT_TRUE(p.structure);
  ASSERT_EQ(p.missions.size(), 1u);
  const auto& m = p.missions[0];
  EXPECT_EQ(m.kind, "structure");
  EXPECT_EQ(m.surface_id, static_cast<int>(d.scene.surfaces.size()));  // above the scene's ids
  EXPECT_TRUE(planning::flyable(m.status)) << m.reason;
  ASSERT_EQ(p.flight.status, planning::FlightPlan::Status::Ok) << p.flight.reason;
  EXPECT_EQ(p.structure->ground_points, 0u);  // the bottom face looks down: not ground
  // The truth: the cube's five visible faces, sampled every 2 cm (not the points it planned on).
  PointList truth;
  for (double a = 0.0; a <= 3.0 + 1e-9; a += 0.02) {
    for (double b = 0.0; b <= 3.0 + 1e-9; b += 0.02) {
      truth.emplace_back(a, b, 4.0);
      truth.emplace_back(0.0, a, 1.0 + b);
      truth.emplace_back(3.0, a, 1.0 + b);
      truth.emplace_back(a, 0.0, 1.0 + b);
      truth.emplace_back(a, 3.0, 1.0 + b);
      truth.emplace_back(a, b, 1.0);
    }
  }
  const auto views = flownViews(p);
  // The footprint camera as a pinhole over 1000 px (app/pipeline.h).
  coverage::PinholeIntrinsics k;
  k.width_px = 1000;
  k.height_px = static_cast<int>(std::lround(1000.0 * 0.4 / 0.6));
  k.fx_px = k.fy_px = 1000.0 * p.structure->standoff_m / 0.6;
  k.cx_px = 500.0;
  k.cy_px = 0.5 * k.height_px;
  const auto ra = coverage::evaluatePixelCoverage(truth, views, k, p.structure->visible_range_m);
  const double a = ra.fraction;
  std::cout << "single_cube structure: " << views.size() << " photos, rule (a) on the truth " << a
            << ", rule (b) " << p.structure->rule_b << "\n";
  EXPECT_GE(a, 0.98);  // the rest lies next to the simulated outliers no free pose sees past
  EXPECT_GE(p.structure->rule_b, 0.95);
  EXPECT_GE(flightClearance(p.flight, raw), d.resolved.config.uav.inflationRadius());
}

TEST(StructureCoverage, TankOnTheGroundLeavesTheGroundOutAndCoversTheShell) {
  // A tank of radius 2 m and height 6 m on a 24 m square of ground, sampled every 10 cm.
  PointList raw;
  for (double x = -12.0; x <= 12.0; x += 0.1)
    for (double y = -12.0; y <= 12.0; y += 0.1)
      if (std::hypot(x, y) > 2.05) raw.emplace_back(x, y, 0.0);
  const int around = static_cast<int>(2.0 * kPi * 2.0 / 0.1);
  for (double z = 0.1; z <= 6.0 + 1e-9; z += 0.1)
    for (int j = 0; j < around; ++j)
      raw.emplace_back(2.0 * std::cos(2 * kPi * j / around), 2.0 * std::sin(2 * kPi * j / around),
                       z);
  for (double r = 0.0; r < 2.0; r += 0.1) {
    const int n = std::max(1, static_cast<int>(2 * kPi * r / 0.1));
    for (int j = 0; j < n; ++j)
      raw.emplace_back(r * std::cos(2 * kPi * j / n), r * std::sin(2 * kPi * j / n), 6.0);
  }
  Config config = parseConfig(
      "camera: {fx: 417.0467, fy: 461.0951, cx: 320, cy: 240, image_px: [640, 480], max_range_m: "
      "6}\n"
      "coverage: {standoff_m: 4}\nuav: {inflation_radius_m: 0.3}\n",
      "(test)");
  const DetectResult d = detect(raw, config, measure(raw));
  const PlanResult p = planStructure(d.scene, d.resolved.config);
  ASSERT_TRUE(p.structure);
  ASSERT_EQ(p.flight.status, planning::FlightPlan::Status::Ok) << p.flight.reason;
  EXPECT_GT(p.structure->ground_points, 50000u);  // the ground square is not photographed
  PointList truth;                                // the shell every 3 cm
  const int fine = static_cast<int>(2.0 * kPi * 2.0 / 0.03);
  for (double z = 0.3; z <= 6.0 + 1e-9; z += 0.03)
    for (int j = 0; j < fine; ++j)
      truth.emplace_back(2.0 * std::cos(2 * kPi * j / fine), 2.0 * std::sin(2 * kPi * j / fine), z);
  const double a =
      coverage::evaluatePixelCoverage(truth, flownViews(p), coverage::PinholeIntrinsics{}, 6.0)
          .fraction;
  std::cout << "tank: " << p.structure->photos << " photos, rule (a) on the shell " << a
            << ", rule (b) " << p.structure->rule_b << "\n";
  EXPECT_GE(a, 0.99);
  EXPECT_GE(p.structure->rule_b, 0.95);
  EXPECT_GE(flightClearance(p.flight, raw), 0.3);
}

TEST(StructureCoverage, SolarPanelsBelowTheAreaThresholdArePhotographed) {
  Scenario sc = loadScenario(std::string(UAVIP_SOURCE_DIR) + "/scenarios/solar_field.yaml");
  const PointList raw = sense(sc);
  const DetectResult d = detect(raw, sc.config, measure(raw, &sc));
  // Plane by plane there is nothing to inspect: the one surface is the ground.
  ASSERT_EQ(d.scene.surfaces.size(), 1u);
  EXPECT_GT(d.scene.surfaces[0].plane.normal.z(), 0.99);
  ASSERT_EQ(d.resolved.config.coverage.mode, "structure");
  const PlanResult p = planStructure(d.scene, d.resolved.config);
  ASSERT_TRUE(p.structure);
  ASSERT_EQ(p.flight.status, planning::FlightPlan::Status::Ok) << p.flight.reason;
  PointList truth;  // the panels' tops, every 2 cm
  for (const auto& r : sc.world.rects()) {
    if (r.name.rfind("panel_", 0) != 0) continue;
    for (double a = 0.0; a <= 1.0 + 1e-9; a += 0.015)
      for (double b = 0.0; b <= 1.0 + 1e-9; b += 0.02)
        truth.push_back(r.corner + a * r.edge_u + b * r.edge_v);
  }
  ASSERT_GT(truth.size(), 10000u);
  coverage::PinholeIntrinsics k;  // the 1.2 x 0.8 m footprint at the standoff, over 1000 px
  k.width_px = 1000;
  k.height_px = 667;
  k.fx_px = k.fy_px = 1000.0 * p.structure->standoff_m / 1.2;
  k.cx_px = 500.0;
  k.cy_px = 333.5;
  const double a =
      coverage::evaluatePixelCoverage(truth, flownViews(p), k, p.structure->visible_range_m)
          .fraction;
  std::cout << "solar field: " << p.structure->photos << " photos, rule (a) on the panels " << a
            << ", rule (b) " << p.structure->rule_b << "\n";
  EXPECT_GE(a, 0.99);
  EXPECT_GE(p.structure->rule_b, 0.95);
  for (const auto& sortie : p.flight.sorties)
    for (const auto& w : sortie.waypoints) EXPECT_GT(w.z(), 0.0) << "never below the ground";
  EXPECT_GE(flightClearance(p.flight, raw), d.resolved.config.uav.inflationRadius());
}

}  // namespace
}  // namespace uavip::app
