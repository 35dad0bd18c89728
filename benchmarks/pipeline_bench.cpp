// Per-stage wall time (median of N runs) and peak memory of the pipeline on a
// scenario. Usage: uavip_pipeline_bench [SCENARIO.yaml] [RUNS]
// Prints a Markdown table; numbers go in benchmarks/README.md, never in tests.

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "bench_util.h"
#include "uavip/app/pipeline.h"
#include "uavip/app/scenario.h"
#include "uavip/core/error.h"
#include "uavip/core/stopwatch.h"
#include "uavip/io/cloud_io.h"

namespace {

using uavip::bench_util::median;
using uavip::bench_util::peakRssMiB;

}  // namespace

int main(int argc, char** argv) {
  const auto [path, runs] =
      uavip::bench_util::startBench(argc, argv, "scenarios/single_cube.yaml", 5);
  try {
    const uavip::app::Scenario sc = uavip::app::loadScenario(path);
    std::vector<double> sense, pre, perc, cov, grid, planning, total;
    std::size_t raw = 0, clean = 0, surfaces = 0, stops = 0, waypoints = 0, raw_waypoints = 0,
                voxels = 0;
    for (int i = 0; i < runs; ++i) {
      const auto t0 = uavip::SteadyClock::now();
      const uavip::PointList cloud = uavip::app::sense(sc);
      const double t_sense = uavip::secondsSince(t0);
      const auto d = uavip::app::detect(cloud, sc.config, uavip::app::measure(cloud, &sc));
      const auto p =
          uavip::app::plan(d.scene, d.resolved.config, uavip::app::selectSurfaces(d.scene, "all"));
      total.push_back(uavip::secondsSince(t0) - t_sense);
      sense.push_back(t_sense);
      pre.push_back(d.times.preprocess_s);
      perc.push_back(d.times.perception_s);
      cov.push_back(p.times.coverage_s);
      grid.push_back(p.times.grid_s);
      planning.push_back(p.times.planning_s);
      raw = cloud.size();
      clean = d.scene.cloud.size();
      surfaces = d.scene.surfaces.size();
      voxels = p.grid_voxels;
      stops = waypoints = raw_waypoints = 0;
      for (const auto& m : p.missions) {
        stops += m.strategy.stops.size();
        waypoints += m.waypoints.size();
        raw_waypoints += m.raw_waypoint_count;
      }
    }
    std::printf("scenario %s, %d runs (median wall time), peak RSS %.1f MiB\n", sc.name.c_str(),
                runs, peakRssMiB());
    std::printf(
        "points %zu raw -> %zu clean; %zu surfaces; grid %zu voxels; %zu stops, %zu waypoints (%zu "
        "voxel steps)\n\n",
        raw, clean, surfaces, voxels, stops, waypoints, raw_waypoints);
    std::printf("| stage | median s |\n|---|---|\n");
    std::printf("| sense (sim, excluded from total) | %.3f |\n", median(sense));
    std::printf("| 3 preprocess | %.3f |\n| 4-5 perception | %.3f |\n| 6 coverage | %.3f |\n",
                median(pre), median(perc), median(cov));
    std::printf(
        "| 7 grid + validator index | %.3f |\n| 7 planning | %.3f |\n| total (3-7) | %.3f |\n",
        median(grid), median(planning), median(total));
  } catch (const uavip::InputError& e) {
    std::cerr << "uavip_pipeline_bench: error: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
