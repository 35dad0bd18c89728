#pragma once
/// \file
/// Statistics of `uavip bench` runs: per-planner summaries (success, medians, ratios
/// to the best planner and to the paper's A* leg by leg) and the issue-4 target check.
/// Pure functions of the runs; bench/runner.h calls them, bench/report.h writes them.

#include <optional>
#include <string>
#include <vector>

#include "uavip/bench/records.h"

namespace uavip::bench {

/// One summary per planner of `planners` (in that order) over `runs`, labelled
/// `scenario`. Lengths and times are those of solved runs; ratios are medians over
/// legs of per-leg median lengths (nan when no leg is comparable).
std::vector<PlannerSummary> summarise(const std::string& scenario,
                                      const std::vector<BenchRun>& runs,
                                      const std::vector<std::string>& planners);

/// Our best A* against the best OMPL planner on one scenario; nullopt unless both
/// sides solved at least one run.
std::optional<TargetCheck> checkTarget(const std::string& scenario,
                                       const std::vector<BenchRun>& runs,
                                       const std::vector<PlannerSummary>& summary);

}  // namespace uavip::bench
