// uavip validate: re-checks the waypoints of a mission.json against its scene.json
// with the collision world and path validator (ARCHITECTURE.md, "Planning").

#include "src/cli/commands.h"

#include "uavip/core/error.h"
#include "uavip/io/atomic_file.h"
#include "uavip/io/scene_json.h"
#include "uavip/planning/path_validator.h"
#include "uavip/world/collision_world.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <limits>
#include <memory>
#include <sstream>

namespace uavip::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

/// One surface of a mission file, as far as validation needs it.
struct MissionSurface {
  std::string label;  ///< "surface 3", or "sortie 2" of the ordered flight
  int surface_id{0};
  std::string status;
  PointList waypoints;
};

struct MissionFile {
  double inflation_radius_m{std::numeric_limits<double>::quiet_NaN()};  ///< NaN if absent
  std::vector<MissionSurface> surfaces;
};

[[noreturn]] void fail(const std::string& path, const std::string& field, const std::string& what) {
  throw InputError(path + ": " + field + " " + what);
}

const json& field(const std::string& path, const json& j, const std::string& key, const std::string& where) {
  if (!j.is_object() || !j.contains(key)) fail(path, where.empty() ? key : where + "." + key, "is missing");
  return j.at(key);
}

/// The `waypoints` list of `js` (field path `f` for messages).
PointList readWaypoints(const std::string& path, const json& js, const std::string& f) {
  const json& wps = field(path, js, "waypoints", f);
  if (!wps.is_array()) fail(path, f + ".waypoints", "must be a list of [x, y, z]");
  PointList out;
  for (std::size_t k = 0; k < wps.size(); ++k) {
    const std::string fw = f + ".waypoints[" + std::to_string(k) + "]";
    const json& w = wps[k];
    if (!w.is_array() || w.size() != 3) fail(path, fw, "must be [x, y, z]");
    Vec3 p;
    for (int c = 0; c < 3; ++c) {
      if (!w[static_cast<std::size_t>(c)].is_number()) fail(path, fw, "must hold numbers");
      p[c] = w[static_cast<std::size_t>(c)].get<double>();
    }
    if (!p.allFinite()) fail(path, fw, "must be finite");
    out.push_back(p);
  }
  return out;
}

/// Reads the parts of OUT/mission.json that validation needs; throws InputError
/// naming the file and the bad field.
MissionFile readMission(const std::string& path) {
  const std::string text = io::readFile(path);
  json j;
  try {
    j = json::parse(text);
  } catch (const json::parse_error& e) {
    throw InputError(path + ": not valid JSON (byte " + std::to_string(e.byte) + ")");
  }
  if (!j.is_object()) fail(path, "the file", "must be a JSON object (a mission.json written by run or plan)");
  MissionFile m;
  if (j.contains("inflation_radius_m")) {
    const json& r = j["inflation_radius_m"];
    if (!r.is_number() || !(r.get<double>() > 0.0)) fail(path, "inflation_radius_m", "must be a number > 0");
    m.inflation_radius_m = r.get<double>();
  }
  const json& surfaces = field(path, j, "surfaces", "");
  if (!surfaces.is_array()) fail(path, "surfaces", "must be a list");
  for (std::size_t i = 0; i < surfaces.size(); ++i) {
    const std::string f = "surfaces[" + std::to_string(i) + "]";
    const json& js = surfaces[i];
    MissionSurface s;
    const json& id = field(path, js, "surface_id", f);
    if (!id.is_number_integer()) fail(path, f + ".surface_id", "must be an integer");
    s.surface_id = id.get<int>();
    const json& status = field(path, js, "status", f);
    if (!status.is_string()) fail(path, f + ".status", "must be a string");
    s.status = status.get<std::string>();
    s.label = "surface " + std::to_string(s.surface_id);
    s.waypoints = readWaypoints(path, js, f);
    m.surfaces.push_back(std::move(s));
  }
  // The ordered flight's sorties (absent in files of older versions).
  if (j.contains("flight") && j["flight"].is_object() && j["flight"].contains("sorties")) {
    const json& sorties = j["flight"]["sorties"];
    if (!sorties.is_array()) fail(path, "flight.sorties", "must be a list");
    for (std::size_t i = 0; i < sorties.size(); ++i) {
      MissionSurface s;
      s.label = "sortie " + std::to_string(i + 1);
      s.status = "ok";
      s.waypoints = readWaypoints(path, sorties[i], "flight.sorties[" + std::to_string(i) + "]");
      m.surfaces.push_back(std::move(s));
    }
  }
  return m;
}

std::string fixed(double v, int digits) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(digits) << v;
  return os.str();
}

std::string point(const Vec3& p) {
  return "(" + fixed(p.x(), 2) + ", " + fixed(p.y(), 2) + ", " + fixed(p.z(), 2) + ")";
}

int validateCommand(const std::string& mission_path, std::string scene_path, double clearance_arg,
                    bool clearance_given, const Verbosity& v) {
  const MissionFile mission = readMission(mission_path);
  if (scene_path.empty()) scene_path = (fs::path(mission_path).parent_path() / "scene.json").string();
  double clearance = mission.inflation_radius_m;
  if (clearance_given) {
    requirePositive(clearance_arg, "--clearance", "the clearance");
    clearance = clearance_arg;
  } else if (std::isnan(clearance)) {
    throw InputError(mission_path + ": inflation_radius_m is missing; give the clearance with --clearance");
  }
  const Scene scene = io::loadScene(scene_path);

  const auto t0 = std::chrono::steady_clock::now();
  auto world = std::make_shared<const world::CollisionWorld>(scene);
  const double build_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const planning::PathValidator validator(world, clearance);

  const auto t1 = std::chrono::steady_clock::now();
  int checked = 0, violated = 0;
  std::ostringstream out;
  std::string first_error;
  for (const auto& s : mission.surfaces) {
    out << "  " << s.label << ": ";
    if (s.status != "ok") {
      out << "status " << s.status << ", not validated\n";
      continue;
    }
    ++checked;
    const planning::ValidationResult r = validator.validate(s.waypoints);
    std::size_t bad = 0;
    for (const double c : r.segment_clearance_m) bad += c < clearance - 1e-9;
    const std::string min =
        std::isfinite(r.min_clearance_m) ? fixed(r.min_clearance_m, 3) + " m" : std::string("unbounded");
    if (r.collision_free) {
      out << "collision-free, " << s.waypoints.size() << " waypoints, min clearance " << min << "\n";
      continue;
    }
    ++violated;
    const auto seg = static_cast<std::size_t>(r.first_violation_segment);
    const Vec3& a = s.waypoints[seg];
    const Vec3& b = s.waypoints.size() > 1 ? s.waypoints[seg + 1] : a;
    std::ostringstream msg;
    msg << "segment " << seg << " " << point(a) << " -> " << point(b) << " comes "
        << fixed(r.segment_clearance_m[seg], 3) << " m from " << r.violation_object << " at "
        << point(r.violation_point) << " (required " << fixed(clearance, 3) << " m)";
    out << "VIOLATION: " << msg.str() << "; " << bad << " of " << r.segment_clearance_m.size()
        << " segments too close, min clearance " << min << "\n";
    if (first_error.empty()) first_error = s.label + ": " + msg.str();
  }
  const double check_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();

  if (!v.quiet) {
    std::cout << "mission " << mission_path << " against " << scene_path << " (clearance " << fixed(clearance, 3)
              << " m" << (clearance_given ? ", from --clearance" : ", inflation_radius_m of the mission") << ")\n";
    std::cout << "world: " << world->objects().size() << " objects (" << scene.surfaces.size() << " surfaces, "
              << scene.obstacles.size() << " obstacles, cloud of " << world->cloudSize() << " points)\n";
    std::cout << out.str();
    std::cout << "validated " << checked << " of " << mission.surfaces.size() << " paths (surfaces and sorties): "
              << (violated == 0 ? std::string("all collision-free") : std::to_string(violated) + " with violations")
              << "\n";
    std::cout << "time: world " << fixed(build_s, 3) << " s, validation " << fixed(check_s, 3) << " s\n";
  }
  if (violated > 0) {
    std::cerr << "uavip: " << first_error << "\n";
    return kExitNoMission;
  }
  return kExitOk;
}

/// Options of validate, kept alive until dispatch.
struct ValidateArgs {
  std::string mission, scene;
  double clearance{0.0};
  CLI::Option* clearance_opt{nullptr};
};

}  // namespace

void addValidateCommands(CLI::App& cli, CommandRegistry& registry) {
  auto a = std::make_shared<ValidateArgs>();
  const Verbosity& v = registry.verbosity();
  auto* val = cli.add_subcommand(
      "validate", "Re-check a mission.json against its scene: sweep the UAV along every waypoint path "
                  "(exit 3 if any ok surface comes closer than the clearance)");
  val->add_option("mission", a->mission, "OUT/mission.json written by run or plan")->required();
  val->add_option("--scene", a->scene, "Scene to check against (default: scene.json next to the mission)");
  a->clearance_opt = val->add_option("--clearance", a->clearance,
                                     "Required clearance [m] (default: the mission's inflation_radius_m)");
  registry.add(val, [a, &v] {
    return validateCommand(a->mission, a->scene, a->clearance, a->clearance_opt->count() > 0, v);
  });
}

}  // namespace uavip::cli
