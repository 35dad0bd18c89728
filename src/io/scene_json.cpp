#include "uavip/io/scene_json.h"

#include "uavip/core/error.h"
#include "uavip/core/geometry.h"
#include "uavip/io/atomic_file.h"

#include <Eigen/Geometry>

#include <cmath>
#include <cstdint>

namespace uavip::io {
namespace {

using nlohmann::json;

double round4(double v) { return std::round(v * 1e4) / 1e4; }

json vec(const Vec3& p) { return json::array({round4(p.x()), round4(p.y()), round4(p.z())}); }

json points(const PointList& pts) {
  json arr = json::array();
  for (const auto& p : pts) arr.push_back(vec(p));
  return arr;
}

/// Reads JSON strictly, naming the file and the field on failure.
class Reader {
 public:
  explicit Reader(std::string path) : path_(std::move(path)) {}

  [[noreturn]] void fail(const std::string& field, const std::string& what) const {
    throw InputError(path_ + ": " + field + " " + what);
  }

  const json& at(const json& j, const std::string& key, const std::string& field) const {
    if (!j.is_object() || !j.contains(key)) fail(field + "." + key, "is missing");
    return j.at(key);
  }

  Vec3 vec3(const json& j, const std::string& field) const {
    if (!j.is_array() || j.size() != 3) fail(field, "must be [x, y, z]");
    Vec3 p;
    for (int i = 0; i < 3; ++i) {
      if (!j[i].is_number()) fail(field, "must hold numbers");
      p[i] = j[i].get<double>();
    }
    if (!p.allFinite()) fail(field, "must be finite");
    return p;
  }

  PointList pointList(const json& j, const std::string& field) const {
    if (!j.is_array()) fail(field, "must be a list of [x, y, z]");
    PointList out;
    out.reserve(j.size());
    for (std::size_t i = 0; i < j.size(); ++i) out.push_back(vec3(j[i], field + "[" + std::to_string(i) + "]"));
    return out;
  }

  double number(const json& j, const std::string& field) const {
    if (!j.is_number()) fail(field, "must be a number");
    return j.get<double>();
  }

 private:
  std::string path_;
};

}  // namespace

json sceneToJson(const Scene& scene) {
  json surfaces = json::array();
  for (const auto& s : scene.surfaces) {
    surfaces.push_back({{"id", s.id},
                        {"normal", vec(s.plane.normal)},
                        {"offset", round4(s.plane.offset)},
                        {"area_m2", round4(s.area_m2)},
                        {"density_area_m2", round4(s.density_area_m2)},
                        {"centroid", vec(s.centroid)},
                        {"axis_u", vec(s.axis_u)},
                        {"boundary", points(s.boundary)},
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
  return j;
}

Scene sceneFromJson(const json& j, const std::string& path) {
  const Reader r(path);
  Scene scene;
  const json& surfaces = r.at(j, "surfaces", "scene");
  if (!surfaces.is_array()) r.fail("surfaces", "must be a list");
  for (std::size_t i = 0; i < surfaces.size(); ++i) {
    const std::string f = "surfaces[" + std::to_string(i) + "]";
    const json& js = surfaces[i];
    Surface s;
    const json& id = r.at(js, "id", f);
    if (!id.is_number_integer() || id.get<std::int64_t>() < 0 || id.get<std::int64_t>() > 1'000'000)
      r.fail(f + ".id", "must be a whole number in [0, 1000000]");
    s.id = id.get<int>();
    for (const auto& earlier : scene.surfaces) {
      if (earlier.id == s.id) r.fail(f + ".id", std::to_string(s.id) + " is used by an earlier surface; ids must differ");
    }
    s.plane.normal = r.vec3(r.at(js, "normal", f), f + ".normal");
    if (std::abs(s.plane.normal.norm() - 1.0) > 1e-3) r.fail(f + ".normal", "must be a unit vector");
    s.plane.normal.normalize();
    s.plane.offset = r.number(r.at(js, "offset", f), f + ".offset");
    s.area_m2 = r.number(r.at(js, "area_m2", f), f + ".area_m2");
    s.density_area_m2 = js.contains("density_area_m2") ? r.number(js["density_area_m2"], f) : s.area_m2;
    if (!(s.area_m2 >= 0.0) || !(s.density_area_m2 >= 0.0)) r.fail(f + ".area_m2", "must be >= 0 m2");
    s.centroid = r.vec3(r.at(js, "centroid", f), f + ".centroid");
    s.axis_u = r.vec3(r.at(js, "axis_u", f), f + ".axis_u");
    s.axis_u = (s.axis_u - s.axis_u.dot(s.plane.normal) * s.plane.normal).normalized();
    s.axis_v = s.plane.normal.cross(s.axis_u);
    s.boundary = r.pointList(r.at(js, "boundary", f), f + ".boundary");
    if (s.boundary.size() < 3) r.fail(f + ".boundary", "needs at least 3 vertices");
    s.inliers = r.pointList(r.at(js, "points", f), f + ".points");
    scene.cloud.insert(scene.cloud.end(), s.inliers.begin(), s.inliers.end());
    scene.surfaces.push_back(std::move(s));
  }
  const json& obstacles = r.at(j, "obstacles", "scene");
  if (!obstacles.is_array()) r.fail("obstacles", "must be a list");
  for (std::size_t i = 0; i < obstacles.size(); ++i) {
    const std::string f = "obstacles[" + std::to_string(i) + "]";
    Obstacle o;
    const json& id = r.at(obstacles[i], "id", f);
    if (!id.is_number_integer()) r.fail(f + ".id", "must be an integer");
    o.id = id.get<int>();
    o.points = r.pointList(r.at(obstacles[i], "points", f), f + ".points");
    const Aabb box = boundingBox(o.points);
    o.aabb_min = box.empty() ? Vec3::Zero() : box.min;
    o.aabb_max = box.empty() ? Vec3::Zero() : box.max;
    scene.cloud.insert(scene.cloud.end(), o.points.begin(), o.points.end());
    scene.obstacles.push_back(std::move(o));
  }
  if (scene.cloud.empty()) throw InputError(path + ": the scene has no points (no surfaces, no obstacles)");
  if (j.contains("cloud")) {  // written since the auto parameters (absent in older files)
    const json& c = j.at("cloud");
    CloudStats m;
    const double points = r.number(r.at(c, "points", "cloud"), "cloud.points");
    if (!(points >= 0.0 && points < 1e12)) r.fail("cloud.points", "must be a count");
    m.points = static_cast<std::size_t>(points);
    m.spacing_m = r.number(r.at(c, "spacing_m", "cloud"), "cloud.spacing_m");
    if (!(std::isfinite(m.spacing_m) && m.spacing_m >= 0.0)) r.fail("cloud.spacing_m", "must be >= 0");
    m.extent_m = r.vec3(r.at(c, "extent_m", "cloud"), "cloud.extent_m");
    m.min = r.vec3(r.at(c, "min", "cloud"), "cloud.min");
    m.max = r.vec3(r.at(c, "max", "cloud"), "cloud.max");
    m.noise_m = r.number(r.at(c, "noise_m", "cloud"), "cloud.noise_m");
    if (!(std::isfinite(m.noise_m) && m.noise_m >= 0.0)) r.fail("cloud.noise_m", "must be >= 0");
    const json& lattice = r.at(c, "lattice", "cloud");
    if (!lattice.is_boolean()) r.fail("cloud.lattice", "must be true or false");
    m.lattice = lattice.get<bool>();
    if (c.contains("scanned_from_origin")) {
      const json& station = c.at("scanned_from_origin");
      if (!station.is_boolean()) r.fail("cloud.scanned_from_origin", "must be true or false");
      m.scanned_from_origin = station.get<bool>();
    }
    scene.measured = m;
  }
  return scene;
}

Scene loadScene(const std::string& path) {
  const std::string text = readFile(path);
  json j;
  try {
    j = json::parse(text);
  } catch (const json::parse_error& e) {
    throw InputError(path + ": not valid JSON (byte " + std::to_string(e.byte) + ")");
  }
  return sceneFromJson(j, path);
}

}  // namespace uavip::io
