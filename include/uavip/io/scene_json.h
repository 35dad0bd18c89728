#pragma once
/// \file
/// OUT/scene.json (docs/ARCHITECTURE.md): surfaces[] {id, normal, offset, area_m2,
/// density_area_m2, centroid, axis_u, boundary, points}, obstacles[] {id, points,
/// aabb}. The union of all points is the clean cloud. `safety` {file, points,
/// cell_m, margin_m, input_points, perception_dropped, source, sha256} names the
/// safety cloud beside it (cloud_safety.pcd: every input point, thinned with a
/// stated margin; preprocess/safety_cloud.h), so `uavip plan` rebuilds the planning
/// world from these two files; for a mesh input `safety.mesh` {file, triangles} names
/// its triangles beside it too (kSafetyMeshFile).

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "uavip/core/types.h"
#include "uavip/io/mesh_reader.h"

namespace uavip::io {

/// File name of the safety cloud, beside scene.json.
inline constexpr const char* kSafetyCloudFile = "cloud_safety.pcd";
/// File name of a mesh input's triangles beside scene.json (binary STL, metres, the
/// scene's frame; `safety.mesh` {file, triangles} names it): the surface the
/// collision world measures against exactly (SafetyCloud::mesh).
inline constexpr const char* kSafetyMeshFile = "cloud_safety_mesh.stl";

/// One resolved parameter (app/config.h), as scene.json's `parameters` records it.
struct ParameterRecord {
  std::string key;  ///< "section.key", e.g. preprocess.voxel_m
  double value{0.0};
  std::string source;  ///< "set", "auto: max(0.05, spacing)", "default (paper)"
};

/// How `uavip detect` read its input file (`input_read`, `source_offset_m`), so
/// that `uavip validate` reads it the same way.
struct InputReadRecord {
  double scale{1.0};                   ///< factor to metres applied to the coordinates
  std::vector<int> drop_classes;       ///< LAS classes left out
  Vec3 source_offset_m{Vec3::Zero()};  ///< add to a point to get the file's coordinates [m]
  /// The cloud's CRS (scene.json "crs": definition, vertical, source); empty if unknown.
  std::string crs;
  std::string crs_vertical;  ///< "egm96", "egm2008", "ellipsoid" or empty
  std::string crs_source;
  /// A mesh input: format, triangles, area, sampling spacing, axes (input_read.mesh).
  MeshReadInfo mesh;
};

/// What scene.json holds beside the scene itself.
struct SceneExtras {
  std::vector<ParameterRecord> parameters;    ///< every resolved parameter
  double preprocess_s{0.0};                   ///< stage 3 wall time [s]
  double perception_s{0.0};                   ///< stages 4–5 wall time [s]
  std::optional<InputReadRecord> input_read;  ///< absent for a simulated scenario
};

/// The text of scene.json: sceneToJson plus the extras. The file's one writer.
std::string sceneJsonText(const Scene& scene, const SceneExtras& extras);

/// Scene → JSON (coordinates rounded to 0.1 mm). The safety cloud's points are not
/// in it: the caller writes them to kSafetyCloudFile beside it.
nlohmann::json sceneToJson(const Scene& scene);
/// JSON → Scene; throws InputError naming `path` and the bad field. A `safety`
/// block's points are read from its file in the directory of `path`.
Scene sceneFromJson(const nlohmann::json& j, const std::string& path);
/// The cloud's CRS as scene.json records it (`crs` and `source_offset_m`).
struct SceneCrsRecord {
  std::string definition;  ///< what PROJ reads: WKT or "EPSG:N[+V]"
  std::string vertical;    ///< "egm96", "egm2008", "ellipsoid" or "" (not recorded)
  std::string source;      ///< where it came from ("LAS WKT record 2112", "detect --crs")
  Vec3 source_offset_m{Vec3::Zero()};  ///< add to a local point for the CRS point [m]
};
/// The CRS record of a scene.json document; nullopt when it has none. Throws
/// InputError naming `path` for a malformed record.
std::optional<SceneCrsRecord> sceneCrsFromJson(const nlohmann::json& j, const std::string& path);

/// Reads OUT/scene.json.
Scene loadScene(const std::string& path);

}  // namespace uavip::io
