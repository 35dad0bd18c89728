#include "uavip/core/geometry.h"

#include <Eigen/Geometry>
#include <algorithm>

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

bool allFinite(const PointList& points) {
  return std::all_of(points.begin(), points.end(), [](const Vec3& p) { return p.allFinite(); });
}

}  // namespace uavip
