// Tests of stage 6 (paper §II-F): photo stops over hand-built surfaces, checked
// against hand-worked counts, a dense coverage sampling, and an independent
// point-in-triangle test.
#include "uavip/coverage/flight_strategy.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "uavip/core/error.h"
#include "uavip/core/geometry.h"

namespace uavip::coverage {
namespace {

constexpr double kDeg = M_PI / 180.0;

/// A Surface built by hand: plane through boundary[0] with normal n, centroid = mean
/// of the boundary, axis_v = n × axis_u.
Surface makeSurface(const PointList& boundary, const Vec3& normal, const Vec3& axis_u, int id = 3) {
  Surface s;
  s.id = id;
  s.plane.normal = normal.normalized();
  s.plane.offset = -s.plane.normal.dot(boundary[0]);
  s.boundary = boundary;
  s.inliers = boundary;
  Vec3 c = Vec3::Zero();
  for (const auto& p : boundary) c += p;
  s.centroid = c / static_cast<double>(boundary.size());
  s.axis_u = axis_u.normalized();
  s.axis_v = s.plane.normal.cross(s.axis_u);
  s.area_m2 = polygonArea(boundary);
  s.density_area_m2 = s.area_m2;
  return s;
}

/// Rectangle origin + [0, a]·u + [0, b]·v, counter-clockwise seen from u × v.
PointList rectangle(const Vec3& origin, const Vec3& u, const Vec3& v, double a, double b) {
  return {origin, origin + a * u, origin + a * u + b * v, origin + b * v};
}

/// The 8 m × 4 m wall of the brief, at x = 2 facing +x (seen from +x, +y is right).
Surface wallFacingX() {
  return makeSurface(rectangle(Vec3(2, 0, 0), Vec3::UnitY(), Vec3::UnitZ(), 8.0, 4.0),
                     Vec3::UnitX(), Vec3::UnitY());
}

/// Camera frame of a 2-DOF mount from (yaw, pitch): forward, right, image-up.
struct Frame {
  Vec3 forward, right, up;
};
Frame frameOf(double yaw_deg, double pitch_deg) {
  const double y = yaw_deg * kDeg, p = pitch_deg * kDeg;
  Frame f;
  f.forward = Vec3(std::cos(p) * std::cos(y), std::cos(p) * std::sin(y), std::sin(p));
  f.right = Vec3(std::sin(y), -std::cos(y), 0.0);  // no roll: right stays horizontal
  f.up = f.right.cross(f.forward);
  return f;
}

/// True when q (on the plane) lies in the footprint of stop s, using axes w, h.
bool inFootprint(const Vec3& q, const Stop& s, const Vec3& w, const Vec3& h, double fw, double fh) {
  const Vec3 d = q - s.target;
  return std::abs(d.dot(w)) <= 0.5 * fw + 1e-9 && std::abs(d.dot(h)) <= 0.5 * fh + 1e-9;
}

TEST(FlightStrategy, PaperSpacingAndWallCount) {
  const Surface wall = wallFacingX();
  CoverageOptions opt;  // 0.6 × 0.4 m, 20 % overlap, standoff 1.5 m
  const FlightStrategy fs = planFlightStrategy(wall, opt);
  EXPECT_NEAR(fs.spacing_w_m, 0.48, 1e-12);
  EXPECT_NEAR(fs.spacing_h_m, 0.32, 1e-12);
  EXPECT_EQ(fs.surface_id, 3);
  EXPECT_EQ(fs.cols, 17);  // ⌈8/0.48⌉ = ⌈16.67⌉
  EXPECT_EQ(fs.rows, 13);  // ⌈4/0.32⌉ = ⌈12.5⌉
  ASSERT_EQ(fs.stops.size(), 221u);
  const double ideal = 32.0 / (0.48 * 0.32);  // area / cell area = 208.3
  EXPECT_LT(std::abs(fs.stops.size() - ideal), 0.1 * ideal);
  EXPECT_DOUBLE_EQ(fs.camera.standoff_m, 1.5);
  std::set<std::pair<int, int>> cells;
  for (size_t i = 0; i < fs.stops.size(); ++i) {
    EXPECT_EQ(fs.stops[i].index, static_cast<int>(i));
    EXPECT_EQ(fs.stops[i].surface_id, 3);
    cells.insert({fs.stops[i].row, fs.stops[i].col});
  }
  EXPECT_EQ(cells.size(), 221u);
}

TEST(FlightStrategy, WallAxesAreHorizontalAndUp) {
  const FlightStrategy fs = planFlightStrategy(wallFacingX(), CoverageOptions{});
  // Facing +x: image width along ±y (horizontal), height along +z.
  EXPECT_NEAR(std::abs(fs.axis_w.y()), 1.0, 1e-12);
  EXPECT_NEAR(fs.axis_h.z(), 1.0, 1e-12);
  EXPECT_NEAR((fs.axis_w.cross(fs.axis_h) - Vec3::UnitX()).norm(), 0.0, 1e-12);
}

/// Every point of a 5 cm sample of the (rectangular) surface origin + [0,a]u + [0,b]v
/// lies in the footprint of some stop.
void expectCovered(const FlightStrategy& fs, const Vec3& origin, const Vec3& u, const Vec3& v,
                   double a, double b) {
  const int nu = static_cast<int>(std::round(a / 0.05)),
            nv = static_cast<int>(std::round(b / 0.05));
  int uncovered = 0;
  for (int i = 0; i <= nu; ++i) {
    for (int j = 0; j <= nv; ++j) {
      const Vec3 q = origin + (a * i / nu) * u + (b * j / nv) * v;
      bool covered = false;
      for (const Stop& s : fs.stops) {
        if (inFootprint(q, s, fs.axis_w, fs.axis_h, fs.camera.footprint_w_m,
                        fs.camera.footprint_h_m)) {
          covered = true;
          break;
        }
      }
      if (!covered) ++uncovered;
    }
  }
  EXPECT_EQ(uncovered, 0);
}

TEST(FlightStrategy, WallIsFullyCovered) {
  const FlightStrategy fs = planFlightStrategy(wallFacingX(), CoverageOptions{});
  expectCovered(fs, Vec3(2, 0, 0), Vec3::UnitY(), Vec3::UnitZ(), 8.0, 4.0);
}

TEST(FlightStrategy, RotatedWallCountAndCoverage) {
  // The same 8 × 4 m wall turned to face (1, 1, 0)/√2, axis_u deliberately vertical:
  // the image width must still be horizontal.
  const Vec3 n = Vec3(1, 1, 0).normalized();
  const Vec3 along = Vec3::UnitZ().cross(n);  // horizontal, right when seen from +n
  const Surface wall =
      makeSurface(rectangle(Vec3(1, -1, 0.5), along, Vec3::UnitZ(), 8.0, 4.0), n, Vec3::UnitZ());
  const FlightStrategy fs = planFlightStrategy(wall, CoverageOptions{});
  EXPECT_NEAR(fs.axis_w.z(), 0.0, 1e-12);
  EXPECT_NEAR(fs.axis_w.dot(n), 0.0, 1e-12);
  EXPECT_EQ(fs.cols, 17);
  EXPECT_EQ(fs.rows, 13);
  EXPECT_EQ(fs.stops.size(), 221u);
  expectCovered(fs, Vec3(1, -1, 0.5), along, Vec3::UnitZ(), 8.0, 4.0);
}

TEST(FlightStrategy, StopsAtStandoffOnNormalSide) {
  const Surface wall = wallFacingX();
  CoverageOptions opt;
  opt.standoff_m = 2.25;
  const FlightStrategy fs = planFlightStrategy(wall, opt);
  ASSERT_FALSE(fs.stops.empty());
  for (const Stop& s : fs.stops) {
    EXPECT_NEAR(s.target.x(), 2.0, 1e-12);     // on the plane x = 2
    EXPECT_NEAR(s.position.x(), 4.25, 1e-12);  // 2.25 m in front, on the +x side
    EXPECT_NEAR((s.position - s.target).norm(), 2.25, 1e-12);
    // Targets are within the wall's extent grown by half a footprint.
    EXPECT_GE(s.target.y(), -0.3 - 1e-9);
    EXPECT_LE(s.target.y(), 8.3 + 1e-9);
    EXPECT_GE(s.target.z(), -0.2 - 1e-9);
    EXPECT_LE(s.target.z(), 4.2 + 1e-9);
  }
}

TEST(FlightStrategy, SensorCameraSetsStandoff) {
  CoverageOptions opt;
  opt.camera.from_sensor = true;
  opt.camera.sensor_w_mm = 10.0;
  opt.camera.sensor_h_mm = 10.0;
  opt.camera.focal_mm = 10.0;
  opt.camera.image_w_px = 2000;
  opt.camera.image_h_px = 1000;
  opt.camera.gsd_mm_per_px = 1.0;  // D = 1 m, footprint 1 × 1 m (camera_test)
  opt.overlap_w = 0.5;
  opt.overlap_h = 0.0;
  const FlightStrategy fs = planFlightStrategy(wallFacingX(), opt);
  EXPECT_NEAR(fs.spacing_w_m, 0.5, 1e-12);
  EXPECT_NEAR(fs.spacing_h_m, 1.0, 1e-12);
  EXPECT_EQ(fs.cols, 16);  // 8/0.5
  EXPECT_EQ(fs.rows, 4);   // 4/1
  ASSERT_EQ(fs.stops.size(), 64u);
  for (const Stop& s : fs.stops) EXPECT_NEAR(s.position.x(), 3.0, 1e-12);
}

TEST(FlightStrategy, YawPitchOfWallsRoofAndCeiling) {
  const FlightStrategy wall = planFlightStrategy(wallFacingX(), CoverageOptions{});
  for (const Stop& s : wall.stops) {
    EXPECT_NEAR(s.gimbal_pitch_deg, 0.0, 1e-9);
    EXPECT_NEAR(s.yaw_deg, 180.0, 1e-9);  // looking along −x
  }
  const Surface north =
      makeSurface(rectangle(Vec3(0, 5, 0), -Vec3::UnitX(), Vec3::UnitZ(), 3.0, 2.0), Vec3::UnitY(),
                  Vec3::UnitX());
  for (const Stop& s : planFlightStrategy(north, CoverageOptions{}).stops) {
    EXPECT_NEAR(s.yaw_deg, -90.0, 1e-9);  // facing +y, looking along −y
    EXPECT_NEAR(s.gimbal_pitch_deg, 0.0, 1e-9);
  }
  // Roof at z = 3 facing up: look straight down.
  const Surface roof = makeSurface(rectangle(Vec3(0, 0, 3), Vec3::UnitX(), Vec3::UnitY(), 4.0, 2.0),
                                   Vec3::UnitZ(), Vec3::UnitX());
  const FlightStrategy rf = planFlightStrategy(roof, CoverageOptions{});
  ASSERT_FALSE(rf.stops.empty());
  for (const Stop& s : rf.stops) {
    EXPECT_NEAR(s.gimbal_pitch_deg, -90.0, 1e-9);
    EXPECT_NEAR(s.position.z(), 4.5, 1e-12);
  }
  // Ceiling at z = 3 facing down (counter-clockwise seen from below): look straight up.
  const Surface ceiling =
      makeSurface(rectangle(Vec3(0, 0, 3), Vec3::UnitY(), Vec3::UnitX(), 2.0, 4.0), -Vec3::UnitZ(),
                  Vec3::UnitX());
  const FlightStrategy cf = planFlightStrategy(ceiling, CoverageOptions{});
  ASSERT_FALSE(cf.stops.empty());
  for (const Stop& s : cf.stops) {
    EXPECT_NEAR(s.gimbal_pitch_deg, 90.0, 1e-9);
    EXPECT_NEAR(s.position.z(), 1.5, 1e-12);
  }
}

TEST(FlightStrategy, HorizontalSurfaceHeadingRule) {
  // Documented rule: on a near-horizontal surface axis_w = axis_u (projected) and the
  // heading is the horizontal direction of axis_h when looking down, of −axis_h when
  // looking up. Roof with axis_u = +x: axis_h = ẑ × x̂ = +y → heading +y (yaw 90).
  const Surface roof = makeSurface(rectangle(Vec3(0, 0, 0), Vec3::UnitX(), Vec3::UnitY(), 4.0, 2.0),
                                   Vec3::UnitZ(), Vec3::UnitX());
  const FlightStrategy rf = planFlightStrategy(roof, CoverageOptions{});
  EXPECT_NEAR((rf.axis_w - Vec3::UnitX()).norm(), 0.0, 1e-12);
  EXPECT_NEAR((rf.axis_h - Vec3::UnitY()).norm(), 0.0, 1e-12);
  EXPECT_EQ(rf.cols, 9);  // ⌈4/0.48⌉
  EXPECT_EQ(rf.rows, 7);  // ⌈2/0.32⌉ = ⌈6.25⌉
  for (const Stop& s : rf.stops) EXPECT_NEAR(s.yaw_deg, 90.0, 1e-9);
  // Ceiling with axis_u = +x: axis_h = (−ẑ) × x̂ = −y → heading +y as well (yaw 90).
  const Surface ceiling =
      makeSurface(rectangle(Vec3(0, 0, 3), Vec3::UnitY(), Vec3::UnitX(), 2.0, 4.0), -Vec3::UnitZ(),
                  Vec3::UnitX());
  const FlightStrategy cf = planFlightStrategy(ceiling, CoverageOptions{});
  EXPECT_NEAR((cf.axis_h + Vec3::UnitY()).norm(), 0.0, 1e-12);
  for (const Stop& s : cf.stops) EXPECT_NEAR(s.yaw_deg, 90.0, 1e-9);
  // Roof with axis_u along the short side: the grid turns with it.
  const Surface turned =
      makeSurface(rectangle(Vec3(0, 0, 0), Vec3::UnitX(), Vec3::UnitY(), 4.0, 2.0), Vec3::UnitZ(),
                  Vec3::UnitY());
  const FlightStrategy tf = planFlightStrategy(turned, CoverageOptions{});
  EXPECT_EQ(tf.cols, 5);   // ⌈2/0.48⌉
  EXPECT_EQ(tf.rows, 13);  // ⌈4/0.32⌉ = ⌈12.5⌉
}

TEST(FlightStrategy, ASquareRoofsRowsRunAlongItsSidesWhateverPcaSays) {
  // A 3 m square roof whose sides run at 30° from +x, planned for a mosaic (at the
  // options' overlap, 0.2). PCA's axis is arbitrary on a square: given along the diagonal
  // (75°), the grid still follows the sides, with the count of the same roof given
  // axis_u along a side (the reference: ⌈3/0.48⌉ × ⌈3/0.32⌉).
  CoverageOptions mosaic;
  mosaic.purpose = "mosaic";
  const Vec3 side(std::cos(30.0 * kDeg), std::sin(30.0 * kDeg), 0.0);
  const Vec3 other = Vec3::UnitZ().cross(side);
  const PointList square = rectangle(Vec3(1, 2, 3), side, other, 3.0, 3.0);
  const Vec3 diagonal = (side + other).normalized();
  const FlightStrategy along = planFlightStrategy(makeSurface(square, Vec3::UnitZ(), side), mosaic);
  const FlightStrategy diag =
      planFlightStrategy(makeSurface(square, Vec3::UnitZ(), diagonal), mosaic);
  EXPECT_EQ(along.cols, 7);
  EXPECT_EQ(along.rows, 10);
  EXPECT_EQ(along.stops.size(), 70u);
  EXPECT_EQ(diag.stops.size(), along.stops.size());
  EXPECT_NEAR(std::abs(diag.axis_w.dot(side)) + std::abs(diag.axis_w.dot(other)), 1.0, 1e-9);
  EXPECT_GE(diag.axis_w.dot(diagonal), 0.0);  // turned to axis_u's side
  // A clearly oblong roof keeps PCA's axis exactly (its rectangle is already the least).
  const Surface oblong =
      makeSurface(rectangle(Vec3(0, 0, 0), side, other, 4.0, 2.0), Vec3::UnitZ(), side);
  EXPECT_LT((planFlightStrategy(oblong, mosaic).axis_w - side).norm(), 1e-12);
  // Inspection keeps PCA's axis: the paper's grid, as before.
  const FlightStrategy inspection =
      planFlightStrategy(makeSurface(square, Vec3::UnitZ(), diagonal), CoverageOptions{});
  EXPECT_LT((inspection.axis_w - diagonal).norm(), 1e-12);
  EXPECT_GT(inspection.stops.size(), along.stops.size());
}

TEST(FlightStrategy, CameraFrameMatchesImageAxes) {
  // For every orientation, the camera frame built from (yaw, pitch) alone looks along
  // −n with image right = axis_w and image up = axis_h (no roll needed).
  std::vector<Surface> surfaces;
  for (double az : {0.0, 37.0, 135.0, -100.0}) {
    for (double el : {0.0, 40.0, -55.0}) {  // |n_z| < 0.95: walls, sloped walls
      const Vec3 n(std::cos(el * kDeg) * std::cos(az * kDeg),
                   std::cos(el * kDeg) * std::sin(az * kDeg), std::sin(el * kDeg));
      const Vec3 u = Vec3::UnitZ().cross(n).normalized();
      const Vec3 v = n.cross(u);
      surfaces.push_back(makeSurface(rectangle(Vec3(1, 2, 3), u, v, 2.0, 1.0), n, v));
    }
  }
  for (double a : {0.0, 25.0, 160.0}) {  // exactly horizontal, any axis_u
    const Vec3 u(std::cos(a * kDeg), std::sin(a * kDeg), 0.0);
    surfaces.push_back(
        makeSurface(rectangle(Vec3(0, 0, 2), u, Vec3::UnitZ().cross(u), 2, 1), Vec3::UnitZ(), u));
    surfaces.push_back(
        makeSurface(rectangle(Vec3(0, 0, 2), u, -Vec3::UnitZ().cross(u), 2, 1), -Vec3::UnitZ(), u));
  }
  for (const Surface& s : surfaces) {
    const FlightStrategy fs = planFlightStrategy(s, CoverageOptions{});
    ASSERT_FALSE(fs.stops.empty());
    const Stop& stop = fs.stops.front();
    const Frame f = frameOf(stop.yaw_deg, stop.gimbal_pitch_deg);
    const Vec3 n = s.plane.normal;
    EXPECT_NEAR((f.forward + n).norm(), 0.0, 1e-9) << "n " << n.transpose();
    EXPECT_NEAR((f.right - fs.axis_w).norm(), 0.0, 1e-9) << "n " << n.transpose();
    EXPECT_NEAR((f.up - fs.axis_h).norm(), 0.0, 1e-9) << "n " << n.transpose();
    EXPECT_GT(stop.yaw_deg, -180.0);
    EXPECT_LE(stop.yaw_deg, 180.0);
    // The view ray from the stop hits the target.
    EXPECT_NEAR((stop.position + fs.camera.standoff_m * f.forward - stop.target).norm(), 0.0, 1e-9);
  }
}

TEST(FlightStrategy, GimbalLimitsMarkCeilingStops) {
  CoverageOptions opt;
  opt.gimbal.pitch_min_deg = -90.0;
  opt.gimbal.pitch_max_deg = 30.0;
  const Surface ceiling =
      makeSurface(rectangle(Vec3(0, 0, 3), Vec3::UnitY(), Vec3::UnitX(), 2.0, 4.0), -Vec3::UnitZ(),
                  Vec3::UnitX());
  const Surface roof = makeSurface(rectangle(Vec3(0, 0, 0), Vec3::UnitX(), Vec3::UnitY(), 4.0, 2.0),
                                   Vec3::UnitZ(), Vec3::UnitX());
  const FlightStrategy cf = planFlightStrategy(ceiling, opt);
  ASSERT_FALSE(cf.stops.empty());
  for (const Stop& s : cf.stops) EXPECT_FALSE(s.gimbal_ok);
  for (const Stop& s : planFlightStrategy(roof, opt).stops) EXPECT_TRUE(s.gimbal_ok);
  for (const Stop& s : planFlightStrategy(wallFacingX(), opt).stops) EXPECT_TRUE(s.gimbal_ok);
  // A wall sloping so the camera must look up by 45°: outside [−90, 30].
  const Vec3 n = Vec3(1, 0, -1).normalized();
  const Vec3 u = Vec3::UnitZ().cross(n).normalized();
  const Surface overhang = makeSurface(rectangle(Vec3(0, 0, 2), u, n.cross(u), 2.0, 1.0), n, u);
  const FlightStrategy of = planFlightStrategy(overhang, opt);
  ASSERT_FALSE(of.stops.empty());
  EXPECT_NEAR(of.stops[0].gimbal_pitch_deg, 45.0, 1e-9);
  EXPECT_FALSE(of.stops[0].gimbal_ok);
  opt.gimbal.pitch_max_deg = 45.0;  // the limit itself is allowed
  EXPECT_TRUE(planFlightStrategy(overhang, opt).stops[0].gimbal_ok);
}

TEST(FlightStrategy, BoustrophedonOrder) {
  const FlightStrategy fs = planFlightStrategy(wallFacingX(), CoverageOptions{});
  ASSERT_EQ(fs.stops.size(), 221u);
  // Independent axes of this wall: width along ±y (the sign is fs.axis_w's), height +z.
  const Vec3 w = fs.axis_w, h = Vec3::UnitZ();
  // Starts in the lowest row at the low-w end.
  const Stop& first = fs.stops.front();
  for (const Stop& s : fs.stops) {
    EXPECT_GE((s.target - first.target).dot(h), -1e-9);
    if (std::abs((s.target - first.target).dot(h)) < 1e-9) {
      EXPECT_GE((s.target - first.target).dot(w), -1e-9);
    }
  }
  int row_changes = 0;
  for (size_t i = 1; i < fs.stops.size(); ++i) {
    const Vec3 d = fs.stops[i].target - fs.stops[i - 1].target;
    const double dw = d.dot(w), dh = d.dot(h);
    const bool step_w = std::abs(std::abs(dw) - 0.48) < 1e-9 && std::abs(dh) < 1e-9;
    const bool step_h = std::abs(dh - 0.32) < 1e-9 && std::abs(dw) < 1e-9;  // up one row
    EXPECT_TRUE(step_w || step_h) << "stop " << i << " dw " << dw << " dh " << dh;
    if (step_h) {
      ++row_changes;
      // The next row runs the other way: direction of travel flips.
      if (i + 1 < fs.stops.size() && i >= 2) {
        const double before = (fs.stops[i - 1].target - fs.stops[i - 2].target).dot(w);
        const double after = (fs.stops[i + 1].target - fs.stops[i].target).dot(w);
        EXPECT_LT(before * after, 0.0);
      }
    }
    EXPECT_GE(fs.stops[i].row, fs.stops[i - 1].row);
  }
  EXPECT_EQ(row_changes, 12);
}

/// Independent point-in-triangle test (same-side signs of 2D cross products).
bool inTriangle(double x, double y, const double (&t)[3][2]) {
  auto cross = [&](int i, int j) {
    return (t[j][0] - t[i][0]) * (y - t[i][1]) - (t[j][1] - t[i][1]) * (x - t[i][0]);
  };
  const double a = cross(0, 1), b = cross(1, 2), c = cross(2, 0);
  return (a > 0 && b > 0 && c > 0) || (a < 0 && b < 0 && c < 0);
}

TEST(FlightStrategy, TriangleKeepsOnlyCellsMeetingIt) {
  // Right triangle on the wall plane x = 0 facing +x, in (y, z): (0,0), (3,0), (0,2).
  const double tri[3][2] = {{0.0, 0.0}, {3.0, 0.0}, {0.0, 2.0}};
  PointList boundary;
  for (const auto& v : tri) boundary.emplace_back(0.0, v[0], v[1]);
  const Surface s = makeSurface(boundary, Vec3::UnitX(), Vec3::UnitY());
  CoverageOptions opt;
  const FlightStrategy fs = planFlightStrategy(s, opt);
  EXPECT_EQ(fs.cols, 7);  // ⌈3/0.48⌉
  EXPECT_EQ(fs.rows, 7);  // ⌈2/0.32⌉ = ⌈6.25⌉
  ASSERT_FALSE(fs.stops.empty());
  EXPECT_LT(fs.stops.size(), 49u);
  // Reconstruct every cell of the grid from one kept stop; sample its footprint.
  const Vec3 w = fs.axis_w, h = fs.axis_h;
  ASSERT_NEAR(std::abs(w.y()), 1.0, 1e-12);
  ASSERT_NEAR(h.z(), 1.0, 1e-12);
  // A stop whose cell centre lies on the triangle keeps it as its photo centre; one
  // whose centre is air looks at the triangle instead (its photo centre moved onto it).
  const Stop* ref = nullptr;
  for (const Stop& st : fs.stops) {
    const bool on = inTriangle(st.target.y(), st.target.z(), tri);
    EXPECT_TRUE(on || std::abs(st.target.y() / 3.0 + st.target.z() / 2.0 - 1.0) < 1e-6 ||
                st.target.y() < 1e-9 || st.target.z() < 1e-9)
        << "photo centre off the triangle: " << st.target.transpose();
    if (on && ref == nullptr) ref = &st;
  }
  ASSERT_NE(ref, nullptr);
  std::set<std::pair<int, int>> kept;
  for (const Stop& st : fs.stops) kept.insert({st.row, st.col});
  const double fw = fs.camera.footprint_w_m, fh = fs.camera.footprint_h_m;
  const int n = 60;
  for (int r = 0; r < fs.rows; ++r) {
    for (int c = 0; c < fs.cols; ++c) {
      const Vec3 centre =
          ref->target + (c - ref->col) * fs.spacing_w_m * w + (r - ref->row) * fs.spacing_h_m * h;
      int inside = 0;
      for (int i = 0; i <= n; ++i) {
        for (int j = 0; j <= n; ++j) {
          const Vec3 q = centre + (-0.5 + double(i) / n) * fw * w + (-0.5 + double(j) / n) * fh * h;
          if (inTriangle(q.y(), q.z(), tri)) ++inside;
        }
      }
      const bool is_kept = kept.count({r, c}) > 0;
      EXPECT_EQ(is_kept, inside > 0) << "cell " << r << "," << c << " inside " << inside;
    }
  }
  // And the kept stops cover the triangle (5 cm sample).
  int uncovered = 0;
  for (int i = 0; i <= 60; ++i) {
    for (int j = 0; j <= 40; ++j) {
      const double y = 0.05 * i, z = 0.05 * j;
      if (y / 3.0 + z / 2.0 > 1.0 + 1e-12) continue;
      bool covered = false;
      for (const Stop& st : fs.stops)
        covered = covered || inFootprint(Vec3(0, y, z), st, w, h, fw, fh);
      if (!covered) ++uncovered;
    }
  }
  EXPECT_EQ(uncovered, 0);
}

TEST(FlightStrategy, DegenerateBoundaryGivesNoStops) {
  Surface s = wallFacingX();
  s.boundary.resize(2);
  const FlightStrategy fs = planFlightStrategy(s, CoverageOptions{});
  EXPECT_TRUE(fs.stops.empty());
  EXPECT_NEAR(fs.spacing_w_m, 0.48, 1e-12);
}

TEST(FlightStrategy, SmallSurfaceGetsOneStop) {
  // A 0.2 × 0.1 m plate: one cell, centred on it.
  const Surface plate =
      makeSurface(rectangle(Vec3(5, 1, 1), Vec3::UnitY(), Vec3::UnitZ(), 0.2, 0.1), Vec3::UnitX(),
                  Vec3::UnitY());
  const FlightStrategy fs = planFlightStrategy(plate, CoverageOptions{});
  EXPECT_EQ(fs.cols, 1);
  EXPECT_EQ(fs.rows, 1);
  ASSERT_EQ(fs.stops.size(), 1u);
  EXPECT_NEAR((fs.stops[0].target - Vec3(5, 1.1, 1.05)).norm(), 0.0, 1e-12);
}

TEST(FlightStrategy, Deterministic) {
  const double tri[3][2] = {{0.0, 0.0}, {3.0, 0.5}, {1.0, 2.0}};
  PointList boundary;
  for (const auto& v : tri) boundary.emplace_back(v[0], v[1], 1.0);
  const Surface s = makeSurface(boundary, Vec3::UnitZ(), Vec3(1, 1, 0));
  const FlightStrategy a = planFlightStrategy(s, CoverageOptions{});
  const FlightStrategy b = planFlightStrategy(s, CoverageOptions{});
  ASSERT_EQ(a.stops.size(), b.stops.size());
  for (size_t i = 0; i < a.stops.size(); ++i) {
    EXPECT_EQ(a.stops[i].position, b.stops[i].position);
    EXPECT_EQ(a.stops[i].target, b.stops[i].target);
    EXPECT_EQ(a.stops[i].yaw_deg, b.stops[i].yaw_deg);
    EXPECT_EQ(a.stops[i].row, b.stops[i].row);
    EXPECT_EQ(a.stops[i].col, b.stops[i].col);
  }
}

std::string errorOf(const CoverageOptions& o) {
  try {
    o.validate();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(CoverageOptions, ValidateNamesTheField) {
  CoverageOptions o;
  EXPECT_EQ(errorOf(o), "");
  o.overlap_w = 1.0;  // the key a file writes: overlap [w, h]
  EXPECT_NE(errorOf(o).find("overlap must be in [0, 1), got 1"), std::string::npos);
  o = CoverageOptions{};
  o.overlap_h = -0.1;
  EXPECT_NE(errorOf(o).find("overlap must be in [0, 1), got -0.1"), std::string::npos);
  o = CoverageOptions{};
  o.standoff_m = 0.0;
  EXPECT_NE(errorOf(o).find("standoff_m"), std::string::npos);
  o = CoverageOptions{};
  o.gimbal.pitch_min_deg = 10.0;
  o.gimbal.pitch_max_deg = 0.0;
  EXPECT_NE(errorOf(o).find("pitch_min_deg"), std::string::npos);
  o = CoverageOptions{};
  o.gimbal.pitch_max_deg = 100.0;
  EXPECT_NE(errorOf(o).find("gimbal_pitch_deg must be in [-90, 90], got 100"), std::string::npos);
  o = CoverageOptions{};
  o.gimbal.pitch_min_deg = -91.0;
  EXPECT_NE(errorOf(o).find("gimbal_pitch_deg must be in [-90, 90], got -91"), std::string::npos);
  o = CoverageOptions{};
  o.purpose = "survey";
  EXPECT_NE(errorOf(o).find("purpose must be one of inspection, mosaic, reconstruction"),
            std::string::npos);
  o = CoverageOptions{};
  o.purpose = "mosaic";
  o.mode = "structure";  // structure mode plans every purpose
  EXPECT_NO_THROW(o.validate());
  o = CoverageOptions{};
  o.camera.footprint_h_m = 0.0;
  EXPECT_NE(errorOf(o).find("footprint_m must be > 0, got 0"), std::string::npos);
  EXPECT_THROW(planFlightStrategy(wallFacingX(), o), InputError);
}

TEST(FlightStrategy, TooManyStopsAreRefusedBeforeAnyIsMade) {
  // 8 × 4 m wall, 1 cm footprint, 20 % overlap: 1000 × 500 cells 0.8 cm apart = 500,000 > 200,000.
  CoverageOptions o;
  o.camera.footprint_w_m = 0.01;
  o.camera.footprint_h_m = 0.01;
  try {
    planFlightStrategy(wallFacingX(), o);
    ADD_FAILURE() << "500,000 stops accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("coverage.max_stops 200000"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("surface 3"), std::string::npos) << e.what();
  }
  o.max_stops = 600000;  // now allowed: the count is the ideal one
  EXPECT_EQ(planFlightStrategy(wallFacingX(), o).stops.size(), 500000u);
}

/// The six faces of the box [lo, hi], outward normals, ids 0–5.
std::vector<Surface> boxFaces(const Vec3& lo, const Vec3& hi) {
  std::vector<Surface> faces;
  for (int axis = 0; axis < 3; ++axis) {
    const int a = (axis + 1) % 3, b = (axis + 2) % 3;
    for (const int side : {0, 1}) {
      Vec3 origin = lo;
      origin[axis] = side == 0 ? lo[axis] : hi[axis];
      const Vec3 u = Vec3::Unit(a), v = Vec3::Unit(b);
      Vec3 n = Vec3::Zero();
      n[axis] = side == 0 ? -1.0 : 1.0;
      faces.push_back(makeSurface(rectangle(origin, u, v, hi[a] - lo[a], hi[b] - lo[b]), n, u,
                                  static_cast<int>(faces.size())));
    }
  }
  return faces;
}

TEST(EdgeLinks, ABoxHasItsTwelveEdgesAndNoOther) {
  const Vec3 lo(0.0, 0.0, 1.0), hi(2.0, 3.0, 2.5);
  const std::vector<Surface> faces = boxFaces(lo, hi);
  std::vector<const Surface*> chosen;
  chosen.reserve(faces.size());
  for (const auto& f : faces) chosen.push_back(&f);
  const std::vector<SurfaceEdge> edges = convexEdges(chosen, 0.25);
  // Reference: the corner pairs that differ in exactly one coordinate.
  std::vector<std::pair<Vec3, Vec3>> truth;
  for (int i = 0; i < 8; ++i)
    for (int j = i + 1; j < 8; ++j) {
      const int diff = i ^ j;
      if (diff != 1 && diff != 2 && diff != 4) continue;
      const auto corner = [&](int k) {
        return Vec3((k & 1) ? hi.x() : lo.x(), (k & 2) ? hi.y() : lo.y(),
                    (k & 4) ? hi.z() : lo.z());
      };
      truth.emplace_back(corner(i), corner(j));
    }
  ASSERT_EQ(truth.size(), 12u);
  ASSERT_EQ(edges.size(), 12u);
  std::set<std::size_t> matched;
  for (const auto& e : edges) {
    for (std::size_t t = 0; t < truth.size(); ++t) {
      const auto& [a, b] = truth[t];
      if (((e.p0 - a).norm() < 1e-9 && (e.p1 - b).norm() < 1e-9) ||
          ((e.p0 - b).norm() < 1e-9 && (e.p1 - a).norm() < 1e-9))
        matched.insert(t);
    }
    const Vec3 sum = faces[static_cast<std::size_t>(e.surface_a)].plane.normal +
                     faces[static_cast<std::size_t>(e.surface_b)].plane.normal;
    EXPECT_LT((e.bisector - sum.normalized()).norm(), 1e-12);
  }
  EXPECT_EQ(matched.size(), 12u);

  // Only a face and its opposite: parallel planes share no edge.
  EXPECT_TRUE(convexEdges({&faces[0], &faces[1]}, 0.25).empty());
  // A wall standing on a floor in front of it meets it at a concave edge: no link.
  const Surface wall = makeSurface(rectangle(Vec3(0, 0, 0), Vec3::UnitX(), Vec3::UnitZ(), 4.0, 3.0),
                                   -Vec3::UnitY(), Vec3::UnitX(), 0);
  const Surface floor =
      makeSurface(rectangle(Vec3(0, -3, 0), Vec3::UnitX(), Vec3::UnitY(), 4.0, 3.0), Vec3::UnitZ(),
                  Vec3::UnitX(), 1);
  EXPECT_TRUE(convexEdges({&wall, &floor}, 0.25).empty());
}

TEST(EdgeLinks, PhotosLookAtTheEdgeAlongItsBisectorAndShareTheirFootprint) {
  const std::vector<Surface> faces = boxFaces(Vec3(0.0, 0.0, 1.0), Vec3(2.0, 3.0, 2.5));
  std::vector<const Surface*> chosen;
  chosen.reserve(faces.size());
  for (const auto& f : faces) chosen.push_back(&f);
  const std::vector<SurfaceEdge> edges = convexEdges(chosen, 0.25);
  CoverageOptions o;
  o.camera.footprint_w_m = 0.9;
  o.camera.footprint_h_m = 0.6;
  o.standoff_m = 1.5;
  const std::vector<FlightStrategy> links = planEdgeLinks(edges, o, 10);
  ASSERT_EQ(links.size(), edges.size());
  for (std::size_t k = 0; k < links.size(); ++k) {
    const SurfaceEdge& e = edges[k];
    const FlightStrategy& fs = links[k];
    EXPECT_EQ(fs.surface_id, 10 + static_cast<int>(k));
    const Vec3 d = (e.p1 - e.p0).normalized();
    const double len = (e.p1 - e.p0).norm();
    // The footprint's side along the edge: the image width for a horizontal edge.
    const double along = std::abs(d.z()) < 0.5 ? 0.9 : 0.6;
    ASSERT_GE(fs.stops.size(), 2u);
    EXPECT_GE(static_cast<double>(fs.stops.size() - 1) * 0.4 * along, len - 2e-3 - 1e-9);
    for (std::size_t i = 0; i < fs.stops.size(); ++i) {
      const Stop& s = fs.stops[i];
      EXPECT_EQ(s.surface_id, fs.surface_id);
      // The target lies on the edge, the UAV on its bisector at the standoff.
      const double t = (s.target - e.p0).dot(d);
      EXPECT_LT((e.p0 + t * d - s.target).norm(), 1e-9);
      EXPECT_GE(t, 0.0);
      EXPECT_LE(t, len);
      EXPECT_LT((s.position - (s.target + 1.5 * e.bisector)).norm(), 1e-9);
      // The camera (yaw by the UAV, pitch by the gimbal) looks at the target.
      const Frame f = frameOf(s.yaw_deg, s.gimbal_pitch_deg);
      EXPECT_LT((f.forward + e.bisector).norm(), 1e-9) << "edge " << k << " stop " << i;
      EXPECT_TRUE(s.gimbal_ok);
      if (i > 0) {  // consecutive photos share >= 60 % of the footprint along the edge
        const double step = (s.target - fs.stops[i - 1].target).norm();
        EXPECT_LE(step, (1.0 - kReconstructionShare) * along + 1e-9);
        EXPECT_GT(step, 0.0);
      }
    }
    EXPECT_LT((fs.stops.front().target - e.p0).norm(), 2e-3);
    EXPECT_LT((fs.stops.back().target - e.p1).norm(), 2e-3);
  }
}

}  // namespace
}  // namespace uavip::coverage
