#include <gtest/gtest.h>

#include "uavip/core/error.h"
#include "uavip/io/json_reader.h"
#include "uavip/io/mission_json.h"
#include "uavip/io/scene_json.h"

namespace uavip::io {
namespace {

Scene smallScene() {
  Scene scene;
  Surface s;
  s.id = 0;
  s.plane.normal = Vec3(0, -1, 0);
  s.plane.offset = 0.0;
  s.inliers = {{0, 0, 0}, {4, 0, 0}, {4, 0, 2}, {0, 0, 2}, {2, 0, 1}};
  s.boundary = {{0, 0, 0}, {4, 0, 0}, {4, 0, 2}, {0, 0, 2}};
  s.centroid = Vec3(2, 0, 1);
  s.axis_u = Vec3(1, 0, 0);
  s.axis_v = s.plane.normal.cross(s.axis_u);
  s.area_m2 = 8.0;
  s.density_area_m2 = 7.5;
  scene.surfaces.push_back(s);
  Obstacle o;
  o.id = 0;
  o.points = {{5, 5, 5}, {5.5, 5, 5.25}};
  o.aabb_min = Vec3(5, 5, 5);
  o.aabb_max = Vec3(5.5, 5, 5.25);
  scene.obstacles.push_back(o);
  scene.cloud = s.inliers;
  scene.cloud.insert(scene.cloud.end(), o.points.begin(), o.points.end());
  return scene;
}

TEST(SceneJson, RoundTripRebuildsTheCloudFromSurfacesAndObstacles) {
  const Scene in = smallScene();
  const Scene out = sceneFromJson(sceneToJson(in), "scene.json");
  ASSERT_EQ(out.surfaces.size(), 1u);
  ASSERT_EQ(out.obstacles.size(), 1u);
  EXPECT_EQ(out.cloud.size(), in.cloud.size());
  EXPECT_LT((out.surfaces[0].plane.normal - in.surfaces[0].plane.normal).norm(), 1e-9);
  EXPECT_DOUBLE_EQ(out.surfaces[0].area_m2, 8.0);
  EXPECT_EQ(out.surfaces[0].boundary.size(), 4u);
  EXPECT_LT((out.surfaces[0].axis_v - in.surfaces[0].axis_v).norm(), 1e-9);
  EXPECT_EQ(out.obstacles[0].aabb_max, in.obstacles[0].aabb_max);
}

TEST(SceneJson, BadFieldsAreNamed) {
  nlohmann::json j = sceneToJson(smallScene());
  j["surfaces"][0].erase("normal");
  try {
    sceneFromJson(j, "s.json");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("s.json: surfaces[0].normal is missing"),
              std::string::npos)
        << e.what();
  }
  j = sceneToJson(smallScene());
  j["obstacles"][0]["points"][1] = {1, "a", 2};
  EXPECT_THROW(sceneFromJson(j, "s.json"), InputError);
  EXPECT_THROW(sceneFromJson(nlohmann::json::object({{"surfaces", nlohmann::json::array()},
                                                     {"obstacles", nlohmann::json::array()}}),
                             "s.json"),
               InputError);  // no points at all
  // Ids out of range or used twice, and negative areas, are named.
  auto expectField = [](const nlohmann::json& scene, const std::string& fragment) {
    try {
      sceneFromJson(scene, "s.json");
      ADD_FAILURE() << "accepted: " << fragment;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  };
  j = sceneToJson(smallScene());
  j["surfaces"][0]["id"] = 4294967296LL;
  expectField(j, "surfaces[0].id");
  j = sceneToJson(smallScene());
  j["surfaces"][0]["id"] = -1;
  expectField(j, "surfaces[0].id");
  j = sceneToJson(smallScene());
  j["surfaces"][0]["area_m2"] = -5.0;
  expectField(j, "surfaces[0].area_m2");
  j = sceneToJson(smallScene());
  j["surfaces"].push_back(j["surfaces"][0]);
  expectField(j, "surfaces[" + std::to_string(j["surfaces"].size() - 1) + "].id");
}

TEST(JsonReader, NamesTheFieldAndBoundsLocalCoordinates) {
  const JsonReader r("f.json");
  auto message = [](const auto& call) -> std::string {
    try {
      call();
    } catch (const InputError& e) {
      return e.what();
    }
    return "accepted";
  };
  const nlohmann::json j = {
      {"p", {1.0, 2.0, 3.0}}, {"far", {1e155, 0.0, 0.0}}, {"n", 5}, {"big", 4294967296LL}};
  EXPECT_EQ(r.vec3(j["p"], "p"), Vec3(1, 2, 3));
  EXPECT_NE(
      message([&] { r.vec3(j["far"], "far"); }).find("f.json: far (1e+155, 0, 0) lies beyond"),
      std::string::npos);
  EXPECT_NO_THROW(r.vec3(j["far"], "far", false));  // not a position: only finite
  EXPECT_NE(message([&] { r.at(j, "q", "top"); }).find("f.json: top.q is missing"),
            std::string::npos);
  EXPECT_EQ(r.integer(j["n"], "n", 0, 10), 5);
  EXPECT_NE(message([&] {
              r.integer(j["big"], "big", 0, 1'000'000);
            }).find("big must be a whole number in [0, 1000000]"),
            std::string::npos);
  EXPECT_NE(
      message([&] { r.number(j["n"], "n", 0.0, 1.0, "m"); }).find("n must be in [0, 1] m, got 5"),
      std::string::npos);
  EXPECT_NE(message([&] { r.parse("{\"a\": \n [1, 2"); }).find("f.json:2: not valid JSON (byte"),
            std::string::npos);
  // A fuzz finding: a number beyond a double threw nlohmann's out_of_range, not an InputError.
  EXPECT_NE(message([&] { r.parse("{\"a\": 1e999}"); }).find("f.json: not valid JSON"),
            std::string::npos);
}

/// A mission of two surfaces and one sortie, as the planner writes it.
nlohmann::json smallMission() {
  auto stop = [](double x) {
    return nlohmann::json{{"position", {x, 0.0, 2.0}},
                          {"yaw_deg", 90.0},
                          {"gimbal_pitch_deg", 0.0},
                          {"problem", "none"}};
  };
  nlohmann::json s0 = {{"surface_id", 0},
                       {"status", "ok"},
                       {"reason", ""},
                       {"stops", {stop(0), stop(2)}},
                       {"waypoints", {{0.0, 0.0, 2.0}, {1.0, 0.0, 2.5}, {2.0, 0.0, 2.0}}}};
  nlohmann::json s3 = {{"surface_id", 3},
                       {"status", "blocked"},
                       {"reason", "no stop reachable"},
                       {"stops", {stop(9)}},
                       {"waypoints", nlohmann::json::array()}};
  nlohmann::json sortie = {
      {"waypoints", {{0.0, 0.0, 0.0}, {0.0, 0.0, 2.0}, {2.0, 0.0, 2.0}, {0.0, 0.0, 0.0}}},
      {"stops",
       {{{"surface_id", 0}, {"stop", 0}, {"waypoint", 1}},
        {{"surface_id", 0}, {"stop", 1}, {"waypoint", 2}}}}};
  return {{"inflation_radius_m", 0.6},
          {"surfaces", {s0, s3}},
          {"flight", {{"status", "ok"}, {"reason", ""}, {"sorties", {sortie}}}}};
}

TEST(MissionJson, ReadsBackWhatThePlannerWrote) {
  const MissionRecord m = missionFromJson(smallMission(), "m.json");
  EXPECT_DOUBLE_EQ(m.inflation_radius_m, 0.6);
  ASSERT_EQ(m.surfaces.size(), 2u);
  EXPECT_TRUE(m.surfaces[0].flyable());
  EXPECT_FALSE(m.surface(3)->flyable());
  EXPECT_EQ(m.surface(7), nullptr);
  EXPECT_EQ(m.surfaces[0].waypoints[1], Vec3(1.0, 0.0, 2.5));
  EXPECT_DOUBLE_EQ(m.surfaces[0].stops[1].yaw_deg, 90.0);
  ASSERT_TRUE(m.flight.has_value());
  ASSERT_EQ(m.flight->sorties.size(), 1u);
  EXPECT_EQ(m.flight->sorties[0].stops[1].waypoint, 2u);
  nlohmann::json old = smallMission();
  old.erase("flight");
  EXPECT_FALSE(missionFromJson(old, "m.json").flight.has_value());  // files of older versions
}

TEST(MissionJson, InconsistentFilesAreNamed) {
  auto expectField = [](const nlohmann::json& mission, const std::string& fragment) {
    try {
      missionFromJson(mission, "m.json");
      ADD_FAILURE() << "accepted: " << fragment;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("m.json: " + fragment), std::string::npos) << e.what();
    }
  };
  nlohmann::json j = smallMission();
  j["surfaces"][1]["surface_id"] = 0;
  expectField(j, "surfaces[1].surface_id 0 is used by an earlier surface");
  j = smallMission();
  j["surfaces"][0]["waypoints"][1] = {1e155, 0.0,
                                      2.0};  // validate once called such a path collision-free
  expectField(j, "surfaces[0].waypoints[1]");
  j = smallMission();
  j["surfaces"][0]["stops"][0]["position"][2] = 1.7e12;  // export once wrote this altitude
  expectField(j, "surfaces[0].stops[0].position");
  j = smallMission();
  j["flight"]["sorties"][0]["stops"][1]["waypoint"] = 1;  // not later than the previous stop
  expectField(j, "flight.sorties[0].stops[1] names no stop");
  j = smallMission();
  j["flight"]["sorties"][0]["stops"][0]["stop"] = 5;
  expectField(j, "flight.sorties[0].stops[0] names no stop");
  j = smallMission();
  j["flight"]["sorties"][0]["waypoints"][1] = {0.0, 0.5, 2.0};
  expectField(j, "flight.sorties[0].stops[0] is not at its waypoint");
  j = smallMission();
  j["inflation_radius_m"] = -1.0;
  expectField(j, "inflation_radius_m must be in");
  j = smallMission();
  j["surfaces"][0].erase("stops");
  expectField(j, "surfaces[0].stops is missing");
}

TEST(MissionJson, CarriesTheContractFields) {
  planning::SurfaceMission m;
  m.surface_id = 3;
  m.status = planning::SurfaceStatus::Blocked;
  m.reason = "2 of 2 stops infeasible";
  coverage::Stop s;
  s.position = Vec3(1, 2, 3);
  s.yaw_deg = 90;
  s.gimbal_pitch_deg = -10;
  m.strategy.stops = {s, s};
  m.stop_problems = {planning::StopProblem::InObstacleSpace, planning::StopProblem::Unreachable};
  m.validation.min_clearance_m = std::numeric_limits<double>::infinity();
  const nlohmann::json j = missionToJson({m}, {{"planner", "astar"}});
  EXPECT_EQ(j["planner"], "astar");
  const auto& js = j["surfaces"][0];
  EXPECT_EQ(js["surface_id"], 3);
  EXPECT_EQ(js["status"], "blocked");
  EXPECT_EQ(js["reason"], m.reason);
  EXPECT_EQ(js["stops"].size(), 2u);
  EXPECT_EQ(js["stops"][0]["position"], nlohmann::json::array({1.0, 2.0, 3.0}));
  EXPECT_EQ(js["stops"][0]["yaw_deg"], 90.0);
  EXPECT_EQ(js["stops"][1]["gimbal_pitch_deg"], -10.0);
  EXPECT_NE(js["stops"][0]["problem"], js["stops"][1]["problem"]);
  EXPECT_TRUE(js["waypoints"].is_array());
  EXPECT_TRUE(js["validation"]["min_clearance_m"].is_null());  // JSON has no infinity
  EXPECT_TRUE(js.contains("raw_waypoint_count"));
  EXPECT_TRUE(js.contains("path_length_m"));
}

}  // namespace
}  // namespace uavip::io
