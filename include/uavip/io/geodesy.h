#pragma once
/// \file
/// Where the local frame lies on the Earth, with heights that are right
/// (docs/formats.md, "Headings and geodesy"). Three height references meet here:
///  - ellipsoidal height h above the WGS84 ellipsoid (GNSS, DJI WPML `WGS84` mode,
///    GeoJSON's third coordinate, RFC 7946 §4);
///  - orthometric height H above the geoid, "above sea level": EGM96 (EPSG:5773,
///    Google Earth's absolute altitudes, DJI's EGM96 template heights) or EGM2008
///    (EPSG:3855);
///  - height relative to home (the take-off point), which needs neither.
/// h = H + N(lat, lon), where N is the geoid undulation of the model (±100 m), read
/// from PROJ's grid (Debian's proj-data ships egm96_15.gtx; never a silent zero: a
/// missing grid is an InputError naming the package).
///
/// The local frame (ENU metres, z up) is placed one of two ways:
///  - `--origin LAT,LON,ALT`: ALT is above mean sea level (EGM96); the local
///    (0, 0, 0) is at ellipsoidal height ALT + N96(LAT, LON), and a local point
///    becomes WGS84 by GeographicLib's LocalCartesian about that point;
///  - the cloud's projected CRS: a local point + scene.json's source_offset_m is a
///    point (E, N, H) of the CRS; PROJ gives latitude and longitude, and H is a
///    height in the CRS's vertical datum (its compound part, e.g. EPSG:32650+5773,
///    else EGM96 unless told otherwise).
/// Both ways have an exact inverse (toLocal), so a file written in geographic
/// coordinates can be read back and checked in the local frame.
///
/// Thread safety: none of these classes may be used from two threads at once (one
/// PROJ context each).

#include <array>
#include <memory>
#include <optional>
#include <string>

#include "uavip/core/types.h"

namespace uavip::io {

/// WGS84 origin of the local ENU frame.
struct GeoOrigin {
  double lat_deg{0.0};  ///< latitude [deg], −90…90
  double lon_deg{0.0};  ///< longitude [deg], −180…180
  double alt_m{0.0};    ///< altitude of the origin (home) above mean sea level [m]
};

/// A geographic position.
struct GeoPoint {
  double lat_deg{0.0};
  double lon_deg{0.0};
  double alt_m{0.0};  ///< altitude in the origin's datum [m]
};

/// Parses "LAT,LON,ALT" (degrees, degrees, metres). Throws InputError
/// "<where>: … got '<text>'" if malformed, not finite or out of range.
GeoOrigin parseOrigin(const std::string& text, const std::string& where = "--origin");

/// Local ENU [m] relative to `origin` → WGS84 (GeographicLib LocalCartesian about
/// the origin at height origin.alt_m, taken as it is).
GeoPoint enuToGeodetic(const GeoOrigin& origin, const Vec3& enu);

/// The projected coordinate reference system (CRS) of a cloud's file coordinates,
/// transformed to and from WGS84 latitude and longitude by PROJ. A compound CRS
/// (e.g. EPSG:32650+5773) is split: its horizontal part transforms, its vertical part
/// is reported by verticalEpsg().
class CrsTransform {
 public:
  /// `crs`: what PROJ reads, e.g. "EPSG:32631" (WGS 84 / UTM zone 31N), a WKT or a
  /// PROJ string. Throws InputError "<where>: …" naming the text when PROJ does not
  /// know it, or when it is not a projected CRS (a geographic CRS is in degrees, a
  /// cloud in metres).
  explicit CrsTransform(const std::string& crs, const std::string& where = "--crs");
  ~CrsTransform();
  CrsTransform(const CrsTransform&) = delete;
  CrsTransform& operator=(const CrsTransform&) = delete;

  /// WGS84 latitude and longitude [deg] of the point (east, north) [m] of the CRS
  /// (divided by the CRS's own unit, e.g. a US survey foot, before PROJ). Throws
  /// InputError naming the point when PROJ cannot transform it.
  GeoPoint toWgs84(double east_m, double north_m) const;
  /// The inverse: (east, north) [m] of the CRS at a WGS84 latitude and longitude.
  Eigen::Vector2d fromWgs84(double lat_deg, double lon_deg) const;
  /// The CRS's name as PROJ gives it (e.g. "WGS 84 / UTM zone 31N").
  const std::string& name() const;
  /// The text it was made from.
  const std::string& text() const;
  /// Metres per unit of the CRS's first axis.
  double unitToMetres() const;
  /// EPSG code of the vertical part of a compound CRS (5773 EGM96 height, 3855
  /// EGM2008 height, …); 0 when the CRS is horizontal only or the code is not EPSG's.
  int verticalEpsg() const;
  /// Name of the vertical part ("EGM96 height"); empty when there is none.
  const std::string& verticalName() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// What a height of the cloud (its z + the offset's z) is measured from.
enum class VerticalDatum { Egm96, Egm2008, Ellipsoid };
/// Parses "egm96", "egm2008" or "ellipsoid"; throws InputError naming `where` and the value.
VerticalDatum parseVerticalDatum(const std::string& text, const std::string& where = "--vertical");
/// "egm96", "egm2008" or "ellipsoid".
const char* verticalDatumName(VerticalDatum datum);
/// The datum of a vertical CRS by its EPSG code: 5773 → EGM96, 3855 → EGM2008;
/// nullopt for any other.
std::optional<VerticalDatum> verticalDatumOfEpsg(int code);

/// A geoid model: N(lat, lon) [m], the height of the geoid above the WGS84 ellipsoid,
/// bilinear in PROJ's grid (EGM96: egm96_15.gtx, 15′; EGM2008: egm08_25.gtx or
/// us_nga_egm08_25.tif, 2.5′). The ellipsoid as a "model" has N = 0 and no grid.
class GeoidModel {
 public:
  /// Throws InputError naming the grid, where PROJ looked and the package to
  /// install when the grid is missing.
  explicit GeoidModel(VerticalDatum datum);
  ~GeoidModel();
  GeoidModel(const GeoidModel&) = delete;
  GeoidModel& operator=(const GeoidModel&) = delete;

  /// Geoid undulation N [m] at a WGS84 latitude and longitude [deg]: h = H + N.
  double undulation(double lat_deg, double lon_deg) const;
  VerticalDatum datum() const;
  /// The grid file PROJ read ("egm96_15.gtx"); empty for the ellipsoid.
  const std::string& gridName() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The datum of a cloud's heights when no --vertical overrides it: `recorded`
/// (scene.json's crs.vertical) if set, else the compound CRS's vertical part, else
/// EGM96. Throws InputError for a vertical CRS that is neither EGM96 nor EGM2008 height.
VerticalDatum defaultVerticalDatum(const CrsTransform& crs, const std::string& recorded,
                                   const std::string& where);

/// A WGS84 position with its ellipsoidal height.
struct Geodetic {
  double lat_deg{0.0};
  double lon_deg{0.0};
  double h_ellipsoid_m{0.0};  ///< above the WGS84 ellipsoid [m]
};

/// The local ENU frame placed on the Earth, both ways, with ellipsoidal heights.
/// Keeps an EGM96 model besides (EGM96 heights are what maps and DJI's templates show).
class Georeference {
 public:
  /// `--origin`: origin.alt_m above EGM96. Throws InputError if the EGM96 grid is missing.
  explicit Georeference(const GeoOrigin& origin);
  /// The cloud's CRS: a local point + source_offset_m is (E, N, H) of `crs`, H in `vertical`.
  Georeference(std::shared_ptr<const CrsTransform> crs, const Vec3& source_offset_m,
               VerticalDatum vertical);
  ~Georeference();
  Georeference(Georeference&&) noexcept;
  Georeference& operator=(Georeference&&) noexcept;

  /// WGS84 latitude, longitude and ellipsoidal height of a local point [m].
  Geodetic toGeodetic(const Vec3& enu) const;
  /// The local point [m] of a WGS84 position (the exact inverse of toGeodetic).
  Vec3 toLocal(const Geodetic& g) const;
  /// Height above EGM96 (mean sea level) [m] of a position.
  double egm96Height(const Geodetic& g) const;
  /// One line: how the frame is placed (origin or CRS, vertical datum, grid).
  std::string describe() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// A Georeference in closed form for a page that has no PROJ (the 3D mission page):
/// latitude, longitude [deg] and ellipsoidal height [m] each Σ c_k b_k(u, v, w), with
/// b = (1, u, v, w, u², v², w², uv, uw, vw) and (u, v, w) = (p − centre) / half the
/// box's extent, least squares over a 7 × 7 × 3 lattice of the box.
struct GeoFit {
  Vec3 centre{Vec3::Zero()};  ///< [m], local
  Vec3 half{Vec3::Ones()};    ///< half extents [m] (≥ 1 m)
  std::array<double, 10> lat{};
  std::array<double, 10> lon{};
  std::array<double, 10> h{};
  /// Largest distance [m] between the fit and the Georeference at the lattice's
  /// cell centres (points the fit did not see).
  double max_error_m{0.0};
  std::string crs;  ///< the CRS's name and vertical datum, one line
};
/// Fits `geo` over the local box [lo, hi].
GeoFit fitGeoreference(const Georeference& geo, const Vec3& lo, const Vec3& hi);

}  // namespace uavip::io
