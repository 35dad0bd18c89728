// The ordered flight (planning/flight_planner.h) on whole structures: the tour's
// length with the solved order against the naive order (surfaces by id, each flown
// forward) and against the lower bound (planning/tour.h), split into what is flown
// along the surfaces and the connecting legs; the time to order (solves and the
// legs they plan) and the whole flight step; sorties and duration. Each scenario is
// sensed and detected once, then planned RUNS times (median times).
// Usage: uavip_flight_bench [SCENARIO.yaml ...] [--runs R]
//        (default scenarios/single_cube.yaml scenarios/bridge.yaml, R = 3)
// Numbers go in benchmarks/README.md, never in tests.

#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

#include "bench_util.h"
#include "command_line.h"
#include "uavip/app/pipeline.h"
#include "uavip/app/scenario.h"
#include "uavip/core/error.h"
#include "uavip/io/cloud_io.h"

namespace {

using uavip::bench_util::median;
using uavip::bench_util::peakRssMiB;

double percentAbove(double value, double bound) {
  return bound > 0.0 ? 100.0 * (value / bound - 1.0) : 0.0;
}

/// One scenario's row: sensed and detected once, the flight planned `runs` times.
void benchScenario(const std::string& path, int runs) {
  const uavip::app::Scenario sc = uavip::app::loadScenario(path);
  const auto raw = uavip::app::sense(sc);
  const auto d = uavip::app::detect(raw, sc.config, uavip::app::measure(raw, &sc));
  const auto ids = uavip::app::selectSurfaces(d.scene, "all");
  auto config = d.resolved.config;
  config.flight.compare_naive = true;
  std::vector<double> order_s, validate_s, flight_s;
  uavip::planning::FlightPlan f;
  std::size_t stops = 0;
  for (int r = 0; r < runs; ++r) {
    const auto p = uavip::app::plan(d.scene, config, ids);
    f = p.flight;
    order_s.push_back(f.order_seconds);
    validate_s.push_back(f.validate_seconds);
    flight_s.push_back(f.seconds);
    stops = 0;
    for (const auto& s : f.sorties) stops += s.stops.size();
  }
  if (f.status != uavip::planning::FlightPlan::Status::Ok) {
    std::printf("| %s | flight %s: %s |\n", sc.name.c_str(), uavip::planning::toString(f.status),
                f.reason.c_str());
    return;
  }
  const double inner = f.inner_length_m;
  std::printf(
      "| %s | %zu | %zu | %.1f | %.1f | %.1f | %.1f %% | %.1f / %.1f / %.1f (%.1f %% above) | "
      "%s | %zu | "
      "%.3f | %.3f | %.3f | %zu | %.1f |\n",
      sc.name.c_str(), f.order.size(), stops, f.tour_length_m, f.naive_length_m, f.lower_bound_m,
      percentAbove(f.tour_length_m, f.lower_bound_m), f.tour_length_m - inner,
      f.naive_length_m - inner, f.lower_bound_m - inner,
      percentAbove(f.tour_length_m - inner, f.lower_bound_m - inner), f.exact_order ? "yes" : "no",
      f.planned_legs, median(order_s), median(validate_s), median(flight_s), f.sorties.size(),
      f.duration_s / 60.0);
}

}  // namespace

int main(int argc, char** argv) {
  uavip::bench_util::prepareProcess();
  const auto args = uavip::bench_util::parseCommandLine(
      argc, argv, {"--runs"}, {"scenarios/single_cube.yaml", "scenarios/bridge.yaml"});
  const int runs = args.count("--runs", 3);
  try {
    std::printf(
        "| scenario | surfaces flown | stops | tour m (solved) | by id m | lower bound m | solved "
        "above bound | "
        "connecting legs solved / by id / bound m | optimal | legs planned | order s | validation "
        "s | flight step s | "
        "sorties | duration min "
        "|\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (const auto& path : args.paths) benchScenario(path, runs);
    std::printf("\npeak RSS %.1f MiB; %d runs per scenario (median times)\n", peakRssMiB(), runs);
  } catch (const uavip::InputError& e) {
    std::cerr << "uavip_flight_bench: error: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
