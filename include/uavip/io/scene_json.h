#pragma once
/// \file
/// OUT/scene.json (ARCHITECTURE.md): surfaces[] {id, normal, offset, area_m2,
/// density_area_m2, centroid, axis_u, boundary, points}, obstacles[] {id, points,
/// aabb}. The union of all points is the clean cloud, so `uavip plan` can rebuild
/// the planning world from this file alone.

#include "uavip/core/types.h"

#include <nlohmann/json.hpp>

#include <string>

namespace uavip::io {

/// Scene → JSON (coordinates rounded to 0.1 mm).
nlohmann::json sceneToJson(const Scene& scene);
/// JSON → Scene; throws InputError naming `path` and the bad field.
Scene sceneFromJson(const nlohmann::json& j, const std::string& path);
/// Reads OUT/scene.json.
Scene loadScene(const std::string& path);

}  // namespace uavip::io
