#include "uavip/photo/point_preview.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "uavip/core/neighbour_index.h"

namespace uavip::photo {

std::array<std::uint8_t, 3> heightColour(double z, double z_min, double z_max) {
  const double t = z_max > z_min ? std::clamp((z - z_min) / (z_max - z_min), 0.0, 1.0) : 0.5;
  // Dark blue → teal → yellow (a viridis-like ramp in three linear pieces).
  const double stops[3][3] = {{40, 60, 140}, {40, 160, 140}, {250, 220, 40}};
  const int seg = t < 0.5 ? 0 : 1;
  const double u = t < 0.5 ? 2.0 * t : 2.0 * t - 1.0;
  std::array<std::uint8_t, 3> out{};
  for (int c = 0; c < 3; ++c)
    out[c] =
        static_cast<std::uint8_t>(std::lround((1.0 - u) * stops[seg][c] + u * stops[seg + 1][c]));
  return out;
}

Image renderPointPreview(const PreviewCloud& cloud, const coverage::PinholeIntrinsics& k,
                         const PhotoPose& pose) {
  Image img;
  img.width = k.width_px;
  img.height = k.height_px;
  const std::size_t n_px = static_cast<std::size_t>(img.width) * img.height;
  img.rgb.resize(3 * n_px);
  for (std::size_t i = 0; i < n_px; ++i)
    for (int c = 0; c < 3; ++c) img.rgb[3 * i + static_cast<std::size_t>(c)] = kSkyRgb[c];
  if (cloud.points.empty()) return img;
  double z_min = std::numeric_limits<double>::infinity(), z_max = -z_min;
  if (cloud.rgb.empty()) {
    for (const Vec3& p : cloud.points) {
      z_min = std::min(z_min, p.z());
      z_max = std::max(z_max, p.z());
    }
  }
  std::vector<float> depth(n_px, std::numeric_limits<float>::infinity());
  const Eigen::Matrix3d r_wc = pose.camera_to_world.transpose();
  const double f = std::min(k.fx_px, k.fy_px);
  for (std::size_t i = 0; i < cloud.points.size(); ++i) {
    const Vec3 c = r_wc * (cloud.points[i] - pose.position);
    if (c.z() <= 1e-6 || c.z() > cloud.max_depth_m) continue;
    const double u = k.fx_px * c.x() / c.z() + k.cx_px, v = k.fy_px * c.y() / c.z() + k.cy_px;
    const double half = std::max(0.5, 0.5 * cloud.splat_m * f / c.z());
    const int u0 = std::max(0, static_cast<int>(std::floor(u - half)));
    const int u1 = std::min(img.width - 1, static_cast<int>(std::floor(u + half)));
    const int v0 = std::max(0, static_cast<int>(std::floor(v - half)));
    const int v1 = std::min(img.height - 1, static_cast<int>(std::floor(v + half)));
    if (u0 > u1 || v0 > v1) continue;
    const std::array<std::uint8_t, 3> base =
        cloud.rgb.empty() ? heightColour(cloud.points[i].z(), z_min, z_max) : cloud.rgb[i];
    const double shade = 1.0 - 0.4 * std::min(1.0, c.z() / cloud.max_depth_m);
    const auto d = static_cast<float>(c.z());
    for (int y = v0; y <= v1; ++y) {
      for (int x = u0; x <= u1; ++x) {
        const std::size_t px = static_cast<std::size_t>(y) * img.width + x;
        if (!(d < depth[px])) continue;  // nearest first; ties keep the lower index
        depth[px] = d;
        for (int ch = 0; ch < 3; ++ch)
          img.rgb[3 * px + static_cast<std::size_t>(ch)] =
              static_cast<std::uint8_t>(std::lround(shade * base[ch]));
      }
    }
  }
  return img;
}

double medianSpacing(const PointList& points, std::size_t sample) {
  if (points.size() < 2) return 0.0;
  const NeighbourIndex index(points);
  const std::size_t step =
      std::max<std::size_t>(1, points.size() / std::max<std::size_t>(1, sample));
  std::vector<double> d;
  std::vector<int> idx;
  std::vector<float> sq;
  for (std::size_t i = 0; i < points.size(); i += step) {
    index.nearest(i, 2, idx, sq);
    if (sq.size() == 2) d.push_back(std::sqrt(static_cast<double>(sq[1])));
  }
  if (d.empty()) return 0.0;
  std::nth_element(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2), d.end());
  return d[d.size() / 2];
}

}  // namespace uavip::photo
