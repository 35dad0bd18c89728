#include "uavip/app/aircraft_profile.h"

#include <algorithm>
#include <cmath>

#include "uavip/core/text.h"

namespace uavip::app {
namespace {

/// Records that the profile sets the key of `field` (a field of `c`); false when a
/// higher layer (the file) already has.
bool byProfile(Config& c, const void* field) {
  return c.sources.set(c.keyOf(field), params::Source::Profile);
}

/// The camera of the profile, at the GSD it gives at the coverage standoff, unless the
/// file describes a camera (any key of its section).
void applyCamera(Config& c, const aircraft::Payload& payload, std::vector<std::string>& notes) {
  coverage::Camera& cam = c.coverage.camera;
  const std::string& key = c.keyOf(&cam.sensor_w_mm);
  if (c.sources.anyFromFile(key.substr(0, key.find('.') + 1))) {
    notes.push_back("camera: the config's own (it sets " + key.substr(0, key.find('.')) +
                    " keys), not the " + payload.model);
    return;
  }
  const aircraft::CameraSpec& s = payload.camera;
  for (const void* f :
       {static_cast<const void*>(&cam.sensor_w_mm), static_cast<const void*>(&cam.focal_mm),
        static_cast<const void*>(&cam.image_w_px), static_cast<const void*>(&cam.gsd_mm_per_px)})
    byProfile(c, f);
  cam.from_sensor = true;
  cam.pinhole = false;
  cam.sensor_w_mm = s.sensor_w_mm;
  cam.sensor_h_mm = s.sensor_h_mm;
  cam.focal_mm = s.focal_mm;
  cam.image_w_px = s.image_w_px;
  cam.image_h_px = s.image_h_px;
  cam.gsd_mm_per_px = gsdAt(s, c.coverage.standoff_m);
  notes.push_back("camera: " + payload.model + " " + formatNumber(s.sensor_w_mm) + " x " +
                  formatNumber(s.sensor_h_mm) + " mm, f " + formatNumber(s.focal_mm) + " mm, " +
                  std::to_string(s.image_w_px) + " x " + std::to_string(s.image_h_px) +
                  " px: " + formatFixed(cam.gsd_mm_per_px, 3) + " mm/px at " +
                  formatNumber(c.coverage.standoff_m) + " m");
}

/// The gimbal's pitch range within the planner's [-90, 90] (a pitch below -90 is the
/// same view as one above it with the aircraft turned round).
void applyGimbal(Config& c, const aircraft::Payload& payload, std::vector<std::string>& notes) {
  auto& g = c.coverage.gimbal;
  if (!byProfile(c, &g)) return;
  g.pitch_min_deg = std::max(-90.0, payload.pitch_min_deg);
  g.pitch_max_deg = std::min(90.0, payload.pitch_max_deg);
  notes.push_back("gimbal pitch: " + formatNumber(g.pitch_min_deg) + " to " +
                  formatNumber(g.pitch_max_deg) + " deg");
}

/// Speed capped by the maker's maximum, endurance and size from the profile.
void applyAirframe(Config& c, const aircraft::Profile& p, std::vector<std::string>& notes) {
  auto& model = c.flight.model;
  if (model.cruise_speed_m_s > p.max_speed_mps) {
    notes.push_back("cruise speed: " + formatNumber(model.cruise_speed_m_s) +
                    " m/s capped at the " + p.model + "'s " + formatNumber(p.max_speed_mps) +
                    " m/s");
    model.cruise_speed_m_s = p.max_speed_mps;
  }
  if (byProfile(c, &model.endurance_s)) {
    model.endurance_s = p.enduranceS();
    notes.push_back("endurance: " + formatNumber(model.endurance_s) + " s (0.8 x the " +
                    formatNumber(p.hover_time_s / 60.0) + " min hover time)");
  }
  // Size and inflation together: a file that sets either keeps both.
  if (c.setInFile(&c.uav.size_m) || c.setInFile(&c.uav.inflation_radius_m)) return;
  byProfile(c, &c.uav.size_m);
  byProfile(c, &c.uav.inflation_radius_m);
  c.uav.size_m = Vec3(p.span_m, p.span_m, p.height_m);
  c.uav.inflation_radius_m = 0.5 * std::hypot(p.span_m, p.height_m);
  notes.push_back("size: " + formatNumber(p.span_m) + " m span with propellers, inflation " +
                  formatFixed(*c.uav.inflation_radius_m, 2) + " m (the enclosing sphere)");
}

}  // namespace

double gsdAt(const aircraft::CameraSpec& camera, double distance_m) {
  return distance_m * 1000.0 *
         std::max(camera.sensor_w_mm / (camera.image_w_px * camera.focal_mm),
                  camera.sensor_h_mm / (camera.image_h_px * camera.focal_mm));
}

std::vector<std::string> applyAircraftProfile(Config& config, const std::string& where) {
  if (config.uav.model == "generic" && config.uav.payload.empty()) return {};
  const aircraft::Profile p =
      aircraft::findProfile(config.uav.model, config.uav.payload,
                            (where.empty() ? "" : where + ": ") + config.keyOf(&config.uav.model));
  if (p.isGeneric()) return {};
  std::vector<std::string> notes;
  applyCamera(config, p.payload, notes);
  applyGimbal(config, p.payload, notes);
  applyAirframe(config, p, notes);
  return notes;
}

std::vector<std::string> selectAircraft(Config& config, const std::string& drone,
                                        const std::string& payload) {
  if (!drone.empty()) {
    config.uav.model = drone;
    config.uav.payload = payload;
    config.sources.set(config.keyOf(&config.uav.model), params::Source::File);
  } else if (!payload.empty()) {
    config.uav.payload = payload;
  }
  return applyAircraftProfile(config, drone.empty() ? "config" : "--drone");
}

}  // namespace uavip::app
