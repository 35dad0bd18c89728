#pragma once
/// \file
/// A tiled site flown by a fleet with its sections at once (`uavip merge --uavs K` on a
/// site of several sections; issue 45, item 5; docs/fleet.md "A tiled site").
///
/// Each section keeps the one-UAV flight it was planned with, as an independent task
/// (`plan-section`, app/site.h). The site's sorties — section by section, each
/// section's in its flown order — are shared among the K UAVs in contiguous runs that
/// minimise the estimated makespan (exact over every split, by dynamic programming):
/// neighbouring UAVs work away from each other, UAV u's last sorties next to UAV
/// u + 1's first ones, which it flew at the start. Each sortie is flown as planned,
/// from its own section's home; a UAV moves to the next section's home on the ground
/// between two sorties, in no time (as the single UAV does between sections). The
/// schedule is planning::scheduleFlights': UAV u takes off u × launch_interval_s after
/// UAV 1, each sortie at its earliest take-off that keeps separation_m from every
/// other UAV with up to slack_s of delay (waits on the ground); each UAV's run in the
/// site's order or in any order, the sooner kept.

#include <cstddef>
#include <vector>

#include "uavip/planning/fleet_types.h"
#include "uavip/planning/types.h"

namespace uavip::app {

/// A sortie of the site: section index (in the site's order) and the sortie's index
/// in that section's flight (0-based).
struct SiteSortie {
  std::size_t section{0};
  std::size_t sortie{0};
};

/// The site's fleet.
struct SiteFleet {
  /// UAV u's flight: copies of its sorties (durations from the flight model), its home
  /// the first one's; with the schedule (sortie_start_s, waits, makespan, separation),
  /// single_uav_s, lower_bound_s, work_s and fallback_single.
  planning::FleetPlan plan;
  std::vector<std::vector<SiteSortie>> runs;  ///< per UAV, in flown order
  std::size_t uavs_flying{0};                 ///< UAVs with at least one sortie
};

/// Throws InputError for fleet.homes on a site of several `sections`: each section flies
/// from its own home (the one check of merge, plan-section and planSiteFleet).
void refuseFleetHomes(const planning::FleetOptions& fleet, std::size_t sections);

/// The split of `seconds` (each sortie's time: flight, hovers and take-off/landing, in
/// site order) into `uavs` contiguous runs that minimises the latest end, UAV u
/// (0-based) ending at u × launch_interval_s + its run's seconds + battery_swap_s
/// between its sorties. Returns uavs + 1 split points: UAV u flies sorties
/// [split[u], split[u + 1]). Exact; ties go to the earliest split. O(uavs × n²).
std::vector<std::size_t> contiguousRuns(const std::vector<double>& seconds, int uavs,
                                        double launch_interval_s, double battery_swap_s);

/// The fleet over the sections' one-UAV flights (`flights`, site order; a flight that
/// is not ok flies nothing). Throws InputError for fleet.homes (each section flies
/// from its own home) and for more UAVs than photo stops.
SiteFleet planSiteFleet(const std::vector<const planning::FlightPlan*>& flights,
                        const planning::FleetOptions& fleet, const planning::FlightModel& model);

}  // namespace uavip::app
