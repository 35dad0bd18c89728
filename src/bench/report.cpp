#include "uavip/bench/report.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "planners/harness.h"
#include "planners/registry.h"
#include "uavip/core/error.h"
#include "uavip/core/text.h"
#include "uavip/render/plot.h"

#ifndef UAVIP_VERSION
#define UAVIP_VERSION "dev"
#endif

namespace uavip::bench {
namespace {

/// A report cell: the number with 10 significant digits, blank when missing (nan/inf:
/// NULL in SQLite).
std::string cell(double v) { return std::isfinite(v) ? formatNumber(v, 10) : ""; }

/// A table entry with `decimals` decimals, "-" when missing (nan/inf).
std::string shown(double v, int decimals) {
  return std::isfinite(v) ? formatFixed(v, decimals) : "-";
}

}  // namespace

std::string benchLog(const BenchResult& result, const std::string& experiment_name,
                     const std::string& host) {
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
  out << "uavip bench: every planner through the ompl::base::Planner interface on R^3 over the "
         "inflated grid\n";
  for (std::size_t s = 0; s < result.scenarios.size(); ++s)
    out << "scenario " << s << ": " << result.scenarios[s] << "\n";
  for (const auto& leg : result.legs) {
    out << "leg " << leg.id << " (scenario " << leg.scenario << "): " << formatPoint(leg.start)
        << " -> " << formatPoint(leg.goal) << (leg.feasible ? "" : " [infeasible on the grid]")
        << "\n";
  }
  out << "|>>>\n";
  out << "<<<|\n|>>>\n";  // CPU info: not collected
  out << result.options.seed << " is the random seed\n";
  out << cell(result.options.time_limit_s) << " seconds per run\n";
  out << "0 MB per run\n";
  out << static_cast<std::size_t>(result.options.runs) * result.legs.size()
      << " runs per planner\n";
  out << cell(result.total_s) << " seconds spent to collect the data\n";
  out << "1 enum type\n";
  out << "status";
  for (const auto& s : planners::plannerStatusNames()) out << "|" << s;
  out << "\n";
  out << result.planners.size() << " planners\n";
  static const char* kProperties[] = {"approximate solution BOOLEAN",
                                      "graph motions INTEGER",
                                      "graph states INTEGER",
                                      "leg id INTEGER",
                                      "min clearance REAL",
                                      "raw waypoints INTEGER",
                                      "scenario id INTEGER",
                                      "simplification time REAL",
                                      "simplified solution length REAL",
                                      "solution length REAL",
                                      "solved BOOLEAN",
                                      "status ENUM",
                                      "time REAL",
                                      "validator verdict BOOLEAN",
                                      "waypoints INTEGER"};
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
      out << (r->approximate ? 1 : 0) << "; " << r->graph_motions << "; " << r->graph_states << "; "
          << r->leg << "; " << (ok ? cell(r->min_clearance_m) : "") << "; " << r->raw_waypoints
          << "; " << r->scenario << "; " << cell(r->simplify_time_s) << "; "
          << (ok ? cell(r->length_m) : "") << "; " << (ok ? cell(r->raw_length_m) : "") << "; "
          << (ok ? 1 : 0) << "; " << r->status << "; " << cell(r->time_s) << "; "
          << (r->valid ? 1 : 0) << "; " << r->waypoints << "; \n";
    }
    out << ".\n";
  }
  return out.str();
}

std::string benchCsv(const BenchResult& result) {
  std::ostringstream out;
  out << "scenario,planner,runs,solved,success_pct,median_time_s,median_length_m,length_ratio_to_"
         "best,"
         "time_ratio_to_astar,length_ratio_to_astar,min_clearance_m,median_waypoints,invalid\n";
  for (const auto& s : result.summary) {
    out << s.scenario << "," << s.planner << "," << s.runs << "," << s.solved << ","
        << cell(s.success_pct) << "," << cell(s.median_time_s) << "," << cell(s.median_length_m)
        << "," << cell(s.length_ratio_to_best) << "," << cell(s.time_ratio_to_astar) << ","
        << cell(s.length_ratio_to_astar) << "," << cell(s.min_clearance_m) << ","
        << cell(s.median_waypoints) << "," << s.invalid << "\n";
  }
  return out.str();
}

std::string benchMarkdown(const BenchResult& result) {
  std::ostringstream out;
  out << "# uavip bench\n\n";
  out << result.scenarios.size() << " scenario(s), " << result.legs.size() << " legs, "
      << result.planners.size() << " planners, " << result.options.runs
      << " runs per planner and leg, time limit " << shown(result.options.time_limit_s, 2)
      << " s, simplification " << (result.options.simplify ? "on" : "off") << ", seed "
      << result.options.seed << "; total " << shown(result.total_s, 1) << " s.\n\n";
  out << "Time = solve + simplification of solved runs. Length and clearance are those of the "
         "final path. "
         "Ratios to the best planner and to the A* are medians over legs of per-leg median lengths "
         "(legs both solved). The anytime OMPL planners (RRT*, Informed RRT*, BIT*, ABIT*, AIT*, "
         "PRM*, LazyPRM*) "
         "use their whole budget.\n";
  std::vector<std::string> groups = result.scenarios;
  if (result.scenarios.size() > 1) groups.push_back("all");
  for (const auto& g : groups) {
    out << "\n## " << (g == "all" ? std::string("All scenarios") : g) << "\n\n";
    out << "| planner | success % | median time [s] | median length [m] | length / best | time / "
           "A* | length / A* "
           "| min clearance [m] | median waypoints | invalid |\n";
    out << "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const auto& s : result.summary) {
      if (s.scenario != g) continue;
      out << "| " << s.planner << " | " << shown(s.success_pct, 0) << " | "
          << shown(s.median_time_s, 4) << " | " << shown(s.median_length_m, 2) << " | "
          << shown(s.length_ratio_to_best, 3) << " | "
          << shown(s.time_ratio_to_astar, s.time_ratio_to_astar < 0.1 ? 4 : 2) << " | "
          << shown(s.length_ratio_to_astar, 3) << " | " << shown(s.min_clearance_m, 3) << " | "
          << shown(s.median_waypoints, 0) << " | " << s.invalid << " |\n";
    }
    for (const auto& t : result.targets) {
      if (t.scenario != g) continue;
      out << "\nTarget (ours at least as short as the best OMPL planner's median path at one tenth "
             "of its time): "
          << (t.holds() ? "**holds**" : "**does not hold**") << ". Ours: " << t.ours << ", "
          << shown(t.ours_length_m, 2) << " m in " << shown(t.ours_time_s, 4)
          << " s; best OMPL: " << t.best_ompl << ", " << shown(t.ompl_length_m, 2) << " m in "
          << shown(t.ompl_time_s, 4) << " s (as short: " << (t.as_short ? "yes" : "no")
          << ", a tenth of the time: " << (t.tenth_time ? "yes" : "no")
          << "; leg by leg, ours / theirs = " << shown(t.leg_length_ratio, 3) << ").\n";
    }
  }
  out << "\n## Legs\n\n| leg | scenario | start | goal | straight [m] | feasible on the grid "
         "|\n|---:|---|---|---|---:|---|\n";
  for (const auto& leg : result.legs) {
    out << "| " << leg.id << " | " << result.scenarios[static_cast<std::size_t>(leg.scenario)]
        << " | " << formatPoint(leg.start) << " | " << formatPoint(leg.goal) << " | "
        << shown(leg.straight_m, 2) << " | " << (leg.feasible ? "yes" : "no") << " |\n";
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
  o.title = "uavip bench: planning time vs path length (solved runs, " +
            std::to_string(result.legs.size()) + " legs)";
  o.x.label = "path length / shortest path found on the leg";
  o.y = {"time: solve + simplification [s]", render::Scale::Log10, std::nullopt, std::nullopt};
  o.legend = render::Corner::TopRight;
  return render::plot(series, o);
}

}  // namespace uavip::bench
