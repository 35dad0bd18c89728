#pragma once
/// \file
/// Small geometric helpers used by several stages.

#include <limits>
#include <utility>
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

/// Least distance between the segments [a0, a1] and [b0, b1] (either may be a point,
/// shorter than 1e-9 m) [m]; the closest points go to `on_a` and `on_b` when given.
/// Ericson, Real-Time Collision Detection §5.1.9; nearly parallel segments (sin² of
/// their angle ≤ 1e-18) take s = 0 on the first.
double segmentSegmentDistance(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1,
                              Vec3* on_a = nullptr, Vec3* on_b = nullptr);

/// A lower bound of segmentSegmentDistance, cheap: the distance between the two segments'
/// axis-aligned bounding boxes [m] (0 when the boxes meet). Exact for segments along one
/// axis; a pair this far apart needs no exact test against a smaller distance.
double segmentBoxesDistance(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1);

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

/// True when p lies inside the 2D polygon (either orientation), by the even-odd rule;
/// a point exactly on an edge may go either way.
bool pointInPolygon2d(const Eigen::Vector2d& p, const std::vector<Eigen::Vector2d>& polygon);

/// Distance from p to the segment a–b in 2D [m] (to a when a == b).
double pointSegmentDistance2d(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                              const Eigen::Vector2d& b);

/// Distance from p to the nearest edge of the closed 2D polygon [m] (inf when empty).
double distanceToPolygonEdges2d(const Eigen::Vector2d& p,
                                const std::vector<Eigen::Vector2d>& polygon);

/// The part of `subject` (any simple polygon) inside the convex counter-clockwise
/// polygon `clip` (Sutherland–Hodgman). For a concave subject the result may hold
/// zero-width bridges; its signed area and area centroid are still exact.
std::vector<Eigen::Vector2d> clipPolygonConvex2d(const std::vector<Eigen::Vector2d>& subject,
                                                 const std::vector<Eigen::Vector2d>& clip);

/// Area centroid of a 2D polygon; the vertex mean when its area is 0.
Eigen::Vector2d polygonCentroid2d(const std::vector<Eigen::Vector2d>& polygon);

/// The first pair (i, j), i < j, of non-adjacent edges (edge k runs from vertex k to
/// k + 1) that cross or touch, or of adjacent edges that fold back onto each other;
/// {-1, -1} when the polygon is simple. Fewer than 3 vertices: {-1, -1}. O(n²).
std::pair<int, int> polygonSelfIntersection2d(const std::vector<Eigen::Vector2d>& polygon);

/// True when every coordinate of every point is finite.
bool allFinite(const PointList& points);

}  // namespace uavip
