#pragma once
/// \file
/// OUT/mission.json (ARCHITECTURE.md): surfaces[] {surface_id, status, reason,
/// stops[] {position, target, yaw_deg, gimbal_pitch_deg, problem}, waypoints,
/// raw_waypoint_count, path_length_m, validation, timings}.

#include "uavip/planning/mission_planner.h"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace uavip::io {

/// One surface's mission as JSON.
nlohmann::json surfaceMissionToJson(const planning::SurfaceMission& mission);

/// The whole mission file; `meta` is merged at the top level (version, source,
/// planner, camera…).
nlohmann::json missionToJson(const std::vector<planning::SurfaceMission>& missions,
                             const nlohmann::json& meta);

}  // namespace uavip::io
