// `uavip validate` as a user runs it: a planned mission passes, a waypoint moved
// into the structure fails naming the segment, bad input exits 2 with one line.

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "tests/cli/cli_runner.h"

namespace {

namespace fs = std::filesystem;

using uavip::cli_test::Result;
using uavip::cli_test::uavip;

nlohmann::json readJson(const fs::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}

void writeJson(const fs::path& p, const nlohmann::json& j) { std::ofstream(p) << j.dump(1); }

std::size_t lines(const std::string& s) {
  return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n'));
}

class ValidateCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("uavip_validate_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    const std::string scenario = std::string(UAVIP_SOURCE_DIR) + "/scenarios/single_cube.yaml";
    run_ = uavip("run " + scenario + " -q -o " + (dir_ / "out").string());
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static fs::path out() { return dir_ / "out"; }

  static inline fs::path dir_;
  static inline Result run_;
};

TEST_F(ValidateCli, PlannedMissionPasses) {
  ASSERT_EQ(run_.code, 0) << run_.out;
  const Result r = uavip("validate " + (out() / "mission.json").string());
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("all collision-free"), std::string::npos) << r.out;
  // One verdict line per surface of the mission.
  const auto mission = readJson(out() / "mission.json");
  for (const auto& s : mission["surfaces"]) {
    const std::string line =
        "surface " + std::to_string(s["surface_id"].get<int>()) + ": collision-free";
    EXPECT_NE(r.out.find(line), std::string::npos) << r.out;
  }
  EXPECT_NE(r.out.find("clearance 0.600 m"), std::string::npos)
      << r.out;  // the mission's inflation radius
  // And one per sortie of the ordered flight.
  ASSERT_GE(mission["flight"]["sorties"].size(), 1u);
  for (std::size_t k = 1; k <= mission["flight"]["sorties"].size(); ++k)
    EXPECT_NE(r.out.find("sortie " + std::to_string(k) + ": collision-free"), std::string::npos)
        << r.out;
}

TEST_F(ValidateCli, SortieWaypointMovedIntoTheCubeFails) {
  ASSERT_EQ(run_.code, 0) << run_.out;
  auto mission = readJson(out() / "mission.json");
  auto& wps = mission["flight"]["sorties"][0]["waypoints"];
  ASSERT_GT(wps.size(), 3u);
  wps[2] = {1.5, 1.5, 2.5};  // the cube's centre: segments 1 and 2 cross a face
  const fs::path edited = dir_ / "edited_sortie";
  fs::create_directories(edited);
  writeJson(edited / "mission.json", mission);
  const Result r = uavip("validate -q " + (edited / "mission.json").string() + " --scene " +
                         (out() / "scene.json").string());
  EXPECT_EQ(r.code, 3) << r.out;
  EXPECT_NE(r.out.find("sortie 1: segment 1 "), std::string::npos) << r.out;
}

TEST_F(ValidateCli, KeepOutRecordedInTheMissionIsChecked) {
  // Issue 33: mission.json's edits.keep_out are solid for validate too. A 0.4 m box on
  // the middle of the first sortie's first segment makes the flight fail.
  ASSERT_EQ(run_.code, 0) << run_.out;
  auto mission = readJson(out() / "mission.json");
  const auto& wps = mission["flight"]["sorties"][0]["waypoints"];
  ASSERT_GT(wps.size(), 2u);
  nlohmann::json centre = nlohmann::json::array();
  for (int k = 0; k < 3; ++k)
    centre.push_back(0.5 * (wps[0][k].get<double>() + wps[1][k].get<double>()));
  mission["edits"] = {{"file", "e.yaml"},
                      {"sha256", "0"},
                      {"applied", nlohmann::json::array()},
                      {"keep_out",
                       {{{"name", "box"},
                         {"shape", "box"},
                         {"center", centre},
                         {"size", {0.4, 0.4, 0.4}},
                         {"yaw_deg", 0.0}}}}};
  const fs::path edited = dir_ / "edited_keep_out";
  fs::create_directories(edited);
  writeJson(edited / "mission.json", mission);
  const Result r = uavip("validate -q " + (edited / "mission.json").string() + " --scene " +
                         (out() / "scene.json").string());
  EXPECT_EQ(r.code, 3) << r.out;
  EXPECT_NE(r.out.find("keep-out 0"), std::string::npos) << r.out;
}

TEST_F(ValidateCli, WaypointMovedIntoTheCubeFailsNamingTheSegment) {
  ASSERT_EQ(run_.code, 0) << run_.out;
  auto mission = readJson(out() / "mission.json");
  ASSERT_GT(mission["surfaces"][0]["waypoints"].size(), 6u);
  // The cube spans [0, 3] × [0, 3] × [1, 4]: waypoint 5 to its centre, so segment 4
  // (waypoint 4 → 5) is the first to cross a face.
  mission["surfaces"][0]["waypoints"][5] = {1.5, 1.5, 2.5};
  const fs::path edited = dir_ / "edited";
  fs::create_directories(edited);
  writeJson(edited / "mission.json", mission);
  const std::string scene = (out() / "scene.json").string();
  Result r = uavip("validate " + (edited / "mission.json").string() + " --scene " + scene);
  EXPECT_EQ(r.code, 3) << r.out;
  const int id = mission["surfaces"][0]["surface_id"].get<int>();
  EXPECT_NE(r.out.find("surface " + std::to_string(id) + ": VIOLATION: segment 4 "),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find(" from surface "), std::string::npos) << r.out;  // the face it crosses
  EXPECT_NE(r.out.find("1 with violations"), std::string::npos) << r.out;
  // With --quiet only the error line remains.
  r = uavip("validate -q " + (edited / "mission.json").string() + " --scene " + scene);
  EXPECT_EQ(r.code, 3);
  EXPECT_EQ(lines(r.out), 1u) << r.out;
  EXPECT_NE(r.out.find("segment 4"), std::string::npos) << r.out;

  // The untouched mission fails too when the clearance asked for is larger than its own.
  r = uavip("validate " + (out() / "mission.json").string() + " --clearance 3");
  EXPECT_EQ(r.code, 3) << r.out;
  // No input file behind a simulated scenario: the safety cloud stands for it, with its margin.
  EXPECT_NE(r.out.find("(required 3.03"), std::string::npos) << r.out;
}

TEST_F(ValidateCli, BadInputExitsTwoWithOneLine) {
  ASSERT_EQ(run_.code, 0) << run_.out;
  auto expectBad = [](const std::string& args, const std::string& fragment) {
    const Result r = uavip(args);
    EXPECT_EQ(r.code, 2) << args << "\n" << r.out;
    EXPECT_NE(r.out.find(fragment), std::string::npos) << args << "\n" << r.out;
    EXPECT_EQ(lines(r.out), 1u) << r.out;
  };
  expectBad("validate " + (dir_ / "nope.json").string(), "nope.json");
  // No scene.json next to the mission.
  const fs::path lonely = dir_ / "lonely";
  fs::create_directories(lonely);
  fs::copy_file(out() / "mission.json", lonely / "mission.json",
                fs::copy_options::overwrite_existing);
  expectBad("validate " + (lonely / "mission.json").string(), "scene.json");
  // Malformed fields are named.
  auto mission = readJson(out() / "mission.json");
  mission["surfaces"][0]["waypoints"][3] = {1.0, 2.0};
  writeJson(lonely / "bad.json", mission);
  expectBad(
      "validate " + (lonely / "bad.json").string() + " --scene " + (out() / "scene.json").string(),
      "surfaces[0].waypoints[3] must be [x, y, z]");
  mission = readJson(out() / "mission.json");
  mission.erase("inflation_radius_m");
  writeJson(lonely / "noradius.json", mission);
  expectBad("validate " + (lonely / "noradius.json").string() + " --scene " +
                (out() / "scene.json").string(),
            "inflation_radius_m");
  std::ofstream(lonely / "garbage.json") << "{ not json";
  expectBad("validate " + (lonely / "garbage.json").string(), "not valid JSON");
  expectBad("validate " + (out() / "mission.json").string() + " --clearance -1", "--clearance");
}

}  // namespace
