// Issue 33: boundaries that follow the surface. The L-shaped, U-shaped and window walls
// of scenarios/ are sensed, detected and planned; each wall's boundary and photo stops
// are scored against the simulator's true rectangles (app/boundary_truth.h: exact
// ray–rectangle tests, footprints over a 2 cm sampling of the truth, brute force).

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "uavip/app/boundary_truth.h"
#include "uavip/app/pipeline.h"
#include "uavip/app/scenario.h"

namespace uavip::app {
namespace {

struct Scored {
  BoundaryScore score;
  std::size_t holes{0};
};

/// The scenario's wall (its one surface) planned with `boundary`, scored.
Scored planWall(const std::string& file, const std::string& boundary) {
  Scenario sc = loadScenario(std::string(UAVIP_SOURCE_DIR) + "/scenarios/" + file);
  sc.config.perception.planes.boundary = boundary;
  const PointList raw = sense(sc);
  const DetectResult d = detect(raw, sc.config, measure(raw, &sc));
  EXPECT_EQ(d.scene.surfaces.size(), 1u) << file;
  if (d.scene.surfaces.empty()) return {};
  const PlanResult p = plan(d.scene, d.resolved.config, {d.scene.surfaces[0].id});
  EXPECT_EQ(p.missions.size(), 1u);
  if (p.missions.empty()) return {};
  Scored out;
  out.score = scoreBoundary(d.scene.surfaces[0], p.missions[0].strategy, sc.world.rects());
  out.holes = d.scene.surfaces[0].holes.size();
  std::printf("%s %s: stops %zu, over air %zu, coverage %.2f %%, area %.2f / %.2f m2 (%.2f %%)\n",
              file.c_str(), boundary.c_str(), out.score.stops, out.score.stops_over_air,
              100.0 * out.score.coverage, out.score.area_m2, out.score.truth_area_m2,
              100.0 * out.score.area_error);
  return out;
}

class ConcaveWall : public ::testing::TestWithParam<const char*> {};

TEST_P(ConcaveWall, OutlineBoundaryKeepsEveryStopOnTheWall) {
  const Scored s = planWall(GetParam(), "outline");
  EXPECT_GT(s.score.stops, 0u);
  EXPECT_EQ(s.score.stops_over_air, 0u);
  EXPECT_GE(s.score.coverage, 0.99);
  EXPECT_LE(s.score.area_error, 0.03);
}

TEST_P(ConcaveWall, ConvexHullPutsStopsOverAir) {
  // The paper's hull (perception.boundary: convex), the reference the outline fixes.
  const Scored s = planWall(GetParam(), "convex");
  EXPECT_GT(s.score.stops_over_air, 0u);
  EXPECT_EQ(s.holes, 0u);
}

INSTANTIATE_TEST_SUITE_P(Walls, ConcaveWall,
                         ::testing::Values("wall_l.yaml", "wall_u.yaml", "wall_window.yaml"));

TEST(ConcaveWall, WindowIsAHole) {
  const Scored s = planWall("wall_window.yaml", "outline");
  EXPECT_EQ(s.holes, 1u);
}

}  // namespace
}  // namespace uavip::app
