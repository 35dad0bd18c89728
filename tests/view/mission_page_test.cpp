// The mission page (view/mission_page.h) on a hand-made scene and mission: the counts it
// embeds, the quantised positions decoded back against the inputs, the scripts kept
// whole, determinism and bad input.

#include "uavip/view/mission_page.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "uavip/core/error.h"
#include "uavip/io/mission_json.h"

namespace {

namespace view = uavip::view;
namespace planning = uavip::planning;
using uavip::Vec3;

/// A 2 × 2 m wall in y = 0 (points every 0.25 m), a 5-point obstacle, 3 stray points;
/// surface 0 flies 2 stops on a 3-waypoint path, surface 7 is blocked with 1 stop; an
/// ordered flight of 2 sorties, one stop each.
struct Fixture {
  uavip::Scene scene;
  std::vector<planning::SurfaceMission> missions;
  planning::FlightPlan flight;
  Fixture() {
    uavip::Surface s;
    s.id = 0;
    s.plane.normal = {0.0, -1.0, 0.0};
    for (int i = 0; i <= 8; ++i)
      for (int j = 0; j <= 8; ++j) s.inliers.emplace_back(0.25 * i, 0.0, 0.25 * j);
    s.boundary = {{0, 0, 0}, {2, 0, 0}, {2, 0, 2}, {0, 0, 2}};
    s.centroid = {1.0, 0.0, 1.0};
    s.area_m2 = 4.0;
    scene.surfaces.push_back(s);
    uavip::Obstacle o;
    for (int i = 0; i < 5; ++i) o.points.emplace_back(4.0, 0.1 * i, 0.5);
    scene.obstacles.push_back(o);
    scene.cloud = s.inliers;
    scene.cloud.insert(scene.cloud.end(), o.points.begin(), o.points.end());
    for (int i = 0; i < 3; ++i) scene.cloud.emplace_back(-2.0, 1.0 + i, 0.0);

    planning::SurfaceMission m;
    m.surface_id = 0;
    m.status = planning::SurfaceStatus::Ok;
    m.strategy.camera.footprint_w_m = 0.6;
    m.strategy.camera.footprint_h_m = 0.4;
    for (int k = 0; k < 2; ++k) {
      uavip::coverage::Stop st;
      st.index = k;
      st.target = {0.5 + k, 0.0, 1.0};
      st.position = {0.5 + k, -1.5, 1.0};
      st.yaw_deg = 90.0;
      st.gimbal_pitch_deg = -10.0;
      m.strategy.stops.push_back(st);
    }
    m.stop_problems.assign(2, planning::StopProblem::None);
    m.waypoints = {{0.5, -1.5, 1.0}, {1.0, -1.6, 1.0}, {1.5, -1.5, 1.0}};
    missions.push_back(m);

    planning::SurfaceMission b;
    b.surface_id = 7;
    b.status = planning::SurfaceStatus::Blocked;
    uavip::coverage::Stop st;
    st.position = {9.0, 9.0, 9.0};
    b.strategy.stops.push_back(st);
    b.stop_problems.assign(1, planning::StopProblem::InObstacleSpace);
    missions.push_back(b);

    flight.status = planning::FlightPlan::Status::Ok;
    flight.home = {0.0, -4.0, 0.0};
    for (int k = 0; k < 2; ++k) {
      planning::Sortie sortie;
      sortie.waypoints = {flight.home, m.strategy.stops[k].position, flight.home};
      sortie.stops.push_back({0, k, 1});
      flight.sorties.push_back(sortie);
    }
  }
};

/// The text of <script type="application/json" id="ID">.
nlohmann::json block(const std::string& html, const std::string& id) {
  const std::string open = "<script type=\"application/json\" id=\"" + id + "\">";
  const auto a = html.find(open);
  if (a == std::string::npos) return nullptr;
  const auto b = html.find("</script>", a);
  return nlohmann::json::parse(html.substr(a + open.size(), b - a - open.size()));
}

std::vector<std::uint8_t> unbase64(const std::string& s) {
  std::vector<std::uint8_t> out;
  std::uint32_t acc = 0;
  int bits = 0;
  for (const char c : s) {
    int v = -1;
    if (c >= 'A' && c <= 'Z')
      v = c - 'A';
    else if (c >= 'a' && c <= 'z')
      v = c - 'a' + 26;
    else if (c >= '0' && c <= '9')
      v = c - '0' + 52;
    else if (c == '+')
      v = 62;
    else if (c == '/')
      v = 63;
    if (v < 0) continue;
    acc = (acc << 6) | static_cast<std::uint32_t>(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<std::uint8_t>((acc >> bits) & 0xff));
    }
  }
  return out;
}

std::vector<Vec3> decodePositions(const nlohmann::json& data, const std::string& b64) {
  const auto bytes = unbase64(b64);
  const Vec3 min(data["box_min"][0].get<double>(), data["box_min"][1].get<double>(),
                 data["box_min"][2].get<double>());
  const Vec3 size(data["box_size"][0].get<double>(), data["box_size"][1].get<double>(),
                  data["box_size"][2].get<double>());
  std::vector<Vec3> out;
  for (std::size_t i = 0; i + 5 < bytes.size(); i += 6) {
    Vec3 p;
    for (int a = 0; a < 3; ++a) {
      const unsigned q = bytes[i + 2 * a] | (bytes[i + 2 * a + 1] << 8);
      p[a] = min[a] + q / 65535.0 * size[a];
    }
    out.push_back(p);
  }
  return out;
}

TEST(MissionPage, EmbedsTheMissionCounts) {
  const Fixture f;
  const std::string html = view::missionPage(f.scene, f.missions, &f.flight);
  const nlohmann::json summary = block(html, "uavip-summary");
  ASSERT_TRUE(summary.is_object());
  EXPECT_EQ(summary["photos"], 3);  // every stop, flown or not
  EXPECT_EQ(summary["photos_flown"], 2);
  EXPECT_EQ(summary["waypoints"], 3);  // surfaces' own paths
  EXPECT_EQ(summary["flight_waypoints"], 6);
  EXPECT_EQ(summary["sorties"], 2);
  EXPECT_EQ(summary["cloud_points"], 81 + 5 + 3);
  EXPECT_EQ(summary["cloud_points_drawn"], 81 + 5 + 3);
  EXPECT_EQ(summary["scene_surfaces"], 1);
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_NE(html.find("REVISION=\"111\""), std::string::npos);  // three.js r111 is inlined
  EXPECT_EQ(html.find("<script src"), std::string::npos);       // nothing is loaded
}

TEST(MissionPage, QuantisedPositionsDecodeToTheInputs) {
  const Fixture f;
  const std::string html = view::missionPage(f.scene, f.missions, &f.flight);
  const nlohmann::json data = block(html, "uavip-data");
  ASSERT_TRUE(data.is_object());
  const auto cloud = decodePositions(data, data["cloud"]["pos"].get<std::string>());
  ASSERT_EQ(cloud.size(), f.scene.cloud.size());
  double step = 0.0;  // half a quantum on the longest axis [m]
  for (int a = 0; a < 3; ++a) step = std::max(step, data["box_size"][a].get<double>() / 65535.0);
  for (std::size_t i = 0; i < cloud.size(); ++i)
    EXPECT_LE((cloud[i] - f.scene.cloud[i]).norm(), step) << i;
  // Classes: the wall's points are surface points, then the obstacle, then the strays.
  const auto cls = unbase64(data["cloud"]["cls"].get<std::string>());
  ASSERT_EQ(cls.size(), cloud.size());
  EXPECT_EQ(cls[0], 1);
  EXPECT_EQ(cls[81], 2);
  EXPECT_EQ(cls[86], 0);
  const auto stops = decodePositions(data, data["stops"]["pos"].get<std::string>());
  ASSERT_EQ(stops.size(), 3u);
  EXPECT_LE((stops[2] - Vec3(9.0, 9.0, 9.0)).norm(), step);
  ASSERT_EQ(data["paths"].size(), 2u);
  EXPECT_EQ(data["paths"][0]["label"], "sortie 1");
  // The first sample of a sortie is home, 4 m from the nearest cloud point (0, 0, 0).
  const auto clearance = unbase64(data["paths"][0]["clearance_cm"].get<std::string>());
  ASSERT_GE(clearance.size(), 2u);
  EXPECT_EQ(clearance[0] | (clearance[1] << 8), 400);
}

TEST(MissionPage, ScriptsStayWholeAndOutputIsDeterministic) {
  Fixture f;
  f.scene.surfaces[0].id = 0;
  view::MissionPageOptions o;
  o.title = "a </script><b> title";
  const std::string html = view::missionPage(f.scene, f.missions, &f.flight, o);
  // Five script elements: summary, data, three.js, the page, its edit mode; a title
  // cannot close one.
  std::size_t closes = 0;
  for (auto at = html.find("</script>"); at != std::string::npos;
       at = html.find("</script>", at + 1))
    ++closes;
  EXPECT_EQ(closes, 5u);
  EXPECT_NE(html.find("<title>a &lt;/script&gt;&lt;b&gt; title</title>"), std::string::npos);
  EXPECT_EQ(html, view::missionPage(f.scene, f.missions, &f.flight, o));
}

TEST(MissionPage, SceneAloneHasNoFlight) {
  const Fixture f;
  const std::string html = view::missionPage(f.scene, nullptr);
  const nlohmann::json summary = block(html, "uavip-summary");
  EXPECT_EQ(summary["photos"], 0);
  EXPECT_EQ(summary["sorties"], 0);
  EXPECT_EQ(summary["cloud_points"], 89);
}

TEST(MissionPage, DecimatesTheCloudEvenly) {
  const Fixture f;
  view::MissionPageOptions o;
  o.max_cloud_points = 30;
  const nlohmann::json summary =
      block(view::missionPage(f.scene, f.missions, &f.flight, o), "uavip-summary");
  EXPECT_EQ(summary["cloud_points_drawn"], 30);  // every 3rd of 89
}

TEST(MissionPage, EmptySceneGivesAnEmptyPage) {
  const uavip::Scene empty;
  const std::string html = view::missionPage(empty, nullptr);
  const nlohmann::json summary = block(html, "uavip-summary");
  EXPECT_EQ(summary["cloud_points"], 0);
  EXPECT_EQ(summary["photos"], 0);
}

TEST(MissionPage, BadInputIsNamed) {
  const Fixture g;
  nlohmann::json bad = {{"surfaces", "none"}};
  try {
    (void)view::missionPage(g.scene, &bad, {}, "x/mission.json");
    FAIL() << "no error for a mission without surfaces";
  } catch (const uavip::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("x/mission.json"), std::string::npos) << e.what();
  }
  view::MissionPageOptions o;
  o.max_cloud_points = 0;
  EXPECT_THROW(o.validate(), uavip::InputError);
}

}  // namespace
