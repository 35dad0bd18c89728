#pragma once
/// \file
/// Small geometric helpers used by several stages.

#include <limits>
#include <vector>

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

/// Twice the signed area of the 2D polygon (shoelace formula) [m²]: positive when its
/// vertices run counter-clockwise; 0 for < 3 vertices. Summed in vertex order from
/// vertex 0 (the closing edge last), so the result is reproducible to the bit.
double polygonTwiceSignedArea2d(const std::vector<Eigen::Vector2d>& polygon);

/// Area of a simple 2D polygon, either orientation [m²]; 0 for < 3 vertices.
double polygonArea2d(const std::vector<Eigen::Vector2d>& polygon);

/// 2D convex hull (Andrew's monotone chain, exact in double): the extreme points,
/// counter-clockwise, starting at the lowest x (then lowest y); collinear and
/// duplicate points dropped. Fewer than 3 input points are returned sorted; a
/// collinear set gives its two ends. O(n log n).
std::vector<Eigen::Vector2d> convexHull2d(std::vector<Eigen::Vector2d> points);

/// True when every coordinate of every point is finite.
bool allFinite(const PointList& points);

}  // namespace uavip
