// uavip validate: re-checks the waypoints of a mission.json against its scene.json
// with the collision world and path validator (docs/ARCHITECTURE.md, "Safety").

#include <cmath>
#include <filesystem>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>

#include "src/cli/commands.h"
#include "uavip/core/error.h"
#include "uavip/core/math.h"
#include "uavip/core/stopwatch.h"
#include "uavip/core/text.h"
#include "uavip/io/cloud_io.h"
#include "uavip/io/file_digest.h"
#include "uavip/io/json_reader.h"
#include "uavip/io/mission_json.h"
#include "uavip/io/scene_json.h"
#include "uavip/planning/fleet_types.h"
#include "uavip/planning/path_validator.h"
#include "uavip/world/collision_world.h"

namespace uavip::cli {
namespace {

namespace fs = std::filesystem;

/// One path to validate: a surface's own path, or a sortie of the ordered flight.
struct NamedPath {
  std::string label;   ///< "surface 3", or "sortie 2"
  std::string status;  ///< a sortie of a recorded flight counts as "ok"
  PointList waypoints;
};

std::vector<NamedPath> pathsOf(const io::MissionRecord& mission) {
  std::vector<NamedPath> out;
  for (const auto& s : mission.surfaces)
    out.push_back({"surface " + std::to_string(s.surface_id), s.status, s.waypoints});
  if (mission.flight) {
    for (std::size_t i = 0; i < mission.flight->sorties.size(); ++i)
      out.push_back(
          {"sortie " + std::to_string(i + 1), "ok", mission.flight->sorties[i].waypoints});
  }
  if (mission.fleet) {
    for (std::size_t u = 0; u < mission.fleet->uavs.size(); ++u) {
      const auto& sorties = mission.fleet->uavs[u].sorties;
      for (std::size_t i = 0; i < sorties.size(); ++i)
        out.push_back({"uav " + std::to_string(u + 1) + " sortie " + std::to_string(i + 1), "ok",
                       sorties[i].waypoints});
    }
  }
  return out;
}

/// Names UAV u's sortie k (0-based) in messages.
using SortieNamer = std::function<std::string(int uav, int sortie)>;

/// The fleet's separation, recomputed from the waypoints, the take-off times and the
/// flight model (planning/fleet_types.h). Empty when it holds, else the error line.
std::string checkFleetSeparation(const io::FleetRecord& fleet, std::ostream& out,
                                 const SortieNamer& name) {
  const auto motion = io::recordedFleetMotion(fleet);
  const planning::SeparationCheck c =
      planning::checkSeparation(motion, fleet.options.separation_m, fleet.options.slack_s);
  out << "fleet: " << fleet.uavs.size() << " UAVs, closest approach "
      << formatFixed(c.nominal_min_m, 3)
      << " m on schedule (t = " << formatFixed(c.nominal_time_s, 1) << " s), "
      << formatFixed(c.swept_min_m, 3) << " m with up to " << formatNumber(fleet.options.slack_s)
      << " s of delay; separation " << formatNumber(fleet.options.separation_m) << " m, " << c.pairs
      << " segment pairs\n";
  if (c.conflict) {
    const auto& k = *c.conflict;
    std::ostringstream msg;
    msg << "uav " << k.uav_a + 1 << " (" << name(k.uav_a, k.sortie_a) << ") and uav " << k.uav_b + 1
        << " (" << name(k.uav_b, k.sortie_b) << ") may come " << formatFixed(k.distance_m, 3)
        << " m apart at t = " << formatFixed(k.time_s, 1) << " s, closer than the separation "
        << formatNumber(fleet.options.separation_m) << " m (with up to "
        << formatNumber(fleet.options.slack_s) << " s of delay)";
    return msg.str();
  }
  return {};
}

/// checkFleetSeparation, and every stop of the flight flown once by the fleet. Empty
/// when both hold, else the error line.
std::string checkFleet(const io::FleetRecord& fleet, const io::MissionRecord& mission,
                       std::ostream& out) {
  std::string separation = checkFleetSeparation(
      fleet, out, [](int, int k) { return "sortie " + std::to_string(k + 1); });
  if (!separation.empty()) return separation;
  std::map<std::pair<int, std::size_t>, int> flown;
  for (const auto& u : fleet.uavs)
    for (const auto& s : u.sorties)
      for (const auto& st : s.stops) ++flown[{st.surface_id, st.stop}];
  if (mission.flight) {
    for (const auto& s : mission.flight->sorties) {
      for (const auto& st : s.stops) {
        const auto it = flown.find({st.surface_id, st.stop});
        const int n = it == flown.end() ? 0 : it->second;
        if (n != 1)
          return "fleet: stop " + std::to_string(st.stop) + " of surface " +
                 std::to_string(st.surface_id) + " is flown " + std::to_string(n) +
                 " times by the fleet, not once";
      }
    }
  }
  return {};
}

}  // namespace

SceneFrameInput readInSceneFrame(const std::string& path, const nlohmann::json& j,
                                 const std::string& scene_path) {
  // The clouds detect wrote beside scene.json are in the scene's frame already.
  const fs::path file(path);
  std::error_code ec;
  if ((file.filename() == "cloud_clean.pcd" || file.filename() == io::kSafetyCloudFile) &&
      fs::equivalent(file.parent_path().empty() ? fs::path(".") : file.parent_path(),
                     fs::path(scene_path).parent_path().empty()
                         ? fs::path(".")
                         : fs::path(scene_path).parent_path(),
                     ec))
    return {io::loadCloud(path), nullptr};
  // Read as detect read it (input options from scene.json), in the scene's frame.
  io::CloudReadOptions options;
  Vec3 scene_offset = Vec3::Zero();
  if (j.contains("input_read")) {
    const nlohmann::json& r = j.at("input_read");
    if (r.contains("scale") && r.at("scale").is_number())
      options.scale = r.at("scale").get<double>();
    if (r.contains("drop_classes") && r.at("drop_classes").is_array())
      options.drop_classes = r.at("drop_classes").get<std::vector<int>>();
    // A mesh is sampled again at the spacing detect used: the same points.
    if (r.contains("mesh") && r.at("mesh").contains("spacing_m") &&
        r.at("mesh").at("spacing_m").is_number())
      options.mesh_spacing_m = r.at("mesh").at("spacing_m").get<double>();
  }
  if (j.contains("source_offset_m"))
    scene_offset =
        io::JsonReader(scene_path).vec3(j.at("source_offset_m"), "source_offset_m", false);
  io::CloudReadInfo info;
  SceneFrameInput in;
  in.points = io::loadCloud(path, options, &info);
  const Vec3 shift = info.origin_m - scene_offset;  // file coordinates − scene offset
  if (shift != Vec3::Zero()) {
    for (auto& p : in.points) p += shift;
  }
  if (info.triangles) {
    auto moved = std::make_shared<TriangleMesh>(*info.triangles);
    for (Vec3& p : moved->vertices) p += shift;
    in.triangles = std::move(moved);
  }
  return in;
}

namespace {

/// The input cloud a mission is checked against point by point: --cloud, else the
/// file scene.json names when it is still there with the same sha256. `note` says
/// which, or why none.
struct InputCloud {
  std::string path;
  PointList points;  ///< in the scene's frame [m]; empty when none
  /// A mesh input's triangles in the scene's frame: measured against exactly, in
  /// place of the points sampled on them; null for a cloud.
  std::shared_ptr<const TriangleMesh> triangles;
  std::string note;
};

InputCloud inputCloud(const std::string& scene_path, const nlohmann::json& j, const Scene& scene,
                      const std::string& cloud_arg) {
  InputCloud in;
  std::string path = cloud_arg;
  if (path.empty()) {
    if (!scene.safety || scene.safety->source.empty()) {
      in.note = "no input file recorded in " + scene_path +
                " (give --cloud FILE to check against every input point)";
      return in;
    }
    path = scene.safety->source;
    if (!fs::exists(path)) {
      in.note = "the input " + path + " is no longer there (give --cloud FILE)";
      return in;
    }
    if (io::sha256File(path) != scene.safety->sha256) {
      in.note = "the input " + path +
                " changed since detect (sha256 differs; give --cloud FILE to check against it)";
      return in;
    }
  }
  SceneFrameInput read = readInSceneFrame(path, j, scene_path);
  in.points = std::move(read.points);
  in.triangles = std::move(read.triangles);
  in.path = path;
  in.note = "input " + path + ": " +
            (in.triangles ? "mesh of " + std::to_string(in.triangles->triangles.size()) +
                                " triangles, measured exactly"
                          : std::to_string(in.points.size()) + " points") +
            (cloud_arg.empty() ? " (from scene.json, sha256 checked)" : " (--cloud)");
  return in;
}

/// The clearance to check at [m]: --clearance, else the mission's inflation radius.
double clearanceOf(const io::MissionRecord& mission, const std::string& mission_path,
                   double clearance_arg, bool clearance_given) {
  if (clearance_given) {
    requirePositive(clearance_arg, "--clearance", "the clearance");
    return clearance_arg;
  }
  if (std::isnan(mission.inflation_radius_m)) {
    throw InputError(mission_path +
                     ": inflation_radius_m is missing; give the clearance with --clearance");
  }
  return mission.inflation_radius_m;
}

/// The checks of one validation: the collision world (at the clearance plus the
/// safety margin when there is no input file) and, with the input file, every input
/// point at the clearance.
struct Checkers {
  std::shared_ptr<const world::CollisionWorld> world;
  double margin{0.0};  ///< added to the clearance in the world check [m]
  std::unique_ptr<const planning::PathValidator> validator;
  std::unique_ptr<const planning::PathValidator> raw;  ///< null without the input file
  bool input_mesh{false};                              ///< `raw` holds a mesh input's triangles
  double clearance{0.0};                               ///< [m]
};

/// The path's validation, the clearance it was checked at [m] and its clearance to
/// the input alone [m] (inf when not checked against the input).
planning::ValidationResult checkPath(const Checkers& c, const PointList& waypoints,
                                     double& required, double& input_clearance) {
  planning::ValidationResult r = c.validator->validate(waypoints);
  required = c.validator->requiredClearance();
  input_clearance = kInf;
  if (r.collision_free && c.raw) {  // then every input point (or triangle), exactly
    planning::ValidationResult to_input = c.raw->validate(waypoints);
    input_clearance = to_input.min_clearance_m;
    if (!to_input.collision_free) {
      to_input.violation_object = c.input_mesh ? "input mesh triangle" : "input point";
      r = std::move(to_input);
      required = c.clearance;
    } else {
      r.min_clearance_m = std::min(r.min_clearance_m, to_input.min_clearance_m);
    }
  }
  return r;
}

/// What the paths' checks found: a line each, and the first violation.
struct Tally {
  int checked{0};
  int violated{0};
  std::ostringstream out;
  std::string first_error;
};

/// Checks path s and adds its line to the tally.
void validatePath(const Checkers& c, const NamedPath& s, Tally& t) {
  t.out << "  " << s.label << ": ";
  if (s.status != "ok") {
    t.out << "status " << s.status << ", not validated\n";
    return;
  }
  ++t.checked;
  double required = 0.0;
  double to_input = kInf;
  const planning::ValidationResult r = checkPath(c, s.waypoints, required, to_input);
  std::size_t bad = 0;
  for (const double x : r.segment_clearance_m) bad += x < required - 1e-9;
  const std::string min = std::isfinite(r.min_clearance_m)
                              ? formatFixed(r.min_clearance_m, 3) + " m"
                              : std::string("unbounded");
  if (r.collision_free) {
    t.out << "collision-free, " << s.waypoints.size() << " waypoints, min clearance " << min;
    // A mesh input: the exact distance to its triangles, to the micrometre.
    if (c.input_mesh && std::isfinite(to_input))
      t.out << ", to the input mesh's triangles " << formatFixed(to_input, 6) << " m";
    t.out << "\n";
    return;
  }
  ++t.violated;
  const auto seg = static_cast<std::size_t>(r.first_violation_segment);
  const Vec3& a = s.waypoints[seg];
  const Vec3& b = s.waypoints.size() > 1 ? s.waypoints[seg + 1] : a;
  std::ostringstream msg;
  msg << "segment " << seg << " " << formatPoint(a) << " -> " << formatPoint(b) << " comes "
      << formatFixed(r.segment_clearance_m[seg], 3) << " m from " << r.violation_object << " at "
      << formatPoint(r.violation_point) << " (required " << formatFixed(required, 3) << " m)";
  t.out << "VIOLATION: " << msg.str() << "; " << bad << " of " << r.segment_clearance_m.size()
        << " segments too close, min clearance " << min << "\n";
  if (t.first_error.empty()) t.first_error = s.label + ": " + msg.str();
}

/// `uavip validate site.json` of a site flown by a fleet with its sections at once
/// (app/site_fleet.h): each UAV's sorties taken from the sections' mission.json by
/// folder and number, their motion recomputed from the waypoints, take-off times and
/// the recorded flight model, the separation checked exactly (checkFleetSeparation), and
/// every sortie of every flown section flown exactly once. The sorties' clearance is
/// each section's (`uavip validate SECTION/mission.json`; merge checked it against every
/// input point).
int validateSiteCommand(const std::string& path, const nlohmann::json& site, const Verbosity& v) {
  if (!site.contains("fleet"))
    throw InputError(path +
                     ": a site without a fleet has nothing to check here; validate each "
                     "section: uavip validate " +
                     (fs::path(path).parent_path() / "section_NNN" / "mission.json").string());
  const auto missions = io::siteMissions(site, path);
  const io::SiteFleetRecord record = io::siteFleetFromJson(site, path, missions);
  std::map<std::pair<std::string, std::size_t>, int> flown;
  for (const auto& run : record.sorties)
    for (const auto& at : run) ++flown[at];
  const auto t0 = SteadyClock::now();
  std::ostringstream out;
  std::string error = checkFleetSeparation(record.fleet, out, [&](int u, int k) {
    const auto& at = record.sorties[static_cast<std::size_t>(u)][static_cast<std::size_t>(k)];
    return at.first + " sortie " + std::to_string(at.second + 1);
  });
  std::size_t sorties = 0;
  for (const auto& [folder, m] : missions) {
    for (std::size_t k = 0; k < m.flight->sorties.size() && error.empty(); ++k) {
      const auto it = flown.find({folder, k});
      const int n = it == flown.end() ? 0 : it->second;
      if (n != 1)
        error = "fleet: " + folder + " sortie " + std::to_string(k + 1) + " is flown " +
                std::to_string(n) + " times by the fleet, not once";
    }
    sorties += m.flight->sorties.size();
  }
  if (!v.quiet) {
    std::cout << "site " << path << ": " << missions.size() << " sections flown at once, "
              << sorties << " sorties\n"
              << out.str() << "checked in " << formatFixed(secondsSince(t0), 3)
              << " s; each sortie's clearance: uavip validate SECTION/mission.json\n";
  }
  if (!error.empty()) {
    std::cerr << "uavip: " << error << "\n";
    return kExitNoMission;
  }
  return kExitOk;
}

int validateCommand(const std::string& mission_path, std::string scene_path, double clearance_arg,
                    bool clearance_given, const std::string& cloud_arg, const Verbosity& v) {
  const nlohmann::json j = io::JsonReader(mission_path).load();
  if (io::isSiteJson(j))  // merge's, several sections
    return validateSiteCommand(mission_path, j, v);
  const io::MissionRecord mission = io::missionFromJson(j, mission_path);
  const std::vector<NamedPath> paths = pathsOf(mission);
  if (scene_path.empty())
    scene_path = (fs::path(mission_path).parent_path() / "scene.json").string();
  Checkers c;
  c.clearance = clearanceOf(mission, mission_path, clearance_arg, clearance_given);
  const nlohmann::json scene_json = io::JsonReader(scene_path).load();  // parsed once
  Scene scene = io::sceneFromJson(scene_json, scene_path);
  scene.keep_out = mission.keep_out;  // the operator's volumes the plan kept out of

  const auto t0 = SteadyClock::now();
  const InputCloud input = inputCloud(scene_path, scene_json, scene, cloud_arg);
  c.world = std::make_shared<const world::CollisionWorld>(scene);
  // Without the input file, the safety cloud stands for it: every input point lies
  // within its margin of a safety point, so the world check keeps that much more. A
  // mesh input's triangles are in the world themselves: no margin.
  c.margin =
      input.points.empty() && scene.safety && !scene.safety->mesh ? scene.safety->margin_m : 0.0;
  c.validator = std::make_unique<const planning::PathValidator>(c.world, c.clearance + c.margin);
  if (input.triangles) {  // a mesh: every triangle, exactly
    c.input_mesh = true;
    c.raw = std::make_unique<const planning::PathValidator>(
        std::make_shared<const world::CollisionWorld>(
            world::CollisionWorld::fromMesh(input.triangles)),
        c.clearance);
  } else if (!input.points.empty()) {
    c.raw = std::make_unique<const planning::PathValidator>(input.points, c.clearance);
  }
  const double build_s = secondsSince(t0);

  const auto t1 = SteadyClock::now();
  Tally t;
  for (const auto& s : paths) validatePath(c, s, t);
  std::ostringstream fleet_out;
  const std::string fleet_error =
      mission.fleet ? checkFleet(*mission.fleet, mission, fleet_out) : std::string();
  const double check_s = secondsSince(t1);

  if (!v.quiet) {
    std::cout << "mission " << mission_path << " against " << scene_path << " (clearance "
              << formatFixed(c.clearance, 3) << " m"
              << (clearance_given ? ", from --clearance" : ", inflation_radius_m of the mission")
              << ")\n";
    std::cout << "world: " << c.world->objects().size() << " objects (" << scene.surfaces.size()
              << " surfaces, " << scene.obstacles.size() << " obstacles, "
              << (c.world->meshTriangles() > 0
                      ? "mesh of " + std::to_string(c.world->meshTriangles()) + " triangles"
                      : "cloud of " + std::to_string(c.world->cloudSize()) + " points")
              << (scene.keep_out.empty()
                      ? std::string()
                      : ", " + std::to_string(scene.keep_out.size()) + " keep-out volumes")
              << ")"
              << (c.margin > 0.0 ? ", checked at clearance + the safety margin " +
                                       formatFixed(c.margin, 3) + " m"
                                 : "")
              << "\n";
    std::cout << input.note << "\n";
    std::cout << t.out.str() << fleet_out.str();
    std::cout << "validated " << t.checked << " of " << paths.size()
              << " paths (surfaces and sorties): "
              << (t.violated == 0 ? std::string("all collision-free")
                                  : std::to_string(t.violated) + " with violations")
              << "\n";
    std::cout << "time: world " << formatFixed(build_s, 3) << " s, validation "
              << formatFixed(check_s, 3) << " s\n";
  }
  if (t.violated > 0) {
    std::cerr << "uavip: " << t.first_error << "\n";
    return kExitNoMission;
  }
  if (!fleet_error.empty()) {
    std::cerr << "uavip: " << fleet_error << "\n";
    return kExitNoMission;
  }
  return kExitOk;
}

/// Options of validate, kept alive until dispatch.
struct ValidateArgs {
  std::string mission, scene, cloud;
  double clearance{0.0};
  CLI::Option* clearance_opt{nullptr};
};

}  // namespace

void addValidateCommands(CLI::App& cli, CommandRegistry& registry) {
  const auto [val, a] = missionCommand<ValidateArgs>(
      cli, "validate",
      "Re-check a mission.json against its scene: sweep the UAV along every waypoint path "
      "(exit 3 if any ok surface comes closer than the clearance). Given a site.json of merge "
      "--uavs K, re-check its fleet's schedule across the sections (exit 3 on a conflict)");
  const Verbosity& v = registry.verbosity();
  val->add_option("--scene", a->scene,
                  "Scene to check against (default: scene.json next to the mission)");
  a->clearance_opt =
      val->add_option("--clearance", a->clearance,
                      "Required clearance [m] (default: the mission's inflation_radius_m)");
  val->add_option("--cloud", a->cloud,
                  "Input cloud to measure every path against, point by point (default: the file "
                  "scene.json names, "
                  "if unchanged)");
  registry.add(val, [a = a, &v] {
    return validateCommand(a->mission, a->scene, a->clearance, a->clearance_opt->count() > 0,
                           a->cloud, v);
  });
}

}  // namespace uavip::cli
