#include "uavip/io/scene_json.h"

#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <memory>

#include "uavip/core/error.h"
#include "uavip/core/geometry.h"
#include "uavip/io/cloud_io.h"
#include "uavip/io/json_numbers.h"
#include "uavip/io/json_reader.h"

namespace uavip::io {
namespace {

using nlohmann::json;

json points(const PointList& pts) {
  json arr = json::array();
  for (const auto& p : pts) arr.push_back(vec(p));
  return arr;
}

/// A count in [0, 1e12).
std::size_t count(const JsonReader& r, const json& j, const std::string& field) {
  const double v = r.number(j, field);
  if (!(v >= 0.0 && v < 1e12) || v != std::floor(v)) r.fail(field, "must be a count");
  return static_cast<std::size_t>(v);
}

/// `safety.mesh`: a mesh input's triangles, read from the STL it names beside `path`.
std::shared_ptr<const TriangleMesh> readSafetyMesh(const JsonReader& r, const json& jm,
                                                   const std::string& path) {
  const json& file = r.at(jm, "file", "safety.mesh");
  if (!file.is_string() || file.get<std::string>().empty() ||
      std::filesystem::path(file.get<std::string>()).has_parent_path()) {
    r.fail("safety.mesh.file",
           std::string("must be a file name beside the scene, e.g. ") + kSafetyMeshFile);
  }
  const std::size_t triangles =
      count(r, r.at(jm, "triangles", "safety.mesh"), "safety.mesh.triangles");
  const std::string stl =
      (std::filesystem::path(path).parent_path() / file.get<std::string>()).string();
  if (!std::filesystem::exists(stl)) {
    throw InputError(path + ": safety.mesh.file " + stl +
                     " is missing; keep it beside scene.json (or run detect again)");
  }
  auto mesh = std::make_shared<TriangleMesh>(readMesh(stl, 1.0));
  if (mesh->triangles.size() != triangles) {
    throw InputError(stl + ": holds " + std::to_string(mesh->triangles.size()) + " triangles, " +
                     path + " says safety.mesh.triangles " + std::to_string(triangles) +
                     "; run detect again");
  }
  return mesh;
}

/// The `safety` block and its points, read from the file it names beside `path`.
SafetyCloud readSafety(const JsonReader& r, const json& js, const std::string& path) {
  SafetyCloud sc;
  const json& file = r.at(js, "file", "safety");
  if (!file.is_string() || file.get<std::string>().empty() ||
      std::filesystem::path(file.get<std::string>()).has_parent_path()) {
    r.fail("safety.file", "must be a file name beside the scene, e.g. cloud_safety.pcd");
  }
  const std::size_t points = count(r, r.at(js, "points", "safety"), "safety.points");
  sc.cell_m = r.number(r.at(js, "cell_m", "safety"), "safety.cell_m", 1e-9, 1e6, "m");
  sc.margin_m = r.number(r.at(js, "margin_m", "safety"), "safety.margin_m", 0.0, 1e6, "m");
  sc.input_points = count(r, r.at(js, "input_points", "safety"), "safety.input_points");
  sc.perception_dropped =
      count(r, r.at(js, "perception_dropped", "safety"), "safety.perception_dropped");
  if (js.contains("source") && js.at("source").is_string())
    sc.source = js.at("source").get<std::string>();
  if (js.contains("sha256") && js.at("sha256").is_string())
    sc.sha256 = js.at("sha256").get<std::string>();
  if (js.contains("mesh")) sc.mesh = readSafetyMesh(r, js.at("mesh"), path);
  if (points == 0) return sc;
  const std::string cloud =
      (std::filesystem::path(path).parent_path() / file.get<std::string>()).string();
  if (!std::filesystem::exists(cloud)) {
    throw InputError(path + ": safety.file " + cloud +
                     " is missing; keep it beside scene.json (or run detect again)");
  }
  sc.points = loadCloud(cloud);
  if (sc.points.size() != points) {
    throw InputError(cloud + ": holds " + std::to_string(sc.points.size()) + " points, " + path +
                     " says safety.points " + std::to_string(points) + "; run detect again");
  }
  return sc;
}

/// input_read.mesh: the mesh and how its surface became points (the file's sha256 is
/// safety.sha256).
json meshRecord(const MeshReadInfo& m) {
  const bool gltf = m.format == "gltf" || m.format == "glb";
  return {{"format", m.format},
          {"triangles", m.triangles},
          {"degenerate_triangles", m.degenerate},
          {"area_m2", round4(m.area_m2)},
          {"spacing_m", m.spacing_m},
          {"spacing_source", m.spacing_source},
          {"seed", m.seed},
          {"unit", gltf ? "metres (glTF), times input.scale"
                        : "the file states none: its numbers times input.scale are metres"},
          {"axes", m.axes}};
}

}  // namespace

json sceneToJson(const Scene& scene) {
  json surfaces = json::array();
  for (const auto& s : scene.surfaces) {
    json holes = json::array();
    for (const auto& h : s.holes) holes.push_back(points(h));
    surfaces.push_back({{"id", s.id},
                        {"normal", vec(s.plane.normal)},
                        {"offset", round4(s.plane.offset)},
                        {"area_m2", round4(s.area_m2)},
                        {"density_area_m2", round4(s.density_area_m2)},
                        {"centroid", vec(s.centroid)},
                        {"axis_u", vec(s.axis_u)},
                        {"boundary", points(s.boundary)},
                        {"holes", holes},
                        {"point_count", s.inliers.size()},
                        {"points", points(s.inliers)}});
  }
  json obstacles = json::array();
  for (const auto& o : scene.obstacles) {
    obstacles.push_back({{"id", o.id},
                         {"aabb", {{"min", vec(o.aabb_min)}, {"max", vec(o.aabb_max)}}},
                         {"point_count", o.points.size()},
                         {"points", points(o.points)}});
  }
  json j = {{"format", "uavip-scene"},
            {"version", 1},
            {"frame", "local ENU, metres, z up"},
            {"cloud_points", scene.cloud.size()},
            {"surfaces", surfaces},
            {"obstacles", obstacles}};
  if (scene.measured) {
    const CloudStats& c = *scene.measured;
    j["cloud"] = {{"points", c.points},
                  {"spacing_m", round4(c.spacing_m)},
                  {"extent_m", vec(c.extent_m)},
                  {"min", vec(c.min)},
                  {"max", vec(c.max)},
                  {"noise_m", round4(c.noise_m)},
                  {"lattice", c.lattice},
                  {"scanned_from_origin", c.scanned_from_origin},
                  {"station_ratio", round4(c.station_ratio)}};
  }
  if (scene.safety) {
    const SafetyCloud& sc = *scene.safety;
    j["safety"] = {{"file", kSafetyCloudFile},
                   {"points", sc.points.size()},
                   {"cell_m", sc.cell_m},
                   {"margin_m", sc.margin_m},
                   {"input_points", sc.input_points},
                   {"perception_dropped", sc.perception_dropped},
                   {"source", sc.source},
                   {"sha256", sc.sha256}};
    if (sc.mesh)
      j["safety"]["mesh"] = {{"file", kSafetyMeshFile}, {"triangles", sc.mesh->triangles.size()}};
  }
  return j;
}

std::string sceneJsonText(const Scene& scene, const SceneExtras& extras) {
  json j = sceneToJson(scene);
  json parameters = json::object();
  for (const auto& r : extras.parameters)
    parameters[r.key] = {{"value", r.value}, {"source", r.source}};
  j["parameters"] = parameters;
  // Stage times [s]: 3 outlier removal + voxel grid, 4-5 planes + obstacle clusters.
  j["timings"] = {{"preprocess_s", extras.preprocess_s}, {"perception_s", extras.perception_s}};
  if (extras.input_read) {
    const InputReadRecord& read = *extras.input_read;
    j["input_read"] = {{"scale", read.scale}, {"drop_classes", read.drop_classes}};
    if (read.mesh.present) j["input_read"]["source_kind"] = "mesh";
    if (read.mesh.present) j["input_read"]["mesh"] = meshRecord(read.mesh);
    // The cloud's CRS, as the file or detect --crs states it (export places the flight by it).
    if (!read.crs.empty())
      j["crs"] = {
          {"definition", read.crs}, {"vertical", read.crs_vertical}, {"source", read.crs_source}};
    // A recentred input (LAS, UTM): add source_offset_m to a point for the file's metres.
    if (read.source_offset_m != Vec3::Zero()) {
      const Vec3& o = read.source_offset_m;
      j["source_offset_m"] = {o.x(), o.y(), o.z()};
    }
  }
  return j.dump(1) + "\n";
}

namespace {

/// Surface `f`'s `holes` (absent in scenes written before outlines: none).
std::vector<PointList> readHoles(const JsonReader& r, const json& js, const std::string& f) {
  std::vector<PointList> out;
  if (!js.contains("holes")) return out;
  const json& holes = js["holes"];
  if (!holes.is_array()) r.fail(f + ".holes", "must be a list of polygons");
  for (std::size_t h = 0; h < holes.size(); ++h) {
    const std::string fh = f + ".holes[" + std::to_string(h) + "]";
    out.push_back(r.points(holes[h], fh));
    if (out.back().size() < 3) r.fail(fh, "needs at least 3 vertices");
  }
  return out;
}

}  // namespace

Scene sceneFromJson(const json& j, const std::string& path) {
  const JsonReader r(path);
  Scene scene;
  const json& surfaces = r.at(j, "surfaces", "");
  if (!surfaces.is_array()) r.fail("surfaces", "must be a list");
  for (std::size_t i = 0; i < surfaces.size(); ++i) {
    const std::string f = "surfaces[" + std::to_string(i) + "]";
    const json& js = surfaces[i];
    Surface s;
    s.id = static_cast<int>(r.integer(r.at(js, "id", f), f + ".id", 0, 1'000'000));
    for (const auto& earlier : scene.surfaces) {
      if (earlier.id == s.id)
        r.fail(f + ".id", std::to_string(s.id) + " is used by an earlier surface; ids must differ");
    }
    s.plane.normal = r.vec3(r.at(js, "normal", f), f + ".normal");
    if (std::abs(s.plane.normal.norm() - 1.0) > 1e-3)
      r.fail(f + ".normal", "must be a unit vector");
    s.plane.normal.normalize();
    s.plane.offset = r.number(r.at(js, "offset", f), f + ".offset", -2.0 * kMaxLocalCoordinateM,
                              2.0 * kMaxLocalCoordinateM, "m");
    s.area_m2 = r.number(r.at(js, "area_m2", f), f + ".area_m2");
    s.density_area_m2 = js.contains("density_area_m2")
                            ? r.number(js["density_area_m2"], f + ".density_area_m2")
                            : s.area_m2;
    if (!(s.area_m2 >= 0.0) || !(s.density_area_m2 >= 0.0))
      r.fail(f + ".area_m2", "must be >= 0 m2");
    s.centroid = r.vec3(r.at(js, "centroid", f), f + ".centroid");
    s.axis_u = r.vec3(r.at(js, "axis_u", f), f + ".axis_u");
    s.axis_u = (s.axis_u - s.axis_u.dot(s.plane.normal) * s.plane.normal).normalized();
    s.axis_v = s.plane.normal.cross(s.axis_u);
    s.boundary = r.points(r.at(js, "boundary", f), f + ".boundary");
    if (s.boundary.size() < 3) r.fail(f + ".boundary", "needs at least 3 vertices");
    s.holes = readHoles(r, js, f);
    s.inliers = r.points(r.at(js, "points", f), f + ".points");
    scene.cloud.insert(scene.cloud.end(), s.inliers.begin(), s.inliers.end());
    scene.surfaces.push_back(std::move(s));
  }
  const json& obstacles = r.at(j, "obstacles", "");
  if (!obstacles.is_array()) r.fail("obstacles", "must be a list");
  for (std::size_t i = 0; i < obstacles.size(); ++i) {
    const std::string f = "obstacles[" + std::to_string(i) + "]";
    Obstacle o;
    o.id = static_cast<int>(r.integer(r.at(obstacles[i], "id", f), f + ".id", 0, 1'000'000'000));
    o.points = r.points(r.at(obstacles[i], "points", f), f + ".points");
    const Aabb box = boundingBox(o.points);
    o.aabb_min = box.empty() ? Vec3::Zero() : box.min;
    o.aabb_max = box.empty() ? Vec3::Zero() : box.max;
    scene.cloud.insert(scene.cloud.end(), o.points.begin(), o.points.end());
    scene.obstacles.push_back(std::move(o));
  }
  if (scene.cloud.empty())
    throw InputError(path + ": the scene has no points (no surfaces, no obstacles)");
  if (j.contains("cloud")) {  // written since the auto parameters (absent in older files)
    const json& c = j.at("cloud");
    CloudStats m;
    const double points = r.number(r.at(c, "points", "cloud"), "cloud.points");
    if (!(points >= 0.0 && points < 1e12)) r.fail("cloud.points", "must be a count");
    m.points = static_cast<std::size_t>(points);
    m.spacing_m = r.number(r.at(c, "spacing_m", "cloud"), "cloud.spacing_m");
    if (!(std::isfinite(m.spacing_m) && m.spacing_m >= 0.0))
      r.fail("cloud.spacing_m", "must be >= 0");
    m.extent_m = r.vec3(r.at(c, "extent_m", "cloud"), "cloud.extent_m", false);
    m.min = r.vec3(r.at(c, "min", "cloud"), "cloud.min");
    m.max = r.vec3(r.at(c, "max", "cloud"), "cloud.max");
    m.noise_m = r.number(r.at(c, "noise_m", "cloud"), "cloud.noise_m");
    if (!(std::isfinite(m.noise_m) && m.noise_m >= 0.0)) r.fail("cloud.noise_m", "must be >= 0");
    m.lattice = r.boolean(r.at(c, "lattice", "cloud"), "cloud.lattice");
    if (c.contains("scanned_from_origin"))
      m.scanned_from_origin = r.boolean(c.at("scanned_from_origin"), "cloud.scanned_from_origin");
    scene.measured = m;
  }
  if (j.contains("safety")) scene.safety = readSafety(r, j.at("safety"), path);
  return scene;
}

std::optional<SceneCrsRecord> sceneCrsFromJson(const json& j, const std::string& path) {
  if (!j.is_object() || !j.contains("crs")) return std::nullopt;
  const JsonReader r(path);
  const json& crs = j.at("crs");
  SceneCrsRecord out;
  out.definition = r.text(r.at(crs, "definition", "crs"), "crs.definition");
  if (out.definition.empty()) r.fail("crs.definition", "must not be empty (the cloud's CRS)");
  if (crs.contains("vertical")) out.vertical = r.text(crs.at("vertical"), "crs.vertical");
  if (crs.contains("source")) out.source = r.text(crs.at("source"), "crs.source");
  if (j.contains("source_offset_m"))
    out.source_offset_m = r.vec3(j.at("source_offset_m"), "source_offset_m", false);
  return out;
}

Scene loadScene(const std::string& path) { return sceneFromJson(JsonReader(path).load(), path); }

}  // namespace uavip::io
