// uavip run → views, and uavip export, as a user runs them: files, exit codes,
// one-line errors.

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "tests/cli/cli_runner.h"

namespace {

namespace fs = std::filesystem;

using uavip::cli_test::Result;
using uavip::cli_test::slurp;
using uavip::cli_test::uavip;

/// One run of the single-plane scenario shared by the tests of this file.
class ExportCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("uavip_export_cli_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    run_ = uavip("run " + std::string(UAVIP_SOURCE_DIR) + "/scenarios/single_plane.yaml -o " +
                 (dir_ / "out").string());
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static std::string mission() { return (dir_ / "out/mission.json").string(); }
  static std::string path(const std::string& name) { return (dir_ / name).string(); }
  void expectBadInput(const std::string& args, const std::string& fragment) {
    const Result r = uavip(args);
    EXPECT_EQ(r.code, 2) << args << "\n" << r.out;
    EXPECT_NE(r.out.find(fragment), std::string::npos) << args << "\n" << r.out;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << "one line expected:\n" << r.out;
  }
  static fs::path dir_;
  static Result run_;
};

fs::path ExportCli::dir_;
Result ExportCli::run_;

TEST_F(ExportCli, RunWritesTheViewsAndASummary) {
  ASSERT_EQ(run_.code, 0) << run_.out;
  EXPECT_NE(run_.out.find("summary:"), std::string::npos) << run_.out;
  EXPECT_NE(run_.out.find("overview.png"), std::string::npos) << run_.out;
  const std::string png = slurp(dir_ / "out/overview.png");
  ASSERT_GT(png.size(), 8u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
  const std::string ply = slurp(dir_ / "out/scene.ply");
  EXPECT_EQ(ply.rfind("ply\nformat ascii 1.0\n", 0), 0u);
  const std::string obj = slurp(dir_ / "out/path.obj");
  EXPECT_NE(obj.find("\nl 1 2"), std::string::npos);
}

TEST_F(ExportCli, QgcPlanMatchesTheMission) {
  ASSERT_EQ(run_.code, 0) << run_.out;
  const Result r = uavip("export " + mission() +
                         " --format qgc-plan --origin 47.3977,8.5456,488 -o " + path("m.plan"));
  ASSERT_EQ(r.code, 0) << r.out;
  const auto m = nlohmann::json::parse(slurp(dir_ / "out/mission.json"));
  const auto plan = nlohmann::json::parse(slurp(dir_ / "m.plan"));
  const auto& s = m["surfaces"][0];
  std::map<int, std::size_t> count;
  for (const auto& it : plan["mission"]["items"]) ++count[it["command"].get<int>()];
  EXPECT_EQ(count[16], s["waypoints"].size());
  EXPECT_EQ(count[2000], s["stops"].size());
  EXPECT_EQ(count[1000], s["stops"].size());
  EXPECT_NEAR(plan["mission"]["plannedHomePosition"][0].get<double>(), 47.3977, 1e-12);
}

TEST_F(ExportCli, WplAndCsv) {
  ASSERT_EQ(run_.code, 0) << run_.out;
  ASSERT_EQ(
      uavip("export " + mission() + " --format wpl --origin 47.3977,8.5456,488 -o " + path("m.wpl"))
          .code,
      0);
  const std::string wpl = slurp(dir_ / "m.wpl");
  EXPECT_EQ(wpl.rfind("QGC WPL 110\n0\t1\t0\t16\t", 0), 0u) << wpl.substr(0, 80);
  ASSERT_EQ(uavip("export " + mission() + " --format csv --origin 47.3977,8.5456,488 -q -o " +
                  path("m.csv"))
                .code,
            0);
  const auto m = nlohmann::json::parse(slurp(dir_ / "out/mission.json"));
  const std::string csv = slurp(dir_ / "m.csv");
  EXPECT_EQ(static_cast<std::size_t>(std::count(csv.begin(), csv.end(), '\n')),
            1 + m["surfaces"][0]["waypoints"].size());
}

TEST_F(ExportCli, BadInputIsOneLineAndExit2) {
  ASSERT_EQ(run_.code, 0) << run_.out;
  const std::string base = "export " + mission() + " --format wpl -o " + path("x.wpl");
  expectBadInput(base, "pass --origin");
  expectBadInput(base + " --origin 47.3,8.5", "'47.3,8.5'");
  expectBadInput(base + " --origin 95,8.5,400", "latitude");
  expectBadInput("export " + mission() + " --format kmz --origin 1,2,3 -o " + path("x"), "kmz");
  expectBadInput("export " + path("nope.json") + " --format wpl --origin 1,2,3 -o " + path("x"),
                 "nope.json");
  std::ofstream(path("bad.json")) << "{ not json";
  expectBadInput("export " + path("bad.json") + " --format wpl --origin 1,2,3 -o " + path("x"),
                 "bad.json");
  expectBadInput(base + " --origin 1,2,3 --surface 9", "no surface with id 9");
  EXPECT_FALSE(fs::exists(dir_ / "x.wpl"));
}

TEST_F(ExportCli, TheOrderedFlightIsExportedAndALegMovedIntoTheStructureIsRefused) {
  ASSERT_EQ(run_.code, 0) << run_.out;
  EXPECT_NE(run_.out.find("flight: "), std::string::npos) << run_.out;
  const auto m = nlohmann::json::parse(slurp(dir_ / "out/mission.json"));
  const auto& flight = m["flight"];
  ASSERT_EQ(flight["status"], "ok") << flight.dump();
  ASSERT_EQ(flight["sorties"].size(), 1u);
  const auto& sortie = flight["sorties"][0];
  EXPECT_EQ(sortie["waypoints"].front(), sortie["waypoints"].back());  // home to home
  EXPECT_EQ(sortie["waypoints"].front(), flight["home"]);
  const Result r = uavip("export " + mission() +
                         " --surface all --format qgc-plan --origin 47.3977,8.5456,488 -o " +
                         path("flight.plan"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("sortie 1"), std::string::npos) << r.out;
  const auto plan = nlohmann::json::parse(slurp(dir_ / "flight.plan"));
  std::map<int, std::size_t> count;
  for (const auto& it : plan["mission"]["items"]) ++count[it["command"].get<int>()];
  EXPECT_EQ(count[16], sortie["waypoints"].size());
  EXPECT_EQ(count[2000], sortie["stops"].size());
  expectBadInput(
      "export " + mission() + " --sortie 2 --format wpl --origin 1,2,3 -o " + path("x.wpl"),
      "--sortie");

  // A waypoint on the plane itself (a photo's centre) inserted after home.
  auto changed = m;
  auto& s = changed["flight"]["sorties"][0];
  s["waypoints"].insert(s["waypoints"].begin() + 1, m["surfaces"][0]["stops"][0]["target"]);
  for (auto& st : s["stops"])
    if (st["waypoint"].get<int>() >= 1) st["waypoint"] = st["waypoint"].get<int>() + 1;
  std::ofstream(dir_ / "out/changed.json") << changed.dump();
  const Result bad =
      uavip("export " + (dir_ / "out/changed.json").string() +
            " --surface all --format qgc-plan --origin 47.3977,8.5456,488 -o " + path("bad.plan"));
  EXPECT_EQ(bad.code, 3) << bad.out;
  EXPECT_NE(bad.out.find("sortie 1, segment 0"), std::string::npos) << bad.out;
  EXPECT_EQ(std::count(bad.out.begin(), bad.out.end(), '\n'), 1) << bad.out;
  EXPECT_FALSE(fs::exists(dir_ / "bad.plan"));
  const Result bad_kmz =
      uavip("export " + (dir_ / "out/changed.json").string() +
            " --surface all --format dji-kmz --origin 47.3977,8.5456,488 -o " + path("bad.kmz"));
  EXPECT_EQ(bad_kmz.code, 3) << bad_kmz.out;
  EXPECT_NE(bad_kmz.out.find("sortie 1, segment 0"), std::string::npos) << bad_kmz.out;
  EXPECT_FALSE(fs::exists(dir_ / "bad.kmz"));
}

TEST_F(ExportCli, DjiKmzPerSortieAndItsMistakes) {
  ASSERT_EQ(run_.code, 0) << run_.out;
  const std::string base = "export " + mission() + " --surface all --format dji-kmz ";
  Result r = uavip(base + "--origin 47.3977,8.5456,488 --drone m30t -o " + path("site.kmz"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("Matrice 30T"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("validated against the scene as flown"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(dir_ / "site.kmz"));
  // A sortie longer than --max-waypoints: routes of at most that many, with a message.
  r = uavip(base + "--origin 47.3977,8.5456,488 --max-waypoints 100 -o " + path("split.kmz"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("split into"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(dir_ / "split_part1.kmz"));
  EXPECT_TRUE(fs::exists(dir_ / "split_part2.kmz"));
  // Mistakes: one line, exit 2, nothing written.
  expectBadInput(base + "--origin 47.3977,8.5456,488 --drone phantom4 -o " + path("x.kmz"), "m4t");
  expectBadInput(base + "--origin 47.3977,8.5456,488 --height-mode msl -o " + path("x.kmz"),
                 "--height-mode");
  expectBadInput(base + "-o " + path("x.kmz"), "pass --origin");
  expectBadInput(base + "--origin 47.3977,8.5456,488 --takeoff-height 0.5 -o " + path("x.kmz"),
                 "--takeoff-height");
  // Without the geoid grid the heights cannot be right: refused, never a zero undulation.
  fs::create_directories(dir_ / "no_grids");
  ::setenv("PROJ_DATA", path("no_grids").c_str(), 1);  // the child's PROJ finds no grid there
  expectBadInput(base + "--origin 47.3977,8.5456,488 -o " + path("x.kmz"), "proj-data");
  ::unsetenv("PROJ_DATA");
  EXPECT_FALSE(fs::exists(dir_ / "x.kmz"));
}

TEST_F(ExportCli, BlockedSurfaceExits3) {
  // A mission.json as run writes it for a blocked surface (no waypoints).
  std::ofstream(path("blocked.json"))
      << R"({"format": "uavip-mission", "surfaces": [{"surface_id": 0,
    "status": "blocked", "reason": "2 of 2 stops infeasible", "stops": [], "waypoints": []}]})";
  const Result r = uavip("export " + path("blocked.json") +
                         " --format wpl --origin 1,2,3 --surface 0 -o " + path("b.wpl"));
  EXPECT_EQ(r.code, 3) << r.out;
  EXPECT_NE(r.out.find("blocked"), std::string::npos) << r.out;
  EXPECT_EQ(
      uavip("export " + path("blocked.json") + " --format wpl --origin 1,2,3 -o " + path("b.wpl"))
          .code,
      3);
  EXPECT_FALSE(fs::exists(dir_ / "b.wpl"));
}

}  // namespace
