// uavip tile | run-tile | merge end to end on a simulated site that crosses tile
// borders: the merged scene against the simulator's truth and against detect on the
// whole cloud in one process, the merged flight against every input point by
// `uavip validate`, and the bad inputs of a tiled site (exit 2, one line, nothing written).

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/cli/cli_runner.h"
#include "tests/cli/fleet_sampling.h"
#include "tests/tiling/block_site.h"

namespace {

namespace fs = std::filesystem;
using uavip::Vec3;
using uavip::cli_test::Result;
using uavip::cli_test::sampledClosestApproach;
using uavip::cli_test::slurp;
using uavip::cli_test::uavip;

int lines(const std::string& s) {
  int n = 0;
  for (const char c : s) n += c == '\n';
  return n;
}

class TileCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("uavip_tile_cli_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    uavip::test::writeBlockSite(dir_ / "site.xyz");
    std::ofstream cfg(dir_ / "site.yaml");
    cfg << "camera: {footprint_m: [3.0, 2.0]}\ncoverage: {standoff_m: 2.0}\n"
           "perception: {min_area_m2: 4.0}\n";
    cfg.close();
    tiled_ = uavip("-q tile " + p("site.xyz") + " --tile-size 15 -c " + p("site.yaml") + " -o " +
                   p("T"));
    manifest_ = nlohmann::json::parse(slurp(dir_ / "T/manifest.json"), nullptr, false);
    if (manifest_.is_object())
      for (std::size_t i = 0; i < manifest_["tiles"].size(); ++i)
        tile_codes_ +=
            uavip("-q run-tile " + p("T/manifest.json") + " --index " + std::to_string(i)).code;
    merged_ = uavip("-q merge " + p("T/manifest.json") + " -o " + p("out") + " --no-views");
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static std::string p(const std::string& name) { return (dir_ / name).string(); }

  static inline fs::path dir_;
  static inline Result tiled_, merged_;
  static inline nlohmann::json manifest_;
  static inline int tile_codes_{0};
};

TEST_F(TileCli, MergedSceneMatchesTruthAndTheWholeCloudRun) {
  ASSERT_EQ(tiled_.code, 0) << tiled_.out;
  ASSERT_EQ(manifest_["tiles"].size(), 4U);  // 50 m / 15 m columns, one row
  ASSERT_EQ(tile_codes_, 0);
  ASSERT_EQ(merged_.code, 0) << merged_.out;
  const auto merged = nlohmann::json::parse(slurp(dir_ / "out/scene.json"));
  // The same cloud in one process.
  const Result whole = uavip("-q detect " + p("site.xyz") + " -c " + p("site.yaml") + " -o " +
                             p("whole") + " --no-views");
  ASSERT_EQ(whole.code, 0) << whole.out;
  const auto one = nlohmann::json::parse(slurp(dir_ / "whole/scene.json"));
  ASSERT_EQ(merged["surfaces"].size(), one["surfaces"].size());
  // Every surface of the single run has a merged twin: same plane, area within 5 %.
  for (const auto& s : one["surfaces"]) {
    const Vec3 n(s["normal"][0], s["normal"][1], s["normal"][2]);
    bool found = false;
    for (const auto& t : merged["surfaces"]) {
      const Vec3 m(t["normal"][0], t["normal"][1], t["normal"][2]);
      if (n.dot(m) > std::cos(5.0 * M_PI / 180.0) &&
          std::abs(double(s["offset"]) - double(t["offset"])) < 0.2 &&
          std::abs(double(s["area_m2"]) - double(t["area_m2"])) < 0.05 * double(s["area_m2"]))
        found = true;
    }
    EXPECT_TRUE(found) << "no merged twin of surface " << s["id"];
  }
  // The block's long faces cross every border: one surface each of the truth's 40 x 3 m.
  int long_faces = 0;
  for (const auto& t : merged["surfaces"])
    long_faces +=
        std::abs(double(t["normal"][1])) > 0.99 && std::abs(double(t["area_m2"]) - 120.0) < 6.0;
  EXPECT_EQ(long_faces, 2);
}

TEST_F(TileCli, MergedFlightKeepsClearOfEveryInputPoint) {
  ASSERT_EQ(merged_.code, 0) << merged_.out;
  const Result v = uavip("validate " + p("out/mission.json") + " --cloud " + p("site.xyz"));
  EXPECT_EQ(v.code, 0) << v.out;
  const auto mission = nlohmann::json::parse(slurp(dir_ / "out/mission.json"));
  EXPECT_GE(mission["flight"]["sorties"].size(), 1U);
}

TEST_F(TileCli, SectionsEachKeepClearOfEveryInputPoint) {
  ASSERT_EQ(tile_codes_, 0);
  const Result r = uavip("-q merge " + p("T/manifest.json") + " -o " + p("sections") +
                         " --section-tiles 1 --no-views");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto site = nlohmann::json::parse(slurp(dir_ / "sections/site.json"));
  ASSERT_EQ(site["sections"].size(), manifest_["tiles"].size());  // one tile a section
  std::size_t surfaces = 0;
  for (const auto& s : site["sections"]) {
    const std::string folder = p("sections/" + std::string(s["folder"]));
    const auto scene = nlohmann::json::parse(slurp(fs::path(folder) / "scene.json"));
    EXPECT_EQ(scene["surfaces"].size(), s["surfaces"].get<std::size_t>());
    surfaces += scene["surfaces"].size();
    if (s["flight_status"] != "ok") continue;
    const Result v = uavip("validate " + folder + "/mission.json --cloud " + p("site.xyz"));
    EXPECT_EQ(v.code, 0) << folder << ": " << v.out;
  }
  // Cut at every section border, the block's long faces are pieces of the one surface.
  const auto whole = nlohmann::json::parse(slurp(dir_ / "out/scene.json"));
  EXPECT_GE(surfaces, whole["surfaces"].size());
}

TEST_F(TileCli, BufferSmallerThanTheStandoffIsRefused) {
  const Result r = uavip("-q tile " + p("site.xyz") + " --tile-size 15 --buffer 1 -c " +
                         p("site.yaml") + " -o " + p("T_small"));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_EQ(lines(r.out), 1) << r.out;
  EXPECT_NE(r.out.find("uavip: error: --buffer 1"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir_ / "T_small/manifest.json"));
}

TEST_F(TileCli, MissingTileResultStopsTheMerge) {
  ASSERT_EQ(tiled_.code, 0);
  fs::copy(dir_ / "T", dir_ / "T_missing", fs::copy_options::recursive);
  fs::remove(dir_ / "T_missing/tile_0001/scene.json");
  const Result r = uavip("-q merge " + p("T_missing/manifest.json") + " -o " + p("out_missing"));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_EQ(lines(r.out), 1) << r.out;
  EXPECT_NE(r.out.find("no result for tile(s) 1"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("--array=1"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir_ / "out_missing"));
}

TEST_F(TileCli, ChangedInputStopsTheMerge) {
  fs::copy(dir_ / "site.xyz", dir_ / "changed.xyz");
  ASSERT_EQ(uavip("-q tile " + p("changed.xyz") + " --tile-size 30 -o " + p("T_changed")).code, 0);
  std::ofstream(dir_ / "changed.xyz", std::ios::app) << "1 1 1\n";
  const Result r = uavip("-q merge " + p("T_changed/manifest.json") + " -o " + p("out_changed"));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_EQ(lines(r.out), 1) << r.out;
  EXPECT_NE(r.out.find("sha256"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir_ / "out_changed"));
}

TEST_F(TileCli, TileWithoutPointsOrIndexIsRefused) {
  ASSERT_TRUE(manifest_.is_object());
  const Result beyond = uavip("-q run-tile " + p("T/manifest.json") + " --index 99");
  EXPECT_EQ(beyond.code, 2) << beyond.out;
  EXPECT_NE(beyond.out.find("no tile 99"), std::string::npos) << beyond.out;
  fs::create_directories(dir_ / "T_empty");
  auto m = manifest_;
  m["tiles"][0]["core_points"] = 0;
  std::ofstream(dir_ / "T_empty/manifest.json") << m.dump();
  const Result empty = uavip("-q run-tile " + p("T_empty/manifest.json") + " --index 0");
  EXPECT_EQ(empty.code, 2) << empty.out;
  EXPECT_EQ(lines(empty.out), 1) << empty.out;
  EXPECT_NE(empty.out.find("no points"), std::string::npos) << empty.out;
  EXPECT_FALSE(fs::exists(dir_ / "T_empty/tile_0000"));
}

/// Every "timings" object removed (benchmarks/compare_outputs.py).
nlohmann::json withoutTimings(const nlohmann::json& j) {
  if (j.is_object()) {
    nlohmann::json out = nlohmann::json::object();
    for (const auto& [k, v] : j.items())
      if (k != "timings") out[k] = withoutTimings(v);
    return out;
  }
  if (j.is_array()) {
    nlohmann::json out = nlohmann::json::array();
    for (const auto& v : j) out.push_back(withoutTimings(v));
    return out;
  }
  return j;
}

// Issue 45, item 5: `merge --uavs K` flies the tiled site with the fleet. A site of one
// section is planned as a scene is: its mission.json has the fleet, which `uavip
// validate` (the motion recomputed from the waypoints and the flight model, every UAV's
// leg against every input point) accepts. A site of several sections keeps each
// section's one-UAV flight and flies the sections at once (app/site_fleet.h): every
// sortie once, never closer than the separation by brute force, `validate site.json`.
// K = 1 is today's merge.
TEST_F(TileCli, FleetFliesTheSiteConflictFree) {
  ASSERT_EQ(tile_codes_, 0);
  ASSERT_EQ(merged_.code, 0) << merged_.out;
  // K = 1: the same mission and scene as the merge without --uavs.
  const Result one =
      uavip("-q merge " + p("T/manifest.json") + " -o " + p("one") + " --no-views --uavs 1");
  ASSERT_EQ(one.code, 0) << one.out;
  for (const char* f : {"mission.json", "scene.json"})
    EXPECT_EQ(withoutTimings(nlohmann::json::parse(slurp(dir_ / "one" / f))),
              withoutTimings(nlohmann::json::parse(slurp(dir_ / "out" / f))))
        << f;
  EXPECT_FALSE(nlohmann::json::parse(slurp(dir_ / "one/mission.json")).contains("fleet"));

  // K = 2 over the whole site (one section). The site is small: UAVs launched 5 s apart
  // with 3 m of separation share it (the defaults, 30 s and 5 m, leave UAV 2 idle).
  {
    std::ofstream cfg(dir_ / "fleet.yaml");
    cfg << slurp(dir_ / "site.yaml")
        << "fleet: {launch_interval_s: 5.0, separation_m: 3.0, slack_s: 10.0}\n";
  }
  const std::string fleet_cfg = " -c " + p("fleet.yaml");
  const Result whole = uavip("merge " + p("T/manifest.json") + " -o " + p("fleet_whole") +
                             " --no-views --uavs 2" + fleet_cfg);
  std::cout << whole.out;
  ASSERT_EQ(whole.code, 0) << whole.out;
  const auto mission = nlohmann::json::parse(slurp(dir_ / "fleet_whole/mission.json"));
  ASSERT_TRUE(mission.contains("fleet"));
  EXPECT_EQ(mission["fleet"]["uavs"].size(), 2U);
  const Result vw =
      uavip("validate " + p("fleet_whole/mission.json") + " --cloud " + p("site.xyz"));
  EXPECT_EQ(vw.code, 0) << vw.out;
  EXPECT_NE(vw.out.find("fleet: 2 UAVs"), std::string::npos) << vw.out;
  EXPECT_FALSE(mission["fleet"]["fallback_single"].get<bool>()) << "both UAVs fly";

  // K = 2, one tile a section: every section planned for one UAV, exactly as the merge
  // of one UAV plans it, and the sections flown at once by site.json's fleet, which
  // `uavip validate site.json` re-checks from the sections' waypoints.
  const Result sections = uavip("merge " + p("T/manifest.json") + " -o " + p("fleet_sections") +
                                " --section-tiles 1 --no-views --uavs 2" + fleet_cfg);
  std::cout << sections.out;
  ASSERT_EQ(sections.code, 0) << sections.out;
  const Result single = uavip("-q merge " + p("T/manifest.json") + " -o " + p("one_sections") +
                              " --section-tiles 1 --no-views" + fleet_cfg);
  ASSERT_EQ(single.code, 0) << single.out;
  const auto site = nlohmann::json::parse(slurp(dir_ / "fleet_sections/site.json"));
  ASSERT_TRUE(site.contains("fleet")) << site.dump(1);
  const auto& fleet = site["fleet"];
  EXPECT_EQ(fleet["mode"], "sections at once");
  EXPECT_FALSE(nlohmann::json::parse(slurp(dir_ / "one_sections/site.json")).contains("fleet"));
  for (const char* command : {"validate ", "export --format csv -o x.csv "}) {  // no fleet there
    const Result none = uavip(std::string(command) + p("one_sections/site.json"));
    EXPECT_EQ(none.code, 2) << command << none.out;
    EXPECT_EQ(lines(none.out), 1) << command << none.out;
    EXPECT_NE(none.out.find("section_NNN"), std::string::npos) << command << none.out;
  }
  // The reference: the one-UAV merge's sections, their sorties and times by the model.
  std::map<std::pair<std::string, int>, int> flown;
  std::size_t sorties = 0;
  double alone_s = 0.0;
  nlohmann::json rebuilt = {{"model", fleet["model"]}, {"options", fleet["options"]}};
  std::map<std::string, nlohmann::json> missions;
  for (const auto& s : site["sections"]) {
    const std::string f = std::string(s["folder"]) + "/mission.json";
    const auto m = nlohmann::json::parse(slurp(dir_ / "fleet_sections" / f));
    EXPECT_FALSE(m.contains("fleet")) << f;
    EXPECT_EQ(withoutTimings(m),
              withoutTimings(nlohmann::json::parse(slurp(dir_ / "one_sections" / f))))
        << f;
    if (s["flight_status"] != "ok") continue;
    sorties += m["flight"]["sorties"].size();
    alone_s += m["flight"]["duration_s"].get<double>();
    missions[s["folder"]] = m;
  }
  ASSERT_GE(missions.size(), 2U) << "the test needs two flown sections";
  std::size_t flying = 0;
  for (const auto& u : fleet["uavs"]) {
    nlohmann::json uav = {{"sorties", nlohmann::json::array()}};
    for (const auto& k : u["sorties"]) {
      const int n = k["sortie"].get<int>();
      ++flown[{k["folder"], n}];
      nlohmann::json sortie = missions.at(k["folder"])["flight"]["sorties"].at(n - 1);
      sortie["start_s"] = k["start_s"];
      uav["sorties"].push_back(sortie);
    }
    flying += !u["sorties"].empty();
    rebuilt["uavs"].push_back(uav);
  }
  EXPECT_EQ(flown.size(), sorties) << "every sortie of the site flown";
  for (const auto& [k, n] : flown) EXPECT_EQ(n, 1) << k.first << " sortie " << k.second;
  EXPECT_EQ(flying, 2U) << "both UAVs fly";
  EXPECT_NEAR(fleet["single_uav_s"].get<double>(), alone_s, 0.01 * sorties);
  EXPECT_LT(fleet["makespan_s"].get<double>(), alone_s);
  EXPECT_GE(fleet["makespan_s"].get<double>(), fleet["lower_bound_s"].get<double>());
  // Brute force on sampled times and delays: never closer than the separation.
  EXPECT_GE(sampledClosestApproach(rebuilt), fleet["options"]["separation_m"].get<double>() - 1e-6);
  const Result vs = uavip("validate " + p("fleet_sections/site.json"));
  EXPECT_EQ(vs.code, 0) << vs.out;
  EXPECT_NE(vs.out.find("sections flown at once"), std::string::npos) << vs.out;

  // Export: one file per UAV and sortie, each the very route the section's own export
  // writes for the sortie it names; map files carry the UAV.
  const std::string origin = " --origin 47.3977,8.5456,488 -o ";
  const Result plan = uavip("export " + p("fleet_sections/site.json") + " --format qgc-plan" +
                            origin + p("export/site.plan"));
  ASSERT_EQ(plan.code, 0) << plan.out;
  for (std::size_t u = 0; u < fleet["uavs"].size(); ++u) {
    const auto& list = fleet["uavs"][u]["sorties"];
    EXPECT_NE(plan.out.find("uav " + std::to_string(u + 1) + ": " + std::to_string(list.size()) +
                            " sorties"),
              std::string::npos)
        << plan.out;
    for (std::size_t k = 0; k < list.size(); ++k) {
      const std::string name =
          "site_uav" + std::to_string(u + 1) + "_sortie" + std::to_string(k + 1) + ".plan";
      const std::string ref = "ref_" + name;
      const Result one = uavip(
          "-q export " + p("fleet_sections/" + std::string(list[k]["folder"]) + "/mission.json") +
          " --sortie " + std::to_string(list[k]["sortie"].get<int>()) + " --format qgc-plan" +
          origin + p("export/" + ref));
      ASSERT_EQ(one.code, 0) << one.out;
      const auto got = nlohmann::json::parse(slurp(dir_ / "export" / name));
      EXPECT_EQ(got["mission"]["items"],
                nlohmann::json::parse(slurp(dir_ / "export" / ref))["mission"]["items"])
          << name;
    }
  }
  const Result geo = uavip("-q export " + p("fleet_sections/site.json") + " --uav 2" +
                           " --format geojson" + origin + p("export/site.geojson"));
  ASSERT_EQ(geo.code, 0) << geo.out;
  const auto g = nlohmann::json::parse(slurp(dir_ / "export/site_uav2_sortie1.geojson"));
  int paths = 0;
  for (const auto& feature : g["features"]) {
    if (feature["properties"]["kind"] == "path") {
      EXPECT_EQ(feature["properties"]["uav"], 2);
      ++paths;
    }
  }
  EXPECT_GE(paths, 1) << "no path feature to carry the UAV";
  EXPECT_FALSE(fs::exists(dir_ / "export/site_uav1_sortie1.geojson")) << "--uav 2 only";

  // A hand-made conflict: UAV 2 flies UAV 1's sorties with it, at the same times.
  auto bad = site;
  bad["fleet"]["uavs"][1]["sorties"] = site["fleet"]["uavs"][0]["sorties"];
  fs::create_directories(dir_ / "bad_site");
  for (const auto& [folder, m] : missions)
    fs::copy(dir_ / "fleet_sections" / folder, dir_ / "bad_site" / folder,
             fs::copy_options::recursive);
  std::ofstream(dir_ / "bad_site/site.json") << bad.dump(1);
  const Result conflict = uavip("validate " + p("bad_site/site.json"));
  EXPECT_EQ(conflict.code, 3) << conflict.out;
  EXPECT_NE(conflict.out.find("closer than the separation"), std::string::npos) << conflict.out;

  // Sections stay independent tasks: plan-section results for one UAV are joined by
  // merge --uavs 2 into the same site fleet as the merge planned.
  fs::copy(dir_ / "T", dir_ / "T_fleet", fs::copy_options::recursive);
  for (std::size_t i = 0; i < site["sections"].size(); ++i) {
    const Result r = uavip("-q plan-section " + p("T_fleet/manifest.json") + " --section " +
                           std::to_string(i) + " --section-tiles 1 --no-views" + fleet_cfg);
    ASSERT_EQ(r.code, 0) << r.out;
  }
  const Result joined =
      uavip("-q merge " + p("T_fleet/manifest.json") + " -o " + p("fleet_joined") +
            " --section-tiles 1 --no-views --uavs 2 --require-sections" + fleet_cfg);
  ASSERT_EQ(joined.code, 0) << joined.out;
  auto a = withoutTimings(nlohmann::json::parse(slurp(dir_ / "fleet_joined/site.json")));
  auto b = withoutTimings(site);
  for (auto* j : {&a, &b}) {  // the manifest's and input's paths: T_fleet/ and T/
    j->erase("manifest");
    j->erase("input");
  }
  EXPECT_EQ(a["fleet"], b["fleet"]);

  // fleet.homes has no place in a site of several sections: exit 2, nothing written.
  {
    std::ofstream cfg(dir_ / "homes.yaml");
    cfg << slurp(dir_ / "site.yaml")
        << "fleet: {uavs: 2, launch_interval_s: 5.0, separation_m: 3.0, slack_s: 10.0,\n"
           "        homes: [[0, -20, 1], [10, -20, 1]]}\n";
  }
  const Result homes = uavip("-q merge " + p("T/manifest.json") + " -o " + p("homes_out") +
                             " --section-tiles 1 --no-views -c " + p("homes.yaml"));
  EXPECT_EQ(homes.code, 2) << homes.out;
  EXPECT_EQ(lines(homes.out), 1) << homes.out;
  EXPECT_NE(homes.out.find("own home"), std::string::npos) << homes.out;
  EXPECT_FALSE(fs::exists(dir_ / "homes_out/site.json"));
}

}  // namespace
