#include "uavip/bench/runner.h"

#include <algorithm>
#include <ctime>
#include <iomanip>
#include <limits>
#include <memory>
#include <random>
#include <set>
#include <sstream>

#include "planners/harness.h"
#include "planners/registry.h"
#include "uavip/bench/stats.h"
#include "uavip/core/error.h"
#include "uavip/core/geometry.h"
#include "uavip/core/math.h"
#include "uavip/core/stopwatch.h"
#include "uavip/core/text.h"
#include "uavip/coverage/flight_strategy.h"
#include "uavip/planning/path_validator.h"
#include "uavip/world/collision_world.h"
#include "uavip/world/voxel_grid.h"

namespace uavip::bench {

void BenchOptions::validate() const {
  const auto names = planners::plannerNames();
  for (const auto& p : planners) {
    if (std::find(names.begin(), names.end(), p) == names.end()) {
      std::string valid;
      for (const auto& n : names) {
        if (!valid.empty()) valid += ", ";
        valid += n;
      }
      throw InputError("--planners: unknown planner '" + p + "'; valid names: " + valid);
    }
  }
  std::set<std::string> seen(planners.begin(), planners.end());
  require(seen.size() == planners.size(), "--planners", "lists a planner twice");
  if (runs < 1 || runs > 10000)
    throw InputError("--runs: must be in [1, 10000], got " + std::to_string(runs));
  requirePositive(time_limit_s, "--time-limit", "the time limit [s]");
  require(time_limit_s <= 3600.0, "--time-limit",
          "must be <= 3600 s, got " + formatNumber(time_limit_s));
  requirePositive(max_total_s, "--max-total", "the worst-case planning time [s]");
}

namespace {

void report(const app::Progress& progress, const std::string& message) {
  if (progress) progress(message);
}

std::string localTime() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  localtime_r(&now, &tm);
  std::ostringstream os;
  os << std::put_time(&tm, "%Y-%m-%d %H:%M:%S");
  return os.str();
}

/// Legs of one scenario with feasibility on the grid.
bool feasibleOnGrid(const world::VoxelGrid& grid, const Vec3& a, const Vec3& b) {
  return grid.connected(grid.indexOf(a), grid.indexOf(b));
}

}  // namespace

std::vector<PointList> stopsBySurface(const Scene& scene,
                                      const coverage::CoverageOptions& coverage) {
  std::vector<PointList> out;
  out.reserve(scene.surfaces.size());
  for (const auto& surface : scene.surfaces) {
    PointList stops;
    for (const auto& stop : coverage::planFlightStrategy(surface, coverage).stops)
      stops.push_back(stop.position);
    out.push_back(std::move(stops));
  }
  return out;
}

std::vector<std::pair<Vec3, Vec3>> sampleLegs(const world::VoxelGrid& grid,
                                              const std::vector<PointList>& stops_by_surface,
                                              int max_legs, std::uint32_t seed) {
  struct Stop {
    std::size_t surface;
    Vec3 p;
  };
  std::vector<Stop> stops;
  for (std::size_t s = 0; s < stops_by_surface.size(); ++s)
    for (const Vec3& p : stops_by_surface[s])
      if (grid.isFree(p)) stops.push_back({s, p});
  std::vector<std::pair<Vec3, Vec3>> legs;
  if (stops.size() < 2 || max_legs < 1) return legs;
  const bool one_surface = std::all_of(
      stops.begin(), stops.end(), [&](const Stop& s) { return s.surface == stops[0].surface; });

  std::mt19937 rng(seed);
  std::set<std::pair<std::size_t, std::size_t>> used;
  const std::size_t n = stops.size();
  for (int attempt = 0; attempt < 20000 && static_cast<int>(legs.size()) < max_legs; ++attempt) {
    const std::size_t i = rng() % n;
    const std::size_t j = rng() % n;
    if (i == j || (!one_surface && stops[i].surface == stops[j].surface)) continue;
    if (used.count({std::min(i, j), std::max(i, j)})) continue;
    const Vec3& a = stops[i].p;
    const Vec3& b = stops[j].p;
    if (grid.segmentFree(a, b)) continue;  // trivial: the straight line is free
    if (!grid.connected(grid.indexOf(a), grid.indexOf(b))) continue;
    used.insert({std::min(i, j), std::max(i, j)});
    legs.emplace_back(a, b);
  }
  return legs;
}

namespace {

/// One scenario made ready for the runs: its planning space, legs and config.
struct PreparedScenario {
  app::PlanningSpace space;
  std::vector<BenchLeg> legs;
  app::Config config;
};

/// Sense, stages 3–5, stage 6 for every surface, the planning space a mission plans
/// in (app::planningSpace) around the stops and the legs, and the legs (explicit, or
/// sampled between stops); the legs are appended to result.legs with global ids.
PreparedScenario prepareScenario(const app::Scenario& sc, int scenario_index,
                                 const BenchOptions& options, BenchResult& result) {
  const PointList raw = sense(sc);
  app::CloudIndex index;
  const preprocess::CloudStats measured = app::measure(raw, &sc, &index);
  const app::DetectResult d = app::detect(raw, sc.config, measured, {}, index);
  const app::Config& config = d.resolved.config;
  const std::vector<PointList> stops_by_surface = stopsBySurface(d.scene, config.coverage);
  PointList extra;
  for (const auto& stops : stops_by_surface) extra.insert(extra.end(), stops.begin(), stops.end());
  for (const auto& [a, b] : sc.bench.legs) {
    extra.push_back(a);
    extra.push_back(b);
  }
  if (config.mission.start) extra.push_back(*config.mission.start);
  if (d.scene.cloud.empty() && extra.empty()) {
    throw InputError(sc.path + ": bench: the scenario has no cloud and no legs");
  }
  if (extra.empty()) {
    throw InputError(
        sc.path + ": bench: no legs (give bench.legs, or a scenario with stops on >= 2 surfaces)");
  }
  // The same grid and validator as a mission: every measured point, the solids and
  // the keep-out volumes, at the safety clearance.
  PreparedScenario out{
      app::planningSpace(d.scene, std::make_shared<const world::CollisionWorld>(d.scene), config,
                         extra),
      {},
      config};
  const world::VoxelGrid& grid = out.space.grid;

  const std::vector<std::pair<Vec3, Vec3>> legs =
      sc.bench.legs.empty() ? sampleLegs(grid, stops_by_surface, sc.bench.max_legs, options.seed)
                            : sc.bench.legs;
  if (legs.empty()) {
    throw InputError(
        sc.path + ": bench: no legs (give bench.legs, or a scenario with stops on >= 2 surfaces)");
  }
  for (const auto& [a, b] : legs) {
    BenchLeg leg;
    leg.id = static_cast<int>(result.legs.size());
    leg.scenario = scenario_index;
    leg.start = a;
    leg.goal = b;
    leg.explicit_leg = !sc.bench.legs.empty();
    leg.feasible = feasibleOnGrid(grid, a, b);
    leg.straight_m = (b - a).norm();
    result.legs.push_back(leg);
    out.legs.push_back(leg);
  }
  return out;
}

/// One run of `planner` on `leg` through the OMPL harness, its final path validated.
BenchRun runOnce(const std::string& planner, const BenchLeg& leg, const PreparedScenario& prepared,
                 const planners::PlannerSettings& settings) {
  const planners::HarnessRun h =
      planners::runPlannerOnce(planner, prepared.space.grid, leg.start, leg.goal, settings);
  BenchRun r;
  r.leg = leg.id;
  r.scenario = leg.scenario;
  r.planner = planner;
  r.ompl_name = h.ompl_name;
  r.status = h.status;
  r.solved = h.solved;
  r.approximate = h.approximate;
  r.time_s = h.time_s;
  r.simplify_time_s = h.simplify_time_s;
  r.raw_length_m = h.solved ? h.raw_length_m : kNan;
  r.length_m = h.solved ? h.length_m : kNan;
  r.raw_waypoints = h.raw_path.size();
  r.waypoints = h.path.size();
  r.graph_states = h.graph_states;
  r.graph_motions = h.graph_motions;
  r.min_clearance_m = kNan;
  if (h.solved) {
    const planning::ValidationResult v = prepared.space.validator.validate(h.path);
    r.min_clearance_m = v.min_clearance_m;
    r.valid = v.collision_free;
  }
  return r;
}

}  // namespace

BenchResult runBench(const std::vector<app::Scenario>& scenarios, const BenchOptions& options,
                     const app::Progress& progress) {
  options.validate();
  if (scenarios.empty()) throw InputError("bench: give at least one scenario");
  BenchResult result;
  result.options = options;
  result.planners = options.planners.empty() ? planners::plannerNames() : options.planners;
  result.start_time = localTime();
  const auto t0 = SteadyClock::now();

  std::vector<std::vector<BenchRun>> runs_by_scenario;
  double worst_case_s = 0.0;  // if every run took its whole time limit
  for (std::size_t si = 0; si < scenarios.size(); ++si) {
    const app::Scenario& sc = scenarios[si];
    result.scenarios.push_back(sc.name);
    report(progress, "bench: " + sc.name + ": sensing, detection, coverage");
    const PreparedScenario prepared = prepareScenario(sc, static_cast<int>(si), options, result);

    worst_case_s += static_cast<double>(prepared.legs.size() * result.planners.size()) *
                    options.runs * options.time_limit_s;
    if (worst_case_s > options.max_total_s)
      throw InputError("bench: " + std::to_string(result.legs.size()) + " legs x " +
                       std::to_string(result.planners.size()) + " planners x " +
                       std::to_string(options.runs) + " runs x " +
                       formatNumber(options.time_limit_s) + " s may take " +
                       formatFixed(worst_case_s / 3600.0, 1) + " h, more than --max-total " +
                       formatNumber(options.max_total_s) +
                       " s; lower --runs, --time-limit or the legs, or raise --max-total");

    planners::PlannerSettings settings = prepared.config.planner_settings;
    settings.time_limit_s = options.time_limit_s;
    settings.simplify = options.simplify;
    settings.seed = options.seed;
    std::vector<BenchRun> runs;
    const auto tp = SteadyClock::now();
    for (const auto& leg : prepared.legs) {
      for (const auto& name : result.planners) {
        report(progress, "bench: " + sc.name + ": leg " + std::to_string(leg.id) + ", " + name +
                             " x" + std::to_string(options.runs));
        for (int k = 0; k < options.runs; ++k)
          runs.push_back(runOnce(name, leg, prepared, settings));
      }
    }
    result.planning_s += secondsSince(tp);
    const std::vector<PlannerSummary> summary = summarise(sc.name, runs, result.planners);
    result.summary.insert(result.summary.end(), summary.begin(), summary.end());
    if (auto t = checkTarget(sc.name, runs, summary)) result.targets.push_back(*t);
    runs_by_scenario.push_back(std::move(runs));
  }

  // Runs grouped by planner (the log lists them per planner), then scenario, leg, run.
  for (const auto& name : result.planners)
    for (const auto& runs : runs_by_scenario)
      for (const auto& r : runs)
        if (r.planner == name) result.runs.push_back(r);
  if (scenarios.size() > 1) {
    for (auto& s : summarise("all", result.runs, result.planners)) result.summary.push_back(s);
  }
  result.total_s = secondsSince(t0);
  return result;
}

}  // namespace uavip::bench
