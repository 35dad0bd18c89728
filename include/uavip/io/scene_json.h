#pragma once
/// \file
/// OUT/scene.json (docs/ARCHITECTURE.md): surfaces[] {id, normal, offset, area_m2,
/// density_area_m2, centroid, axis_u, boundary, points}, obstacles[] {id, points,
/// aabb}. The union of all points is the clean cloud. `safety` {file, points,
/// cell_m, margin_m, input_points, perception_dropped, source, sha256} names the
/// safety cloud beside it (cloud_safety.pcd: every input point, thinned with a
/// stated margin; preprocess/safety_cloud.h), so `uavip plan` rebuilds the planning
/// world from these two files.

#include <nlohmann/json.hpp>
#include <string>

#include "uavip/core/types.h"

namespace uavip::io {

/// File name of the safety cloud, beside scene.json.
inline constexpr const char* kSafetyCloudFile = "cloud_safety.pcd";

/// Scene → JSON (coordinates rounded to 0.1 mm). The safety cloud's points are not
/// in it: the caller writes them to kSafetyCloudFile beside it.
nlohmann::json sceneToJson(const Scene& scene);
/// JSON → Scene; throws InputError naming `path` and the bad field. A `safety`
/// block's points are read from its file in the directory of `path`.
Scene sceneFromJson(const nlohmann::json& j, const std::string& path);
/// Reads OUT/scene.json.
Scene loadScene(const std::string& path);

}  // namespace uavip::io
