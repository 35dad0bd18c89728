#pragma once
/// \file
/// Scenario and configuration files (YAML, schema in scenarios/README.md). Parsing
/// is strict: an unknown key, a wrong type, a missing required field or a bad value
/// throws InputError naming the file, the key path and the value.

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "uavip/core/params.h"
#include "uavip/core/types.h"
#include "uavip/coverage/flight_strategy.h"
#include "uavip/io/cloud_io.h"
#include "uavip/perception/scene_builder.h"
#include "uavip/planning/fleet_types.h"
#include "uavip/planning/planner_table.h"
#include "uavip/planning/types.h"
#include "uavip/preprocess/filters.h"
#include "uavip/preprocess/safety_cloud.h"
#include "uavip/registration/station_registration.h"
#include "uavip/scan/station_assembler.h"
#include "uavip/sim/scanner_sim.h"
#include "uavip/sim/surface_sampler.h"
#include "uavip/sim/world_model.h"
#include "uavip/tiling/merge.h"
#include "uavip/world/voxel_grid.h"

namespace uavip::app {

/// The UAV (paper §III: 0.6 × 0.6 × 0.4 m).
struct UavConfig {
  /// The aircraft profile (core/aircraft.h; app/aircraft_profile.h): "generic" sets
  /// nothing, any other name its camera, gimbal, speed, endurance and size.
  std::string model{"generic"};
  std::string payload;         ///< the camera of an m300/m350 ("" its default)
  Vec3 size_m{0.6, 0.6, 0.4};  ///< [m]
  /// Inflation radius of the grid [m]; default: the largest dimension (paper).
  std::optional<double> inflation_radius_m;
  double inflationRadius() const {
    return inflation_radius_m ? *inflation_radius_m : size_m.maxCoeff();
  }
  /// Throws InputError naming the bad key (prefix `where`).
  void validate(const std::string& where = "uav") const;
  /// The keys of `uav:` (core/params.h).
  static const params::Table<UavConfig>& table();
};

/// Every stage's parameters (the non-world part of a scenario; also the `-c`
/// config of `uavip detect`, `uavip plan` and `uavip assemble`).
struct Config {
  /// How `uavip detect` reads the cloud file, section `input:`.
  io::CloudReadOptions input;
  /// Stage 1 (paper §II-A), section `assembly:`; used with sensing mode `scan` only.
  scan::AssemblerOptions assembly;
  /// Stage 2 (paper §II-B), section `registration:`; used with sensing mode `scan` only.
  registration::RegistrationOptions registration;
  preprocess::PreprocessOptions preprocess;
  /// Safety from every measured point (preprocess/safety_cloud.h), section `safety:`.
  preprocess::SafetyOptions safety;
  perception::PerceptionOptions perception;
  UavConfig uav;
  world::GridOptions grid;
  coverage::CoverageOptions coverage;
  std::string planner{"astar-coarse"};
  planning::PlannerSettings planner_settings;
  planning::MissionOptions mission;
  /// The flight over all chosen surfaces: `mission.home` and section `flight:`
  /// (speeds, hover and settle time, endurance, reserve; planning/flight_planner.h).
  planning::FlightOptions flight;
  /// Several UAVs at once, section `fleet:` (planning/fleet.h).
  planning::FleetOptions fleet;
  /// Which layer set each key (core/params.h: default < profile < auto < file): the
  /// reader records the file's keys, app::resolveConfig the `auto` ones.
  params::Sources sources;

  /// Validates every section; throws InputError prefixed by `where` (the file).
  void validate(const std::string& where) const;
  /// Grid options inflated by `clearance_m` [m], the distance the flight keeps from
  /// every measured point (app::safetyClearance: the UAV's radius plus the safety
  /// cloud's margin). The one place the grid's inflation is set.
  world::GridOptions gridOptions(double clearance_m) const;
  /// gridOptions(the UAV's inflation radius).
  world::GridOptions gridOptions() const;
  /// Mission options with the camera's gimbal limits (`camera.gimbal`) filled in.
  planning::MissionOptions missionOptions() const;
  /// Flight options with `mission.start` and `mission.simplify` filled in.
  planning::FlightOptions flightOptions() const;
  /// The merge's join of tile scenes (tiling/merge.h) with this config's detector
  /// options; `keep_buffer_safety` when a section is planned apart from its neighbours.
  tiling::MergeOptions mergeOptions(bool keep_buffer_safety) const;

  /// Every key a config file may set ("section.key"), each once: the sections' tables
  /// beside their Options structs and the app's own keys. The YAML reader, the
  /// unknown-key check, `auto` and `uavip config --list` read it.
  static const params::Table<Config>& table();
  /// The key ("section.key") of `field`, a field of this config that table() lists;
  /// throws std::logic_error for any other address.
  const std::string& keyOf(const void* field) const;
  /// True when the file set the key of `field` (a field of this config).
  bool setInFile(const void* field) const { return sources.fromFile(keyOf(field)); }
};

/// The optional `bench:` section: the legs `uavip bench` plans (bench/runner.h).
struct BenchSpec {
  /// Explicit legs (start, goal) [m]; empty = sampled from the photo stops.
  std::vector<std::pair<Vec3, Vec3>> legs;
  int max_legs{10};  ///< number of sampled legs when `legs` is empty
};

/// A synthetic scenario: a world, how it is sensed and every stage's parameters.
/// Its `expect:` section (the paper's outcome) is read by the tests only
/// (tests/app/expectation.h).
struct Scenario {
  std::string path;  ///< file it was read from
  std::string name;
  std::string description;
  sim::WorldModel world;
  std::string sensing_mode{
      "sample"};              ///< "sample" (surface sampling) or "scan" (two 2D scanners + IMU)
  sim::SampleOptions sample;  ///< options of mode "sample"
  sim::ScanSimOptions scan;   ///< options of mode "scan"
  Config config;
  BenchSpec bench;
  /// `edits:` an edits file (app/edits.h) `uavip run` applies after detection; a
  /// relative name is resolved against the scenario's folder. Empty: none.
  std::string edits;
};

/// The scenario reference generated from Config::table() (`uavip config --list`, the
/// generated part of scenarios/README.md): per section a Markdown table of key, default,
/// unit, bounds, the layers that may set it (default < profile < auto < file) and help.
/// `keys_only`: one "section.key" a line instead.
std::string configReference(bool keys_only = false);

/// Reads and validates a scenario file. Throws InputError on any problem.
Scenario loadScenario(const std::string& path);
/// Parses a scenario from YAML text; `path` is used in messages.
Scenario parseScenario(const std::string& yaml_text, const std::string& path);
/// Reads a config file (the sections of a scenario other than name, world,
/// sensing and expect). Throws InputError on any problem.
Config loadConfig(const std::string& path);
/// Parses a config from YAML text.
Config parseConfig(const std::string& yaml_text, const std::string& path);
/// The `-c` file of `uavip assemble`: a scenario (a mapping with a top-level
/// `world` key: its config part) or a config file. Throws InputError on any problem.
Config loadConfigOrScenario(const std::string& path);

}  // namespace uavip::app
