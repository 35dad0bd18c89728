// The bridge pipeline from raw scans (target: stages 1-7 under 3 s): simulate once (excluded), then
// per run: stage 1 assembly, stage 2 registration, stage 3 preprocess, stages 4-5 perception, grid,
// stages 6-7 planning, with wall time per stage (median of N runs), peak memory and the accuracy
// against the truth; then stage 1 with and without the IMU prior (the paper's customisation) and
// with PCL's ICP. Usage: uavip_bridge_bench [SCENARIO.yaml] [RUNS]   (default
// scenarios/bridge.yaml, 3) Numbers go in benchmarks/README.md, never in tests.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

#include "bench_util.h"
#include "uavip/app/assemble.h"
#include "uavip/app/assemble_truth.h"
#include "uavip/app/pipeline.h"
#include "uavip/app/scenario.h"
#include "uavip/core/error.h"
#include "uavip/core/stopwatch.h"
#include "uavip/io/cloud_io.h"
#include "uavip/scan/station_assembler.h"
#include "uavip/sim/scanner_sim.h"

namespace {

using uavip::bench_util::median;
using uavip::bench_util::peakRssMiB;

/// Wall times per stage, one entry per run [s], and what the last run produced.
struct Timings {
  std::vector<double> asm_s, reg_s, measure_s, pre_s, perc_s, grid_s, cov_s, plan_s, flight_s,
      total_s;
  std::size_t clean = 0, surfaces = 0, stops = 0, waypoints = 0;
};

/// Stages 1-7 on the simulated log `s`, `runs` times.
Timings timedRuns(const uavip::app::Scenario& sc, const uavip::sim::SimulatedLog& s, int runs) {
  Timings t;
  for (int i = 0; i < runs; ++i) {
    // Timed without the truth: scoring the cloud and the drift against the
    // simulator is evaluation, not a stage; one scored run follows the loop.
    const auto t0 = uavip::SteadyClock::now();
    uavip::app::AssembleResult a = uavip::app::assemble(s.log, {});
    for (auto& p : a.cloud) p += s.origin_m;  // scenario coordinates, like `uavip run`
    const auto tm = uavip::SteadyClock::now();
    uavip::app::CloudIndex index;  // the kd-tree is timed with the measurement
    const uavip::preprocess::CloudStats stats = uavip::app::measure(a.cloud, &sc, &index);
    t.measure_s.push_back(uavip::secondsSince(tm));
    const auto d = uavip::app::detect(a.cloud, sc.config, stats, {}, index);
    const auto p =
        uavip::app::plan(d.scene, d.resolved.config, uavip::app::selectSurfaces(d.scene, "all"));
    t.total_s.push_back(uavip::secondsSince(t0));
    t.asm_s.push_back(a.assembly_s);
    t.reg_s.push_back(a.registration_s);
    t.pre_s.push_back(d.times.preprocess_s);
    t.perc_s.push_back(d.times.perception_s);
    t.grid_s.push_back(p.times.grid_s);
    t.cov_s.push_back(p.times.coverage_s);
    t.plan_s.push_back(p.times.planning_s);
    t.flight_s.push_back(p.times.flight_s);
    t.clean = d.scene.cloud.size();
    t.surfaces = d.scene.surfaces.size();
    t.stops = t.waypoints = 0;
    for (const auto& m : p.missions) {
      t.stops += m.strategy.stops.size();
      t.waypoints += m.waypoints.size();
    }
  }
  return t;
}

/// The median wall time of every stage.
void printStages(const Timings& t) {
  std::printf("| stage | median s |\n|---|---|\n");
  std::printf(
      "| 1 assembly | %.3f |\n| 2 registration | %.3f |\n| cloud measurement (auto parameters) | "
      "%.3f |\n"
      "| 3 preprocess | %.3f |\n",
      median(t.asm_s), median(t.reg_s), median(t.measure_s), median(t.pre_s));
  std::printf(
      "| 4-5 perception | %.3f |\n| 6 coverage | %.3f |\n| 7 grid | %.3f |\n| 7 planning | %.3f "
      "|\n"
      "| 7 flight (order, legs, sorties, validation) | %.3f |\n",
      median(t.perc_s), median(t.cov_s), median(t.grid_s), median(t.plan_s), median(t.flight_s));
  std::printf("| total (1-7, wall time of the whole run) | %.3f |\n\n", median(t.total_s));
}

/// Per station: stage 1's drift and stage 2's pose against the truth; the merged cloud
/// against the true surfaces.
void printStations(const uavip::app::AssembleResult& last) {
  std::printf(
      "| station | loop closure cm | drift max cm (true) | drift error max / rms cm | recorded "
      "pos err cm | "
      "registered pos err cm | stage 2 pairs fixing the weakest direction "
      "|\n|---|---|---|---|---|---|---|\n");
  for (const auto& st : last.stations) {
    char closure[32] = "n/a (unobservable)";
    if (st.loop_closure_m >= 0.0)
      std::snprintf(closure, sizeof closure, "%.1f", 100 * st.loop_closure_m);
    std::printf(
        "| %d | %s | %.1f (%.1f) | %.1f / %.1f | %.1f | %.1f | %.0f along (%.2f, %.2f, %.2f)%s "
        "|\n",
        st.id, closure, 100 * st.drift_max_m, 100 * st.true_drift_max_m.value_or(-0.01),
        100 * st.drift_error_max_m.value_or(-0.01), 100 * st.drift_error_rms_m.value_or(-0.01),
        100 * st.initial_pose_error_m.value_or(-0.01), 100 * st.pose_error_m.value_or(-0.01),
        st.registration_information.x(), st.weakest_direction.x(), st.weakest_direction.y(),
        st.weakest_direction.z(), st.position_observed ? "" : " (unobserved: GPS)");
  }
  if (last.rms_to_truth_m) {
    std::printf(
        "\nmerged cloud to the true surfaces: RMS %.2f cm, 95 %% %.2f cm (%zu points scored)\n",
        100 * *last.rms_to_truth_m, 100 * last.p95_to_truth_m.value_or(0.0), last.scored_points);
  }
}

/// Stage 1 variants: the paper's IMU prior vs plain ICP, point-to-line vs PCL.
void printVariants(const uavip::sim::SimulatedLog& s) {
  std::printf(
      "\n| stage 1 variant | ICP s (all stations) | mean iterations | drift error max / rms cm "
      "(worst station) |\n"
      "|---|---|---|---|\n");
  struct Variant {
    const char* name;
    bool prior;
    uavip::scan::IcpMethod icp;
  };
  const Variant variants[] = {
      {"IMU prior + point-to-line (default)", true, uavip::scan::IcpMethod::PointToLine2D},
      {"plain point-to-line (no IMU prior)", false, uavip::scan::IcpMethod::PointToLine2D},
      {"IMU prior + PCL ICP", true, uavip::scan::IcpMethod::PclPointToPoint},
      {"plain PCL ICP", false, uavip::scan::IcpMethod::PclPointToPoint}};
  for (const auto& v : variants) {
    uavip::scan::AssemblerOptions o;
    o.use_imu_prior = v.prior;
    o.icp = v.icp;
    double icp = 0.0, iters = 0.0, worst = 0.0, worst_rms = 0.0;
    for (std::size_t i = 0; i < s.log.stations.size(); ++i) {
      const auto c = uavip::scan::assembleStation(s.log, i, o);
      icp += c.stats.icp_s;
      iters += c.stats.mean_icp_iterations / static_cast<double>(s.log.stations.size());
      const auto& tp = s.truth.stations[i].horizontal_poses;
      double e_max = 0.0, e_sum = 0.0;
      for (std::size_t k = 0; k < c.poses.size() && k < tp.size(); ++k) {
        const double e = (c.poses[k].translation() - (tp[k].translation() - tp[0].translation()))
                             .head<2>()
                             .norm();
        e_max = std::max(e_max, e);
        e_sum += e * e;
      }
      worst = std::max(worst, e_max);
      worst_rms = std::max(
          worst_rms,
          std::sqrt(e_sum / static_cast<double>(std::max<std::size_t>(1, c.poses.size()))));
    }
    std::printf("| %s | %.3f | %.1f | %.1f / %.1f (xy) |\n", v.name, icp, iters, 100 * worst,
                100 * worst_rms);
  }
}

}  // namespace

int main(int argc, char** argv) {
  const auto [path, runs] = uavip::bench_util::startBench(argc, argv, "scenarios/bridge.yaml", 3);
  try {
    const uavip::app::Scenario sc = uavip::app::loadScenario(path);
    if (sc.sensing_mode != "scan") throw uavip::InputError(path + ": sensing.mode must be scan");
    const auto ts = uavip::SteadyClock::now();
    const uavip::sim::SimulatedLog s = uavip::sim::simulateScans(sc.world, sc.scan);
    const double sim_s = uavip::secondsSince(ts);
    const uavip::sim::WorldModel world = uavip::app::worldInLogFrame(sc.world, s.origin_m);
    const Timings t = timedRuns(sc, s, runs);
    const uavip::app::AssembleResult last = uavip::app::assemble(s.log, {}, &s.truth, &world);
    std::printf(
        "scenario %s, %d runs (median wall time), peak RSS %.1f MiB, simulation %.2f s "
        "(excluded)\n",
        sc.name.c_str(), runs, peakRssMiB(), sim_s);
    std::printf(
        "raw points %zu -> merged %zu -> clean %zu; %zu surfaces; %zu stops, %zu waypoints\n\n",
        last.station_points, last.cloud.size(), t.clean, t.surfaces, t.stops, t.waypoints);
    printStages(t);
    printStations(last);
    printVariants(s);
  } catch (const uavip::InputError& e) {
    std::cerr << "uavip_bridge_bench: error: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
