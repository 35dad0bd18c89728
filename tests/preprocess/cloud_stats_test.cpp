// The unit check of a measured cloud against the clouds it should and should not
// flag: the same structure (a 20 m x 12 m x 9 m building sampled every 0.1 m) written
// in metres, millimetres, kilometres and as longitude/latitude with heights in metres.

#include "uavip/preprocess/cloud_stats.h"

#include <gtest/gtest.h>

#include <random>
#include <string>

namespace uavip::preprocess {
namespace {

/// The building's walls and roof, each coordinate scaled by `scale`; with `degrees`,
/// x and y become longitude/latitude near Hong Kong (1° ≈ 111 km) and z stays metres.
PointList building(double scale, bool degrees = false) {
  PointList cloud;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 4000; ++i) {
    Vec3 p(20.0 * u(rng), 12.0 * u(rng), 9.0 * u(rng));
    switch (i % 3) {  // on a wall x = 0, a wall y = 0, or the roof
      case 0:
        p.x() = 0.0;
        break;
      case 1:
        p.y() = 0.0;
        break;
      default:
        p.z() = 9.0;
        break;
    }
    if (degrees) {
      cloud.emplace_back(114.17 + p.x() / 111000.0, 22.32 + p.y() / 111000.0, p.z());
    } else {
      cloud.push_back(p * scale);
    }
  }
  return cloud;
}

TEST(UnitWarning, OnlyCloudsNotInMetresAreFlaggedAndEachIsToldItsFix) {
  EXPECT_EQ(unitWarning(measureCloud(building(1.0))), "");
  const std::string mm = unitWarning(measureCloud(building(1000.0)));
  EXPECT_NE(mm.find("scale: 0.001"), std::string::npos) << mm;
  const std::string km = unitWarning(measureCloud(building(0.001)));
  EXPECT_NE(km.find("scale: 1000"), std::string::npos) << km;
  const std::string deg = unitWarning(measureCloud(building(1.0, true)));
  EXPECT_NE(deg.find("degrees"), std::string::npos) << deg;
  // Large but real: a 1.2 km airborne strip with points 0.6 m apart is metres.
  CloudStats strip;
  strip.points = 100000;
  strip.extent_m = Vec3(1177.0, 563.0, 114.0) * 0.3048;
  strip.spacing_m = 0.6;
  EXPECT_EQ(unitWarning(strip), "");
  // Anything under 1 m across is flagged (a warning, not an error): no UAV
  // inspects it.
  strip.extent_m = Vec3(0.5, 0.3, 0.4);
  strip.spacing_m = 0.002;
  EXPECT_NE(unitWarning(strip).find("kilometres"), std::string::npos);
}

}  // namespace
}  // namespace uavip::preprocess
