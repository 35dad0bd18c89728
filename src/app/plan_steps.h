#pragma once
/// \file
/// Steps shared by app::plan (surfaces) and app::planStructure (the whole
/// structure); private to src/app.

#include <optional>
#include <string>

#include "uavip/app/scenario.h"
#include "uavip/planning/fleet.h"
#include "uavip/planning/flight_planner.h"
#include "uavip/planning/path_validator.h"
#include "uavip/world/collision_world.h"
#include "uavip/world/voxel_grid.h"

namespace uavip::app {

/// mission.start and mission.home must lie within one battery's reach of the photo
/// stops: there and back at cruise speed in the usable endurance. Throws InputError.
void requireWithinReach(const std::optional<Vec3>& point, const std::string& key,
                        const PointList& stops, const planning::FlightModel& model);

/// mission.start and mission.home must lie in free space: at least the safety
/// clearance from every measured point and solid. Throws InputError.
void requireFree(const std::optional<Vec3>& point, const std::string& key,
                 const planning::PathValidator& validator);

/// The one flight over `missions` (planning/flight_planner.h) with the config's
/// flight options, mission.start and mission.simplify.
planning::FlightPlan flyMissions(const std::vector<planning::SurfaceMission>& missions,
                                 const world::VoxelGrid& grid,
                                 const planning::PathValidator& validator,
                                 planning::Planner& planner, const app::Config& config);

/// With a fleet (fleet.uavs > 1 or fleet.homes), the points the planning grid must
/// also cover for its homes (planning::fleetRegion) around mission.home, else
/// mission.start, else the lowest of `positions`; appended to `positions`. Throws
/// InputError for more UAVs than `stops` (the photo stops, when known).
void addFleetRegion(const app::Config& config, PointList& positions, std::size_t stops);

/// The fleet over the single flight (planning/fleet.h), when the config asks for one
/// and the single flight is ok.
std::optional<planning::FleetPlan> flyFleet(const std::vector<planning::SurfaceMission>& missions,
                                            const planning::FlightPlan& single,
                                            const world::VoxelGrid& grid,
                                            const planning::PathValidator& validator,
                                            planning::Planner& planner, const app::Config& config);

}  // namespace uavip::app
