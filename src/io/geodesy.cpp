#include "uavip/io/geodesy.h"

#include <proj.h>

#include <Eigen/Dense>
#include <GeographicLib/LocalCartesian.hpp>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <vector>

#include "uavip/core/error.h"
#include "uavip/core/math.h"
#include "uavip/core/text.h"

namespace uavip::io {
namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  const auto e = s.find_last_not_of(" \t");
  return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}

bool parseDouble(const std::string& text, double& out) {
  const std::string t = trim(text);
  if (t.empty()) return false;
  char* end = nullptr;
  errno = 0;
  out = std::strtod(t.c_str(), &end);
  return errno == 0 && end == t.c_str() + t.size() && std::isfinite(out);
}

}  // namespace

GeoOrigin parseOrigin(const std::string& text, const std::string& where) {
  const std::string shown = "got '" + text + "'";
  std::vector<std::string> parts;
  std::string cur;
  for (char c : text) {
    if (c == ',') {
      parts.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  parts.push_back(cur);
  GeoOrigin o;
  if (parts.size() != 3 || !parseDouble(parts[0], o.lat_deg) || !parseDouble(parts[1], o.lon_deg) ||
      !parseDouble(parts[2], o.alt_m))
    throw InputError(where +
                     ": expected LAT,LON,ALT (degrees, degrees, metres above sea level, e.g. "
                     "47.3977,8.5456,488), " +
                     shown);
  require(o.lat_deg >= -90.0 && o.lat_deg <= 90.0, where,
          "latitude must be in [-90, 90] degrees, " + shown);
  require(o.lon_deg >= -180.0 && o.lon_deg <= 180.0, where,
          "longitude must be in [-180, 180] degrees, " + shown);
  require(o.alt_m >= -500.0 && o.alt_m <= 9000.0, where,
          "altitude must be in [-500, 9000] m, " + shown);
  return o;
}

GeoPoint enuToGeodetic(const GeoOrigin& origin, const Vec3& enu) {
  const GeographicLib::LocalCartesian lc(origin.lat_deg, origin.lon_deg, origin.alt_m);
  GeoPoint g;
  lc.Reverse(enu.x(), enu.y(), enu.z(), g.lat_deg, g.lon_deg, g.alt_m);
  return g;
}

struct CrsTransform::Impl {
  PJ_CONTEXT* ctx{nullptr};
  PJ* to_wgs84{nullptr};
  double unit_to_m{1.0};
  std::string name;
  std::string text;
  int vertical_epsg{0};
  std::string vertical_name;
  ~Impl() {
    if (to_wgs84 != nullptr) proj_destroy(to_wgs84);
    if (ctx != nullptr) proj_context_destroy(ctx);
  }
};

CrsTransform::CrsTransform(const std::string& crs, const std::string& where)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.text = crs;
  m.ctx = proj_context_create();
  if (m.ctx == nullptr) throw InputError(where + ": PROJ could not start (no memory?)");
  proj_log_level(m.ctx, PJ_LOG_NONE);  // errors are ours, on one line
  const std::string shown = "'" + crs.substr(0, 80) + (crs.size() > 80 ? "…" : "") + "'";
  const auto why = [&] {
    return std::string(proj_context_errno_string(m.ctx, proj_context_errno(m.ctx)));
  };
  // The PJ objects are destroyed on every path: a small owner.
  struct Owned {
    PJ* p;
    ~Owned() {
      if (p != nullptr) proj_destroy(p);
    }
  };
  Owned source{proj_create(m.ctx, crs.c_str())};
  if (source.p == nullptr || !proj_is_crs(source.p))
    throw InputError(where + ": PROJ does not know the CRS " + shown +
                     (source.p == nullptr ? " (" + why() + ")" : "") +
                     "; give the cloud's projected CRS, e.g. EPSG:32631 (WGS 84 / UTM zone 31N)");
  Owned horizontal{proj_get_type(source.p) == PJ_TYPE_COMPOUND_CRS
                       ? proj_crs_get_sub_crs(m.ctx, source.p, 0)
                       : nullptr};
  PJ* h = horizontal.p != nullptr ? horizontal.p : source.p;
  if (horizontal.p != nullptr) {
    Owned vertical{proj_crs_get_sub_crs(m.ctx, source.p, 1)};
    if (vertical.p != nullptr) {
      const char* vname = proj_get_name(vertical.p);
      m.vertical_name = vname != nullptr ? vname : "";
      const char* auth = proj_get_id_auth_name(vertical.p, 0);
      const char* code = proj_get_id_code(vertical.p, 0);
      if (auth != nullptr && code != nullptr && std::string(auth) == "EPSG")
        m.vertical_epsg = std::atoi(code);
    }
  }
  if (proj_get_type(h) != PJ_TYPE_PROJECTED_CRS)
    throw InputError(
        where + ": " + shown +
        " is not a projected CRS (a geographic CRS gives degrees, the cloud is in "
        "metres); give its projected CRS, e.g. the UTM zone (EPSG:326NN north, 327NN south)");
  const char* name = proj_get_name(h);
  m.name = name != nullptr ? name : crs;
  Owned cs{proj_crs_get_coordinate_system(m.ctx, h)};
  double factor = 1.0;
  if (cs.p == nullptr ||
      !proj_cs_get_axis_info(m.ctx, cs.p, 0, nullptr, nullptr, nullptr, &factor, nullptr, nullptr,
                             nullptr) ||
      !(factor > 0.0 && std::isfinite(factor)))
    throw InputError(where + ": " + shown + " has no linear unit PROJ can read");
  m.unit_to_m = factor;
  Owned op{proj_create_crs_to_crs(m.ctx, crs.c_str(), "EPSG:4326", nullptr)};
  if (op.p == nullptr)
    throw InputError(where + ": PROJ finds no transformation from " + shown + " to WGS84 (" +
                     why() + ")");
  m.to_wgs84 =
      proj_normalize_for_visualization(m.ctx, op.p);  // east, north in; longitude, latitude out
  if (m.to_wgs84 == nullptr)
    throw InputError(where + ": PROJ cannot order the axes of " + shown + " (" + why() + ")");
}

CrsTransform::~CrsTransform() = default;

GeoPoint CrsTransform::toWgs84(double east_m, double north_m) const {
  const Impl& m = *impl_;
  PJ_COORD c = proj_coord(east_m / m.unit_to_m, north_m / m.unit_to_m, 0.0, 0.0);
  proj_errno_reset(m.to_wgs84);
  const PJ_COORD g = proj_trans(m.to_wgs84, PJ_FWD, c);
  GeoPoint out;
  out.lon_deg = g.lp.lam;
  out.lat_deg = g.lp.phi;
  if (!(std::isfinite(out.lat_deg) && std::isfinite(out.lon_deg) && std::abs(out.lat_deg) <= 90.0 &&
        std::abs(out.lon_deg) <= 180.0 && out.lat_deg != HUGE_VAL))
    throw InputError("--crs: the point (" + formatFixed(east_m, 3) + ", " +
                     formatFixed(north_m, 3) + ") m of " + m.name +
                     " has no WGS84 position (PROJ: " +
                     proj_context_errno_string(m.ctx, proj_errno(m.to_wgs84)) + "); is " + m.text +
                     " the cloud's CRS?");
  return out;
}

const std::string& CrsTransform::name() const { return impl_->name; }

double CrsTransform::unitToMetres() const { return impl_->unit_to_m; }

Eigen::Vector2d CrsTransform::fromWgs84(double lat_deg, double lon_deg) const {
  const Impl& m = *impl_;
  proj_errno_reset(m.to_wgs84);
  const PJ_COORD c = proj_trans(m.to_wgs84, PJ_INV, proj_coord(lon_deg, lat_deg, 0.0, 0.0));
  Eigen::Vector2d out(c.xy.x * m.unit_to_m, c.xy.y * m.unit_to_m);
  if (!(std::isfinite(out.x()) && std::isfinite(out.y()) && c.xy.x != HUGE_VAL))
    throw InputError("the WGS84 position " + formatFixed(lat_deg, 9) + ", " +
                     formatFixed(lon_deg, 9) + " has no point in " + m.name +
                     " (PROJ: " + proj_context_errno_string(m.ctx, proj_errno(m.to_wgs84)) + ")");
  return out;
}

const std::string& CrsTransform::text() const { return impl_->text; }

int CrsTransform::verticalEpsg() const { return impl_->vertical_epsg; }

const std::string& CrsTransform::verticalName() const { return impl_->vertical_name; }

VerticalDatum parseVerticalDatum(const std::string& text, const std::string& where) {
  if (text == "egm96") return VerticalDatum::Egm96;
  if (text == "egm2008") return VerticalDatum::Egm2008;
  if (text == "ellipsoid") return VerticalDatum::Ellipsoid;
  throw InputError(where +
                   ": must be egm96, egm2008 or ellipsoid (what the cloud's z is measured "
                   "from), got '" +
                   text + "'");
}

const char* verticalDatumName(VerticalDatum datum) {
  switch (datum) {
    case VerticalDatum::Egm96:
      return "egm96";
    case VerticalDatum::Egm2008:
      return "egm2008";
    case VerticalDatum::Ellipsoid:
      return "ellipsoid";
  }
  return "?";
}

std::optional<VerticalDatum> verticalDatumOfEpsg(int code) {
  if (code == 5773) return VerticalDatum::Egm96;
  if (code == 3855) return VerticalDatum::Egm2008;
  return std::nullopt;
}

VerticalDatum defaultVerticalDatum(const CrsTransform& crs, const std::string& recorded,
                                   const std::string& where) {
  if (!recorded.empty()) return parseVerticalDatum(recorded, where + ": crs.vertical");
  if (!crs.verticalName().empty()) {
    const std::optional<VerticalDatum> d = verticalDatumOfEpsg(crs.verticalEpsg());
    if (!d)
      throw InputError(where + ": the CRS's vertical part " + crs.verticalName() +
                       " (EPSG:" + std::to_string(crs.verticalEpsg()) +
                       ") is not EGM96 height (5773) or EGM2008 height (3855); pass --vertical "
                       "egm96|egm2008|ellipsoid for what the cloud's z is measured from");
    return *d;
  }
  return VerticalDatum::Egm96;
}

struct GeoidModel::Impl {
  VerticalDatum datum{VerticalDatum::Ellipsoid};
  PJ_CONTEXT* ctx{nullptr};
  PJ* shift{nullptr};  ///< +proj=vgridshift: z_out = z_in + N
  std::string grid;
  ~Impl() {
    if (shift != nullptr) proj_destroy(shift);
    if (ctx != nullptr) proj_context_destroy(ctx);
  }
};

GeoidModel::GeoidModel(VerticalDatum datum) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.datum = datum;
  if (datum == VerticalDatum::Ellipsoid) return;
  m.ctx = proj_context_create();
  if (m.ctx == nullptr) throw InputError("geoid: PROJ could not start (no memory?)");
  proj_log_level(m.ctx, PJ_LOG_NONE);
  // The grids PROJ may know each model by (PROJ-data's name first for EGM2008;
  // Debian 12's proj-data ships only egm96_15.gtx). No '@' prefix: a missing grid
  // must fail, not shift by zero.
  const std::vector<std::string> names =
      datum == VerticalDatum::Egm96
          ? std::vector<std::string>{"egm96_15.gtx", "us_nga_egm96_15.tif"}
          : std::vector<std::string>{"us_nga_egm08_25.tif", "egm08_25.gtx"};
  for (const std::string& name : names) {
    const std::string def = "+proj=vgridshift +grids=" + name + " +multiplier=1";
    PJ* p = proj_create(m.ctx, def.c_str());
    if (p == nullptr) continue;
    // A grid that exists gives a finite value at (0, 0); proj_create alone may defer the check.
    const PJ_COORD c = proj_trans(p, PJ_FWD, proj_coord(0.0, 0.0, 0.0, 0.0));
    if (std::isfinite(c.xyz.z) && c.xyz.z != HUGE_VAL) {
      m.shift = p;
      m.grid = name;
      return;
    }
    proj_destroy(p);
  }
  std::string where = "PROJ's data folder";
  const PJ_INFO info = proj_info();
  if (info.searchpath != nullptr && *info.searchpath != '\0') where = info.searchpath;
  throw InputError(datum == VerticalDatum::Egm96
                       ? "geoid: the EGM96 grid egm96_15.gtx is not installed (searched " + where +
                             "); install Debian's proj-data (apt-get install proj-data)"
                       : "geoid: the EGM2008 grid (us_nga_egm08_25.tif or egm08_25.gtx) is not "
                         "installed (searched " +
                             where +
                             "; Debian 12's proj-data does not ship it): copy it from "
                             "https://cdn.proj.org/us_nga_egm08_25.tif into that folder or "
                             "PROJ_DATA, or give --vertical egm96|ellipsoid if that is what the "
                             "cloud's heights are");
}

GeoidModel::~GeoidModel() = default;

double GeoidModel::undulation(double lat_deg, double lon_deg) const {
  const Impl& m = *impl_;
  if (m.shift == nullptr) return 0.0;
  const PJ_COORD c =
      proj_trans(m.shift, PJ_FWD, proj_coord(lon_deg * kDegToRad, lat_deg * kDegToRad, 0.0, 0.0));
  if (!std::isfinite(c.xyz.z) || c.xyz.z == HUGE_VAL)
    throw InputError("geoid: " + m.grid + " has no value at " + formatFixed(lat_deg, 6) + ", " +
                     formatFixed(lon_deg, 6));
  return c.xyz.z;
}

VerticalDatum GeoidModel::datum() const { return impl_->datum; }

const std::string& GeoidModel::gridName() const { return impl_->grid; }

struct Georeference::Impl {
  std::unique_ptr<GeoidModel> egm96;
  // --origin
  std::optional<GeographicLib::LocalCartesian> local;
  GeoOrigin origin;
  // CRS
  std::shared_ptr<const CrsTransform> crs;
  Vec3 offset{Vec3::Zero()};
  std::unique_ptr<GeoidModel> vertical;  ///< the datum of H (may be egm96's twin)
};

Georeference::Georeference(const GeoOrigin& origin) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.egm96 = std::make_unique<GeoidModel>(VerticalDatum::Egm96);
  m.origin = origin;
  const double h0 = origin.alt_m + m.egm96->undulation(origin.lat_deg, origin.lon_deg);
  m.local.emplace(origin.lat_deg, origin.lon_deg, h0);
}

Georeference::Georeference(std::shared_ptr<const CrsTransform> crs, const Vec3& source_offset_m,
                           VerticalDatum vertical)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.egm96 = std::make_unique<GeoidModel>(VerticalDatum::Egm96);
  m.crs = std::move(crs);
  m.offset = source_offset_m;
  m.vertical = std::make_unique<GeoidModel>(vertical);
}

Georeference::~Georeference() = default;
Georeference::Georeference(Georeference&&) noexcept = default;
Georeference& Georeference::operator=(Georeference&&) noexcept = default;

Geodetic Georeference::toGeodetic(const Vec3& enu) const {
  const Impl& m = *impl_;
  Geodetic g;
  if (m.local) {
    m.local->Reverse(enu.x(), enu.y(), enu.z(), g.lat_deg, g.lon_deg, g.h_ellipsoid_m);
    return g;
  }
  const Vec3 p = enu + m.offset;
  const GeoPoint ll = m.crs->toWgs84(p.x(), p.y());
  g.lat_deg = ll.lat_deg;
  g.lon_deg = ll.lon_deg;
  g.h_ellipsoid_m = p.z() + m.vertical->undulation(g.lat_deg, g.lon_deg);
  return g;
}

Vec3 Georeference::toLocal(const Geodetic& g) const {
  const Impl& m = *impl_;
  Vec3 out;
  if (m.local) {
    m.local->Forward(g.lat_deg, g.lon_deg, g.h_ellipsoid_m, out.x(), out.y(), out.z());
    return out;
  }
  const Eigen::Vector2d en = m.crs->fromWgs84(g.lat_deg, g.lon_deg);
  const double h = g.h_ellipsoid_m - m.vertical->undulation(g.lat_deg, g.lon_deg);
  return Vec3(en.x(), en.y(), h) - m.offset;
}

double Georeference::egm96Height(const Geodetic& g) const {
  return g.h_ellipsoid_m - impl_->egm96->undulation(g.lat_deg, g.lon_deg);
}

std::string Georeference::describe() const {
  const Impl& m = *impl_;
  if (m.local)
    return "--origin " + formatFixed(m.origin.lat_deg, 8) + ", " +
           formatFixed(m.origin.lon_deg, 8) + ", " + formatFixed(m.origin.alt_m, 2) +
           " m above EGM96 (N = " +
           formatFixed(m.egm96->undulation(m.origin.lat_deg, m.origin.lon_deg), 2) + " m from " +
           m.egm96->gridName() + ")";
  return m.crs->name() + " (" + m.crs->text().substr(0, 60) +
         (m.crs->text().size() > 60 ? "…" : "") + "), heights above " +
         verticalDatumName(m.vertical->datum()) +
         (m.vertical->gridName().empty() ? "" : " (" + m.vertical->gridName() + ")") +
         ", source_offset_m (" + formatFixed(m.offset.x(), 3) + ", " +
         formatFixed(m.offset.y(), 3) + ", " + formatFixed(m.offset.z(), 3) + ")";
}

namespace {

/// The basis of GeoFit at normalised (u, v, w).
Eigen::Matrix<double, 10, 1> geoBasis(const Vec3& q) {
  Eigen::Matrix<double, 10, 1> b;
  b << 1.0, q.x(), q.y(), q.z(), q.x() * q.x(), q.y() * q.y(), q.z() * q.z(), q.x() * q.y(),
      q.x() * q.z(), q.y() * q.z();
  return b;
}

}  // namespace

GeoFit fitGeoreference(const Georeference& geo, const Vec3& lo, const Vec3& hi) {
  GeoFit fit;
  fit.centre = 0.5 * (lo + hi);
  fit.half = (0.5 * (hi - lo)).cwiseMax(Vec3::Ones());
  const auto lattice = [&](int n_xy, int n_z, double shift) {
    std::vector<Vec3> q;
    for (int i = 0; i < n_xy; ++i)
      for (int j = 0; j < n_xy; ++j)
        for (int k = 0; k < n_z; ++k)
          q.emplace_back(-1.0 + 2.0 * (i + shift) / (n_xy - 1),
                         -1.0 + 2.0 * (j + shift) / (n_xy - 1),
                         n_z == 1 ? 0.0 : -1.0 + 2.0 * (k + shift) / (n_z - 1));
    return q;
  };
  const std::vector<Vec3> samples = lattice(7, 3, 0.0);
  Eigen::MatrixXd a(static_cast<Eigen::Index>(samples.size()), 10);
  Eigen::MatrixXd b(static_cast<Eigen::Index>(samples.size()), 3);
  for (std::size_t s = 0; s < samples.size(); ++s) {
    const Geodetic g = geo.toGeodetic(fit.centre + samples[s].cwiseProduct(fit.half));
    a.row(static_cast<Eigen::Index>(s)) = geoBasis(samples[s]).transpose();
    b.row(static_cast<Eigen::Index>(s)) << g.lat_deg, g.lon_deg, g.h_ellipsoid_m;
  }
  const Eigen::MatrixXd c = a.colPivHouseholderQr().solve(b);
  for (int k = 0; k < 10; ++k) {
    fit.lat[static_cast<std::size_t>(k)] = c(k, 0);
    fit.lon[static_cast<std::size_t>(k)] = c(k, 1);
    fit.h[static_cast<std::size_t>(k)] = c(k, 2);
  }
  // Checked where it was not fitted: the centres of the lattice's cells.
  constexpr double kMetresPerDegree = 111320.0;
  for (const Vec3& q : lattice(6, 2, 0.5)) {
    if (q.cwiseAbs().maxCoeff() > 1.0) continue;
    const Geodetic g = geo.toGeodetic(fit.centre + q.cwiseProduct(fit.half));
    const Eigen::Matrix<double, 10, 1> basis = geoBasis(q);
    double lat = 0.0, lon = 0.0, h = 0.0;
    for (int k = 0; k < 10; ++k) {
      lat += fit.lat[static_cast<std::size_t>(k)] * basis(k);
      lon += fit.lon[static_cast<std::size_t>(k)] * basis(k);
      h += fit.h[static_cast<std::size_t>(k)] * basis(k);
    }
    const Vec3 error((lon - g.lon_deg) * kMetresPerDegree * std::cos(g.lat_deg * kDegToRad),
                     (lat - g.lat_deg) * kMetresPerDegree, h - g.h_ellipsoid_m);
    fit.max_error_m = std::max(fit.max_error_m, error.norm());
  }
  fit.crs = geo.describe();
  return fit;
}

}  // namespace uavip::io
