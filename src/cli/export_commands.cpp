// uavip export: a mission.json as a QGroundControl .plan, a QGC WPL 110 file or a
// CSV (io/mission_export.h has the item layout and the heading convention).

#include "src/cli/commands.h"

#include "uavip/core/error.h"
#include "uavip/io/atomic_file.h"
#include "uavip/io/mission_export.h"

#include <algorithm>
#include <iomanip>
#include <iostream>
#include <memory>

namespace uavip::cli {
namespace {

/// Options of export, kept alive until dispatch.
struct ExportArgs {
  std::string mission, format, origin, out, surface, autopilot{"px4"};
  double hold_s{1.0}, acceptance_m{0.3}, speed_m_s{2.0};
};

int exportCommand(const ExportArgs& a, const Verbosity& v) {
  if (a.origin.empty())
    throw InputError("--origin: missing; pass --origin LAT,LON,ALT, the WGS84 position (degrees, degrees, metres above "
                     "sea level) of the local frame's origin (0, 0, 0), which is also home");
  io::ExportOptions options;
  options.origin = io::parseOrigin(a.origin);
  options.autopilot = io::parseAutopilot(a.autopilot);
  options.hold_s = a.hold_s;
  options.acceptance_m = a.acceptance_m;
  options.speed_m_s = a.speed_m_s;
  options.validate();
  const io::ExportFormat format = io::parseExportFormat(a.format);

  const std::string text = io::readFile(a.mission);
  nlohmann::json mission;
  try {
    mission = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(a.mission + ": not valid JSON (" + std::string(e.what()) + "); pass the mission.json of uavip run or plan");
  }

  io::Flight flight;
  try {
    flight = io::flightFromMissionJson(mission, a.mission, a.surface);
  } catch (const io::NoMissionError& e) {
    std::cerr << "uavip: " << e.what() << "\n";
    return kExitNoMission;
  }
  if (flight.surface_ids.size() > 1 && !v.quiet) {
    std::cerr << "uavip: warning: " << flight.surface_ids.size()
              << " surfaces joined by straight legs that were not planned or checked for collisions\n";
  }
  double min_up = 0.0;
  for (const auto& w : flight.waypoints) min_up = std::min(min_up, w.enu.z());
  if (min_up < 0.0 && !v.quiet) {
    std::cerr << "uavip: warning: the lowest waypoint is " << std::fixed << std::setprecision(2) << -min_up
              << " m below the origin (home); check that the origin's altitude is that of the ground or lower\n";
  }

  io::writeFileAtomic(a.out, io::exportFlight(flight, format, options));
  if (!v.quiet) {
    std::string ids;
    for (int id : flight.surface_ids) ids += (ids.empty() ? "" : ", ") + std::to_string(id);
    const std::size_t items = format == io::ExportFormat::Csv ? flight.waypoints.size()
                                                              : io::missionItems(flight, options).size();
    std::cout << "exported surface" << (flight.surface_ids.size() > 1 ? "s " : " ") << ids << ": "
              << flight.waypoints.size() << " waypoints, " << flight.stopCount() << " photo stops, " << items
              << (format == io::ExportFormat::Csv ? " rows" : " mission items") << " -> " << a.out << "\n";
  }
  return kExitOk;
}

}  // namespace

void addExportCommands(CLI::App& cli, CommandRegistry& registry) {
  auto a = std::make_shared<ExportArgs>();
  const Verbosity& v = registry.verbosity();
  auto* ex = cli.add_subcommand(
      "export",
      "Write a mission.json as a QGroundControl .plan, QGC WPL 110 or CSV file. Local ENU -> WGS84 about --origin; "
      "headings are compass (0 = north, clockwise) = 90 - ENU yaw");
  ex->add_option("mission", a->mission, "OUT/mission.json written by run or plan")->required();
  ex->add_option("--format", a->format, "qgc-plan, wpl or csv")->required();
  ex->add_option("--origin", a->origin, "LAT,LON,ALT of the local origin (0,0,0) = home [deg, deg, m above sea level]");
  ex->add_option("-o,--out", a->out, "Output file")->required();
  ex->add_option("--surface", a->surface,
                 "Surface id, or 'all' (joined by unchecked straight legs); default: the only surface with a mission");
  ex->add_option("--autopilot", a->autopilot, "px4 (heading in NAV_WAYPOINT) or ardupilot (adds CONDITION_YAW)")
      ->capture_default_str();
  ex->add_option("--hold", a->hold_s, "Hover time at each photo stop [s]")->capture_default_str();
  ex->add_option("--acceptance", a->acceptance_m, "Waypoint acceptance radius [m]")->capture_default_str();
  ex->add_option("--speed", a->speed_m_s, "Flight speed (hoverSpeed of the .plan) [m/s]")->capture_default_str();
  registry.add(ex, [a, &v] { return exportCommand(*a, v); });
}

}  // namespace uavip::cli
