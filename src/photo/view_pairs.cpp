#include "uavip/photo/view_pairs.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "uavip/core/math.h"
#include "uavip/core/parallel.h"
#include "uavip/photo/renderer.h"

namespace uavip::photo {

double targetShare(const coverage::PinholeIntrinsics& k, const PlannedPhoto& a,
                   const PlannedPhoto& b) {
  const Vec3 to_a = a.pose.position - b.target;
  const Vec3 to_b = b.pose.position - b.target;
  const double na = to_a.norm();
  const double nb = to_b.norm();
  if (!(na > 0.0) || !(nb > 0.0)) return 0.0;
  if (to_a.dot(to_b) < std::cos(kPairMaxRayDeg * kDegToRad) * na * nb) return 0.0;
  const Eigen::Vector3d uvz = projectToImage(k, a.pose, b.target);
  if (!(uvz.z() > 1e-9)) return 0.0;
  const double w = k.width_px;
  const double h = k.height_px;
  const double du = std::abs(uvz.x() - 0.5 * w) / w;
  const double dv = std::abs(uvz.y() - 0.5 * h) / h;
  return std::max(0.0, 1.0 - du) * std::max(0.0, 1.0 - dv);
}

std::vector<std::pair<std::size_t, std::size_t>> viewPairs(const std::vector<PlannedPhoto>& photos,
                                                           const PhotoCamera& camera, int per_photo,
                                                           int threads) {
  const std::size_t n = photos.size();
  const auto keep = static_cast<std::size_t>(std::max(0, per_photo));
  std::vector<std::vector<std::size_t>> best(n);
  parallelFor(n, std::max(1, threads), [&](std::size_t i, std::size_t /*worker*/) {
    std::vector<std::pair<double, std::size_t>> scored;  // (−score, j): ascending is best first
    for (std::size_t j = 0; j < n; ++j) {
      if (j == i) continue;
      const double s = std::min(targetShare(camera.intrinsics, photos[i], photos[j]),
                                targetShare(camera.intrinsics, photos[j], photos[i]));
      if (s > 0.0) scored.emplace_back(-s, j);
    }
    const std::size_t m = std::min(keep, scored.size());
    std::partial_sort(scored.begin(), scored.begin() + static_cast<std::ptrdiff_t>(m),
                      scored.end());
    for (std::size_t t = 0; t < m; ++t) best[i].push_back(scored[t].second);
  });
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  for (std::size_t i = 0; i < n; ++i)
    for (const std::size_t j : best[i]) pairs.emplace_back(std::min(i, j), std::max(i, j));
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

std::string colmapPairs(const std::vector<PlannedPhoto>& photos,
                        const std::vector<std::pair<std::size_t, std::size_t>>& pairs) {
  std::string out;
  for (const auto& [i, j] : pairs)
    out += photos[i].stop_id + ".png " + photos[j].stop_id + ".png\n";
  return out;
}

}  // namespace uavip::photo
