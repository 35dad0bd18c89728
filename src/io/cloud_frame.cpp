// The frame of a cloud: every reader's recentring of a cloud far from the origin
// (io/cloud_io.h) and its check of the cloud's extent.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "cloud_formats.h"
#include "uavip/core/error.h"
#include "uavip/core/text.h"
#include "uavip/io/cloud_io.h"

namespace uavip::io {

Vec3 recentringOrigin(const Vec3& lo, const Vec3& hi) {
  const Vec3 centre = lo + 0.5 * (hi - lo);  // lo + hi could overflow
  const bool z_far = std::max(std::abs(lo.z()), std::abs(hi.z())) > kRecentreBeyondM;
  return Vec3(std::round(centre.x()), std::round(centre.y()), z_far ? std::round(centre.z()) : 0.0);
}

bool farFromOrigin(const Vec3& lo, const Vec3& hi) {
  return std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff()) > kRecentreBeyondM;
}

void requirePhysicalExtent(const std::string& path, const PointList& points, const Vec3& lo,
                           const Vec3& hi, const Vec3& origin) {
  const Vec3 extent = hi - lo;
  if (extent.allFinite() && extent.maxCoeff() <= kMaxCloudExtentM) {
    // Narrow, but maybe far: a lone point at 1e308, a georeferenced file in millimetres.
    if (std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff()) > kMaxCoordinateM) {
      std::size_t i = 0;
      while (i + 1 < points.size() && !(points[i].cwiseAbs().maxCoeff() > kMaxCoordinateM)) ++i;
      throw InputError(path + ": point " + std::to_string(i) + " " +
                       formatRawPoint(points[i] + origin) + " lies beyond " +
                       formatNumber(kMaxCoordinateM / 1e3) +
                       " km of the file's origin, on no map of "
                       "the earth: remove it, or set input.scale if the file is not in metres");
    }
    return;
  }
  Vec3 median;
  std::vector<double> axis(points.size());
  for (int a = 0; a < 3; ++a) {
    for (std::size_t i = 0; i < points.size(); ++i) axis[i] = points[i][a];
    std::nth_element(axis.begin(), axis.begin() + static_cast<std::ptrdiff_t>(axis.size() / 2),
                     axis.end());
    median[a] = axis[axis.size() / 2];
  }
  std::size_t worst = 0, strays = 0;
  double worst_d = -1.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double d = (points[i] - median).cwiseAbs().maxCoeff();
    if (!(d <= 0.5 * kMaxCloudExtentM)) ++strays;
    if (d > worst_d || std::isnan(d)) {
      worst_d = d;
      worst = i;
    }
  }
  const std::string span = path + ": the cloud spans " + formatNumber(extent.maxCoeff(), 3) +
                           " m (more than " + formatNumber(kMaxCloudExtentM / 1e3) +
                           " km, beyond any structure to inspect); ";
  // A few stray points (at most 1 %): named. Most of the cloud: a unit, not a point.
  if (strays <= std::max<std::size_t>(1, points.size() / 100))
    throw InputError(
        span +
        (strays > 1 ? std::to_string(strays) + " points lie far from the others, the farthest "
                    : "") +
        "point " + std::to_string(worst) + " " + formatRawPoint(points[worst] + origin) + " lies " +
        formatNumber(worst_d, 3) + " m from the cloud's median: remove it");
  throw InputError(span + std::to_string(strays) + " of " + std::to_string(points.size()) +
                   " points lie over " + formatNumber(0.5 * kMaxCloudExtentM / 1e3) +
                   " km from the median: the file is not in metres (set input.scale, e.g. 0.001 "
                   "for millimetres) "
                   "or holds more than one site");
}

}  // namespace uavip::io
