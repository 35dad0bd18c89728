#pragma once
/// \file
/// `uavip bench`: the paper's grid A* (§II-G) and OMPL planners side by side
/// on the legs of benchmark scenarios, all through the ompl::base::Planner interface
/// (planners/harness.h). For each scenario: sense, stages 3–5, stage 6 for every
/// surface, the inflated grid over the cloud, the stops and the legs; then every leg
/// with every planner `runs` times, then the statistics (bench/stats.h). The records
/// are bench/records.h; their four report formats (OMPL log, CSV, Markdown, plot)
/// are written by bench/report.h. Nothing here prints.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "planners/registry.h"
#include "uavip/app/pipeline.h"
#include "uavip/app/scenario.h"
#include "uavip/bench/records.h"

namespace uavip::bench {

/// Each surface's photo-stop positions (stage 6, planFlightStrategy), in scene order
/// [m]: what sampleLegs draws its legs between.
std::vector<PointList> stopsBySurface(const Scene& scene,
                                      const coverage::CoverageOptions& coverage);

/// The legs of a scenario: its `bench.legs`, or up to `bench.max_legs` legs sampled
/// deterministically (seeded) between free photo stops of different surfaces whose
/// straight segment is blocked, keeping only legs the grid allows. `stops_by_surface`
/// are the stop positions of each surface [m].
std::vector<std::pair<Vec3, Vec3>> sampleLegs(const world::VoxelGrid& grid,
                                              const std::vector<PointList>& stops_by_surface,
                                              int max_legs, std::uint32_t seed);

/// Runs the benchmark. Throws InputError for bad options or scenarios.
BenchResult runBench(const std::vector<app::Scenario>& scenarios, const BenchOptions& options,
                     const app::Progress& progress = {});

}  // namespace uavip::bench
