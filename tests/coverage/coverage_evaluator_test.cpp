// Tests of the coverage evaluator against independent references: a per-point per-view
// brute force written from the geometric definitions (footprint rectangle of a nadir
// camera, a frustum built from Eigen rotations, GSD and incidence by acos), the
// analytic shadow of a wall, an exact slab test and a 1 mm sampling of random rays,
// and the footprints of the flight strategy's stops.
#include "uavip/coverage/coverage_evaluator.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <random>
#include <set>
#include <stdexcept>
#include <tuple>
#include <vector>

#include "uavip/core/error.h"
#include "uavip/core/parallel.h"
#include "uavip/coverage/flight_strategy.h"

namespace uavip::coverage {
namespace {

constexpr double kDeg = M_PI / 180.0;

/// Points x0 + i·step, y0 + j·step at height z (i, j from 0 while ≤ the far edge).
PointList planeGrid(double x0, double x1, double y0, double y1, double step, double z) {
  PointList pts;
  const int nx = static_cast<int>(std::round((x1 - x0) / step));
  const int ny = static_cast<int>(std::round((y1 - y0) / step));
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) pts.emplace_back(x0 + i * step, y0 + j * step, z);
  }
  return pts;
}

/// The test's own camera frame: start looking along +x with image right = −y and image
/// up = +z, pitch about the image right axis, then yaw about +z (Eigen rotations, not
/// the closed formulas of the implementation).
struct RefFrame {
  Vec3 forward, right, up;
};
RefFrame refFrame(double yaw_deg, double pitch_deg) {
  const Eigen::Matrix3d r = (Eigen::AngleAxisd(yaw_deg * kDeg, Vec3::UnitZ()) *
                             Eigen::AngleAxisd(pitch_deg * kDeg, -Vec3::UnitY()))
                                .toRotationMatrix();
  return {r * Vec3::UnitX(), r * -Vec3::UnitY(), r * Vec3::UnitZ()};
}

/// The paper-like footprint camera of the brute-force tests: 1.2 × 0.8 m at 1.5 m,
/// 1000 px across → focal 1250 px, GSD = range·0.8 mm/px.
FootprintCameraOptions narrowCamera() {
  FootprintCameraOptions o;
  o.camera.footprint_w_m = 1.2;
  o.camera.footprint_h_m = 0.8;
  o.standoff_m = 1.5;
  o.range_slack = 2.0;
  return o;
}

/// Straightforward reference: views_per_point by looping every point and every view.
/// `inside(view, point)` is the image test; range, GSD and incidence by definition.
template <typename InsideFn>
std::vector<int> bruteForce(const PointList& pts, const Vec3& normal,
                            const std::vector<ViewPose>& views, double focal_px, double range_limit,
                            const CoverageCriteria& c, InsideFn inside) {
  std::vector<int> count(pts.size(), 0);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    for (const ViewPose& v : views) {
      const Vec3 to_cam = v.position - pts[i];
      const double range = to_cam.norm();
      if (range > range_limit) continue;
      const double gsd = range * 1000.0 / focal_px;
      if (c.max_gsd_mm_per_px > 0 && gsd > c.max_gsd_mm_per_px) continue;
      const double incidence = std::acos(normal.normalized().dot(to_cam) / range) / kDeg;
      if (incidence > c.max_incidence_deg) continue;
      if (!inside(v, pts[i])) continue;
      ++count[i];
    }
  }
  return count;
}

std::vector<std::size_t> zeros(const std::vector<int>& count) {
  std::vector<std::size_t> z;
  for (std::size_t i = 0; i < count.size(); ++i) {
    if (count[i] == 0) z.push_back(i);
  }
  return z;
}

int differing(const std::vector<int>& a, const std::vector<int>& b) {
  int d = 0;
  for (std::size_t i = 0; i < a.size(); ++i) d += a[i] != b[i];
  return d;
}

// ------------------------------------------------------------------ camera frame

TEST(CoverageFrame, NadirCameraImagesThePointBelow) {
  const FootprintCamera footprint(FootprintCameraOptions{});
  const PinholeCamera pinhole(PinholeIntrinsics{});
  for (double yaw : {0.0, 37.0, 90.0, -150.0}) {
    const ViewPose pose{Vec3(0, 0, 5), yaw, -90.0};
    for (const CameraModel* cam :
         {static_cast<const CameraModel*>(&footprint), static_cast<const CameraModel*>(&pinhole)}) {
      const Projection below = cam->project(pose, Vec3(0, 0, 0));
      EXPECT_TRUE(below.in_image) << "yaw " << yaw;
      EXPECT_NEAR(below.range_m, 5.0, 1e-12);
      EXPECT_FALSE(cam->project(pose, Vec3(0, 0, 10)).in_image);  // behind
      EXPECT_FALSE(cam->project(pose, Vec3(5, 0, 5)).in_image);   // level with it
    }
  }
}

TEST(CoverageFrame, MatchesEigenRotationsAndIsOrthonormal) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> yaw(-180, 180), pitch(-90, 90);
  for (int k = 0; k < 200; ++k) {
    const ViewPose pose{Vec3(1, 2, 3), yaw(rng), pitch(rng)};
    const ViewFrame f = makeViewFrame(pose);
    const RefFrame r = refFrame(pose.yaw_deg, pose.pitch_deg);
    EXPECT_NEAR((f.forward - r.forward).norm(), 0.0, 1e-12);
    EXPECT_NEAR((f.right - r.right).norm(), 0.0, 1e-12);
    EXPECT_NEAR((f.up - r.up).norm(), 0.0, 1e-12);
    EXPECT_NEAR(f.right.z(), 0.0, 1e-15);  // no roll
    EXPECT_NEAR(f.up.norm(), 1.0, 1e-12);
    EXPECT_NEAR((f.right.cross(f.up) + f.forward).norm(), 0.0, 1e-12);
  }
}

TEST(CoverageFrame, ImageRightAndUpWithAnOffCentreSensor) {
  // cx = cy = 0: only the lower-right quarter of the view (x right ≥ 0, y down ≥ 0)
  // is inside the image, which tells image right and up apart.
  PinholeIntrinsics k;
  k.cx_px = 0.0;
  k.cy_px = 0.0;
  const PinholeCamera cam(k);
  const Vec3 o = Vec3::Zero();
  // Yaw 0, level: forward +x, right −y, up +z.
  EXPECT_TRUE(cam.project({o, 0, 0}, Vec3(5, -1, -1)).in_image);
  EXPECT_FALSE(cam.project({o, 0, 0}, Vec3(5, 1, -1)).in_image);
  EXPECT_FALSE(cam.project({o, 0, 0}, Vec3(5, -1, 1)).in_image);
  // Yaw 90: forward +y, right +x.
  EXPECT_TRUE(cam.project({o, 90, 0}, Vec3(1, 5, -1)).in_image);
  EXPECT_FALSE(cam.project({o, 90, 0}, Vec3(-1, 5, -1)).in_image);
  // Straight down with yaw 90: right +x, photo up +y (a roof stop of flight_strategy).
  EXPECT_TRUE(cam.project({o, 90, -90}, Vec3(1, -1, -5)).in_image);
  EXPECT_FALSE(cam.project({o, 90, -90}, Vec3(1, 1, -5)).in_image);
  EXPECT_FALSE(cam.project({o, 90, -90}, Vec3(-1, -1, -5)).in_image);
  // Straight up with yaw 90 (a ceiling stop): right +x, photo up −y.
  EXPECT_TRUE(cam.project({o, 90, 90}, Vec3(1, 1, 5)).in_image);
  EXPECT_FALSE(cam.project({o, 90, 90}, Vec3(1, -1, 5)).in_image);
}

// ------------------------------------------------------------------ camera models

TEST(FootprintCamera, FootprintAtStandoffAndGsdRule) {
  const FootprintCamera cam(FootprintCameraOptions{});  // paper: 0.6 × 0.4 m at 1.5 m
  EXPECT_DOUBLE_EQ(cam.focalPx(), 2500.0);              // 1000 px · 1.5 / 0.6
  const ViewPose pose{Vec3(0, 0, 1.5), 90.0, -90.0};    // right +x, up +y
  const Projection centre = cam.project(pose, Vec3(0, 0, 0));
  EXPECT_NEAR(centre.gsd_mm_per_px, 0.6, 1e-12);  // footprint_w·1000 / 1000 px
  EXPECT_TRUE(cam.project(pose, Vec3(0.2999, 0.1999, 0)).in_image);
  EXPECT_FALSE(cam.project(pose, Vec3(0.3001, 0, 0)).in_image);
  EXPECT_FALSE(cam.project(pose, Vec3(0, 0.2001, 0)).in_image);
  // Twice as far: twice the footprint.
  EXPECT_TRUE(cam.project(pose, Vec3(0.5999, 0.3999, -1.5)).in_image);
  EXPECT_FALSE(cam.project(pose, Vec3(0.6001, 0, -1.5)).in_image);
  EXPECT_DOUBLE_EQ(cam.maxRange(0.0), 2.25);  // standoff × slack 1.5
  EXPECT_DOUBLE_EQ(cam.maxRange(1.0), 2.25);  // 1 mm/px reached at 2.5 m
  EXPECT_DOUBLE_EQ(cam.maxRange(0.8), 2.0);   // 0.8·2500/1000
  EXPECT_THROW(cam.maxRange(-1.0), InputError);

  // Sensor camera (camera_test): 10 × 10 mm, f 10 mm, 2000 × 1000 px, 1 mm/px →
  // D = 1 m; focal = min(2000, 1000) px, so the GSD at D is the required 1 mm/px.
  FootprintCameraOptions s;
  s.camera.from_sensor = true;
  s.camera.sensor_w_mm = s.camera.sensor_h_mm = s.camera.focal_mm = 10.0;
  s.camera.image_w_px = 2000;
  s.camera.image_h_px = 1000;
  s.camera.gsd_mm_per_px = 1.0;
  const FootprintCamera sensor(s);
  EXPECT_DOUBLE_EQ(sensor.geometry().standoff_m, 1.0);
  EXPECT_DOUBLE_EQ(sensor.focalPx(), 1000.0);
  EXPECT_NEAR(sensor.project({Vec3(0, 0, 1), 0, -90}, Vec3::Zero()).gsd_mm_per_px, 1.0, 1e-12);
  EXPECT_DOUBLE_EQ(sensor.maxRange(1.2), 1.2);

  FootprintCameraOptions bad;
  bad.range_slack = 0.5;
  EXPECT_THROW(FootprintCamera{bad}, InputError);
  bad = FootprintCameraOptions{};
  bad.assumed_image_w_px = 0;
  EXPECT_THROW(FootprintCamera{bad}, InputError);
  bad = FootprintCameraOptions{};
  bad.standoff_m = 0.0;
  EXPECT_THROW(FootprintCamera{bad}, InputError);
}

TEST(PinholeCamera, FieldOfViewEdges) {
  const PinholeIntrinsics k;  // FC-Planner: 640 × 480, fx 417.0467, fy 461.0951
  const PinholeCamera cam(k);
  const ViewPose pose{Vec3(1, 2, 3), 0.0, 0.0};  // forward +x, right −y, up +z
  const Projection axis = cam.project(pose, Vec3(6, 2, 3));
  EXPECT_TRUE(axis.in_image);
  EXPECT_NEAR(axis.gsd_mm_per_px, 5.0 * 1000.0 / 417.0467, 1e-9);  // worse axis: fx
  const double half_h = std::atan(320.0 / 417.0467);               // 37.5°
  const double half_v = std::atan(240.0 / 461.0951);               // 27.5°
  const double eps = 1e-6;
  auto horizontal = [&](double angle) {  // angle to the right of the axis, 5 m away
    return Vec3(1 + 5 * std::cos(angle), 2 - 5 * std::sin(angle), 3);
  };
  auto vertical = [&](double angle) {  // angle above the axis
    return Vec3(1 + 5 * std::cos(angle), 2, 3 + 5 * std::sin(angle));
  };
  EXPECT_TRUE(cam.project(pose, horizontal(half_h - eps)).in_image);
  EXPECT_FALSE(cam.project(pose, horizontal(half_h + eps)).in_image);
  EXPECT_TRUE(cam.project(pose, horizontal(-half_h + eps)).in_image);
  EXPECT_FALSE(cam.project(pose, horizontal(-half_h - eps)).in_image);
  EXPECT_TRUE(cam.project(pose, vertical(half_v - eps)).in_image);
  EXPECT_FALSE(cam.project(pose, vertical(half_v + eps)).in_image);
  EXPECT_TRUE(cam.project(pose, vertical(-half_v + eps)).in_image);
  EXPECT_FALSE(cam.project(pose, vertical(-half_v - eps)).in_image);
  EXPECT_FALSE(cam.project(pose, Vec3(-4, 2, 3)).in_image);  // behind

  EXPECT_TRUE(std::isinf(cam.maxRange(0.0)));
  EXPECT_NEAR(cam.maxRange(2.0), 2.0 * 417.0467 / 1000.0, 1e-12);
  PinholeIntrinsics limited = k;
  limited.max_range_m = 0.5;
  EXPECT_DOUBLE_EQ(PinholeCamera(limited).maxRange(2.0), 0.5);
  PinholeIntrinsics bad = k;
  bad.fy_px = 0.0;
  EXPECT_THROW(PinholeCamera{bad}, InputError);
  bad = k;
  bad.width_px = 0;
  EXPECT_THROW(PinholeCamera{bad}, InputError);
}

TEST(CameraModels, EveryImagedPointLiesWithinTheLargestOffAxisAngle) {
  // The evaluators skip cells outside the cone of maxOffAxisRad(): every point in the
  // image must lie inside it, and the image corners reach it (it is not loose).
  PinholeIntrinsics off_centre;
  off_centre.cx_px = 250.0;  // the farthest corner is not symmetric
  off_centre.cy_px = 300.0;
  const PinholeCamera pinhole(PinholeIntrinsics{}), shifted(off_centre);
  const FootprintCamera footprint(narrowCamera());
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const ViewPose pose{Vec3(1, 2, 3), 30.0, -20.0};
  const ViewFrame frame = makeViewFrame(pose);
  for (const CameraModel* cam :
       {static_cast<const CameraModel*>(&pinhole), static_cast<const CameraModel*>(&shifted),
        static_cast<const CameraModel*>(&footprint)}) {
    const double cone = cam->maxOffAxisRad();
    ASSERT_GT(cone, 0.0);
    ASSERT_LT(cone, 0.5 * kPi);
    double widest = 0.0;
    int imaged = 0;
    for (int k = 0; k < 20000; ++k) {
      const Vec3 d(1.0 + u(rng), 1.5 * u(rng), 1.5 * u(rng));  // mostly ahead, in camera axes
      const Vec3 p = pose.position + d.x() * frame.forward + d.y() * frame.right + d.z() * frame.up;
      if (!cam->project(pose, p).in_image) continue;
      ++imaged;
      const double angle = std::acos(std::clamp(d.x() / d.norm(), -1.0, 1.0));
      EXPECT_LE(angle, cone + 1e-12);
      widest = std::max(widest, angle);
    }
    EXPECT_GT(imaged, 1000);
    EXPECT_GT(widest, cone - 0.02);
  }
  EXPECT_NEAR(pinhole.maxOffAxisRad(), std::atan(std::hypot(320.0 / 417.0467, 240.0 / 461.0951)),
              1e-12);
}

// ------------------------------------------------------------------ brute force

TEST(CoverageEvaluator, NadirViewsMatchFootprintRectangles) {
  const PointList plane = planeGrid(-2.0, 2.0, -1.5, 1.5, 0.1, 0.0);  // 41 × 31
  ASSERT_EQ(plane.size(), 1271u);
  const FootprintCamera cam(narrowCamera());
  const double w = 1.2, h = 0.8, d = 1.5;
  // Nadir views at several heights and headings (offsets avoid ties at the edges).
  const std::vector<ViewPose> views = {
      {Vec3(0.0137, 0.0213, 1.0), 90.0, -90.0},   {Vec3(-1.2071, 0.5113, 1.5), 0.0, -90.0},
      {Vec3(1.4033, -0.7391, 1.9), 30.0, -90.0},  {Vec3(0.6047, 0.9517, 1.2), -120.0, -90.0},
      {Vec3(-0.4517, -1.0219, 2.4), 90.0, -90.0}, {Vec3(1.9611, 1.4827, 1.7), 145.0, -90.0},
      {Vec3(0.8123, 0.1377, 1.55), 90.0, -90.0}};
  // The footprint rectangle on the plane: a = offset along the image width axis
  // (sin y, −cos y), b = along the photo's up axis (cos y, sin y); half sizes scale
  // with height: (w/2)·H/D, (h/2)·H/D.
  auto inside = [&](const ViewPose& v, const Vec3& p) {
    const double dx = p.x() - v.position.x(), dy = p.y() - v.position.y();
    const double yaw = v.yaw_deg * kDeg, height = v.position.z() - p.z();
    const double a = dx * std::sin(yaw) - dy * std::cos(yaw);
    const double b = dx * std::cos(yaw) + dy * std::sin(yaw);
    return std::abs(a) <= 0.5 * w * height / d && std::abs(b) <= 0.5 * h * height / d;
  };
  CoverageCriteria c;
  c.max_gsd_mm_per_px = 1.6;   // GSD = range·0.8 → range ≤ 2 m: cuts the corners at 1.9 m
  c.max_incidence_deg = 20.0;  // cuts the sides below 1.1 m (atan(0.4/1.0) = 21.8°)
  const Vec3 up = Vec3::UnitZ();
  const std::vector<Vec3> normal{up};
  const double focal = 1000.0 * d / w;
  const double own_range = d * 2.0;  // standoff × slack

  const auto ref = bruteForce(plane, up, views, focal, own_range, c, inside);
  const CoverageResult res = evaluateCoverage(plane, normal, views, cam, c, nullptr);
  EXPECT_EQ(res.points, plane.size());
  EXPECT_EQ(res.views_per_point, ref);
  EXPECT_EQ(res.uncovered, zeros(ref));
  EXPECT_EQ(res.covered, plane.size() - zeros(ref).size());
  EXPECT_NEAR(res.fraction, static_cast<double>(res.covered) / plane.size(), 1e-15);
  EXPECT_DOUBLE_EQ(res.range_limit_m, 2.0);
  EXPECT_GT(res.covered, 200u);
  EXPECT_LT(res.covered, plane.size());

  // Each limit matters here (otherwise the comparison above could not catch it).
  CoverageCriteria no_gsd = c, no_incidence = c;
  no_gsd.max_gsd_mm_per_px = 0.0;
  no_incidence.max_incidence_deg = 90.0;
  EXPECT_GT(differing(ref, bruteForce(plane, up, views, focal, own_range, no_gsd, inside)), 10);
  EXPECT_GT(differing(ref, bruteForce(plane, up, views, focal, own_range, no_incidence, inside)),
            10);
  for (const CoverageCriteria& relaxed : {no_gsd, no_incidence}) {
    const auto r = bruteForce(plane, up, views, focal, own_range, relaxed, inside);
    EXPECT_EQ(evaluateCoverage(plane, normal, views, cam, relaxed, nullptr).views_per_point, r);
  }

  // An explicit range limit smaller than the GSD range (grid cells of 1.3 m).
  CoverageCriteria ranged = c;
  ranged.max_range_m = 1.3;
  const auto ref_ranged = bruteForce(plane, up, views, focal, 1.3, ranged, inside);
  EXPECT_GT(differing(ref, ref_ranged), 10);
  EXPECT_EQ(evaluateCoverage(plane, normal, views, cam, ranged, nullptr, 3).views_per_point,
            ref_ranged);
  // A range limit beyond the GSD range: the GSD test decides.
  ranged.max_range_m = 2.6;
  const auto ref_far = bruteForce(plane, up, views, focal, 2.6, ranged, inside);
  EXPECT_EQ(ref_far, ref);
  EXPECT_EQ(evaluateCoverage(plane, normal, views, cam, ranged, nullptr).views_per_point, ref_far);
}

TEST(CoverageEvaluator, ObliqueViewsMatchFrustumDefinition) {
  // A tilted plane (normal (0.3, −0.2, 1)) seen by oblique, level and nadir views, some
  // from outside the points' bounding box; pinhole and footprint cameras.
  const Vec3 n = Vec3(0.3, -0.2, 1.0).normalized();
  PointList pts;
  for (const Vec3& p : planeGrid(-2.0, 2.0, -1.5, 1.5, 0.1, 0.0)) {
    pts.emplace_back(p.x(), p.y(), -(n.x() * p.x() + n.y() * p.y()) / n.z());
  }
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> ux(-3.5, 3.5), uy(-2.5, 2.5), uz(0.6, 3.0), yaw(-180, 180),
      pitch(-90, -10);
  std::vector<ViewPose> views;
  views.reserve(41);
  for (int k = 0; k < 40; ++k) {  // braces: the draws are made left to right
    views.push_back({Vec3{ux(rng), uy(rng), uz(rng)}, yaw(rng), pitch(rng)});
  }
  views.push_back({Vec3(3.3, 0.1, 0.5), 180.0, -5.0});  // outside the box, nearly level

  CoverageCriteria c;
  c.max_gsd_mm_per_px = 5.0;
  c.max_incidence_deg = 50.0;

  // Footprint camera (wide: 3 × 2 m at 1.5 m), frustum from the reference frame.
  FootprintCameraOptions fo = narrowCamera();
  fo.camera.footprint_w_m = 3.0;
  fo.camera.footprint_h_m = 2.0;
  const FootprintCamera footprint(fo);
  auto in_frustum = [&](const ViewPose& v, const Vec3& p) {
    const RefFrame f = refFrame(v.yaw_deg, v.pitch_deg);
    const Vec3 d = p - v.position;
    const double z = f.forward.dot(d);
    return z > 0 && std::abs(f.right.dot(d)) <= z * 3.0 / (2 * 1.5) &&
           std::abs(f.up.dot(d)) <= z * 2.0 / (2 * 1.5);
  };
  const auto ref_fp = bruteForce(pts, n, views, 1000.0 * 1.5 / 3.0, 3.0, c, in_frustum);
  const CoverageResult res_fp = evaluateCoverage(pts, {n}, views, footprint, c, nullptr, 2);
  EXPECT_EQ(res_fp.views_per_point, ref_fp);
  EXPECT_GT(res_fp.covered, 100u);
  EXPECT_LT(res_fp.covered, pts.size());

  // Pinhole (FC-Planner), pixel test from the reference frame.
  const PinholeIntrinsics k;
  const PinholeCamera pinhole(k);
  auto in_pixels = [&](const ViewPose& v, const Vec3& p) {
    const RefFrame f = refFrame(v.yaw_deg, v.pitch_deg);
    const Vec3 d = p - v.position;
    const double z = f.forward.dot(d);
    if (z <= 0) return false;
    const double u = k.cx_px + k.fx_px * f.right.dot(d) / z;
    const double vv = k.cy_px + k.fy_px * -f.up.dot(d) / z;
    return u >= 0 && u <= k.width_px && vv >= 0 && vv <= k.height_px;
  };
  CoverageCriteria cp = c;
  cp.max_gsd_mm_per_px = 6.0;  // range ≤ 2.50 m
  const double range_p = 6.0 * 417.0467 / 1000.0;
  const auto ref_p = bruteForce(pts, n, views, 417.0467, range_p, cp, in_pixels);
  const CoverageResult res_p = evaluateCoverage(pts, {n}, views, pinhole, cp, nullptr, 3);
  EXPECT_EQ(res_p.views_per_point, ref_p);
  EXPECT_GT(res_p.covered, 100u);
  EXPECT_LT(res_p.covered, pts.size());
  // A per-point normal list gives the same as one normal for all.
  const std::vector<Vec3> per_point(pts.size(), 2.0 * n);
  EXPECT_EQ(evaluateCoverage(pts, per_point, views, pinhole, cp, nullptr).views_per_point, ref_p);
}

/// A camera that implements project() only: exercises the default projectInFrame.
class ProjectOnlyCamera : public CameraModel {
 public:
  explicit ProjectOnlyCamera(const CameraModel& inner) : inner_(inner) {}
  Projection project(const ViewPose& pose, const Vec3& point) const override {
    return inner_.project(pose, point);
  }
  double maxRange(double g) const override { return inner_.maxRange(g); }

 private:
  const CameraModel& inner_;
};

TEST(CoverageEvaluator, PluggedCameraWithProjectOnly) {
  const PointList plane = planeGrid(-2.0, 2.0, -1.5, 1.5, 0.1, 0.0);
  const PinholeCamera pinhole(PinholeIntrinsics{});
  const ProjectOnlyCamera plugged(pinhole);
  const std::vector<ViewPose> views = {{Vec3(0.31, 0.17, 1.2), 20.0, -70.0},
                                       {Vec3(-1.1, -0.4, 1.0), 160.0, -90.0}};
  CoverageCriteria c;
  c.max_gsd_mm_per_px = 4.0;
  const auto a = evaluateCoverage(plane, {Vec3::UnitZ()}, views, pinhole, c, nullptr);
  const auto b = evaluateCoverage(plane, {Vec3::UnitZ()}, views, plugged, c, nullptr);
  EXPECT_EQ(a.views_per_point, b.views_per_point);
  EXPECT_GT(a.covered, 50u);
}

// ------------------------------------------------------------------ line of sight

/// Scene of the shadow test: the plane z = 0.05 (voxel layer [0, 0.1)) and a wall
/// filling the voxels x ∈ [0.5, 0.6), y ∈ [−2, 2), z ∈ [0.4, 1.5) at voxel 0.1 m.
struct WallScene {
  PointList plane = planeGrid(-2.0, 2.0, -1.5, 1.5, 0.1, 0.05);
  PointList cloud;
  WallScene() {
    cloud = plane;
    for (int j = 0; j < 40; ++j) {
      for (int k = 0; k < 11; ++k) cloud.emplace_back(0.55, -1.95 + 0.1 * j, 0.45 + 0.1 * k);
    }
  }
};

/// Analytic shadow of the wall box B = [0.5, 0.6] × [−2, 2] × [0.4, 1.5] for a camera
/// c with c.x < 0.5 above the wall's top: the ray's height falls linearly with x, so it
/// meets B iff it reaches x = 0.5 and its heights over x ∈ [0.5, min(0.6, p.x)] reach
/// into [0.4, 1.5]: z(min(0.6, p.x)) ≤ 1.5 and z(0.5) ≥ 0.4. (The ray stays within
/// |y| < 2, and the wall is ≥ 0.35 m from the plane, beyond the 0.15 m slack.)
/// `margin` receives how far the point is from the shadow's edge, in height [m].
bool behindWall(const Vec3& c, const Vec3& p, double* margin) {
  if (p.x() <= 0.5) {       // never beyond x = 0.5; meets that face at most at the target's
    *margin = 0.4 - p.z();  // height, far below the wall (the limit of `high` below)
    return false;
  }
  auto z_at = [&](double x) { return c.z() + (p.z() - c.z()) * (x - c.x()) / (p.x() - c.x()); };
  const double low = 1.5 - z_at(std::min(0.6, p.x()));  // ≥ 0: passes below the top
  const double high = z_at(0.5) - 0.4;                  // ≥ 0: passes above the bottom
  *margin = std::min(std::abs(low), std::abs(high));
  return low >= 0 && high >= 0;
}

TEST(VoxelLineOfSight, WallHidesExactlyItsAnalyticShadow) {
  const WallScene s;
  const VoxelLineOfSight los(s.cloud, 0.1, 0.15);
  FootprintCameraOptions o;  // a wide camera that sees the whole plane from 3 m
  o.camera.footprint_w_m = 12.0;
  o.camera.footprint_h_m = 12.0;
  o.standoff_m = 3.0;
  o.range_slack = 2.0;
  const FootprintCamera cam(o);
  const std::vector<ViewPose> views = {{Vec3(0.2, 0.3, 3.0), 0.0, -90.0},
                                       {Vec3(-0.3, -0.2, 2.5), 90.0, -90.0}};
  const CoverageCriteria c;  // incidence ≤ 60°: every plane point passes from both
  const std::vector<Vec3> up{Vec3::UnitZ()};

  EXPECT_EQ(evaluateCoverage(s.plane, up, views, cam, c, nullptr).covered, s.plane.size());

  // One camera: the uncovered points are exactly the shadow.
  const std::vector<ViewPose> first(views.begin(), views.begin() + 1);
  std::vector<std::size_t> shadow;
  for (std::size_t i = 0; i < s.plane.size(); ++i) {
    double margin = 0;
    if (behindWall(first[0].position, s.plane[i], &margin)) shadow.push_back(i);
    ASSERT_GT(margin, 1e-3) << "point " << i << " too close to the shadow edge for the test";
  }
  EXPECT_EQ(shadow.size(), 4u * 31u);  // columns x = 0.6 … 0.9
  const CoverageResult one = evaluateCoverage(s.plane, up, first, cam, c, &los);
  EXPECT_EQ(one.uncovered, shadow);

  // Two cameras: each point is imaged by the cameras it is not hidden from.
  std::vector<int> expected(s.plane.size(), 0);
  for (std::size_t i = 0; i < s.plane.size(); ++i) {
    for (const ViewPose& v : views) {
      double margin = 0;
      expected[i] += behindWall(v.position, s.plane[i], &margin) ? 0 : 1;
      ASSERT_GT(margin, 1e-3);
    }
  }
  const CoverageResult two = evaluateCoverage(s.plane, up, views, cam, c, &los, 3);
  EXPECT_EQ(two.views_per_point, expected);
  EXPECT_EQ(two.uncovered.size(), 3u * 31u);  // x = 0.7 … 0.9 hidden from both
}

TEST(VoxelLineOfSight, EndSlackAndStartVoxel) {
  const PointList cloud = {Vec3(0.05, 0.05, 0.05), Vec3(1.05, 0.05, 0.05)};
  const VoxelLineOfSight tight(cloud, 0.1, 0.0);
  const VoxelLineOfSight slack(cloud, 0.1, 0.2);
  const Vec3 cam(0.05, 0.05, 3.0);
  EXPECT_FALSE(tight.clear(cam, cloud[0]));  // the target's own voxel blocks without slack
  EXPECT_TRUE(slack.clear(cam, cloud[0]));
  EXPECT_TRUE(tight.clear(cam, Vec3(0.5, 0.05, 0.05)));       // between the voxels
  EXPECT_FALSE(tight.clear(cloud[0], Vec3(0.5, 0.05, 3.0)));  // starts in an occupied voxel
  EXPECT_FALSE(slack.clear(Vec3(-1, 0.05, 0.05), Vec3(2, 0.05, 0.05)));      // through both
  EXPECT_TRUE(slack.clear(Vec3(0.9, 0.05, 0.05), Vec3(1.05, 0.05, 0.05)));   // shorter than…
  EXPECT_FALSE(tight.clear(Vec3(0.9, 0.05, 0.05), Vec3(1.05, 0.05, 0.05)));  // …the slack
  // Slack 0.2 of a 0.35 m segment: walks to x = 1.05, into the occupied voxel at 1.0.
  EXPECT_FALSE(slack.clear(Vec3(0.9, 0.05, 0.05), Vec3(1.25, 0.05, 0.05)));
  EXPECT_TRUE(slack.clear(Vec3(0.9, 0.05, 0.05), Vec3(1.19, 0.05, 0.05)));  // stops at 0.99
  EXPECT_TRUE(slack.clear(cam, cam));
  EXPECT_TRUE(VoxelLineOfSight({}, 0.1, 0.0).clear(Vec3::Zero(), Vec3::Ones()));
  EXPECT_EQ(tight.occupiedVoxels(), 2u);
  EXPECT_TRUE(tight.occupied(Vec3(0.01, 0.09, 0.0)));
  EXPECT_FALSE(tight.occupied(Vec3(-0.01, 0.05, 0.05)));
  EXPECT_THROW(VoxelLineOfSight(cloud, 0.0, 0.1), InputError);
  EXPECT_THROW(VoxelLineOfSight(cloud, 0.1, -0.1), InputError);
  // More than 2^21 voxels on an axis throws; far from the origin (UTM-like) does not.
  EXPECT_THROW(VoxelLineOfSight({Vec3(0, 0, 0), Vec3(3e5, 0, 0)}, 0.1, 0.1), InputError);
  const Vec3 far(500000.05, 5000000.05, 100.05);  // mid-voxel
  const VoxelLineOfSight utm({far, far + Vec3(1.0, 0, 0)}, 0.1, 0.0);
  EXPECT_EQ(utm.occupiedVoxels(), 2u);
  EXPECT_TRUE(utm.occupied(far + Vec3(0.01, 0.01, 0.01)));
  EXPECT_FALSE(utm.occupied(far + Vec3(0.51, 0.01, 0.01)));
  EXPECT_FALSE(utm.clear(far - Vec3(1.0, 0, 0), far + Vec3(2.0, 0, 0)));
  EXPECT_TRUE(utm.clear(far + Vec3(-1.0, 0.5, 0), far + Vec3(2.0, 0.5, 0)));
  EXPECT_THROW(tight.clear(Vec3(NAN, 0, 0), cam), InputError);
}

TEST(VoxelLineOfSight, PointExtentClosesAWallSampledOnTheGridsLattice) {
  // A wall x = 3 sampled every v on the grid's own lattice (a simulator's sampling),
  // with millimetre noise across it: its points fall on both sides of the voxel
  // boundary, each layer with holes. Every segment that crosses the wall within its
  // extent must be blocked (the wall is solid); with each point's cube of edge v the
  // voxels close, with the points alone some rays slip through.
  const double v = 0.2;
  PointList wall;
  std::mt19937 rng(46);
  std::uniform_real_distribution<double> noise(-0.01, 0.01);
  for (int j = -20; j <= 20; ++j)
    for (int k = 0; k <= 40; ++k) wall.push_back(Vec3(3.0 + noise(rng), j * v, k * v));
  const VoxelLineOfSight points_only(wall, v, 3.5 * v);
  const VoxelLineOfSight closed(wall, v, 3.5 * v, v);
  std::uniform_real_distribution<double> across(-3.0, 3.0), up(1.0, 7.0), tilt(-0.3, 0.3);
  int crossing = 0, leaked_points_only = 0, leaked_closed = 0, beside_blocked = 0;
  for (int r = 0; r < 2000; ++r) {
    const Vec3 from(-1.0, across(rng), up(rng));
    const Vec3 to(7.0, from.y() + tilt(rng), from.z() + tilt(rng));
    const double t = (3.0 - from.x()) / (to.x() - from.x());
    const Vec3 hit = from + t * (to - from);  // where the segment meets the wall's plane
    if (std::abs(hit.y()) < 3.8 && hit.z() > 0.2 && hit.z() < 7.8) {
      ++crossing;
      leaked_points_only += points_only.clear(from, to) ? 1 : 0;
      leaked_closed += closed.clear(from, to) ? 1 : 0;
    } else if (std::abs(hit.y()) > 4.0 + v || hit.z() > 8.0 + v) {
      beside_blocked += closed.clear(from, to) ? 0 : 1;  // past the wall's edge: clear
    }
  }
  EXPECT_GT(crossing, 1000);
  EXPECT_EQ(leaked_closed, 0) << "of " << crossing << " segments through the wall";
  EXPECT_GT(leaked_points_only, 0) << "the lattice-aligned wall should leak without extent";
  EXPECT_EQ(beside_blocked, 0);
  EXPECT_GE(closed.occupiedVoxels(), points_only.occupiedVoxels());
  EXPECT_THROW(VoxelLineOfSight(wall, v, 0.1, -0.1), InputError);
  EXPECT_THROW(VoxelLineOfSight(wall, v, 0.1, NAN), InputError);
}

/// Tallies of DdaMatchesSlabTestAndMillimetreSampling for one occupancy layout.
struct RayStats {
  int rays{0}, blocked{0}, clear{0};
  int slab_mismatch{0};              ///< DDA ≠ exact slab test
  int sampled_blocked_dda_clear{0};  ///< sampling hit something the DDA missed
  int short_chords{0};               ///< DDA hit a voxel the ray cuts for < 1 mm; sampling missed
  int long_chord_missed{0};          ///< sampling missed a chord ≥ 1 mm (a reference bug)
};

/// Random rays with end points in [lo, hi]³ through the voxels `cells` (indices at kV),
/// compared with an exact slab test and 1 mm sampling; `extra` points join the cloud
/// (far away, to change the brick size) but not the references.
RayStats compareRays(const std::vector<std::tuple<int, int, int>>& cells, const PointList& extra,
                     double lo, double hi, std::mt19937& rng) {
  constexpr double kV = 0.1;
  std::uniform_real_distribution<double> u01(0.0, 1.0), coord(lo, hi);
  std::set<std::tuple<int, int, int>> occ(cells.begin(), cells.end());
  PointList cloud = extra;
  for (const auto& [i, j, k] : cells) {
    cloud.push_back(Vec3{(i + u01(rng)) * kV, (j + u01(rng)) * kV, (k + u01(rng)) * kV});
  }
  auto occupied_at = [&](const Vec3& p) {
    return occ.count({static_cast<int>(std::floor(p.x() / kV)),
                      static_cast<int>(std::floor(p.y() / kV)),
                      static_cast<int>(std::floor(p.z() / kV))}) > 0;
  };
  const double slacks[] = {0.0, 0.05, 0.3};
  const VoxelLineOfSight los_by_slack[] = {VoxelLineOfSight(cloud, kV, slacks[0]),
                                           VoxelLineOfSight(cloud, kV, slacks[1]),
                                           VoxelLineOfSight(cloud, kV, slacks[2])};
  RayStats st;
  for (int r = 0; r < 1500; ++r) {
    const Vec3 a{coord(rng), coord(rng), coord(rng)};  // braces: drawn left to right
    Vec3 b{coord(rng), coord(rng), coord(rng)};
    if (r % 3 == 0) b = a + 0.4 * (b - a);  // some short rays
    if (r % 50 == 1) b.y() = a.y();         // some rays in a coordinate plane
    const double slack = slacks[r % 3];
    const bool dda_clear = los_by_slack[r % 3].clear(a, b);
    const double len = (b - a).norm();
    const double t_end = len - slack;
    const Vec3 dir = (b - a) / len;
    // Exact reference: slab test of [0, t_end] against every occupied voxel; the
    // longest chord inside one.
    double longest = -1.0;
    if (t_end > 0) {
      for (const auto& [i, j, k] : cells) {
        const Vec3 vlo(i * kV, j * kV, k * kV), vhi = vlo + Vec3::Constant(kV);
        double t0 = 0, t1 = t_end;
        for (int ax = 0; ax < 3; ++ax) {
          if (dir[ax] == 0) {
            if (a[ax] < vlo[ax] || a[ax] > vhi[ax]) t0 = 1, t1 = 0;
            continue;
          }
          double ta = (vlo[ax] - a[ax]) / dir[ax], tb = (vhi[ax] - a[ax]) / dir[ax];
          if (ta > tb) std::swap(ta, tb);
          t0 = std::max(t0, ta);
          t1 = std::min(t1, tb);
        }
        if (t0 <= t1) longest = std::max(longest, t1 - t0);
      }
    }
    const bool slab_clear = longest < 0;
    // Sampling reference: every 1 mm along [0, t_end], and t_end itself.
    bool sampled_clear = true;
    if (t_end > 0) {
      for (double t = 0; t < t_end && sampled_clear; t += 1e-3) {
        sampled_clear = !occupied_at(a + t * dir);
      }
      if (sampled_clear) sampled_clear = !occupied_at(a + t_end * dir);
    }
    ++st.rays;
    st.slab_mismatch += dda_clear != slab_clear;
    st.sampled_blocked_dda_clear += !sampled_clear && dda_clear;
    if (sampled_clear && !dda_clear) {
      // Sampling may only miss a voxel the ray cuts for less than one step.
      (longest < 1e-3 ? st.short_chords : st.long_chord_missed)++;
    }
    (dda_clear ? st.clear : st.blocked)++;
  }
  return st;
}

void expectAgreement(const RayStats& st) {
  EXPECT_EQ(st.slab_mismatch, 0);
  EXPECT_EQ(st.sampled_blocked_dda_clear, 0);
  EXPECT_EQ(st.long_chord_missed, 0);
  EXPECT_LE(st.short_chords, st.rays / 100);
  EXPECT_GT(st.blocked, st.rays / 10);  // both outcomes are well represented
  EXPECT_GT(st.clear, st.rays / 10);
}

TEST(VoxelLineOfSight, DdaMatchesSlabTestAndMillimetreSampling) {
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  {
    SCOPED_TRACE("uniform 2 % of 20^3 voxels");
    std::vector<std::tuple<int, int, int>> cells;
    for (int i = 0; i < 20; ++i) {
      for (int j = 0; j < 20; ++j) {
        for (int k = 0; k < 20; ++k) {
          if (u01(rng) < 0.02) cells.emplace_back(i, j, k);
        }
      }
    }
    expectAgreement(compareRays(cells, {}, -0.5, 2.5, rng));
  }
  // Clusters: 20 % of 6^3 blocks of 8^3 voxels hold 12 % of their voxels, so the walk
  // crosses empty bricks (jumped) and occupied ones; once more with a point 50 km
  // away, which makes the bricks far larger than the clusters.
  std::vector<std::tuple<int, int, int>> clustered;
  for (int bi = 0; bi < 6; ++bi) {
    for (int bj = 0; bj < 6; ++bj) {
      for (int bk = 0; bk < 6; ++bk) {
        if (u01(rng) >= 0.2) continue;
        for (int n = 0; n < 512; ++n) {
          if (u01(rng) < 0.12)
            clustered.emplace_back(bi * 8 + n % 8, bj * 8 + n / 8 % 8, bk * 8 + n / 64);
        }
      }
    }
  }
  {
    SCOPED_TRACE("clustered");
    expectAgreement(compareRays(clustered, {}, -0.5, 5.3, rng));
  }
  {
    SCOPED_TRACE("clustered, far point");
    expectAgreement(compareRays(clustered, {Vec3(5.0e4, -2.0e4, 3.0e4)}, -0.5, 5.3, rng));
  }
}

// ------------------------------------------------------------------ evaluator

/// A camera that opens `gate` on its first projection (the views are then part-way).
class GateOpeningCamera : public CameraModel {
 public:
  GateOpeningCamera(const CameraModel& inner, WorkerGate& gate) : inner_(inner), gate_(gate) {}
  Projection project(const ViewPose& pose, const Vec3& p) const override {
    gate_.open();
    return inner_.project(pose, p);
  }
  Projection projectInFrame(const ViewFrame& frame, const Vec3& p) const override {
    gate_.open();
    return inner_.projectInFrame(frame, p);
  }
  double maxRange(double gsd) const override { return inner_.maxRange(gsd); }
  double maxOffAxisRad() const override { return inner_.maxOffAxisRad(); }

 private:
  const CameraModel& inner_;
  WorkerGate& gate_;
};

TEST(CoverageEvaluator, ThreadCountDoesNotChangeTheResult) {
  const WallScene s;
  const VoxelLineOfSight los(s.cloud, 0.05, 0.2);
  const PinholeCamera cam(PinholeIntrinsics{});
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> ux(-2.5, 2.5), uy(-2, 2), uz(0.8, 3.0), yaw(-180, 180),
      pitch(-90, -20);
  std::vector<ViewPose> views;
  views.reserve(37);
  for (int k = 0; k < 37; ++k) {  // braces: the draws are made left to right
    views.push_back({Vec3{ux(rng), uy(rng), uz(rng)}, yaw(rng), pitch(rng)});
  }
  CoverageCriteria c;
  c.max_gsd_mm_per_px = 5.5;
  const std::vector<Vec3> up{Vec3::UnitZ()};
  const CoverageResult r1 = evaluateCoverage(s.plane, up, views, cam, c, &los, 1);
  EXPECT_GT(r1.covered, 100u);
  EXPECT_LT(r1.covered, s.plane.size());
  EXPECT_GT(r1.los_queries, 1000u);
  for (int t : {2, 3, 8, 64}) {
    const CoverageResult rt = evaluateCoverage(s.plane, up, views, cam, c, &los, t);
    EXPECT_EQ(rt.views_per_point, r1.views_per_point) << t << " threads";
    EXPECT_EQ(rt.uncovered, r1.uncovered);
    EXPECT_EQ(rt.covered, r1.covered);
    EXPECT_EQ(rt.pairs_in_range, r1.pairs_in_range);
    EXPECT_EQ(rt.los_queries, r1.los_queries);
  }
  // Workers that join part-way (a gate opened by a view, as the flight's end opens
  // it in the pipeline) or never (a closed gate) change nothing either.
  WorkerGate opened_midway, closed;
  const GateOpeningCamera opening(cam, opened_midway);
  for (WorkerGate* gate : {&opened_midway, &closed}) {
    const CameraModel& camera = gate == &closed ? static_cast<const CameraModel&>(cam) : opening;
    const CoverageResult rg =
        evaluateCoverage(s.plane, up, views, camera, c, &los, 2, nullptr, gate);
    EXPECT_EQ(rg.views_per_point, r1.views_per_point);
    EXPECT_EQ(rg.pairs_in_range, r1.pairs_in_range);
    EXPECT_EQ(rg.los_queries, r1.los_queries);
  }
  EXPECT_TRUE(opened_midway.isOpen());
  // And the occlusion test matters in this scene.
  EXPECT_GT(differing(r1.views_per_point,
                      evaluateCoverage(s.plane, up, views, cam, c, nullptr, 3).views_per_point),
            10);
}

/// Throws from project() for the view with yaw 13°.
class FailingCamera : public CameraModel {
 public:
  Projection project(const ViewPose& pose, const Vec3&) const override {
    if (pose.yaw_deg == 13.0) throw std::runtime_error("camera failed");
    Projection p;
    p.in_image = true;
    return p;
  }
  double maxRange(double) const override { return 10.0; }
};

TEST(CoverageEvaluator, WorkerExceptionReachesTheCaller) {
  const PointList plane = planeGrid(-1, 1, -1, 1, 0.1, 0.0);
  std::vector<ViewPose> views(20, ViewPose{Vec3(0, 0, 1), 0.0, -90.0});
  views[11].yaw_deg = 13.0;
  const FailingCamera cam;
  for (int t : {1, 3}) {
    EXPECT_THROW(evaluateCoverage(plane, {Vec3::UnitZ()}, views, cam, {}, nullptr, t),
                 std::runtime_error);
  }
  views[11].yaw_deg = 0.0;
  EXPECT_EQ(evaluateCoverage(plane, {Vec3::UnitZ()}, views, cam, {}, nullptr, 3).covered,
            plane.size());
}

TEST(CoverageEvaluator, EmptyInputsAndBadInput) {
  const FootprintCamera cam(FootprintCameraOptions{});
  const PointList plane = planeGrid(0, 1, 0, 1, 0.5, 0.0);
  const std::vector<Vec3> up{Vec3::UnitZ()};
  const std::vector<ViewPose> one = {{Vec3(0, 0, 1.5), 0.0, -90.0}};
  const CoverageResult none = evaluateCoverage({}, {}, one, cam, {}, nullptr);
  EXPECT_EQ(none.points, 0u);
  EXPECT_DOUBLE_EQ(none.fraction, 1.0);
  const CoverageResult no_views = evaluateCoverage(plane, up, {}, cam, {}, nullptr);
  EXPECT_EQ(no_views.covered, 0u);
  EXPECT_DOUBLE_EQ(no_views.fraction, 0.0);
  EXPECT_EQ(no_views.uncovered.size(), plane.size());

  EXPECT_THROW(evaluateCoverage(plane, {up[0], up[0]}, one, cam, {}, nullptr), InputError);
  EXPECT_THROW(evaluateCoverage(plane, {}, one, cam, {}, nullptr), InputError);
  EXPECT_THROW(evaluateCoverage(plane, {Vec3::Zero()}, one, cam, {}, nullptr), InputError);
  EXPECT_THROW(evaluateCoverage(plane, up, one, cam, {}, nullptr, 0), InputError);
  PointList nan_points = plane;
  nan_points[2].y() = NAN;
  EXPECT_THROW(evaluateCoverage(nan_points, up, one, cam, {}, nullptr), InputError);
  std::vector<ViewPose> nan_view = one;
  nan_view[0].pitch_deg = INFINITY;
  EXPECT_THROW(evaluateCoverage(plane, up, nan_view, cam, {}, nullptr), InputError);
  CoverageCriteria bad;
  bad.max_incidence_deg = 0.0;
  EXPECT_THROW(evaluateCoverage(plane, up, one, cam, bad, nullptr), InputError);
  bad = CoverageCriteria{};
  bad.max_gsd_mm_per_px = -1.0;
  EXPECT_THROW(evaluateCoverage(plane, up, one, cam, bad, nullptr), InputError);
  bad = CoverageCriteria{};
  bad.max_range_m = -2.0;
  EXPECT_THROW(bad.validate(), InputError);
}

/// A Surface by hand: plane through boundary[0] with normal n (as in flight_strategy_test).
Surface makeSurface(const PointList& boundary, const Vec3& normal, const Vec3& axis_u) {
  Surface s;
  s.plane.normal = normal.normalized();
  s.plane.offset = -s.plane.normal.dot(boundary[0]);
  s.boundary = boundary;
  Vec3 c = Vec3::Zero();
  for (const auto& p : boundary) c += p;
  s.centroid = c / static_cast<double>(boundary.size());
  s.axis_u = axis_u.normalized();
  s.axis_v = s.plane.normal.cross(s.axis_u);
  return s;
}

/// 5 cm samples of origin + [0, a]·u + [0, b]·v.
PointList sampleRect(const Vec3& origin, const Vec3& u, const Vec3& v, double a, double b) {
  PointList pts;
  const int nu = static_cast<int>(std::round(a / 0.05)),
            nv = static_cast<int>(std::round(b / 0.05));
  for (int j = 0; j <= nv; ++j) {
    for (int i = 0; i <= nu; ++i) pts.push_back(origin + (a * i / nu) * u + (b * j / nv) * v);
  }
  return pts;
}

TEST(CoverageEvaluator, FlightStrategyStopsCoverTheirSurface) {
  struct Case {
    const char* name;
    Vec3 origin, u, v, normal, axis_u;
    double a, b;
  };
  const Case cases[] = {
      {"wall facing +x", Vec3(2, 0, 0), Vec3::UnitY(), Vec3::UnitZ(), Vec3::UnitX(), Vec3::UnitY(),
       8.0, 4.0},
      {"wall facing (1,1,0)", Vec3(1, -1, 0.5), Vec3(-1, 1, 0).normalized(), Vec3::UnitZ(),
       Vec3(1, 1, 0).normalized(), Vec3::UnitZ(), 8.0, 4.0},
      {"roof", Vec3(0, 0, 3), Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ(), Vec3::UnitX(), 4.0, 2.0},
      {"ceiling", Vec3(0, 0, 3), Vec3::UnitY(), Vec3::UnitX(), -Vec3::UnitZ(), Vec3::UnitX(), 4.0,
       2.0}};
  const CoverageOptions opt;  // paper: 0.6 × 0.4 m, 20 % overlap, 1.5 m
  FootprintCameraOptions fo;
  fo.camera = opt.camera;
  fo.standoff_m = opt.standoff_m;
  const FootprintCamera cam(fo);
  for (const Case& k : cases) {
    SCOPED_TRACE(k.name);
    const PointList boundary = {k.origin, k.origin + k.a * k.u, k.origin + k.a * k.u + k.b * k.v,
                                k.origin + k.b * k.v};
    const FlightStrategy fs = planFlightStrategy(makeSurface(boundary, k.normal, k.axis_u), opt);
    ASSERT_GT(fs.stops.size(), 10u);
    std::vector<ViewPose> views;
    for (const Stop& s : fs.stops) views.push_back({s.position, s.yaw_deg, s.gimbal_pitch_deg});
    const PointList pts = sampleRect(k.origin, k.u, k.v, k.a, k.b);
    const std::vector<Vec3> normal{k.normal};
    const CoverageResult all = evaluateCoverage(pts, normal, views, cam, {}, nullptr);
    EXPECT_EQ(all.covered, pts.size());
    EXPECT_LE(*std::max_element(all.views_per_point.begin(), all.views_per_point.end()), 4);

    // Without one interior stop, what is lost lies inside that stop's footprint.
    const std::size_t drop = fs.stops.size() / 2;
    const Stop& gone = fs.stops[drop];
    std::vector<ViewPose> fewer = views;
    fewer.erase(fewer.begin() + static_cast<std::ptrdiff_t>(drop));
    const CoverageResult less = evaluateCoverage(pts, normal, fewer, cam, {}, nullptr);
    EXPECT_GT(less.uncovered.size(), 5u);
    for (std::size_t i : less.uncovered) {
      const Vec3 d = pts[i] - gone.target;
      EXPECT_LE(std::abs(d.dot(fs.axis_w)), 0.3 + 1e-9);
      EXPECT_LE(std::abs(d.dot(fs.axis_h)), 0.2 + 1e-9);
    }
  }
}

TEST(CoverageEvaluator, TimingTwentyThousandPointsFiveHundredViews) {
  // A 10 × 8 m roof sampled by 160 × 125 = 20 000 points, 20 × 25 = 500 nadir views
  // 1.5 m above it; the occupied cloud is the roof plus a 1 × 1 × 1 m chimney (top and
  // sides sampled every 5 cm; 5 cm voxels).
  PointList pts;
  for (int j = 0; j < 125; ++j) {
    for (int i = 0; i < 160; ++i) pts.emplace_back(0.0625 * i + 0.01, 0.064 * j + 0.01, 0.0);
  }
  PointList cloud = pts;
  for (int i = 0; i <= 20; ++i) {
    for (int j = 0; j <= 20; ++j) {
      const double x = 4.5 + 0.05 * i, y = 3.5 + 0.05 * j, h = 0.05 * j;
      cloud.emplace_back(x, y, 1.0);                                 // top
      cloud.emplace_back(x, 3.5, h), cloud.emplace_back(x, 4.5, h);  // sides
      cloud.emplace_back(4.5, 3.5 + 0.05 * i, h), cloud.emplace_back(5.5, 3.5 + 0.05 * i, h);
    }
  }
  std::vector<ViewPose> views;
  for (int r = 0; r < 25; ++r) {
    for (int c = 0; c < 20; ++c)
      views.push_back({Vec3(0.25 + 0.5 * c, 0.16 + 0.32 * r, 1.5), 90.0, -90.0});
  }
  ASSERT_EQ(pts.size(), 20000u);
  ASSERT_EQ(views.size(), 500u);
  const VoxelLineOfSight los(cloud, 0.05, 0.2);
  const std::vector<Vec3> up{Vec3::UnitZ()};
  const FootprintCamera paper(FootprintCameraOptions{});
  const PinholeCamera pinhole(PinholeIntrinsics{});
  CoverageCriteria c;
  c.max_gsd_mm_per_px = 6.0;  // pinhole: range ≤ 2.5 m
  struct Run {
    const char* name;
    const CameraModel* cam;
    int threads;
  };
  for (const Run& run : {Run{"footprint 0.6x0.4", &paper, 2}, Run{"pinhole 640x480", &pinhole, 1},
                         Run{"pinhole 640x480", &pinhole, 2}}) {
    const auto t0 = std::chrono::steady_clock::now();
    const CoverageResult res = evaluateCoverage(pts, up, views, *run.cam, c, &los, run.threads);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    std::cout << "[ timing   ] 20000 points x 500 views, line of sight, " << run.name << ", "
              << run.threads << " thread(s): " << ms << " ms; covered " << res.covered
              << ", pairs in range " << res.pairs_in_range << ", los queries " << res.los_queries
              << "\n";
    EXPECT_GT(res.covered, 15000u);
    EXPECT_LT(res.covered, pts.size() - 20);  // the chimney hides the roof below it
  }
}

}  // namespace
}  // namespace uavip::coverage
