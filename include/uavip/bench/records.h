#pragma once
/// \file
/// The bench's records: options, legs, runs, per-planner summaries, target checks
/// and the whole result (the model: ompl::tools::Benchmark's experiment records).
/// bench/runner.h fills them, bench/stats.h summarises, bench/report.h writes.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "uavip/core/types.h"

namespace uavip::bench {

/// Options of a benchmark.
struct BenchOptions {
  std::vector<std::string> planners;  ///< registry names; empty = every registered planner
  int runs{5};                        ///< runs per planner and leg
  double time_limit_s{1.0};           ///< budget per run of an OMPL planner [s]
  bool simplify{true};                ///< simplify every path (OMPL PathSimplifier, no B-spline)
  std::uint32_t seed{1};  ///< OMPL's global seed (first seed of the process wins) and leg sampling
  /// Most planning time the bench may take in the worst case (every run using its whole
  /// time limit): legs × planners × runs × time_limit_s, checked before planning [s].
  double max_total_s{4.0 * 3600.0};

  /// Throws InputError naming the bad option (unknown planner, runs not in [1, 10000],
  /// limit not in (0, 3600] s, max_total_s <= 0).
  void validate() const;
};

/// One benchmark leg.
struct BenchLeg {
  int id{0};                 ///< global leg id (the log's `leg id`)
  int scenario{0};           ///< index into BenchResult::scenarios
  Vec3 start{Vec3::Zero()};  ///< [m]
  Vec3 goal{Vec3::Zero()};   ///< [m]
  bool explicit_leg{false};  ///< from the scenario's `bench.legs` (else sampled between stops)
  bool feasible{false};      ///< both ends free and 26-connected on the grid (the A* can solve it)
  double straight_m{0.0};    ///< |goal − start| [m]
};

/// One run of one planner on one leg.
struct BenchRun {
  int leg{0};  ///< BenchLeg::id
  int scenario{0};
  std::string planner;    ///< registry name
  std::string ompl_name;  ///< e.g. "RRTConnect" (the log's planner is geometric_<ompl_name>)
  int status{0};          ///< index into planners::plannerStatusNames()
  bool solved{false};     ///< exact solution
  bool approximate{false};
  double time_s{0.0};           ///< solve time [s]
  double simplify_time_s{0.0};  ///< [s]
  double raw_length_m{0.0};     ///< the planner's path [m]
  double length_m{0.0};         ///< the final (simplified) path [m]
  std::size_t raw_waypoints{0};
  std::size_t waypoints{0};  ///< vertices of the final path
  std::size_t graph_states{0};
  std::size_t graph_motions{0};
  double min_clearance_m{
      0.0};           ///< final path vs the clean cloud (PathValidator) [m]; nan if unsolved
  bool valid{false};  ///< validator verdict on the final path (false if unsolved)
};

/// Summary of one planner on one scenario (or on every scenario: scenario = "all").
struct PlannerSummary {
  std::string scenario;
  std::string planner;
  std::size_t runs{0};
  std::size_t solved{0};
  double success_pct{0.0};
  double median_time_s{0.0};    ///< solve + simplification of solved runs [s]
  double median_length_m{0.0};  ///< final path of solved runs [m]
  double length_ratio_to_best{
      0.0};  ///< median over legs of (median length / best planner's median length)
  double time_ratio_to_astar{
      0.0};  ///< median time / the paper A*'s median time (nan without astar)
  double length_ratio_to_astar{0.0};  ///< median over legs of length / the A*'s (nan without astar)
  double min_clearance_m{0.0};        ///< smallest clearance over solved runs [m]
  double median_waypoints{0.0};
  std::size_t invalid{0};  ///< solved runs the validator rejected
};

/// The planner target on one scenario: the grid A* must plan legs as short as the
/// best OMPL planner in a tenth of its time. Our best configuration (astar or
/// astar-euclid) against the best OMPL planner, each chosen by success, then by the
/// shortest median length; "as short" compares the two medians (1 mm tolerance).
struct TargetCheck {
  std::string scenario;
  std::string ours;       ///< our planner with the shortest median length
  std::string best_ompl;  ///< OMPL planner with the shortest median length
  double ours_length_m{0.0}, ompl_length_m{0.0};
  double ours_time_s{0.0}, ompl_time_s{0.0};
  double leg_length_ratio{0.0};  ///< median over legs of ours' / theirs' per-leg median length
  bool as_short{false};    ///< leg_length_ratio ≤ 1 (per-leg medians), with at least its success
  bool tenth_time{false};  ///< ours_time ≤ ompl_time / 10
  bool holds() const { return as_short && tenth_time; }
};

/// Everything a benchmark measured.
struct BenchResult {
  std::vector<std::string> scenarios;  ///< scenario names, in input order
  std::vector<BenchLeg> legs;
  std::vector<BenchRun> runs;           ///< ordered by planner, then scenario, leg, run
  std::vector<std::string> planners;    ///< registry names, in order
  std::vector<PlannerSummary> summary;  ///< per scenario and planner, then "all"
  std::vector<TargetCheck> targets;     ///< per scenario (when astar* and an OMPL planner ran)
  BenchOptions options;
  double total_s{0.0};     ///< wall time of the whole benchmark [s]
  double planning_s{0.0};  ///< wall time spent in the runs [s]
  std::string start_time;  ///< local time the benchmark started, "YYYY-MM-DD HH:MM:SS"
};

}  // namespace uavip::bench
