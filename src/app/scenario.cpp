#include "uavip/app/scenario.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <initializer_list>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include "uavip/app/aircraft_profile.h"
#include "uavip/core/aircraft.h"
#include "uavip/core/error.h"
#include "uavip/core/text.h"
#include "uavip/io/atomic_file.h"
#include "yaml_section.h"

namespace uavip::app {
namespace {

using yaml::Section;

void parseBench(Section s, BenchSpec& b) {
  if (s.has("legs")) {
    const YAML::Node legs = s.node()["legs"];
    if (!legs.IsSequence()) s.fail("legs", "must be a list of [[x, y, z], [x, y, z]] pairs");
    for (std::size_t i = 0; i < legs.size(); ++i) {
      const std::string key = "legs[" + std::to_string(i) + "]";
      const YAML::Node leg = legs[i];
      if (!leg.IsSequence() || leg.size() != 2)
        s.fail(key, "must be a pair [[x, y, z], [x, y, z]]");
      Vec3 ends[2];
      for (std::size_t e = 0; e < 2; ++e) {
        const YAML::Node p = leg[e];
        if (!p.IsSequence() || p.size() != 3) s.fail(key, "must hold two points of 3 numbers");
        for (std::size_t k = 0; k < 3; ++k) {
          double v = 0.0;
          if (!p[k].IsScalar() || !YAML::convert<double>::decode(p[k], v) || !std::isfinite(v)) {
            s.fail(key, "must hold finite numbers");
          }
          ends[e][static_cast<int>(k)] = v;
        }
      }
      b.legs.emplace_back(ends[0], ends[1]);
    }
  }
  b.max_legs = s.integer("max_legs", b.max_legs);
  if (b.max_legs < 1) s.fail("max_legs", "must be >= 1, got " + std::to_string(b.max_legs));
  s.finish();
}

/// A key's value as its row says (kind, count), refused unless within the row's bounds.
template <typename O>
params::Value readValue(Section& s, const params::Param<O>& p, const std::string& key) {
  params::Value v;
  switch (p.kind) {
    case params::Kind::Boolean:
      v.numbers = {s.boolean(key, false) ? 1.0 : 0.0};
      break;
    case params::Kind::Integer:
      v.numbers = {static_cast<double>(s.integer(key, 0))};
      break;
    case params::Kind::Number:
      v.numbers = {s.number(key)};
      break;
    case params::Kind::Text:
      v.text = s.text(key);
      break;
    case params::Kind::Numbers:
      if (p.scalar_ok && s.node()[key].IsScalar()) {
        v.numbers = {s.number(key)};
      } else if (s.node()[key].IsSequence() && s.node()[key].size() > 0 &&
                 s.node()[key][0].IsSequence()) {  // [[x, y, z], …]
        for (const auto& q : s.vec3List(key))
          v.numbers.insert(v.numbers.end(), {q.x(), q.y(), q.z()});
      } else {
        v.numbers = s.numbers(key, p.min_count, p.max_count);
      }
      break;
  }
  const std::string what = p.problem(v);
  if (!what.empty()) s.fail(key, what);
  return v;
}

/// Reads every key of Config::table() the file gives, section by section, and records
/// it as set by the file; a key no table lists throws (Section::finish).
void readTableKeys(Section& top, Config& c) {
  std::map<std::string, Section> sections;
  for (const auto& p : Config::table().rows()) {
    const std::size_t dot = p.key.find('.');
    const std::string section = p.key.substr(0, dot);
    const std::string key = p.key.substr(dot + 1);
    auto it = sections.find(section);
    if (it == sections.end()) {
      if (!top.has(section)) continue;
      it = sections.emplace(section, top.child(section)).first;
    }
    if (!it->second.has(key)) continue;
    p.set(c, readValue(it->second, p, key));
    c.sources.set(p.key, params::Source::File);
  }
  for (const auto& entry : sections) entry.second.finish();
}

/// The camera model the file's camera keys describe (coverage/camera.h: a sensor key
/// sets from_sensor, a pinhole key pinhole): refuses a second model's keys and a missing
/// key of the model; a pinhole's principal point defaults to the image centre.
void completeCamera(Section& top, Config& c) {
  using Fields = std::initializer_list<const void*>;
  coverage::Camera& cam = c.coverage.camera;
  const auto missing = [&](const void* field, const std::string& needs) {
    if (!c.setInFile(field)) top.fail(c.keyOf(field), "is missing (" + needs + ")");
  };
  const auto conflicts = [&](const void* field, const std::string& what) {
    if (c.setInFile(field)) top.fail(c.keyOf(field), what);
  };
  if (cam.pinhole) {
    const std::string what =
        "conflicts with fx/fy (a pinhole camera); describe the camera one way only";
    for (const void* f : Fields{&cam.footprint_w_m, &cam.sensor_w_mm, &cam.focal_mm})
      conflicts(f, what);
    const std::string needs = "a pinhole camera needs fx, fy and image_px";
    for (const void* f : Fields{&cam.fx_px, &cam.fy_px, &cam.image_w_px}) missing(f, needs);
    if (!c.setInFile(&cam.cx_px)) cam.cx_px = 0.5 * cam.image_w_px;
    if (!c.setInFile(&cam.cy_px)) cam.cy_px = 0.5 * cam.image_h_px;
  } else if (cam.from_sensor) {
    if (c.setInFile(&cam.footprint_w_m)) {
      const std::string& key = c.keyOf(&cam.footprint_w_m);
      top.fail(key.substr(0, key.find('.')),
               "gives both footprint_m and a sensor; use one of them");
    }
    const std::string needs =
        "a sensor camera needs sensor_mm, focal_mm, image_px and gsd_mm_per_px";
    for (const void* f :
         Fields{&cam.sensor_w_mm, &cam.focal_mm, &cam.image_w_px, &cam.gsd_mm_per_px})
      missing(f, needs);
  }
}

void parseConfigSections(Section& top, Config& c) {
  readTableKeys(top, c);
  completeCamera(top, c);
  applyAircraftProfile(c, "");
}

/// A non-negative `seed` key, or the fallback.
std::uint32_t seedOf(Section& s, std::uint32_t fallback) {
  const int seed = s.integer("seed", static_cast<int>(fallback));
  if (seed < 0) s.fail("seed", "must be >= 0, got " + std::to_string(seed));
  return static_cast<std::uint32_t>(seed);
}

/// Sensing mode `scan` (sim/scanner_sim.h).
void parseScanSensing(Section& s, sim::ScanSimOptions& o) {
  const YAML::Node list = s.node()["stations"];
  s.has("stations");
  if (!list.IsDefined() || !list.IsSequence() || list.size() == 0) {
    s.fail("stations", "must be a non-empty list of [x, y, z] station positions");
  }
  o.stations.clear();
  for (std::size_t i = 0; i < list.size(); ++i) {
    const YAML::Node p = list[i];
    double v[3] = {0.0, 0.0, 0.0};
    bool ok = p.IsSequence() && p.size() == 3;
    for (std::size_t k = 0; ok && k < 3; ++k) {
      ok = p[k].IsScalar() && YAML::convert<double>::decode(p[k], v[k]) && std::isfinite(v[k]);
    }
    if (!ok) s.fail("stations[" + std::to_string(i) + "]", "must be [x, y, z] with finite numbers");
    o.stations.emplace_back(v[0], v[1], v[2]);
  }
  o.start_yaw_deg = s.number("start_yaw_deg", o.start_yaw_deg);
  o.yaw_rate_deg_s = s.number("yaw_rate_deg_s", o.yaw_rate_deg_s);
  o.turn_deg = s.number("turn_deg", o.turn_deg);
  o.max_readings = s.number("max_readings", o.max_readings);
  o.scanner.max_range_m = s.number("max_range_m", o.scanner.max_range_m);
  o.scanner.min_range_m = s.number("min_range_m", o.scanner.min_range_m);
  o.scanner.fov_deg = s.number("fov_deg", o.scanner.fov_deg);
  o.scanner.step_deg = s.number("step_deg", o.scanner.step_deg);
  o.scanner.period_s = s.number("scan_period_s", o.scanner.period_s);
  o.scanner.range_noise_m = s.number("range_noise_m", o.scanner.range_noise_m);
  o.vertical_mount_m = s.vec3("vertical_mount_m", o.vertical_mount_m);
  o.horizontal_mount_m = s.vec3("horizontal_mount_m", o.horizontal_mount_m);
  o.vertical_mount_rpy_deg = s.vec3("vertical_mount_rpy_deg", o.vertical_mount_rpy_deg);
  o.horizontal_mount_rpy_deg = s.vec3("horizontal_mount_rpy_deg", o.horizontal_mount_rpy_deg);
  o.horizontal_time_offset_s = s.number("horizontal_time_offset_s", o.horizontal_time_offset_s);
  o.imu_rate_hz = s.number("imu_rate_hz", o.imu_rate_hz);
  o.imu_error_deg = s.number("imu_error_deg", o.imu_error_deg);
  o.wind_step_m = s.number("wind_step_m", o.wind_step_m);
  o.wind_bound_m = s.number("wind_bound_m", o.wind_bound_m);
  o.tilt_step_deg = s.number("tilt_step_deg", o.tilt_step_deg);
  o.tilt_bound_deg = s.number("tilt_bound_deg", o.tilt_bound_deg);
  o.gps_sigma_m = s.number("gps_sigma_m", o.gps_sigma_m);
  o.thin_radius_m = s.number("thin_radius_m", o.thin_radius_m);
  o.deskew = s.boolean("deskew", o.deskew);
  o.station_gap_s = s.number("station_gap_s", o.station_gap_s);
  o.seed = seedOf(s, o.seed);
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
  } else if (type == "tree") {
    sim::TreeOptions o;
    o.trunk_height_m = s.number("trunk_height_m", o.trunk_height_m);
    o.trunk_width_m = s.number("trunk_width_m", o.trunk_width_m);
    o.crown_radius_m = s.number("crown_radius_m", o.crown_radius_m);
    o.crown_boxes = s.integer("crown_boxes", o.crown_boxes);
    o.crown_box_m = s.number("crown_box_m", o.crown_box_m);
    o.seed = seedOf(s, static_cast<std::uint32_t>(index + 1));
    world.addTree(name, s.vec3("at"), o);
  } else if (type == "grass") {
    sim::GrassOptions o;
    if (s.has("size_m")) {
      const auto v = s.numbers("size_m", 2, 2);
      o.size_x_m = v[0];
      o.size_y_m = v[1];
    }
    o.tufts = s.integer("tufts", o.tufts);
    o.tuft_height_m = s.number("tuft_height_m", o.tuft_height_m);
    o.tuft_width_m = s.number("tuft_width_m", o.tuft_width_m);
    o.seed = seedOf(s, static_cast<std::uint32_t>(index + 1));
    world.addGrass(name, s.vec3("center"), o);
  } else {
    s.fail(
        "type",
        "'" + type + "' is not a primitive (point, line, plane, box, crossed_planes, tree, grass)");
  }
  s.finish();
}

YAML::Node parseYaml(const std::string& text, const std::string& path) {
  try {
    return YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError(path + ": not valid YAML (line " + std::to_string(e.mark.line + 1) +
                     "): " + e.msg);
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
    input.validate("input");
    preprocess.validate("preprocess");
    safety.validate("safety");
    perception.validate("perception");
    uav.validate("uav");
    gridOptions().validate("grid");
    coverage.validate("coverage");
    planner_settings.validate("planner");
    planning::requireKnownPlanner(planner);  // creates nothing, so OMPL stays unseeded
    missionOptions().validate("mission");
    if (flight.home) require(flight.home->allFinite(), "mission", "home must be finite");
    flightOptions().validate("flight");
    fleet.validate("fleet");
    requireThat(
        !fleet.active() || fleet.separation_m >= 2.0 * uav.inflationRadius(), "fleet",
        planning::FleetOptions::keyOf(&planning::FleetOptions::separation_m),
        ">= " + formatNumber(2.0 * uav.inflationRadius()) + " m (twice uav.inflation_radius_m)",
        fleet.separation_m);
    assembly.validate("assembly");
    registration.validate("registration");
  });
}

void UavConfig::validate(const std::string& where) const { table().check(*this, where); }

const params::Table<UavConfig>& UavConfig::table() {
  static const params::Table<UavConfig> t = [] {
    params::Table<UavConfig> p;
    std::vector<std::string> models;
    for (const auto& a : aircraft::profiles()) models.push_back(a.name);
    p.add("model", &UavConfig::model,
          "aircraft profile (core/aircraft.h): its camera, gimbal, speed, endurance and size "
          "where the file sets none; generic sets nothing")
        .oneOf(models);
    std::vector<std::string> payloads{""};
    for (const auto& a : aircraft::payloads()) payloads.push_back(a.name);
    p.add("payload", &UavConfig::payload,
          "m300/m350: the camera on the gimbal (empty: the drone's default)")
        .oneOf(payloads);
    p.add("size_m", &UavConfig::size_m, "the UAV's [x, y, z] extent (paper: 0.6 × 0.6 × 0.4 m)")
        .unitIs("m")
        .positive()
        .fromProfile();
    p.add("inflation_radius_m", &UavConfig::inflation_radius_m,
          "radius kept from every point (default: the largest of size_m)")
        .unitIs("m")
        .positive()
        .fromProfile();
    return p;
  }();
  return t;
}

const params::Table<Config>& Config::table() {
  static const params::Table<Config> t = [] {
    params::Table<Config> p;
    p.include("input.", &Config::input, io::CloudReadOptions::table());
    p.include("assembly.", &Config::assembly, scan::AssemblerOptions::table());
    p.include("registration.", &Config::registration, registration::RegistrationOptions::table());
    p.include("preprocess.", &Config::preprocess, preprocess::PreprocessOptions::table());
    p.include("safety.", &Config::safety, preprocess::SafetyOptions::table());
    p.include("perception.", &Config::perception, perception::PerceptionOptions::table());
    p.include("uav.", &Config::uav, UavConfig::table());
    p.include("grid.", &Config::grid, world::GridOptions::table());
    params::Table<coverage::CoverageOptions> camera;  // section camera: is coverage.camera
    camera.include("", &coverage::CoverageOptions::camera, coverage::Camera::table());
    p.include("camera.", &Config::coverage, camera);
    p.include("coverage.", &Config::coverage, coverage::CoverageOptions::table());
    p.add("planner.name", &Config::planner, "the planner of every leg (planning/planner_table.h)")
        .oneOf(planning::plannerNames());
    p.include("planner.", &Config::planner_settings, planning::PlannerSettings::table());
    p.include("mission.", &Config::mission, planning::MissionOptions::table());
    // mission.home is a field of the flight (planning/types.h FlightOptions::home).
    p.add(
         "mission.home", params::Kind::Numbers,
         [](const Config& c) { return params::toValue(c.flight.home); },
         [](Config& c, const params::Value& v) { params::fromValue(v, c.flight.home); },
         "take-off and landing point [x, y, z] of every sortie; must be free (default: "
         "mission.start, else the lowest stop)")
        .count(3, 3)
        .unitIs("m")
        .storedAt([](const Config& c) -> const void* { return &c.flight.home; });
    params::Table<planning::FlightOptions> flight;  // section flight: is flight.model
    flight.include("", &planning::FlightOptions::model, planning::FlightModel::table());
    p.include("flight.", &Config::flight, flight);
    p.include("fleet.", &Config::fleet, planning::FleetOptions::table());
    return p;
  }();
  return t;
}

const std::string& Config::keyOf(const void* field) const {
  const auto* row = table().find(*this, field);
  if (row == nullptr) throw std::logic_error("Config::keyOf: a field no parameter table lists");
  return row->key;
}

namespace {

/// A default as the reference prints it: 0.2, [0.6, 0.4], true, outline, "none".
std::string defaultText(const params::Param<Config>& row, const params::Value& v) {
  if (!v.present) return "none";
  switch (row.kind) {
    case params::Kind::Boolean:
      return v.number() != 0.0 ? "true" : "false";
    case params::Kind::Text:
      return v.text;
    case params::Kind::Numbers: {
      std::string out = "[";
      for (std::size_t i = 0; i < v.numbers.size(); ++i)
        out += (i ? ", " : "") + formatNumber(v.numbers[i]);
      return out + "]";
    }
    default:
      return formatNumber(v.number());
  }
}

/// The layers that may set a row, lowest first.
std::string layersText(unsigned layers) {
  std::string out = "default";
  if ((layers & params::kProfile) != 0U) out += " < profile";
  if ((layers & params::kAuto) != 0U) out += " < auto";
  return out + " < file";
}

}  // namespace

std::string configReference(bool keys_only) {
  const Config defaults;
  std::string out;
  std::string section;
  for (const auto& row : Config::table().rows()) {
    if (keys_only) {
      out += row.key + "\n";
      continue;
    }
    const std::size_t dot = row.key.find('.');
    if (row.key.substr(0, dot) != section) {
      section = row.key.substr(0, dot);
      out += std::string(out.empty() ? "" : "\n") + "### `" + section + ":`\n\n" +
             "| key | default | unit | bounds | set by | what |\n|---|---|---|---|---|---|\n";
    }
    std::string bounds = row.range();
    if (!row.choices.empty()) {
      for (const auto& c : row.choices) bounds += (bounds.empty() ? "" : " \\| ") + c;
    }
    out += "| `" + row.key.substr(dot + 1) + "` | " + defaultText(row, row.get(defaults)) + " | " +
           row.unit + " | " + bounds + " | " + layersText(row.layers) + " | " + row.help + " |\n";
  }
  return out;
}

world::GridOptions Config::gridOptions(double clearance_m) const {
  world::GridOptions g = grid;
  g.inflation_radius_m = clearance_m;
  return g;
}

world::GridOptions Config::gridOptions() const { return gridOptions(uav.inflationRadius()); }

planning::MissionOptions Config::missionOptions() const {
  planning::MissionOptions m = mission;
  m.gimbal = coverage.gimbal;
  m.mosaic_repair = coverage.purpose == "mosaic";
  return m;
}

tiling::MergeOptions Config::mergeOptions(bool keep_buffer_safety) const {
  tiling::MergeOptions m;
  m.planes = perception.planes;
  m.keep_buffer_safety = keep_buffer_safety;
  return m;
}

planning::FlightOptions Config::flightOptions() const {
  planning::FlightOptions f = flight;
  f.start = mission.start;
  f.simplify = mission.simplify;
  return f;
}

Config parseConfig(const std::string& yaml_text, const std::string& path) {
  Config c;
  const YAML::Node root = parseYaml(yaml_text, path);
  if (root.IsNull()) return c;  // an empty config means defaults
  Section top(root, path, "");
  withFile(path, [&] { parseConfigSections(top, c); });
  top.finish();
  c.validate(path);
  return c;
}

Config loadConfig(const std::string& path) { return parseConfig(io::readFile(path), path); }

Config loadConfigOrScenario(const std::string& path) {
  const std::string text = io::readFile(path);
  const YAML::Node root = parseYaml(text, path);
  if (root.IsMap() && root["world"].IsDefined()) return parseScenario(text, path).config;
  return parseConfig(text, path);
}

Scenario parseScenario(const std::string& yaml_text, const std::string& path) {
  Scenario sc;
  sc.path = path;
  const YAML::Node root = parseYaml(yaml_text, path);
  if (!root.IsMap())
    throw InputError(path + ": a scenario must be a YAML mapping with name, world, sensing");
  Section top(root, path, "");
  sc.name = top.text("name");
  sc.description = top.text("description", "");

  withFile(path, [&] {
    const YAML::Node world = root["world"];
    top.has("world");
    if (!world.IsDefined() || !world.IsSequence())
      top.fail("world", "must be a list of primitives");
    for (std::size_t i = 0; i < world.size(); ++i) {
      parseWorldItem(Section(world[i], path, "world[" + std::to_string(i) + "]"), sc.world, i);
    }

    Section sensing = top.child("sensing");
    sc.sensing_mode = sensing.text("mode", "sample");
    if (sc.sensing_mode != "sample" && sc.sensing_mode != "scan") {
      sensing.fail("mode", "'" + sc.sensing_mode + "' is not supported (supported: sample, scan)");
    }
    if (sc.sensing_mode == "scan") {
      parseScanSensing(sensing, sc.scan);
      // Stages 3-7 run in scenario coordinates (app::senseScans shifts the merged
      // cloud back from the raw log's frame), so the stations are viewpoints as given.
      // They scanned the cloud: stage 4 orients each normal toward the side they see.
      sc.config.perception.planes.viewpoint = sc.scan.stations.front();
      if (sensing.has("viewpoint"))
        sc.config.perception.planes.viewpoint = sensing.vec3("viewpoint");
      sc.config.perception.planes.extra_viewpoints = sc.scan.stations;
      sc.config.perception.planes.viewpoints_scanned = true;
      sensing.finish();
      sc.scan.validate("sensing");
    } else {
      sc.sample.spacing_m = sensing.number("spacing_m", sc.sample.spacing_m);
      sc.sample.noise_sigma_m = sensing.number("noise_sigma_m", sc.sample.noise_sigma_m);
      sc.sample.outlier_fraction = sensing.number("outlier_fraction", sc.sample.outlier_fraction);
      sc.sample.outlier_margin_m = sensing.number("outlier_margin_m", sc.sample.outlier_margin_m);
      const int seed = sensing.integer("seed", static_cast<int>(sc.sample.seed));
      if (seed < 0) sensing.fail("seed", "must be >= 0, got " + std::to_string(seed));
      sc.sample.seed = static_cast<std::uint32_t>(seed);
      if (sensing.has("viewpoint"))
        sc.config.perception.planes.viewpoint = sensing.vec3("viewpoint");
      if (sensing.has("viewpoints"))
        sc.config.perception.planes.extra_viewpoints = sensing.vec3List("viewpoints");
      sensing.finish();
      sc.sample.validate("sensing");
    }

    parseConfigSections(top, sc.config);
    // The scenario's sensor is known (its viewpoint, by default the origin).
    sc.config.sources.set(sc.config.keyOf(&sc.config.perception.planes.viewpoint),
                          params::Source::File);

    if (top.has("bench")) parseBench(top.child("bench"), sc.bench);
    // `edits:` the operator's corrections (app/edits.h), relative to the scenario's folder.
    if (top.has("edits")) {
      sc.edits = top.text("edits");
      if (sc.edits.empty()) top.fail("edits", "must name an edits file");
      const std::filesystem::path e(sc.edits);
      if (e.is_relative())
        sc.edits = (std::filesystem::path(path).parent_path() / e).lexically_normal().string();
    }

    // `expect:` (the paper's outcome) is for the tests (tests/app/expectation.h).
    if (top.has("expect") && !top.node()["expect"].IsMap())
      top.fail("expect", "must be a mapping (surfaces, status, min_surface_area_m2)");
  });
  top.finish();
  if (sc.world.empty()) top.fail("world", "is empty: add at least one primitive");
  sc.config.validate(path);
  return sc;
}

Scenario loadScenario(const std::string& path) { return parseScenario(io::readFile(path), path); }

}  // namespace uavip::app
