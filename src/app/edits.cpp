#include "uavip/app/edits.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "uavip/app/scenario.h"
#include "uavip/core/error.h"
#include "uavip/core/geometry.h"
#include "uavip/core/math.h"
#include "uavip/core/text.h"
#include "uavip/coverage/flight_strategy.h"
#include "uavip/io/file_digest.h"
#include "uavip/perception/surface_outline.h"
#include "yaml_section.h"

namespace uavip::app {
namespace {

using Vec2 = Eigen::Vector2d;

/// "<file>:<line>" for messages.
std::string at(const std::string& file, int line) {
  return line > 0 ? file + ":" + std::to_string(line) : file;
}

int lineOf(const YAML::Node& n) { return n.Mark().line >= 0 ? n.Mark().line + 1 : 0; }

/// A polygon: a list of at least 3 [x, y, z] points.
PointList polygon(const YAML::Node& n, const std::string& where) {
  if (!n.IsSequence() || n.size() < 3)
    throw InputError(where + " must be a list of at least 3 points [x, y, z]");
  PointList out;
  for (std::size_t i = 0; i < n.size(); ++i) {
    Vec3 v;
    if (!n[i].IsSequence() || n[i].size() != 3)
      throw InputError(where + "[" + std::to_string(i) + "] must be a point [x, y, z]");
    for (int k = 0; k < 3; ++k) {
      if (!YAML::convert<double>::decode(n[i][k], v[k]) || !std::isfinite(v[k]))
        throw InputError(where + "[" + std::to_string(i) + "] must hold finite numbers");
    }
    out.push_back(v);
  }
  return out;
}

std::vector<PointList> polygons(const YAML::Node& n, const std::string& where) {
  if (!n.IsSequence() || n.size() == 0)
    throw InputError(where + " must be a list of polygons (each a list of [x, y, z])");
  std::vector<PointList> out;
  for (std::size_t i = 0; i < n.size(); ++i)
    out.push_back(polygon(n[i], where + "[" + std::to_string(i) + "]"));
  return out;
}

SurfaceEdit parseSurfaceEdit(const YAML::Node& node, const std::string& file, std::size_t i) {
  SurfaceEdit e;
  e.line = lineOf(node);
  const std::string where = "surfaces[" + std::to_string(i) + "]";
  yaml::Section s(node, at(file, e.line), where);
  const double id = s.number("id");
  if (!(id >= 0.0 && id <= 1e9 && std::floor(id) == id))
    s.fail("id", "must be a surface id (a whole number >= 0)");
  e.id = static_cast<int>(id);
  yaml::Section f = s.child("fingerprint");
  e.centroid = f.vec3("centroid");
  e.normal = f.vec3("normal");
  if (!(e.normal.norm() > 0.5)) f.fail("normal", "must be a unit vector");
  e.normal.normalize();
  f.finish();
  const std::string prefix = at(file, e.line) + ": " + where;
  if (s.has("boundary")) e.boundary = polygon(s.node()["boundary"], prefix + ".boundary");
  if (s.has("add")) e.add = polygons(s.node()["add"], prefix + ".add");
  if (s.has("cut")) e.cut = polygons(s.node()["cut"], prefix + ".cut");
  e.remove = s.boolean("delete", false);
  if (s.has("merge")) {
    for (const double v : s.numbers("merge", 1, 1000)) {
      if (!(v >= 0.0 && std::floor(v) == v)) s.fail("merge", "must list surface ids");
      e.merge.push_back(static_cast<int>(v));
    }
  }
  s.finish();
  const bool changes = !e.boundary.empty() || !e.add.empty() || !e.cut.empty() || !e.merge.empty();
  if (e.remove && changes)
    throw InputError(prefix + ": delete cannot be combined with boundary, add, cut or merge");
  if (!e.remove && !changes)
    throw InputError(prefix + ": changes nothing; give boundary, add, cut, delete or merge");
  return e;
}

KeepOutEdit parseKeepOut(const YAML::Node& node, const std::string& file, std::size_t i) {
  KeepOutEdit k;
  k.line = lineOf(node);
  yaml::Section s(node, at(file, k.line), "keep_out[" + std::to_string(i) + "]");
  k.volume.name = s.text("name");
  if (k.volume.name.empty()) s.fail("name", "must not be empty");
  const bool box = s.has("box");
  const bool cylinder = s.has("cylinder");
  if (box == cylinder) s.fail("", "needs exactly one of box or cylinder");
  if (box) {
    yaml::Section b = s.child("box");
    k.volume.shape = KeepOut::Shape::Box;
    k.volume.center = b.vec3("center");
    k.volume.size = b.vec3("size");
    k.volume.yaw_deg = b.number("yaw_deg", 0.0);
    if (std::abs(k.volume.yaw_deg) > 360.0) b.fail("yaw_deg", "must be in [-360, 360]");
    if (!(k.volume.size.minCoeff() > 0.0)) b.fail("size", "must be > 0 on every axis");
    b.finish();
  } else {
    yaml::Section c = s.child("cylinder");
    k.volume.shape = KeepOut::Shape::Cylinder;
    const std::vector<double> xy = c.numbers("center", 2, 2);
    const double r = c.number("radius_m");
    const std::vector<double> z = c.numbers("z", 2, 2);
    if (!(r > 0.0)) c.fail("radius_m", "must be > 0");
    if (!(z[1] > z[0])) c.fail("z", "must be [bottom, top] with top > bottom");
    k.volume.center = Vec3(xy[0], xy[1], 0.5 * (z[0] + z[1]));
    k.volume.size = Vec3(2.0 * r, 2.0 * r, z[1] - z[0]);
    c.finish();
  }
  s.finish();
  return k;
}

std::string num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string point(const Vec3& p) {
  return "[" + num(p.x()) + ", " + num(p.y()) + ", " + num(p.z()) + "]";
}

std::string pointList(const PointList& pts) {
  std::string out = "[";
  for (std::size_t i = 0; i < pts.size(); ++i) out += (i ? ", " : "") + point(pts[i]);
  return out + "]";
}

// ---- applying

/// A surface's plane coordinates about its centroid.
Vec2 planeUv(const Surface& s, const Vec3& p) {
  const Vec3 d = p - s.centroid;
  return {d.dot(s.axis_u), d.dot(s.axis_v)};
}

std::vector<Vec2> loopUv(const Surface& s, const PointList& loop) {
  std::vector<Vec2> out;
  out.reserve(loop.size());
  for (const auto& p : loop) out.push_back(planeUv(s, p));
  return out;
}

PointList loop3d(const Surface& s, const std::vector<Vec2>& loop) {
  PointList out;
  out.reserve(loop.size());
  for (const auto& q : loop) out.push_back(s.centroid + q.x() * s.axis_u + q.y() * s.axis_v);
  return out;
}

/// Checks a polygon of an edit against surface `s` and returns it in plane coordinates:
/// every vertex within the tolerance of the plane, a simple polygon with area.
std::vector<Vec2> checkedPolygon(const Surface& s, const PointList& poly, const std::string& where,
                                 const EditsOptions& o) {
  for (std::size_t k = 0; k < poly.size(); ++k) {
    const double d = std::abs(s.plane.signedDistance(poly[k]));
    if (d > o.plane_tolerance_m)
      throw InputError(where + ": vertex " + std::to_string(k) + " " + formatPoint(poly[k]) +
                       " is " + formatFixed(d, 3) + " m off the plane of surface " +
                       std::to_string(s.id) + " (tolerance " + formatFixed(o.plane_tolerance_m, 2) +
                       " m); give points on the surface");
  }
  std::vector<Vec2> uv = loopUv(s, poly);
  const auto [i, j] = polygonSelfIntersection2d(uv);
  if (i >= 0)
    throw InputError(where + ": the polygon intersects itself (edges " + std::to_string(i) +
                     " and " + std::to_string(j) + " cross or touch); draw it without crossings");
  if (!(polygonArea2d(uv) > 1e-6)) throw InputError(where + ": the polygon has no area");
  if (polygonTwiceSignedArea2d(uv) < 0.0) std::reverse(uv.begin(), uv.end());
  return uv;
}

/// True when q lies on the surface: inside its boundary and in none of its holes.
bool onSurface(const std::vector<Vec2>& outer, const std::vector<std::vector<Vec2>>& holes,
               const Vec2& q) {
  if (!pointInPolygon2d(q, outer)) return false;
  return std::none_of(holes.begin(), holes.end(),
                      [&](const auto& h) { return pointInPolygon2d(q, h); });
}

double regionArea(const std::vector<Vec2>& outer, const std::vector<std::vector<Vec2>>& holes) {
  double a = polygonArea2d(outer);
  for (const auto& h : holes) a -= polygonArea2d(h);
  return std::max(a, 0.0);
}

/// The in-plane axis the raster of `outer` is laid along: its first edge's direction
/// (an outline's edges then run along the cells).
Vec2 rasterAxis(const std::vector<Vec2>& outer) {
  for (std::size_t i = 0; i < outer.size(); ++i) {
    const Vec2 e = outer[(i + 1) % outer.size()] - outer[i];
    if (e.norm() > 1e-9) return e.normalized();
  }
  return Vec2::UnitX();
}

/// The region (outer, holes) of surface `s` in plane coordinates.
struct Region2d {
  std::vector<Vec2> outer;
  std::vector<std::vector<Vec2>> holes;
};

Region2d regionOf(const Surface& s) {
  Region2d r;
  r.outer = loopUv(s, s.boundary);
  for (const auto& h : s.holes) r.holes.push_back(loopUv(s, h));
  return r;
}

/// Sets s's boundary, holes and area from an outline in its plane coordinates.
void setOutline(Surface& s, const std::vector<Vec2>& outer,
                const std::vector<std::vector<Vec2>>& holes, double area) {
  s.boundary = loop3d(s, outer);
  s.holes.clear();
  for (const auto& h : holes) s.holes.push_back(loop3d(s, h));
  s.area_m2 = area;
}

/// Traces what `inside` accepts around the union of `loops` (plane coordinates of s)
/// on cells of `cell`, and makes it s's outline. Throws when nothing is left.
void rasterise(Surface& s, const std::vector<std::vector<Vec2>>& loops,
               const std::function<bool(const Vec2&)>& inside, const Vec2& axis, double cell,
               const std::string& where) {
  const Vec2 ey(-axis.y(), axis.x());
  Vec2 lo = Vec2::Constant(kInf);
  Vec2 hi = -lo;
  for (const auto& l : loops) {
    for (const auto& q : l) {
      const Vec2 r(q.dot(axis), q.dot(ey));
      lo = lo.cwiseMin(r);
      hi = hi.cwiseMax(r);
    }
  }
  const perception::Outline2d o = perception::rasterOutline2d(inside, lo, hi, axis, cell, 0.0);
  if (o.outer.size() < 3)
    throw InputError(where + ": nothing of surface " + std::to_string(s.id) +
                     " is left; use delete: true to drop a surface");
  setOutline(s, o.outer, o.holes, o.area_m2);
}

std::string describe(const SurfaceEdit& e) {
  std::string what;
  const auto add = [&](const std::string& w) { what += (what.empty() ? "" : ", ") + w; };
  if (!e.merge.empty()) {
    std::string ids;
    for (const int m : e.merge) ids += (ids.empty() ? "" : ", ") + std::to_string(m);
    add("merged with " + ids);
  }
  if (!e.boundary.empty())
    add("boundary replaced (" + std::to_string(e.boundary.size()) + " vertices)");
  if (!e.add.empty()) add(std::to_string(e.add.size()) + " polygon(s) added");
  if (!e.cut.empty()) add(std::to_string(e.cut.size()) + " polygon(s) cut");
  if (e.remove) add("deleted (its points are an obstacle)");
  return what;
}

Surface* findSurface(Scene& scene, int id) {
  for (auto& s : scene.surfaces) {
    if (s.id == id) return &s;
  }
  return nullptr;
}

/// Throws unless `s` is the surface the edit was made on (centroid and normal).
void checkFingerprint(const Surface& s, const SurfaceEdit& e, const std::string& where,
                      const EditsOptions& o) {
  const double moved = (s.centroid - e.centroid).norm();
  const double turned = std::acos(std::clamp(s.plane.normal.dot(e.normal), -1.0, 1.0)) * kRadToDeg;
  if (moved > o.fingerprint_centroid_m || turned > o.fingerprint_normal_deg)
    throw InputError(where + ": surface " + std::to_string(e.id) +
                     " does not match the fingerprint (centroid " + formatFixed(moved, 3) +
                     " m away, normal " + formatFixed(turned, 1) +
                     " deg off): the edit was made on another detection; redo it on this scene");
}

/// Surface `id` leaves the scene; its points become an obstacle (a hedge, a truck).
void removeSurface(Scene& scene, int id) {
  const auto it = std::find_if(scene.surfaces.begin(), scene.surfaces.end(),
                               [&](const Surface& x) { return x.id == id; });
  Obstacle ob;
  for (const auto& x : scene.obstacles) ob.id = std::max(ob.id, x.id + 1);
  ob.points = it->inliers;
  const Aabb box = boundingBox(ob.points);
  ob.aabb_min = box.empty() ? Vec3::Zero() : box.min;
  ob.aabb_max = box.empty() ? Vec3::Zero() : box.max;
  scene.obstacles.push_back(std::move(ob));
  scene.surfaces.erase(it);
}

/// The regions of the surfaces `e` merges into `s`, in s's plane coordinates; throws
/// for an id that is not a surface (or s itself) and for one that is not coplanar.
std::vector<Region2d> mergedRegions(Scene& scene, const Surface& s, const SurfaceEdit& e,
                                    const std::map<int, std::string>& gone,
                                    const std::string& where, const EditsOptions& o) {
  std::vector<Region2d> merged;
  for (const int m : e.merge) {
    const Surface* other = findSurface(scene, m);
    if (m == e.id || other == nullptr || gone.count(m))
      throw InputError(where + ".merge: " + std::to_string(m) + " is " +
                       (m == e.id ? "the surface itself" : "not a surface of the scene"));
    const double angle =
        std::acos(std::min(1.0, std::abs(s.plane.normal.dot(other->plane.normal)))) * kRadToDeg;
    const double offset = std::abs(s.plane.signedDistance(other->centroid));
    if (angle > o.coplanar_deg || offset > o.plane_tolerance_m)
      throw InputError(where + ".merge: surface " + std::to_string(m) +
                       " is not coplanar with surface " + std::to_string(e.id) + " (normals " +
                       formatFixed(angle, 1) + " deg apart, centroid " + formatFixed(offset, 3) +
                       " m off its plane; limits " + formatFixed(o.coplanar_deg, 1) + " deg, " +
                       formatFixed(o.plane_tolerance_m, 2) + " m)");
    Region2d r;
    r.outer = loopUv(s, other->boundary);
    if (polygonTwiceSignedArea2d(r.outer) < 0.0) std::reverse(r.outer.begin(), r.outer.end());
    for (const auto& h : other->holes) r.holes.push_back(loopUv(s, h));
    merged.push_back(std::move(r));
  }
  return merged;
}

/// The new outline of `s`: its boundary replaced (exact; the holes inside it kept), then
/// the added polygons and the merged regions joined and the cut ones removed, traced
/// on cells of raster_cell_m.
void reshape(Surface& s, const SurfaceEdit& e, const std::vector<Region2d>& merged,
             const std::string& where, const EditsOptions& o) {
  Region2d region = regionOf(s);
  if (!e.boundary.empty()) {
    region.outer = checkedPolygon(s, e.boundary, where + ".boundary", o);
    std::vector<std::vector<Vec2>> kept;
    for (auto& h : region.holes) {
      if (std::all_of(h.begin(), h.end(),
                      [&](const Vec2& q) { return pointInPolygon2d(q, region.outer); }))
        kept.push_back(std::move(h));
    }
    region.holes = std::move(kept);
  }
  std::vector<std::vector<Vec2>> loops{region.outer};
  std::vector<std::vector<Vec2>> adds;
  std::vector<std::vector<Vec2>> cuts;
  for (std::size_t k = 0; k < e.add.size(); ++k) {
    adds.push_back(checkedPolygon(s, e.add[k], where + ".add[" + std::to_string(k) + "]", o));
    loops.push_back(adds.back());
  }
  for (std::size_t k = 0; k < e.cut.size(); ++k)
    cuts.push_back(checkedPolygon(s, e.cut[k], where + ".cut[" + std::to_string(k) + "]", o));
  for (const auto& r : merged) loops.push_back(r.outer);
  if (merged.empty() && adds.empty() && cuts.empty()) {
    setOutline(s, region.outer, region.holes, regionArea(region.outer, region.holes));
    return;
  }
  const auto inside = [&](const Vec2& q) {
    const auto in = [&](const std::vector<Vec2>& p) { return pointInPolygon2d(q, p); };
    if (std::any_of(cuts.begin(), cuts.end(), in)) return false;
    if (onSurface(region.outer, region.holes, q) || std::any_of(adds.begin(), adds.end(), in))
      return true;
    return std::any_of(merged.begin(), merged.end(),
                       [&](const Region2d& r) { return onSurface(r.outer, r.holes, q); });
  };
  rasterise(s, loops, inside, rasterAxis(region.outer), o.raster_cell_m, where);
}

std::string describe(const KeepOut& k) {
  const std::string shape =
      k.shape == KeepOut::Shape::Box
          ? "box " + formatFixed(k.size.x(), 1) + " x " + formatFixed(k.size.y(), 1) + " x " +
                formatFixed(k.size.z(), 1) + " m at " + formatPoint(k.center)
          : "cylinder r " + formatFixed(0.5 * k.size.x(), 1) + " m, " + formatFixed(k.size.z(), 1) +
                " m tall at " + formatPoint(k.center);
  return "'" + k.name + "' " + shape + " is solid";
}

}  // namespace

void EditsOptions::validate(const std::string& where) const {
  requirePositive(fingerprint_centroid_m, where, "fingerprint_centroid_m");
  requirePositive(fingerprint_normal_deg, where, "fingerprint_normal_deg");
  requirePositive(plane_tolerance_m, where, "plane_tolerance_m");
  requirePositive(coplanar_deg, where, "coplanar_deg");
  requirePositive(raster_cell_m, where, "raster_cell_m");
}

Edits parseEdits(const std::string& yaml_text, const std::string& file) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw InputError(file + ":" + std::to_string(e.mark.line + 1) + ": not valid YAML (" + e.msg +
                     ")");
  }
  if (!root.IsMap())
    throw InputError(file + ": not an edits file (expected a mapping with uavip-edits: 1)");
  Edits edits;
  edits.file = file;
  yaml::Section top(root, file, "");
  if (top.integer("uavip-edits", 0) != 1)
    top.fail("uavip-edits", "must be 1 (the edits file format version)");
  if (top.has("scene")) (void)top.text("scene");
  if (top.has("surfaces")) {
    const YAML::Node list = root["surfaces"];
    if (!list.IsSequence()) top.fail("surfaces", "must be a list");
    for (std::size_t i = 0; i < list.size(); ++i)
      edits.surfaces.push_back(parseSurfaceEdit(list[i], file, i));
  }
  if (top.has("keep_out")) {
    const YAML::Node list = root["keep_out"];
    if (!list.IsSequence()) top.fail("keep_out", "must be a list");
    std::set<std::string> names;
    for (std::size_t i = 0; i < list.size(); ++i) {
      edits.keep_out.push_back(parseKeepOut(list[i], file, i));
      if (!names.insert(edits.keep_out.back().volume.name).second)
        throw InputError(at(file, edits.keep_out.back().line) + ": keep_out[" + std::to_string(i) +
                         "] name '" + edits.keep_out.back().volume.name +
                         "' is used twice; names must differ");
    }
  }
  top.finish();
  return edits;
}

Edits loadEdits(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot read the edits file");
  std::ostringstream text;
  text << in.rdbuf();
  Edits e = parseEdits(text.str(), path);
  e.sha256 = io::sha256File(path);
  return e;
}

std::string editsYamlText(const Edits& edits) {
  std::ostringstream os;
  os << "uavip-edits: 1\n";
  if (!edits.surfaces.empty()) os << "surfaces:\n";
  for (const auto& e : edits.surfaces) {
    os << "  - id: " << e.id << "\n";
    os << "    fingerprint: {centroid: " << point(e.centroid) << ", normal: " << point(e.normal)
       << "}\n";
    if (!e.boundary.empty()) os << "    boundary: " << pointList(e.boundary) << "\n";
    const auto list = [&](const char* key, const std::vector<PointList>& polys) {
      if (polys.empty()) return;
      os << "    " << key << ":\n";
      for (const auto& p : polys) os << "      - " << pointList(p) << "\n";
    };
    list("add", e.add);
    list("cut", e.cut);
    if (e.remove) os << "    delete: true\n";
    if (!e.merge.empty()) {
      os << "    merge: [";
      for (std::size_t i = 0; i < e.merge.size(); ++i) os << (i ? ", " : "") << e.merge[i];
      os << "]\n";
    }
  }
  if (!edits.keep_out.empty()) os << "keep_out:\n";
  for (const auto& k : edits.keep_out) {
    const KeepOut& v = k.volume;
    os << "  - name: \"" << v.name << "\"\n";
    if (v.shape == KeepOut::Shape::Box) {
      os << "    box: {center: " << point(v.center) << ", size: " << point(v.size)
         << ", yaw_deg: " << num(v.yaw_deg) << "}\n";
    } else {
      os << "    cylinder: {center: [" << num(v.center.x()) << ", " << num(v.center.y())
         << "], radius_m: " << num(0.5 * v.size.x()) << ", z: ["
         << num(v.center.z() - 0.5 * v.size.z()) << ", " << num(v.center.z() + 0.5 * v.size.z())
         << "]}\n";
    }
  }
  return os.str();
}

std::vector<std::string> applyEdits(Scene& scene, const Edits& edits) {
  edits.options.validate();
  const EditsOptions& o = edits.options;
  Scene out = scene;
  std::vector<std::string> lines;
  std::map<int, std::string> gone;  // id → the edit that removed it
  for (std::size_t i = 0; i < edits.surfaces.size(); ++i) {
    const SurfaceEdit& e = edits.surfaces[i];
    const std::string name = "surfaces[" + std::to_string(i) + "]";
    const std::string where = at(edits.file, e.line) + ": " + name;
    if (gone.count(e.id))
      throw InputError(where + ": surface " + std::to_string(e.id) + " was removed by " +
                       gone[e.id] + "; edit it there");
    Surface* s = findSurface(out, e.id);
    if (s == nullptr)
      throw InputError(where + ": no surface with id " + std::to_string(e.id) +
                       " in the scene (ids are in scene.json); check the id or detect again");
    checkFingerprint(*s, e, where, o);
    const std::string line = name + " (" + at(edits.file, e.line) + "): surface " +
                             std::to_string(e.id) + " " + describe(e);
    if (e.remove) {
      removeSurface(out, e.id);
      gone[e.id] = name;
      lines.push_back(line);
      continue;
    }
    const double area_before = s->area_m2;
    const std::vector<Region2d> merged = mergedRegions(out, *s, e, gone, where, o);
    reshape(*s, e, merged, where, o);
    for (const int m : e.merge) {
      const Surface* other = findSurface(out, m);
      s->inliers.insert(s->inliers.end(), other->inliers.begin(), other->inliers.end());
      gone[m] = name + " (merged into " + std::to_string(e.id) + ")";
    }
    const double area_after = s->area_m2;
    for (const int m : e.merge) {
      out.surfaces.erase(std::remove_if(out.surfaces.begin(), out.surfaces.end(),
                                        [&](const Surface& x) { return x.id == m; }),
                         out.surfaces.end());
    }
    lines.push_back(line + ", area " + formatFixed(area_before, 1) + " -> " +
                    formatFixed(area_after, 1) + " m2");
  }
  for (std::size_t i = 0; i < edits.keep_out.size(); ++i) {
    out.keep_out.push_back(edits.keep_out[i].volume);
    lines.push_back("keep_out[" + std::to_string(i) + "] (" +
                    at(edits.file, edits.keep_out[i].line) +
                    "): " + describe(edits.keep_out[i].volume));
  }
  scene = std::move(out);
  return lines;
}

void checkKeepOuts(const Scene& scene, const Config& config, const std::vector<int>& surface_ids,
                   const Edits& edits) {
  for (std::size_t i = 0; i < edits.keep_out.size(); ++i) {
    const KeepOut& k = edits.keep_out[i].volume;
    const std::string where = at(edits.file, edits.keep_out[i].line) + ": keep_out[" +
                              std::to_string(i) + "] '" + k.name + "'";
    const auto point = [&](const std::optional<Vec3>& p, const std::string& name) {
      if (p && k.contains(*p))
        throw InputError(where + " contains " + name + " " + formatPoint(*p) +
                         "; move the keep-out or the " + name);
    };
    point(config.flight.home, config.keyOf(&config.flight.home));
    point(config.mission.start, config.keyOf(&config.mission.start));
    for (const int id : surface_ids) {
      const auto it = std::find_if(scene.surfaces.begin(), scene.surfaces.end(),
                                   [&](const Surface& s) { return s.id == id; });
      if (it == scene.surfaces.end()) continue;
      const coverage::FlightStrategy fs = coverage::planFlightStrategy(*it, config.coverage);
      if (!fs.stops.empty() &&
          std::all_of(fs.stops.begin(), fs.stops.end(),
                      [&](const coverage::Stop& st) { return k.contains(st.position); }))
        throw InputError(where + " contains every photo stop of surface " + std::to_string(id) +
                         " (" + std::to_string(fs.stops.size()) +
                         "); shrink it, or delete the surface in the edits");
    }
  }
}

}  // namespace uavip::app
