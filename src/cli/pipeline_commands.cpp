// uavip run | detect | plan: the pipeline of docs/ARCHITECTURE.md from the command line.

#include <algorithm>
#include <filesystem>
#include <future>
#include <iomanip>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>

#include "planners/registry.h"
#include "src/cli/commands.h"
#include "src/cli/scenario_dir.h"
#include "uavip/app/aircraft_profile.h"
#include "uavip/app/edits.h"
#include "uavip/app/pipeline.h"
#include "uavip/app/scenario.h"
#include "uavip/core/error.h"
#include "uavip/core/stopwatch.h"
#include "uavip/core/text.h"
#include "uavip/io/atomic_file.h"
#include "uavip/io/cloud_io.h"
#include "uavip/io/file_digest.h"
#include "uavip/io/geodesy.h"
#include "uavip/io/json_reader.h"
#include "uavip/io/mission_json.h"
#include "uavip/io/scene_json.h"
#include "uavip/view/views.h"

namespace uavip::cli {
namespace {

namespace fs = std::filesystem;

/// The operator's edits (app/edits.h) applied to a copy of `scene`, checked against
/// the plan `config` asks for: the scene to plan, and what mission.json records.
/// Without a file, the scene as it is and nothing to record.
struct EditedScene {
  Scene scene;
  std::optional<io::EditsSummary> summary;
};

EditedScene applyEditsFile(const Scene& detected, const std::string& edits_path,
                           const app::Config& config, const std::string& surface) {
  EditedScene out{detected, std::nullopt};
  if (edits_path.empty()) return out;
  const app::Edits edits = app::loadEdits(edits_path);
  io::EditsSummary summary;
  summary.file = edits_path;
  summary.sha256 = edits.sha256;
  summary.applied = app::applyEdits(out.scene, edits);
  summary.keep_out = out.scene.keep_out;
  const std::vector<int> ids =
      surface.empty() ? std::vector<int>{} : app::selectSurfaces(out.scene, surface);
  app::checkKeepOuts(out.scene, config, ids, edits);
  out.summary = std::move(summary);
  return out;
}

/// One line per applied edit (nothing without an edits file).
void printEdits(const std::optional<io::EditsSummary>& edits) {
  if (!edits) return;
  std::cout << "edits: " << edits->file << " (sha256 " << edits->sha256.substr(0, 12) << "…), "
            << edits->applied.size() << " applied\n";
  for (const auto& line : edits->applied) std::cout << "  edit " << line << "\n";
}

void printDetectSummary(const app::DetectResult& d) {
  const CloudStats& c = *d.scene.measured;  // set by app::detect
  std::cout << "measured: " << c.points << " points, spacing " << formatFixed(c.spacing_m, 3)
            << " m, extent " << formatFixed(c.extent_m.x(), 1) << " x "
            << formatFixed(c.extent_m.y(), 1) << " x " << formatFixed(c.extent_m.z(), 1)
            << " m, noise " << formatFixed(c.noise_m, 3) << " m"
            << (c.scanned_from_origin
                    ? ", one scan from the origin (the sensor orients the normals)"
                    : "")
            << "\n";
  const std::string unit = preprocess::unitWarning(c);
  if (!unit.empty()) std::cout << "warning: " << unit << "\n";
  std::cout << "parameters:";
  for (const auto& r : d.resolved.values) {
    std::string key = r.key.substr(r.key.find('.') + 1);
    std::cout << " " << key << " " << r.value << (r.source == "set" ? " (set)" : "");
  }
  std::cout << "\n";
  std::cout << "cloud: " << d.preprocess.input_points << " points -> "
            << d.preprocess.after_outliers << " after outlier removal -> "
            << d.preprocess.output_points << " after voxel grid\n";
  if (d.scene.safety) {
    const SafetyCloud& sc = *d.scene.safety;
    std::cout << "safety: every input point kept (" << sc.perception_dropped
              << " that outlier removal dropped): " << sc.points.size() << " points on a "
              << formatFixed(sc.cell_m, 3) << " m lattice, within " << formatFixed(sc.margin_m, 3)
              << " m of each input point\n";
    if (sc.mesh)
      std::cout << "safety: the mesh's " << sc.mesh->triangles.size()
                << " triangles kept beside scene.json (" << io::kSafetyMeshFile
                << "): clearances are measured to them exactly\n";
  }
  std::cout << "surfaces: " << d.scene.surfaces.size()
            << ", obstacles: " << d.scene.obstacles.size() << "\n";
  for (const auto& s : d.scene.surfaces) {
    std::cout << "  surface " << s.id << ": area " << formatFixed(s.area_m2, 2) << " m2, normal ("
              << formatFixed(s.plane.normal.x(), 2) << ", " << formatFixed(s.plane.normal.y(), 2)
              << ", " << formatFixed(s.plane.normal.z(), 2) << "), " << s.inliers.size()
              << " points\n";
  }
  if (d.scene.surfaces.empty()) {
    std::cout << "no surface detected (none with area >= the threshold): nothing to inspect, no "
                 "waypoints\n";
  }
}

void printPlanSummary(const app::PlanResult& p) {
  if (p.structure) {
    const planning::StructureSummary& st = *p.structure;
    std::cout << "structure: " << st.points << " points (" << st.ground_points
              << " ground left out), " << st.free_candidates << " of " << st.candidates
              << " candidate views kept (free, nearest per direction), " << st.photos
              << " photos at " << formatFixed(st.standoff_m, 2) << " m; coverage rule (a) "
              << formatFixed(100.0 * st.rule_a, 1) << " %, rule (b) "
              << formatFixed(100.0 * st.rule_b, 1) << " %";
    if (st.photo_groups > 0)
      std::cout << "; " << st.linking_photos << " photos added to link them, " << st.photo_groups
                << " linked group" << (st.photo_groups == 1 ? "" : "s");
    std::cout << "\n";
  }
  for (const auto& m : p.missions) {
    const char* what = m.kind == "plane"  ? "surface "
                       : m.kind == "edge" ? "edge link "
                                          : "structure ";
    std::cout << "  " << what << m.surface_id << ": " << planning::toString(m.status) << ", "
              << m.strategy.stops.size() << " stops";
    if (!m.moved_stops.empty()) std::cout << " (" << m.moved_stops.size() << " moved by repair)";
    if (m.coverage.evaluated)
      std::cout << ", coverage " << formatFixed(100.0 * m.coverage.fraction, 1) << " %";
    if (planning::flyable(m.status)) {
      std::cout << ", " << m.waypoints.size() << " waypoints (" << m.raw_waypoint_count
                << " voxel steps), " << formatFixed(m.path_length_m, 1) << " m, min clearance "
                << formatFixed(m.validation.min_clearance_m, 2) << " m";
    }
    if (!m.reason.empty()) std::cout << " - " << m.reason;
    std::cout << "\n";
  }
}

/// The ordered flight: order, length against the bound, duration, sorties.
void printFlight(const planning::FlightPlan& f) {
  if (f.status != planning::FlightPlan::Status::Ok) {
    std::cout << "flight: " << planning::toString(f.status) << " - " << f.reason << "\n";
    return;
  }
  std::string order;
  for (const auto& v : f.order)
    order += (order.empty() ? "" : " ") + std::to_string(v.surface_id) + (v.reversed ? "r" : "");
  const double gap =
      f.lower_bound_m > 0.0 ? 100.0 * (f.tour_length_m / f.lower_bound_m - 1.0) : 0.0;
  std::cout << "flight: " << formatFixed(f.length_m, 1) << " m, "
            << formatFixed(f.duration_s / 60.0, 1) << " min, " << f.sorties.size() << " sortie"
            << (f.sorties.size() == 1 ? "" : "s") << " from home "
            << "(" << formatFixed(f.home.x(), 1) << ", " << formatFixed(f.home.y(), 1) << ", "
            << formatFixed(f.home.z(), 1) << ", " << f.home_source << "); order " << order
            << " (r = reversed); tour " << formatFixed(f.tour_length_m, 1) << " m, "
            << formatFixed(gap, 1) << " % above the lower bound " << formatFixed(f.lower_bound_m, 1)
            << " m" << (f.exact_order ? " (optimal order)" : "");
  if (f.naive_length_m > 0.0) std::cout << ", by id " << formatFixed(f.naive_length_m, 1) << " m";
  std::cout << "\n";
  for (const auto& e : f.excluded)
    std::cout << "  not flown: surface " << e.surface_id << " (" << e.reason << ")\n";
}

/// One line over all surfaces: what the mission is, in numbers.
void printTotals(const app::PlanResult& p) {
  std::size_t ok = 0, stops = 0, waypoints = 0, links = 0, links_ok = 0;
  double length = 0.0;
  for (const auto& m : p.missions) {
    const bool link = m.kind == "edge";
    links += link ? 1 : 0;
    if (!planning::flyable(m.status)) continue;
    (link ? links_ok : ok) += 1;
    stops += m.strategy.stops.size();
    waypoints += m.waypoints.size();
    length += m.path_length_m;
  }
  std::cout << "summary: " << ok << " of " << p.missions.size() - links
            << " surfaces with a mission, ";
  if (links > 0) std::cout << links_ok << " of " << links << " edge links, ";
  std::cout << stops << " photo stops, " << waypoints << " waypoints, " << formatFixed(length, 1)
            << " m over the surfaces\n";
  printFlight(p.flight);
}

/// Exit code of run and plan: 0 when a flight exists, listing (on stderr, unless -q)
/// the chosen surfaces it leaves out; 3 when nothing chosen can be flown, when the
/// one chosen surface cannot be, or when the flight failed. An empty flight is never 0.
int missionExitCode(const app::PlanResult& p, const Verbosity& v) {
  const auto unflyable = [](const planning::SurfaceMission& m) {
    return !planning::flyable(m.status);
  };
  const auto first = std::find_if(p.missions.begin(), p.missions.end(), unflyable);
  const auto count = std::count_if(p.missions.begin(), p.missions.end(), unflyable);
  const bool flight =
      p.flight.status == planning::FlightPlan::Status::Ok && !p.flight.sorties.empty();
  const std::string chosen =
      std::to_string(p.missions.size()) + " chosen surface" + (p.missions.size() == 1 ? "" : "s");
  if (first != p.missions.end() && (!flight || p.missions.size() == 1)) {
    std::cerr << "uavip: "
              << (count > 1 ? std::to_string(count) + " of " + chosen +
                                  " have no collision-free mission (each one's reason is in "
                                  "mission.json); first: "
                            : std::string())
              << "surface " << first->surface_id
              << " has no collision-free mission: " << first->reason << "\n";
    return kExitNoMission;
  }
  if (!flight) {
    std::cerr << "uavip: no collision-free flight"
              << (p.flight.reason.empty() ? std::string(" (nothing to fly)")
                                          : ": " + p.flight.reason)
              << "\n";
    return kExitNoMission;
  }
  if (first != p.missions.end() && !v.quiet) {
    std::cerr << "uavip: the flight leaves out " << count << " of " << chosen
              << " (reasons in mission.json):";
    for (const auto& m : p.missions) {
      if (unflyable(m)) std::cerr << " " << m.surface_id << " " << planning::toString(m.status);
    }
    std::cerr << "\n";
  }
  return kExitOk;
}

view::OverviewOptions overviewOptions(
    const std::string& name, double clearance_m = std::numeric_limits<double>::quiet_NaN()) {
  view::OverviewOptions o;
  o.clearance_m = clearance_m;  // mission.html colours the path by clearance against it
  o.title = name.empty() ? "uavip mission overview" : name + ": uavip mission overview";
  return o;
}

/// The views rendered on a thread of their own while the scene and the mission are
/// written; none with --no-views. The arguments must outlive the future (declare it
/// after them: its destructor waits for the thread).
std::future<view::ViewFiles> renderViewsAsync(bool views, const Scene& scene,
                                              const std::vector<planning::SurfaceMission>& missions,
                                              const view::OverviewOptions& options,
                                              const planning::FlightPlan* flight,
                                              const planning::FleetPlan* fleet = nullptr) {
  if (!views) return {};
  return std::async(std::launch::async, [&scene, &missions, options, flight, fleet] {
    return view::renderViews(scene, missions, options, flight, fleet);
  });
}

/// Stages the views once rendered (nothing with --no-views).
void stageViews(io::StagedOutputs& outputs, const std::string& out,
                std::future<view::ViewFiles>& views) {
  if (views.valid()) view::stageViews(outputs, out, views.get());
}

/// --drone / --payload of run and plan (empty: the config's uav.model).
struct AircraftArgs {
  std::string drone;
  std::string payload;
};

/// --drone / --payload: the aircraft profile the config plans for (app/aircraft_profile.h);
/// prints what the profile set.
void chooseAircraft(app::Config& config, const AircraftArgs& aircraft, const Verbosity& v) {
  const std::vector<std::string> notes =
      app::selectAircraft(config, aircraft.drone, aircraft.payload);
  if (v.quiet) return;
  for (const auto& n : notes) std::cerr << "uavip: " << config.uav.model << ": " << n << "\n";
}

int runCommand(const std::string& scenario_arg, std::string out, const std::string& surface,
               bool surface_given, const std::string& planner, const AircraftArgs& aircraft,
               int uavs, bool views, bool photos, const Verbosity& v) {
  std::string path = scenario_arg;
  if (path.empty()) {
    path = bundledScenarioDir() + "/single_cube.yaml";
    if (!v.quiet)
      std::cerr << "uavip: no scenario given, using the bundled default " << path << "\n";
  }
  app::Scenario scenario = app::loadScenario(path);
  if (!planner.empty()) {
    scenario.config.planner = planner;
    scenario.config.validate("--planner");
  }
  chooseAircraft(scenario.config, aircraft, v);
  setUavs(scenario.config, uavs);
  if (out.empty()) out = "out/" + scenario.name;
  io::ensureDirectory(out);
  const app::Progress progress = progressPrinter(v);
  // A world far from the origin is planned recentred, as a far cloud is read.
  io::CloudReadInfo recentred;
  recentred.origin_m = app::recentreScenario(scenario);
  const bool far = recentred.origin_m != Vec3::Zero();
  if (far && !v.quiet)
    std::cerr << "uavip: the world lies far from the origin: planned in a frame moved by "
              << formatRawPoint(recentred.origin_m) << " m (scene.json source_offset_m)\n";

  const auto t0 = SteadyClock::now();
  if (progress) progress("sensing " + scenario.name + " (" + scenario.sensing_mode + ")");
  const PointList raw = app::sense(scenario);
  app::CloudIndex index;  // one kd-tree for the measurement and the outlier removal
  const preprocess::CloudStats measured = app::measure(raw, &scenario, &index);
  const app::DetectResult d = app::detect(raw, scenario.config, measured, progress, index);
  const bool structure = d.resolved.config.coverage.mode == "structure";
  if (structure && surface_given)
    throw InputError(
        "--surface: the scenario's coverage.mode is structure, which covers the whole structure; "
        "leave out --surface");
  // scene.json keeps the detection; the edits (scenario `edits:`) change what is planned.
  const EditedScene edited =
      applyEditsFile(d.scene, scenario.edits, d.resolved.config, structure ? "" : surface);
  const app::PlanResult p = structure
                                ? app::planStructure(edited.scene, d.resolved.config, progress)
                                : app::plan(edited.scene, d.resolved.config,
                                            app::selectSurfaces(edited.scene, surface), progress);
  // The outputs are staged and renamed together once all of them are written: a run
  // that fails leaves the previous scene, mission and views together.
  auto rendered =
      renderViewsAsync(views, edited.scene, p.missions,
                       overviewOptions(scenario.name, d.resolved.config.uav.inflationRadius()),
                       &p.flight, p.fleet ? &*p.fleet : nullptr);
  io::StagedOutputs outputs;
  writeScene(outputs, out, d, far ? &recentred : nullptr);
  writeMission(outputs, out, p, d.resolved.config, path, edited.summary);
  stageViews(outputs, out, rendered);
  outputs.commit();
  const double total = secondsSince(t0);

  if (!v.quiet) {
    std::cout << "scenario " << scenario.name << " (" << path << ")\n";
    printDetectSummary(d);
    printEdits(edited.summary);
    printPlanSummary(p);
    std::cout << "time: " << formatFixed(total, 2) << " s (perception "
              << formatFixed(d.times.total_s, 2) << " s, grid " << formatFixed(p.times.grid_s, 2)
              << " s, planning " << formatFixed(p.times.planning_s, 2) << " s)\n";
    printTotals(p);
    printFleet(p.fleet);
    std::cout << "results: " << out << "/mission.json, " << out << "/scene.json, " << out
              << "/cloud_clean.pcd, " << out << "/" << io::kSafetyCloudFile << "\n"
              << (views ? "views: " + out + "/overview.png, " + out + "/scene.ply, " + out +
                              "/path.obj, " + out + "/mission.html\n"
                        : "");
  }
  // A scenario without surfaces (the single point, the line) has nothing to fly, as
  // the paper expects: that is a result, not a failure.
  if (p.missions.empty()) return kExitOk;
  if (photos)
    renderPlanPhotos(out + "/mission.json", scenario.world, path, out + "/photos", 0, 1.0, v);
  return missionExitCode(p, v);
}

/// --cover: "" (planes by --surface) or "structure"; exit 2 for anything else or both.
bool structureCover(const std::string& cover, bool surface_given) {
  if (cover.empty()) {
    if (!surface_given)
      throw InputError(
          "plan: give --surface (an id, a list '0,3,5' or 'all') or --cover structure");
    return false;
  }
  if (cover != "structure")
    throw InputError("--cover: '" + cover + "' is not a coverage mode; use --cover structure");
  if (surface_given)
    throw InputError(
        "--cover structure covers the whole structure; leave out --surface (or drop --cover)");
  return true;
}

}  // namespace

/// --uavs K (K >= 0 when given) sets fleet.uavs and checks the config again.
void setUavs(app::Config& config, int uavs) {
  if (uavs < 0) return;
  config.fleet.uavs = uavs;
  config.sources.set(config.keyOf(&config.fleet.uavs), params::Source::File);
  config.validate("--uavs");
}

std::string fleetTimesText(const planning::FleetPlan& f) {
  const auto minutes = [](double s) { return formatFixed(s / 60.0, 1) + " min"; };
  return "makespan " + minutes(f.makespan_s) + " (single UAV " + minutes(f.single_uav_s) +
         ", speed-up " + formatFixed(f.makespan_s > 0.0 ? f.single_uav_s / f.makespan_s : 0.0, 2) +
         ", lower bound " + minutes(f.lower_bound_s) + ")";
}

std::string fleetSeparationText(const planning::FleetPlan& f) {
  return "closest approach " + formatFixed(f.separation.nominal_min_m, 2) + " m on schedule, " +
         formatFixed(f.separation.swept_min_m, 2) + " m with " + formatNumber(f.options.slack_s) +
         " s slack (separation " + formatNumber(f.options.separation_m) + " m)";
}

/// The fleet: makespan against the single flight and the bound, separation, each UAV.
void printFleet(const std::optional<planning::FleetPlan>& fleet) {
  if (!fleet) return;
  const planning::FleetPlan& f = *fleet;
  std::cout << "fleet: " << f.uavs.size() << " UAVs, " << fleetTimesText(f) << ", " << f.jobs
            << " jobs, " << f.split_surfaces << " surfaces shared, " << f.waits << " waits"
            << (f.assignment.empty() ? ""
                                     : ", assignment " + f.assignment + " of " +
                                           std::to_string(f.candidates) + " tried")
            << (f.fallback_single ? "; UAV 1 flies alone (the fleet was no faster)" : "") << "; "
            << fleetSeparationText(f) << "\n";
  for (std::size_t i = 0; i < f.uavs.size(); ++i) {
    const auto& u = f.uavs[i];
    std::cout << "  uav " << i + 1 << ": home " << formatPoint(u.home) << ", " << u.stops
              << " stops, " << u.flight.sorties.size() << " sorties, take-off at "
              << formatFixed(u.sortie_start_s.empty() ? 0.0 : u.sortie_start_s.front(), 1)
              << " s, lands " << formatFixed(u.end_s, 1) << " s\n";
  }
}

// Declared in commands.h.
void resolveCrs(io::CloudReadInfo& read, const std::string& cloud_path, const std::string& crs,
                const std::string& vertical, const Verbosity& v) {
  if (!crs.empty()) {
    if (!read.crs.empty() && read.crs != crs && !v.quiet)
      std::cerr << "uavip: warning: --crs " << crs << " differs from the CRS " << cloud_path
                << " states (" << read.crs_source << ": " << read.crs.substr(0, 80)
                << (read.crs.size() > 80 ? "…" : "") << "); recording --crs " << crs << "\n";
    read.crs = crs;
    read.crs_source = "detect --crs";
  }
  if (read.crs.empty()) {
    if (!vertical.empty())
      throw InputError("--vertical: " + cloud_path +
                       " states no CRS; give --crs too (e.g. --crs EPSG:32631 --vertical egm96)");
    return;
  }
  int vertical_epsg = 0;
  try {
    vertical_epsg = io::CrsTransform(read.crs, "--crs").verticalEpsg();
  } catch (const InputError& e) {
    if (!crs.empty()) throw;  // what the user typed must be a CRS PROJ knows
    if (!v.quiet)
      std::cerr << "uavip: warning: " << cloud_path << ": PROJ cannot use the CRS the file states ("
                << e.what() << "); export will need --crs or --origin\n";
  }
  if (!vertical.empty()) {
    read.crs_vertical = io::verticalDatumName(io::parseVerticalDatum(vertical));
  } else if (const auto d = io::verticalDatumOfEpsg(vertical_epsg)) {
    read.crs_vertical = io::verticalDatumName(*d);
  }
}

namespace {

int detectCommand(const std::string& cloud_path, const std::string& config_path,
                  const std::string& out, const std::string& crs, const std::string& vertical,
                  bool views, const Verbosity& v) {
  const app::Config config =
      config_path.empty() ? app::parseConfig("", "(defaults)") : app::loadConfig(config_path);
  io::CloudReadInfo read;
  const PointList raw = io::loadCloud(cloud_path, config.input, &read);
  resolveCrs(read, cloud_path, crs, vertical, v);
  if (!v.quiet && !read.note.empty()) std::cout << read.note << "\n";
  if (!v.quiet && !read.crs.empty())
    std::cout << "CRS: " << read.crs.substr(0, 80) << (read.crs.size() > 80 ? "…" : "") << " ("
              << read.crs_source << "), heights above "
              << (read.crs_vertical.empty() ? "EGM96 unless export --vertical says otherwise"
                                            : read.crs_vertical)
              << "\n";
  io::ensureDirectory(out);
  const app::Progress progress = progressPrinter(v);
  if (progress)
    progress("measuring spacing, extent and noise of " + std::to_string(raw.size()) + " points");
  app::CloudIndex index;  // one kd-tree for the measurement and the outlier removal
  const preprocess::CloudStats measured = app::measure(raw, nullptr, &index);
  app::DetectResult d = app::detect(raw, config, measured, progress, index);
  // The input file, so that validate can measure a flight against every point of it.
  d.scene.safety->source = fs::absolute(cloud_path).lexically_normal().string();
  d.scene.safety->sha256 = io::sha256File(cloud_path);
  d.scene.safety->mesh = read.triangles;  // a mesh: its triangles, measured exactly
  const std::vector<planning::SurfaceMission> no_missions;
  view::OverviewOptions view_options = overviewOptions(fs::path(cloud_path).stem().string());
  if (views && !read.crs.empty())
    view_options.geo =
        pageGeoFit(io::SceneCrsRecord{read.crs, read.crs_vertical, read.crs_source, read.origin_m},
                   d.scene, v);
  auto rendered = renderViewsAsync(views, d.scene, no_missions, view_options, nullptr);
  io::StagedOutputs outputs;
  writeScene(outputs, out, d, &read);
  stageViews(outputs, out, rendered);
  outputs.commit();
  if (!v.quiet) {
    printDetectSummary(d);
    std::cout << "results: " << out << "/scene.json, " << out << "/cloud_clean.pcd, " << out << "/"
              << io::kSafetyCloudFile << "\n"
              << (views ? "views: " + out + "/overview.png, " + out + "/scene.ply, " + out +
                              "/mission.html\n"
                        : "");
  }
  return kExitOk;
}

/// plan -o OTHER: scene.json and the safety cloud (and a mesh input's triangles) it names
/// copied beside mission.json,
/// so that export and validate find the scene there as after run (nothing when OUT is
/// the scene's own folder).
void stageSceneBeside(io::StagedOutputs& outputs, const std::string& scene_path,
                      const nlohmann::json& scene_json, const std::string& out) {
  const fs::path from = fs::absolute(scene_path).parent_path();
  std::error_code ec;
  if (fs::equivalent(from, out, ec)) return;
  std::vector<std::pair<fs::path, fs::path>> copies = {{scene_path, fs::path(out) / "scene.json"}};
  if (scene_json.contains("safety") && scene_json["safety"].contains("file") &&
      scene_json["safety"]["file"].is_string()) {
    const std::string name = scene_json["safety"]["file"].get<std::string>();
    if (fs::exists(from / name)) copies.emplace_back(from / name, fs::path(out) / name);
    const nlohmann::json& safety = scene_json["safety"];
    if (safety.contains("mesh") && safety["mesh"].contains("file") &&
        safety["mesh"]["file"].is_string()) {  // a mesh input's triangles
      const std::string mesh = safety["mesh"]["file"].get<std::string>();
      if (fs::exists(from / mesh)) copies.emplace_back(from / mesh, fs::path(out) / mesh);
    }
  }
  for (const auto& [src, dst] : copies) {
    outputs.writeWith(dst.string(), [&src = src, &dst = dst](const std::string& tmp) {
      std::error_code copy_ec;
      fs::copy_file(src, tmp, fs::copy_options::overwrite_existing, copy_ec);
      if (copy_ec)
        throw InputError(dst.string() + ": cannot copy the scene's " + src.string() + " here (" +
                         copy_ec.message() + ")");
    });
  }
}

int planCommand(const std::string& scene_path, const std::string& config_path,
                const std::string& surface, const std::string& cover, const std::string& planner,
                const AircraftArgs& aircraft, int uavs, const std::string& edits_path,
                const std::string& out, bool views, const Verbosity& v) {
  const bool structure = structureCover(cover, !surface.empty());
  app::Config config =
      config_path.empty() ? app::parseConfig("", "(defaults)") : app::loadConfig(config_path);
  if (!planner.empty()) {
    config.planner = planner;
    config.validate("--planner");
  }
  chooseAircraft(config, aircraft, v);
  setUavs(config, uavs);
  const nlohmann::json scene_json = io::JsonReader(scene_path).load();
  const Scene detected = io::sceneFromJson(scene_json, scene_path);
  const app::Config resolved = app::resolveForScene(detected, config).config;
  const EditedScene edited =
      applyEditsFile(detected, edits_path, resolved, structure ? "" : surface);
  const Scene& scene = edited.scene;
  const std::vector<int> ids = structure ? std::vector<int>{} : app::selectSurfaces(scene, surface);
  io::ensureDirectory(out);
  const app::PlanResult p = structure ? app::planStructure(scene, resolved, progressPrinter(v))
                                      : app::plan(scene, resolved, ids, progressPrinter(v));
  view::OverviewOptions view_options = overviewOptions(
      fs::path(scene_path).parent_path().filename().string(), resolved.uav.inflationRadius());
  if (views) view_options.geo = pageGeoFit(io::sceneCrsFromJson(scene_json, scene_path), scene, v);
  auto rendered = renderViewsAsync(views, scene, p.missions, view_options, &p.flight,
                                   p.fleet ? &*p.fleet : nullptr);
  io::StagedOutputs outputs;
  writeMission(outputs, out, p, resolved, scene_path, edited.summary);
  stageSceneBeside(outputs, scene_path, scene_json, out);
  stageViews(outputs, out, rendered);
  outputs.commit();
  if (!v.quiet) {
    printEdits(edited.summary);
    printPlanSummary(p);
    printTotals(p);
    printFleet(p.fleet);
    std::cout << "results: " << out << "/mission.json\n"
              << (views ? "views: " + out + "/overview.png, " + out + "/scene.ply, " + out +
                              "/path.obj, " + out + "/mission.html\n"
                        : "");
  }
  return missionExitCode(p, v);
}

std::string plannerList() {
  std::string names;
  for (const auto& n : planners::plannerNames()) names += (names.empty() ? "" : ", ") + n;
  return names;
}

/// detect --help: how the parameters follow the cloud.
constexpr const char* kDetectFooter =
    "Parameters follow the cloud: its spacing, extent and noise are measured first, and every\n"
    "parameter the config does not set is chosen from them ('auto': the voxel, the RANSAC band,\n"
    "the cluster tolerances, the area cell, the planning grid). On a dense scan (spacing <= 5 "
    "cm)\n"
    "they are the paper's values. The chosen values are printed and written to scene.json.\n"
    "LAS files: metres from the file's CRS unit, recentred (source_offset_m in scene.json);\n"
    "'input: {drop_classes: [3, 4, 5, 7]}' in the config drops vegetation and noise.";

/// plan --help: the flight, stop repair, coverage and --cover structure.
constexpr const char* kPlanFooter =
    "The flight: the flyable surfaces ordered from home and back (each forward or reversed),\n"
    "every connecting leg planned on the grid, split into battery sorties, each validated.\n"
    "Home: mission.home, else mission.start, else the lowest photo stop. Flight model: section\n"
    "'flight: {cruise_speed_m_s: 3, climb_speed_m_s: 2, descent_speed_m_s: 1.5, hover_s: 2,\n"
    "settle_s: 1, endurance_s: 1200, reserve: 0.25}'. Export it with 'uavip export --surface "
    "all'.\n"
    "Stop repair: a photo stop too close to something (the ground under a facade) is moved to a\n"
    "free pose that still sees its photo centre: tilted from above/below/the sides, or up to\n"
    "mission.max_standoff_factor (1.25) x farther; 'mission: {repair_stops: false}' turns it "
    "off.\n"
    "Coverage: the share of the surface's points that some flown photo images (in the photo,\n"
    "<= 75 deg off the normal, clear line of sight); below mission.min_coverage (0.95) a "
    "surface\n"
    "is 'partial'. Parameters not in the config follow the cloud numbers stored in scene.json.\n"
    "\n"
    "--cover structure: photos of the whole structure in one flight, not plane by plane. The\n"
    "structure is every point of the clean cloud except the ground (horizontal surfaces at the\n"
    "site's lowest level spanning a quarter of its footprint, and every point below\n"
    "coverage.ground_z_m). Candidate views at the viewing distance (coverage.standoff_m, else "
    "the\n"
    "camera's GSD) along each seed point's normal, tilted 35 deg up and down, free by the UAV's\n"
    "clearance from every input point; chosen by set cover until coverage.structure_target "
    "(0.99)\n"
    "of what can be seen, then pruned. Camera: 'camera: {fx: 417, fy: 461, cx: 320, cy: 240,\n"
    "image_px: [640, 480], max_range_m: 11}' (a pinhole), or the footprint/sensor keys.\n"
    "Coverage: rule (a) FC-Planner's pixel rule; rule (b) GSD and range <= 1.25 x the viewing\n"
    "distance, <= 75 deg incidence, clear line of sight.";

/// --drone / --payload on run and plan.
void addAircraftOptions(CLI::App& cmd, AircraftArgs& a) {
  cmd.add_option("--drone", a.drone,
                 "Plan for this aircraft (camera, gimbal pitch, speed, endurance, size; the "
                 "config's own keys win): " +
                     aircraft::profileList());
  cmd.add_option("--payload", a.payload,
                 "m300/m350: the camera on the gimbal (" + aircraft::payloadList() + ")");
}

/// Options of run / detect / plan, kept alive until dispatch.
struct PipelineArgs {
  std::string scenario, out, surface, planner, cloud, config, scene, cover, crs, vertical, edits;
  AircraftArgs aircraft;
  int uavs{-1};  ///< --uavs; −1 when not given
  bool no_views{false};
  bool photos{false};
};

}  // namespace

// Declared in commands.h.
void writeScene(io::StagedOutputs& outputs, const std::string& out, const app::DetectResult& d,
                const io::CloudReadInfo* read) {
  const std::string pcd = (std::filesystem::path(out) / "cloud_clean.pcd").string();
  outputs.writeWith(
      pcd, [&](const std::string& tmp) { io::writeCloudPcdFile(tmp, d.scene.cloud, pcd); });
  if (d.scene.safety) {
    const std::string safety = (std::filesystem::path(out) / io::kSafetyCloudFile).string();
    outputs.writeWith(safety, [&](const std::string& tmp) {
      io::writeCloudPcdFile(tmp, d.scene.safety->points, safety);
    });
    if (d.scene.safety->mesh) {
      const std::string stl = (std::filesystem::path(out) / io::kSafetyMeshFile).string();
      outputs.writeWith(stl, [&](const std::string& tmp) {
        io::writeMeshStlFile(tmp, *d.scene.safety->mesh, stl);
      });
    }
  }
  outputs.write((std::filesystem::path(out) / "scene.json").string(),
                io::sceneJsonText(d.scene, app::sceneExtras(d, read)));
}

void writeMission(io::StagedOutputs& outputs, const std::string& out, const app::PlanResult& plan,
                  const app::Config& config, const std::string& source,
                  const std::optional<io::EditsSummary>& edits) {
  io::MissionExtras extras = app::missionExtras(plan, config, source);
  extras.edits = edits;
  outputs.write((std::filesystem::path(out) / "mission.json").string(),
                io::missionJsonText(plan.missions, plan.flight, config.flight.model, extras));
}

void addPipelineCommands(CLI::App& cli, CommandRegistry& registry) {
  auto a = std::make_shared<PipelineArgs>();
  const Verbosity& v = registry.verbosity();
  const std::string planner_help =
      "Point-to-point planner (" + plannerList() + "); default: the file's";
  const std::string views_help =
      "Skip overview.png, scene.ply, path.obj and mission.html (the views are drawn on a second "
      "thread)";
  const std::string uavs_help =
      "Fly the site with K UAVs at once (fleet.uavs; section 'fleet:' in the config)";

  auto* run = cli.add_subcommand(
      "run", "Sense a scenario, detect surfaces and obstacles, plan photo stops and waypoints");
  run->add_option("scenario", a->scenario, "Scenario YAML (default: the bundled single_cube.yaml)");
  run->add_option("-o,--out", a->out, "Output directory (default: out/<scenario name>)");
  run->add_option("--surface", a->surface, "Surface id, a list '0,3,5', or 'all' (default: all)");
  run->add_option("--planner", a->planner, planner_help);
  addAircraftOptions(*run, a->aircraft);
  run->add_option("--uavs", a->uavs, uavs_help);
  run->add_flag("--no-views", a->no_views, views_help);
  run->add_flag("--photos", a->photos,
                "Also render every photo stop against the scenario's world into OUT/photos (as "
                "uavip photos)");
  registry.add(run, [a, &v] {
    return runCommand(a->scenario, a->out, a->surface.empty() ? "all" : a->surface,
                      !a->surface.empty(), a->planner, a->aircraft, a->uavs, !a->no_views,
                      a->photos, v);
  });

  auto* det = cli.add_subcommand(
      "detect", "Stages 3-5 on a point cloud file: clean cloud, surfaces, obstacles");
  det->footer(kDetectFooter);
  det->add_option("cloud", a->cloud,
                  "Cloud file (.pcd, .ply, .xyz, .txt, .las) or mesh (.stl, .obj, .ply with faces, "
                  ".gltf, .glb, .dae, .fbx, .3ds, .off: its surface sampled)")
      ->required();
  det->add_option("-c,--config", a->config,
                  "Config YAML (scenario sections; default: auto from the cloud, see below)");
  det->add_option("-o,--out", a->out, "Output directory")->required();
  det->add_option("--crs", a->crs,
                  "The cloud's CRS when the file does not state it (e.g. EPSG:32631, or "
                  "EPSG:32650+5773 with EGM96 heights); recorded in scene.json for export");
  det->add_option("--vertical", a->vertical,
                  "What the cloud's z is measured from: egm96, egm2008 or ellipsoid (default: the "
                  "CRS's vertical part, else unknown: export assumes egm96)");
  det->add_flag("--no-views", a->no_views, views_help);
  registry.add(det, [a, &v] {
    return detectCommand(a->cloud, a->config, a->out, a->crs, a->vertical, !a->no_views, v);
  });

  auto* pl = cli.add_subcommand(
      "plan", "Stages 6-7 for the chosen surfaces of a scene.json, and one flight over them");
  pl->footer(kPlanFooter);
  pl->add_option("scene", a->scene, "OUT/scene.json written by run or detect")->required();
  pl->add_option("--surface", a->surface, "Surface id, a list '0,3,5', or 'all'");
  pl->add_option("--cover", a->cover,
                 "'structure': cover the whole structure (instead of --surface)");
  pl->add_option("-c,--config", a->config, "Config YAML (camera, overlap, uav, grid, planner)");
  pl->add_option("--planner", a->planner, planner_help);
  addAircraftOptions(*pl, a->aircraft);
  pl->add_option("--edits", a->edits,
                 "Edits YAML (uavip-edits: 1): boundaries, deleted or merged surfaces, keep-out "
                 "volumes; mission.html's edit mode saves one");
  pl->add_option("-o,--out", a->out, "Output directory")->required();
  pl->add_option("--uavs", a->uavs, uavs_help);
  pl->add_flag("--no-views", a->no_views, views_help);
  registry.add(pl, [a, &v] {
    return planCommand(a->scene, a->config, a->surface, a->cover, a->planner, a->aircraft, a->uavs,
                       a->edits, a->out, !a->no_views, v);
  });
}

}  // namespace uavip::cli
