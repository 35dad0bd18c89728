// The scene travels with the mission: plan -o OTHER puts scene.json (and the safety
// cloud it names) beside mission.json, so export and validate need no --scene; a
// tiled LAS site keeps the file's CRS through tile, run-tile and merge, so its merged
// flight exports to GeoJSON without --crs.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/cli/cli_runner.h"

namespace {

namespace fs = std::filesystem;
using uavip::cli_test::Result;
using uavip::cli_test::slurp;
using uavip::cli_test::uavip;

fs::path freshDir(const std::string& name) {
  const fs::path d =
      fs::temp_directory_path() / ("uavip_scene_travel_" + name + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

TEST(SceneTravel, PlanIntoAnotherFolderTakesTheSceneAlong) {
  const fs::path d = freshDir("plan");
  const std::string plane = std::string(UAVIP_SOURCE_DIR) + "/scenarios/single_plane.yaml";
  ASSERT_EQ(uavip("-q run " + plane + " -o " + (d / "run").string() + " --no-views").code, 0);
  const Result plan = uavip("-q plan " + (d / "run" / "scene.json").string() +
                            " --surface all -o " + (d / "other").string() + " --no-views");
  ASSERT_EQ(plan.code, 0) << plan.out;
  EXPECT_EQ(slurp(d / "other" / "scene.json"), slurp(d / "run" / "scene.json"));
  const Result val = uavip("validate " + (d / "other" / "mission.json").string());
  EXPECT_EQ(val.code, 0) << val.out;
  EXPECT_NE(val.out.find((d / "other" / "scene.json").string()), std::string::npos) << val.out;
  const Result exp =
      uavip("-q export " + (d / "other" / "mission.json").string() +
            " --surface all --format csv --origin 48,3,100 -o " + (d / "m.csv").string());
  EXPECT_EQ(exp.code, 0) << exp.out;
  // Planned in the scene's own folder: nothing is copied over itself.
  const Result same = uavip("-q plan " + (d / "run" / "scene.json").string() +
                            " --surface all -o " + (d / "run").string() + " --no-views");
  EXPECT_EQ(same.code, 0) << same.out;
}

TEST(SceneTravel, MergedLasSiteExportsWithoutCrs) {
  const fs::path d = freshDir("site");
  const std::string las = std::string(UAVIP_SOURCE_DIR) + "/tests/data/autzen_trim.las";
  const Result tiled = uavip("-q tile " + las + " --tile-size 200 -o " + (d / "T").string());
  ASSERT_EQ(tiled.code, 0) << tiled.out;
  const nlohmann::json manifest = nlohmann::json::parse(slurp(d / "T" / "manifest.json"));
  ASSERT_TRUE(manifest.contains("crs"));
  EXPECT_EQ(manifest["crs"]["source"], "LAS WKT record 2112");
  for (std::size_t i = 0; i < manifest["tiles"].size(); ++i) {
    const Result t = uavip("-q run-tile " + (d / "T" / "manifest.json").string() + " --index " +
                           std::to_string(i));
    ASSERT_EQ(t.code, 0) << t.out;
    const std::string tile_scene =
        slurp(d / "T" / manifest["tiles"][i]["out"].get<std::string>() / "scene.json");
    EXPECT_EQ(nlohmann::json::parse(tile_scene)["crs"]["definition"],
              manifest["crs"]["definition"]);
  }
  const Result merged = uavip("-q merge " + (d / "T" / "manifest.json").string() + " -o " +
                              (d / "out").string() + " --no-views");
  ASSERT_EQ(merged.code, 0) << merged.out;
  const nlohmann::json scene = nlohmann::json::parse(slurp(d / "out" / "scene.json"));
  EXPECT_EQ(scene["crs"]["definition"], manifest["crs"]["definition"]);
  const Result exp = uavip("-q export " + (d / "out" / "mission.json").string() +
                           " --surface all --format geojson -o " + (d / "site.geojson").string());
  ASSERT_EQ(exp.code, 0) << exp.out;
  const nlohmann::json geo = nlohmann::json::parse(slurp(d / "site.geojson"));
  ASSERT_FALSE(geo["features"].empty());
  // Autzen stadium, Eugene, Oregon: every coordinate within a few km of it.
  for (const auto& f : geo["features"]) {
    if (f["geometry"]["type"] != "Point") continue;
    EXPECT_NEAR(f["geometry"]["coordinates"][0].get<double>(), -123.07, 0.05);
    EXPECT_NEAR(f["geometry"]["coordinates"][1].get<double>(), 44.06, 0.05);
  }
}

}  // namespace
