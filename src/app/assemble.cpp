#include "uavip/app/assemble.h"

#include <algorithm>
#include <string>
#include <vector>

#include "uavip/app/assemble_truth.h"
#include "uavip/core/error.h"
#include "uavip/core/parallel.h"
#include "uavip/core/stopwatch.h"
#include "uavip/sim/scanner_sim.h"

namespace uavip::app {
namespace {

/// Stage 1 on every station, `threads` at a time (each station is independent), in
/// two passes: every station's odometry (ICP), then every station's cloud. One
/// station's ICP is often most of the work; in one pass the other thread ran out of
/// stations while it finished.
/// `seconds` gets each station's time in both.
std::vector<scan::StationCloud> assembleAll(const RawLog& log,
                                            const scan::AssemblerOptions& options, int threads,
                                            std::vector<double>& seconds) {
  const std::size_t n = log.stations.size();
  std::vector<scan::StationOdometry> odometry(n);
  std::vector<scan::StationCloud> clouds(n);
  seconds.assign(n, 0.0);
  parallelFor(n, threads, [&](std::size_t i, std::size_t) {
    const auto t0 = SteadyClock::now();
    odometry[i] = scan::stationOdometry(log, i, options);
    seconds[i] = secondsSince(t0);
  });
  parallelFor(n, threads, [&](std::size_t i, std::size_t) {
    const auto t0 = SteadyClock::now();
    clouds[i] = scan::assembleStation(log, options, odometry[i]);
    seconds[i] += secondsSince(t0);
  });
  return clouds;
}

/// The IMU heading at a station's first sample [rad] (0 without samples: assembly
/// refuses such a station anyway).
double imuYaw(const Station& station) {
  return station.imu.empty() ? 0.0 : scan::yawOf(station.imu.front().world_q_body);
}

/// Stage 2 on the station clouds, each starting from its recorded pose (and the
/// recorded heading when the options say so); `points` gets their total.
registration::RegistrationResult registerAll(const RawLog& log,
                                             const std::vector<scan::StationCloud>& clouds,
                                             const registration::RegistrationOptions& options,
                                             std::size_t& points) {
  std::vector<registration::StationInput> inputs;
  for (std::size_t i = 0; i < clouds.size(); ++i) {
    const Eigen::Isometry3d initial =
        options.use_recorded_yaw
            ? registration::initialStationPose(log, i, true, imuYaw(log.stations[i]),
                                               imuYaw(log.stations.front()))
            : registration::initialStationPose(log, i);
    inputs.push_back({clouds[i].station_id, clouds[i].points, initial});
    points += clouds[i].points.size();
  }
  return registration::registerStations(inputs, options);
}

/// What stages 1 (`c`, `assembly_s` [s]) and 2 (`r`) did at one station.
StationReport stationReport(const scan::StationCloud& c, const registration::StationResult& r,
                            double assembly_s) {
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
  s.position_observed = r.iterations == 0 || r.information(0) >= registration::kMinInformationPairs;
  s.assembly_s = assembly_s;
  s.registration_s = r.time_s;
  return s;
}

}  // namespace

AssembleResult assemble(const RawLog& log, const AssembleOptions& options, const RawLogTruth* truth,
                        const sim::WorldModel* world, const Progress& progress) {
  options.scan.validate("scan");
  options.registration.validate("registration");
  if (log.stations.empty()) throw InputError("assemble: the raw log has no station");
  AssembleResult result;
  const auto t0 = SteadyClock::now();

  reportProgress(progress, "stage 1: assembling " + std::to_string(log.stations.size()) +
                               " stations (eq. (1), IMU, ICP)");
  std::vector<double> seconds;
  const std::vector<scan::StationCloud> clouds =
      assembleAll(log, options.scan, options.threads, seconds);
  result.assembly_s = secondsSince(t0);

  const auto t1 = SteadyClock::now();
  reportProgress(progress, "stage 2: registering the stations");
  registration::RegistrationResult reg =
      registerAll(log, clouds, options.registration, result.station_points);
  result.registration_s = secondsSince(t1);
  result.cloud = std::move(reg.merged);

  for (std::size_t i = 0; i < clouds.size(); ++i) {
    result.stations.push_back(stationReport(clouds[i], reg.stations[i], seconds[i]));
    if (truth && i < truth->stations.size())
      scoreStation(result.stations.back(), clouds[i], reg.stations[i], truth->stations[i]);
  }
  if (world) scoreCloud(result, *world, options.threads);
  result.total_s = secondsSince(t0);
  return result;
}

AssembleResult senseScans(const app::Scenario& scenario, const Progress& progress) {
  if (scenario.sensing_mode != "scan") {
    throw InputError(scenario.path + ": sensing.mode must be 'scan' for raw scans, got '" +
                     scenario.sensing_mode + "'");
  }
  reportProgress(progress, "simulating the two 2D scanners and the IMU");
  const sim::SimulatedLog s = sim::simulateScans(scenario.world, scenario.scan, progress);
  const sim::WorldModel world = worldInLogFrame(scenario.world, s.origin_m);  // to score
  AssembleOptions options;
  options.scan = scenario.config.assembly;
  options.registration = scenario.config.registration;
  AssembleResult result = assemble(s.log, options, &s.truth, &world, progress);
  for (auto& p : result.cloud) p += s.origin_m;  // back into scenario coordinates
  return result;
}

}  // namespace uavip::app
