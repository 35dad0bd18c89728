// The one table of config keys (Config::table(), core/params.h) against the YAML
// reader: every key it lists is read into its field and recorded as set by the file,
// any other key is refused, a value out of its bounds is refused naming the file, the
// key and the value, options built in code meet the same bounds, and `auto` never
// overrides the file.

#include <gtest/gtest.h>

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
