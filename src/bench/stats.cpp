#include "uavip/bench/stats.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "uavip/core/math.h"
#include "uavip/planning/planner_table.h"

namespace uavip::bench {
namespace {

/// Our planners: the grid A* rows of the planner table (the paper's and its variants).
bool isOurs(const std::string& planner) {
  const planning::PlannerSpec* spec = planning::findPlanner(planner);
  return spec != nullptr && spec->gridSearch();
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

}  // namespace

std::vector<PlannerSummary> summarise(const std::string& scenario,
                                      const std::vector<BenchRun>& runs,
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
    s.success_pct =
        s.runs > 0 ? 100.0 * static_cast<double>(s.solved) / static_cast<double>(s.runs) : 0.0;
    s.median_time_s = median(times);
    s.median_length_m = median(lengths);
    s.median_waypoints = median(waypoints);
    std::vector<double> to_best;
    const auto it = m.find(planner);
    if (it != m.end()) {
      for (const auto& [leg, len] : it->second) to_best.push_back(len / best[leg]);
    }
    s.length_ratio_to_best = median(to_best);
    s.length_ratio_to_astar = legRatio(m, planner, planning::kPaperPlanner);
    s.time_ratio_to_astar = kNan;
    out.push_back(s);
  }
  for (auto& s : out) {
    const auto a = std::find_if(out.begin(), out.end(), [](const PlannerSummary& p) {
      return p.planner == planning::kPaperPlanner;
    });
    if (a != out.end() && a->median_time_s > 0.0)
      s.time_ratio_to_astar = s.median_time_s / a->median_time_s;
  }
  return out;
}

std::optional<TargetCheck> checkTarget(const std::string& scenario,
                                       const std::vector<BenchRun>& runs,
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

}  // namespace uavip::bench
