#include "uavip/app/assemble.h"

#include <algorithm>
#include <string>
#include <vector>

#include "uavip/app/assemble_truth.h"
#include "uavip/core/error.h"
#include "uavip/core/memory.h"
#include "uavip/core/parallel.h"
#include "uavip/core/stopwatch.h"
#include "uavip/sim/scanner_sim.h"

namespace uavip::app {
namespace {

/// The IMU heading at a station's first sample [rad] (0 without samples: assembly
/// refuses such a station anyway).
double imuYaw(const Station& station) {
  return station.imu.empty() ? 0.0 : scan::yawOf(station.imu.front().world_q_body);
}

/// Bytes a station takes while it is assembled, per byte of its files: a range
/// takes 4 bytes in memory and at least 2 characters on disk ("0,"); a return
/// (at least 6: "1.234,") becomes a 24-byte point, then its copy at the
/// registered pose, its down-sampling keys and the odometry's work.
constexpr double kBytesPerFileByte = 14.0;

/// One batch of stations through stage 1 and stage 2's per-station half, read,
/// assembled and prepared `threads` at a time.
struct Batch {
  RawLog log;  ///< the header with this batch's stations
  std::vector<scan::StationCloud> clouds;
  std::vector<registration::StationInput> inputs;
  std::vector<registration::PreparedStation> prepared;
  std::vector<double> seconds;  ///< stage 1 time per station [s]
};

/// Reads stations [first, first + count) of `source` and runs stage 1 on them (in
/// two passes: every station's odometry, then every station's cloud, as one
/// station's ICP is often most of the work) and registration's preparation.
void runBatch(const StationSource& source, std::size_t first, std::size_t count,
              const AssembleOptions& options, const registration::StationMerger& merger,
              double& imu_yaw0, Batch& b) {
  b.log.stations.assign(count, Station{});
  b.seconds.assign(count, 0.0);
  std::vector<scan::StationOdometry> odometry(count);
  b.clouds.assign(count, scan::StationCloud{});
  b.inputs.assign(count, registration::StationInput{});
  b.prepared.assign(count, registration::PreparedStation{});
  parallelFor(count, options.threads, [&](std::size_t k, std::size_t) {
    b.log.stations[k] = source.read(first + k);
    const auto t0 = SteadyClock::now();
    odometry[k] = scan::stationOdometry(b.log, k, options.scan);
    b.seconds[k] = secondsSince(t0);
  });
  if (first == 0) imu_yaw0 = imuYaw(b.log.stations.front());
  parallelFor(count, options.threads, [&](std::size_t k, std::size_t) {
    const auto t0 = SteadyClock::now();
    b.clouds[k] = scan::assembleStation(b.log, options.scan, odometry[k]);
    b.seconds[k] += secondsSince(t0);
    const bool yaw = options.registration.use_recorded_yaw;
    b.inputs[k] = {
        b.clouds[k].station_id, std::move(b.clouds[k].points),
        registration::initialStationPose(source.header, first + k, yaw,
                                         yaw ? imuYaw(b.log.stations[k]) : 0.0, imu_yaw0)};
    b.prepared[k] = merger.prepare(b.inputs[k]);
    b.log.stations[k] = Station{};  // the raw scans are done with
  });
}

/// What stages 1 (`c`, `assembly_s` [s]) and 2 (`r`) did at one station.
StationReport stationReport(const scan::StationCloud& c, const registration::StationResult& r,
                            double assembly_s) {
  StationReport s;
  s.id = c.station_id;
  s.points = r.points;
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

AssembleResult assemble(const StationSource& source, const AssembleOptions& options,
                        const RawLogTruth* truth, const sim::WorldModel* world,
                        const Progress& progress) {
  options.scan.validate("scan");
  options.registration.validate("registration");
  const std::size_t n = source.header.stations.size();
  if (n == 0) throw InputError("assemble: the raw log has no station");
  AssembleResult result;
  const auto t0 = SteadyClock::now();
  registration::StationMerger merger(options.registration);
  const std::size_t batch = 2 * static_cast<std::size_t>(options.threads);
  double imu_yaw0 = 0.0;
  Batch b;
  b.log = source.header;
  b.log.stations.clear();
  for (std::size_t first = 0; first < n; first += batch) {
    const std::size_t count = std::min(batch, n - first);
    double bytes = 0.0;
    for (std::size_t k = 0; k < count && !source.file_bytes.empty(); ++k)
      bytes += kBytesPerFileByte * source.file_bytes[first + k];
    requireMemory(bytes,
                  "assembling stations " + std::to_string(first) + "-" +
                      std::to_string(first + count - 1) + " of the raw log",
                  "split the raw log into logs of fewer stations");
    reportProgress(progress, "stages 1-2: stations " + std::to_string(first + 1) + "-" +
                                 std::to_string(first + count) + " of " + std::to_string(n) +
                                 " (eq. (1), IMU, ICP; registration)");
    const auto t1 = SteadyClock::now();
    runBatch(source, first, count, options, merger, imu_yaw0, b);
    result.assembly_s += secondsSince(t1);
    const auto t2 = SteadyClock::now();
    for (std::size_t k = 0; k < count; ++k) {
      result.station_points += b.inputs[k].points.size();
      const registration::StationResult r = merger.add(b.inputs[k], std::move(b.prepared[k]));
      b.inputs[k] = {};  // merged: released
      result.stations.push_back(stationReport(b.clouds[k], r, b.seconds[k]));
      if (truth && first + k < truth->stations.size())
        scoreStation(result.stations.back(), b.clouds[k], r, truth->stations[first + k]);
      b.clouds[k] = {};
    }
    result.registration_s += secondsSince(t2);
  }
  const auto t3 = SteadyClock::now();
  result.cloud = merger.finish();
  result.registration_s += secondsSince(t3);
  if (world) scoreCloud(result, *world, options.threads);
  result.total_s = secondsSince(t0);
  return result;
}

AssembleResult assemble(const RawLog& log, const AssembleOptions& options, const RawLogTruth* truth,
                        const sim::WorldModel* world, const Progress& progress) {
  StationSource source;
  source.header.body_T_vertical = log.body_T_vertical;
  source.header.body_T_horizontal = log.body_T_horizontal;
  source.header.max_range_m = log.max_range_m;
  source.header.min_range_m = log.min_range_m;
  for (const Station& st : log.stations) {
    Station record;
    record.id = st.id;
    record.recorded_position = st.recorded_position;
    record.recorded_yaw_rad = st.recorded_yaw_rad;
    source.header.stations.push_back(record);
  }
  source.read = [&log](std::size_t i) { return log.stations[i]; };
  return assemble(source, options, truth, world, progress);
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
