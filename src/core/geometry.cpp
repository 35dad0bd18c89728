#include "uavip/core/geometry.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace uavip {

Aabb boundingBox(const PointList& points) {
  Aabb box;
  for (const auto& p : points) box.extend(p);
  return box;
}

PointList safetyPoints(const Scene& scene) {
  PointList out = scene.cloud;
  if (scene.safety) out.insert(out.end(), scene.safety->points.begin(), scene.safety->points.end());
  return out;
}

double pointSegmentDistance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double len2 = ab.squaredNorm();
  if (len2 <= 0.0) return (p - a).norm();
  const double t = std::clamp((p - a).dot(ab) / len2, 0.0, 1.0);
  return (p - (a + t * ab)).norm();
}

double polylineLength(const PointList& path) {
  double len = 0.0;
  for (size_t i = 1; i < path.size(); ++i) len += (path[i] - path[i - 1]).norm();
  return len;
}

double polygonArea(const PointList& polygon) {
  if (polygon.size() < 3) return 0.0;
  // Half the norm of the vector area (sum of cross products about a vertex).
  Vec3 sum = Vec3::Zero();
  for (size_t i = 1; i + 1 < polygon.size(); ++i) {
    sum += (polygon[i] - polygon[0]).cross(polygon[i + 1] - polygon[0]);
  }
  return 0.5 * sum.norm();
}

double polygonTwiceSignedArea2d(const std::vector<Eigen::Vector2d>& polygon) {
  if (polygon.size() < 3) return 0.0;
  double twice = 0.0;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const auto& a = polygon[i];
    const auto& b = polygon[(i + 1) % polygon.size()];
    twice += a.x() * b.y() - b.x() * a.y();
  }
  return twice;
}

double polygonArea2d(const std::vector<Eigen::Vector2d>& polygon) {
  return 0.5 * std::abs(polygonTwiceSignedArea2d(polygon));
}

namespace {

/// z of (a − o) × (b − o): > 0 when o → a → b turns left.
double turn(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

}  // namespace

std::vector<Eigen::Vector2d> convexHull2d(std::vector<Eigen::Vector2d> points) {
  std::sort(points.begin(), points.end(), [](const auto& l, const auto& r) {
    return l.x() < r.x() || (l.x() == r.x() && l.y() < r.y());
  });
  if (points.size() < 3) return points;
  std::vector<Eigen::Vector2d> h(2 * points.size());
  std::size_t k = 0;
  for (const auto& p : points) {  // lower chain
    while (k >= 2 && turn(h[k - 2], h[k - 1], p) <= 0.0) --k;
    h[k++] = p;
  }
  for (std::size_t i = points.size() - 1, t = k + 1; i-- > 0;) {  // upper chain
    while (k >= t && turn(h[k - 2], h[k - 1], points[i]) <= 0.0) --k;
    h[k++] = points[i];
  }
  h.resize(k - 1);
  return h;
}

bool allFinite(const PointList& points) {
  return std::all_of(points.begin(), points.end(), [](const Vec3& p) { return p.allFinite(); });
}

}  // namespace uavip
