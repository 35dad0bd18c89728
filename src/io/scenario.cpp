#include "uavip/io/scenario.h"

#include "uavip/core/error.h"
#include "uavip/io/atomic_file.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <set>
#include <sstream>

namespace uavip::io {
namespace {

/// A YAML mapping read strictly: every key must be consumed, types are checked, and
/// every message names the file and the key path.
class Section {
 public:
  Section(YAML::Node node, std::string file, std::string path)
      : node_(std::move(node)), file_(std::move(file)), path_(std::move(path)) {
    if (!node_.IsMap()) fail("", "must be a mapping (key: value)");
  }

  bool has(const std::string& key) {
    known_.insert(key);
    return node_[key].IsDefined() && !node_[key].IsNull();
  }

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw InputError(file_ + ": " + where(key) + " " + what);
  }

  std::string where(const std::string& key) const {
    if (path_.empty()) return key.empty() ? std::string("top level") : key;
    return key.empty() ? path_ : path_ + "." + key;
  }

  double number(const std::string& key) {
    const YAML::Node n = get(key);
    double v = 0.0;
    if (!n.IsScalar() || !YAML::convert<double>::decode(n, v)) {
      fail(key, "must be a number, got '" + dump(n) + "'");
    }
    if (!std::isfinite(v)) fail(key, "must be finite, got " + dump(n));
    return v;
  }
  double number(const std::string& key, double fallback) { return has(key) ? number(key) : fallback; }

  int integer(const std::string& key, int fallback) {
    if (!has(key)) return fallback;
    const YAML::Node n = get(key);
    long long v = 0;
    if (!n.IsScalar() || !YAML::convert<long long>::decode(n, v)) {
      fail(key, "must be an integer, got '" + dump(n) + "'");
    }
    if (v < -2147483647LL || v > 2147483647LL) fail(key, "is out of range: " + dump(n));
    return static_cast<int>(v);
  }

  bool boolean(const std::string& key, bool fallback) {
    if (!has(key)) return fallback;
    const YAML::Node n = get(key);
    bool v = false;
    if (!n.IsScalar() || !YAML::convert<bool>::decode(n, v)) {
      fail(key, "must be true or false, got '" + dump(n) + "'");
    }
    return v;
  }

  std::string text(const std::string& key) {
    const YAML::Node n = get(key);
    if (!n.IsScalar()) fail(key, "must be a string");
    return n.Scalar();
  }
  std::string text(const std::string& key, const std::string& fallback) {
    return has(key) ? text(key) : fallback;
  }

  std::vector<double> numbers(const std::string& key, std::size_t min_count, std::size_t max_count) {
    const YAML::Node n = get(key);
    if (!n.IsSequence() || n.size() < min_count || n.size() > max_count) {
      std::ostringstream os;
      os << "must be a list of " << min_count;
      if (max_count != min_count) os << " to " << max_count;
      os << " numbers, got '" << dump(n) << "'";
      fail(key, os.str());
    }
    std::vector<double> out;
    for (const auto& item : n) {
      double v = 0.0;
      if (!item.IsScalar() || !YAML::convert<double>::decode(item, v) || !std::isfinite(v)) {
        fail(key, "must hold finite numbers, got '" + dump(n) + "'");
      }
      out.push_back(v);
    }
    return out;
  }

  Vec3 vec3(const std::string& key) {
    const auto v = numbers(key, 3, 3);
    return {v[0], v[1], v[2]};
  }
  Vec3 vec3(const std::string& key, const Vec3& fallback) { return has(key) ? vec3(key) : fallback; }

  Section child(const std::string& key) { return Section(get(key), file_, where(key)); }

  /// Throws for any key that was never asked for (typos, unsupported options).
  void finish() const {
    for (const auto& kv : node_) {
      const std::string key = kv.first.as<std::string>();
      if (!known_.count(key)) {
        std::string valid;
        for (const auto& k : known_) valid += (valid.empty() ? "" : ", ") + k;
        fail(key, "is not a known key (valid here: " + valid + ")");
      }
    }
  }

  const YAML::Node& node() const { return node_; }
  const std::string& file() const { return file_; }

 private:
  YAML::Node get(const std::string& key) {
    known_.insert(key);
    const YAML::Node n = node_[key];
    if (!n.IsDefined() || n.IsNull()) fail(key, "is missing");
    return n;
  }

  static std::string dump(const YAML::Node& n) {
    YAML::Emitter e;
    e << YAML::Flow << n;
    return e.c_str();
  }

  YAML::Node node_;
  std::string file_;
  std::string path_;
  std::set<std::string> known_;
};

void parsePreprocess(Section s, preprocess::PreprocessOptions& o) {
  o.remove_outliers = s.boolean("remove_outliers", o.remove_outliers);
  o.outlier_k = s.integer("outlier_k", o.outlier_k);
  o.outlier_std_ratio = s.number("outlier_std_ratio", o.outlier_std_ratio);
  o.voxelize = s.boolean("voxelize", o.voxelize);
  o.voxel_m = s.number("voxel_m", o.voxel_m);
  s.finish();
}

void parsePerception(Section s, perception::PerceptionOptions& o) {
  auto& p = o.planes;
  p.distance_threshold_m = s.number("distance_threshold_m", p.distance_threshold_m);
  p.max_iterations = s.integer("max_iterations", p.max_iterations);
  p.min_area_m2 = s.number("min_area_m2", p.min_area_m2);
  p.cluster_tolerance_m = s.number("plane_cluster_tolerance_m", p.cluster_tolerance_m);
  p.max_planes = s.integer("max_planes", p.max_planes);
  p.max_failures = s.integer("max_failures", p.max_failures);
  p.seed = static_cast<std::uint32_t>(s.integer("seed", static_cast<int>(p.seed)));
  p.viewpoint = s.vec3("viewpoint", p.viewpoint);
  o.clusters.tolerance_m = s.number("obstacle_tolerance_m", o.clusters.tolerance_m);
  o.clusters.min_points = s.integer("obstacle_min_points", o.clusters.min_points);
  s.finish();
}

void parseUav(Section s, UavConfig& o) {
  o.size_m = s.vec3("size_m", o.size_m);
  if (s.has("inflation_radius_m")) o.inflation_radius_m = s.number("inflation_radius_m");
  s.finish();
}

void parseGrid(Section s, world::GridOptions& o) {
  o.resolution_m = s.number("resolution_m", o.resolution_m);
  o.padding_m = s.number("padding_m", o.padding_m);
  s.finish();
}

void parseCamera(Section s, coverage::Camera& c) {
  if (s.has("footprint_m")) {
    const auto f = s.numbers("footprint_m", 2, 2);
    c.footprint_w_m = f[0];
    c.footprint_h_m = f[1];
  }
  if (s.has("sensor_mm") || s.has("focal_mm") || s.has("image_px") || s.has("gsd_mm_per_px")) {
    if (s.has("footprint_m")) s.fail("", "gives both footprint_m and a sensor; use one of them");
    c.from_sensor = true;
    const auto sensor = s.numbers("sensor_mm", 2, 2);
    c.sensor_w_mm = sensor[0];
    c.sensor_h_mm = sensor[1];
    c.focal_mm = s.number("focal_mm");
    const auto px = s.numbers("image_px", 2, 2);
    if (px[0] != std::floor(px[0]) || px[1] != std::floor(px[1]) || px[0] > 1e6 || px[1] > 1e6) {
      s.fail("image_px", "must be two whole pixel counts");
    }
    c.image_w_px = static_cast<int>(px[0]);
    c.image_h_px = static_cast<int>(px[1]);
    c.gsd_mm_per_px = s.number("gsd_mm_per_px");
  }
  s.finish();
}

void parseCoverage(Section s, coverage::CoverageOptions& o) {
  if (s.has("overlap")) {
    if (s.node()["overlap"].IsSequence()) {
      const auto v = s.numbers("overlap", 2, 2);
      o.overlap_w = v[0];
      o.overlap_h = v[1];
    } else {
      o.overlap_w = o.overlap_h = s.number("overlap");
    }
  }
  o.standoff_m = s.number("standoff_m", o.standoff_m);
  if (s.has("gimbal_pitch_deg")) {
    const auto v = s.numbers("gimbal_pitch_deg", 2, 2);
    o.gimbal.pitch_min_deg = v[0];
    o.gimbal.pitch_max_deg = v[1];
  }
  s.finish();
}

void parsePlanner(Section s, Config& c) {
  c.planner = s.text("name", c.planner);
  auto& a = c.planner_settings.astar;
  if (s.has("cost_weights")) {
    const auto w = s.numbers("cost_weights", 3, 3);
    a.a1 = w[0];
    a.a2 = w[1];
    a.a3 = w[2];
  }
  const int budget = s.integer("max_expansions", static_cast<int>(a.max_expansions));
  if (budget < 0) s.fail("max_expansions", "must be >= 0 (0 = unlimited), got " + std::to_string(budget));
  a.max_expansions = static_cast<std::size_t>(budget);
  s.finish();
}

void parseMission(Section s, planning::MissionOptions& o) {
  o.simplify = s.boolean("simplify", o.simplify);
  if (s.has("start")) o.start = s.vec3("start");
  s.finish();
}

/// Reads the config sections present in `top` (unknown keys are left to the caller).
void parseConfigSections(Section& top, Config& c) {
  if (top.has("preprocess")) parsePreprocess(top.child("preprocess"), c.preprocess);
  if (top.has("perception")) parsePerception(top.child("perception"), c.perception);
  if (top.has("uav")) parseUav(top.child("uav"), c.uav);
  if (top.has("grid")) parseGrid(top.child("grid"), c.grid);
  if (top.has("camera")) parseCamera(top.child("camera"), c.coverage.camera);
  if (top.has("coverage")) parseCoverage(top.child("coverage"), c.coverage);
  if (top.has("planner")) parsePlanner(top.child("planner"), c);
  if (top.has("mission")) parseMission(top.child("mission"), c.mission);
}

void parseWorldItem(Section s, sim::WorldModel& world, std::size_t index) {
  const std::string type = s.text("type");
  const std::string name = s.text("name", type + std::to_string(index));
  if (type == "point") {
    world.addPoint(name, s.vec3("at"));
  } else if (type == "line") {
    world.addLine(name, s.vec3("from"), s.vec3("to"));
  } else if (type == "plane") {
    sim::Rect r;
    r.name = name;
    r.corner = s.vec3("corner");
    r.edge_u = s.vec3("edge_u");
    r.edge_v = s.vec3("edge_v");
    world.addPlane(r);
  } else if (type == "box") {
    world.addBox(name, s.vec3("min"), s.vec3("max"), s.number("yaw_deg", 0.0));
  } else if (type == "crossed_planes") {
    world.addCrossedPlanes(name, s.vec3("center"), s.number("width_m"), s.number("height_m"),
                           s.number("yaw_deg", 0.0));
  } else {
    s.fail("type", "'" + type + "' is not a primitive (point, line, plane, box, crossed_planes)");
  }
  s.finish();
}

YAML::Node parseYaml(const std::string& text, const std::string& path) {
  try {
    return YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError(path + ": not valid YAML (line " + std::to_string(e.mark.line + 1) + "): " + e.msg);
  }
}

/// Wraps errors thrown by option constructors (world primitives) with the file name.
template <typename F>
void withFile(const std::string& path, F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    const std::string msg = e.what();
    if (msg.rfind(path, 0) == 0) throw;
    throw InputError(path + ": " + msg);
  }
}

}  // namespace

void Config::validate(const std::string& where) const {
  withFile(where, [&] {
    preprocess.validate("preprocess");
    perception.validate("perception");
    for (int i = 0; i < 3; ++i) requirePositive(uav.size_m[i], "uav", "size_m");
    requirePositive(uav.inflationRadius(), "uav", "inflation_radius_m");
    gridOptions().validate("grid");
    coverage.validate("coverage");
    planner_settings.astar.validate("planner");
    planners::makePlanner(planner, planner_settings);  // throws for an unknown name
    if (mission.start) require(mission.start->allFinite(), "mission", "start must be finite");
  });
}

world::GridOptions Config::gridOptions() const {
  world::GridOptions g = grid;
  g.inflation_radius_m = uav.inflationRadius();
  return g;
}

Config parseConfig(const std::string& yaml_text, const std::string& path) {
  Config c;
  const YAML::Node root = parseYaml(yaml_text, path);
  if (root.IsNull()) return c;  // an empty config means defaults
  Section top(root, path, "");
  withFile(path, [&] { parseConfigSections(top, c); });
  top.finish();
  if (c.preprocess.voxelize) c.perception.planes.cell_size_m = c.preprocess.voxel_m;
  c.validate(path);
  return c;
}

Config loadConfig(const std::string& path) { return parseConfig(readFile(path), path); }

Scenario parseScenario(const std::string& yaml_text, const std::string& path) {
  Scenario sc;
  sc.path = path;
  const YAML::Node root = parseYaml(yaml_text, path);
  if (!root.IsMap()) throw InputError(path + ": a scenario must be a YAML mapping with name, world, sensing");
  Section top(root, path, "");
  sc.name = top.text("name");
  sc.description = top.text("description", "");

  withFile(path, [&] {
    const YAML::Node world = root["world"];
    top.has("world");
    if (!world.IsDefined() || !world.IsSequence()) top.fail("world", "must be a list of primitives");
    for (std::size_t i = 0; i < world.size(); ++i) {
      parseWorldItem(Section(world[i], path, "world[" + std::to_string(i) + "]"), sc.world, i);
    }

    Section sensing = top.child("sensing");
    sc.sensing_mode = sensing.text("mode", "sample");
    if (sc.sensing_mode != "sample") {
      sensing.fail("mode", "'" + sc.sensing_mode + "' is not supported (supported: sample)");
    }
    sc.sample.spacing_m = sensing.number("spacing_m", sc.sample.spacing_m);
    sc.sample.noise_sigma_m = sensing.number("noise_sigma_m", sc.sample.noise_sigma_m);
    sc.sample.outlier_fraction = sensing.number("outlier_fraction", sc.sample.outlier_fraction);
    sc.sample.outlier_margin_m = sensing.number("outlier_margin_m", sc.sample.outlier_margin_m);
    const int seed = sensing.integer("seed", static_cast<int>(sc.sample.seed));
    if (seed < 0) sensing.fail("seed", "must be >= 0, got " + std::to_string(seed));
    sc.sample.seed = static_cast<std::uint32_t>(seed);
    if (sensing.has("viewpoint")) sc.config.perception.planes.viewpoint = sensing.vec3("viewpoint");
    sensing.finish();
    sc.sample.validate("sensing");

    parseConfigSections(top, sc.config);

    if (top.has("expect")) {
      Section e = top.child("expect");
      if (e.has("surfaces")) sc.expect.surfaces = e.integer("surfaces", 0);
      if (e.has("status")) sc.expect.status = e.text("status");
      if (e.has("min_surface_area_m2")) sc.expect.min_surface_area_m2 = e.number("min_surface_area_m2");
      e.finish();
    }
  });
  top.finish();
  if (sc.world.empty()) top.fail("world", "is empty: add at least one primitive");
  // The density area of stage 4 uses the spacing of the clean cloud.
  sc.config.perception.planes.cell_size_m =
      sc.config.preprocess.voxelize ? std::max(sc.config.preprocess.voxel_m, sc.sample.spacing_m)
                                    : sc.sample.spacing_m;
  sc.config.validate(path);
  return sc;
}

Scenario loadScenario(const std::string& path) { return parseScenario(readFile(path), path); }

}  // namespace uavip::io
