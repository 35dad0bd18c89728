// uavip tile | run-tile | merge end to end on a simulated site that crosses tile
// borders: the merged scene against the simulator's truth and against detect on the
// whole cloud in one process, the merged flight against every input point by
// `uavip validate`, and the bad inputs of a tiled site (exit 2, one line, nothing written).

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/cli/cli_runner.h"
#include "tests/tiling/block_site.h"

namespace {

namespace fs = std::filesystem;
using uavip::Vec3;
using uavip::cli_test::Result;
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

}  // namespace
