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

namespace {

void requireGsd(double max_gsd_mm_per_px, const std::string& where) {
  requireThat(std::isfinite(max_gsd_mm_per_px) && max_gsd_mm_per_px >= 0.0, where,
              "max_gsd_mm_per_px", ">= 0 and finite", max_gsd_mm_per_px);
}

}  // namespace

// ---------------------------------------------------------------- camera frame

ViewFrame makeViewFrame(const ViewPose& pose) {
  const double y = pose.yaw_deg * kDegToRad;
  const double p = pose.pitch_deg * kDegToRad;
  ViewFrame f;
  f.pose = pose;
  f.forward = Vec3(std::cos(p) * std::cos(y), std::cos(p) * std::sin(y), std::sin(p));
  f.right = Vec3(std::sin(y), -std::cos(y), 0.0);
  f.up = f.right.cross(f.forward);
  return f;
}

// ---------------------------------------------------------------- footprint camera

void FootprintCameraOptions::validate(const std::string& where) const {
  camera.validate(where + ".camera");
  if (!camera.from_sensor) requirePositive(standoff_m, where, "standoff_m");
  requireThat(std::isfinite(range_slack) && range_slack >= 1.0, where, "range_slack",
              ">= 1 and finite", range_slack);
  requireThat(assumed_image_w_px > 0, where, "assumed_image_w_px", "> 0",
              static_cast<double>(assumed_image_w_px));
}

FootprintCamera::FootprintCamera(const FootprintCameraOptions& options) : options_(options) {
  options_.validate();
  geometry_ = solveCamera(options_.camera, options_.standoff_m);
  const double d = geometry_.standoff_m;
  tan_half_w_ = geometry_.footprint_w_m / (2.0 * d);
  tan_half_h_ = geometry_.footprint_h_m / (2.0 * d);
  if (options_.camera.from_sensor) {
    const Camera& c = options_.camera;
    focal_px_ = std::min(c.image_w_px * c.focal_mm / c.sensor_w_mm,
                         c.image_h_px * c.focal_mm / c.sensor_h_mm);
  } else {
    focal_px_ = options_.assumed_image_w_px * d / geometry_.footprint_w_m;
  }
}

namespace {

/// A central camera's projection of `point` from `frame`: the range, the GSD at
/// focal length `focal_px` (range·1000 / focal_px), and, for a point in front,
/// in_image = inside(x, y, z) with x = right·d, y = up·d, z = forward·d (d = point −
/// camera centre) [m].
template <typename Inside>
Projection centralProjection(const ViewFrame& frame, const Vec3& point, double focal_px,
                             Inside inside) {
  const Vec3 d = point - frame.pose.position;
  Projection pr;
  pr.range_m = d.norm();
  pr.gsd_mm_per_px = pr.range_m * 1000.0 / focal_px;
  const double z = frame.forward.dot(d);
  if (z > 0.0) pr.in_image = inside(frame.right.dot(d), frame.up.dot(d), z);
  return pr;
}

}  // namespace

Projection CentralCamera::project(const ViewPose& pose, const Vec3& point) const {
  return projectInFrame(makeViewFrame(pose), point);
}

double CentralCamera::cappedRange(double r, double max_gsd_mm_per_px,
                                  const std::string& where) const {
  requireGsd(max_gsd_mm_per_px, where);
  if (max_gsd_mm_per_px > 0.0) r = std::min(r, max_gsd_mm_per_px * focal_px_ / 1000.0);
  return r;
}

Projection FootprintCamera::projectInFrame(const ViewFrame& frame, const Vec3& point) const {
  return centralProjection(frame, point, focal_px_, [this](double x, double y, double z) {
    return std::abs(x) <= tan_half_w_ * z && std::abs(y) <= tan_half_h_ * z;
  });
}

double FootprintCamera::maxOffAxisRad() const {
  return std::atan(std::hypot(tan_half_w_, tan_half_h_));
}

double FootprintCamera::maxRange(double max_gsd_mm_per_px) const {
  return cappedRange(geometry_.standoff_m * options_.range_slack, max_gsd_mm_per_px,
                     "footprint_camera.maxRange");
}

// ---------------------------------------------------------------- pinhole camera

void PinholeIntrinsics::validate(const std::string& where) const {
  requireThat(width_px > 0, where, "width_px", "> 0", static_cast<double>(width_px));
  requireThat(height_px > 0, where, "height_px", "> 0", static_cast<double>(height_px));
  requirePositive(fx_px, where, "fx_px");
  requirePositive(fy_px, where, "fy_px");
  requireThat(std::isfinite(cx_px), where, "cx_px", "finite", cx_px);
  requireThat(std::isfinite(cy_px), where, "cy_px", "finite", cy_px);
  requireThat(std::isfinite(max_range_m) && max_range_m >= 0.0, where, "max_range_m",
              ">= 0 and finite (0 = none)", max_range_m);
}

PinholeCamera::PinholeCamera(const PinholeIntrinsics& intrinsics) : k_(intrinsics) {
  k_.validate();
  focal_px_ = std::min(k_.fx_px, k_.fy_px);
}

Projection PinholeCamera::projectInFrame(const ViewFrame& frame, const Vec3& point) const {
  return centralProjection(frame, point, focal_px_, [this](double x, double y, double z) {
    const double u = k_.cx_px + k_.fx_px * x / z;
    const double v = k_.cy_px - k_.fy_px * y / z;  // image y points down
    return u >= 0.0 && u <= k_.width_px && v >= 0.0 && v <= k_.height_px;
  });
}

double PinholeCamera::maxOffAxisRad() const {
  const double du = std::max(std::abs(k_.cx_px), std::abs(k_.width_px - k_.cx_px)) / k_.fx_px;
  const double dv = std::max(std::abs(k_.cy_px), std::abs(k_.height_px - k_.cy_px)) / k_.fy_px;
  return std::atan(std::hypot(du, dv));
}

double PinholeCamera::maxRange(double max_gsd_mm_per_px) const {
  double r = kInf;  // the model's own range limit; none: +inf
  if (k_.max_range_m > 0.0) r = k_.max_range_m;
  return cappedRange(r, max_gsd_mm_per_px, "pinhole.maxRange");
}

}  // namespace uavip::coverage
