// Reading mission.json back (io/mission_json.h): kept apart from the writer so that
// readers (export, validate, the fuzz target) need no planning code.

#include <filesystem>

#include "uavip/core/error.h"
#include "uavip/io/json_reader.h"
#include "uavip/io/mission_json.h"

namespace uavip::io {
namespace {

using nlohmann::json;

StopRecord readStop(const JsonReader& r, const json& j, const std::string& f) {
  StopRecord s;
  s.position = r.vec3(r.at(j, "position", f), JsonReader::join(f, "position"));
  s.yaw_deg = r.number(r.at(j, "yaw_deg", f), JsonReader::join(f, "yaw_deg"), -720.0, 720.0, "deg");
  s.gimbal_pitch_deg = r.number(r.at(j, "gimbal_pitch_deg", f),
                                JsonReader::join(f, "gimbal_pitch_deg"), -180.0, 180.0, "deg");
  if (j.contains("problem")) s.problem = r.text(j.at("problem"), JsonReader::join(f, "problem"));
  if (j.contains("target")) s.target = r.vec3(j.at("target"), JsonReader::join(f, "target"));
  return s;
}

/// `camera_model` (mission_json.cpp's cameraModel): pinhole, sensor or footprint.
coverage::Camera readCameraModel(const JsonReader& r, const json& j) {
  const std::string f = "camera_model";
  coverage::Camera c;
  const auto imagePx = [&] {
    const json& px = r.at(j, "image_px", f);
    if (!px.is_array() || px.size() != 2) r.fail(f + ".image_px", "must be [width, height]");
    c.image_w_px = static_cast<int>(r.integer(px[0], f + ".image_px[0]", 1, 1'000'000));
    c.image_h_px = static_cast<int>(r.integer(px[1], f + ".image_px[1]", 1, 1'000'000));
  };
  if (j.contains("pinhole_px")) {
    const json& k = j.at("pinhole_px");
    const std::string fk = f + ".pinhole_px";
    c.pinhole = true;
    c.fx_px = r.number(r.at(k, "fx", fk), fk + ".fx", 1e-6, 1e9, "px");
    c.fy_px = r.number(r.at(k, "fy", fk), fk + ".fy", 1e-6, 1e9, "px");
    c.cx_px = r.number(r.at(k, "cx", fk), fk + ".cx", 0.0, 1e6, "px");
    c.cy_px = r.number(r.at(k, "cy", fk), fk + ".cy", 0.0, 1e6, "px");
    imagePx();
    if (j.contains("gsd_mm_per_px"))
      c.gsd_mm_per_px = r.number(j.at("gsd_mm_per_px"), f + ".gsd_mm_per_px", 0.0, 1e6, "mm/px");
  } else if (j.contains("sensor_mm")) {
    c.from_sensor = true;
    const json& s = j.at("sensor_mm");
    if (!s.is_array() || s.size() != 2) r.fail(f + ".sensor_mm", "must be [width, height]");
    c.sensor_w_mm = r.number(s[0], f + ".sensor_mm[0]", 1e-6, 1e6, "mm");
    c.sensor_h_mm = r.number(s[1], f + ".sensor_mm[1]", 1e-6, 1e6, "mm");
    c.focal_mm = r.number(r.at(j, "focal_mm", f), f + ".focal_mm", 1e-6, 1e6, "mm");
    imagePx();
    c.gsd_mm_per_px =
        r.number(r.at(j, "gsd_mm_per_px", f), f + ".gsd_mm_per_px", 1e-9, 1e6, "mm/px");
  } else {
    const json& fp = r.at(j, "footprint_m", f);
    if (!fp.is_array() || fp.size() != 2) r.fail(f + ".footprint_m", "must be [width, height]");
    c.footprint_w_m = r.number(fp[0], f + ".footprint_m[0]", 1e-6, 1e6, "m");
    c.footprint_h_m = r.number(fp[1], f + ".footprint_m[1]", 1e-6, 1e6, "m");
  }
  return c;
}

SurfaceRecord readSurface(const JsonReader& r, const json& j, const std::string& f) {
  SurfaceRecord s;
  s.surface_id = static_cast<int>(
      r.integer(r.at(j, "surface_id", f), JsonReader::join(f, "surface_id"), 0, 1'000'000));
  s.status = r.text(r.at(j, "status", f), JsonReader::join(f, "status"));
  if (j.contains("kind")) s.kind = r.text(j.at("kind"), JsonReader::join(f, "kind"));
  if (j.contains("camera") && j.at("camera").contains("standoff_m"))
    s.standoff_m = r.number(j.at("camera").at("standoff_m"),
                            JsonReader::join(f, "camera.standoff_m"), 0.0, 1e6, "m");
  if (j.contains("reason")) s.reason = r.text(j.at("reason"), JsonReader::join(f, "reason"));
  const std::string fs = JsonReader::join(f, "stops");
  const json& stops = r.list(r.at(j, "stops", f), fs);
  for (std::size_t k = 0; k < stops.size(); ++k)
    s.stops.push_back(readStop(r, stops[k], JsonReader::item(fs, k)));
  s.waypoints = r.points(r.at(j, "waypoints", f), JsonReader::join(f, "waypoints"));
  return s;
}

SortieRecord readSortie(const JsonReader& r, const json& j, const std::string& f,
                        const MissionRecord& m) {
  SortieRecord s;
  s.waypoints = r.points(r.at(j, "waypoints", f), JsonReader::join(f, "waypoints"));
  if (s.waypoints.size() < 2) r.fail(JsonReader::join(f, "waypoints"), "must list home ... home");
  const std::string fs = JsonReader::join(f, "stops");
  const json& stops = r.list(r.at(j, "stops", f), fs);
  for (std::size_t k = 0; k < stops.size(); ++k) {
    const std::string w = JsonReader::item(fs, k);
    SortieStopRecord st;
    st.surface_id = static_cast<int>(r.integer(r.at(stops[k], "surface_id", w),
                                               JsonReader::join(w, "surface_id"), 0, 1'000'000));
    st.stop = static_cast<std::size_t>(
        r.integer(r.at(stops[k], "stop", w), JsonReader::join(w, "stop"), 0, 1'000'000'000));
    st.waypoint = static_cast<std::size_t>(r.integer(
        r.at(stops[k], "waypoint", w), JsonReader::join(w, "waypoint"), 0, 1'000'000'000));
    const SurfaceRecord* surface = m.surface(st.surface_id);
    const bool later = s.stops.empty() || st.waypoint > s.stops.back().waypoint;
    if (surface == nullptr || st.stop >= surface->stops.size() || !later ||
        st.waypoint >= s.waypoints.size())
      r.fail(w, "names no stop of the mission or no later waypoint of the sortie");
    if ((s.waypoints[st.waypoint] - surface->stops[st.stop].position).norm() > kStopMatchM)
      r.fail(w, "is not at its waypoint; the file was changed or is not a uavip mission");
    s.stops.push_back(st);
  }
  return s;
}

/// A fleet block's status, options (through their table), flight model and makespan.
FleetRecord readFleetSettings(const JsonReader& r, const json& j, const std::string& where) {
  FleetRecord f;
  f.status = r.text(r.at(j, "status", where), where + ".status");
  const json& options = r.at(j, "options", where);
  for (const auto& row : planning::FleetOptions::table().rows()) {
    if (!options.contains(row.key)) continue;
    params::Value v;
    v.numbers = {r.number(options.at(row.key), where + ".options." + row.key)};
    const std::string what = row.problem(v);
    if (!what.empty()) r.fail(where + ".options." + row.key, what);
    row.set(f.options, v);
  }
  const json& model = r.at(j, "model", where);
  const auto field = [&](const char* key, double& out) {
    out = r.number(r.at(model, key, where + ".model"), where + ".model." + key);
  };
  field("cruise_speed_m_s", f.model.cruise_speed_m_s);
  field("climb_speed_m_s", f.model.climb_speed_m_s);
  field("descent_speed_m_s", f.model.descent_speed_m_s);
  field("hover_s", f.model.hover_s);
  field("settle_s", f.model.settle_s);
  field("endurance_s", f.model.endurance_s);
  field("reserve", f.model.reserve);
  try {
    f.model.validate(where + ".model");
  } catch (const InputError& e) {
    r.fail(where + ".model", e.what());
  }
  f.makespan_s = r.number(r.at(j, "makespan_s", where), where + ".makespan_s");
  return f;
}

/// `fleet`: the settings, then each UAV's sorties.
FleetRecord readFleet(const JsonReader& r, const json& j, const MissionRecord& m) {
  FleetRecord f = readFleetSettings(r, j, "fleet");
  const std::string list = JsonReader::join("fleet", "uavs");
  const json& uavs = r.list(r.at(j, "uavs", "fleet"), list);
  for (std::size_t u = 0; u < uavs.size(); ++u) {
    const std::string fu = JsonReader::item(list, u);
    FleetUavRecord rec;
    rec.home = r.vec3(r.at(uavs[u], "home", fu), fu + ".home");
    const json& sorties = r.list(r.at(uavs[u], "sorties", fu), fu + ".sorties");
    for (std::size_t i = 0; i < sorties.size(); ++i) {
      const std::string fs = JsonReader::item(fu + ".sorties", i);
      rec.start_s.push_back(
          r.number(r.at(sorties[i], "start_s", fs), fs + ".start_s", 0.0, 1e9, "s"));
      rec.sorties.push_back(readSortie(r, sorties[i], fs, m));
    }
    f.uavs.push_back(std::move(rec));
  }
  return f;
}

}  // namespace

FleetRecord fleetSettingsFromJson(const json& fleet, const std::string& path,
                                  const std::string& where) {
  return readFleetSettings(JsonReader(path), fleet, where);
}

std::vector<std::vector<planning::MotionPiece>> recordedFleetMotion(const FleetRecord& fleet) {
  std::vector<std::vector<planning::MotionPiece>> motion;
  for (const auto& u : fleet.uavs) {
    std::vector<planning::MotionPiece> m;
    for (std::size_t i = 0; i < u.sorties.size(); ++i) {
      std::vector<std::size_t> at;
      for (const auto& st : u.sorties[i].stops) at.push_back(st.waypoint);
      const auto pieces = planning::sortieMotion(u.sorties[i].waypoints, at, fleet.model,
                                                 fleet.options.takeoff_landing_s, u.start_s[i],
                                                 static_cast<int>(i));
      m.insert(m.end(), pieces.begin(), pieces.end());
    }
    motion.push_back(std::move(m));
  }
  return motion;
}

const SurfaceRecord* MissionRecord::surface(int id) const {
  for (const auto& s : surfaces) {
    if (s.surface_id == id) return &s;
  }
  return nullptr;
}

MissionRecord missionFromJson(const json& j, const std::string& path) {
  const JsonReader r(path);
  if (!j.is_object())
    r.fail("the file", "must be a JSON object (a mission.json written by run or plan)");
  MissionRecord m;
  if (j.contains("inflation_radius_m"))
    m.inflation_radius_m =
        r.number(j.at("inflation_radius_m"), "inflation_radius_m", 1e-6, 1e3, "m");
  if (j.contains("source")) m.source = r.text(j.at("source"), "source");
  if (j.contains("camera_model")) m.camera = readCameraModel(r, j.at("camera_model"));
  if (j.contains("aircraft")) {
    m.drone = r.text(r.at(j.at("aircraft"), "drone", "aircraft"), "aircraft.drone");
    m.payload = r.text(r.at(j.at("aircraft"), "payload", "aircraft"), "aircraft.payload");
  }
  const json& surfaces = r.list(r.at(j, "surfaces", ""), "surfaces");
  for (std::size_t i = 0; i < surfaces.size(); ++i) {
    const std::string f = JsonReader::item("surfaces", i);
    SurfaceRecord s = readSurface(r, surfaces[i], f);
    if (m.surface(s.surface_id) != nullptr)
      r.fail(f + ".surface_id",
             std::to_string(s.surface_id) + " is used by an earlier surface; ids must differ");
    m.surfaces.push_back(std::move(s));
  }
  if (j.contains("flight")) {
    const json& jf = j.at("flight");
    FlightRecord flight;
    flight.status = r.text(r.at(jf, "status", "flight"), "flight.status");
    if (jf.contains("reason")) flight.reason = r.text(jf.at("reason"), "flight.reason");
    const json& sorties = r.list(r.at(jf, "sorties", "flight"), "flight.sorties");
    for (std::size_t i = 0; i < sorties.size(); ++i)
      flight.sorties.push_back(readSortie(r, sorties[i], JsonReader::item("flight.sorties", i), m));
    m.flight = std::move(flight);
  }
  if (j.contains("fleet")) m.fleet = readFleet(r, j.at("fleet"), m);
  if (j.contains("edits")) {
    const json& volumes = r.list(r.at(j.at("edits"), "keep_out", "edits"), "edits.keep_out");
    for (std::size_t i = 0; i < volumes.size(); ++i) {
      const std::string f = JsonReader::item("edits.keep_out", i);
      KeepOut k;
      k.name = r.text(r.at(volumes[i], "name", f), f + ".name");
      const std::string shape = r.text(r.at(volumes[i], "shape", f), f + ".shape");
      if (shape != "box" && shape != "cylinder") r.fail(f + ".shape", "must be box or cylinder");
      k.shape = shape == "box" ? KeepOut::Shape::Box : KeepOut::Shape::Cylinder;
      k.center = r.vec3(r.at(volumes[i], "center", f), f + ".center");
      k.size = r.vec3(r.at(volumes[i], "size", f), f + ".size");
      if (!(k.size.minCoeff() > 0.0)) r.fail(f + ".size", "must be > 0 on every axis");
      k.yaw_deg = r.number(r.at(volumes[i], "yaw_deg", f), f + ".yaw_deg", -360.0, 360.0, "deg");
      m.keep_out.push_back(std::move(k));
    }
  }
  return m;
}

MissionRecord loadMission(const std::string& path) {
  return missionFromJson(JsonReader(path).load(), path);
}

bool isSiteJson(const json& j) {
  if (!j.is_object()) return false;
  const auto it = j.find("format");
  return it != j.end() && it->is_string() && it->get<std::string>() == kSiteFormat;
}

std::map<std::string, MissionRecord> siteMissions(const json& site, const std::string& path) {
  const JsonReader r(path);
  std::map<std::string, MissionRecord> out;
  const json& sections = r.list(r.at(site, "sections", ""), "sections");
  for (std::size_t i = 0; i < sections.size(); ++i) {
    const std::string f = JsonReader::item("sections", i);
    const std::string folder = r.text(r.at(sections[i], "folder", f), f + ".folder");
    if (folder.empty() || folder.find('/') != std::string::npos || folder == "..")
      r.fail(f + ".folder", "must name a folder beside site.json");
    if (r.text(r.at(sections[i], "flight_status", f), f + ".flight_status") != "ok") continue;
    const std::string mission =
        (std::filesystem::path(path).parent_path() / folder / "mission.json").string();
    MissionRecord m = loadMission(mission);
    if (!m.flight) throw InputError(mission + ": no flight; merge the site again");
    out.emplace(folder, std::move(m));
  }
  return out;
}

SiteFleetRecord siteFleetFromJson(const json& site, const std::string& path,
                                  const std::map<std::string, MissionRecord>& missions) {
  const JsonReader r(path);
  SiteFleetRecord out;
  const json& fleet = r.at(site, "fleet", "");
  out.fleet = readFleetSettings(r, fleet, "fleet");
  const std::string uavs_where = JsonReader::join("fleet", "uavs");
  const json& uavs = r.list(r.at(fleet, "uavs", "fleet"), uavs_where);
  for (std::size_t u = 0; u < uavs.size(); ++u) {
    const std::string fu = JsonReader::item(uavs_where, u);
    const json& list = r.list(r.at(uavs[u], "sorties", fu), fu + ".sorties");
    FleetUavRecord rec;
    out.sorties.emplace_back();
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string fs = JsonReader::item(fu + ".sorties", i);
      const std::string folder = r.text(r.at(list[i], "folder", fs), fs + ".folder");
      const auto it = missions.find(folder);
      if (it == missions.end()) r.fail(fs + ".folder", "names no flown section of the site");
      const auto& sorties = it->second.flight->sorties;
      const auto k =
          static_cast<std::size_t>(r.integer(r.at(list[i], "sortie", fs), fs + ".sortie", 1,
                                             static_cast<std::int64_t>(sorties.size())));
      rec.sorties.push_back(sorties[k - 1]);
      rec.start_s.push_back(r.number(r.at(list[i], "start_s", fs), fs + ".start_s", 0.0, 1e9, "s"));
      out.sorties.back().emplace_back(folder, k - 1);
    }
    if (!rec.sorties.empty()) rec.home = rec.sorties.front().waypoints.front();
    out.fleet.uavs.push_back(std::move(rec));
  }
  return out;
}

}  // namespace uavip::io
