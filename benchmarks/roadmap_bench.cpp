// What an OMPL planner gains from planning leg after leg on one grid (one
// SpaceInformation and planner per grid, clearQuery() between legs; planners/
// ompl_planners.h, OmplPlanner) against a fresh space and planner per leg (the
// harness's runPlannerOnce, as `uavip bench` runs them). Multi-query planners
// (PRM*, LazyPRM*) keep their roadmap; the others are cleared, so they are the
// control. Each scenario is sensed and detected once; the legs are sampled between
// photo stops of different surfaces (bench::sampleLegs), the same legs for every
// planner and mode, planned in order with the same budget per leg.
// Usage: uavip_roadmap_bench [SCENARIO.yaml ...] [--legs N] [--time S]
//        (default scenarios/bench_cluttered.yaml scenarios/bridge.yaml, N = 30, S = 0.2)
// Numbers go in benchmarks/README.md, never in tests.

#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>
#include <utility>
#include <vector>

#include "bench_util.h"
#include "command_line.h"
#include "planners/harness.h"
#include "planners/registry.h"
#include "uavip/app/pipeline.h"
#include "uavip/app/scenario.h"
#include "uavip/bench/runner.h"
#include "uavip/core/error.h"
#include "uavip/core/stopwatch.h"
#include "uavip/io/cloud_io.h"

namespace {

using uavip::Vec3;
using uavip::bench_util::median;

/// One planner's legs in one mode.
struct ModeRun {
  std::vector<bool> solved;
  std::vector<double> length_m;
  std::vector<double> seconds;
  std::size_t last_graph_states{0};
};

/// The legs of a scenario's grid, as `uavip bench` samples them.
struct Legs {
  uavip::world::VoxelGrid grid;
  std::vector<std::pair<Vec3, Vec3>> legs;
};

Legs prepare(const uavip::app::Scenario& sc, int max_legs) {
  const auto raw = uavip::app::sense(sc);
  const auto d = uavip::app::detect(raw, sc.config, uavip::app::measure(raw, &sc));
  const auto stops_by_surface = uavip::bench::stopsBySurface(d.scene, d.resolved.config.coverage);
  uavip::PointList extra;
  for (const auto& stops : stops_by_surface) extra.insert(extra.end(), stops.begin(), stops.end());
  Legs out;
  out.grid = uavip::world::VoxelGrid::build(d.scene.cloud, extra, d.resolved.config.gridOptions());
  out.legs = uavip::bench::sampleLegs(out.grid, stops_by_surface, max_legs, 1);
  return out;
}

ModeRun runFresh(const std::string& name, const Legs& l,
                 const uavip::planners::PlannerSettings& settings) {
  ModeRun m;
  for (const auto& [a, b] : l.legs) {
    const auto t0 = uavip::SteadyClock::now();
    const auto r = uavip::planners::runPlannerOnce(name, l.grid, a, b, settings);
    m.seconds.push_back(uavip::secondsSince(t0));
    m.solved.push_back(r.solved);
    m.length_m.push_back(r.length_m);
    m.last_graph_states = r.graph_states;
  }
  return m;
}

ModeRun runKept(const std::string& name, const Legs& l,
                const uavip::planners::PlannerSettings& settings) {
  ModeRun m;
  const auto planner = uavip::planners::makePlanner(name, settings);
  for (const auto& [a, b] : l.legs) {
    const auto r = planner->plan(l.grid, a, b);
    m.seconds.push_back(r.seconds);
    m.solved.push_back(r.solved());
    m.length_m.push_back(r.cost);
    m.last_graph_states = r.graph_states;
  }
  return m;
}

}  // namespace

int main(int argc, char** argv) {
  uavip::bench_util::prepareProcess();
  const auto args = uavip::bench_util::parseCommandLine(
      argc, argv, {"--legs", "--time"},
      {"scenarios/bench_cluttered.yaml", "scenarios/bridge.yaml"});
  const int max_legs = args.count("--legs", 30);
  const double time_s = args.number("--time", 0.2);
  try {
    uavip::planners::PlannerSettings settings;
    settings.time_limit_s = time_s;
    settings.validate("--time");
    std::printf(
        "| scenario | planner | legs | solved: fresh / kept | length of legs both solved, m: fresh "
        "/ kept (kept/fresh) "
        "| median s per leg: fresh / kept | graph states after the last leg: fresh / kept |\n"
        "|---|---|---|---|---|---|---|\n");
    for (const auto& path : args.paths) {
      const uavip::app::Scenario sc = uavip::app::loadScenario(path);
      const Legs l = prepare(sc, max_legs);
      for (const char* name : {"prmstar", "lazyprmstar", "rrtstar"}) {
        const ModeRun fresh = runFresh(name, l, settings);
        const ModeRun kept = runKept(name, l, settings);
        int solved_fresh = 0, solved_kept = 0;
        double len_fresh = 0.0, len_kept = 0.0;
        for (std::size_t i = 0; i < l.legs.size(); ++i) {
          solved_fresh += fresh.solved[i];
          solved_kept += kept.solved[i];
          if (fresh.solved[i] && kept.solved[i]) {
            len_fresh += fresh.length_m[i];
            len_kept += kept.length_m[i];
          }
        }
        std::printf("| %s | %s | %zu | %d / %d | %.1f / %.1f (%.3f) | %.3f / %.3f | %zu / %zu |\n",
                    sc.name.c_str(), name, l.legs.size(), solved_fresh, solved_kept, len_fresh,
                    len_kept, len_fresh > 0.0 ? len_kept / len_fresh : 0.0, median(fresh.seconds),
                    median(kept.seconds), fresh.last_graph_states, kept.last_graph_states);
        std::fflush(stdout);
      }
    }
    std::printf("\nbudget %.3f s per leg; legs sampled with seed 1\n", time_s);
  } catch (const uavip::InputError& e) {
    std::cerr << "uavip_roadmap_bench: error: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
