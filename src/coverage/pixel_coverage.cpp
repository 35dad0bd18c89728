#include "uavip/coverage/pixel_coverage.h"

#include "uavip/core/error.h"
#include "uavip/core/parallel.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

namespace uavip::coverage {

namespace {

/// One worker's z-buffer: per pixel the nearest range and its point, reset after
/// each view through the list of touched pixels.
struct ZBuffer {
  std::vector<float> range;
  std::vector<std::uint32_t> point;
  std::vector<std::uint32_t> touched;
};

void projectView(const PointList& points, const ViewPose& view, const PinholeIntrinsics& k, double range_m,
                 ZBuffer& z, std::vector<char>& covered) {
  const ViewFrame f = makeViewFrame(view);
  const double r2_max = range_m * range_m;
  const int w = k.width_px, h = k.height_px;
  if (z.range.empty()) {
    z.range.assign(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), std::numeric_limits<float>::infinity());
    z.point.assign(z.range.size(), 0);
  }
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3 d = points[i] - view.position;
    const double r2 = d.squaredNorm();
    if (r2 > r2_max) continue;
    const double depth = f.forward.dot(d);
    if (!(depth > 0.0)) continue;
    const double u = k.cx_px + k.fx_px * f.right.dot(d) / depth;
    const double v = k.cy_px - k.fy_px * f.up.dot(d) / depth;
    if (!(u >= 0.0 && u < w && v >= 0.0 && v < h)) continue;
    const std::size_t pixel = static_cast<std::size_t>(v) * static_cast<std::size_t>(w) + static_cast<std::size_t>(u);
    const float r = static_cast<float>(r2);
    if (std::isinf(z.range[pixel])) z.touched.push_back(static_cast<std::uint32_t>(pixel));
    if (r < z.range[pixel]) {
      z.range[pixel] = r;
      z.point[pixel] = static_cast<std::uint32_t>(i);
    }
  }
  for (const auto pixel : z.touched) {
    covered[z.point[pixel]] = 1;
    z.range[pixel] = std::numeric_limits<float>::infinity();
  }
  z.touched.clear();
}

}  // namespace

PixelCoverageResult evaluatePixelCoverage(const PointList& points, const std::vector<ViewPose>& views,
                                          const PinholeIntrinsics& camera, double visible_range_m, int threads) {
  const std::string where = "pixel coverage";
  camera.validate(where + ".camera");
  requireThat(std::isfinite(visible_range_m) && visible_range_m > 0.0, where, "visible_range_m", "> 0 and finite",
              visible_range_m);
  require(points.size() < std::numeric_limits<std::uint32_t>::max(), where, "more than 2^32 - 1 points");
  for (std::size_t i = 0; i < points.size(); ++i)
    require(points[i].allFinite(), where, "point " + std::to_string(i) + " is not finite");
  for (std::size_t v = 0; v < views.size(); ++v)
    require(views[v].position.allFinite() && std::isfinite(views[v].yaw_deg) && std::isfinite(views[v].pitch_deg),
            where, "view " + std::to_string(v) + " is not finite");
  PixelCoverageResult result;
  result.points = points.size();
  const std::size_t workers = std::max<std::size_t>(1, std::min<std::size_t>(static_cast<std::size_t>(std::max(threads, 1)), views.size()));
  std::vector<ZBuffer> buffers(workers);
  std::vector<std::vector<char>> covered(workers, std::vector<char>(points.size(), 0));
  parallelFor(views.size(), static_cast<int>(workers), [&](std::size_t v, std::size_t worker) {
    projectView(points, views[v], camera, visible_range_m, buffers[worker], covered[worker]);
  });
  result.flags.assign(points.size(), 0);
  for (const auto& c : covered)
    for (std::size_t i = 0; i < c.size(); ++i) result.flags[i] |= c[i];
  for (const char c : result.flags) result.covered += c != 0;
  result.fraction = points.empty() ? 1.0 : static_cast<double>(result.covered) / static_cast<double>(points.size());
  return result;
}

}  // namespace uavip::coverage
