// Tests of the camera model (paper §II-F, QGroundControl CameraCalc on both axes):
// footprint and standoff worked by hand.
#include "uavip/coverage/camera.h"

#include <gtest/gtest.h>

#include <string>

#include "uavip/core/error.h"
#include "uavip/coverage/flight_strategy.h"

namespace uavip::coverage {
namespace {

Camera sensorCamera(double sw, double sh, double f, int iw, int ih, double gsd) {
  Camera c;
  c.from_sensor = true;
  c.sensor_w_mm = sw;
  c.sensor_h_mm = sh;
  c.focal_mm = f;
  c.image_w_px = iw;
  c.image_h_px = ih;
  c.gsd_mm_per_px = gsd;
  return c;
}

TEST(Camera, DirectFootprintKeepsStandoff) {
  Camera c;  // the paper's 0.6 × 0.4 m photo
  const CameraGeometry g = solveCamera(c, 1.5);
  EXPECT_DOUBLE_EQ(g.footprint_w_m, 0.6);
  EXPECT_DOUBLE_EQ(g.footprint_h_m, 0.4);
  EXPECT_DOUBLE_EQ(g.standoff_m, 1.5);
  EXPECT_EQ(g.gsd_w_mm, 0.0);
  EXPECT_EQ(g.gsd_h_mm, 0.0);
  EXPECT_THROW(solveCamera(c, 0.0), InputError);
}

TEST(Camera, SymmetricSensorByHand) {
  // 1" sensor 13.2 × 8.8 mm, f 8.8 mm, 5472 × 3648 px, GSD 1 mm/px:
  // D = min(5472·1·8.8/13.2, 3648·1·8.8/8.8) mm = min(3648, 3648) mm = 3.648 m;
  // footprint = D·S/f = 3.648·13.2/8.8 = 5.472 m by 3.648·8.8/8.8 = 3.648 m (= I·GSD).
  const CameraGeometry g = solveCamera(sensorCamera(13.2, 8.8, 8.8, 5472, 3648, 1.0), 99.0);
  EXPECT_NEAR(g.standoff_m, 3.648, 1e-9);
  EXPECT_NEAR(g.footprint_w_m, 5.472, 1e-9);
  EXPECT_NEAR(g.footprint_h_m, 3.648, 1e-9);
  EXPECT_NEAR(g.gsd_w_mm, 1.0, 1e-9);
  EXPECT_NEAR(g.gsd_h_mm, 1.0, 1e-9);
}

TEST(Camera, AsymmetricSensorHeightLimits) {
  // 10 × 10 mm sensor, f 10 mm, 2000 × 1000 px, GSD 1 mm/px:
  // D_w = 2000·1·10/10 = 2000 mm, D_h = 1000·1·10/10 = 1000 mm → D = 1 m (height limits);
  // footprint 1·10/10 = 1 m on both axes; GSD_w = 1000·10/(2000·10) = 0.5 mm/px, GSD_h = 1.
  const CameraGeometry g = solveCamera(sensorCamera(10.0, 10.0, 10.0, 2000, 1000, 1.0), 5.0);
  EXPECT_NEAR(g.standoff_m, 1.0, 1e-12);
  EXPECT_NEAR(g.footprint_w_m, 1.0, 1e-12);
  EXPECT_NEAR(g.footprint_h_m, 1.0, 1e-12);
  EXPECT_NEAR(g.gsd_w_mm, 0.5, 1e-12);
  EXPECT_NEAR(g.gsd_h_mm, 1.0, 1e-12);
}

TEST(Camera, AsymmetricSensorWidthLimits) {
  // 1/2.3" sensor 6.17 × 4.55 mm, f 4.5 mm, 4000 × 3000 px, GSD 2 mm/px:
  // D_w = 4000·2·4.5/6.17 = 5834.68 mm, D_h = 3000·2·4.5/4.55 = 5934.07 mm → D = 5.83468 m;
  // footprint_w = I_w·GSD = 8.000 m, footprint_h = 5.83468·4.55/4.5 = 5.89951 m;
  // GSD_h = 5834.68·4.55/(3000·4.5) = 1.96650 mm/px (finer than required).
  const CameraGeometry g = solveCamera(sensorCamera(6.17, 4.55, 4.5, 4000, 3000, 2.0), 5.0);
  EXPECT_NEAR(g.standoff_m, 5.83468, 1e-5);
  EXPECT_NEAR(g.footprint_w_m, 8.0, 1e-9);
  EXPECT_NEAR(g.footprint_h_m, 5.89951, 1e-5);
  EXPECT_NEAR(g.gsd_w_mm, 2.0, 1e-9);
  EXPECT_NEAR(g.gsd_h_mm, 1.96650, 1e-5);
  EXPECT_LE(g.gsd_h_mm, 2.0);  // the requirement holds on both axes
}

std::string errorOf(const Camera& c) {
  try {
    c.validate();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// Validation names the config key of the bad field (camera.footprint_m holds
// footprint_w_m and footprint_h_m) and the value.
TEST(Camera, ValidateNamesTheField) {
  Camera c;
  EXPECT_EQ(errorOf(c), "");
  c.footprint_w_m = 0.0;
  EXPECT_NE(errorOf(c).find("footprint_m must be > 0, got 0"), std::string::npos);
  c = Camera{};
  c.footprint_h_m = -1.0;
  EXPECT_NE(errorOf(c).find("footprint_m must be > 0, got -1"), std::string::npos);
  EXPECT_NE(errorOf(c).find("camera:"), std::string::npos);

  const Camera good = sensorCamera(13.2, 8.8, 8.8, 5472, 3648, 1.0);
  EXPECT_EQ(errorOf(good), "");
  Camera bad = good;
  bad.sensor_w_mm = 0.0;
  EXPECT_NE(errorOf(bad).find("sensor_mm must be > 0, got 0"), std::string::npos);
  bad = good;
  bad.sensor_h_mm = -2.0;
  EXPECT_NE(errorOf(bad).find("sensor_mm must be > 0, got -2"), std::string::npos);
  bad = good;
  bad.focal_mm = 0.0;
  EXPECT_NE(errorOf(bad).find("focal_mm"), std::string::npos);
  bad = good;
  bad.image_w_px = 0;
  EXPECT_NE(errorOf(bad).find("image_px must be in [1, 1e+06], got 0"), std::string::npos);
  bad = good;
  bad.image_h_px = -5;
  EXPECT_NE(errorOf(bad).find("image_px must be in [1, 1e+06], got -5"), std::string::npos);
  bad = good;
  bad.gsd_mm_per_px = 0.0;
  EXPECT_NE(errorOf(bad).find("gsd_mm_per_px"), std::string::npos);
  EXPECT_THROW(solveCamera(bad, 1.0), InputError);
  // With from_sensor the direct footprint is not used, so it need not be valid.
  Camera ignored = good;
  ignored.footprint_w_m = 0.0;
  EXPECT_EQ(errorOf(ignored), "");
}

TEST(Camera, AStandoffBeyondTheCamerasRangeIsRefused) {
  // The camera: 5472 px × 1e6 mm/px × 8.8 mm / 13.2 mm = 3,648 km away.
  Camera far = sensorCamera(13.2, 8.8, 8.8, 5472, 3648, 1e6);
  try {
    far.validate("camera");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("3.648e+06 m"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("max_range_m"), std::string::npos) << e.what();
  }
  // 2 mm/px: 7.296 m, within 1 km; within a given max_range_m of 8 m, not of 7 m.
  Camera near = sensorCamera(13.2, 8.8, 8.8, 5472, 3648, 2.0);
  EXPECT_NO_THROW(near.validate());
  near.max_range_m = 8.0;
  EXPECT_NO_THROW(near.validate());
  near.max_range_m = 7.0;
  EXPECT_THROW(near.validate(), InputError);
  near.max_range_m = -1.0;
  EXPECT_THROW(near.validate(), InputError);
  // A direct footprint: the standoff of the coverage options is checked.
  CoverageOptions o;
  o.standoff_m = 1500.0;
  EXPECT_THROW(o.validate("coverage"), InputError);
  o.camera.max_range_m = 2000.0;
  EXPECT_NO_THROW(o.validate("coverage"));
  o.camera.max_range_m = 10.0;
  o.standoff_m = 20.0;
  EXPECT_THROW(o.validate("coverage"), InputError);
}

}  // namespace
}  // namespace uavip::coverage
