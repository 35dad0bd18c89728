#include "uavip/photo/view_pairs.h"

#include <algorithm>
#include <cmath>

#include "uavip/core/geometry.h"
#include "uavip/core/math.h"
#include "uavip/core/parallel.h"
#include "uavip/photo/renderer.h"

namespace uavip::photo {

namespace {

/// A sample counts as the surface point itself within this distance along the ray [m].
constexpr double kHitTolM = 1e-3;

}  // namespace

PhotoSamples photoSamples(const RayCaster& surface, const coverage::PinholeIntrinsics& k,
                          const PhotoPose& pose) {
  PhotoSamples s;
  for (int iv = 0; iv < kPairSamplesH; ++iv) {
    for (int iu = 0; iu < kPairSamplesW; ++iu) {
      const double x = (iu + 0.5) * k.width_px / kPairSamplesW;
      const double y = (iv + 0.5) * k.height_px / kPairSamplesH;
      const RayHit hit = surface.cast(pose.position, pixelRay(k, pose, x, y));
      if (!hit.hit) continue;
      s.points.push_back(hit.point);
      s.normals.push_back(hit.normal);
    }
  }
  return s;
}

double seenShare(const RayCaster& surface, const coverage::PinholeIntrinsics& k,
                 const PhotoSamples& a, const PhotoPose& a_pose, const PhotoPose& b_pose) {
  if (a.points.empty()) return 0.0;
  const double cos_max = std::cos(kPairMaxRayDeg * kDegToRad);
  std::size_t seen = 0;
  for (std::size_t i = 0; i < a.points.size(); ++i) {
    const Vec3& p = a.points[i];
    const Vec3 to_b = b_pose.position - p;
    const Vec3 to_a = a_pose.position - p;
    const double db = to_b.norm();
    const double da = to_a.norm();
    if (!(db > 0.0) || !(da > 0.0)) continue;
    const Vec3& n = a.normals[i];
    // on the side of the face b stands on as a does (a two-sided plane: either side)
    if (n.dot(to_b) * n.dot(to_a) <= 0.0) continue;
    if (to_a.dot(to_b) < cos_max * da * db) continue;
    const Eigen::Vector3d uvz = projectToImage(k, b_pose, p);
    if (!(uvz.z() > 0.0) || uvz.x() < 0.0 || uvz.x() >= k.width_px || uvz.y() < 0.0 ||
        uvz.y() >= k.height_px)
      continue;
    const RayHit hit = surface.cast(b_pose.position, -to_b / db, db + kHitTolM);
    if (hit.hit && hit.t < db - kHitTolM - 1e-6 * db) continue;  // something nearer
    ++seen;
  }
  return static_cast<double>(seen) / static_cast<double>(a.points.size());
}

std::vector<std::pair<std::size_t, std::size_t>> viewPairs(const std::vector<PlannedPhoto>& photos,
                                                           const PhotoCamera& camera,
                                                           const RayCaster& surface, int per_photo,
                                                           int threads) {
  const std::size_t n = photos.size();
  const int workers = std::max(1, threads);
  std::vector<PhotoSamples> samples(n);
  std::vector<Aabb> box(n);  // each photo's samples, grown by its footprint's larger side
  parallelFor(n, workers, [&](std::size_t i, std::size_t /*worker*/) {
    samples[i] = photoSamples(surface, camera.intrinsics, photos[i].pose);
    const double grow = std::max(photos[i].footprint_w_m, photos[i].footprint_h_m);
    for (const Vec3& p : samples[i].points) box[i].extend(p);
    box[i].min.array() -= grow;
    box[i].max.array() += grow;
  });
  // Photo j can see a sample of i only where what they see is near: the shares of
  // the pairs whose boxes meet, kept sparse (j ascending).
  std::vector<std::vector<std::pair<std::size_t, double>>> share(n);
  parallelFor(n, workers, [&](std::size_t i, std::size_t /*worker*/) {
    if (samples[i].points.empty()) return;
    for (std::size_t j = 0; j < n; ++j) {
      if (j == i || samples[j].points.empty() || (box[i].max.array() < box[j].min.array()).any() ||
          (box[j].max.array() < box[i].min.array()).any())
        continue;
      const double s =
          seenShare(surface, camera.intrinsics, samples[i], photos[i].pose, photos[j].pose);
      if (s > 0.0) share[i].emplace_back(j, s);
    }
  });
  const auto shareOf = [&](std::size_t i, std::size_t j) {
    const auto& row = share[i];
    const auto it = std::lower_bound(row.begin(), row.end(), std::make_pair(j, 0.0));
    return it != row.end() && it->first == j ? it->second : 0.0;
  };
  const auto keep = static_cast<std::size_t>(std::max(0, per_photo));
  std::vector<std::vector<std::size_t>> best(n);
  parallelFor(n, workers, [&](std::size_t i, std::size_t /*worker*/) {
    std::vector<std::pair<double, std::size_t>> scored;  // (−score, j): ascending is best first
    for (const auto& [j, s] : share[i]) {
      const double both = std::min(s, shareOf(j, i));
      if (both > 0.0) scored.emplace_back(-both, j);
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
