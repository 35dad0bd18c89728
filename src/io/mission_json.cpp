#include "uavip/io/mission_json.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "uavip/io/json_numbers.h"

namespace uavip::io {
namespace {

using nlohmann::json;

/// JSON has no infinity: an unbounded clearance is written as null.
json finiteOrNull(double v) { return std::isfinite(v) ? json(round4(v)) : json(nullptr); }

json modelToJson(const planning::FlightModel& model);

json validationToJson(const planning::ValidationResult& v) {
  return {{"collision_free", v.collision_free},
          {"min_clearance_m", finiteOrNull(v.min_clearance_m)},
          {"first_violation_segment", v.first_violation_segment},
          {"violation_object", v.violation_object},
          {"violation_point", v.collision_free ? json(nullptr) : vec(v.violation_point)}};
}

}  // namespace

/// A mission's measured coverage; the multi-view counts only where they were measured.
json coverageToJson(const planning::SurfaceMission::Coverage& c) {
  if (!c.evaluated) return nullptr;
  json j = {{"fraction", round4(c.fraction)}, {"points", c.points}, {"uncovered", c.uncovered}};
  if (c.multi_view) {
    j["views_min"] = c.views_min;
    j["views_median"] = c.views_median;
    if (c.views_below_min >= 0) j["views_below_min"] = c.views_below_min;
    j["triangulation_deg_min"] = round4(c.angle_min_deg);
    j["triangulation_deg_median"] = round4(c.angle_median_deg);
    j["consecutive_share_min"] = round4(c.consecutive_share_min);
  }
  return j;
}

json surfaceMissionToJson(const planning::SurfaceMission& m) {
  json stops = json::array();
  for (std::size_t i = 0; i < m.strategy.stops.size(); ++i) {
    const auto& s = m.strategy.stops[i];
    const auto problem =
        i < m.stop_problems.size() ? m.stop_problems[i] : planning::StopProblem::None;
    stops.push_back({{"index", s.index},
                     {"row", s.row},
                     {"col", s.col},
                     {"position", vec(s.position)},
                     {"target", vec(s.target)},
                     {"yaw_deg", round4(s.yaw_deg)},
                     {"gimbal_pitch_deg", round4(s.gimbal_pitch_deg)},
                     {"problem", planning::toString(problem)},
                     {"moved", std::find(m.moved_stops.begin(), m.moved_stops.end(),
                                         static_cast<int>(i)) != m.moved_stops.end()}});
  }
  json waypoints = json::array();
  for (const auto& p : m.waypoints) waypoints.push_back(vec(p));
  const auto& cam = m.strategy.camera;
  json out = {{"surface_id", m.surface_id},
              {"kind", m.kind},
              {"status", planning::toString(m.status)},
              {"reason", m.reason},
              {"camera",
               {{"footprint_m", {round4(cam.footprint_w_m), round4(cam.footprint_h_m)}},
                {"standoff_m", round4(cam.standoff_m)},
                {"spacing_m", {round4(m.strategy.spacing_w_m), round4(m.strategy.spacing_h_m)}},
                {"grid", {m.strategy.cols, m.strategy.rows}}}},
              {"stop_count", m.strategy.stops.size()},
              {"moved_stop_count", m.moved_stops.size()},
              {"coverage", coverageToJson(m.coverage)},
              {"stops", stops},
              {"waypoint_count", m.waypoints.size()},
              {"waypoints", waypoints},
              {"raw_waypoint_count", m.raw_waypoint_count},
              {"path_length_m", round4(m.path_length_m)},
              {"raw_path_length_m", round4(m.raw_length_m)},
              {"validation", validationToJson(m.validation)},
              {"timings", {{"planning_s", round4(m.seconds)}}}};
  // Written only when the gimbal's limits moved a stop (a mission planned for a
  // gimbal that turns anywhere reads as before).
  if (!m.gimbal_moved_stops.empty()) out["gimbal_moved_stop_count"] = m.gimbal_moved_stops.size();
  return out;
}

namespace {

/// A sortie's photo stops ({surface_id, stop, waypoint}) and waypoints, as mission.json
/// writes them for the flight and for each UAV of a fleet.
std::pair<json, json> sortieStopsAndWaypoints(const planning::Sortie& s) {
  json stops = json::array();
  for (const auto& st : s.stops)
    stops.push_back({{"surface_id", st.surface_id}, {"stop", st.stop}, {"waypoint", st.waypoint}});
  json waypoints = json::array();
  for (const auto& p : s.waypoints) waypoints.push_back(vec(p));
  return {stops, waypoints};
}

}  // namespace

json flightToJson(const planning::FlightPlan& f, const planning::FlightModel& model) {
  json order = json::array();
  for (const auto& v : f.order)
    order.push_back({{"surface_id", v.surface_id}, {"reversed", v.reversed}});
  json excluded = json::array();
  for (const auto& e : f.excluded)
    excluded.push_back({{"surface_id", e.surface_id}, {"reason", e.reason}});
  json sorties = json::array();
  for (std::size_t i = 0; i < f.sorties.size(); ++i) {
    const auto& s = f.sorties[i];
    const auto [stops, waypoints] = sortieStopsAndWaypoints(s);
    sorties.push_back({{"sortie", i + 1},
                       {"length_m", round4(s.length_m)},
                       {"duration_s", round4(s.duration_s)},
                       {"stop_count", s.stops.size()},
                       {"stops", stops},
                       {"waypoint_count", s.waypoints.size()},
                       {"waypoints", waypoints},
                       {"validation", validationToJson(s.validation)}});
  }
  return {
      {"status", planning::toString(f.status)},
      {"reason", f.reason},
      {"home", vec(f.home)},
      {"home_source", f.home_source},
      {"order", order},
      {"excluded", excluded},
      {"tour_length_m", round4(f.tour_length_m)},
      {"inner_length_m", round4(f.inner_length_m)},
      {"naive_length_m", f.naive_length_m > 0.0 ? json(round4(f.naive_length_m)) : json(nullptr)},
      {"lower_bound_m", round4(f.lower_bound_m)},
      {"exact_order", f.exact_order},
      {"planned_legs", f.planned_legs},
      {"length_m", round4(f.length_m)},
      {"duration_s", round4(f.duration_s)},
      {"sortie_count", f.sorties.size()},
      {"model", modelToJson(model)},
      {"sorties", sorties},
      {"timings",
       {{"order_s", round4(f.order_seconds)},
        {"validate_s", round4(f.validate_seconds)},
        {"flight_s", round4(f.seconds)}}}};
}

namespace {

json modelToJson(const planning::FlightModel& model) {
  return {{"cruise_speed_m_s", model.cruise_speed_m_s},
          {"climb_speed_m_s", model.climb_speed_m_s},
          {"descent_speed_m_s", model.descent_speed_m_s},
          {"hover_s", model.hover_s},
          {"settle_s", model.settle_s},
          {"endurance_s", model.endurance_s},
          {"reserve", model.reserve}};
}

/// Arrival time at each waypoint of a sortie that takes off at `start_s` [s]
/// (the motion of planning/fleet_types.h).
json arrivalTimes(const planning::Sortie& s, const planning::FleetPlan& f, double start_s) {
  std::vector<int> hovers(s.waypoints.size(), 0);
  for (const auto& st : s.stops) ++hovers.at(st.waypoint);
  json out = json::array();
  double t = start_s + 0.5 * f.options.takeoff_landing_s;
  for (std::size_t i = 0; i < s.waypoints.size(); ++i) {
    if (i > 0) t += f.model.segmentSeconds(s.waypoints[i - 1], s.waypoints[i]);
    out.push_back(round4(t));
    t += hovers[i] * f.model.stopSeconds();
  }
  return out;
}

json fleetUavToJson(const planning::FleetUav& u, std::size_t index, const planning::FleetPlan& f) {
  json sorties = json::array();
  for (std::size_t i = 0; i < u.flight.sorties.size(); ++i) {
    const auto& s = u.flight.sorties[i];
    const auto [stops, waypoints] = sortieStopsAndWaypoints(s);
    sorties.push_back({{"sortie", i + 1},
                       {"start_s", round4(u.sortie_start_s.at(i))},
                       {"duration_s", round4(s.duration_s)},
                       {"length_m", round4(s.length_m)},
                       {"stops", stops},
                       {"waypoints", waypoints},
                       {"times_s", arrivalTimes(s, f, u.sortie_start_s.at(i))},
                       {"validation", validationToJson(s.validation)}});
  }
  return {{"uav", index + 1},      {"home", vec(u.home)},        {"home_source", u.home_source},
          {"stop_count", u.stops}, {"wait_s", round4(u.wait_s)}, {"end_s", round4(u.end_s)},
          {"sorties", sorties}};
}

}  // namespace

json fleetToJson(const planning::FleetPlan& f) {
  json uavs = json::array();
  for (std::size_t i = 0; i < f.uavs.size(); ++i) uavs.push_back(fleetUavToJson(f.uavs[i], i, f));
  json j = fleetSummaryToJson(f);
  j["uavs"] = std::move(uavs);
  return j;
}

json fleetSummaryToJson(const planning::FleetPlan& f) {
  json options = json::object();
  for (const auto& row : planning::FleetOptions::table().rows()) {
    const params::Value v = row.get(f.options);
    if (v.present && v.numbers.size() == 1) options[row.key] = v.number();
  }
  const auto& sep = f.separation;
  return {{"status", planning::toString(f.status)},
          {"reason", f.reason},
          {"options", options},
          {"makespan_s", round4(f.makespan_s)},
          {"single_uav_s", round4(f.single_uav_s)},
          {"speedup", f.makespan_s > 0.0 ? round4(f.single_uav_s / f.makespan_s) : 0.0},
          {"lower_bound_s", round4(f.lower_bound_s)},
          {"work_s", round4(f.work_s)},
          {"jobs", f.jobs},
          {"split_surfaces", f.split_surfaces},
          {"waits", f.waits},
          {"fallback_single", f.fallback_single},
          {"assignment", f.assignment},
          {"candidates", f.candidates},
          {"closest_approach",
           {{"nominal_m", finiteOrNull(sep.nominal_min_m)},
            {"at_s",
             std::isfinite(sep.nominal_min_m) ? json(round4(sep.nominal_time_s)) : json(nullptr)},
            {"swept_m", finiteOrNull(sep.swept_min_m)}}},
          {"model", modelToJson(f.model)},
          {"timings", {{"fleet_s", round4(f.seconds)}}}};
}

namespace {

/// `camera_model`: the pinhole intrinsics, the sensor and its GSD, or the paper's footprint.
json cameraModel(const coverage::Camera& cam) {
  if (cam.pinhole)
    return {{"pinhole_px",
             {{"fx", cam.fx_px}, {"fy", cam.fy_px}, {"cx", cam.cx_px}, {"cy", cam.cy_px}}},
            {"image_px", {cam.image_w_px, cam.image_h_px}},
            {"gsd_mm_per_px", cam.gsd_mm_per_px}};
  if (!cam.from_sensor) return {{"footprint_m", {cam.footprint_w_m, cam.footprint_h_m}}};
  return {{"sensor_mm", {cam.sensor_w_mm, cam.sensor_h_mm}},
          {"focal_mm", cam.focal_mm},
          {"image_px", {cam.image_w_px, cam.image_h_px}},
          {"gsd_mm_per_px", cam.gsd_mm_per_px}};
}

/// `structure`: rule (a) FC-Planner's pixel rule, rule (b) ours (docs/ARCHITECTURE.md).
json structureToJson(const planning::StructureSummary& st) {
  json j = {{"surface_id", st.surface_id},       {"points", st.points},
            {"ground_points", st.ground_points}, {"seeds", st.seeds},
            {"candidates", st.candidates},       {"free_candidates", st.free_candidates},
            {"imageable_points", st.imageable},  {"photos", st.photos},
            {"standoff_m", st.standoff_m},       {"visible_range_m", st.visible_range_m},
            {"coverage_rule_a", st.rule_a},      {"coverage_rule_b", st.rule_b}};
  if (st.photo_groups > 0) {
    j["linking_photos"] = st.linking_photos;
    j["photo_groups"] = st.photo_groups;
  }
  return j;
}

}  // namespace

std::string missionJsonText(const std::vector<planning::SurfaceMission>& missions,
                            const planning::FlightPlan& flight, const planning::FlightModel& model,
                            const MissionExtras& e) {
  json meta = {{"uavip_version", e.uavip_version},
               {"source", e.source},
               {"planner", e.planner},
               {"cost_weights", {e.cost_weights.x(), e.cost_weights.y(), e.cost_weights.z()}},
               {"inflation_radius_m", e.inflation_radius_m},
               {"grid_resolution_m", e.grid_resolution_m},
               {"overlap", {e.overlap_w, e.overlap_h}},
               {"camera_model", cameraModel(e.camera)}};
  meta["timings"] = {{"coverage_s", e.coverage_s},
                     {"grid_s", e.grid_s},
                     {"planning_s", e.planning_s},
                     {"flight_s", e.flight_s}};
  meta["grid"] = {{"voxels", e.grid_voxels},
                  {"blocked", e.grid_blocked},
                  {"resolution_m", e.grid_resolution_m}};
  meta["safety_clearance_m"] = e.safety_clearance_m;
  if (e.purpose != "inspection") meta["purpose"] = e.purpose;
  if (!e.drone.empty()) meta["aircraft"] = {{"drone", e.drone}, {"payload", e.payload}};
  if (e.structure) {
    meta["structure"] = structureToJson(*e.structure);
    meta["timings"]["prepare_s"] = e.structure->prepare_s;
    meta["timings"]["select_s"] = e.structure->select_s;
    meta["timings"]["order_s"] = e.structure->order_s;
    meta["timings"]["legs_s"] = e.structure->legs_s;
    meta["timings"]["score_s"] = e.structure->score_s;
  }
  if (e.edits) {
    json volumes = json::array();
    for (const auto& k : e.edits->keep_out) {
      const bool box = k.shape == KeepOut::Shape::Box;
      volumes.push_back({{"name", k.name},
                         {"shape", box ? "box" : "cylinder"},
                         {"center", vec(k.center)},
                         {"size", vec(k.size)},
                         {"yaw_deg", k.yaw_deg}});
    }
    meta["edits"] = {{"file", e.edits->file},
                     {"sha256", e.edits->sha256},
                     {"applied", e.edits->applied},
                     {"keep_out", volumes}};
  }
  json doc = missionToJson(missions, meta);
  doc["flight"] = flightToJson(flight, model);
  if (e.fleet) doc["fleet"] = fleetToJson(*e.fleet);
  return doc.dump(1) + "\n";
}

json missionToJson(const std::vector<planning::SurfaceMission>& missions, const json& meta) {
  json out = {{"format", "uavip-mission"},
              {"version", 1},
              {"frame", "local ENU, metres, z up; yaw CCW from +x (east)"}};
  for (const auto& [k, v] : meta.items()) out[k] = v;
  json arr = json::array();
  for (const auto& m : missions) arr.push_back(surfaceMissionToJson(m));
  out["surfaces"] = arr;
  return out;
}

}  // namespace uavip::io
