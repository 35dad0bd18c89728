#pragma once
/// \file
/// A fleet: the site's photo stops shared among K UAVs so that the last one lands as
/// early as possible (the makespan), each UAV's share flown as today's single flight
/// (planning/flight_planner.h: order, legs, battery sorties, validation) from its own
/// home, and a schedule that keeps every two UAVs `separation_m` apart at every
/// instant with any delay up to `slack_s` (planning/fleet_types.h).
///
/// Jobs: each flyable surface is one job, flown in one pass by one UAV. A surface is
/// cut into 2..K parts of consecutive stops only when that lowers the estimated
/// makespan by at least 5 % (an inspector reads a surface in one pass).
///
/// Assignment (min–max): a UAV's time for a set of jobs is estimated from the flight
/// model — a tour over the jobs on straight-line times (planning/tour.h), plus one
/// round trip per extra battery sortie, take-off/landing and battery swaps, plus its
/// launch offset. Jobs are placed longest first on the UAV that ends earliest with
/// them (LPT), then moved and swapped between the latest UAV and the others while the
/// estimated makespan falls. Each UAV's jobs are then flown by planFlight.
///
/// Conflict-aware: the estimates ignore the separation, so several candidate
/// assignments (the min–max one, the next best ones, spatial slabs, short parts of
/// surfaces) are flown — one flight per UAV, and one flight per job — and scheduled,
/// and the shortest makespan with its waits is kept (docs/fleet.md, "Candidates").
///
/// Schedule: UAV i takes off at i × launch_interval_s, each sortie after the last
/// one's landing and the battery swap. List scheduling (each sortie at its earliest
/// conflict-free take-off) or, whichever lands sooner: the earliest conflict of the separation
/// check is resolved by a wait on the ground before the sortie of one of the two UAVs (the one
/// whose landing moves least), until none is left. When the fleet would land no sooner than the
/// single flight, UAV 1 flies the single flight alone.
///
/// Lower bound of the makespan: the larger of the longest round trip home → stop →
/// home and (W + launch_interval_s × K'(K'−1)/2) / K' minimised over K' ≤ K UAVs,
/// where W sums over the stops their photo time and the shortest flight that can
/// reach them (from another stop or a home).

#include <functional>
#include <vector>

#include "uavip/planning/fleet_types.h"
#include "uavip/planning/flight_planner.h"

namespace uavip::planning {

/// Plans the fleet for the missions whose single-UAV flight is `single` (status Ok).
/// Throws InputError for more UAVs than flown photo stops, a home that is not free,
/// keeps less than the validator's clearance or cannot reach the single flight's
/// home on the grid, or default homes that find no free place.
FleetPlan planFleet(const std::vector<SurfaceMission>& missions, const FlightPlan& single,
                    const world::VoxelGrid& grid, const PathValidator& validator, Planner& planner,
                    const FlightOptions& flight, const FleetOptions& fleet);

/// Schedules a fleet whose flights are fixed (plan.uavs[u].flight, its sorties round
/// trips; plan.options and plan.model set): list scheduling as for planFleet's
/// candidates, each sortie at its earliest take-off that keeps the separation with the
/// slack from every sortie placed before. In order, or with `any_order` the UAV that is
/// ready takes whichever of its sorties left can take off earliest (its flight's sorties
/// reordered so). Sets each UAV's sortie_start_s, wait_s and end_s, and the plan's
/// makespan_s, waits and separation (the check of the final schedule). False when that
/// check still finds a conflict.
bool scheduleFlights(FleetPlan& plan, bool any_order = false);

/// Spacing of the default homes along their line [m]: 1.2 × separation_m, at least
/// separation_m + 1 m.
double fleetHomeSpacing(const FleetOptions& fleet);

/// Points the planning grid must cover for the fleet's homes: fleet.homes, or a box of
/// the default homes' reach around `home` (the single flight's home or its estimate).
PointList fleetRegion(const FleetOptions& fleet, const Vec3& home);

/// The lower bound of the file comment for the stops at `stops` [s].
struct FleetBound {
  double work_s{0.0};        ///< W [s]
  double round_trip_s{0.0};  ///< the longest home → stop → home (+ take-off/landing) [s]
  double bound_s{0.0};       ///< the bound [s]
};
FleetBound fleetLowerBound(const PointList& stops, const PointList& homes, const FlightModel& model,
                           const FleetOptions& fleet);

/// Min–max assignment of jobs to UAVs for a set cost: `cost(u, jobs)` is UAV u's
/// finishing time with those jobs (0 for none). LPT by `alone` (each job's cost on its
/// own), then local search (moves and swaps off the latest UAV); every assignment when
/// there are at most 729 (uavs^jobs). Returns the UAV of each job. Deterministic.
std::vector<int> assignMinMax(
    int uavs, const std::vector<double>& alone,
    const std::function<double(int uav, const std::vector<int>& jobs)>& cost);

}  // namespace uavip::planning
