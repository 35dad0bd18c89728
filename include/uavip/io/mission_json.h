#pragma once
/// \file
/// OUT/mission.json (ARCHITECTURE.md): surfaces[] {surface_id, status, reason,
/// stops[] {position, target, yaw_deg, gimbal_pitch_deg, problem}, waypoints,
/// raw_waypoint_count, path_length_m, validation, timings}, flight {…}.

#include "uavip/planning/flight_planner.h"
#include "uavip/planning/mission_planner.h"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace uavip::io {

/// One surface's mission as JSON.
nlohmann::json surfaceMissionToJson(const planning::SurfaceMission& mission);

/// The ordered flight (`flight` of mission.json): status, reason, home,
/// home_source, order[] {surface_id, reversed}, excluded[] {surface_id, reason},
/// tour_length_m, naive_length_m, lower_bound_m, exact_order, length_m, duration_s,
/// model {…}, sorties[] {sortie (from 1), length_m, duration_s, stops[] {surface_id,
/// stop, waypoint (index in this sortie's waypoints)}, waypoints (home … home),
/// validation}.
nlohmann::json flightToJson(const planning::FlightPlan& flight, const planning::FlightModel& model);

/// The whole mission file; `meta` is merged at the top level (version, source,
/// planner, camera…).
nlohmann::json missionToJson(const std::vector<planning::SurfaceMission>& missions,
                             const nlohmann::json& meta);

}  // namespace uavip::io
