#include "uavip/app/scenario.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include "uavip/core/error.h"
#include "uavip/core/text.h"
#include "uavip/io/atomic_file.h"
#include "yaml_section.h"

namespace uavip::app {
namespace {

using yaml::Section;

void parsePreprocess(Section s, preprocess::PreprocessOptions& o) {
  o.remove_outliers = s.boolean("remove_outliers", o.remove_outliers);
  o.outlier_k = s.integer("outlier_k", o.outlier_k);
  o.outlier_std_ratio = s.number("outlier_std_ratio", o.outlier_std_ratio);
  o.voxelize = s.boolean("voxelize", o.voxelize);
  o.voxel_m = s.number("voxel_m", o.voxel_m);
  s.finish();
}

void parseSafety(Section s, preprocess::SafetyOptions& o) {
  o.cell_m = s.number("cell_m", o.cell_m);
  o.sparse_factor = s.number("sparse_factor", o.sparse_factor);
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

/// Pinhole keys (fx, fy, cx, cy with image_px); the other camera models' keys conflict.
void parsePinhole(Section& s, coverage::Camera& c) {
  for (const char* other : {"footprint_m", "sensor_mm", "focal_mm"}) {
    if (s.has(other))
      s.fail(other, "conflicts with fx/fy (a pinhole camera); describe the camera one way only");
  }
  c.pinhole = true;
  c.fx_px = s.number("fx");
  c.fy_px = s.number("fy");
  const auto px = s.numbers("image_px", 2, 2);
  if (px[0] != std::floor(px[0]) || px[1] != std::floor(px[1]) || px[0] > 1e6 || px[1] > 1e6 ||
      px[0] < 1 || px[1] < 1) {
    s.fail("image_px", "must be two whole positive pixel counts");
  }
  c.image_w_px = static_cast<int>(px[0]);
  c.image_h_px = static_cast<int>(px[1]);
  c.cx_px = s.number("cx", 0.5 * px[0]);
  c.cy_px = s.number("cy", 0.5 * px[1]);
  c.gsd_mm_per_px = s.number("gsd_mm_per_px", 0.0);
  c.max_range_m = s.number("max_range_m", c.max_range_m);
  s.finish();
}

void parseCamera(Section s, coverage::Camera& c) {
  if (s.has("fx") || s.has("fy") || s.has("cx") || s.has("cy")) return parsePinhole(s, c);
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
  c.max_range_m = s.number("max_range_m", c.max_range_m);
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
  o.max_stops = s.number("max_stops", o.max_stops);
  o.mode = s.text("mode", o.mode);
  if (o.mode != "surfaces" && o.mode != "structure")
    s.fail("mode", "'" + o.mode +
                       "' is not a coverage mode; use surfaces (plane by plane) or structure (the "
                       "whole structure)");
  if (s.has("ground_z_m")) o.ground_z_m = s.number("ground_z_m");
  o.structure_target = s.number("structure_target", o.structure_target);
  if (s.has("gimbal_pitch_deg")) {
    const auto v = s.numbers("gimbal_pitch_deg", 2, 2);
    o.gimbal.pitch_min_deg = v[0];
    o.gimbal.pitch_max_deg = v[1];
  }
  s.finish();
}

void parsePlanner(Section s, Config& c) {
  c.planner = s.text("name", c.planner);
  c.planner_settings.time_limit_s = s.number("time_limit_s", c.planner_settings.time_limit_s);
  const int seed = s.integer("seed", static_cast<int>(c.planner_settings.seed));
  if (seed < 0) s.fail("seed", "must be >= 0, got " + std::to_string(seed));
  c.planner_settings.seed = static_cast<std::uint32_t>(seed);
  c.planner_settings.simplify = s.boolean("simplify", c.planner_settings.simplify);
  auto& a = c.planner_settings.astar;
  if (s.has("cost_weights")) {
    const auto w = s.numbers("cost_weights", 3, 3);
    a.a1 = w[0];
    a.a2 = w[1];
    a.a3 = w[2];
  }
  const int budget = s.integer("max_expansions", static_cast<int>(a.max_expansions));
  if (budget < 0)
    s.fail("max_expansions", "must be >= 0 (0 = unlimited), got " + std::to_string(budget));
  a.max_expansions = static_cast<std::size_t>(budget);
  a.coarse_factor = s.integer("coarse_factor", a.coarse_factor);
  s.finish();
}

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

void parseMission(Section s, planning::MissionOptions& o, planning::FlightOptions& flight) {
  o.simplify = s.boolean("simplify", o.simplify);
  o.max_skipped_fraction = s.number("max_skipped_fraction", o.max_skipped_fraction);
  if (s.has("start")) o.start = s.vec3("start");
  if (s.has("home")) flight.home = s.vec3("home");
  o.repair_stops = s.boolean("repair_stops", o.repair_stops);
  o.min_coverage = s.number("min_coverage", o.min_coverage);
  o.max_standoff_factor = s.number("max_standoff_factor", o.max_standoff_factor);
  s.finish();
}

/// The flight model (planning/flight_planner.h), section `flight:`.
void parseFlight(Section s, planning::FlightModel& o) {
  o.cruise_speed_m_s = s.number("cruise_speed_m_s", o.cruise_speed_m_s);
  o.climb_speed_m_s = s.number("climb_speed_m_s", o.climb_speed_m_s);
  o.descent_speed_m_s = s.number("descent_speed_m_s", o.descent_speed_m_s);
  o.hover_s = s.number("hover_s", o.hover_s);
  o.settle_s = s.number("settle_s", o.settle_s);
  o.endurance_s = s.number("endurance_s", o.endurance_s);
  o.reserve = s.number("reserve", o.reserve);
  s.finish();
}

/// A name parsed by `from_string` (which throws "<module>: <key> must be ..., got '…'"),
/// re-thrown with the file and the YAML path.
template <typename T, typename F>
T named(Section& s, const std::string& key, T fallback, F&& from_string) {
  if (!s.has(key)) return fallback;
  const std::string name = s.text(key);
  try {
    return from_string(name);
  } catch (const InputError& e) {
    const std::string msg = e.what();
    const std::size_t pos = msg.find(" must be");
    s.fail(key, pos == std::string::npos ? "is not valid: " + msg : msg.substr(pos + 1));
  }
}

/// Stage 1 (scan/station_assembler.h); mode scan only.
void parseAssembly(Section s, scan::AssemblerOptions& o) {
  o.use_imu_prior = s.boolean("use_imu_prior", o.use_imu_prior);
  o.icp = named(s, "icp", o.icp, [](const std::string& n) { return scan::icpMethodFromString(n); });
  o.max_iterations = s.integer("max_iterations", o.max_iterations);
  o.max_correspondence_m = s.number("max_correspondence_m", o.max_correspondence_m);
  o.keyframe_yaw_deg = s.number("keyframe_yaw_deg", o.keyframe_yaw_deg);
  o.keyframe_translation_m = s.number("keyframe_translation_m", o.keyframe_translation_m);
  o.horizontal_stride = s.integer("horizontal_stride", o.horizontal_stride);
  o.imu_smoothing_s = s.number("imu_smoothing_s", o.imu_smoothing_s);
  o.max_imu_gap_s = s.number("max_imu_gap_s", o.max_imu_gap_s);
  o.estimate_z = s.boolean("estimate_z", o.estimate_z);
  o.z_cone_deg = s.number("z_cone_deg", o.z_cone_deg);
  o.include_horizontal = s.boolean("include_horizontal", o.include_horizontal);
  o.refine_drift = s.boolean("refine_drift", o.refine_drift);
  o.drift_segment_deg = s.number("drift_segment_deg", o.drift_segment_deg);
  o.drift_iterations = s.integer("drift_iterations", o.drift_iterations);
  o.drift_voxel_m = s.number("drift_voxel_m", o.drift_voxel_m);
  s.finish();
}

/// Stage 2 (registration/station_registration.h); mode scan only.
void parseRegistration(Section s, registration::RegistrationOptions& o) {
  o.method = named(s, "method", o.method,
                   [](const std::string& n) { return registration::methodFromString(n); });
  o.overlap_margin_m = s.number("overlap_margin_m", o.overlap_margin_m);
  o.search_radius_m = s.number("search_radius_m", o.search_radius_m);
  o.search_step_m = s.number("search_step_m", o.search_step_m);
  o.downsample_m = s.number("downsample_m", o.downsample_m);
  o.max_correspondence_m = s.number("max_correspondence_m", o.max_correspondence_m);
  o.max_iterations = s.integer("max_iterations", o.max_iterations);
  o.ndt_resolution_m = s.number("ndt_resolution_m", o.ndt_resolution_m);
  o.use_recorded_yaw = s.boolean("use_recorded_yaw", o.use_recorded_yaw);
  o.output_voxel_m = s.number("output_voxel_m", o.output_voxel_m);
  o.normal_k = s.integer("normal_k", o.normal_k);
  o.pcl_normal_k = s.integer("pcl_normal_k", o.pcl_normal_k);
  s.finish();
}

/// Reads the config sections present in `top` (unknown keys are left to the caller).
void parseInput(Section s, io::CloudReadOptions& o) {
  if (s.has("drop_classes")) {
    o.drop_classes.clear();
    for (const double v : s.numbers("drop_classes", 0, 256)) {
      if (v != std::floor(v) || v < 0 || v > 255)
        s.fail("drop_classes", "must hold ASPRS class codes 0..255");
      o.drop_classes.push_back(static_cast<int>(v));
    }
  }
  o.scale = s.number("scale", o.scale);
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

/// Records the keys the file gives in sections still read by hand.
void recordFileKeys(const YAML::Node& top, Config& c) {
  for (const char* section : {"preprocess", "grid", "coverage", "camera"}) {
    const YAML::Node n = top[section];
    if (!n.IsDefined() || !n.IsMap()) continue;
    for (const auto& kv : n) {
      if (kv.first.IsScalar())
        c.sources.set(std::string(section) + "." + kv.first.Scalar(), params::Source::File);
    }
  }
}

void parseConfigSections(Section& top, Config& c) {
  if (top.has("input")) parseInput(top.child("input"), c.input);
  if (top.has("preprocess")) parsePreprocess(top.child("preprocess"), c.preprocess);
  if (top.has("safety")) parseSafety(top.child("safety"), c.safety);
  if (top.has("uav")) parseUav(top.child("uav"), c.uav);
  if (top.has("grid")) parseGrid(top.child("grid"), c.grid);
  if (top.has("camera")) parseCamera(top.child("camera"), c.coverage.camera);
  if (top.has("coverage")) parseCoverage(top.child("coverage"), c.coverage);
  if (top.has("planner")) parsePlanner(top.child("planner"), c);
  if (top.has("mission")) parseMission(top.child("mission"), c.mission, c.flight);
  if (top.has("flight")) parseFlight(top.child("flight"), c.flight.model);
  if (top.has("assembly")) parseAssembly(top.child("assembly"), c.assembly);
  if (top.has("registration")) parseRegistration(top.child("registration"), c.registration);
  readTableKeys(top, c);
  recordFileKeys(top.node(), c);
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
    for (int i = 0; i < 3; ++i) requirePositive(uav.size_m[i], "uav", "size_m");
    requirePositive(uav.inflationRadius(), "uav", "inflation_radius_m");
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

const params::Table<Config>& Config::table() {
  static const params::Table<Config> t = [] {
    params::Table<Config> p;
    p.include("perception.", &Config::perception, perception::PerceptionOptions::table());
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
