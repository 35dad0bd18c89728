#include "uavip/coverage/camera.h"

#include <algorithm>
#include <cmath>

#include "uavip/core/error.h"
#include "uavip/core/text.h"

namespace uavip::coverage {

double Camera::maxStandoff() const {
  return max_range_m > 0.0 ? max_range_m : kMaxStandoffWithoutRangeM;
}

void Camera::validate(const std::string& where) const {
  if (!(std::isfinite(max_range_m) && max_range_m >= 0.0))
    throw InputError(where + ": max_range_m must be > 0 (or left out), got " +
                     formatNumber(max_range_m));
  if (pinhole) {
    requirePositive(fx_px, where, "fx");
    requirePositive(fy_px, where, "fy");
    requirePositive(static_cast<double>(image_w_px), where, "image_px[0]");
    requirePositive(static_cast<double>(image_h_px), where, "image_px[1]");
    if (!(cx_px >= 0.0 && cx_px <= image_w_px))
      throw InputError(where + ": cx " + formatNumber(cx_px) + " px lies outside the image width " +
                       std::to_string(image_w_px));
    if (!(cy_px >= 0.0 && cy_px <= image_h_px))
      throw InputError(where + ": cy " + formatNumber(cy_px) +
                       " px lies outside the image height " + std::to_string(image_h_px));
    if (!(std::isfinite(gsd_mm_per_px) && gsd_mm_per_px >= 0.0))
      throw InputError(where + ": gsd_mm_per_px must be > 0 (or left out), got " +
                       formatNumber(gsd_mm_per_px));
    if (!(gsd_mm_per_px * std::min(fx_px, fy_px) / 1000.0 <= maxStandoff()))
      throw InputError(where + ": gsd_mm_per_px " + formatNumber(gsd_mm_per_px) +
                       " puts the camera beyond " + formatNumber(maxStandoff()) +
                       " m; give the GSD in mm per pixel, or set camera.max_range_m");
    return;
  }
  if (!from_sensor) {
    requirePositive(footprint_w_m, where, "footprint_w_m");
    requirePositive(footprint_h_m, where, "footprint_h_m");
    return;
  }
  requirePositive(sensor_w_mm, where, "sensor_w_mm");
  requirePositive(sensor_h_mm, where, "sensor_h_mm");
  requirePositive(focal_mm, where, "focal_mm");
  requirePositive(static_cast<double>(image_w_px), where, "image_w_px");
  requirePositive(static_cast<double>(image_h_px), where, "image_h_px");
  requirePositive(gsd_mm_per_px, where, "gsd_mm_per_px");
  // The standoff of solveCamera: the GSD is met on both axes.
  const double standoff_m = std::min(image_w_px * gsd_mm_per_px * focal_mm / sensor_w_mm,
                                     image_h_px * gsd_mm_per_px * focal_mm / sensor_h_mm) /
                            1000.0;
  if (!(standoff_m <= maxStandoff()))
    throw InputError(where + ": gsd_mm_per_px " + formatNumber(gsd_mm_per_px) +
                     " puts the camera " + formatNumber(standoff_m, 4) +
                     " m from the surface, beyond " +
                     (max_range_m > 0.0
                          ? "its max_range_m " + formatNumber(max_range_m)
                          : formatNumber(kMaxStandoffWithoutRangeM) + " m (no max_range_m given)") +
                     "; give the GSD in mm per pixel (e.g. 2), or set camera.max_range_m");
}

CameraGeometry solveCamera(const Camera& camera, double standoff_m) {
  camera.validate();
  CameraGeometry g;
  if (camera.pinhole) {
    const double f = std::min(camera.fx_px, camera.fy_px);
    g.standoff_m = camera.gsd_mm_per_px > 0.0 ? camera.gsd_mm_per_px * f / 1000.0 : standoff_m;
    requirePositive(g.standoff_m, "camera", "standoff_m");
    g.footprint_w_m = g.standoff_m * camera.image_w_px / camera.fx_px;
    g.footprint_h_m = g.standoff_m * camera.image_h_px / camera.fy_px;
    g.gsd_w_mm = g.standoff_m * 1000.0 / camera.fx_px;
    g.gsd_h_mm = g.standoff_m * 1000.0 / camera.fy_px;
    return g;
  }
  if (!camera.from_sensor) {
    requirePositive(standoff_m, "camera", "standoff_m");
    g.footprint_w_m = camera.footprint_w_m;
    g.footprint_h_m = camera.footprint_h_m;
    g.standoff_m = standoff_m;
    return g;
  }
  // QGroundControl CameraCalc on both axes (docs/formats.md), GSD in mm/px:
  // D [mm] = I·GSD·f/S; take the nearer so the required GSD is met on both axes.
  const double iw = static_cast<double>(camera.image_w_px);
  const double ih = static_cast<double>(camera.image_h_px);
  const double f = camera.focal_mm;
  const double d_w_mm = iw * camera.gsd_mm_per_px * f / camera.sensor_w_mm;
  const double d_h_mm = ih * camera.gsd_mm_per_px * f / camera.sensor_h_mm;
  const double d_mm = std::min(d_w_mm, d_h_mm);
  g.standoff_m = d_mm / 1000.0;
  g.footprint_w_m = g.standoff_m * camera.sensor_w_mm / f;
  g.footprint_h_m = g.standoff_m * camera.sensor_h_mm / f;
  g.gsd_w_mm = d_mm * camera.sensor_w_mm / (iw * f);
  g.gsd_h_mm = d_mm * camera.sensor_h_mm / (ih * f);
  return g;
}

}  // namespace uavip::coverage
