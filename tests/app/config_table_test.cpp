// The one table of config keys (Config::table(), core/params.h) against the YAML
// reader: every key it lists is read into its field and recorded as set by the file,
// any other key is refused, a value out of its bounds is refused naming the file, the
// key and the value, options built in code meet the same bounds, and `auto` never
// overrides the file.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <set>
#include <sstream>

#include "uavip/app/config.h"
#include "uavip/app/scenario.h"
#include "uavip/core/error.h"

namespace uavip::app {
namespace {

/// `v` as YAML text for a row of `kind`.
std::string yamlOf(const params::Param<Config>& row, const params::Value& v) {
  std::ostringstream os;
  os.precision(17);
  switch (row.kind) {
    case params::Kind::Boolean:
      return v.number() != 0.0 ? "true" : "false";
    case params::Kind::Text:
      return "'" + v.text + "'";
    case params::Kind::Numbers:
      os << "[";
      for (std::size_t i = 0; i < v.numbers.size(); ++i) os << (i ? ", " : "") << v.numbers[i];
      os << "]";
      return os.str();
    default:
      os << v.number();
      return os.str();
  }
}

/// "section" and "key" of "section.key".
std::pair<std::string, std::string> split(const std::string& key) {
  const std::size_t dot = key.find('.');
  return {key.substr(0, dot), key.substr(dot + 1)};
}

std::string errorOf(const std::string& yaml) {
  try {
    parseConfig(yaml, "x.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ConfigTable, EveryKeyIsReadIntoItsFieldAndRecordedAsSet) {
  const Config defaults;
  ASSERT_FALSE(Config::table().rows().empty());
  std::set<std::string> keys;
  for (const auto& row : Config::table().rows()) {
    EXPECT_TRUE(keys.insert(row.key).second) << row.key << " declared twice";
    EXPECT_FALSE(row.help.empty()) << row.key;
    params::Value v = row.get(defaults);
    if (!v.present) continue;  // an optional with no default: set elsewhere in these tests
    // A value other than the default where the bounds allow, so reading it is seen.
    if (row.kind == params::Kind::Boolean) v.numbers = {v.number() != 0.0 ? 0.0 : 1.0};
    const auto [section, key] = split(row.key);
    const Config c = parseConfig(section + ":\n  " + key + ": " + yamlOf(row, v) + "\n", "x.yaml");
    EXPECT_TRUE(c.sources.fromFile(row.key)) << row.key;
    EXPECT_EQ(row.get(c).numbers, v.numbers) << row.key;
    EXPECT_EQ(row.get(c).text, v.text) << row.key;
    EXPECT_FALSE(defaults.sources.fromFile(row.key));
  }
}

/// A value of `row` other than `v` (its default) inside the row's bounds: another
/// choice, the other boolean, the middle of a closed range, or 10 past a one-sided bound.
params::Value otherValue(const params::Param<Config>& row, params::Value v) {
  if (row.kind == params::Kind::Text) {
    for (const auto& c : row.choices) {
      if (c != v.text) {
        v.text = c;
        return v;
      }
    }
    v.text += "x";
    return v;
  }
  const bool whole = row.kind != params::Kind::Number && row.kind != params::Kind::Numbers;
  for (double& d : v.numbers) {
    if (row.kind == params::Kind::Boolean) {
      d = d != 0.0 ? 0.0 : 1.0;
    } else if (std::isfinite(row.min) && std::isfinite(row.max)) {
      d = 0.5 * (row.min + row.max);
    } else if (std::isfinite(row.max)) {
      d = row.max - 1.0;
    } else {
      d = std::max(d, std::isfinite(row.min) ? row.min : 0.0) + 10.0;
    }
    if (whole || row.whole) d = std::floor(d);
  }
  return v;
}

// For every row with a default: the file's value (first the default, then another value
// in bounds) reads back into the row's field and nowhere else, and only its key is
// recorded as set by the file. The reference is a default-constructed Config.
TEST(ConfigTable, EveryRowReadsItsDefaultAndAnotherValueIntoItsFieldOnly) {
  const Config defaults;
  const auto& rows = Config::table().rows();
  std::set<std::string> no_default;
  for (const auto& row : rows) {
    const params::Value d = row.get(defaults);
    if (!d.present) {
      no_default.insert(row.key);
      continue;
    }
    // The aircraft profile's own keys set other keys at the profile layer by design
    // (tests/app/config_test.cpp, AircraftProfile): here only their default is read.
    const bool profile_key = row.key == defaults.keyOf(&defaults.uav.model) ||
                             row.key == defaults.keyOf(&defaults.uav.payload);
    const std::vector<params::Value> values =
        profile_key ? std::vector<params::Value>{d}
                    : std::vector<params::Value>{d, otherValue(row, d)};
    for (const params::Value& v : values) {
      const auto [section, key] = split(row.key);
      const std::string yaml = section + ":\n  " + key + ": " + yamlOf(row, v) + "\n";
      SCOPED_TRACE(yaml);
      const Config c = parseConfig(yaml, "x.yaml");
      EXPECT_EQ(c.sources.of(row.key), params::Source::File);
      EXPECT_EQ(row.get(c).numbers, v.numbers);
      EXPECT_EQ(row.get(c).text, v.text);
      for (const auto& other : rows) {
        if (other.key == row.key) continue;
        EXPECT_EQ(c.sources.of(other.key), params::Source::Default) << other.key;
        EXPECT_EQ(other.get(c).numbers, other.get(defaults).numbers) << other.key;
        EXPECT_EQ(other.get(c).text, other.get(defaults).text) << other.key;
      }
    }
  }
  // The rows with no default: optional points and radii, and the keys of the camera
  // models other than the default footprint (read in CameraModelsAreReadWhole below).
  const std::set<std::string> expected{"uav.inflation_radius_m",
                                       "mission.start",
                                       "mission.home",
                                       "fleet.homes",
                                       "coverage.ground_z_m",
                                       "camera.sensor_mm",
                                       "camera.focal_mm",
                                       "camera.image_px",
                                       "camera.gsd_mm_per_px",
                                       "camera.fx",
                                       "camera.fy",
                                       "camera.cx",
                                       "camera.cy"};
  EXPECT_EQ(no_default, expected);
}

TEST(ConfigTable, CameraModelsAreReadWhole) {
  const Config pin =
      parseConfig("camera: {fx: 1000, fy: 900, image_px: [640, 480], max_range_m: 30}\n", "x.yaml");
  const auto& p = pin.coverage.camera;
  EXPECT_TRUE(p.pinhole);
  EXPECT_FALSE(p.from_sensor);
  EXPECT_EQ(p.fx_px, 1000.0);
  EXPECT_EQ(p.fy_px, 900.0);
  EXPECT_EQ(p.image_w_px, 640);
  EXPECT_EQ(p.image_h_px, 480);
  EXPECT_EQ(p.cx_px, 320.0);  // the image centre when not given
  EXPECT_EQ(p.cy_px, 240.0);
  EXPECT_EQ(p.gsd_mm_per_px, 0.0);
  EXPECT_EQ(p.max_range_m, 30.0);
  const Config sen = parseConfig(
      "camera: {image_px: [5472, 3648], sensor_mm: [13.2, 8.8], focal_mm: 8.8, gsd_mm_per_px: 2}\n",
      "x.yaml");
  const auto& s = sen.coverage.camera;
  EXPECT_TRUE(s.from_sensor);
  EXPECT_FALSE(s.pinhole);
  EXPECT_EQ(s.sensor_w_mm, 13.2);
  EXPECT_EQ(s.sensor_h_mm, 8.8);
  EXPECT_EQ(s.focal_mm, 8.8);
  EXPECT_EQ(s.image_w_px, 5472);
  EXPECT_EQ(s.gsd_mm_per_px, 2.0);
  EXPECT_TRUE(sen.sources.anyFromFile("camera."));
  EXPECT_EQ(errorOf("camera: {fx: 1000, image_px: [640, 480]}\n"),
            "x.yaml: camera.fy is missing (a pinhole camera needs fx, fy and image_px)");
  EXPECT_EQ(errorOf("camera: {fx: 1, fy: 1, image_px: [2, 2], focal_mm: 8}\n"),
            "x.yaml: camera.focal_mm conflicts with fx/fy (a pinhole camera); describe the "
            "camera one way only");
  EXPECT_EQ(errorOf("camera: {sensor_mm: [13.2, 8.8], focal_mm: 8.8, image_px: [10, 10]}\n"),
            "x.yaml: camera.gsd_mm_per_px is missing (a sensor camera needs sensor_mm, focal_mm, "
            "image_px and gsd_mm_per_px)");
  EXPECT_EQ(errorOf("camera: {footprint_m: [1, 1], gsd_mm_per_px: 2}\n"),
            "x.yaml: camera gives both footprint_m and a sensor; use one of them");
  EXPECT_EQ(errorOf("camera: {fx: 1, fy: 1, image_px: [2.5, 2]}\n"),
            "x.yaml: camera.image_px must hold whole numbers, got 2.5");
}

TEST(ConfigTable, AnUnknownKeyInEverySectionIsRefusedNamingFileAndKey) {
  std::set<std::string> sections;
  for (const auto& row : Config::table().rows()) sections.insert(split(row.key).first);
  EXPECT_GE(sections.size(), 12U);
  for (const auto& section : sections) {
    const std::string msg = errorOf(section + ":\n  no_such_key: 1\n");
    EXPECT_EQ(msg.rfind("x.yaml: " + section + ".no_such_key is not a known key", 0), 0U) << msg;
  }
}

/// A value just outside `row`'s bounds (below the lower one when there is one), or a
/// text no choice matches; nullopt when the row has neither.
std::optional<params::Value> outside(const params::Param<Config>& row, params::Value v) {
  if (row.kind == params::Kind::Text) {
    if (row.choices.empty()) return std::nullopt;
    v.text = "no_such_choice";
    return v;
  }
  if (!row.bounded() || row.kind == params::Kind::Boolean) return std::nullopt;
  const bool whole = row.kind == params::Kind::Integer;
  for (double& d : v.numbers) {
    if (std::isfinite(row.min)) {
      d = row.min_open ? row.min : row.min - (whole ? 1.0 : 0.5);
    } else {
      d = row.max_open ? row.max : row.max + (whole ? 1.0 : 0.5);
    }
  }
  return v;
}

// Every bounded row refuses a value outside its bounds, in a file (naming the file, the
// key and the value) and in options built in code (Config::validate).
TEST(ConfigTable, EveryBoundedRowRefusesAValueOutsideItsBounds) {
  const Config defaults;
  int bounded = 0;
  for (const auto& row : Config::table().rows()) {
    params::Value d = row.get(defaults);
    if (!d.present)
      d = {std::vector<double>(std::max<std::size_t>(row.min_count, 1), 1.0), {}, true};
    const auto bad = outside(row, d);
    if (!bad) continue;
    ++bounded;
    const auto [section, key] = split(row.key);
    EXPECT_EQ(errorOf(section + ":\n  " + key + ": " + yamlOf(row, *bad) + "\n"),
              "x.yaml: " + row.key + " " + row.problem(*bad));
    // Options built in code: a double field (an unsigned one cannot hold the value).
    if (row.get(defaults).present && row.kind == params::Kind::Number) {
      Config c;
      row.set(c, *bad);
      EXPECT_THROW(c.validate("code"), InputError) << row.key;
    }
  }
  EXPECT_GE(bounded, 50);
}

// `auto` sets only the rows marked kAuto, and every such row the rules resolve ends as
// set by auto when the file left it, by the file when the file set it.
TEST(ConfigTable, AutoSetsOnlyAutoRows) {
  preprocess::CloudStats stats;
  stats.spacing_m = 0.4;
  stats.noise_m = 0.01;
  stats.points = 1000;
  stats.extent_m = Vec3(100, 100, 30);
  const ResolvedConfig r = resolveConfig(parseConfig("", "x.yaml"), stats);
  int auto_rows = 0;
  for (const auto& row : Config::table().rows()) {
    if (r.config.sources.of(row.key) == params::Source::Auto) {
      EXPECT_NE(row.layers & params::kAuto, 0U) << row.key;
      ++auto_rows;
    }
  }
  EXPECT_GE(auto_rows, 7);
  EXPECT_EQ(r.config.sources.of("preprocess.voxel_m"), params::Source::Auto);
  EXPECT_EQ(r.config.sources.of("grid.resolution_m"), params::Source::Auto);
  EXPECT_DOUBLE_EQ(r.config.preprocess.voxel_m, 0.4);  // max(0.05, spacing)
  const ResolvedConfig f = resolveConfig(
      parseConfig("preprocess: {voxel_m: 0.07}\ngrid: {resolution_m: 0.3}\n", "x.yaml"), stats);
  EXPECT_EQ(f.config.sources.of("preprocess.voxel_m"), params::Source::File);
  EXPECT_DOUBLE_EQ(f.config.preprocess.voxel_m, 0.07);
  EXPECT_DOUBLE_EQ(f.config.grid.resolution_m, 0.3);
  for (const auto& v : f.values) {
    if (v.key == "preprocess.voxel_m" || v.key == "grid.resolution_m") {
      EXPECT_EQ(v.source, "set");
    }
  }
}

TEST(ConfigTable, AKeyNoTableListsIsRefusedWithTheTablesKeys) {
  const std::string msg = errorOf("perception:\n  distance_treshold_m: 0.1\n");
  EXPECT_NE(msg.find("x.yaml: perception.distance_treshold_m is not a known key"),
            std::string::npos)
      << msg;
  for (const auto& row : Config::table().rows()) {
    const auto [section, key] = split(row.key);
    if (section == "perception") {
      EXPECT_NE(msg.find(key), std::string::npos) << key;
    }
  }
}

TEST(ConfigTable, OutOfBoundsNamesTheFileTheKeyAndTheValue) {
  EXPECT_EQ(errorOf("perception: {distance_threshold_m: 0}\n"),
            "x.yaml: perception.distance_threshold_m must be > 0, got 0");
  EXPECT_EQ(errorOf("perception: {min_inliers: 2}\n"),
            "x.yaml: perception.min_inliers must be >= 3, got 2");
  EXPECT_EQ(errorOf("perception: {boundary: round}\n"),
            "x.yaml: perception.boundary must be one of outline, convex, got 'round'");
  EXPECT_EQ(errorOf("perception: {seed: -1}\n"), "x.yaml: perception.seed must be >= 0, got -1");
}

TEST(ConfigTable, OptionsBuiltInCodeMeetTheSameBounds) {
  perception::PlaneDetectionOptions planes;
  EXPECT_NO_THROW(planes.validate());
  planes.cell_size_m = 0.0;
  try {
    planes.validate();
    FAIL() << "a zero area cell accepted";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "perception: area_cell_m must be > 0, got 0");
  }
  perception::ClusterOptions clusters;
  clusters.min_points = 0;
  EXPECT_THROW(clusters.validate(), InputError);
}

TEST(ConfigTable, AutoFillsWhatTheFileLeftAndNeverOverridesIt) {
  Config c = parseConfig("perception: {distance_threshold_m: 0.15}\n", "x.yaml");
  // A profile's value is below auto: auto replaces it.
  c.sources.set(c.keyOf(&c.perception.planes.open_voxel_m), params::Source::Profile);
  preprocess::CloudStats stats;
  stats.spacing_m = 0.4;  // sparse: every auto rule moves off the paper's value
  stats.noise_m = 0.01;
  stats.points = 1000;
  stats.extent_m = Vec3(10, 10, 10);
  const ResolvedConfig r = resolveConfig(c, stats);
  const auto& planes = r.config.perception.planes;
  EXPECT_DOUBLE_EQ(planes.distance_threshold_m, 0.15);
  EXPECT_TRUE(r.config.sources.fromFile("perception.distance_threshold_m"));
  EXPECT_EQ(r.config.sources.of("perception.open_voxel_m"), params::Source::Auto);
  EXPECT_DOUBLE_EQ(planes.open_voxel_m, 0.8);  // max(0.1, 2 spacing)
  EXPECT_EQ(r.config.sources.of("perception.plane_cluster_tolerance_m"), params::Source::Auto);
  for (const auto& v : r.values) {
    if (v.key == "perception.distance_threshold_m") {
      EXPECT_EQ(v.source, "set");
    }
    if (v.key == "perception.open_voxel_m") {
      EXPECT_EQ(v.source, "auto: max(0.1, 2 spacing')");
    }
  }
  // Every key auto resolves is one its table marks auto.
  for (const auto& v : r.values) {
    for (const auto& row : Config::table().rows()) {
      if (row.key == v.key && v.source.rfind("auto", 0) == 0) {
        EXPECT_NE(row.layers & params::kAuto, 0U) << v.key;
      }
    }
  }
}

}  // namespace
}  // namespace uavip::app
