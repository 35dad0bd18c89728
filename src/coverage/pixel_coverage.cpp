#include "uavip/coverage/pixel_coverage.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "uavip/core/error.h"
#include "uavip/core/parallel.h"

namespace uavip::coverage {

namespace {

/// One view's hits (pixel, squared range, point), kept by a worker between views.
struct Hit {
  std::uint64_t pixel;
  double range2;
  std::uint32_t point;
  bool operator<(const Hit& o) const {
    return pixel != o.pixel     ? pixel < o.pixel
           : range2 != o.range2 ? range2 < o.range2
                                : point < o.point;
  }
};

/// Marks the nearest point of every pixel of one view: the view's hits sorted by
/// pixel then range (no image-sized buffer: a 20 MP camera costs what it sees).
void projectView(const PointList& points, const ViewPose& view, const PinholeIntrinsics& k,
                 double range_m, std::vector<Hit>& hits, std::vector<char>& covered) {
  const ViewFrame f = makeViewFrame(view);
  const double r2_max = range_m * range_m;
  const double w = k.width_px, h = k.height_px;
  hits.clear();
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3 d = points[i] - view.position;
    const double r2 = d.squaredNorm();
    if (r2 > r2_max) continue;
    const double depth = f.forward.dot(d);
    if (!(depth > 0.0)) continue;
    const double u = k.cx_px + k.fx_px * f.right.dot(d) / depth;
    const double v = k.cy_px - k.fy_px * f.up.dot(d) / depth;
    if (!(u >= 0.0 && u < w && v >= 0.0 && v < h)) continue;
    const auto pixel = static_cast<std::uint64_t>(v) * static_cast<std::uint64_t>(k.width_px) +
                       static_cast<std::uint64_t>(u);
    hits.push_back({pixel, r2, static_cast<std::uint32_t>(i)});
  }
  std::sort(hits.begin(), hits.end());
  for (std::size_t j = 0; j < hits.size(); ++j) {
    if (j == 0 || hits[j].pixel != hits[j - 1].pixel) covered[hits[j].point] = 1;
  }
}

}  // namespace

PixelCoverageResult evaluatePixelCoverage(const PointList& points,
                                          const std::vector<ViewPose>& views,
                                          const PinholeIntrinsics& camera, double visible_range_m,
                                          int threads) {
  const std::string where = "pixel coverage";
  camera.validate(where + ".camera");
  requireThat(std::isfinite(visible_range_m) && visible_range_m > 0.0, where, "visible_range_m",
              "> 0 and finite", visible_range_m);
  require(points.size() < std::numeric_limits<std::uint32_t>::max(), where,
          "more than 2^32 - 1 points");
  for (std::size_t i = 0; i < points.size(); ++i)
    require(points[i].allFinite(), where, "point " + std::to_string(i) + " is not finite");
  for (std::size_t v = 0; v < views.size(); ++v)
    require(views[v].position.allFinite() && std::isfinite(views[v].yaw_deg) &&
                std::isfinite(views[v].pitch_deg),
            where, "view " + std::to_string(v) + " is not finite");
  PixelCoverageResult result;
  result.points = points.size();
  const std::size_t workers = std::max<std::size_t>(
      1, std::min<std::size_t>(static_cast<std::size_t>(std::max(threads, 1)), views.size()));
  std::vector<std::vector<Hit>> buffers(workers);
  std::vector<std::vector<char>> covered(workers, std::vector<char>(points.size(), 0));
  parallelFor(views.size(), static_cast<int>(workers), [&](std::size_t v, std::size_t worker) {
    projectView(points, views[v], camera, visible_range_m, buffers[worker], covered[worker]);
  });
  result.flags.assign(points.size(), 0);
  for (const auto& c : covered)
    for (std::size_t i = 0; i < c.size(); ++i)
      if (c[i] != 0) result.flags[i] = 1;
  for (const char c : result.flags) result.covered += c != 0;
  result.fraction = points.empty()
                        ? 1.0
                        : static_cast<double>(result.covered) / static_cast<double>(points.size());
  return result;
}

}  // namespace uavip::coverage
