#include "uavip/core/geometry.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "uavip/core/math.h"

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

double segmentBoxesDistance(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1) {
  // Per axis the gap between the intervals [lo, hi] of the two boxes, 0 where they overlap.
  const Vec3 gap =
      (b0.cwiseMin(b1) - a0.cwiseMax(a1)).cwiseMax(a0.cwiseMin(a1) - b0.cwiseMax(b1)).cwiseMax(0.0);
  return gap.norm();
}

double segmentSegmentDistance(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1,
                              Vec3* on_a, Vec3* on_b) {
  const Vec3 d1 = a1 - a0;
  const Vec3 d2 = b1 - b0;
  const Vec3 r = a0 - b0;
  const double a = d1.squaredNorm();
  const double e = d2.squaredNorm();
  const double f = d2.dot(r);
  constexpr double kTiny = 1e-18;  // [m²] a segment this short is a point
  double s = 0.0;
  double t = 0.0;
  if (a <= kTiny && e <= kTiny) {
    // both points: s = t = 0
  } else if (a <= kTiny) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= kTiny) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2);
      const double denom = a * e - b * b;
      s = denom > kTiny * a * e ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1.0) {
        t = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  const Vec3 pa = a0 + s * d1;
  const Vec3 pb = b0 + t * d2;
  if (on_a != nullptr) *on_a = pa;
  if (on_b != nullptr) *on_b = pb;
  return (pa - pb).norm();
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

bool pointInPolygon2d(const Eigen::Vector2d& p, const std::vector<Eigen::Vector2d>& polygon) {
  bool inside = false;
  const std::size_t n = polygon.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const Eigen::Vector2d& a = polygon[i];
    const Eigen::Vector2d& b = polygon[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) &&
        p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x()) {
      inside = !inside;
    }
  }
  return inside;
}

double pointSegmentDistance2d(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                              const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

double distanceToPolygonEdges2d(const Eigen::Vector2d& p,
                                const std::vector<Eigen::Vector2d>& polygon) {
  double best = std::numeric_limits<double>::infinity();
  const std::size_t n = polygon.size();
  for (std::size_t i = 0; i < n; ++i)
    best = std::min(best, pointSegmentDistance2d(p, polygon[i], polygon[(i + 1) % n]));
  return best;
}

std::vector<Eigen::Vector2d> clipPolygonConvex2d(const std::vector<Eigen::Vector2d>& subject,
                                                 const std::vector<Eigen::Vector2d>& clip) {
  std::vector<Eigen::Vector2d> out = subject;
  const std::size_t m = clip.size();
  for (std::size_t k = 0; k < m && !out.empty(); ++k) {
    const Eigen::Vector2d& c0 = clip[k];
    const Eigen::Vector2d& c1 = clip[(k + 1) % m];
    const auto side = [&](const Eigen::Vector2d& p) { return turn(c0, c1, p); };
    std::vector<Eigen::Vector2d> in = std::move(out);
    out.clear();
    for (std::size_t i = 0; i < in.size(); ++i) {
      const Eigen::Vector2d& p = in[i];
      const Eigen::Vector2d& q = in[(i + 1) % in.size()];
      const double sp = side(p);
      const double sq = side(q);
      if (sp >= 0.0) out.push_back(p);
      if ((sp >= 0.0) != (sq >= 0.0)) out.push_back(p + (sp / (sp - sq)) * (q - p));
    }
  }
  return out;
}

Eigen::Vector2d polygonCentroid2d(const std::vector<Eigen::Vector2d>& polygon) {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  if (polygon.empty()) return mean;
  for (const auto& p : polygon) mean += p;
  mean /= static_cast<double>(polygon.size());
  double a2 = 0.0;
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  const std::size_t n = polygon.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d p = polygon[i] - mean;
    const Eigen::Vector2d q = polygon[(i + 1) % n] - mean;
    const double w = p.x() * q.y() - q.x() * p.y();
    a2 += w;
    c += w * (p + q);
  }
  if (std::abs(a2) <= 1e-15) return mean;
  return mean + c / (3.0 * a2);
}

namespace {

/// True when the closed segments [a, b] and [c, d] share a point.
bool segmentsMeet(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                  const Eigen::Vector2d& d) {
  const double d1 = turn(c, d, a);
  const double d2 = turn(c, d, b);
  const double d3 = turn(a, b, c);
  const double d4 = turn(a, b, d);
  if (((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0)) &&
      ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))) {
    return true;
  }
  const auto onSegment = [](const Eigen::Vector2d& p, const Eigen::Vector2d& q,
                            const Eigen::Vector2d& r) {
    return r.x() >= std::min(p.x(), q.x()) && r.x() <= std::max(p.x(), q.x()) &&
           r.y() >= std::min(p.y(), q.y()) && r.y() <= std::max(p.y(), q.y());
  };
  return (d1 == 0.0 && onSegment(c, d, a)) || (d2 == 0.0 && onSegment(c, d, b)) ||
         (d3 == 0.0 && onSegment(a, b, c)) || (d4 == 0.0 && onSegment(a, b, d));
}

}  // namespace

std::pair<int, int> polygonSelfIntersection2d(const std::vector<Eigen::Vector2d>& polygon) {
  const std::size_t n = polygon.size();
  if (n < 3) return {-1, -1};
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d& a = polygon[i];
    const Eigen::Vector2d& b = polygon[(i + 1) % n];
    for (std::size_t j = i + 1; j < n; ++j) {
      const Eigen::Vector2d& c = polygon[j];
      const Eigen::Vector2d& d = polygon[(j + 1) % n];
      const bool adjacent = j == i + 1 || (i == 0 && j == n - 1);
      if (adjacent) {
        // Adjacent edges share one vertex; they overlap only when they fold back.
        const Eigen::Vector2d& shared = j == i + 1 ? b : a;
        const Eigen::Vector2d& p = j == i + 1 ? a : b;
        const Eigen::Vector2d& q = j == i + 1 ? d : c;
        const Eigen::Vector2d u = p - shared;
        const Eigen::Vector2d v = q - shared;
        if (u.squaredNorm() == 0.0 || v.squaredNorm() == 0.0 ||
            (std::abs(u.x() * v.y() - u.y() * v.x()) <= 1e-12 * u.norm() * v.norm() &&
             u.dot(v) > 0.0)) {
          return {static_cast<int>(i), static_cast<int>(j)};
        }
        continue;
      }
      if (segmentsMeet(a, b, c, d)) return {static_cast<int>(i), static_cast<int>(j)};
    }
  }
  return {-1, -1};
}

bool KeepOut::contains(const Vec3& p, double margin) const {
  const Vec3 d = p - center;
  if (std::abs(d.z()) > 0.5 * size.z() + margin) return false;
  if (shape == Shape::Cylinder) return d.head<2>().norm() <= 0.5 * size.x() + margin;
  const double yaw = yaw_deg * kDegToRad;
  const double x = std::cos(yaw) * d.x() + std::sin(yaw) * d.y();
  const double y = -std::sin(yaw) * d.x() + std::cos(yaw) * d.y();
  return std::abs(x) <= 0.5 * size.x() + margin && std::abs(y) <= 0.5 * size.y() + margin;
}

bool allFinite(const PointList& points) {
  return std::all_of(points.begin(), points.end(), [](const Vec3& p) { return p.allFinite(); });
}

}  // namespace uavip
