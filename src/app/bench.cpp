#include "uavip/app/bench.h"

#include "uavip/core/error.h"
#include "uavip/core/geometry.h"
#include "uavip/core/math.h"
#include "uavip/core/stopwatch.h"
#include "uavip/core/text.h"
#include "uavip/coverage/flight_strategy.h"
#include "uavip/planning/path_validator.h"
#include "uavip/render/plot.h"
#include "uavip/world/voxel_grid.h"
#include "planners/harness.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <iomanip>
#include <limits>
#include <map>
#include <optional>
#include <random>
#include <set>
#include <sstream>

#ifndef UAVIP_VERSION
#define UAVIP_VERSION "dev"
#endif

namespace uavip::app {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kNan = std::numeric_limits<double>::quiet_NaN();


void report(const Progress& progress, const std::string& message) {
  if (progress) progress(message);
}

bool isOurs(const std::string& planner) { return planner == "astar" || planner == "astar-euclid"; }

std::string localTime() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  localtime_r(&now, &tm);
  std::ostringstream os;
  os << std::put_time(&tm, "%Y-%m-%d %H:%M:%S");
  return os.str();
}

/// A report cell: the number with 10 significant digits, blank when missing (nan/inf:
/// NULL in SQLite).
std::string cell(double v) { return std::isfinite(v) ? formatNumber(v, 10) : ""; }

/// A table entry with `decimals` decimals, "-" when missing (nan/inf).
std::string shown(double v, int decimals) { return std::isfinite(v) ? formatFixed(v, decimals) : "-"; }

/// Legs of one scenario with feasibility on the grid.
bool feasibleOnGrid(const world::VoxelGrid& grid, const Vec3& a, const Vec3& b) {
  return grid.connected(grid.indexOf(a), grid.indexOf(b));
}

/// Per-leg median final length of each planner's solved runs.
using LegMedians = std::map<std::string, std::map<int, double>>;

LegMedians legMedians(const std::vector<BenchRun>& runs) {
  std::map<std::string, std::map<int, std::vector<double>>> lengths;
  for (const auto& r : runs) {
    if (r.solved) lengths[r.planner][r.leg].push_back(r.length_m);
  }
  LegMedians out;
  for (const auto& [planner, legs] : lengths)
    for (const auto& [leg, v] : legs) out[planner][leg] = median(v);
  return out;
}

/// Median over the legs both planners solved of a's leg median / b's.
double legRatio(const LegMedians& m, const std::string& a, const std::string& b) {
  const auto ia = m.find(a);
  const auto ib = m.find(b);
  if (ia == m.end() || ib == m.end()) return kNan;
  std::vector<double> ratios;
  for (const auto& [leg, la] : ia->second) {
    const auto jb = ib->second.find(leg);
    if (jb != ib->second.end() && jb->second > 0.0) ratios.push_back(la / jb->second);
  }
  return median(ratios);
}

std::vector<PlannerSummary> summarise(const std::string& scenario, const std::vector<BenchRun>& runs,
                                      const std::vector<std::string>& planners) {
  const LegMedians m = legMedians(runs);
  // Best planner per leg: the shortest leg median.
  std::map<int, double> best;
  for (const auto& [planner, legs] : m)
    for (const auto& [leg, len] : legs) {
      const auto it = best.find(leg);
      if (it == best.end() || len < it->second) best[leg] = len;
    }
  std::vector<PlannerSummary> out;
  for (const auto& planner : planners) {
    PlannerSummary s;
    s.scenario = scenario;
    s.planner = planner;
    std::vector<double> times, lengths, waypoints;
    s.min_clearance_m = kNan;
    for (const auto& r : runs) {
      if (r.planner != planner) continue;
      ++s.runs;
      if (!r.solved) continue;
      ++s.solved;
      if (!r.valid) ++s.invalid;
      times.push_back(r.time_s + r.simplify_time_s);
      lengths.push_back(r.length_m);
      waypoints.push_back(static_cast<double>(r.waypoints));
      if (!(s.min_clearance_m <= r.min_clearance_m)) s.min_clearance_m = r.min_clearance_m;
    }
    s.success_pct = s.runs > 0 ? 100.0 * static_cast<double>(s.solved) / static_cast<double>(s.runs) : 0.0;
    s.median_time_s = median(times);
    s.median_length_m = median(lengths);
    s.median_waypoints = median(waypoints);
    std::vector<double> to_best;
    const auto it = m.find(planner);
    if (it != m.end()) {
      for (const auto& [leg, len] : it->second) to_best.push_back(len / best[leg]);
    }
    s.length_ratio_to_best = median(to_best);
    s.length_ratio_to_astar = legRatio(m, planner, "astar");
    s.time_ratio_to_astar = kNan;
    out.push_back(s);
  }
  for (auto& s : out) {
    const auto a = std::find_if(out.begin(), out.end(), [](const PlannerSummary& p) { return p.planner == "astar"; });
    if (a != out.end() && a->median_time_s > 0.0) s.time_ratio_to_astar = s.median_time_s / a->median_time_s;
  }
  return out;
}

std::optional<TargetCheck> checkTarget(const std::string& scenario, const std::vector<BenchRun>& runs,
                                       const std::vector<PlannerSummary>& summary) {
  // The best of each side: highest success, then shortest median length.
  auto better = [](const PlannerSummary* cur, const PlannerSummary& cand) {
    if (cur == nullptr) return true;
    if (cand.success_pct != cur->success_pct) return cand.success_pct > cur->success_pct;
    return cand.median_length_m < cur->median_length_m;
  };
  const PlannerSummary* ours = nullptr;
  const PlannerSummary* ompl = nullptr;
  for (const auto& s : summary) {
    if (s.solved == 0) continue;
    if (isOurs(s.planner)) {
      if (better(ours, s)) ours = &s;
    } else if (better(ompl, s)) {
      ompl = &s;
    }
  }
  if (ours == nullptr || ompl == nullptr) return std::nullopt;
  TargetCheck t;
  t.scenario = scenario;
  t.ours = ours->planner;
  t.best_ompl = ompl->planner;
  t.ours_length_m = ours->median_length_m;
  t.ompl_length_m = ompl->median_length_m;
  t.ours_time_s = ours->median_time_s;
  t.ompl_time_s = ompl->median_time_s;
  t.leg_length_ratio = legRatio(legMedians(runs), ours->planner, ompl->planner);
  // Leg by leg: a median pooled over legs of different lengths compares nothing.
  t.as_short = ours->success_pct >= ompl->success_pct && t.leg_length_ratio <= 1.0 + 1e-4;
  t.tenth_time = t.ours_time_s <= t.ompl_time_s / 10.0;
  return t;
}

}  // namespace

void BenchOptions::validate() const {
  const auto names = planners::plannerNames();
  for (const auto& p : planners) {
    if (std::find(names.begin(), names.end(), p) == names.end()) {
      std::string valid;
      for (const auto& n : names) valid += (valid.empty() ? "" : ", ") + n;
      throw InputError("--planners: unknown planner '" + p + "'; valid names: " + valid);
    }
  }
  std::set<std::string> seen(planners.begin(), planners.end());
  require(seen.size() == planners.size(), "--planners", "lists a planner twice");
  if (runs < 1 || runs > 10000) throw InputError("--runs: must be in [1, 10000], got " + std::to_string(runs));
  requirePositive(time_limit_s, "--time-limit", "the time limit [s]");
  require(time_limit_s <= 3600.0, "--time-limit", "must be <= 3600 s, got " + formatNumber(time_limit_s));
  requirePositive(max_total_s, "--max-total", "the worst-case planning time [s]");
}

std::vector<std::pair<Vec3, Vec3>> sampleLegs(const world::VoxelGrid& grid,
                                              const std::vector<PointList>& stops_by_surface, int max_legs,
                                              std::uint32_t seed) {
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
  const bool one_surface = std::all_of(stops.begin(), stops.end(), [&](const Stop& s) { return s.surface == stops[0].surface; });

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

BenchResult runBench(const std::vector<io::Scenario>& scenarios, const BenchOptions& options,
                     const Progress& progress) {
  options.validate();
  if (scenarios.empty()) throw InputError("bench: give at least one scenario");
  BenchResult result;
  result.options = options;
  result.planners = options.planners.empty() ? planners::plannerNames() : options.planners;
  result.start_time = localTime();
  const auto t0 = Clock::now();

  std::vector<std::vector<BenchRun>> runs_by_scenario;
  double worst_case_s = 0.0;  // if every run took its whole time limit
  for (std::size_t si = 0; si < scenarios.size(); ++si) {
    const io::Scenario& sc = scenarios[si];
    result.scenarios.push_back(sc.name);
    report(progress, "bench: " + sc.name + ": sensing, detection, coverage");
    const PointList raw = sense(sc);
    const DetectResult d = detect(raw, sc.config, measure(raw, &sc));
    const io::Config& config = d.resolved.config;

    std::vector<PointList> stops_by_surface;
    PointList extra;
    for (const auto& surface : d.scene.surfaces) {
      const auto strategy = coverage::planFlightStrategy(surface, config.coverage);
      PointList stops;
      for (const auto& stop : strategy.stops) stops.push_back(stop.position);
      extra.insert(extra.end(), stops.begin(), stops.end());
      stops_by_surface.push_back(std::move(stops));
    }
    for (const auto& [a, b] : sc.bench.legs) {
      extra.push_back(a);
      extra.push_back(b);
    }
    if (config.mission.start) extra.push_back(*config.mission.start);
    if (d.scene.cloud.empty() && extra.empty()) {
      throw InputError(sc.path + ": bench: the scenario has no cloud and no legs");
    }
    const world::VoxelGrid grid = world::VoxelGrid::build(d.scene.cloud, extra, config.gridOptions());
    const planning::PathValidator validator(d.scene.cloud, config.uav.inflationRadius());

    const std::vector<std::pair<Vec3, Vec3>> legs =
        sc.bench.legs.empty() ? sampleLegs(grid, stops_by_surface, sc.bench.max_legs, options.seed) : sc.bench.legs;
    if (legs.empty()) {
      throw InputError(sc.path + ": bench: no legs (give bench.legs, or a scenario with stops on >= 2 surfaces)");
    }
    std::vector<BenchLeg> scenario_legs;
    for (const auto& [a, b] : legs) {
      BenchLeg leg;
      leg.id = static_cast<int>(result.legs.size());
      leg.scenario = static_cast<int>(si);
      leg.start = a;
      leg.goal = b;
      leg.explicit_leg = !sc.bench.legs.empty();
      leg.feasible = feasibleOnGrid(grid, a, b);
      leg.straight_m = (b - a).norm();
      result.legs.push_back(leg);
      scenario_legs.push_back(leg);
    }

    worst_case_s += static_cast<double>(scenario_legs.size() * result.planners.size()) * options.runs * options.time_limit_s;
    if (worst_case_s > options.max_total_s)
      throw InputError("bench: " + std::to_string(result.legs.size()) + " legs x " + std::to_string(result.planners.size()) +
                       " planners x " + std::to_string(options.runs) + " runs x " + formatNumber(options.time_limit_s) +
                       " s may take " + formatFixed(worst_case_s / 3600.0, 1) + " h, more than --max-total " +
                       formatNumber(options.max_total_s) + " s; lower --runs, --time-limit or the legs, or raise --max-total");

    planners::PlannerSettings settings = config.planner_settings;
    settings.time_limit_s = options.time_limit_s;
    settings.simplify = options.simplify;
    settings.seed = options.seed;
    std::vector<BenchRun> runs;
    const auto tp = Clock::now();
    for (const auto& leg : scenario_legs) {
      for (const auto& name : result.planners) {
        report(progress, "bench: " + sc.name + ": leg " + std::to_string(leg.id) + ", " + name + " x" +
                             std::to_string(options.runs));
        for (int k = 0; k < options.runs; ++k) {
          const planners::HarnessRun h = planners::runPlannerOnce(name, grid, leg.start, leg.goal, settings);
          BenchRun r;
          r.leg = leg.id;
          r.scenario = leg.scenario;
          r.planner = name;
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
            const planning::ValidationResult v = validator.validate(h.path);
            r.min_clearance_m = v.min_clearance_m;
            r.valid = v.collision_free;
          }
          runs.push_back(r);
        }
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

std::string benchLog(const BenchResult& result, const std::string& experiment_name, const std::string& host) {
  std::ostringstream out;
  out << "OMPL version " << planners::omplVersion() << "\n";
  out << "Experiment " << (experiment_name.empty() ? "uavip_bench" : experiment_name) << "\n";
  out << "4 experiment properties\n";
  out << "uavip version VARCHAR(32) = " << UAVIP_VERSION << "\n";
  out << "scenarios INTEGER = " << result.scenarios.size() << "\n";
  out << "legs INTEGER = " << result.legs.size() << "\n";
  out << "simplify BOOLEAN = " << (result.options.simplify ? 1 : 0) << "\n";
  out << "Running on " << (host.empty() ? "UNKNOWN" : host) << "\n";
  out << "Starting at " << result.start_time << "\n";
  out << "<<<|\n";
  out << "uavip bench: every planner through the ompl::base::Planner interface on R^3 over the inflated grid\n";
  for (std::size_t s = 0; s < result.scenarios.size(); ++s) out << "scenario " << s << ": " << result.scenarios[s] << "\n";
  for (const auto& leg : result.legs) {
    out << "leg " << leg.id << " (scenario " << leg.scenario << "): " << formatPoint(leg.start) << " -> " << formatPoint(leg.goal)
        << (leg.feasible ? "" : " [infeasible on the grid]") << "\n";
  }
  out << "|>>>\n";
  out << "<<<|\n|>>>\n";  // CPU info: not collected
  out << result.options.seed << " is the random seed\n";
  out << cell(result.options.time_limit_s) << " seconds per run\n";
  out << "0 MB per run\n";
  out << static_cast<std::size_t>(result.options.runs) * result.legs.size() << " runs per planner\n";
  out << cell(result.total_s) << " seconds spent to collect the data\n";
  out << "1 enum type\n";
  out << "status";
  for (const auto& s : planners::plannerStatusNames()) out << "|" << s;
  out << "\n";
  out << result.planners.size() << " planners\n";
  static const char* kProperties[] = {
      "approximate solution BOOLEAN", "graph motions INTEGER",       "graph states INTEGER",
      "leg id INTEGER",               "min clearance REAL",          "raw waypoints INTEGER",
      "scenario id INTEGER",          "simplification time REAL",    "simplified solution length REAL",
      "solution length REAL",         "solved BOOLEAN",              "status ENUM",
      "time REAL",                    "validator verdict BOOLEAN",   "waypoints INTEGER"};
  for (const auto& name : result.planners) {
    std::string ompl_name = name;
    std::vector<const BenchRun*> runs;
    for (const auto& r : result.runs) {
      if (r.planner != name) continue;
      runs.push_back(&r);
      ompl_name = r.ompl_name;
    }
    out << "geometric_" << ompl_name << "\n";
    out << "3 common properties\n";
    out << "registry name = " << name << "\n";
    out << "simplify = " << (result.options.simplify ? 1 : 0) << "\n";
    out << "time limit = " << cell(result.options.time_limit_s) << "\n";
    out << std::size(kProperties) << " properties for each run\n";
    for (const char* p : kProperties) out << p << "\n";
    out << runs.size() << " runs\n";
    for (const BenchRun* r : runs) {
      const bool ok = r->solved;
      out << (r->approximate ? 1 : 0) << "; " << r->graph_motions << "; " << r->graph_states << "; " << r->leg << "; "
          << (ok ? cell(r->min_clearance_m) : "") << "; " << r->raw_waypoints << "; " << r->scenario << "; "
          << cell(r->simplify_time_s) << "; " << (ok ? cell(r->length_m) : "") << "; "
          << (ok ? cell(r->raw_length_m) : "") << "; " << (ok ? 1 : 0) << "; " << r->status << "; " << cell(r->time_s)
          << "; " << (r->valid ? 1 : 0) << "; " << r->waypoints << "; \n";
    }
    out << ".\n";
  }
  return out.str();
}

std::string benchCsv(const BenchResult& result) {
  std::ostringstream out;
  out << "scenario,planner,runs,solved,success_pct,median_time_s,median_length_m,length_ratio_to_best,"
         "time_ratio_to_astar,length_ratio_to_astar,min_clearance_m,median_waypoints,invalid\n";
  for (const auto& s : result.summary) {
    out << s.scenario << "," << s.planner << "," << s.runs << "," << s.solved << "," << cell(s.success_pct) << ","
        << cell(s.median_time_s) << "," << cell(s.median_length_m) << "," << cell(s.length_ratio_to_best) << ","
        << cell(s.time_ratio_to_astar) << "," << cell(s.length_ratio_to_astar) << "," << cell(s.min_clearance_m) << ","
        << cell(s.median_waypoints) << "," << s.invalid << "\n";
  }
  return out.str();
}

std::string benchMarkdown(const BenchResult& result) {
  std::ostringstream out;
  out << "# uavip bench\n\n";
  out << result.scenarios.size() << " scenario(s), " << result.legs.size() << " legs, " << result.planners.size()
      << " planners, " << result.options.runs << " runs per planner and leg, time limit "
      << shown(result.options.time_limit_s, 2) << " s, simplification " << (result.options.simplify ? "on" : "off")
      << ", seed " << result.options.seed << "; total " << shown(result.total_s, 1) << " s.\n\n";
  out << "Time = solve + simplification of solved runs. Length and clearance are those of the final path. "
         "Ratios to the best planner and to the A* are medians over legs of per-leg median lengths "
         "(legs both solved). The anytime OMPL planners (RRT*, Informed RRT*, BIT*, ABIT*, AIT*, PRM*, LazyPRM*) "
         "use their whole budget.\n";
  std::vector<std::string> groups = result.scenarios;
  if (result.scenarios.size() > 1) groups.push_back("all");
  for (const auto& g : groups) {
    out << "\n## " << (g == "all" ? std::string("All scenarios") : g) << "\n\n";
    out << "| planner | success % | median time [s] | median length [m] | length / best | time / A* | length / A* "
           "| min clearance [m] | median waypoints | invalid |\n";
    out << "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const auto& s : result.summary) {
      if (s.scenario != g) continue;
      out << "| " << s.planner << " | " << shown(s.success_pct, 0) << " | " << shown(s.median_time_s, 4) << " | "
          << shown(s.median_length_m, 2) << " | " << shown(s.length_ratio_to_best, 3) << " | "
          << shown(s.time_ratio_to_astar, s.time_ratio_to_astar < 0.1 ? 4 : 2) << " | " << shown(s.length_ratio_to_astar, 3) << " | "
          << shown(s.min_clearance_m, 3) << " | " << shown(s.median_waypoints, 0) << " | " << s.invalid << " |\n";
    }
    for (const auto& t : result.targets) {
      if (t.scenario != g) continue;
      out << "\nTarget (ours at least as short as the best OMPL planner's median path at one tenth of its time): "
          << (t.holds() ? "**holds**" : "**does not hold**") << ". Ours: " << t.ours << ", "
          << shown(t.ours_length_m, 2) << " m in " << shown(t.ours_time_s, 4) << " s; best OMPL: " << t.best_ompl
          << ", " << shown(t.ompl_length_m, 2) << " m in " << shown(t.ompl_time_s, 4) << " s (as short: "
          << (t.as_short ? "yes" : "no") << ", a tenth of the time: " << (t.tenth_time ? "yes" : "no")
          << "; leg by leg, ours / theirs = " << shown(t.leg_length_ratio, 3) << ").\n";
    }
  }
  out << "\n## Legs\n\n| leg | scenario | start | goal | straight [m] | feasible on the grid |\n|---:|---|---|---|---:|---|\n";
  for (const auto& leg : result.legs) {
    out << "| " << leg.id << " | " << result.scenarios[static_cast<std::size_t>(leg.scenario)] << " | "
        << formatPoint(leg.start) << " | " << formatPoint(leg.goal) << " | " << shown(leg.straight_m, 2) << " | "
        << (leg.feasible ? "yes" : "no") << " |\n";
  }
  return out.str();
}

render::Figure benchPlot(const BenchResult& result) {
  std::map<int, double> shortest;
  for (const auto& r : result.runs) {
    if (!r.solved) continue;
    const auto it = shortest.find(r.leg);
    if (it == shortest.end() || r.length_m < it->second) shortest[r.leg] = r.length_m;
  }
  std::vector<render::Series> series;
  for (const auto& name : result.planners) {
    render::Series s;
    s.label = name;
    for (const auto& r : result.runs) {
      if (r.planner != name || !r.solved || !(shortest[r.leg] > 0.0)) continue;
      s.x.push_back(r.length_m / shortest[r.leg]);
      s.y.push_back(std::max(r.time_s + r.simplify_time_s, 1e-6));
    }
    series.push_back(std::move(s));
  }
  render::PlotOptions o;
  o.title = "uavip bench: planning time vs path length (solved runs, " + std::to_string(result.legs.size()) + " legs)";
  o.x.label = "path length / shortest path found on the leg";
  o.y = {"time: solve + simplification [s]", render::Scale::Log10, std::nullopt, std::nullopt};
  o.legend = render::Corner::TopRight;
  return render::plot(series, o);
}

}  // namespace uavip::app
