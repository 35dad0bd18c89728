#include "uavip/app/assemble.h"

#include <algorithm>
#include <cmath>

#include "uavip/core/error.h"
#include "uavip/core/math.h"
#include "uavip/core/parallel.h"
#include "uavip/core/stopwatch.h"
#include "uavip/sim/scanner_sim.h"

namespace uavip::app {
namespace {

/// The merged cloud is scored on at most this many points (an even subsample).
constexpr std::size_t kMaxScored = 200000;

void report(const Progress& progress, const std::string& message) {
  if (progress) progress(message);
}

/// Stage 1 on every station, `threads` at a time (each station is independent).
std::vector<scan::StationCloud> assembleAll(const RawLog& log,
                                            const scan::AssemblerOptions& options, int threads,
                                            std::vector<double>& seconds) {
  const std::size_t n = log.stations.size();
  std::vector<scan::StationCloud> clouds(n);
  seconds.assign(n, 0.0);
  parallelFor(n, threads, [&](std::size_t i, std::size_t) {
    const auto t0 = SteadyClock::now();
    clouds[i] = scan::assembleStation(log, i, options);
    seconds[i] = secondsSince(t0);
  });
  return clouds;
}

/// The IMU heading at a station's first sample [rad] (0 without samples: assembly
/// refuses such a station anyway).
double imuYaw(const Station& station) {
  return station.imu.empty() ? 0.0 : scan::yawOf(station.imu.front().world_q_body);
}

}  // namespace

// Long (96 lines): stages 1 and 2 and the per-station report that joins both (and the truth, when
// given); each part is a call, the rest is the report's field copies.
AssembleResult assemble(const RawLog& log, const AssembleOptions& options, const RawLogTruth* truth,
                        const sim::WorldModel* world, const Progress& progress) {
  options.scan.validate("scan");
  options.registration.validate("registration");
  if (log.stations.empty()) throw InputError("assemble: the raw log has no station");
  AssembleResult result;
  const auto t0 = SteadyClock::now();

  report(progress, "stage 1: assembling " + std::to_string(log.stations.size()) +
                       " stations (eq. (1), IMU, ICP)");
  std::vector<double> seconds;
  const std::vector<scan::StationCloud> clouds =
      assembleAll(log, options.scan, options.threads, seconds);
  result.assembly_s = secondsSince(t0);

  const auto t1 = SteadyClock::now();
  report(progress, "stage 2: registering the stations");
  std::vector<registration::StationInput> inputs;
  for (std::size_t i = 0; i < clouds.size(); ++i) {
    const Eigen::Isometry3d initial =
        options.registration.use_recorded_yaw
            ? registration::initialStationPose(log, i, true, imuYaw(log.stations[i]),
                                               imuYaw(log.stations.front()))
            : registration::initialStationPose(log, i);
    inputs.push_back({clouds[i].station_id, clouds[i].points, initial});
    result.station_points += clouds[i].points.size();
  }
  registration::RegistrationResult reg =
      registration::registerStations(inputs, options.registration);
  result.registration_s = secondsSince(t1);
  result.cloud = std::move(reg.merged);

  for (std::size_t i = 0; i < clouds.size(); ++i) {
    const scan::StationCloud& c = clouds[i];
    const registration::StationResult& r = reg.stations[i];
    StationReport s;
    s.id = c.station_id;
    s.points = c.points.size();
    s.invalid_beams = c.stats.invalid_beams;
    s.keyframes = c.stats.keyframes;
    s.mean_icp_iterations = c.stats.mean_icp_iterations;
    s.loop_closure_m = c.loop_closure_m;
    for (const auto& p : c.poses) s.drift_max_m = std::max(s.drift_max_m, p.translation().norm());
    if (!c.poses.empty()) s.drift_final_m = c.poses.back().translation().norm();
    s.initial_pose = r.initial_pose;
    s.pose = r.pose;
    s.registered = r.converged;
    s.registration_rms_m = r.fitness_rms_m;
    s.registration_information = r.information;
    s.weakest_direction = r.weakest_direction;
    s.position_observed =
        r.iterations == 0 || r.information(0) >= registration::kMinInformationPairs;
    s.assembly_s = seconds[i];
    s.registration_s = r.time_s;
    if (truth && i < truth->stations.size() && !truth->stations[i].horizontal_poses.empty()) {
      const auto& tp = truth->stations[i].horizontal_poses;
      const Vec3 origin = tp.front().translation();
      double worst = 0.0, sum = 0.0, true_max = 0.0;
      const std::size_t n = std::min(tp.size(), c.poses.size());
      for (std::size_t k = 0; k < n; ++k) {
        const Vec3 true_d = tp[k].translation() - origin;
        const double e = (c.poses[k].translation() - true_d).norm();
        worst = std::max(worst, e);
        sum += e * e;
        true_max = std::max(true_max, true_d.norm());
      }
      if (n > 0) {
        s.drift_error_max_m = worst;
        s.drift_error_rms_m = std::sqrt(sum / static_cast<double>(n));
        s.true_drift_max_m = true_max;
      }
      // Station frame: origin at the UAV centre at the first horizontal scan, world axes.
      s.initial_pose_error_m = (r.initial_pose.translation() - origin).norm();
      s.pose_error_m = (r.pose.translation() - origin).norm();
      s.pose_error_deg = Eigen::AngleAxisd(r.pose.linear()).angle() * kRadToDeg;
    }
    result.stations.push_back(s);
  }

  if (world && !world->empty() && !result.cloud.empty()) {
    const std::size_t stride = std::max<std::size_t>(1, result.cloud.size() / kMaxScored);
    // Independent per point: in blocks on every core, summed below in order.
    std::vector<double> d((result.cloud.size() + stride - 1) / stride);
    constexpr std::size_t kBlock = 4096;
    parallelFor((d.size() + kBlock - 1) / kBlock, options.threads, [&](std::size_t b, std::size_t) {
      for (std::size_t j = b * kBlock; j < std::min(d.size(), (b + 1) * kBlock); ++j) {
        d[j] = world->distanceToTruth(result.cloud[j * stride]);
      }
    });
    double sum = 0.0;
    for (const double v : d) sum += v * v;
    result.rms_to_truth_m = std::sqrt(sum / static_cast<double>(d.size()));
    const auto p95 =
        d.begin() + static_cast<std::ptrdiff_t>(0.95 * static_cast<double>(d.size() - 1));
    std::nth_element(d.begin(), p95, d.end());
    result.p95_to_truth_m = *p95;
    result.scored_points = d.size();
  }
  result.total_s = secondsSince(t0);
  return result;
}

AssembleResult senseScans(const app::Scenario& scenario, const Progress& progress) {
  if (scenario.sensing_mode != "scan") {
    throw InputError(scenario.path + ": sensing.mode must be 'scan' for raw scans, got '" +
                     scenario.sensing_mode + "'");
  }
  report(progress, "simulating the two 2D scanners and the IMU");
  const sim::SimulatedLog s = sim::simulateScans(scenario.world, scenario.scan, progress);
  // The truth in the log frame, to score.
  sim::WorldModel world;
  for (auto r : scenario.world.rects()) {
    r.corner -= s.origin_m;
    world.addPlane(r);
  }
  for (const auto& seg : scenario.world.segments())
    world.addLine(seg.name, seg.a - s.origin_m, seg.b - s.origin_m);
  for (const auto& p : scenario.world.points()) world.addPoint(p.name, p.p - s.origin_m);
  AssembleOptions options;
  options.scan = scenario.config.assembly;
  options.registration = scenario.config.registration;
  AssembleResult result = assemble(s.log, options, &s.truth, &world, progress);
  for (auto& p : result.cloud) p += s.origin_m;  // back into scenario coordinates
  return result;
}

}  // namespace uavip::app
