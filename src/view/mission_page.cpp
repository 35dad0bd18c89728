// OUT/mission.html: the mission as one self-contained 3D page (view/mission_page.h).
// The page's script is src/view/mission_page.js; both it and three.js are compiled
// into the binary (CMake generates uavip_page_assets.cpp from the files).

#include "uavip/view/mission_page.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "uavip/core/error.h"
#include "uavip/core/geometry.h"
#include "uavip/core/neighbour_index.h"
#include "uavip/core/text.h"
#include "uavip/io/mission_json.h"
#include "uavip/render/figure.h"

namespace uavip::view {

// Generated at build time (cmake/embed_text.cmake): NUL-terminated texts.
namespace page_assets {
extern const char kThreeJs[];
extern const std::size_t kThreeJsSize;
extern const char kOrbitControlsJs[];
extern const std::size_t kOrbitControlsJsSize;
extern const char kPageJs[];
extern const std::size_t kPageJsSize;
}  // namespace page_assets

namespace {

using nlohmann::json;

std::string base64(const std::vector<std::uint8_t>& bytes) {
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const std::uint32_t v =
        (std::uint32_t{bytes[i]} << 16) | (std::uint32_t{bytes[i + 1]} << 8) | bytes[i + 2];
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += kAlphabet[(v >> 6) & 63];
    out += kAlphabet[v & 63];
  }
  if (i < bytes.size()) {
    const bool two = i + 1 < bytes.size();
    const std::uint32_t v =
        (std::uint32_t{bytes[i]} << 16) | (two ? std::uint32_t{bytes[i + 1]} << 8 : 0u);
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += two ? kAlphabet[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

/// Little-endian byte buffer (the page reads it with typed arrays, which are
/// little-endian on every browser platform).
struct Bytes {
  std::vector<std::uint8_t> b;
  void u8(unsigned v) { b.push_back(static_cast<std::uint8_t>(v)); }
  void u16(unsigned v) {
    b.push_back(static_cast<std::uint8_t>(v & 0xff));
    b.push_back(static_cast<std::uint8_t>((v >> 8) & 0xff));
  }
  void u32(std::uint32_t v) {
    for (int k = 0; k < 4; ++k) b.push_back(static_cast<std::uint8_t>((v >> (8 * k)) & 0xff));
  }
  void f32(double v) {
    const float f = static_cast<float>(v);
    std::uint32_t u = 0;
    std::memcpy(&u, &f, sizeof u);
    u32(u);
  }
  std::string str() const { return base64(b); }
};

/// Positions as 16 bits per axis over a box: p = min + q / 65535 · size.
struct Quantiser {
  Vec3 min{Vec3::Zero()};
  Vec3 size{Vec3::Ones()};
  void put(Bytes& out, const Vec3& p) const {
    for (int a = 0; a < 3; ++a) {
      const double t = std::clamp((p[a] - min[a]) / size[a], 0.0, 1.0);
      out.u16(static_cast<unsigned>(std::lround(t * 65535.0)));
    }
  }
};

std::string hex(const render::Color& c) {
  char s[8];
  std::snprintf(s, sizeof s, "#%02x%02x%02x", c.red8(), c.green8(), c.blue8());
  return s;
}

json vec(const Vec3& p) {
  auto r = [](double v) { return std::round(v * 1e4) / 1e4; };
  return json::array({r(p.x()), r(p.y()), r(p.z())});
}

/// Text for inside an HTML element.
std::string htmlEscape(const std::string& s) {
  std::string out;
  for (const char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

/// JSON text safe inside <script>: no "</" (which could close the element).
std::string scriptJson(const json& j) {
  std::string s = j.dump();
  std::string out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '<' && i + 1 < s.size() && s[i + 1] == '/') {
      out += "<\\/";
      ++i;
    } else {
      out += s[i];
    }
  }
  return out;
}

/// Class of a cloud point: 0 other, 1 surface, 2 obstacle; surface: index in scene.surfaces.
struct PointClass {
  std::array<double, 3> key;
  std::uint8_t cls;
  std::uint16_t surface;
  bool operator<(const PointClass& o) const { return key < o.key; }
};

constexpr unsigned kNoSurface = 65535;

/// What the page needs of a recorded mission beyond MissionRecord.
struct StopExtra {
  Vec3 target{Vec3::Zero()};
  bool has_target{false};
};

double numberOr(const json& j, const char* key, double fallback) {
  if (!j.is_object() || !j.contains(key) || !j.at(key).is_number()) return fallback;
  return j.at(key).get<double>();
}

/// The nearest cloud point's distance for many query points [m].
class Clearance {
 public:
  Clearance(const PointList& cloud, const Vec3& origin) {
    if (!cloud.empty()) tree_ = std::make_unique<NeighbourIndex>(cloud, origin);
  }
  double at(const Vec3& p) const {
    if (!tree_) return std::numeric_limits<double>::infinity();
    float d2 = 0.0f;
    if (tree_->nearestTo(p, &d2) < 0) return std::numeric_limits<double>::infinity();
    return std::sqrt(static_cast<double>(d2));
  }

 private:
  std::unique_ptr<NeighbourIndex> tree_;  ///< floats relative to the page's origin
};

/// One polyline of the flight: a sortie, or a surface's own path.
struct PagePath {
  std::string label;
  std::string color;
  PointList waypoints;
  /// Where a surface is entered: (waypoint, surface id), numbered in flight order.
  std::vector<std::pair<std::size_t, int>> entries;
};

}  // namespace

void MissionPageOptions::validate() const {
  if (max_cloud_points < 1)
    throw InputError("mission page: max_cloud_points is 0; give at least 1 point to draw");
  if (!std::isnan(clearance_m) && !(clearance_m > 0.0 && std::isfinite(clearance_m)))
    throw InputError("mission page: clearance_m " + std::to_string(clearance_m) +
                     " must be a positive number of metres");
  if (max_path_samples < 2)
    throw InputError("mission page: max_path_samples is " + std::to_string(max_path_samples) +
                     "; give at least 2");
}

const std::string& embeddedThreeJs() {
  static const std::string text =
      std::string(page_assets::kThreeJs, page_assets::kThreeJsSize) + "\n" +
      std::string(page_assets::kOrbitControlsJs, page_assets::kOrbitControlsJsSize);
  return text;
}

std::string missionPage(const Scene& scene, const json* mission, const MissionPageOptions& options,
                        const std::string& mission_path) {
  options.validate();

  // ---- the recorded mission (strict), and what the page shows beyond MissionRecord
  io::MissionRecord rec;
  std::vector<std::vector<StopExtra>> stop_extra;
  std::vector<json> surface_extra;
  json flight_extra = json::object();
  if (mission != nullptr) {
    rec = io::missionFromJson(*mission, mission_path);
    const json& surfaces = mission->at("surfaces");
    for (std::size_t i = 0; i < rec.surfaces.size(); ++i) {
      const json& sj = surfaces[i];
      std::vector<StopExtra> extras(rec.surfaces[i].stops.size());
      const json& stops = sj.at("stops");
      for (std::size_t k = 0; k < extras.size(); ++k) {
        const json& t = stops[k].contains("target") ? stops[k].at("target") : json();
        if (t.is_array() && t.size() == 3 && t[0].is_number() && t[1].is_number() &&
            t[2].is_number()) {
          extras[k].target = {t[0].get<double>(), t[1].get<double>(), t[2].get<double>()};
          extras[k].has_target = extras[k].target.allFinite();
        }
      }
      stop_extra.push_back(std::move(extras));
      json e = json::object();
      if (sj.contains("camera")) e["camera"] = sj.at("camera");
      if (sj.contains("coverage")) e["coverage"] = sj.at("coverage");
      e["path_length_m"] = numberOr(sj, "path_length_m", 0.0);
      surface_extra.push_back(e);
    }
    if (mission->contains("flight") && mission->at("flight").is_object()) {
      const json& f = mission->at("flight");
      for (const char* k : {"length_m", "duration_s"})
        if (f.contains(k) && f.at(k).is_number()) flight_extra[k] = f.at(k);
      const bool ok = f.contains("status") && f.at("status") == "ok";
      if (ok && f.contains("home") && f.at("home").is_array() && f.at("home").size() == 3)
        flight_extra["home"] = f.at("home");
      if (f.contains("home_source") && f.at("home_source").is_string())
        flight_extra["home_source"] = f.at("home_source");
    }
  }

  // ---- the paths: sorties of an ordered flight, else each flyable surface's own path
  std::vector<PagePath> paths;
  const bool flown = rec.flight && rec.flight->status == "ok" && !rec.flight->sorties.empty();
  if (flown) {
    int current = -1;
    for (std::size_t k = 0; k < rec.flight->sorties.size(); ++k) {
      const auto& s = rec.flight->sorties[k];
      PagePath p{"sortie " + std::to_string(k + 1),
                 hex(render::palette(static_cast<int>(k)).mix(render::kBlack, 0.35)),
                 s.waypoints,
                 {}};
      for (const auto& st : s.stops) {
        if (st.surface_id == current) continue;
        current = st.surface_id;
        p.entries.emplace_back(st.waypoint, st.surface_id);
      }
      paths.push_back(std::move(p));
    }
  } else {
    for (const auto& s : rec.surfaces) {
      if (!s.flyable() || s.waypoints.size() < 2) continue;
      paths.push_back({"surface " + std::to_string(s.surface_id),
                       hex(render::palette(s.surface_id).mix(render::kBlack, 0.35)),
                       s.waypoints,
                       {{0, s.surface_id}}});
    }
  }

  // ---- the box of everything drawn, and its quantiser
  Aabb box = boundingBox(scene.cloud);
  for (std::size_t i = 0; i < rec.surfaces.size(); ++i) {
    for (std::size_t k = 0; k < rec.surfaces[i].stops.size(); ++k) {
      box.extend(rec.surfaces[i].stops[k].position);
      if (stop_extra[i][k].has_target) box.extend(stop_extra[i][k].target);
    }
  }
  for (const auto& p : paths)
    for (const auto& w : p.waypoints) box.extend(w);
  for (const auto& s : scene.surfaces)
    for (const auto& b : s.boundary) box.extend(b);
  if (box.empty())
    box = {Vec3::Constant(-1.0), Vec3::Constant(1.0)};  // nothing to draw: an empty page
  Quantiser q;
  q.min = box.min;
  q.size = (box.max - box.min).cwiseMax(Vec3::Constant(1e-3));

  // ---- the cloud: class and surface of each point, evenly decimated
  std::vector<PointClass> classes;
  for (std::size_t i = 0; i < scene.surfaces.size(); ++i)
    for (const auto& p : scene.surfaces[i].inliers)
      classes.push_back({{p.x(), p.y(), p.z()},
                         1,
                         static_cast<std::uint16_t>(std::min<std::size_t>(i, kNoSurface - 1))});
  for (const auto& o : scene.obstacles)
    for (const auto& p : o.points) classes.push_back({{p.x(), p.y(), p.z()}, 2, kNoSurface});
  std::sort(classes.begin(), classes.end());
  const std::size_t n = scene.cloud.size();
  const std::size_t stride = (n + options.max_cloud_points - 1) / options.max_cloud_points;
  Bytes cloud_pos, cloud_cls, cloud_sid;
  std::size_t drawn = 0;
  std::array<std::size_t, 3> class_count{0, 0, 0};
  for (std::size_t i = 0; i < n; i += stride) {
    const Vec3& p = scene.cloud[i];
    const PointClass probe{{p.x(), p.y(), p.z()}, 0, kNoSurface};
    auto it = std::lower_bound(classes.begin(), classes.end(), probe);
    const bool found = it != classes.end() && it->key == probe.key;
    const PointClass& c = found ? *it : probe;
    q.put(cloud_pos, p);
    cloud_cls.u8(c.cls);
    cloud_sid.u16(c.surface);
    ++class_count[c.cls];
    ++drawn;
  }

  // ---- surfaces: boundary, status from the mission
  json surfaces = json::array();
  for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
    const Surface& s = scene.surfaces[i];
    Bytes b;
    for (const auto& p : s.boundary) q.put(b, p);
    const io::SurfaceRecord* r = rec.surface(s.id);
    json e = {{"id", s.id},
              {"color", hex(render::palette(s.id))},
              {"status", r != nullptr ? r->status : std::string("not planned")},
              {"reason", r != nullptr ? r->reason : std::string()},
              {"area_m2", std::round(s.area_m2 * 100.0) / 100.0},
              {"points", s.inliers.size()},
              {"normal", vec(s.plane.normal)},
              {"centroid", vec(s.centroid)},
              {"boundary", b.str()},
              {"boundary_n", s.boundary.size()}};
    surfaces.push_back(e);
  }

  // ---- photo stops
  Bytes stop_pos, stop_tgt, stop_ang, stop_sid, stop_idx, stop_flown;
  std::size_t photos = 0, photos_flown = 0, waypoints = 0;
  json missions = json::array();
  for (std::size_t i = 0; i < rec.surfaces.size(); ++i) {
    const io::SurfaceRecord& s = rec.surfaces[i];
    waypoints += s.waypoints.size();
    json m = surface_extra[i];
    m["surface_id"] = s.surface_id;
    m["status"] = s.status;
    m["reason"] = s.reason;
    m["color"] = hex(render::palette(s.surface_id));
    m["stops"] = s.stops.size();
    m["waypoints"] = s.waypoints.size();
    missions.push_back(m);
    for (std::size_t k = 0; k < s.stops.size(); ++k) {
      const io::StopRecord& st = s.stops[k];
      q.put(stop_pos, st.position);
      q.put(stop_tgt, stop_extra[i][k].has_target ? stop_extra[i][k].target : st.position);
      stop_ang.f32(st.yaw_deg);
      stop_ang.f32(st.gimbal_pitch_deg);
      stop_sid.u16(static_cast<unsigned>(std::min<std::size_t>(i, kNoSurface)));
      stop_idx.u32(static_cast<std::uint32_t>(k));
      stop_flown.u8(st.flown() ? 1 : 0);
      ++photos;
      photos_flown += st.flown();
    }
  }

  // ---- paths resampled with the clearance at each sample
  double total_length = 0.0;
  for (const auto& p : paths)
    for (std::size_t k = 1; k < p.waypoints.size(); ++k)
      total_length += (p.waypoints[k] - p.waypoints[k - 1]).norm();
  const double step =
      std::max(total_length / static_cast<double>(options.max_path_samples), 0.05);  // [m]
  const Clearance clearance(scene.cloud, box.min);
  json path_list = json::array();
  std::size_t flight_waypoints = 0;
  double min_clearance = std::numeric_limits<double>::infinity();
  for (const auto& p : paths) {
    flight_waypoints += p.waypoints.size();
    Bytes wp, samples, clear, sample_of_waypoint;
    std::size_t count = 0;
    auto sample = [&](const Vec3& x) {
      q.put(samples, x);
      const double c = clearance.at(x);
      min_clearance = std::min(min_clearance, c);
      clear.u16(static_cast<unsigned>(std::min(std::lround(c * 100.0), 65535L)));  // [cm]
      ++count;
    };
    for (std::size_t k = 0; k < p.waypoints.size(); ++k) {
      q.put(wp, p.waypoints[k]);
      sample_of_waypoint.u32(static_cast<std::uint32_t>(count));
      sample(p.waypoints[k]);
      if (k + 1 == p.waypoints.size()) break;
      const Vec3 a = p.waypoints[k], b = p.waypoints[k + 1];
      const auto pieces = static_cast<std::size_t>(std::ceil((b - a).norm() / step));
      for (std::size_t j = 1; j < pieces; ++j)
        sample(a + (b - a) * (static_cast<double>(j) / static_cast<double>(pieces)));
    }
    json entries = json::array();
    for (const auto& [w, id] : p.entries) entries.push_back({w, id});
    path_list.push_back({{"label", p.label},
                         {"color", p.color},
                         {"waypoints", wp.str()},
                         {"waypoint_n", p.waypoints.size()},
                         {"sample_of_waypoint", sample_of_waypoint.str()},
                         {"samples", samples.str()},
                         {"sample_n", count},
                         {"clearance_cm", clear.str()},
                         {"entries", entries}});
  }

  // ---- the summary line and the counts
  const std::size_t sorties = flown ? rec.flight->sorties.size() : 0;
  std::ostringstream line;
  line << scene.cloud.size() << " cloud points"
       << (drawn < scene.cloud.size() ? " (" + std::to_string(drawn) + " in the page)"
                                      : std::string())
       << ", " << scene.surfaces.size() << " surfaces, " << scene.obstacles.size()
       << " obstacle clusters";
  if (mission != nullptr) {
    std::size_t ok = 0;
    for (const auto& s : rec.surfaces) ok += s.flyable();
    line << " | " << rec.surfaces.size() << " surfaces planned, " << ok
         << " with a flight: " << photos << " photo stops, " << waypoints << " waypoints";
    if (flown) {
      line << " | flight " << formatFixed(numberOr(flight_extra, "length_m", 0.0), 1) << " m, "
           << formatFixed(numberOr(flight_extra, "duration_s", 0.0) / 60.0, 1) << " min, "
           << sorties << " sortie" << (sorties == 1 ? "" : "s");
    } else if (rec.flight) {
      line << " | no ordered flight (" << rec.flight->status << ")";
    }
  }
  line << " | local ENU frame, metres";

  json summary = {{"format", "uavip-mission-page"},
                  {"version", 1},
                  {"photos", photos},
                  {"photos_flown", photos_flown},
                  {"waypoints", waypoints},
                  {"flight_waypoints", flight_waypoints},
                  {"sorties", sorties},
                  {"surfaces_planned", rec.surfaces.size()},
                  {"scene_surfaces", scene.surfaces.size()},
                  {"obstacles", scene.obstacles.size()},
                  {"cloud_points", scene.cloud.size()},
                  {"cloud_points_drawn", drawn},
                  {"min_clearance_m", std::isfinite(min_clearance)
                                          ? json(std::round(min_clearance * 1000.0) / 1000.0)
                                          : json(nullptr)}};

  const double spacing = scene.measured ? scene.measured->spacing_m : 0.0;
  json data = {
      {"title", options.title},
      {"summary_line", line.str()},
      {"box_min", vec(q.min)},
      {"box_size", vec(q.size)},
      {"spacing_m", spacing},
      {"inflation_radius_m", std::isfinite(options.clearance_m)      ? json(options.clearance_m)
                             : std::isfinite(rec.inflation_radius_m) ? json(rec.inflation_radius_m)
                                                                     : json(nullptr)},
      {"colors",
       {{"other", hex(render::Color{0.78, 0.78, 0.78})},
        {"obstacle", hex(render::Color{0.30, 0.30, 0.30})}}},
      {"cloud",
       {{"n", drawn},
        {"stride", stride},
        {"by_class", class_count},
        {"pos", cloud_pos.str()},
        {"cls", cloud_cls.str()},
        {"sid", cloud_sid.str()}}},
      {"surfaces", surfaces},
      {"missions", missions},
      {"stops",
       {{"n", photos},
        {"pos", stop_pos.str()},
        {"target", stop_tgt.str()},
        {"angles", stop_ang.str()},
        {"mission", stop_sid.str()},
        {"index", stop_idx.str()},
        {"flown", stop_flown.str()}}},
      {"flown", flown},
      {"flight", flight_extra},
      {"paths", path_list}};

  std::string html;
  html.reserve(embeddedThreeJs().size() + cloud_pos.b.size() * 2 + 100000);
  html +=
      "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<meta name=\"viewport\" "
      "content=\"width=device-width, initial-scale=1\">\n<title>";
  html += htmlEscape(options.title);
  html += R"(</title>
<!-- uavip mission page (issue 22): three.js r111 (MIT licence, threejs.org) and the data are inlined; no network. -->
<style>
html,body{margin:0;height:100%;overflow:hidden;font:13px/1.35 sans-serif;background:#fff;color:#222}
#side{position:absolute;left:0;top:0;bottom:0;width:270px;overflow:auto;padding:8px 10px;box-sizing:border-box;border-right:1px solid #ccc;background:#f7f7f7}
#view{position:absolute;left:270px;top:0;right:0;bottom:0}
#view canvas{display:block}
h1{font-size:15px;margin:0 0 4px}
h2{font-size:13px;margin:10px 0 3px}
#summary{font-size:12px;color:#444}
button{font-size:12px;margin:1px}
label{display:block;white-space:nowrap}
.sw{display:inline-block;width:11px;height:11px;margin-right:4px;vertical-align:-1px;border:1px solid #0004}
#pick{font-size:12px;white-space:pre-wrap;background:#fff;border:1px solid #ddd;padding:4px;min-height:2em}
#labels{position:absolute;left:0;top:0;right:0;bottom:0;pointer-events:none;overflow:hidden}
.lbl{position:absolute;transform:translate(-50%,-50%);font:bold 12px sans-serif;color:#000;text-shadow:0 0 2px #fff,0 0 2px #fff;white-space:nowrap}
#north{position:absolute;right:10px;top:10px;pointer-events:none}
#scale{position:absolute;left:12px;bottom:12px;pointer-events:none;font:12px sans-serif}
#scalebar{height:6px;border:1px solid #000;border-top:none}
#ramp{height:10px;width:200px;border:1px solid #999}
#status{position:absolute;right:10px;bottom:8px;font-size:11px;color:#666;pointer-events:none}
</style></head><body>
<div id="side">
<h1 id="heading"></h1>
<div id="summary"></div>
<h2>View</h2>
<div><button data-view="orbit">orbit</button><button data-view="top">top</button><button data-view="front">front</button><button data-view="side">side</button><button data-view="fit">fit all</button></div>
<h2>Layers</h2>
<div id="layers"></div>
<h2>Cloud colour</h2>
<div id="legend-cloud"></div>
<h2>Path</h2>
<div id="legend-path"></div>
<h2>Picked</h2>
<div id="pick">Click a photo (frustum) to see it; shift-click two cloud points for their distance.</div>
</div>
<div id="view"><div id="labels"></div>
<svg id="north" width="46" height="56" viewBox="-23 -30 46 56"><circle r="20" fill="#fff" fill-opacity="0.8" stroke="#888"/><g id="northarrow"><path d="M0,-17 L6,4 L0,0 L-6,4 Z" fill="#c00"/><text y="18" text-anchor="middle" font-size="11" font-weight="bold">N</text></g></svg>
<div id="scale"><div id="scalelabel"></div><div id="scalebar"></div></div>
<div id="status"></div>
</div>
<div id="uavip-state" hidden></div>
<script type="application/json" id="uavip-summary">)";
  html += scriptJson(summary);
  html += "</script>\n<script type=\"application/json\" id=\"uavip-data\">";
  html += scriptJson(data);
  html += "</script>\n<script>\n";
  html += embeddedThreeJs();
  html += "\n</script>\n<script>\n";
  html += std::string(page_assets::kPageJs, page_assets::kPageJsSize);
  html += "\n</script>\n</body></html>\n";
  return html;
}

std::string missionPage(const Scene& scene, const std::vector<planning::SurfaceMission>& missions,
                        const planning::FlightPlan* flight, const MissionPageOptions& options) {
  json doc = io::missionToJson(missions, json::object());
  if (flight != nullptr) doc["flight"] = io::flightToJson(*flight, planning::FlightModel{});
  return missionPage(scene, &doc, options, "mission");
}

}  // namespace uavip::view
