// The uavip executable as a user runs it: exit codes, one-line errors, outputs.

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "tests/cli/cli_runner.h"
#include "uavip/core/geometry.h"

namespace {

namespace fs = std::filesystem;

using uavip::cli_test::Result;
using uavip::cli_test::slurp;
using uavip::cli_test::uavip;

std::string scenario(const std::string& name) {
  return std::string(UAVIP_SOURCE_DIR) + "/scenarios/" + name;
}

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("uavip_cli_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(path(name)) << text;
    return path(name);
  }
  /// Exit code 2 and a single line that mentions `fragment`.
  void expectBadInput(const std::string& args, const std::string& fragment) {
    const Result r = uavip(args);
    EXPECT_EQ(r.code, 2) << args << "\n" << r.out;
    EXPECT_NE(r.out.find(fragment), std::string::npos) << args << "\n" << r.out;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << "one line expected:\n" << r.out;
  }
  fs::path dir_;
};

TEST_F(Cli, HelpAndVersion) {
  Result r = uavip("--help");
  EXPECT_EQ(r.code, 0);
  for (const char* cmd : {"run", "detect", "plan"}) EXPECT_NE(r.out.find(cmd), std::string::npos);
  r = uavip("run --help");
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("--surface"), std::string::npos);
  EXPECT_NE(r.out.find("astar"), std::string::npos);
  r = uavip("--version");
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("uavip"), std::string::npos);
  EXPECT_EQ(uavip("").code, 2);
  EXPECT_EQ(uavip("fly").code, 2);
}

TEST_F(Cli, RunWritesTheContractFiles) {
  const Result r = uavip("run " + scenario("single_plane.yaml") + " -o " + path("out"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(fs::exists(dir_ / "out/cloud_clean.pcd"));
  const auto scene = nlohmann::json::parse(slurp(dir_ / "out/scene.json"));
  ASSERT_EQ(scene["surfaces"].size(), 1u);
  for (const char* k : {"id", "normal", "area_m2", "boundary", "points"})
    EXPECT_TRUE(scene["surfaces"][0].contains(k)) << k;
  const auto mission = nlohmann::json::parse(slurp(dir_ / "out/mission.json"));
  const auto& m = mission["surfaces"][0];
  EXPECT_EQ(m["status"], "ok");
  EXPECT_GT(m["stops"].size(), 100u);
  for (const char* k : {"position", "yaw_deg", "gimbal_pitch_deg"})
    EXPECT_TRUE(m["stops"][0].contains(k)) << k;
  EXPECT_GT(m["waypoints"].size(), 0u);
  EXPECT_EQ(m["validation"]["collision_free"], true);
  for (const auto& e : fs::directory_iterator(dir_ / "out")) {
    EXPECT_EQ(e.path().string().find(".tmp"), std::string::npos)
        << "temporary file left: " << e.path();
  }
}

TEST_F(Cli, NoSurfaceIsAResultNotAnError) {
  const Result r = uavip("run " + scenario("single_point.yaml") + " -o " + path("out"));
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("no surface detected"), std::string::npos) << r.out;
  const auto mission = nlohmann::json::parse(slurp(dir_ / "out/mission.json"));
  EXPECT_TRUE(mission["surfaces"].empty());
}

TEST_F(Cli, DetectThenPlanOneSurface) {
  // A wall as an .xyz file, every 5 cm.
  std::ostringstream xyz;
  for (int i = 0; i <= 100; ++i)
    for (int j = 0; j <= 60; ++j) xyz << i * 0.05 << " 0 " << 0.5 + j * 0.05 << "\n";
  const std::string cloud = write("wall.xyz", xyz.str());
  Result r = uavip("detect " + cloud + " -o " + path("d"));
  ASSERT_EQ(r.code, 0) << r.out;
  r = uavip("plan " + path("d/scene.json") + " --surface 0 -o " + path("p"));
  ASSERT_EQ(r.code, 0) << r.out;
  const auto mission = nlohmann::json::parse(slurp(dir_ / "p/mission.json"));
  EXPECT_EQ(mission["surfaces"][0]["status"], "ok");
  expectBadInput("plan " + path("d/scene.json") + " --surface 9 -o " + path("p"),
                 "no surface with id 9");
}

TEST_F(Cli, CoverStructureFlowsIntoValidateAndExport) {
  // A 2 m pole (curved: no plane of 2 m2) as an .xyz file: plane by plane nothing to fly.
  std::ostringstream xyz;
  for (int k = 0; k <= 40; ++k)
    for (int j = 0; j < 32; ++j)
      xyz << 0.25 * std::cos(j * 0.19635) << " " << 0.25 * std::sin(j * 0.19635) << " "
          << 1.0 + k * 0.05 << "\n";
  const std::string cloud = write("pole.xyz", xyz.str());
  Result r = uavip("detect " + cloud + " -o " + path("d"));
  ASSERT_EQ(r.code, 0) << r.out;
  const std::string config = write("cam.yaml",
                                   "camera: {fx: 417, fy: 461, image_px: [640, 480]}\n"
                                   "coverage: {standoff_m: 2.5}\nuav: {inflation_radius_m: 0.3}\n");
  r = uavip("plan " + path("d/scene.json") + " --cover structure -c " + config + " -o " +
            path("p"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("rule (a)"), std::string::npos) << r.out;
  const auto mission = nlohmann::json::parse(slurp(dir_ / "p/mission.json"));
  const auto scene = nlohmann::json::parse(slurp(dir_ / "d/scene.json"));
  ASSERT_EQ(mission["surfaces"].size(), 1u);
  const auto& s = mission["surfaces"][0];
  EXPECT_EQ(s["kind"], "structure");
  EXPECT_EQ(s["surface_id"].get<int>(),
            static_cast<int>(scene["surfaces"].size()));  // above the scene's ids
  EXPECT_GT(s["stop_count"].get<int>(), 3);
  EXPECT_GE(mission["structure"]["coverage_rule_a"].get<double>(), 0.95);
  for (const auto& st : mission["flight"]["sorties"][0]["stops"])
    EXPECT_EQ(st["surface_id"], s["surface_id"]);
  r = uavip("validate " + path("p/mission.json") + " --scene " + path("d/scene.json"));
  EXPECT_EQ(r.code, 0) << r.out;
  r = uavip("export " + path("p/mission.json") + " --scene " + path("d/scene.json") +
            " --surface all --format csv --origin 47.3977,8.5456,488 -o " + path("p/pole.csv"));
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(fs::exists(path("p/pole.csv")));
}

TEST_F(Cli, TheFlightKeepsClearOfPointsOutlierRemovalDrops) {
  // A wall (6 × 3 m, 5 cm lattice) and two sparse poles 1.5 m in front of and behind
  // it, where the photo stops would be: outlier removal drops every pole point, so a
  // safety map of the cleaned cloud would fly through them.
  std::ostringstream xyz;
  for (int i = 0; i <= 120; ++i)
    for (int j = 0; j <= 60; ++j) xyz << i * 0.05 << " 0 " << 0.5 + j * 0.05 << "\n";
  uavip::PointList poles;
  for (const double y : {-1.5, 1.5})
    for (int k = 0; k <= 10; ++k) poles.emplace_back(3.0, y, 0.5 + 0.3 * k);
  for (const auto& p : poles) xyz << p.x() << " " << p.y() << " " << p.z() << "\n";
  const std::string cloud = write("poles.xyz", xyz.str());
  Result r = uavip("detect " + cloud + " --no-views -o " + path("d"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("(22 that outlier removal dropped)"), std::string::npos) << r.out;
  ASSERT_TRUE(fs::exists(dir_ / "d/cloud_safety.pcd"));
  r = uavip("plan " + path("d/scene.json") + " --surface 0 --no-views -o " + path("d"));
  ASSERT_EQ(r.code, 0) << r.out;
  const auto mission = nlohmann::json::parse(slurp(dir_ / "d/mission.json"));
  const double inflation = mission["inflation_radius_m"].get<double>();
  double nearest = 1e9;  // brute force: every sortie segment against every pole point
  for (const auto& sortie : mission["flight"]["sorties"]) {
    const auto& w = sortie["waypoints"];
    for (std::size_t i = 0; i + 1 < w.size(); ++i) {
      const uavip::Vec3 a(w[i][0], w[i][1], w[i][2]), b(w[i + 1][0], w[i + 1][1], w[i + 1][2]);
      for (const auto& p : poles) nearest = std::min(nearest, uavip::pointSegmentDistance(p, a, b));
    }
  }
  EXPECT_GE(nearest, inflation) << "the flight passes " << nearest << " m from a pole";
  // validate re-reads the input named in scene.json (sha256 checked) and measures every point.
  r = uavip("validate " + path("d/mission.json"));
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("poles.xyz: 7403 points (from scene.json, sha256 checked)"),
            std::string::npos)
      << r.out;
  // A waypoint moved 0.3 m from a pole point fails.
  auto moved = mission;
  moved["surfaces"][0]["waypoints"][1] = {3.0, 1.5, 2.0};
  moved["surfaces"][0]["waypoints"][2] = {3.0, -1.5, 2.0};
  std::ofstream(dir_ / "d/moved.json") << moved.dump();
  r = uavip("validate " + path("d/moved.json") + " --scene " + path("d/scene.json"));
  EXPECT_EQ(r.code, 3) << r.out;
  EXPECT_NE(r.out.find("VIOLATION"), std::string::npos) << r.out;
}

TEST_F(Cli, BlockedSurfaceMakesPlanExit3) {
  // The one chosen surface cannot be flown: exit 3 from run as from plan, with the
  // scene and the mission written (its reason is there).
  Result r = uavip("run " + scenario("cube_crossed_planes.yaml") + " --surface 0 -o " + path("x"));
  ASSERT_EQ(r.code, 3) << r.out;
  EXPECT_NE(r.out.find("blocked"), std::string::npos) << r.out;
  ASSERT_TRUE(fs::exists(dir_ / "x/mission.json"));
  // The paper's perpendicular stops only (stop repair would move them, see PaperCases).
  r = uavip("plan " + path("x/scene.json") + " --surface 0 -c " +
            write("norepair.yaml", "mission: {repair_stops: false}\n") + " -o " + path("p"));
  EXPECT_EQ(r.code, 3) << r.out;
}

TEST_F(Cli, EverySurfaceBlockedIsCountedAndSaysWhatToChange) {
  ASSERT_EQ(uavip("run " + scenario("single_cube.yaml") + " --no-views -o " + path("c")).code, 0);
  std::ifstream in(path("c/scene.json"));
  const std::size_t surfaces = nlohmann::json::parse(in)["surfaces"].size();
  ASSERT_GT(surfaces, 1u);
  // A 4 m UAV fits nowhere near a 3 m cube at its standoff.
  const Result r = uavip("plan " + path("c/scene.json") + " --surface all --no-views -q -c " +
                         write("huge.yaml", "uav: {size_m: [4, 4, 4]}\n") + " -o " + path("p"));
  EXPECT_EQ(r.code, 3) << r.out;
  const std::string count =
      std::to_string(surfaces) + " of " + std::to_string(surfaces) + " chosen surfaces";
  EXPECT_NE(r.out.find(count), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("try a smaller uav.inflation_radius_m"), std::string::npos) << r.out;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;  // one line
}

TEST_F(Cli, BadInputIsOneLineAndExit2) {
  expectBadInput("run " + path("nope.yaml"), "nope.yaml: no such file");
  expectBadInput(
      "run " +
          write("k.yaml", "name: t\nworld: [{type: point, at: [0,0,0]}]\nsensing: {spacing: 1}\n"),
      "sensing.spacing");
  expectBadInput(
      "run " + write("t.yaml", "name: t\nworld: [{type: point, at: [0,0,x]}]\nsensing: {}\n"),
      "world[0].at");
  expectBadInput("run " + scenario("single_plane.yaml") + " --planner nope -o " + path("o"),
                 "nope");
  expectBadInput("run " + scenario("single_plane.yaml") + " --surface 42 -o " + path("o"),
                 "no surface with id 42");
  expectBadInput("detect " + write("e.xyz", "") + " -o " + path("o"), "no points");
  expectBadInput("detect " + write("n.xyz", "0 0 0\nnan 1 1\n") + " -o " + path("o"), "n.xyz:2");
  expectBadInput("detect " + write("c.xyz", "0 0 0\n") + " -c " +
                     write("c.yaml", "preprocess: {voxel_m: -1}\n") + " -o " + path("o"),
                 "voxel_m");
  expectBadInput("plan " + write("s.json", "{}") + " --surface 0 -o " + path("o"), "surfaces");
  const std::string start_inside =
      write("s.yaml", slurp(scenario("single_plane.yaml")) + "mission: {start: [4.0, 0.0, 2.0]}\n");
  expectBadInput("run " + start_inside + " -o " + path("o"), "start");
}

TEST_F(Cli, AFailedRunKeepsEarlierResults) {
  ASSERT_EQ(uavip("run " + scenario("single_plane.yaml") + " -o " + path("out")).code, 0);
  const std::string before = slurp(dir_ / "out/mission.json");
  EXPECT_EQ(uavip("run " + scenario("single_plane.yaml") + " --surface 5 -o " + path("out")).code,
            2);
  EXPECT_EQ(slurp(dir_ / "out/mission.json"), before);
}

}  // namespace
