// Issue 33: the operator's edits file. Parsed and written back identically; bad edits
// refused with the edit's line and reason; boundaries replaced, cut, merged and deleted
// checked against areas computed independently (rectangles, shoelace); a keep-out box
// across a planned flight checked by brute force over every leg of the new flight.

#include "uavip/app/edits.h"

#include <gtest/gtest.h>

#include <string>

#include "uavip/app/pipeline.h"
#include "uavip/app/scenario.h"
#include "uavip/core/error.h"
#include "uavip/core/geometry.h"

namespace uavip::app {
namespace {

/// A vertical w × h rectangle in the plane y = y0 facing −y, from x = x0, z = 0.
Surface wall(int id, double x0, double y0, double w, double h) {
  Surface s;
  s.id = id;
  s.plane.normal = Vec3(0, -1, 0);
  s.plane.offset = y0;  // −y + y0 = 0 on the plane
  s.axis_u = Vec3::UnitX();
  s.axis_v = s.plane.normal.cross(s.axis_u);
  s.boundary = {Vec3(x0, y0, 0), Vec3(x0 + w, y0, 0), Vec3(x0 + w, y0, h), Vec3(x0, y0, h)};
  s.centroid = Vec3(x0 + w / 2, y0, h / 2);
  s.area_m2 = w * h;
  s.density_area_m2 = w * h;
  for (double x = x0; x <= x0 + w; x += 0.5)
    for (double z = 0; z <= h; z += 0.5) s.inliers.emplace_back(x, y0, z);
  return s;
}

Scene twoWalls() {
  Scene sc;
  sc.surfaces = {wall(0, 0, 0, 4, 2), wall(1, 4, 0, 2, 2)};
  Surface side = wall(2, 0, 0, 3, 2);  // the plane x = 0, facing −x
  side.plane.normal = Vec3(-1, 0, 0);
  side.plane.offset = 0;
  side.axis_u = Vec3::UnitY();
  side.axis_v = side.plane.normal.cross(side.axis_u);
  side.boundary = {Vec3(0, 0, 0), Vec3(0, 3, 0), Vec3(0, 3, 2), Vec3(0, 0, 2)};
  side.centroid = Vec3(0, 1.5, 1);
  sc.surfaces.push_back(side);
  return sc;
}

/// An edits file for surface `s` with its fingerprint and `body` (YAML lines under it).
std::string editFor(const Surface& s, const std::string& body) {
  Edits e;
  SurfaceEdit se;
  se.id = s.id;
  se.centroid = s.centroid;
  se.normal = s.plane.normal;
  se.remove = true;  // placeholder so the writer writes a valid entry; replaced below
  e.surfaces.push_back(se);
  std::string text = editsYamlText(e);
  const auto at = text.find("    delete: true\n");
  return text.replace(at, std::string("    delete: true\n").size(), body);
}

/// The message of the InputError `f` throws ("" when none).
template <typename F>
std::string errorOf(F f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Edits, ParsedAndWrittenBackIdentically) {
  Edits e;
  SurfaceEdit a;
  a.id = 3;
  a.centroid = Vec3(1.0 / 3.0, -2.5e-7, 12345.678901234567);
  a.normal = Vec3(0.6, -0.8, 0.0);
  a.boundary = {Vec3(0.1, 0.2, 0.3), Vec3(1.1, 0.2, 0.3), Vec3(1.1, 0.2, 2.3)};
  a.add = {{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 0, 1)}};
  a.cut = {{Vec3(0, 0, 0), Vec3(0.5, 0, 0), Vec3(0.5, 0, 0.5)},
           {Vec3(2, 0, 0), Vec3(2.5, 0, 0), Vec3(2.5, 0, 0.5)}};
  a.merge = {4, 7};
  SurfaceEdit b;
  b.id = 5;
  b.remove = true;
  e.surfaces = {a, b};
  KeepOutEdit box;
  box.volume.name = "crane swing";
  box.volume.center = Vec3(10, 20, 5);
  box.volume.size = Vec3(4, 6, 10);
  box.volume.yaw_deg = 33.3;
  KeepOutEdit mast;
  mast.volume.name = "mast";
  mast.volume.shape = KeepOut::Shape::Cylinder;
  mast.volume.center = Vec3(-3, 4, 15);
  mast.volume.size = Vec3(2.5, 2.5, 30);
  e.keep_out = {box, mast};

  const std::string text = editsYamlText(e);
  const Edits back = parseEdits(text, "edits.yaml");
  EXPECT_EQ(editsYamlText(back), text);
  ASSERT_EQ(back.surfaces.size(), 2u);
  EXPECT_EQ(back.surfaces[0].centroid, a.centroid);  // bit for bit
  EXPECT_EQ(back.surfaces[0].boundary, a.boundary);
  EXPECT_EQ(back.surfaces[0].cut.size(), 2u);
  EXPECT_EQ(back.surfaces[0].merge, a.merge);
  EXPECT_TRUE(back.surfaces[1].remove);
  ASSERT_EQ(back.keep_out.size(), 2u);
  EXPECT_EQ(back.keep_out[0].volume.name, "crane swing");
  EXPECT_EQ(back.keep_out[0].volume.yaw_deg, 33.3);
  EXPECT_EQ(back.keep_out[1].volume.shape, KeepOut::Shape::Cylinder);
  EXPECT_EQ(back.keep_out[1].volume.center, mast.volume.center);
  EXPECT_EQ(back.keep_out[1].volume.size, mast.volume.size);
  EXPECT_GT(back.surfaces[0].line, 0);
}

TEST(Edits, BoundaryReplacedCutAndMergedMatchIndependentAreas) {
  Scene sc = twoWalls();
  // Replace: a 3 × 1.5 rectangle (0.1 m in front of the plane: projected onto it).
  Scene a = sc;
  applyEdits(a, parseEdits(editFor(sc.surfaces[0],
                                   "    boundary: [[0.5, -0.1, 0.2], [3.5, -0.1, "
                                   "0.2], [3.5, 0.1, 1.7], [0.5, 0, 1.7]]\n"),
                           "e.yaml"));
  EXPECT_NEAR(a.surfaces[0].area_m2, 3.0 * 1.5, 1e-9);
  EXPECT_NEAR(polygonArea(a.surfaces[0].boundary), 4.5, 1e-9);
  for (const auto& p : a.surfaces[0].boundary) EXPECT_NEAR(p.y(), 0.0, 1e-9);
  // Cut a 1 × 1 square out of the 4 × 2 wall's middle: a hole of 1 m².
  Scene b = sc;
  applyEdits(b, parseEdits(editFor(sc.surfaces[0],
                                   "    cut:\n      - [[1.5, 0, 0.5], [2.5, 0, "
                                   "0.5], [2.5, 0, 1.5], [1.5, 0, 1.5]]\n"),
                           "e.yaml"));
  EXPECT_NEAR(b.surfaces[0].area_m2, 8.0 - 1.0, 0.05 * 0.05 * 4 * 12);  // cells along the edges
  EXPECT_EQ(b.surfaces[0].holes.size(), 1u);
  // Merge the coplanar neighbour: 8 + 4 m², one surface fewer, its points joined.
  Scene c = sc;
  const auto lines =
      applyEdits(c, parseEdits(editFor(sc.surfaces[0], "    merge: [1]\n"), "e.yaml"));
  ASSERT_EQ(c.surfaces.size(), 2u);
  EXPECT_NEAR(c.surfaces[0].area_m2, 12.0, 0.05 * 0.05 * 4 * 20);
  EXPECT_EQ(c.surfaces[0].inliers.size(),
            sc.surfaces[0].inliers.size() + sc.surfaces[1].inliers.size());
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_NE(lines[0].find("merged with 1"), std::string::npos);
  // Delete: the surface goes, its points become an obstacle.
  Scene d = sc;
  applyEdits(d, parseEdits(editFor(sc.surfaces[2], "    delete: true\n"), "e.yaml"));
  EXPECT_EQ(d.surfaces.size(), 2u);
  ASSERT_EQ(d.obstacles.size(), 1u);
  EXPECT_EQ(d.obstacles[0].points.size(), sc.surfaces[2].inliers.size());
}

TEST(Edits, BadEditsNameTheEditAndWhyAndLeaveTheSceneAlone) {
  const Scene sc = twoWalls();
  const auto refused = [&](const std::string& text, const std::string& why) {
    Scene copy = sc;
    const std::string msg = errorOf([&] { applyEdits(copy, parseEdits(text, "e.yaml")); });
    EXPECT_NE(msg.find(why), std::string::npos) << msg;
    EXPECT_NE(msg.find("e.yaml:3"), std::string::npos) << msg;  // the entry's line
    EXPECT_NE(msg.find("surfaces[0]"), std::string::npos) << msg;
    EXPECT_EQ(copy.surfaces.size(), sc.surfaces.size());
    EXPECT_EQ(copy.surfaces[0].boundary, sc.surfaces[0].boundary);
  };
  Surface unknown = sc.surfaces[0];
  unknown.id = 9;
  refused(editFor(unknown, "    delete: true\n"), "no surface with id 9");
  Surface moved = sc.surfaces[0];
  moved.centroid.x() += 0.5;
  refused(editFor(moved, "    delete: true\n"), "does not match the fingerprint");
  refused(editFor(sc.surfaces[0],
                  "    boundary: [[0, 0, 0], [2, 0, 2], [2, 0, 0], [0, 0, 2]]\n"),  // a bow tie
          "intersects itself");
  refused(editFor(sc.surfaces[0], "    boundary: [[0, 0, 0], [2, 0, 0], [2, 1.5, 2]]\n"),
          "off the plane of surface 0");
  refused(editFor(sc.surfaces[0], "    merge: [2]\n"), "not coplanar");
  // Strict format: an unknown key names the key.
  EXPECT_NE(
      errorOf([] { parseEdits("uavip-edits: 1\nsurfacez: []\n", "e.yaml"); }).find("surfacez"),
      std::string::npos);
  EXPECT_NE(errorOf([] { parseEdits("uavip-edits: 2\n", "e.yaml"); }).find("uavip-edits"),
            std::string::npos);
}

/// Every point of the segment [a, b], 1 cm apart, outside `k` grown by `margin`.
bool segmentAvoids(const KeepOut& k, const Vec3& a, const Vec3& b, double margin) {
  const int n = std::max(1, static_cast<int>((b - a).norm() / 0.01));
  for (int i = 0; i <= n; ++i) {
    if (k.contains(a + (b - a) * (static_cast<double>(i) / n), margin)) return false;
  }
  return true;
}

TEST(Edits, KeepOutAcrossThePlannedFlightIsAvoidedByEveryLeg) {
  Scenario sc = loadScenario(std::string(UAVIP_SOURCE_DIR) + "/scenarios/single_plane.yaml");
  const PointList raw = sense(sc);
  const DetectResult d = detect(raw, sc.config, measure(raw, &sc));
  const std::vector<int> ids = selectSurfaces(d.scene, "all");
  const PlanResult before = plan(d.scene, d.resolved.config, ids);
  ASSERT_FALSE(before.flight.sorties.empty());
  // A 0.8 m box on the middle of the flight's longest segment.
  Vec3 a = Vec3::Zero();
  Vec3 b = Vec3::Zero();
  for (const auto& s : before.flight.sorties) {
    for (std::size_t i = 0; i + 1 < s.waypoints.size(); ++i) {
      if ((s.waypoints[i + 1] - s.waypoints[i]).norm() > (b - a).norm()) {
        a = s.waypoints[i];
        b = s.waypoints[i + 1];
      }
    }
  }
  ASSERT_GT((b - a).norm(), 1.0);
  KeepOut box;
  box.name = "no-fly";
  box.center = 0.5 * (a + b);
  box.size = Vec3(0.8, 0.8, 0.8);
  ASSERT_FALSE(segmentAvoids(box, a, b, 0.0));  // the old flight crosses it

  Edits e;
  e.file = "e.yaml";
  e.keep_out.push_back({0, box});
  Scene edited = d.scene;
  applyEdits(edited, e);
  checkKeepOuts(edited, d.resolved.config, ids, e);
  const PlanResult after = plan(edited, d.resolved.config, ids);
  ASSERT_EQ(after.flight.status, planning::FlightPlan::Status::Ok) << after.flight.reason;
  const double r = d.resolved.config.uav.inflationRadius();
  std::size_t segments = 0;
  for (const auto& s : after.flight.sorties) {
    EXPECT_TRUE(s.validation.collision_free);
    for (std::size_t i = 0; i + 1 < s.waypoints.size(); ++i, ++segments)
      EXPECT_TRUE(segmentAvoids(box, s.waypoints[i], s.waypoints[i + 1], r))
          << "segment " << i << " comes within " << r << " m of the keep-out";
  }
  EXPECT_GT(segments, 0u);
  // No flown stop inside (stops that fell inside are skipped, the surface partial).
  std::size_t flown = 0;
  for (const auto& s : after.flight.sorties) {
    for (const auto& fs : s.stops) {
      for (const auto& m : after.missions) {
        if (m.surface_id != fs.surface_id) continue;
        ++flown;
        EXPECT_FALSE(box.contains(m.strategy.stops[static_cast<std::size_t>(fs.stop)].position));
      }
    }
  }
  EXPECT_GT(flown, 0u);
}

TEST(Edits, KeepOutOverHomeOrEveryStopIsRefused) {
  Scenario sc = loadScenario(std::string(UAVIP_SOURCE_DIR) + "/scenarios/single_plane.yaml");
  const PointList raw = sense(sc);
  const DetectResult d = detect(raw, sc.config, measure(raw, &sc));
  Edits e;
  e.file = "e.yaml";
  KeepOut all;
  all.name = "everything";
  all.center = Vec3(4, -1.5, 2.5);
  all.size = Vec3(20, 6, 12);
  e.keep_out.push_back({7, all});
  Scene edited = d.scene;
  applyEdits(edited, e);
  const std::string msg = errorOf([&] { checkKeepOuts(edited, d.resolved.config, {0}, e); });
  EXPECT_NE(msg.find("e.yaml:7: keep_out[0] 'everything' contains every photo stop"),
            std::string::npos)
      << msg;
  Config home = d.resolved.config;
  home.flight.home = Vec3(4, -6, 1);
  all.center = Vec3(4, -6, 1);
  all.size = Vec3(1, 1, 1);
  e.keep_out[0].volume = all;
  EXPECT_NE(errorOf([&] { checkKeepOuts(edited, home, {}, e); }).find("contains mission.home"),
            std::string::npos);
}

}  // namespace
}  // namespace uavip::app
