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
  table().check(*this, where);
  if (pinhole) {
    if (!(cx_px >= 0.0 && cx_px <= image_w_px))
      throw InputError(where + ": cx " + formatNumber(cx_px) + " px lies outside the image width " +
                       std::to_string(image_w_px));
    if (!(cy_px >= 0.0 && cy_px <= image_h_px))
      throw InputError(where + ": cy " + formatNumber(cy_px) +
                       " px lies outside the image height " + std::to_string(image_h_px));
    if (!(gsd_mm_per_px * std::min(fx_px, fy_px) / 1000.0 <= maxStandoff()))
      throw InputError(where + ": gsd_mm_per_px " + formatNumber(gsd_mm_per_px) +
                       " puts the camera beyond " + formatNumber(maxStandoff()) +
                       " m; give the GSD in mm per pixel, or set camera.max_range_m");
    return;
  }
  if (!from_sensor) return;
  requirePositive(gsd_mm_per_px, where, table().find(*this, &gsd_mm_per_px)->key);
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

namespace {

/// A camera key's value, read as unset (none) unless the camera is of the model
/// `active` says.
template <typename F>
params::Value when(bool active, F&& value) {
  return active ? value() : params::Value{{}, {}, false};
}

/// A sensor key was read: the camera is a sensor camera unless a pinhole key says pinhole.
void sensorKey(Camera& c) { c.from_sensor = !c.pinhole; }
/// A pinhole key was read.
void pinholeKey(Camera& c) {
  c.pinhole = true;
  c.from_sensor = false;
}

/// The row of a pinhole intrinsic `field` [px].
params::Param<Camera>& addPinhole(params::Table<Camera>& p, const std::string& key,
                                  double Camera::*field, const std::string& help) {
  return p
      .add(
          key, params::Kind::Number,
          [field](const Camera& c) {
            return when(c.pinhole, [&] { return params::toValue(c.*field); });
          },
          [field](Camera& c, const params::Value& v) {
            c.*field = v.number();
            pinholeKey(c);
          },
          help)
      .unitIs("px")
      .storedAt([field](const Camera& c) -> const void* { return &(c.*field); })
      .fromProfile();
}

/// The rows of the footprint and the sensor (QGroundControl's CameraCalc).
void addSensor(params::Table<Camera>& p) {
  using V = params::Value;
  p.add(
       "footprint_m", params::Kind::Numbers,
       [](const Camera& c) {
         return when(!c.from_sensor && !c.pinhole, [&] {
           return V{{c.footprint_w_m, c.footprint_h_m}, {}, true};
         });
       },
       [](Camera& c, const V& v) {
         c.footprint_w_m = v.numbers.at(0);
         c.footprint_h_m = v.numbers.at(1);
       },
       "photo [width, height] on the surface, given directly (paper: 0.6 × 0.4 m at 1.5 m)")
      .count(2, 2)
      .unitIs("m")
      .positive()
      .storedAt([](const Camera& c) -> const void* { return &c.footprint_w_m; });
  p.add(
       "sensor_mm", params::Kind::Numbers,
       [](const Camera& c) {
         return when(c.from_sensor, [&] { return V{{c.sensor_w_mm, c.sensor_h_mm}, {}, true}; });
       },
       [](Camera& c, const V& v) {
         c.sensor_w_mm = v.numbers.at(0);
         c.sensor_h_mm = v.numbers.at(1);
         sensorKey(c);
       },
       "sensor [width, height] (with focal_mm, image_px and gsd_mm_per_px)")
      .count(2, 2)
      .unitIs("mm")
      .positive()
      .storedAt([](const Camera& c) -> const void* { return &c.sensor_w_mm; })
      .fromProfile();
  p.add(
       "focal_mm", params::Kind::Number,
       [](const Camera& c) {
         return when(c.from_sensor, [&] { return params::toValue(c.focal_mm); });
       },
       [](Camera& c, const V& v) {
         c.focal_mm = v.number();
         sensorKey(c);
       },
       "focal length of a sensor camera")
      .unitIs("mm")
      .positive()
      .storedAt([](const Camera& c) -> const void* { return &c.focal_mm; })
      .fromProfile();
}

/// The rows a sensor and a pinhole camera share, and the range.
void addImage(params::Table<Camera>& p) {
  using V = params::Value;
  p.add(
       "image_px", params::Kind::Numbers,
       [](const Camera& c) {
         return when(c.from_sensor || c.pinhole, [&] {
           return V{
               {static_cast<double>(c.image_w_px), static_cast<double>(c.image_h_px)}, {}, true};
         });
       },
       [](Camera& c, const V& v) {
         c.image_w_px = static_cast<int>(v.numbers.at(0));
         c.image_h_px = static_cast<int>(v.numbers.at(1));
         sensorKey(c);
       },
       "image [width, height] in pixels")
      .count(2, 2)
      .unitIs("px")
      .within(1, 1e6)
      .integral()
      .storedAt([](const Camera& c) -> const void* { return &c.image_w_px; })
      .fromProfile();
  p.add(
       "gsd_mm_per_px", params::Kind::Number,
       [](const Camera& c) {
         return when(c.from_sensor || c.pinhole, [&] { return params::toValue(c.gsd_mm_per_px); });
       },
       [](Camera& c, const V& v) {
         c.gsd_mm_per_px = v.number();
         sensorKey(c);
       },
       "required ground sample distance, met on both axes (pinhole: 0 = none)")
      .unitIs("mm/px")
      .atLeast(0)
      .storedAt([](const Camera& c) -> const void* { return &c.gsd_mm_per_px; });
}

}  // namespace

const params::Table<Camera>& Camera::table() {
  static const params::Table<Camera> t = [] {
    params::Table<Camera> p;
    addSensor(p);
    addImage(p);
    addPinhole(p, "fx", &Camera::fx_px, "pinhole focal length along the image width").positive();
    addPinhole(p, "fy", &Camera::fy_px, "pinhole focal length along the image height").positive();
    addPinhole(p, "cx", &Camera::cx_px, "pinhole principal point x (default: image centre)");
    addPinhole(p, "cy", &Camera::cy_px, "pinhole principal point y (default: image centre)");
    p.add("max_range_m", &Camera::max_range_m,
          "farthest distance the camera works at (0: none, then 1 km bounds the standoff)")
        .unitIs("m")
        .atLeast(0);
    return p;
  }();
  return t;
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
