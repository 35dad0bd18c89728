#include "uavip/app/scenario.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <utility>

#include "expectation.h"
#include "planners/harness.h"
#include "uavip/core/error.h"

namespace uavip::app {
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
    for (const auto& f : fragments)
      EXPECT_NE(msg.find(f), std::string::npos) << "'" << f << "' not in: " << msg;
  }
}

TEST(Scenario, EveryBundledScenarioParses) {
  int count = 0;
  for (const auto& entry :
       std::filesystem::directory_iterator(std::string(UAVIP_SOURCE_DIR) + "/scenarios")) {
    if (entry.path().extension() != ".yaml") continue;
    SCOPED_TRACE(entry.path().string());
    const Scenario s = loadScenario(entry.path().string());
    EXPECT_FALSE(s.name.empty());
    EXPECT_FALSE(s.world.empty());
    EXPECT_NO_THROW(test::readExpectation(entry.path().string()));
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
  // The paper's step cost and weights, searched coarse to fine (planners/astar.h).
  EXPECT_EQ(s.config.planner, "astar-coarse");
  // The area cell is resolved from the cloud (app/config.h), not by the parser.
  EXPECT_FALSE(s.config.setInFile(&s.config.perception.planes.cell_size_m));
  // A scenario knows its sensor.
  EXPECT_TRUE(s.config.setInFile(&s.config.perception.planes.viewpoint));
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
  EXPECT_EQ(s.config.missionOptions().gimbal.pitch_max_deg, 30.0);  // the camera's gimbal
  ASSERT_TRUE(s.config.flightOptions().start.has_value());
  EXPECT_DOUBLE_EQ(s.config.flightOptions().start->y(), -3.0);
}

TEST(Scenario, UnknownKeyIsNamed) {
  expectInputError(kMinimal + "grid: {resolution: 0.1}\n",
                   {"x.yaml", "grid.resolution", "not a known key"});
  expectInputError(kMinimal + "colour: red\n", {"x.yaml", "colour"});
}

TEST(Scenario, DuplicateKeyIsRefusedWithItsLine) {
  // yaml-cpp keeps the first of two equal keys; a user who repeats one means the second.
  expectInputError(kMinimal + "grid: {resolution_m: 0.1, resolution_m: 0.3}\n",
                   {"x.yaml", "grid.resolution_m", "twice"});
  const auto second =
      std::count(kMinimal.begin(), kMinimal.end(), '\n') + 2;  // 1-based line of the repeat
  expectInputError(kMinimal + "planner: {name: astar}\nplanner: {name: rrtstar}\n",
                   {"x.yaml", "planner", "twice", "line " + std::to_string(second)});
}

TEST(Config, NonScalarKeyInsideASectionIsNamed) {
  // A fuzz finding: a key such as [1] inside a section escaped as a yaml-cpp exception.
  try {
    parseConfig("preprocess: {[1]: 2}\n", "c.yaml");
    FAIL() << "a non-scalar key was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("c.yaml"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("not a plain name"), std::string::npos) << e.what();
  }
}

TEST(Scenario, WrongTypeIsNamed) {
  expectInputError(kMinimal + "grid: {resolution_m: fine}\n",
                   {"x.yaml", "grid.resolution_m", "number", "fine"});
  expectInputError(kMinimal + "perception: {max_iterations: 2.5}\n",
                   {"perception.max_iterations", "integer"});
  expectInputError(kMinimal + "camera: {footprint_m: [0.6]}\n",
                   {"camera.footprint_m", "list of 2"});
  expectInputError(kMinimal + "preprocess: {voxelize: maybe}\n",
                   {"preprocess.voxelize", "true or false"});
}

TEST(Scenario, MissingFieldIsNamed) {
  expectInputError("name: t\nsensing: {mode: sample}\n", {"x.yaml", "world"});
  expectInputError("name: t\nworld:\n  - {type: point, at: [0, 0, 0]}\n", {"sensing", "missing"});
  expectInputError("name: t\nworld:\n  - {type: line, from: [0, 0, 0]}\nsensing: {}\n",
                   {"world[0].to", "missing"});
}

TEST(Scenario, BadValuesAreRejected) {
  expectInputError(kMinimal + "grid: {resolution_m: 0}\n", {"x.yaml", "resolution_m", "0"});
  expectInputError(kMinimal + "uav: {size_m: [0.6, -0.6, 0.4]}\n", {"x.yaml", "size_m"});
  expectInputError(kMinimal + "coverage: {overlap: 1.0}\n", {"x.yaml", "overlap"});
  expectInputError(kMinimal + "planner: {name: warp-drive}\n", {"x.yaml", "warp-drive", "astar"});
  expectInputError(kMinimal + "camera: {footprint_m: [0.6, 0.4], focal_mm: 8}\n",
                   {"camera", "both"});
  expectInputError("name: t\nworld:\n  - {type: torus}\nsensing: {}\n",
                   {"torus", "not a primitive"});
  expectInputError("name: t\nworld: []\nsensing: {}\n", {"world", "empty"});
  expectInputError("name: [unclosed\n", {"x.yaml", "YAML"});
  // Checked by MissionOptions::validate, which Config::validate calls.
  expectInputError(kMinimal + "mission: {max_skipped_fraction: 1.5}\n",
                   {"x.yaml", "mission", "max_skipped_fraction", "1.5"});
  expectInputError(kMinimal + "mission: {max_standoff_factor: 0.5}\n",
                   {"x.yaml", "max_standoff_factor", "[1, 3]"});
  expectInputError(kMinimal + "expect: 3\n", {"x.yaml", "expect", "mapping"});
}

TEST(Scenario, ExpectBlockIsForTheTestsAndStrictThere) {
  // uavip accepts the section; the tests' reader refuses a misspelt key, so a typo
  // cannot silently turn an expectation off.
  EXPECT_NO_THROW(parseScenario(kMinimal + "expect: {surfaces: 1, status: ok}\n", "x.yaml"));
  const std::string path = ::testing::TempDir() + "expect_typo.yaml";
  std::ofstream(path) << kMinimal << "expect: {surfaces: 1, statuss: ok}\n";
  EXPECT_THROW(test::readExpectation(path), std::runtime_error);
  std::ofstream(path) << kMinimal << "expect: {surfaces: 2, status: blocked}\n";
  const test::Expectation e = test::readExpectation(path);
  EXPECT_EQ(e.surfaces, 2);
  EXPECT_EQ(e.status, std::string("blocked"));
  EXPECT_FALSE(e.min_surface_area_m2);
}

TEST(Scenario, MissingFileIsNamed) {
  try {
    loadScenario("/nonexistent/dir/s.yaml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/dir/s.yaml: no such file"),
              std::string::npos);
  }
}

TEST(Config, EmptyConfigMeansDefaults) {
  const Config c = parseConfig("", "c.yaml");
  EXPECT_EQ(c.planner, "astar-coarse");
  EXPECT_THROW(parseConfig("world: []\n", "c.yaml"), InputError);  // a config has no world
}

// The `assembly:` and `registration:` sections (stages 1-2). Every value set below
// differs from the option structs' defaults, checked first, so a value that was
// not read cannot pass.
const std::string kStages = R"(
assembly:
  use_imu_prior: false
  icp: pcl
  max_iterations: 12
  max_correspondence_m: 0.35
  keyframe_yaw_deg: 7.5
  keyframe_translation_m: 0.15
  horizontal_stride: 3
  imu_smoothing_s: 0.05
  max_imu_gap_s: 0.04
  estimate_z: false
  z_cone_deg: 25
  include_horizontal: true
  refine_drift: false
  drift_segment_deg: 20
  drift_iterations: 2
  drift_voxel_m: 0.4
registration:
  method: gicp
  overlap_margin_m: 0.5
  search_radius_m: 1.5
  search_step_m: 0.25
  downsample_m: 0.1
  max_correspondence_m: 0.8
  max_iterations: 17
  ndt_resolution_m: 0.7
  use_recorded_yaw: true
  output_voxel_m: 0.03
)";

void expectStagesRead(const Config& c) {
  const scan::AssemblerOptions& a = c.assembly;
  EXPECT_FALSE(a.use_imu_prior);
  EXPECT_EQ(a.icp, scan::IcpMethod::PclPointToPoint);
  EXPECT_EQ(a.max_iterations, 12);
  EXPECT_DOUBLE_EQ(a.max_correspondence_m, 0.35);
  EXPECT_DOUBLE_EQ(a.keyframe_yaw_deg, 7.5);
  EXPECT_DOUBLE_EQ(a.keyframe_translation_m, 0.15);
  EXPECT_EQ(a.horizontal_stride, 3);
  EXPECT_DOUBLE_EQ(a.imu_smoothing_s, 0.05);
  EXPECT_DOUBLE_EQ(a.max_imu_gap_s, 0.04);
  EXPECT_FALSE(a.estimate_z);
  EXPECT_DOUBLE_EQ(a.z_cone_deg, 25.0);
  EXPECT_TRUE(a.include_horizontal);
  EXPECT_FALSE(a.refine_drift);
  EXPECT_DOUBLE_EQ(a.drift_segment_deg, 20.0);
  EXPECT_EQ(a.drift_iterations, 2);
  EXPECT_DOUBLE_EQ(a.drift_voxel_m, 0.4);
  const registration::RegistrationOptions& r = c.registration;
  EXPECT_EQ(r.method, registration::Method::Gicp);
  EXPECT_DOUBLE_EQ(r.overlap_margin_m, 0.5);
  EXPECT_DOUBLE_EQ(r.search_radius_m, 1.5);
  EXPECT_DOUBLE_EQ(r.search_step_m, 0.25);
  EXPECT_DOUBLE_EQ(r.downsample_m, 0.1);
  EXPECT_DOUBLE_EQ(r.max_correspondence_m, 0.8);
  EXPECT_EQ(r.max_iterations, 17);
  EXPECT_DOUBLE_EQ(r.ndt_resolution_m, 0.7);
  EXPECT_TRUE(r.use_recorded_yaw);
  EXPECT_DOUBLE_EQ(r.output_voxel_m, 0.03);
}

TEST(Scenario, AssemblyAndRegistrationDefaultToTheOptionStructs) {
  const Scenario s = parseScenario(kMinimal, "x.yaml");
  const scan::AssemblerOptions a;
  const registration::RegistrationOptions r;
  EXPECT_EQ(s.config.assembly.use_imu_prior, a.use_imu_prior);
  EXPECT_EQ(s.config.assembly.icp, a.icp);
  EXPECT_EQ(s.config.assembly.max_iterations, a.max_iterations);
  EXPECT_EQ(s.config.assembly.horizontal_stride, a.horizontal_stride);
  EXPECT_EQ(s.config.assembly.refine_drift, a.refine_drift);
  EXPECT_EQ(s.config.assembly.drift_iterations, a.drift_iterations);
  EXPECT_EQ(s.config.registration.method, r.method);
  EXPECT_EQ(s.config.registration.max_iterations, r.max_iterations);
  EXPECT_EQ(s.config.registration.output_voxel_m, r.output_voxel_m);
  // The test values below are not the defaults.
  EXPECT_TRUE(a.use_imu_prior);
  EXPECT_NE(a.icp, scan::IcpMethod::PclPointToPoint);
  EXPECT_FALSE(a.include_horizontal);
  EXPECT_TRUE(a.refine_drift);
  EXPECT_NE(r.method, registration::Method::Gicp);
  EXPECT_FALSE(r.use_recorded_yaw);
}

TEST(Scenario, AssemblyAndRegistrationValuesAreRead) {
  SCOPED_TRACE("scenario");
  expectStagesRead(parseScenario(kMinimal + kStages, "x.yaml").config);
}

TEST(Config, AssemblyAndRegistrationValuesAreRead) {
  SCOPED_TRACE("config");
  expectStagesRead(parseConfig(kStages, "c.yaml"));
  // Every registration method name maps to its enum value.
  const std::pair<const char*, registration::Method> methods[] = {
      {"none", registration::Method::None},
      {"translation", registration::Method::PointToPlaneTranslation},
      {"icp", registration::Method::Icp},
      {"icp_point_to_plane", registration::Method::IcpPointToPlane},
      {"gicp", registration::Method::Gicp},
      {"ndt", registration::Method::Ndt}};
  for (const auto& [name, method] : methods) {
    EXPECT_EQ(parseConfig(std::string("registration: {method: ") + name + "}\n", "c.yaml")
                  .registration.method,
              method)
        << name;
  }
  EXPECT_EQ(parseConfig("assembly: {icp: point_to_line}\n", "c.yaml").assembly.icp,
            scan::IcpMethod::PointToLine2D);
}

TEST(Scenario, AssemblyAndRegistrationAreStrict) {
  expectInputError(kMinimal + "assembly: {max_iteration: 5}\n",
                   {"x.yaml", "assembly.max_iteration", "not a known key"});
  expectInputError(kMinimal + "registration: {convergence: 1}\n",
                   {"x.yaml", "registration.convergence", "not a known key"});
  expectInputError(kMinimal + "registration: {method: sgd}\n",
                   {"x.yaml", "registration.method", "'sgd'", "gicp"});
  expectInputError(kMinimal + "assembly: {icp: svd}\n",
                   {"x.yaml", "assembly.icp", "'svd'", "point_to_line"});
  expectInputError(kMinimal + "registration: {method: [icp]}\n",
                   {"x.yaml", "registration.method", "string"});
  expectInputError(kMinimal + "assembly: {use_imu_prior: often}\n",
                   {"x.yaml", "assembly.use_imu_prior", "true or false"});
  expectInputError(kMinimal + "assembly: {horizontal_stride: 1.5}\n",
                   {"x.yaml", "assembly.horizontal_stride", "integer"});
  expectInputError(kMinimal + "registration: {downsample_m: fine}\n",
                   {"x.yaml", "registration.downsample_m", "number"});
  expectInputError(kMinimal + "assembly: 3\n", {"x.yaml", "assembly", "mapping"});
  // Values are checked by the options' own validate(), named by section.
  expectInputError(kMinimal + "assembly: {max_iterations: 0}\n",
                   {"x.yaml", "assembly", "max_iterations"});
  expectInputError(kMinimal + "assembly: {z_cone_deg: 95}\n", {"x.yaml", "assembly", "z_cone_deg"});
  expectInputError(kMinimal + "assembly: {drift_segment_deg: 0}\n",
                   {"x.yaml", "assembly", "drift_segment_deg"});
  expectInputError(kMinimal + "registration: {downsample_m: 0}\n",
                   {"x.yaml", "registration", "downsample_m"});
  expectInputError(kMinimal + "registration: {search_radius_m: -1}\n",
                   {"x.yaml", "registration", "search_radius_m"});
  EXPECT_THROW(parseConfig("registration: {method: sgd}\n", "c.yaml"), InputError);
}

TEST(Config, FlightModelAndHomeAreRead) {
  const Config d = parseConfig("", "c.yaml");
  EXPECT_FALSE(d.flight.home);
  EXPECT_DOUBLE_EQ(d.flight.model.endurance_s, 1200.0);
  const Config c = parseConfig(
      "mission: {home: [1, 2, 3]}\nflight: {cruise_speed_m_s: 4, climb_speed_m_s: 1, "
      "descent_speed_m_s: 0.5, hover_s: 0, "
      "settle_s: 0.5, endurance_s: 600, reserve: 0.3}\n",
      "c.yaml");
  ASSERT_TRUE(c.flight.home);
  EXPECT_EQ(*c.flight.home, Vec3(1, 2, 3));
  EXPECT_DOUBLE_EQ(c.flight.model.cruise_speed_m_s, 4.0);
  EXPECT_DOUBLE_EQ(c.flight.model.climb_speed_m_s, 1.0);
  EXPECT_DOUBLE_EQ(c.flight.model.descent_speed_m_s, 0.5);
  EXPECT_DOUBLE_EQ(c.flight.model.hover_s, 0.0);
  EXPECT_DOUBLE_EQ(c.flight.model.settle_s, 0.5);
  EXPECT_DOUBLE_EQ(c.flight.model.endurance_s, 600.0);
  EXPECT_DOUBLE_EQ(c.flight.model.reserve, 0.3);
  for (const std::string bad :
       {"flight: {reserve: 1}\n", "flight: {endurance_s: 0}\n", "flight: {hover_s: -1}\n",
        "flight: {speed: 3}\n", "mission: {home: [1, 2]}\n"}) {
    try {
      parseConfig(bad, "c.yaml");
      ADD_FAILURE() << "accepted " << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("c.yaml"), std::string::npos) << e.what();
    }
  }
}

// Validating a config names an unknown planner without creating one: creating an
// OMPL planner would seed OMPL's global RNG with the config's seed, and a later
// `bench --seed` could no longer take effect.
TEST(Config, ValidatingDoesNotSeedOmpl) {
  EXPECT_EXIT(
      {
        parseConfig("planner: {name: rrtconnect, seed: 5}\n", "c.yaml");
        std::exit(planners::seedOmpl(9) ? 0 : 1);
      },
      ::testing::ExitedWithCode(0), "");
  EXPECT_THROW(parseConfig("planner: {name: warp}\n", "c.yaml"), InputError);
}

TEST(Config, ScenarioOrConfigFile) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("uavip_cfg_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
    return (dir / name).string();
  };
  {
    SCOPED_TRACE("scenario file");
    expectStagesRead(loadConfigOrScenario(write("s.yaml", kMinimal + kStages)));
  }
  {
    SCOPED_TRACE("config file");
    expectStagesRead(loadConfigOrScenario(write("c.yaml", kStages)));
  }
  try {
    loadConfigOrScenario(write("bad.yaml", "registration: {method: sgd}\n"));
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find((dir / "bad.yaml").string() + ": registration.method"),
              std::string::npos)
        << e.what();
  }
  std::filesystem::remove_all(dir);
}

TEST(Scenario, ScanModeIsParsedStrictly) {
  const std::string base = R"(
name: s
world:
  - {type: box, min: [0, 0, 0], max: [1, 1, 1]}
  - {type: tree, name: t, at: [5, 5, 0], crown_boxes: 4, seed: 3}
  - {type: grass, name: g, center: [-3, 0, 0], size_m: [2, 1], tufts: 5}
sensing:
  mode: scan
  stations: [[3, 0, 0.5], [-3, 2, 0.5]]
  yaw_rate_deg_s: 45
  range_noise_m: 0.02
  imu_rate_hz: 2000
  imu_error_deg: 0.4
  wind_step_m: 0.001
  gps_sigma_m: 0.3
  seed: 9
)";
  const Scenario s = parseScenario(base, "s.yaml");
  EXPECT_EQ(s.sensing_mode, "scan");
  ASSERT_EQ(s.scan.stations.size(), 2u);
  EXPECT_EQ(s.scan.stations[1], Vec3(-3, 2, 0.5));
  EXPECT_DOUBLE_EQ(s.scan.yaw_rate_deg_s, 45.0);
  EXPECT_DOUBLE_EQ(s.scan.scanner.range_noise_m, 0.02);
  EXPECT_DOUBLE_EQ(s.scan.imu_rate_hz, 2000.0);
  EXPECT_DOUBLE_EQ(s.scan.imu_error_deg, 0.4);
  EXPECT_DOUBLE_EQ(s.scan.wind_step_m, 0.001);
  EXPECT_DOUBLE_EQ(s.scan.gps_sigma_m, 0.3);
  EXPECT_EQ(s.scan.seed, 9u);
  EXPECT_EQ(s.world.rects().size(), 6u + 6u * 5u + 6u * 5u);  // box, tree (trunk + 4), grass (5)
  // Stages 3-7 run in scenario coordinates: the stations are the viewpoints as given,
  // and they scanned the cloud (stage 4 orients normals by their line of sight).
  EXPECT_EQ(s.config.perception.planes.viewpoint, s.scan.stations[0]);
  ASSERT_EQ(s.config.perception.planes.extra_viewpoints.size(), 2u);
  EXPECT_EQ(s.config.perception.planes.extra_viewpoints[1], Vec3(-3, 2, 0.5));
  EXPECT_TRUE(s.config.perception.planes.viewpoints_scanned);

  auto expectError = [](const std::string& text, const std::string& fragment) {
    try {
      parseScenario(text, "s.yaml");
      ADD_FAILURE() << "expected an error with " << fragment;
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_EQ(msg.find('\n'), std::string::npos);
      EXPECT_NE(msg.find(fragment), std::string::npos) << msg;
    }
  };
  expectError(base + "  spacing_m: 0.05\n", "sensing.spacing_m is not a known key");
  expectError(base + "  yaw_rat_deg_s: 3\n", "yaw_rat_deg_s");
  expectError(std::regex_replace(base, std::regex("stations: .*"), "stations: [[1, 2]]"),
              "sensing.stations[0]");
  expectError(std::regex_replace(base, std::regex("imu_rate_hz: 2000"), "imu_rate_hz: -5"),
              "imu_rate_hz");
  expectError(std::regex_replace(base, std::regex("tufts: 5"), "tufts: 0"), "tufts");
  expectError(std::regex_replace(base, std::regex("mode: scan"), "mode: lidar"),
              "supported: sample, scan");
}

}  // namespace
}  // namespace uavip::app
