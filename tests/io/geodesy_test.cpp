// io/geodesy.h against independent references: the EGM96 geoid heights NGA publishes
// with the model (readme of WW15MGH.GRD, "OUTINTPT.DAT"), GeographicLib's own UTM and
// LocalCartesian, and the round trip local -> WGS84 -> local.

#include "uavip/io/geodesy.h"

#include <gtest/gtest.h>

#include <GeographicLib/LocalCartesian.hpp>
#include <GeographicLib/UTMUPS.hpp>
#include <random>
#include <string>

#include "uavip/core/error.h"

namespace {

namespace io = uavip::io;
using uavip::Vec3;

/// NGA's EGM96 check points: latitude, longitude (0..360), geoid height [m].
struct CheckPoint {
  double lat, lon, n;
};
constexpr CheckPoint kNgaEgm96[] = {
    {38.6281550, 269.7791550, -31.628}, {-14.6212170, 305.0211140, -2.969},
    {46.8743190, 102.4487290, -43.575}, {-23.6174460, 133.8747120, 15.871},
    {38.6254730, 359.9995000, 50.066},  {-0.4667440, 0.0023000, 17.329}};

double signedLon(double lon) { return lon > 180.0 ? lon - 360.0 : lon; }

TEST(Geoid, Egm96MatchesNgasPublishedCheckPoints) {
  const io::GeoidModel egm96(io::VerticalDatum::Egm96);
  EXPECT_EQ(egm96.gridName(), "egm96_15.gtx");
  for (const CheckPoint& c : kNgaEgm96) {
    // NGA interpolates the same 15' grid with a 4 x 4 spline, PROJ bilinearly: they
    // agree to 6 cm at these points (5.6 cm at -23.6, 133.9), far inside GNSS heights.
    EXPECT_NEAR(egm96.undulation(c.lat, signedLon(c.lon)), c.n, 0.08) << c.lat << ", " << c.lon;
  }
}

TEST(Geoid, TheEllipsoidHasNoUndulationAndDatumsParse) {
  const io::GeoidModel ellipsoid(io::VerticalDatum::Ellipsoid);
  EXPECT_EQ(ellipsoid.undulation(38.6, -90.2), 0.0);
  EXPECT_EQ(io::parseVerticalDatum("egm2008"), io::VerticalDatum::Egm2008);
  EXPECT_THROW(io::parseVerticalDatum("msl"), uavip::InputError);
  EXPECT_EQ(io::verticalDatumOfEpsg(5773), io::VerticalDatum::Egm96);
  EXPECT_EQ(io::verticalDatumOfEpsg(3855), io::VerticalDatum::Egm2008);
  EXPECT_FALSE(io::verticalDatumOfEpsg(5703));  // NAVD88: not a global geoid model
}

TEST(Georeference, OriginAltitudeIsAboveEgm96AndTheFrameRoundTrips) {
  // The origin at NGA's first check point: N = -31.628 m there.
  const CheckPoint& c = kNgaEgm96[0];
  const double alt_msl = 150.0;
  const io::Georeference geo(io::GeoOrigin{c.lat, signedLon(c.lon), alt_msl});
  const io::Geodetic o = geo.toGeodetic(Vec3::Zero());
  EXPECT_NEAR(o.lat_deg, c.lat, 1e-12);
  EXPECT_NEAR(o.h_ellipsoid_m, alt_msl + c.n, 0.05);
  EXPECT_NEAR(geo.egm96Height(o), alt_msl, 1e-9);
  // GeographicLib's LocalCartesian about the same ellipsoidal origin, built here.
  const GeographicLib::LocalCartesian lc(c.lat, signedLon(c.lon), o.h_ellipsoid_m);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-2000.0, 2000.0);
  for (int i = 0; i < 50; ++i) {
    const Vec3 p(u(rng), u(rng), u(rng) / 20.0);
    const io::Geodetic g = geo.toGeodetic(p);
    double lat = 0.0, lon = 0.0, h = 0.0;
    lc.Reverse(p.x(), p.y(), p.z(), lat, lon, h);
    EXPECT_NEAR(g.lat_deg, lat, 1e-12);
    EXPECT_NEAR(g.lon_deg, lon, 1e-12);
    EXPECT_NEAR(g.h_ellipsoid_m, h, 1e-6);
    EXPECT_LT((geo.toLocal(g) - p).norm(), 1e-6);
  }
}

TEST(Georeference, ACompoundUtmCrsGivesEllipsoidalHeightsAboveItsGeoid) {
  const auto crs = std::make_shared<const io::CrsTransform>("EPSG:32631+5773");
  EXPECT_EQ(crs->verticalEpsg(), 5773);
  EXPECT_EQ(crs->verticalName(), "EGM96 height");
  EXPECT_EQ(io::CrsTransform("EPSG:32631").verticalEpsg(), 0);
  const Vec3 offset(500125.0, 5400458.0, 100.0);
  const io::Georeference geo(crs, offset, io::VerticalDatum::Egm96);
  const io::Georeference on_ellipsoid(crs, offset, io::VerticalDatum::Ellipsoid);
  const io::GeoidModel egm96(io::VerticalDatum::Egm96);
  for (const Vec3& p : {Vec3(1.0, -2.0, 10.0), Vec3(-350.5, 812.25, 42.0)}) {
    double lat = 0.0, lon = 0.0;
    GeographicLib::UTMUPS::Reverse(31, true, p.x() + offset.x(), p.y() + offset.y(), lat, lon);
    const io::Geodetic g = geo.toGeodetic(p);
    EXPECT_NEAR(g.lat_deg, lat, 1e-9);
    EXPECT_NEAR(g.lon_deg, lon, 1e-9);
    EXPECT_NEAR(g.h_ellipsoid_m, p.z() + offset.z() + egm96.undulation(lat, lon), 1e-9);
    EXPECT_NEAR(on_ellipsoid.toGeodetic(p).h_ellipsoid_m, p.z() + offset.z(), 1e-9);
    EXPECT_LT((geo.toLocal(g) - p).norm(), 1e-6);  // 1 µm: the inverse is exact
  }
}

}  // namespace
