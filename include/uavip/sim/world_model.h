#pragma once
/// \file
/// Ground-truth synthetic worlds built from primitives (ARCHITECTURE.md, `sim/`):
/// point, line, plane (rectangle), box, crossed planes. Every primitive is stored as
/// the rectangles, segments and points it consists of, so every stage can be scored
/// against the truth.

#include "uavip/core/types.h"

#include <string>
#include <vector>

namespace uavip::sim {

/// A planar rectangle corner + s·edge_u + t·edge_v, s, t ∈ [0, 1] [m].
struct Rect {
  std::string name;
  Vec3 corner{Vec3::Zero()};
  Vec3 edge_u{Vec3::UnitX()};
  Vec3 edge_v{Vec3::UnitY()};

  /// Unit normal edge_u × edge_v (normalised).
  Vec3 normal() const;
  /// Area |edge_u × edge_v| [m²].
  double area() const;
  Vec3 center() const { return corner + 0.5 * (edge_u + edge_v); }
  /// Euclidean distance from p to the rectangle (a closed set) [m].
  double distance(const Vec3& p) const;
};

/// A straight segment a→b [m].
struct Segment {
  std::string name;
  Vec3 a{Vec3::Zero()};
  Vec3 b{Vec3::UnitX()};
};

/// A named isolated point [m].
struct TruthPoint {
  std::string name;
  Vec3 p{Vec3::Zero()};
};

/// The ground truth of a synthetic scenario.
class WorldModel {
 public:
  /// Adds a single point.
  void addPoint(const std::string& name, const Vec3& p);
  /// Adds a segment from a to b; throws InputError if a == b.
  void addLine(const std::string& name, const Vec3& a, const Vec3& b);
  /// Adds a rectangle; throws InputError if the edges are degenerate or parallel.
  void addPlane(const Rect& rect);
  /// Adds the 6 faces of a box with corners lo < hi, rotated by yaw_deg about its
  /// vertical centre axis. Face names are "<name>/+x", "<name>/-x", … (before yaw).
  void addBox(const std::string& name, const Vec3& lo, const Vec3& hi, double yaw_deg = 0.0);
  /// Adds two vertical rectangles width × height [m] crossing on the vertical line
  /// through center, at yaw_deg and yaw_deg + 90 (an "X" seen from above).
  void addCrossedPlanes(const std::string& name, const Vec3& center, double width, double height,
                        double yaw_deg = 0.0);

  const std::vector<Rect>& rects() const { return rects_; }
  const std::vector<Segment>& segments() const { return segments_; }
  const std::vector<TruthPoint>& points() const { return points_; }
  bool empty() const { return rects_.empty() && segments_.empty() && points_.empty(); }

  /// Distance from p to the nearest primitive of the world [m] (inf if empty).
  double distanceToTruth(const Vec3& p) const;

 private:
  std::vector<Rect> rects_;
  std::vector<Segment> segments_;
  std::vector<TruthPoint> points_;
};

}  // namespace uavip::sim
