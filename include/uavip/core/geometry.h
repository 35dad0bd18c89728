#pragma once
/// \file
/// Small geometric helpers used by several stages.

#include <limits>

#include "uavip/core/types.h"

namespace uavip {

/// Axis-aligned bounding box [m].
struct Aabb {
  Vec3 min{Vec3::Constant(std::numeric_limits<double>::infinity())};
  Vec3 max{Vec3::Constant(-std::numeric_limits<double>::infinity())};
  bool empty() const { return (min.array() > max.array()).any(); }
  void extend(const Vec3& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
};

/// Bounding box of a point list (empty box for an empty list).
Aabb boundingBox(const PointList& points);

/// Every point safety keeps clear of: the clean cloud followed by the safety cloud's
/// points (every input point, preprocess/safety_cloud.h) when the scene has one.
PointList safetyPoints(const Scene& scene);

/// Euclidean distance from p to the segment [a, b] [m].
double pointSegmentDistance(const Vec3& p, const Vec3& a, const Vec3& b);

/// Sum of segment lengths of a polyline [m].
double polylineLength(const PointList& path);

/// Area of a planar polygon given in 3D (any orientation) [m²]; 0 for < 3 vertices.
double polygonArea(const PointList& polygon);

/// True when every coordinate of every point is finite.
bool allFinite(const PointList& points);

}  // namespace uavip
