#include "uavip/io/scenario.h"

#include "uavip/core/error.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace uavip::io {
namespace {

const std::string kMinimal = R"(
name: t
world:
  - {type: plane, name: w, corner: [0, 0, 0], edge_u: [4, 0, 0], edge_v: [0, 0, 2]}
sensing: {mode: sample, spacing_m: 0.1, seed: 1}
)";

/// Expects an InputError whose message contains every fragment.
void expectInputError(const std::string& yaml, std::initializer_list<std::string> fragments) {
  try {
    parseScenario(yaml, "x.yaml");
    FAIL() << "no error for:\n" << yaml;
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.find('\n'), std::string::npos) << "error must be one line: " << msg;
    for (const auto& f : fragments) EXPECT_NE(msg.find(f), std::string::npos) << "'" << f << "' not in: " << msg;
  }
}

TEST(Scenario, EveryBundledScenarioParses) {
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(std::string(UAVIP_SOURCE_DIR) + "/scenarios")) {
    if (entry.path().extension() != ".yaml") continue;
    SCOPED_TRACE(entry.path().string());
    const Scenario s = loadScenario(entry.path().string());
    EXPECT_FALSE(s.name.empty());
    EXPECT_FALSE(s.world.empty());
    ++count;
  }
  EXPECT_GE(count, 5);
}

TEST(Scenario, MinimalScenarioGetsThePapersDefaults) {
  const Scenario s = parseScenario(kMinimal, "x.yaml");
  EXPECT_EQ(s.world.rects().size(), 1u);
  EXPECT_DOUBLE_EQ(s.config.perception.planes.distance_threshold_m, 0.2);
  EXPECT_EQ(s.config.perception.planes.max_iterations, 200);
  EXPECT_DOUBLE_EQ(s.config.perception.planes.min_area_m2, 2.0);
  EXPECT_DOUBLE_EQ(s.config.coverage.camera.footprint_w_m, 0.6);
  EXPECT_DOUBLE_EQ(s.config.coverage.camera.footprint_h_m, 0.4);
  EXPECT_DOUBLE_EQ(s.config.coverage.overlap_w, 0.2);
  EXPECT_DOUBLE_EQ(s.config.uav.inflationRadius(), 0.6);  // largest UAV dimension (paper)
  EXPECT_EQ(s.config.planner, "astar");
  // density area cell = the clean cloud's spacing: max(voxel 0.05, sampling 0.1)
  EXPECT_DOUBLE_EQ(s.config.perception.planes.cell_size_m, 0.1);
}

TEST(Scenario, ValuesAreRead) {
  const Scenario s = parseScenario(kMinimal + R"(
uav: {size_m: [1.0, 0.5, 0.3], inflation_radius_m: 0.8}
camera: {sensor_mm: [13.2, 8.8], focal_mm: 8.8, image_px: [5472, 3648], gsd_mm_per_px: 1.0}
coverage: {overlap: [0.3, 0.1], gimbal_pitch_deg: [-90, 30]}
planner: {name: astar-euclid, cost_weights: [1, 2, 3]}
mission: {start: [1, -3, 1]}
expect: {surfaces: 1, status: ok}
)",
                                   "x.yaml");
  EXPECT_DOUBLE_EQ(s.config.uav.inflationRadius(), 0.8);
  EXPECT_TRUE(s.config.coverage.camera.from_sensor);
  EXPECT_EQ(s.config.coverage.camera.image_w_px, 5472);
  EXPECT_DOUBLE_EQ(s.config.coverage.overlap_w, 0.3);
  EXPECT_DOUBLE_EQ(s.config.coverage.overlap_h, 0.1);
  EXPECT_DOUBLE_EQ(s.config.coverage.gimbal.pitch_max_deg, 30.0);
  EXPECT_EQ(s.config.planner, "astar-euclid");
  EXPECT_DOUBLE_EQ(s.config.planner_settings.astar.a3, 3.0);
  ASSERT_TRUE(s.config.mission.start.has_value());
  EXPECT_DOUBLE_EQ(s.config.mission.start->y(), -3.0);
  EXPECT_EQ(*s.expect.surfaces, 1);
  EXPECT_EQ(*s.expect.status, "ok");
}

TEST(Scenario, UnknownKeyIsNamed) {
  expectInputError(kMinimal + "grid: {resolution: 0.1}\n", {"x.yaml", "grid.resolution", "not a known key"});
  expectInputError(kMinimal + "colour: red\n", {"x.yaml", "colour"});
}

TEST(Scenario, WrongTypeIsNamed) {
  expectInputError(kMinimal + "grid: {resolution_m: fine}\n", {"x.yaml", "grid.resolution_m", "number", "fine"});
  expectInputError(kMinimal + "perception: {max_iterations: 2.5}\n", {"perception.max_iterations", "integer"});
  expectInputError(kMinimal + "camera: {footprint_m: [0.6]}\n", {"camera.footprint_m", "list of 2"});
  expectInputError(kMinimal + "preprocess: {voxelize: maybe}\n", {"preprocess.voxelize", "true or false"});
}

TEST(Scenario, MissingFieldIsNamed) {
  expectInputError("name: t\nsensing: {mode: sample}\n", {"x.yaml", "world"});
  expectInputError("name: t\nworld:\n  - {type: point, at: [0, 0, 0]}\n", {"sensing", "missing"});
  expectInputError("name: t\nworld:\n  - {type: line, from: [0, 0, 0]}\nsensing: {}\n", {"world[0].to", "missing"});
}

TEST(Scenario, BadValuesAreRejected) {
  expectInputError(kMinimal + "grid: {resolution_m: 0}\n", {"x.yaml", "resolution_m", "0"});
  expectInputError(kMinimal + "uav: {size_m: [0.6, -0.6, 0.4]}\n", {"x.yaml", "size_m"});
  expectInputError(kMinimal + "coverage: {overlap: 1.0}\n", {"x.yaml", "overlap"});
  expectInputError(kMinimal + "planner: {name: warp-drive}\n", {"x.yaml", "warp-drive", "astar"});
  expectInputError(kMinimal + "camera: {footprint_m: [0.6, 0.4], focal_mm: 8}\n", {"camera", "both"});
  expectInputError("name: t\nworld:\n  - {type: torus}\nsensing: {}\n", {"torus", "not a primitive"});
  expectInputError("name: t\nworld: []\nsensing: {}\n", {"world", "empty"});
  expectInputError("name: [unclosed\n", {"x.yaml", "YAML"});
}

TEST(Scenario, MissingFileIsNamed) {
  try {
    loadScenario("/nonexistent/dir/s.yaml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/dir/s.yaml: no such file"), std::string::npos);
  }
}

TEST(Config, EmptyConfigMeansDefaults) {
  const Config c = parseConfig("", "c.yaml");
  EXPECT_EQ(c.planner, "astar");
  EXPECT_THROW(parseConfig("world: []\n", "c.yaml"), InputError);  // a config has no world
}

}  // namespace
}  // namespace uavip::io
