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
#include "uavip/io/json_numbers.h"
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
extern const char kEditJs[];
extern const std::size_t kEditJsSize;
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
  void f64(double v) {
    std::uint64_t u = 0;
    std::memcpy(&u, &v, sizeof u);
    u32(static_cast<std::uint32_t>(u & 0xffffffffu));
    u32(static_cast<std::uint32_t>(u >> 32));
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

using io::vec;  // [x, y, z] rounded to 4 decimals, as in mission.json

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
  int uav{0};  ///< the fleet's UAV (1-based) flying it; 0 without a fleet
};

// ---- the recorded mission (strict), and what the page shows beyond MissionRecord

/// A mission record with the extras the page shows (stop targets, camera, coverage, flight).
struct RecordedMission {
  io::MissionRecord rec;
  std::vector<std::vector<StopExtra>> stop_extra;  ///< [surface][stop], as rec.surfaces
  std::vector<json> surface_extra;                 ///< camera, coverage, path_length_m
  json flight_extra = json::object();              ///< length_m, duration_s, home, home_source
  json fleet_extra = json::object();  ///< makespan_s, single_uav_s, closest_approach (a fleet)
};

/// The aimed-at point of each of n stops, where the JSON gives a finite one.
std::vector<StopExtra> stopExtras(const json& stops, std::size_t n) {
  std::vector<StopExtra> extras(n);
  for (std::size_t k = 0; k < n; ++k) {
    const json& t = stops[k].contains("target") ? stops[k].at("target") : json();
    if (t.is_array() && t.size() == 3 && t[0].is_number() && t[1].is_number() && t[2].is_number()) {
      extras[k].target = {t[0].get<double>(), t[1].get<double>(), t[2].get<double>()};
      extras[k].has_target = extras[k].target.allFinite();
    }
  }
  return extras;
}

/// A surface mission's camera, coverage and path length [m] as the page lists them.
json surfaceExtra(const json& sj) {
  json e = json::object();
  if (sj.contains("camera")) e["camera"] = sj.at("camera");
  if (sj.contains("coverage")) e["coverage"] = sj.at("coverage");
  e["path_length_m"] = numberOr(sj, "path_length_m", 0.0);
  return e;
}

/// The flight's length [m], duration [s] and home (only for an "ok" flight).
json flightExtra(const json& mission) {
  json extra = json::object();
  if (!mission.contains("flight") || !mission.at("flight").is_object()) return extra;
  const json& f = mission.at("flight");
  for (const char* k : {"length_m", "duration_s"})
    if (f.contains(k) && f.at(k).is_number()) extra[k] = f.at(k);
  const bool ok = f.contains("status") && f.at("status") == "ok";
  if (ok && f.contains("home") && f.at("home").is_array() && f.at("home").size() == 3)
    extra["home"] = f.at("home");
  if (f.contains("home_source") && f.at("home_source").is_string())
    extra["home_source"] = f.at("home_source");
  return extra;
}

/// The mission JSON read strictly (empty without one), with its extras.
RecordedMission readMission(const json* mission, const std::string& mission_path) {
  RecordedMission m;
  if (mission == nullptr) return m;
  m.rec = io::missionFromJson(*mission, mission_path);
  const json& surfaces = mission->at("surfaces");
  for (std::size_t i = 0; i < m.rec.surfaces.size(); ++i) {
    const json& sj = surfaces[i];
    m.stop_extra.push_back(stopExtras(sj.at("stops"), m.rec.surfaces[i].stops.size()));
    m.surface_extra.push_back(surfaceExtra(sj));
  }
  m.flight_extra = flightExtra(*mission);
  if (mission->contains("fleet")) {
    const json& f = mission->at("fleet");
    for (const char* k : {"makespan_s", "single_uav_s", "lower_bound_s"})
      if (f.contains(k) && f.at(k).is_number()) m.fleet_extra[k] = f.at(k);
    if (f.contains("closest_approach") && f.at("closest_approach").is_object())
      m.fleet_extra["closest_approach"] = f.at("closest_approach");
  }
  return m;
}

// ---- the paths: sorties of an ordered flight, else each flyable surface's own path

/// Whether the mission has an ordered flight ("ok", at least one sortie).
bool flownInOrder(const io::MissionRecord& rec) {
  return rec.flight && rec.flight->status == "ok" && !rec.flight->sorties.empty();
}

/// Colour of path k: palette colour darkened by 35 %.
std::string pathColor(int k) { return hex(render::palette(k).mix(render::kBlack, 0.35)); }

/// One path per sortie, with an entry wherever the next stop's surface changes.
std::vector<PagePath> sortiePaths(const io::FlightRecord& flight) {
  std::vector<PagePath> paths;
  int current = -1;
  for (std::size_t k = 0; k < flight.sorties.size(); ++k) {
    const auto& s = flight.sorties[k];
    PagePath p{"sortie " + std::to_string(k + 1), pathColor(static_cast<int>(k)), s.waypoints, {}};
    for (const auto& st : s.stops) {
      if (st.surface_id == current) continue;
      current = st.surface_id;
      p.entries.emplace_back(st.waypoint, st.surface_id);
    }
    paths.push_back(std::move(p));
  }
  return paths;
}

/// Whether the page shows a fleet: an "ok" fleet block of at least two UAVs with a sortie.
/// (K = 1 or no fleet block: the page of a single UAV.)
bool showsFleet(const io::MissionRecord& rec) {
  if (!rec.fleet || rec.fleet->status != "ok" || rec.fleet->uavs.size() < 2) return false;
  for (const auto& u : rec.fleet->uavs)
    if (!u.sorties.empty()) return true;
  return false;
}

/// One path per sortie of every UAV of the fleet, in its UAV's colour, with an entry
/// wherever the next stop's surface changes.
std::vector<PagePath> fleetPaths(const io::FleetRecord& fleet) {
  std::vector<PagePath> paths;
  for (std::size_t u = 0; u < fleet.uavs.size(); ++u) {
    int current = -1;
    const auto& sorties = fleet.uavs[u].sorties;
    for (std::size_t k = 0; k < sorties.size(); ++k) {
      PagePath p{"uav " + std::to_string(u + 1) + " sortie " + std::to_string(k + 1),
                 pathColor(static_cast<int>(u)),
                 sorties[k].waypoints,
                 {},
                 static_cast<int>(u) + 1};
      for (const auto& st : sorties[k].stops) {
        if (st.surface_id == current) continue;
        current = st.surface_id;
        p.entries.emplace_back(st.waypoint, st.surface_id);
      }
      paths.push_back(std::move(p));
    }
  }
  return paths;
}

/// One path per flyable surface with at least two waypoints.
std::vector<PagePath> surfacePaths(const io::MissionRecord& rec) {
  std::vector<PagePath> paths;
  for (const auto& s : rec.surfaces) {
    if (!s.flyable() || s.waypoints.size() < 2) continue;
    paths.push_back({"surface " + std::to_string(s.surface_id),
                     pathColor(s.surface_id),
                     s.waypoints,
                     {{0, s.surface_id}}});
  }
  return paths;
}

// ---- the box of everything drawn, and its quantiser

/// Box of the cloud, the stops and their targets, the paths and the surface boundaries;
/// [-1, 1]³ when there is nothing to draw.
Aabb drawnBox(const Scene& scene, const RecordedMission& m, const std::vector<PagePath>& paths) {
  Aabb box = boundingBox(scene.cloud);
  for (std::size_t i = 0; i < m.rec.surfaces.size(); ++i) {
    for (std::size_t k = 0; k < m.rec.surfaces[i].stops.size(); ++k) {
      box.extend(m.rec.surfaces[i].stops[k].position);
      if (m.stop_extra[i][k].has_target) box.extend(m.stop_extra[i][k].target);
    }
  }
  for (const auto& p : paths)
    for (const auto& w : p.waypoints) box.extend(w);
  for (const auto& s : scene.surfaces)
    for (const auto& b : s.boundary) box.extend(b);
  if (box.empty())
    box = {Vec3::Constant(-1.0), Vec3::Constant(1.0)};  // nothing to draw: an empty page
  return box;
}

/// The quantiser over a box, each side at least 1 mm.
Quantiser quantiserOver(const Aabb& box) {
  Quantiser q;
  q.min = box.min;
  q.size = (box.max - box.min).cwiseMax(Vec3::Constant(1e-3));
  return q;
}

// ---- the cloud: class and surface of each point, evenly decimated

/// The page's cloud layer: every stride-th point with its class and surface.
struct CloudLayer {
  Bytes pos, cls, sid;
  std::size_t stride{1};
  std::size_t drawn{0};
  std::array<std::size_t, 3> class_count{0, 0, 0};
};

/// Surface inliers (class 1) and obstacle points (class 2), sorted by position.
std::vector<PointClass> pointClasses(const Scene& scene) {
  std::vector<PointClass> classes;
  for (std::size_t i = 0; i < scene.surfaces.size(); ++i)
    for (const auto& p : scene.surfaces[i].inliers)
      classes.push_back({{p.x(), p.y(), p.z()},
                         1,
                         static_cast<std::uint16_t>(std::min<std::size_t>(i, kNoSurface - 1))});
  for (const auto& o : scene.obstacles)
    for (const auto& p : o.points) classes.push_back({{p.x(), p.y(), p.z()}, 2, kNoSurface});
  std::sort(classes.begin(), classes.end());
  return classes;
}

/// The cloud decimated to at most max_points, each point classed by exact position.
CloudLayer cloudLayer(const Scene& scene, const Quantiser& q, std::size_t max_points) {
  const std::vector<PointClass> classes = pointClasses(scene);
  CloudLayer c;
  const std::size_t n = scene.cloud.size();
  c.stride = (n + max_points - 1) / max_points;
  for (std::size_t i = 0; i < n; i += c.stride) {
    const Vec3& p = scene.cloud[i];
    const PointClass probe{{p.x(), p.y(), p.z()}, 0, kNoSurface};
    auto it = std::lower_bound(classes.begin(), classes.end(), probe);
    const bool found = it != classes.end() && it->key == probe.key;
    const PointClass& pc = found ? *it : probe;
    q.put(c.pos, p);
    c.cls.u8(pc.cls);
    c.sid.u16(pc.surface);
    ++c.class_count[pc.cls];
    ++c.drawn;
  }
  return c;
}

// ---- surfaces: boundary, status from the mission

/// What the edit mode (mission_edit.js) needs of a surface: its boundary in metres
/// (the edits file's coordinates), its in-plane axes and its holes' count.
json editJson(const Surface& s) {
  json boundary = json::array();
  for (const auto& p : s.boundary) boundary.push_back(vec(p));
  return {{"boundary_m", boundary},
          {"axis_u", vec(s.axis_u)},
          {"axis_v", vec(s.axis_v)},
          {"holes", s.holes.size()}};
}

/// Each scene surface with its boundary and its status in the mission.
json surfacesJson(const Scene& scene, const io::MissionRecord& rec, const Quantiser& q) {
  json surfaces = json::array();
  for (const Surface& s : scene.surfaces) {
    Bytes b;
    for (const auto& p : s.boundary) q.put(b, p);
    json holes = json::array();
    for (const auto& h : s.holes) {
      Bytes hb;
      for (const auto& p : h) q.put(hb, p);
      holes.push_back(hb.str());
    }
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
              {"boundary_n", s.boundary.size()},
              {"holes", holes},
              {"edit", editJson(s)}};
    surfaces.push_back(e);
  }
  return surfaces;
}

// ---- photo stops

/// The photo stops of all surface missions, and the missions' list entries.
struct StopLayer {
  Bytes pos, tgt, ang, sid, idx, flown;
  std::size_t photos{0}, photos_flown{0}, waypoints{0};
  json missions = json::array();
};

/// A surface mission's entry in the page's list.
json missionJson(const io::SurfaceRecord& s, const json& extra) {
  json m = extra;
  m["surface_id"] = s.surface_id;
  m["status"] = s.status;
  m["reason"] = s.reason;
  m["color"] = hex(render::palette(s.surface_id));
  m["stops"] = s.stops.size();
  m["waypoints"] = s.waypoints.size();
  return m;
}

/// Position, target, yaw and gimbal pitch [deg], mission, index and flown flag of every stop.
StopLayer stopLayer(const RecordedMission& m, const Quantiser& q) {
  StopLayer l;
  for (std::size_t i = 0; i < m.rec.surfaces.size(); ++i) {
    const io::SurfaceRecord& s = m.rec.surfaces[i];
    l.waypoints += s.waypoints.size();
    l.missions.push_back(missionJson(s, m.surface_extra[i]));
    for (std::size_t k = 0; k < s.stops.size(); ++k) {
      const io::StopRecord& st = s.stops[k];
      const StopExtra& x = m.stop_extra[i][k];
      q.put(l.pos, st.position);
      q.put(l.tgt, x.has_target ? x.target : st.position);
      l.ang.f32(st.yaw_deg);
      l.ang.f32(st.gimbal_pitch_deg);
      l.sid.u16(static_cast<unsigned>(std::min<std::size_t>(i, kNoSurface)));
      l.idx.u32(static_cast<std::uint32_t>(k));
      l.flown.u8(st.flown() ? 1 : 0);
      ++l.photos;
      l.photos_flown += st.flown();
    }
  }
  return l;
}

// ---- paths resampled with the clearance at each sample

/// The page's paths, and what the summary counts of them.
struct PathLayer {
  json list = json::array();
  std::size_t flight_waypoints{0};
  double min_clearance{std::numeric_limits<double>::infinity()};  ///< [m]
};

/// Summed length of all paths [m].
double totalLength(const std::vector<PagePath>& paths) {
  double total = 0.0;
  for (const auto& p : paths)
    for (std::size_t k = 1; k < p.waypoints.size(); ++k)
      total += (p.waypoints[k] - p.waypoints[k - 1]).norm();
  return total;
}

/// One path's JSON: its waypoints, and samples at most step [m] apart with their clearance
/// [cm]; lowers min_clearance [m] to the least clearance sampled.
json resampledPath(const PagePath& p, const Quantiser& q, const Clearance& clearance, double step,
                   double& min_clearance) {
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
  json out = {{"label", p.label},
              {"color", p.color},
              {"waypoints", wp.str()},
              {"waypoint_n", p.waypoints.size()},
              {"sample_of_waypoint", sample_of_waypoint.str()},
              {"samples", samples.str()},
              {"sample_n", count},
              {"clearance_cm", clear.str()},
              {"entries", entries}};
  if (p.uav > 0) out["uav"] = p.uav;
  return out;
}

/// All paths resampled to about max_samples samples in all (steps of at least 5 cm), with
/// the clearance to the scene's cloud.
PathLayer pathLayer(const std::vector<PagePath>& paths, const Scene& scene, const Quantiser& q,
                    std::size_t max_samples) {
  const double step = std::max(totalLength(paths) / static_cast<double>(max_samples), 0.05);  // [m]
  const Clearance clearance(scene.cloud, q.min);
  PathLayer l;
  for (const auto& p : paths) {
    l.flight_waypoints += p.waypoints.size();
    l.list.push_back(resampledPath(p, q, clearance, step, l.min_clearance));
  }
  return l;
}

// ---- the fleet: each UAV's motion over the schedule, for the time slider

/// Each UAV's colour, home, sortie count and motion (planning/fleet_types.h, recomputed
/// from the recorded waypoints and flight model by io::recordedFleetMotion): per piece
/// t0, t1 [s], then a and b [m] relative to the box's min corner, as float64.
json fleetJson(const RecordedMission& m, const Quantiser& q) {
  const io::FleetRecord& fleet = *m.rec.fleet;
  const auto motion = io::recordedFleetMotion(fleet);
  json uavs = json::array();
  for (std::size_t u = 0; u < fleet.uavs.size(); ++u) {
    Bytes pieces;
    for (const auto& p : motion[u]) {
      pieces.f64(p.t0);
      pieces.f64(p.t1);
      for (const Vec3& x : {p.a, p.b})
        for (int a = 0; a < 3; ++a) pieces.f64(x[a] - q.min[a]);
    }
    uavs.push_back({{"uav", u + 1},
                    {"color", pathColor(static_cast<int>(u))},
                    {"home", vec(fleet.uavs[u].home)},
                    {"sorties", fleet.uavs[u].sorties.size()},
                    {"pieces", pieces.str()},
                    {"piece_n", motion[u].size()}});
  }
  json out = m.fleet_extra;
  using planning::FleetOptions;  // the keys through the fleet's table
  out[FleetOptions::keyOf(&FleetOptions::separation_m)] = fleet.options.separation_m;
  out[FleetOptions::keyOf(&FleetOptions::slack_s)] = fleet.options.slack_s;
  out["uavs"] = uavs;
  return out;
}

// ---- the summary line and the counts

/// What the page draws, as the summary and the data both need it.
struct PageLayers {
  const Scene& scene;
  const RecordedMission& m;
  bool has_mission;
  bool flown;
  bool fleet;  ///< the paths are the fleet's sorties (showsFleet)
  const CloudLayer& cloud;
  const StopLayer& stops;
  const PathLayer& paths;
  std::size_t sorties() const {
    if (fleet) {
      std::size_t n = 0;
      for (const auto& u : m.rec.fleet->uavs) n += u.sorties.size();
      return n;
    }
    return flown ? m.rec.flight->sorties.size() : 0;
  }
};

/// The one-line summary under the heading.
std::string summaryLine(const PageLayers& l) {
  const Scene& scene = l.scene;
  std::ostringstream line;
  line << scene.cloud.size() << " cloud points"
       << (l.cloud.drawn < scene.cloud.size()
               ? " (" + std::to_string(l.cloud.drawn) + " in the page)"
               : std::string())
       << ", " << scene.surfaces.size() << " surfaces, " << scene.obstacles.size()
       << " obstacle clusters";
  if (l.has_mission) {
    const io::MissionRecord& rec = l.m.rec;
    std::size_t ok = 0;
    for (const auto& s : rec.surfaces) ok += s.flyable();
    line << " | " << rec.surfaces.size() << " surfaces planned, " << ok
         << " with a flight: " << l.stops.photos << " photo stops, " << l.stops.waypoints
         << " waypoints";
    if (l.fleet) {
      line << " | fleet of " << l.m.rec.fleet->uavs.size() << " UAVs, " << l.sorties()
           << " sorties, makespan "
           << formatFixed(numberOr(l.m.fleet_extra, "makespan_s", 0.0) / 60.0, 1)
           << " min (one UAV: "
           << formatFixed(numberOr(l.m.fleet_extra, "single_uav_s", 0.0) / 60.0, 1) << " min)";
    } else if (l.flown) {
      const std::size_t sorties = l.sorties();
      line << " | flight " << formatFixed(numberOr(l.m.flight_extra, "length_m", 0.0), 1) << " m, "
           << formatFixed(numberOr(l.m.flight_extra, "duration_s", 0.0) / 60.0, 1) << " min, "
           << sorties << " sortie" << (sorties == 1 ? "" : "s");
    } else if (rec.flight) {
      line << " | no ordered flight (" << rec.flight->status << ")";
    }
  }
  line << " | local ENU frame, metres";
  return line.str();
}

/// The counts the page's test and tools read (uavip-summary).
json summaryJson(const PageLayers& l) {
  const double c = l.paths.min_clearance;
  json out = {{"format", "uavip-mission-page"},
              {"version", 1},
              {"photos", l.stops.photos},
              {"photos_flown", l.stops.photos_flown},
              {"waypoints", l.stops.waypoints},
              {"flight_waypoints", l.paths.flight_waypoints},
              {"sorties", l.sorties()},
              {"surfaces_planned", l.m.rec.surfaces.size()},
              {"scene_surfaces", l.scene.surfaces.size()},
              {"obstacles", l.scene.obstacles.size()},
              {"cloud_points", l.scene.cloud.size()},
              {"cloud_points_drawn", l.cloud.drawn},
              {"min_clearance_m",
               std::isfinite(c) ? json(std::round(c * 1000.0) / 1000.0) : json(nullptr)}};
  if (l.fleet) out["uavs"] = l.m.rec.fleet->uavs.size();
  return out;
}

// ---- the data the page's script draws

/// Everything the page's script draws (uavip-data).
json dataJson(const PageLayers& l, const json& surfaces, const Quantiser& q,
              const MissionPageOptions& options) {
  const double spacing = l.scene.measured ? l.scene.measured->spacing_m : 0.0;
  const double inflation = l.m.rec.inflation_radius_m;
  const CloudLayer& c = l.cloud;
  const StopLayer& s = l.stops;
  json out = {{"title", options.title},
              {"summary_line", summaryLine(l)},
              {"box_min", vec(q.min)},
              {"box_size", vec(q.size)},
              {"spacing_m", spacing},
              {"inflation_radius_m", std::isfinite(options.clearance_m) ? json(options.clearance_m)
                                     : std::isfinite(inflation)         ? json(inflation)
                                                                        : json(nullptr)},
              {"colors",
               {{"other", hex(render::Color{0.78, 0.78, 0.78})},
                {"obstacle", hex(render::Color{0.30, 0.30, 0.30})}}},
              {"cloud",
               {{"n", c.drawn},
                {"stride", c.stride},
                {"by_class", c.class_count},
                {"pos", c.pos.str()},
                {"cls", c.cls.str()},
                {"sid", c.sid.str()}}},
              {"surfaces", surfaces},
              {"missions", s.missions},
              {"stops",
               {{"n", s.photos},
                {"pos", s.pos.str()},
                {"target", s.tgt.str()},
                {"angles", s.ang.str()},
                {"mission", s.sid.str()},
                {"index", s.idx.str()},
                {"flown", s.flown.str()}}},
              {"flown", l.flown},
              {"flight", l.m.flight_extra},
              {"paths", l.paths.list}};
  if (l.fleet) out["fleet"] = fleetJson(l.m, q);
  return out;
}

// ---- the HTML document

/// The page up to the title text.
constexpr const char* kHeadOpen =
    "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<meta name=\"viewport\" "
    "content=\"width=device-width, initial-scale=1\">\n<title>";

/// The page from the end of the title to the summary JSON: style and the side panel's
/// and the view's markup, which the page's script fills.
constexpr const char* kHeadRestAndBody = R"(</title>
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
<h2>Edit</h2>
<div id="edit"></div>
</div>
<div id="view"><div id="labels"></div>
<svg id="north" width="46" height="56" viewBox="-23 -30 46 56"><circle r="20" fill="#fff" fill-opacity="0.8" stroke="#888"/><g id="northarrow"><path d="M0,-17 L6,4 L0,0 L-6,4 Z" fill="#c00"/><text y="18" text-anchor="middle" font-size="11" font-weight="bold">N</text></g></svg>
<div id="scale"><div id="scalelabel"></div><div id="scalebar"></div></div>
<div id="status"></div>
</div>
<div id="uavip-state" hidden></div>
<script type="application/json" id="uavip-summary">)";

/// The self-contained page: markup, the summary and data JSON, three.js and the page's script.
/// The #uavip-geo block of a page (io::GeoFit), or null.
json geoJson(const std::optional<io::GeoFit>& geo) {
  if (!geo) return nullptr;
  return {{"centre", {geo->centre.x(), geo->centre.y(), geo->centre.z()}},
          {"half", {geo->half.x(), geo->half.y(), geo->half.z()}},
          {"lat", geo->lat},
          {"lon", geo->lon},
          {"h", geo->h},
          {"max_error_m", geo->max_error_m},
          {"crs", geo->crs}};
}

std::string htmlDocument(const std::string& title, const json& summary, const json& data,
                         const json& geo, std::size_t cloud_bytes) {
  std::string html;
  html.reserve(embeddedThreeJs().size() + cloud_bytes * 2 + 100000);
  html += kHeadOpen;
  html += markupEscaped(title);
  html += kHeadRestAndBody;
  html += scriptJson(summary);
  html += "</script>\n<script type=\"application/json\" id=\"uavip-data\">";
  html += scriptJson(data);
  if (!geo.is_null()) {
    html += "</script>\n<script type=\"application/json\" id=\"uavip-geo\">";
    html += scriptJson(geo);
  }
  html += "</script>\n<script>\n";
  html += embeddedThreeJs();
  html += "\n</script>\n<script>\n";
  html += std::string(page_assets::kPageJs, page_assets::kPageJsSize);
  html += "\n</script>\n<script>\n";
  html += std::string(page_assets::kEditJs, page_assets::kEditJsSize);
  html += "\n</script>\n</body></html>\n";
  return html;
}

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
  const RecordedMission m = readMission(mission, mission_path);
  const bool flown = flownInOrder(m.rec);
  const bool fleet = showsFleet(m.rec);
  const std::vector<PagePath> paths = fleet   ? fleetPaths(*m.rec.fleet)
                                      : flown ? sortiePaths(*m.rec.flight)
                                              : surfacePaths(m.rec);
  const Quantiser q = quantiserOver(drawnBox(scene, m, paths));
  const CloudLayer cloud = cloudLayer(scene, q, options.max_cloud_points);
  const json surfaces = surfacesJson(scene, m.rec, q);
  const StopLayer stops = stopLayer(m, q);
  const PathLayer path_layer = pathLayer(paths, scene, q, options.max_path_samples);
  const PageLayers layers{scene, m,     mission != nullptr, flown || fleet, fleet,
                          cloud, stops, path_layer};
  return htmlDocument(options.title, summaryJson(layers), dataJson(layers, surfaces, q, options),
                      geoJson(options.geo), cloud.pos.b.size());
}

std::string missionPage(const Scene& scene, const std::vector<planning::SurfaceMission>& missions,
                        const planning::FlightPlan* flight, const MissionPageOptions& options,
                        const planning::FleetPlan* fleet) {
  json doc = io::missionToJson(missions, json::object());
  if (flight != nullptr) doc["flight"] = io::flightToJson(*flight, planning::FlightModel{});
  if (fleet != nullptr) doc["fleet"] = io::fleetToJson(*fleet);
  return missionPage(scene, &doc, options, "mission");
}

}  // namespace uavip::view
