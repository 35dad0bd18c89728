#pragma once
/// \file
/// The one writer of the bench's four report formats: the OMPL benchmark log that
/// `ompl_benchmark_statistics LOG -d DB` loads (Planner Arena), a CSV and a Markdown
/// summary per scenario and planner, and a plot of time against path length.

#include <string>

#include "uavip/bench/records.h"
#include "uavip/render/figure.h"

namespace uavip::bench {

/// The OMPL benchmark log (format of ompl::tools::Benchmark, one experiment; the
/// first line is "OMPL version <OMPL's version>" since Debian's OMPL_VERSION is empty).
std::string benchLog(const BenchResult& result, const std::string& experiment_name,
                     const std::string& host);

/// One CSV row per summary entry, with a header.
std::string benchCsv(const BenchResult& result);

/// The Markdown summary: the table per scenario, ratios to the A*, the target check,
/// and the legs.
std::string benchMarkdown(const BenchResult& result);

/// Time (solve + simplification, log axis) against path length relative to the
/// shortest solved run of the same leg, one series per planner (solved runs only).
render::Figure benchPlot(const BenchResult& result);

}  // namespace uavip::bench
