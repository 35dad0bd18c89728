#pragma once
/// \file
/// Ground-truth synthetic worlds built from primitives (docs/ARCHITECTURE.md, `sim`):
/// point, line, plane (rectangle), box, crossed planes. Every primitive is stored as
/// the rectangles, segments and points it consists of, so every stage can be scored
/// against the truth. Clutter (trees, grass, paper §III-B bridge) is made of small
/// boxes, so it is seen by the ray-casting scanner simulation (scanner_sim.h) and
/// stays an obstacle: no piece is a plane of 2 m² or more.

#include <cstdint>
#include <string>
#include <vector>

#include "uavip/core/types.h"

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

/// A tree: a square trunk box standing on its base point and a crown of small cubes
/// whose centres are uniform in a ball on top of the trunk (seeded). With the
/// defaults every planar slice of the tree is well under 2 m², so stage 4 leaves it
/// to the obstacles.
struct TreeOptions {
  double trunk_height_m{1.5};  ///< trunk box height [m]
  double trunk_width_m{0.15};  ///< trunk box width and depth [m]
  double crown_radius_m{
      0.35};                 ///< crown cube centres lie within this radius of the crown centre [m]
  int crown_boxes{8};        ///< number of crown cubes
  double crown_box_m{0.25};  ///< crown cube edge [m]
  std::uint32_t seed{1};     ///< seed of the crown layout

  /// Throws InputError naming the bad field (prefix `where`).
  void validate(const std::string& where = "tree") const;
};

/// A patch of grass: thin vertical tuft boxes at uniform positions on the ground
/// (seeded); tuft heights uniform in [0.5, 1] × tuft_height_m.
struct GrassOptions {
  double size_x_m{2.0};       ///< patch extent along x [m]
  double size_y_m{2.0};       ///< patch extent along y [m]
  int tufts{12};              ///< number of tufts
  double tuft_height_m{0.4};  ///< tallest tuft [m]
  double tuft_width_m{0.06};  ///< tuft box width and depth [m]
  std::uint32_t seed{1};      ///< seed of the layout

  /// Throws InputError naming the bad field (prefix `where`).
  void validate(const std::string& where = "grass") const;
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

  /// Adds a tree standing on `base` (the trunk's bottom centre): 6 faces per box,
  /// named "<name>/trunk/+x", "<name>/crown0/-z", …
  void addTree(const std::string& name, const Vec3& base, const TreeOptions& options = {});
  /// Adds a grass patch centred on `center` (the ground level is center.z): 6 faces
  /// per tuft box, named "<name>/tuft0/+x", …
  void addGrass(const std::string& name, const Vec3& center, const GrassOptions& options = {});

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
