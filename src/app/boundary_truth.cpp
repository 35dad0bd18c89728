#include "uavip/app/boundary_truth.h"

#include <algorithm>
#include <cmath>

#include "uavip/core/error.h"

namespace uavip::app {
namespace {

/// True when the ray from `from` through `to` (beyond `to` too) meets the rectangle.
bool rayHits(const sim::Rect& r, const Vec3& from, const Vec3& to) {
  const Vec3 n = r.normal();
  const Vec3 dir = to - from;
  const double denom = n.dot(dir);
  if (std::abs(denom) < 1e-12) return false;
  const double t = n.dot(r.corner - from) / denom;
  if (t < 0.0) return false;
  const Vec3 d = from + t * dir - r.corner;
  const double s = d.dot(r.edge_u) / r.edge_u.squaredNorm();
  const double q = d.dot(r.edge_v) / r.edge_v.squaredNorm();
  return s >= 0.0 && s <= 1.0 && q >= 0.0 && q <= 1.0;
}

}  // namespace

BoundaryScore scoreBoundary(const Surface& surface, const coverage::FlightStrategy& strategy,
                            const std::vector<sim::Rect>& truth, double sample_m) {
  requirePositive(sample_m, "scoreBoundary", "sample_m");
  BoundaryScore score;
  score.stops = strategy.stops.size();
  score.area_m2 = surface.area_m2;
  for (const auto& stop : strategy.stops) {
    bool hit = false;
    for (const auto& r : truth) hit = hit || rayHits(r, stop.position, stop.target);
    if (!hit) ++score.stops_over_air;
  }
  std::size_t samples = 0;
  std::size_t covered = 0;
  const double half_w = 0.5 * strategy.camera.footprint_w_m + 1e-9;
  const double half_h = 0.5 * strategy.camera.footprint_h_m + 1e-9;
  for (const auto& r : truth) {
    score.truth_area_m2 += r.area();
    const int nu = std::max(1, static_cast<int>(std::round(r.edge_u.norm() / sample_m)));
    const int nv = std::max(1, static_cast<int>(std::round(r.edge_v.norm() / sample_m)));
    for (int i = 0; i < nu; ++i) {
      for (int j = 0; j < nv; ++j) {  // cell centres: rectangles sharing an edge count once
        const Vec3 p = r.corner + (i + 0.5) / nu * r.edge_u + (j + 0.5) / nv * r.edge_v;
        ++samples;
        for (const auto& stop : strategy.stops) {
          const Vec3 d = p - stop.target;
          if (std::abs(d.dot(strategy.axis_w)) <= half_w &&
              std::abs(d.dot(strategy.axis_h)) <= half_h) {
            ++covered;
            break;
          }
        }
      }
    }
  }
  score.coverage = samples > 0 ? static_cast<double>(covered) / static_cast<double>(samples) : 0.0;
  score.area_error = score.truth_area_m2 > 0.0
                         ? std::abs(score.area_m2 - score.truth_area_m2) / score.truth_area_m2
                         : 0.0;
  return score;
}

}  // namespace uavip::app
