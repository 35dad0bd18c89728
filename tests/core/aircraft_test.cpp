#include "uavip/core/aircraft.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "uavip/core/error.h"
#include "uavip/core/math.h"

namespace uavip::aircraft {
namespace {

/// Diagonal field of view of a camera [deg].
double diagonalFovDeg(const CameraSpec& c) {
  return 2.0 * std::atan(0.5 * std::hypot(c.sensor_w_mm, c.sensor_h_mm) / c.focal_mm) / kDegToRad;
}

TEST(Aircraft, CamerasMatchTheMakersPublishedFieldOfViewAndGsd) {
  // Diagonal fields of view printed in the data sheets (wide cameras).
  EXPECT_NEAR(diagonalFovDeg(findProfile("m3e").payload.camera), 84.0, 2.5);
  EXPECT_NEAR(diagonalFovDeg(findProfile("m30").payload.camera), 84.0, 2.5);
  EXPECT_NEAR(diagonalFovDeg(findProfile("m350").payload.camera), 82.9, 2.5);
  EXPECT_NEAR(diagonalFovDeg(findProfile("m350", "h20n").payload.camera), 70.5, 2.5);
  // Mavic 3 Enterprise: GSD = H / 36.5 cm/px (its specifications); at 100 m 27.4 mm/px.
  const CameraSpec& m3e = findProfile("m3e").payload.camera;
  const double gsd_mm = 100.0 * 1000.0 * m3e.sensor_w_mm / (m3e.image_w_px * m3e.focal_mm);
  EXPECT_NEAR(gsd_mm, 1000.0 / 36.5, 0.03 * 1000.0 / 36.5);
}

TEST(Aircraft, EveryProfileIsCompleteAndNamedOnce) {
  std::set<std::string> names;
  for (const Profile& p : profiles()) {
    EXPECT_TRUE(names.insert(p.name).second) << p.name;
    if (p.isGeneric()) continue;
    const CameraSpec& c = p.payload.camera;
    EXPECT_GT(c.sensor_w_mm, 0.0) << p.name;
    EXPECT_GT(c.focal_mm, 0.0) << p.name;
    EXPECT_GT(c.image_w_px, 0) << p.name;
    EXPECT_LT(p.payload.pitch_min_deg, p.payload.pitch_max_deg) << p.name;
    EXPECT_GT(p.max_speed_mps, 0.0) << p.name;
    EXPECT_GT(p.enduranceS(), 0.0) << p.name;
    EXPECT_GT(p.span_m, 0.0) << p.name;
    EXPECT_GT(p.drone_enum, 0) << p.name;
  }
  EXPECT_TRUE(names.count("generic"));
}

TEST(Aircraft, PayloadsGoOnTheM300AndM350OnlyAndUnknownNamesAreRefused) {
  const Profile up = findProfile("m350", "h20-up");
  EXPECT_EQ(up.payload.position_index, 2);
  EXPECT_GE(up.payload.pitch_max_deg, 90.0);
  EXPECT_EQ(findProfile("m300", "h30").payload.payload_enum, 82);
  EXPECT_THROW(findProfile("m3e", "h30"), InputError);
  EXPECT_THROW(findProfile("m350", "p1"), InputError);
  try {
    findProfile("phantom4");
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("m4t"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(pitchWithin(35.0 + 1e-7, -90.0, 35.0));
  EXPECT_FALSE(pitchWithin(35.01, -90.0, 35.0));
}

}  // namespace
}  // namespace uavip::aircraft
