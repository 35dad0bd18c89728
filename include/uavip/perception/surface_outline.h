#pragma once
/// \file
/// Stage 4 (paper §II-D, and its bridge results §III-B: "for concave surfaces extra areas
/// should be accounted for"): the boundary that follows a surface's points. The projected
/// inliers are binned into square cells on the plane, aligned with the smallest-area
/// rectangle around their convex hull (so the edges of an L-shaped wall or a window run
/// along the cells); the occupied cells are closed morphologically (gaps of the
/// sampling), the largest 4-connected region is kept, openings smaller than
/// `min_hole_m2` are filled, and its outline (outer polygon and holes) is traced along
/// the cell edges, collinear vertices merged.

#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

namespace uavip::perception {

/// Options of the outline.
struct OutlineOptions {
  double cell_m{0.1};             ///< cell edge on the plane (perception.area_cell_m) [m]
  int close_cells{1};             ///< closing radius: gaps up to 2 × this many cells are bridged
  double min_hole_m2{0.25};       ///< openings smaller than this are filled (missing points) [m²]
  long long max_cells{20000000};  ///< the cell grid over the surface's extent may hold no more

  /// Throws InputError naming the bad field (prefix `where`).
  void validate(const std::string& where = "perception.outline") const;
};

/// An outline on the plane, in the plane's 2D coordinates [m].
struct Outline2d {
  std::vector<Eigen::Vector2d> outer;               ///< counter-clockwise
  std::vector<std::vector<Eigen::Vector2d>> holes;  ///< clockwise
  /// Area of the outer polygon minus the holes = occupied cells × cell² [m²].
  double area_m2{0.0};
};

/// The outline of the cells `uv` occupies (see the file comment). Empty (no outer
/// polygon) for fewer than 3 points. A grid over `max_cells` is traced at a coarser
/// cell that fits. Deterministic: the same points in any order give the same outline.
Outline2d occupiedOutline2d(const std::vector<Eigen::Vector2d>& uv, const OutlineOptions& options);

/// The outline of the cells of edge `cell_m` [m], laid along `axis` (and `axis` turned
/// 90°) over [lo, hi] (coordinates along those two axes), whose centres `inside`
/// accepts: the largest 4-connected region, openings under `min_hole_m2` filled. How
/// an edit adds or cuts a polygon (app/edits.h). Throws InputError beyond 2·10⁷ cells.
Outline2d rasterOutline2d(const std::function<bool(const Eigen::Vector2d&)>& inside,
                          const Eigen::Vector2d& lo, const Eigen::Vector2d& hi,
                          const Eigen::Vector2d& axis, double cell_m, double min_hole_m2);

}  // namespace uavip::perception
