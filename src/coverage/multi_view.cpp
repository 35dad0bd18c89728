#include "uavip/coverage/multi_view.h"

#include <algorithm>
#include <cmath>

#include "uavip/core/math.h"
#include "uavip/core/parallel.h"

namespace uavip::coverage {
namespace {

/// The lower median of `values` (0 for none).
template <typename T>
T lowerMedian(std::vector<T> values) {
  if (values.empty()) return T{};
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>((values.size() - 1) / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

}  // namespace

MultiViewStats multiViewStats(const PointList& points, const std::vector<Vec3>& normals,
                              const std::vector<ViewPose>& views, const CameraModel& camera,
                              const CoverageCriteria& criteria, const LineOfSight* los, int threads,
                              const std::vector<char>* two_sided) {
  const auto imaged =
      imagedByView(points, normals, views, camera, criteria, los, threads, two_sided);
  MultiViewStats st;
  st.points = points.size();
  std::vector<std::vector<std::uint32_t>> seen_by(points.size());
  for (std::size_t v = 0; v < imaged.size(); ++v) {
    for (const auto i : imaged[v]) seen_by[i].push_back(static_cast<std::uint32_t>(v));
  }
  st.views.assign(points.size(), 0);
  st.angle_deg.assign(points.size(), 0.0);
  parallelFor(points.size(), threads, [&](std::size_t i, std::size_t) {
    const auto& by = seen_by[i];
    st.views[i] = static_cast<int>(by.size());
    std::vector<Vec3> rays;
    rays.reserve(by.size());
    for (const auto v : by) rays.push_back((views[v].position - points[i]).normalized());
    double min_cos = 1.0;
    for (std::size_t a = 0; a < rays.size(); ++a) {
      for (std::size_t b = a + 1; b < rays.size(); ++b)
        min_cos = std::min(min_cos, rays[a].dot(rays[b]));
    }
    st.angle_deg[i] = std::acos(std::clamp(min_cos, -1.0, 1.0)) * kRadToDeg;
  });
  if (!points.empty()) {
    st.views_min = *std::min_element(st.views.begin(), st.views.end());
    st.angle_min_deg = *std::min_element(st.angle_deg.begin(), st.angle_deg.end());
  }
  st.views_median = lowerMedian(st.views);
  st.angle_median_deg = lowerMedian(st.angle_deg);
  return st;
}

}  // namespace uavip::coverage
