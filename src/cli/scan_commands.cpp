// uavip simulate: a scenario's world seen by the paper's two 2D scanners and IMU,
// written as a raw log directory (docs/raw_log_format.md).
// uavip assemble: stages 1-2 on a raw log directory: merged cloud + cloud.report.json.

#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>

#include "src/cli/commands.h"
#include "uavip/app/assemble.h"
#include "uavip/app/scenario.h"
#include "uavip/core/error.h"
#include "uavip/core/math.h"
#include "uavip/core/stopwatch.h"
#include "uavip/core/text.h"
#include "uavip/io/atomic_file.h"
#include "uavip/io/cloud_io.h"
#include "uavip/io/raw_log_io.h"
#include "uavip/sim/scanner_sim.h"

namespace uavip::cli {
namespace {

int simulateCommand(const std::string& scenario_path, const std::string& out, const Verbosity& v) {
  const app::Scenario scenario = app::loadScenario(scenario_path);
  if (scenario.sensing_mode != "scan") {
    throw InputError(scenario_path + ": sensing.mode must be 'scan' to simulate raw scans, got '" +
                     scenario.sensing_mode + "' (mode sample makes a cloud: use `uavip run`)");
  }
  const app::Progress progress = progressPrinter(v);
  const auto t0 = SteadyClock::now();
  const sim::SimulatedLog sim = sim::simulateScans(scenario.world, scenario.scan, progress);
  const double sim_s = secondsSince(t0);
  if (progress) progress("writing " + out);
  const auto t1 = SteadyClock::now();
  io::writeRawLog(out, sim.log);
  io::writeRawLogTruth(out, sim.truth, scenario.world, sim.origin_m, scenario_path);
  const double write_s = secondsSince(t1);
  if (!v.quiet) {
    const auto& o = scenario.scan;
    std::cout << "scenario " << scenario.name << " (" << scenario_path << ")\n";
    std::cout << "stations: " << sim.log.stations.size() << ", " << o.scansPerStation()
              << " scans per scanner each (" << formatFixed(o.turn_deg, 0) << " deg at "
              << formatFixed(o.yaw_rate_deg_s, 1) << " deg/s), " << o.scanner.beamCount()
              << " beams per scan\n";
    std::cout << "rays: " << sim.rays << ", returns: " << sim.returns << " ("
              << formatFixed(sim.rays ? 100.0 * static_cast<double>(sim.returns) /
                                            static_cast<double>(sim.rays)
                                      : 0.0,
                             1)
              << " %)\n";
    std::cout << "log origin (station 0) in scenario coordinates: ["
              << formatFixed(sim.origin_m.x(), 3) << ", " << formatFixed(sim.origin_m.y(), 3)
              << ", " << formatFixed(sim.origin_m.z(), 3) << "]\n";
    std::cout << "time: simulation " << formatFixed(sim_s, 2) << " s, writing "
              << formatFixed(write_s, 2) << " s\n";
    std::cout << "results: " << out << "/log.json (+ station CSV files), " << out
              << "/truth.json\n";
  }
  return kExitOk;
}

nlohmann::json vec(const Vec3& v) { return {v.x(), v.y(), v.z()}; }

nlohmann::json reportJson(const app::AssembleResult& r, const app::AssembleOptions& o,
                          const std::string& source, const std::string& config_path,
                          const io::RawLogReadStats& read, bool truth) {
  nlohmann::json stations = nlohmann::json::array();
  for (const auto& s : r.stations) {
    nlohmann::json j = {{"id", s.id},
                        {"points", s.points},
                        {"invalid_beams", s.invalid_beams},
                        {"keyframes", s.keyframes},
                        {"mean_icp_iterations", s.mean_icp_iterations},
                        {"loop_closure_m", s.loop_closure_m},
                        {"drift_final_m", s.drift_final_m},
                        {"drift_max_m", s.drift_max_m},
                        {"initial_position", vec(s.initial_pose.translation())},
                        {"position", vec(s.pose.translation())},
                        {"rotation_deg", Eigen::AngleAxisd(s.pose.linear()).angle() * 180.0 / kPi},
                        {"registered", s.registered},
                        {"registration_rms_m", s.registration_rms_m},
                        {"registration_information_pairs", vec(s.registration_information)},
                        {"weakest_direction", vec(s.weakest_direction)},
                        {"position_observed", s.position_observed},
                        {"assembly_s", s.assembly_s},
                        {"registration_s", s.registration_s}};
    if (s.pose_error_m) {
      j["truth"] = {{"drift_error_max_m", s.drift_error_max_m.value_or(-1.0)},
                    {"drift_error_rms_m", s.drift_error_rms_m.value_or(-1.0)},
                    {"true_drift_max_m", s.true_drift_max_m.value_or(-1.0)},
                    {"initial_position_error_m", *s.initial_pose_error_m},
                    {"position_error_m", *s.pose_error_m},
                    {"rotation_error_deg", *s.pose_error_deg}};
    }
    stations.push_back(j);
  }
  nlohmann::json j = {{"source", source},
                      {"stations", stations},
                      {"cloud", {{"points", r.cloud.size()}, {"station_points", r.station_points}}},
                      {"raw",
                       {{"scans", read.scans},
                        {"beams", read.beams},
                        {"no_return", read.no_return},
                        {"replaced_ranges", read.replaced_ranges},
                        {"imu_samples", read.imu_samples}}},
                      {"options",
                       {{"imu_prior", o.scan.use_imu_prior},
                        {"icp", scan::toString(o.scan.icp)},
                        {"registration", registration::toString(o.registration.method)},
                        {"use_recorded_yaw", o.registration.use_recorded_yaw},
                        {"output_voxel_m", o.registration.output_voxel_m},
                        {"config", config_path}}},
                      {"timings",
                       {{"assembly_s", r.assembly_s},
                        {"registration_s", r.registration_s},
                        {"total_s", r.total_s}}}};
  if (truth && r.rms_to_truth_m) {
    j["truth"] = {{"rms_to_truth_m", *r.rms_to_truth_m},
                  {"p95_to_truth_m", r.p95_to_truth_m.value_or(-1.0)},
                  {"scored_points", r.scored_points}};
  }
  return j;
}

/// One station's line of the assembly summary (and its warning when its position is
/// not fixed by the scans).
void printStation(const app::StationReport& s) {
  std::cout << "  station " << s.id << ": " << s.points << " points, loop closure "
            << (s.loop_closure_m >= 0.0 ? formatFixed(100.0 * s.loop_closure_m, 1) + " cm"
                                        : std::string("n/a (unobservable)"))
            << ", drift " << formatFixed(100.0 * s.drift_max_m, 1) << " cm max, "
            << (s.registered ? "registered" : "NOT registered");
  if (s.pose_error_m) {
    std::cout << "; truth: drift error "
              << formatFixed(100.0 * s.drift_error_max_m.value_or(0.0), 1)
              << " cm max, position error " << formatFixed(100.0 * *s.initial_pose_error_m, 1)
              << " cm recorded -> " << formatFixed(100.0 * *s.pose_error_m, 1) << " cm registered";
  }
  std::cout << "\n";
  if (!s.position_observed) {
    std::cout << "  warning: station " << s.id << "'s position along ("
              << formatFixed(s.weakest_direction.x(), 2) << ", "
              << formatFixed(s.weakest_direction.y(), 2) << ", "
              << formatFixed(s.weakest_direction.z(), 2) << ") is not fixed by the scans ("
              << formatFixed(s.registration_information.x(), 1)
              << " effective pairs): it is the recorded (GPS) one; add a station that sees a "
                 "surface facing it\n";
  }
}

/// The assembly's summary on stdout.
void printAssembly(const app::AssembleResult& r, const app::AssembleOptions& options,
                   const std::string& out, const std::string& report_path) {
  std::cout << "stations: " << r.stations.size() << ", " << r.station_points << " points -> "
            << r.cloud.size() << " merged (voxel "
            << formatFixed(options.registration.output_voxel_m, 3) << " m)\n";
  for (const auto& s : r.stations) printStation(s);
  if (r.rms_to_truth_m) {
    std::cout << "merged cloud to the true surfaces: RMS "
              << formatFixed(100.0 * *r.rms_to_truth_m, 2) << " cm, 95 % "
              << formatFixed(100.0 * r.p95_to_truth_m.value_or(0.0), 2) << " cm\n";
  }
  std::cout << "time: assembly " << formatFixed(r.assembly_s, 2) << " s, registration "
            << formatFixed(r.registration_s, 2) << " s\n";
  std::cout << "results: " << out << ", " << report_path << "\n";
}

/// The assembly options: the config file's, then the flags.
app::AssembleOptions assembleOptions(const std::string& config_path, bool no_imu_prior,
                                     const std::string& method) {
  app::AssembleOptions options;
  if (!config_path.empty()) {
    const app::Config config = app::loadConfigOrScenario(config_path);
    options.scan = config.assembly;
    options.registration = config.registration;
  }
  // The flags override the config file.
  if (no_imu_prior) options.scan.use_imu_prior = false;
  if (!method.empty()) {
    try {
      options.registration.method = registration::methodFromString(method);
    } catch (const InputError& e) {
      const std::string msg = e.what();
      const std::size_t pos = msg.find(" must be");
      throw InputError(pos == std::string::npos ? msg : "--registration" + msg.substr(pos));
    }
  }
  return options;
}

int assembleCommand(const std::string& dir, const std::string& out, const std::string& config_path,
                    bool no_imu_prior, const std::string& method, const Verbosity& v) {
  const app::AssembleOptions options = assembleOptions(config_path, no_imu_prior, method);
  namespace fs = std::filesystem;
  const std::string report_path = fs::path(out).replace_extension(".report.json").string();
  if (fs::path(out).extension() != ".pcd")
    throw InputError("-o: " + out +
                     " must end in .pcd (the merged cloud is written as binary PCD)");
  {
    std::vector<std::string> inputs;
    std::error_code ec;
    if (fs::is_directory(dir, ec))
      for (const auto& e : fs::directory_iterator(dir, ec)) inputs.push_back(e.path().string());
    if (!config_path.empty()) inputs.push_back(config_path);
    io::requireDistinctOutputs(inputs, {out, report_path});
  }
  const app::Progress progress = progressPrinter(v);
  if (progress) progress("reading " + dir);
  // The stations are read one at a time as assembly needs them (bounded memory).
  const io::RawLogReader reader(dir);
  io::RawLogReadStats read;
  std::mutex read_mutex;
  app::StationSource source;
  source.header = reader.header();
  source.read = [&](std::size_t i) {
    io::RawLogReadStats s;
    Station st = reader.readStation(i, s);
    const std::lock_guard<std::mutex> lock(read_mutex);
    read.scans += s.scans;
    read.beams += s.beams;
    read.no_return += s.no_return;
    read.replaced_ranges += s.replaced_ranges;
    read.imu_samples += s.imu_samples;
    return st;
  };
  for (std::size_t i = 0; i < reader.stationCount(); ++i)
    source.file_bytes.push_back(static_cast<double>(reader.stationFileBytes(i)));
  const std::optional<io::RawLogTruthFile> truth = io::readRawLogTruth(dir);
  const app::AssembleResult r = app::assemble(source, options, truth ? &truth->poses : nullptr,
                                              truth ? &truth->world : nullptr, progress);
  const fs::path parent = fs::path(out).parent_path();
  if (!parent.empty()) io::ensureDirectory(parent.string());
  io::StagedOutputs outputs;  // the cloud and its report are written together
  outputs.writeWith(out, [&](const std::string& tmp) { io::writeCloudPcdFile(tmp, r.cloud, out); });
  outputs.write(report_path,
                reportJson(r, options, dir, config_path, read, truth.has_value()).dump(1) + "\n");
  outputs.commit();
  if (!v.quiet) printAssembly(r, options, out, report_path);
  return kExitOk;
}

/// Options of simulate and assemble, kept alive until dispatch.
struct ScanArgs {
  std::string scenario, out, scans, cloud_out, config, registration;
  bool no_imu_prior{false};
};

}  // namespace

void addScanCommands(CLI::App& cli, CommandRegistry& registry) {
  auto a = std::make_shared<ScanArgs>();
  const Verbosity& v = registry.verbosity();

  auto* sim = cli.add_subcommand("simulate",
                                 "Simulate the two 2D scanners and the IMU on a scenario (sensing "
                                 "mode scan): a raw log directory");
  sim->add_option("scenario", a->scenario, "Scenario YAML with sensing: {mode: scan, ...}")
      ->required();
  sim->add_option("-o,--out", a->out,
                  "Output directory for the raw log (log.json, CSV files, truth.json)")
      ->required();
  registry.add(sim, [a, &v] { return simulateCommand(a->scenario, a->out, v); });

  auto* as = cli.add_subcommand(
      "assemble",
      "Stages 1-2 on a raw log directory: one cloud per station (eq. (1), IMU, ICP), "
      "registered and merged; writes the cloud and <cloud>.report.json");
  as->add_option("scans", a->scans, "Raw log directory (written by uavip simulate)")->required();
  as->add_option("-o,--out", a->cloud_out, "Merged cloud (.pcd); the report goes beside it")
      ->required();
  as->add_option("-c,--config", a->config,
                 "Scenario or config YAML: its assembly: and registration: sections (default: the "
                 "built-in options)");
  as->add_flag("--no-imu-prior", a->no_imu_prior,
               "Plain ICP between horizontal scans (no IMU rotation first); overrides the config");
  as->add_option(
      "--registration", a->registration,
      "none, translation (default), icp, icp_point_to_plane, gicp or ndt; overrides the config");
  registry.add(as, [a, &v] {
    return assembleCommand(a->scans, a->cloud_out, a->config, a->no_imu_prior, a->registration, v);
  });
}

}  // namespace uavip::cli
