// `uavip run --uavs K` as a user runs it: K = 1 is today's mission; K = 2, 3 give a
// fleet that `uavip validate` finds conflict-free from the waypoints and the flight
// model alone, flies every stop once, and lands no later than one UAV and no sooner
// than the lower bound; a hand-made conflict exits 3; bad fleets exit 2 writing nothing.

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "tests/cli/cli_runner.h"
#include "tests/cli/fleet_sampling.h"

namespace {

namespace fs = std::filesystem;

using uavip::cli_test::Result;
using uavip::cli_test::sampledClosestApproach;
using uavip::cli_test::uavip;

nlohmann::json readJson(const fs::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}

/// Every "timings" object removed (benchmarks/compare_outputs.py).
nlohmann::json strip(const nlohmann::json& j) {
  if (j.is_object()) {
    nlohmann::json out = nlohmann::json::object();
    for (const auto& [k, v] : j.items())
      if (k != "timings") out[k] = strip(v);
    return out;
  }
  if (j.is_array()) {
    nlohmann::json out = nlohmann::json::array();
    for (const auto& v : j) out.push_back(strip(v));
    return out;
  }
  return j;
}

std::string scenario(const std::string& name) {
  return std::string(UAVIP_SOURCE_DIR) + "/scenarios/" + name + ".yaml";
}

class FleetCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("uavip_fleet_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    const std::vector<std::pair<std::string, int>> runs{
        {"single_plane", 0}, {"single_plane", 1}, {"single_plane", 2}, {"single_plane", 3},
        {"single_cube", 2},  {"single_cube", 3},  {"tower", 2}};
    for (const auto& [name, uavs] : runs) {
      const std::string key = name + "_" + std::to_string(uavs);
      const std::string flag = uavs > 0 ? " --uavs " + std::to_string(uavs) : "";
      runs_[key] = uavip("run " + scenario(name) + flag + " -q --no-views -o " + out(key).string());
    }
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static fs::path out(const std::string& key) { return dir_ / key; }

  static inline fs::path dir_;
  static inline std::map<std::string, Result> runs_;
};

TEST_F(FleetCli, OneUavIsTodaysMission) {
  ASSERT_EQ(runs_["single_plane_0"].code, 0) << runs_["single_plane_0"].out;
  ASSERT_EQ(runs_["single_plane_1"].code, 0) << runs_["single_plane_1"].out;
  const auto a = strip(readJson(out("single_plane_0") / "mission.json"));
  const auto b = strip(readJson(out("single_plane_1") / "mission.json"));
  EXPECT_FALSE(b.contains("fleet"));
  EXPECT_EQ(a, b);
}

/// Stops of the single flight, (surface, stop) → 1.
std::map<std::pair<int, int>, int> singleStops(const nlohmann::json& mission) {
  std::map<std::pair<int, int>, int> stops;
  for (const auto& s : mission["flight"]["sorties"])
    for (const auto& st : s["stops"])
      stops[{st["surface_id"].get<int>(), st["stop"].get<int>()}] = 1;
  return stops;
}

TEST_F(FleetCli, FleetsAreConflictFreeAndFlyEveryStopOnce) {
  for (const std::string key :
       {"single_plane_2", "single_plane_3", "single_cube_2", "single_cube_3", "tower_2"}) {
    SCOPED_TRACE(key);
    ASSERT_EQ(runs_[key].code, 0) << runs_[key].out;
    const auto mission = readJson(out(key) / "mission.json");
    ASSERT_TRUE(mission.contains("fleet"));
    const auto& fleet = mission["fleet"];
    EXPECT_EQ(fleet["status"], "ok");
    const std::size_t k = key.back() - '0';
    ASSERT_EQ(fleet["uavs"].size(), k);
    // Every stop of the single flight flown exactly once by the fleet.
    std::map<std::pair<int, int>, int> flown;
    for (const auto& u : fleet["uavs"])
      for (const auto& s : u["sorties"])
        for (const auto& st : s["stops"])
          ++flown[{st["surface_id"].get<int>(), st["stop"].get<int>()}];
    EXPECT_EQ(flown, singleStops(mission));
    // One UAV alone is never faster; no schedule beats the bound.
    const double makespan = fleet["makespan_s"].get<double>();
    EXPECT_LE(makespan, fleet["single_uav_s"].get<double>() + 1e-3);
    EXPECT_GE(makespan, fleet["lower_bound_s"].get<double>() - 1e-3);
    // Homes apart by the separation.
    const double separation = fleet["options"]["separation_m"].get<double>();
    for (std::size_t i = 0; i < k; ++i)
      for (std::size_t j = 0; j < i; ++j) {
        const auto& a = fleet["uavs"][i]["home"];
        const auto& b = fleet["uavs"][j]["home"];
        const double d = std::hypot(a[0].get<double>() - b[0].get<double>(),
                                    a[1].get<double>() - b[1].get<double>(),
                                    a[2].get<double>() - b[2].get<double>());
        EXPECT_GE(d, separation);
      }
    // Brute force on sampled times and delays: never closer than the separation.
    EXPECT_GE(sampledClosestApproach(fleet), separation - 1e-6);
    // The independent check: motion from the waypoints and the flight model.
    const Result v = uavip("validate " + (out(key) / "mission.json").string());
    EXPECT_EQ(v.code, 0) << v.out;
    EXPECT_NE(v.out.find("fleet: " + std::to_string(k) + " UAVs"), std::string::npos) << v.out;
  }
}

TEST_F(FleetCli, ExportWritesOneFilePerUavAndSortie) {
  ASSERT_EQ(runs_["tower_2"].code, 0) << runs_["tower_2"].out;
  const auto mission = readJson(out("tower_2") / "mission.json");
  const fs::path dir = dir_ / "export";
  const std::string m = (out("tower_2") / "mission.json").string();
  const Result plan =
      uavip("export " + m + " --surface all --format qgc-plan --origin 47,8,400 -o " +
            (dir / "tower.plan").string());
  ASSERT_EQ(plan.code, 0) << plan.out;
  const Result geo = uavip("export " + m + " --surface all --format geojson --origin 47,8,400 -o " +
                           (dir / "tower.geojson").string());
  ASSERT_EQ(geo.code, 0) << geo.out;
  for (std::size_t u = 0; u < mission["fleet"]["uavs"].size(); ++u) {
    const auto& uav = mission["fleet"]["uavs"][u];
    const std::string n = std::to_string(u + 1);
    if (uav["sorties"].empty()) continue;
    EXPECT_NE(plan.out.find("uav " + n + ": home"), std::string::npos) << plan.out;
    for (std::size_t s = 0; s < uav["sorties"].size(); ++s) {
      const fs::path f = dir / ("tower_uav" + n + "_sortie" + std::to_string(s + 1) + ".plan");
      ASSERT_TRUE(fs::exists(f)) << f;
      EXPECT_FALSE(readJson(f)["mission"]["items"].empty());
    }
    // The map files carry the UAV in their path's properties.
    const auto g = readJson(dir / ("tower_uav" + n + ".geojson"));
    int paths = 0;
    for (const auto& feature : g["features"]) {
      if (feature["properties"]["kind"] != "path") continue;
      ++paths;
      EXPECT_EQ(feature["properties"]["uav"].get<std::size_t>(), u + 1);
    }
    EXPECT_EQ(paths, static_cast<int>(uav["sorties"].size()));
  }
}

TEST_F(FleetCli, HandMadeConflictExitsThree) {
  ASSERT_EQ(runs_["single_cube_2"].code, 0);
  auto mission = readJson(out("single_cube_2") / "mission.json");
  auto& uavs = mission["fleet"]["uavs"];
  // UAV 2 flies UAV 1's first sortie at the same time.
  uavs[1]["home"] = uavs[0]["home"];
  uavs[1]["sorties"] = nlohmann::json::array({uavs[0]["sorties"][0]});
  const fs::path bad = out("single_cube_2") / "conflict.json";
  std::ofstream(bad) << mission.dump(1);
  const Result v = uavip("validate " + bad.string() + " --scene " +
                         (out("single_cube_2") / "scene.json").string());
  EXPECT_EQ(v.code, 3) << v.out;
  EXPECT_NE(v.out.find("uav 1 (sortie 1) and uav 2 (sortie 1)"), std::string::npos) << v.out;
  EXPECT_NE(v.out.find("0.000 m apart at t = "), std::string::npos) << v.out;
}

TEST_F(FleetCli, BadFleetsExitTwoWritingNothing) {
  const auto expectRefused = [&](const std::string& args, const std::string& words) {
    const fs::path o = dir_ / "refused";
    fs::remove_all(o);
    const Result r =
        uavip("run " + scenario("single_plane") + " -q --no-views -o " + o.string() + " " + args);
    EXPECT_EQ(r.code, 2) << args << ": " << r.out;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
    EXPECT_NE(r.out.find(words), std::string::npos) << r.out;
    EXPECT_FALSE(fs::exists(o / "mission.json")) << args;
  };
  expectRefused("--uavs 0", "uavs must be >= 1");
  expectRefused("--uavs 100000", "more than the");
  // A scenario with a fleet section: too small a separation, homes too close, a home
  // inside the structure.
  const std::string base = uavip::cli_test::slurp(scenario("single_plane"));
  const auto withFleet = [&](const std::string& fleet) {
    const fs::path p =
        dir_ / ("fleet_" + std::to_string(std::hash<std::string>{}(fleet)) + ".yaml");
    std::ofstream(p) << base << "\nfleet:\n" << fleet;
    return p.string();
  };
  const auto runRefused = [&](const std::string& fleet, const std::string& words) {
    const fs::path o = dir_ / "refused";
    fs::remove_all(o);
    const Result r = uavip("run " + withFleet(fleet) + " -q --no-views -o " + o.string());
    EXPECT_EQ(r.code, 2) << fleet << ": " << r.out;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
    EXPECT_NE(r.out.find(words), std::string::npos) << r.out;
    EXPECT_FALSE(fs::exists(o / "mission.json")) << fleet;
  };
  runRefused("  uavs: 2\n  separation_m: 1.0\n", "twice uav.inflation_radius_m");
  runRefused("  uavs: 2\n  homes: [[0, -8, 1], [2, -8, 1]]\n", "closer than separation_m");
  runRefused("  uavs: 2\n  homes: [[0, -8, 1]]\n", "one home per UAV");
  runRefused("  uavs: 2\n  homes: [[4, 0, 2], [4, -8, 2]]\n", "inside the");
}

}  // namespace
