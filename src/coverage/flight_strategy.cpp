#include "uavip/coverage/flight_strategy.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <utility>

#include "uavip/core/error.h"
#include "uavip/core/geometry.h"
#include "uavip/core/math.h"
#include "uavip/core/parallel.h"
#include "uavip/core/text.h"

// Conventions of the photo stops (paper §II-F, 2-DOF mount: yaw by the UAV, pitch by
// a gimbal without roll).
//
// The camera looks along −n (n = outward surface normal). Its image x axis (width,
// "right" in the photo) is axis_w and its image y axis (height, "up" in the photo) is
// axis_h, with axis_w × axis_h = n.
//  * Non-horizontal surface (|n_z| < kHorizontalNz): axis_w = normalize(ẑ × n) is
//    horizontal, axis_h = n × axis_w points up the surface. The heading is the
//    horizontal view direction: yaw = atan2(−n_y, −n_x).
//  * Near-horizontal surface (|n_z| >= kHorizontalNz: roof, deck top, ceiling, deck
//    underside): axis_w = surface.axis_u projected onto the plane (a mosaic or a
//    reconstruction: the longer side of the boundary's least enclosing rectangle when
//    that is 2 % smaller than the one along axis_u, horizontalRowAxis), axis_h = n × axis_w.
//    A gimbal pitched from horizontal to straight down turns the image "up" onto the
//    UAV's forward direction, so when looking down (pitch < 0) the heading is the
//    horizontal direction of axis_h: yaw = atan2(axis_h_y, axis_h_x). Pitched to
//    straight up, image "up" turns onto the UAV's backward direction, so when looking up
//    (pitch > 0) the heading is the horizontal direction of −axis_h:
//    yaw = atan2(−axis_h_y, −axis_h_x). Both keep image width along axis_w.
//    On an exactly horizontal surface the view is exactly along −n. On a slightly
//    tilted one (tilt θ < acos 0.95 ≈ 18°) a mount without roll cannot both look along
//    −n and keep the image width on axis_w; the image axes win and the view direction
//    may differ from −n by up to 2θ (position and target are still exact).
//  * Pitch = asin(−n_z) [deg]: −90 straight down, 0 horizontal, +90 straight up.
//  * Yaw in degrees counter-clockwise from +x, in (−180, 180].

namespace uavip::coverage {

namespace {

/// |n_z| at and above which a surface counts as horizontal (roof, ceiling).
constexpr double kHorizontalNz = 0.95;
/// Overlap of a footprint with the boundary below this [m²] counts as touching only.
constexpr double kOverlapTol = 1e-9;
/// A photo centre moved off air onto the surface lies at least this fraction of the
/// smaller stop spacing inside the surface's edges, when the footprint allows.
constexpr double kInsetFraction = 0.25;
/// Samples per footprint side searched for a photo centre on the surface.
constexpr int kCentreSamples = 24;
/// Grids of at least this many cells find their rows on every core.
constexpr double kParallelCells = 1000.0;
/// Reconstruction: the first and last photo centres of an axis lie this far inside
/// the boundary's extent, so they are on the surface, not on its edge [m].
constexpr double kEdgeInsetM = 1e-3;
/// Reconstruction: footprints per spacing are raised to this much above an even
/// count, so an edge point keeps its extra footprint despite rounding.
constexpr double kEdgeMargin = 0.1;
/// Reconstruction: the quantile of the inliers' heights in front of the plane the
/// rows' margin keeps in view (reconstructionShrink).
constexpr double kReconstructionFrontQuantile = 0.999;
/// Reconstruction: the largest margin the inliers' heights may ask for, a share of the
/// footprint (a surface whose points stand farther out is not a plane to photograph).
constexpr double kMaxReconstructionShrink = 0.3;
/// addStopsFor: a stop added counts a view for the points within this share of its
/// footprint about its target (room for a repair's tilt; a point still short is found
/// again in the pipeline's next round).
constexpr double kTopUpFootprintShare = 0.8;
/// addStopsFor: candidate targets per footprint side.
constexpr double kTopUpCells = 8.0;

using Vec2 = Eigen::Vector2d;

/// Projection of a 2D point set onto axis: [min, max].
std::pair<double, double> projectRange(const std::vector<Vec2>& pts, const Vec2& axis) {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -lo;
  for (const auto& p : pts) {
    const double s = p.dot(axis);
    lo = std::min(lo, s);
    hi = std::max(hi, s);
  }
  return {lo, hi};
}

/// The surface's region in the frame of its stops: the boundary minus its holes.
struct Region {
  std::vector<Vec2> outer;
  std::vector<std::vector<Vec2>> holes;
  /// The edges a traced outline may overshoot into air: every hole edge and every
  /// edge of the outline off its convex hull (a concave corner), as segments.
  std::vector<std::pair<Vec2, Vec2>> inner_edges;

  bool contains(const Vec2& p) const {
    if (!pointInPolygon2d(p, outer)) return false;
    return std::none_of(holes.begin(), holes.end(),
                        [&](const auto& h) { return pointInPolygon2d(p, h); });
  }
  /// True when p lies at least `inset` from every inner edge (always when there is
  /// none: a convex boundary keeps the paper's regular grid). An edge is measured
  /// both ways, as the closed polygon {a, b} of distanceToPolygonEdges2d, and the
  /// first edge closer than `inset` decides.
  bool deepEnough(const Vec2& p, double inset) const {
    return std::none_of(inner_edges.begin(), inner_edges.end(), [&](const auto& e) {
      return std::min(pointSegmentDistance2d(p, e.first, e.second),
                      pointSegmentDistance2d(p, e.second, e.first)) < inset;
    });
  }
  /// Area of the part of the convex counter-clockwise polygon `window` inside the
  /// region [m²] and that part's centroid.
  std::pair<double, Vec2> overlap(const std::vector<Vec2>& window) const {
    const auto part = [&](const std::vector<Vec2>& poly) {
      const std::vector<Vec2> clipped = clipPolygonConvex2d(poly, window);
      return std::make_pair(polygonArea2d(clipped), polygonCentroid2d(clipped));
    };
    auto [area, c] = part(outer);
    Vec2 moment = area * c;
    for (const auto& h : holes) {
      const auto [ha, hc] = part(h);
      area -= ha;
      moment -= ha * hc;
    }
    return {area, area > 0.0 ? Vec2(moment / area) : c};
  }
};

/// The axis-aligned rectangle of half sizes (hw, hh) about (a, b), counter-clockwise.
std::vector<Vec2> rectangle(double a, double b, double hw, double hh) {
  return {Vec2(a - hw, b - hh), Vec2(a + hw, b - hh), Vec2(a + hw, b + hh), Vec2(a - hw, b + hh)};
}

/// Angle in degrees wrapped to (−180, 180] (atan2 gives −180 for a −0 y component).
double wrapDeg(double deg) {
  while (deg <= -180.0) deg += 360.0;
  while (deg > 180.0) deg -= 360.0;
  return deg;
}

/// Any unit vector orthogonal to n.
Vec3 anyOrthogonal(const Vec3& n) {
  const Vec3 trial = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  return (trial - trial.dot(n) * n).normalized();
}

}  // namespace

void CoverageOptions::validate(const std::string& where) const {
  camera.validate(where + ".camera");
  table().check(*this, where);
  if (!camera.from_sensor && standoff_m > camera.maxStandoff())
    throw InputError(
        where + ": standoff_m " + formatNumber(standoff_m) + " is beyond " +
        (camera.max_range_m > 0.0
             ? "camera.max_range_m " + formatNumber(camera.max_range_m)
             : formatNumber(kMaxStandoffWithoutRangeM) + " m (no camera.max_range_m given)") +
        "; fly closer, or set camera.max_range_m");
  requireThat(gimbal.pitch_min_deg <= gimbal.pitch_max_deg, where, "gimbal.pitch_min_deg",
              "<= gimbal.pitch_max_deg (" + std::to_string(gimbal.pitch_max_deg) + ")",
              gimbal.pitch_min_deg);
}

const params::Table<CoverageOptions>& CoverageOptions::table() {
  static const params::Table<CoverageOptions> t = [] {
    using O = CoverageOptions;
    params::Table<O> p;
    p.add(
         "overlap", params::Kind::Numbers,
         [](const O& o) {
           return params::Value{{o.overlap_w, o.overlap_h}, {}, true};
         },
         [](O& o, const params::Value& v) {
           o.overlap_w = v.numbers.at(0);
           o.overlap_h = v.numbers.size() > 1 ? v.numbers[1] : v.numbers[0];
         },
         "overlap of neighbouring photos [along the width, along the height] (paper: 0.2)")
        .count(2, 2)
        .orScalar()
        .atLeast(0.0)
        .below(1.0)
        .address = [](const O& o) -> const void* { return &o.overlap_w; };
    p.add("standoff_m", &O::standoff_m,
          "distance from the surface when the camera gives a footprint directly (paper: 1.5 m)")
        .unitIs("m")
        .positive();
    p.add("max_stops", &O::max_stops, "most photo stops one surface may get").within(1.0, 1e8);
    p.add("mode", &O::mode,
          "surfaces (the paper's rows, plane by plane) or structure (one view selection over "
          "the whole structure)")
        .oneOf({"surfaces", "structure"});
    p.add("ground_z_m", &O::ground_z_m,
          "structure mode: points below this height are ground (unset: the lowest level "
          "surfaces)")
        .unitIs("m");
    p.add("structure_target", &O::structure_target,
          "structure mode: share of the imageable structure points the photos must image")
        .above(0.0)
        .atMost(1.0);
    p.add(
         "gimbal_pitch_deg", params::Kind::Numbers,
         [](const O& o) {
           return params::Value{{o.gimbal.pitch_min_deg, o.gimbal.pitch_max_deg}, {}, true};
         },
         [](O& o, const params::Value& v) {
           o.gimbal.pitch_min_deg = v.numbers.at(0);
           o.gimbal.pitch_max_deg = v.numbers.at(1);
         },
         "gimbal pitch limits [most downward, most upward] (-90 = straight down)")
        .unitIs("deg")
        .count(2, 2)
        .within(-90.0, 90.0)
        .fromProfile()
        .address = [](const O& o) -> const void* { return &o.gimbal; };
    p.add("purpose", &O::purpose,
          "inspection (the paper's rows at overlap), mosaic (overlap 0.6 / 0.3 unless set) or "
          "reconstruction (min_views photos of every point, 60 % shared by consecutive photos, "
          "rows overlapping by what the points in front of the plane need unless overlap is set)")
        .oneOf({"inspection", "mosaic", "reconstruction"});
    p.add("min_views", &O::min_views, "reconstruction: photos that image every surface point")
        .within(2, 50);
    p.add("min_triangulation_deg", &O::min_triangulation_deg,
          "reconstruction: largest angle between two rays to a point, at least")
        .unitIs("deg")
        .within(0.0, 60.0);
    return p;
  }();
  return t;
}

namespace {

/// A surface's unit normal and its image axes on the surface (see the conventions at
/// the top of this file).
struct SurfaceFrame {
  Vec3 n;
  Vec3 axis_w;
  Vec3 axis_h;
  bool horizontal{false};
};

/// `axis_u`: the surface's first in-plane axis, the image width of a horizontal one.
SurfaceFrame surfaceFrame(const Vec3& axis_u, const Vec3& n) {
  SurfaceFrame f;
  f.n = n;
  f.horizontal = std::abs(n.z()) >= kHorizontalNz;
  if (!f.horizontal) {
    f.axis_w = Vec3::UnitZ().cross(n).normalized();
  } else {
    f.axis_w = axis_u - axis_u.dot(n) * n;
    f.axis_w = f.axis_w.norm() > 1e-9 ? f.axis_w.normalized() : anyOrthogonal(n);
  }
  f.axis_h = n.cross(f.axis_w).normalized();
  return f;
}

/// Orientation, the same for every stop of a planar surface [deg].
struct Attitude {
  double pitch{0.0};
  double yaw{0.0};
  bool gimbal_ok{false};  ///< the pitch is within the gimbal's range
};

Attitude stopAttitude(const SurfaceFrame& f, const GimbalLimits& gimbal) {
  Attitude at;
  const Vec3& n = f.n;
  at.pitch = std::asin(std::clamp(-n.z(), -1.0, 1.0)) * kRadToDeg;
  if (!f.horizontal) {
    at.yaw = std::atan2(-n.y(), -n.x()) * kRadToDeg;
  } else {
    const double sign = at.pitch < 0.0 ? 1.0 : -1.0;
    at.yaw = std::atan2(sign * f.axis_h.y(), sign * f.axis_h.x()) * kRadToDeg;
  }
  at.yaw = wrapDeg(at.yaw);
  at.gimbal_ok = at.pitch >= gimbal.pitch_min_deg - 1e-9 && at.pitch <= gimbal.pitch_max_deg + 1e-9;
  return at;
}

/// A horizontal surface's rows run along the boundary's minimum-area enclosing
/// rectangle (rotating calipers over its convex hull: one side lies on a hull edge)
/// when that rectangle is at least this much smaller than the one along axis_u.
constexpr double kRectangleGain = 0.02;

/// Row axis of a horizontal surface of a mosaic or a reconstruction (its image width, see
/// the conventions at the top; inspection keeps axis_u, the paper's grid as before):
/// axis_u (PCA's first axis, projected on the plane n) unless the boundary's
/// minimum-area rectangle is kRectangleGain smaller than its rectangle along axis_u;
/// then that rectangle's longer side, turned to axis_u's side. PCA's axis is arbitrary
/// on a near-square roof and would lay the grid diagonally: more photos, and centres
/// moved off the corners' air that break the rows' shared footprint.
Vec3 horizontalRowAxis(const Surface& surface, const Vec3& n) {
  Vec3 u = surface.axis_u - surface.axis_u.dot(n) * n;
  u = u.norm() > 1e-9 ? u.normalized() : anyOrthogonal(n);
  const Vec3 v = n.cross(u);
  std::vector<Vec2> pts;
  pts.reserve(surface.boundary.size());
  for (const auto& p : surface.boundary) pts.emplace_back(p.dot(u), p.dot(v));
  const std::vector<Vec2> hull = convexHull2d(pts);
  if (hull.size() < 3) return u;
  const auto extents = [&](const Vec2& dir) {
    const auto [alo, ahi] = projectRange(hull, dir);
    const auto [blo, bhi] = projectRange(hull, Vec2(-dir.y(), dir.x()));
    return std::make_pair(ahi - alo, bhi - blo);
  };
  const auto [bu, bv] = extents(Vec2::UnitX());
  double best_area = (1.0 - kRectangleGain) * bu * bv;
  std::optional<Vec2> best;
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const Vec2 e = hull[(i + 1) % hull.size()] - hull[i];
    if (!(e.norm() > 1e-12)) continue;
    const Vec2 dir = e.normalized();
    const auto [a, b] = extents(dir);
    if (a * b < best_area) {
      best_area = a * b;
      best = a >= b ? dir : Vec2(-dir.y(), dir.x());
    }
  }
  if (!best) return u;
  const Vec2 w = best->x() >= 0.0 ? *best : Vec2(-*best);
  return (w.x() * u + w.y() * v).normalized();
}

/// The boundary and its holes in (axis_w, axis_h) coordinates about origin [m].
Region regionInFrame(const Surface& surface, const SurfaceFrame& f, const Vec3& origin) {
  const auto toFrame = [&](const PointList& loop) {
    std::vector<Vec2> poly;
    poly.reserve(loop.size());
    for (const auto& p : loop) {
      const Vec3 d = p - origin;
      poly.emplace_back(d.dot(f.axis_w), d.dot(f.axis_h));
    }
    return poly;
  };
  Region region;
  region.outer = toFrame(surface.boundary);
  if (polygonTwiceSignedArea2d(region.outer) < 0.0)
    std::reverse(region.outer.begin(), region.outer.end());
  for (const auto& h : surface.holes) {
    if (h.size() >= 3 && allFinite(h)) region.holes.push_back(toFrame(h));
  }
  const std::size_t n = region.outer.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2& a = region.outer[i];
    const Vec2& b = region.outer[(i + 1) % n];
    const Vec2 e = b - a;
    const double len = e.norm();
    const bool on_hull = std::all_of(region.outer.begin(), region.outer.end(), [&](const Vec2& q) {
      return e.x() * (q.y() - a.y()) - e.y() * (q.x() - a.x()) >= -1e-9 * len;
    });
    if (!on_hull) region.inner_edges.emplace_back(a, b);
  }
  for (const auto& h : region.holes) {
    for (std::size_t i = 0; i < h.size(); ++i)
      region.inner_edges.emplace_back(h[i], h[(i + 1) % h.size()]);
  }
  return region;
}

/// The photo centre of the cell about (a, b) whose footprint meets the region by
/// `area` (> 0) (paper §II-F; the stop must look at the surface, not at air): the cell
/// centre when it lies on the region at least kInsetFraction of the spacing from its
/// inner edges (holes, concave corners: a boundary traced around the points may reach
/// a little past them there), else
/// the point of the region nearest to the centroid of what the cell (or, if the cell
/// holds none, the footprint) holds, that far inside when the footprint allows. Empty when no
/// sample of the footprint lies on the region.
std::optional<Vec2> photoCentre(const Region& region, const FlightStrategy& fs, double a,
                                double b) {
  const Vec2 centre(a, b);
  const double inset = kInsetFraction * std::min(fs.spacing_w_m, fs.spacing_h_m);
  if (region.contains(centre) && region.deepEnough(centre, inset)) return centre;
  const double half_w = 0.5 * fs.camera.footprint_w_m;
  const double half_h = 0.5 * fs.camera.footprint_h_m;
  auto [cell_area, goal] =
      region.overlap(rectangle(a, b, 0.5 * fs.spacing_w_m, 0.5 * fs.spacing_h_m));
  if (!(cell_area > kOverlapTol)) goal = region.overlap(rectangle(a, b, half_w, half_h)).second;
  if (region.contains(goal) && region.deepEnough(goal, inset)) return goal;
  // The samples nearest to the goal first (ties in sampling order): the first deep
  // sample on the region is the answer, else the nearest sample on it.
  std::vector<std::pair<double, Vec2>> samples;
  samples.reserve(static_cast<std::size_t>(kCentreSamples + 1) * (kCentreSamples + 1));
  for (int i = 0; i <= kCentreSamples; ++i) {
    for (int j = 0; j <= kCentreSamples; ++j) {
      const Vec2 q(a - half_w + 2.0 * half_w * i / kCentreSamples,
                   b - half_h + 2.0 * half_h * j / kCentreSamples);
      samples.emplace_back((q - goal).squaredNorm(), q);
    }
  }
  std::stable_sort(samples.begin(), samples.end(),
                   [](const auto& x, const auto& y) { return x.first < y.first; });
  std::optional<Vec2> best;
  for (const auto& [d, q] : samples) {
    if (!region.contains(q)) continue;
    if (region.deepEnough(q, inset)) return q;
    if (!best) best = q;
  }
  return best;
}

/// Cells along an axis of extent `len` at most `spacing` apart, counted in double
/// (a tiny footprint or a huge boundary must not overflow). Rows: max(⌈len/spacing⌉,
/// 1), tolerant of rounding (4.8/0.48 = 10), centred on the extent. Edge to edge (an
/// edge link, planEdgeLinks): the first and last photo centres kEdgeInsetM inside the extent's
/// ends, so a point at an edge is in as many footprints as half a footprint holds.
double cellsAlong(double len, double spacing, bool edge_to_edge) {
  if (!edge_to_edge) return std::max(1.0, std::ceil(len / spacing - 1e-9));
  const double span = len - 2.0 * kEdgeInsetM;
  return span > 0.0 ? std::ceil(span / spacing - 1e-9) + 1.0 : 1.0;
}

/// The spacing of `cells` centres edge to edge over `len` (cellsAlong) [m].
double edgeSpacing(double len, double cells, double spacing) {
  return cells > 1.0 ? (len - 2.0 * kEdgeInsetM) / (cells - 1.0) : spacing;
}

/// Reconstruction's photo centres along a row over the extent [lo, hi] [m] (issue 46):
/// every point of the extent in `views` footprints of width `footprint` from this row
/// alone, consecutive centres at most `spacing` apart (spacing <= footprint / views, so
/// a point inside is in ⌊footprint / spacing⌋ >= views). At each end the first `views`
/// centres (the outer one kEdgeInsetM inside the end) lie within half a footprint of the
/// edge, `edge` = footprint / (2 (views − 1) + margin) apart, so an edge point is in
/// `views` too; between them the centres are evenly spaced. An extent too short for
/// that gets `edge` spacing throughout, and at least `views` centres.
class ReconstructionColumns {
 public:
  ReconstructionColumns(double lo, double hi, double footprint, double spacing, int views)
      : a_(lo + kEdgeInsetM), b_(hi - kEdgeInsetM), views_(views) {
    if (!(b_ > a_)) {
      a_ = b_ = 0.5 * (lo + hi);
      return;
    }
    edge_ = views > 1 ? std::min(spacing, 0.5 * footprint / (views - 1 + kEdgeMargin)) : spacing;
    c0_ = a_ + (views - 1) * edge_;
    c1_ = b_ - (views - 1) * edge_;
    dense_ = c1_ - c0_ < edge_;
    intervals_ = dense_
                     ? std::max(std::ceil((b_ - a_) / edge_ - 1e-9), std::max(views - 1, 1) + 0.0)
                     : std::ceil((c1_ - c0_) / spacing - 1e-9);
  }
  /// How many centres (counted in double: checked against max_stops before any is made).
  double count() const {
    if (!(b_ > a_)) return 1.0;
    return dense_ ? intervals_ + 1.0 : intervals_ + 1.0 + 2.0 * (views_ - 1);
  }
  /// The centres, in increasing order [m].
  std::vector<double> centres() const {
    if (!(b_ > a_)) return {a_};
    std::vector<double> xs;
    xs.reserve(static_cast<std::size_t>(count()));
    const auto evenly = [&xs](double from, double to, double intervals) {
      for (double k = 0.0; k <= intervals; ++k) xs.push_back(from + (to - from) * k / intervals);
    };
    if (dense_) {
      evenly(a_, b_, intervals_);
      return xs;
    }
    for (int k = 0; k + 1 < views_; ++k) xs.push_back(a_ + k * edge_);
    evenly(c0_, c1_, intervals_);
    for (int k = views_ - 2; k >= 0; --k) xs.push_back(b_ - k * edge_);
    return xs;
  }

 private:
  double a_, b_;
  int views_;
  double edge_{0.0}, c0_{0.0}, c1_{0.0}, intervals_{0.0};
  bool dense_{false};
};

/// A reconstruction's rows over an extent `len` [m] across them, counted in double:
/// each row holds the points `shrink` of a footprint in front of the plane within its
/// reach, fh (1 − max(overlap_h, shrink)) (the file's side overlap is a margin at least
/// as large), and the rows are as few as reach the extent's two edges, spread evenly
/// between them: every seam and both edges keep the same margin (a grid centred on the
/// extent left its slack beyond the edges). Sets fs.spacing_h_m to their spacing.
double reconstructionRows(FlightStrategy& fs, double len, double overlap_h, double shrink) {
  const double reach = fs.camera.footprint_h_m * (1.0 - std::max(overlap_h, shrink));
  if (!(len > reach) || !(reach > 0.0)) {
    fs.spacing_h_m = std::max(reach, 0.0);
    return 1.0;
  }
  const double rows = std::ceil((len - reach) / reach - 1e-9) + 1.0;
  fs.spacing_h_m = (len - reach) / (rows - 1.0);
  return rows;
}

/// The photo centres' coordinates along axis_w of every row (fs.cols of them) and
/// fs.rows to cover the boundary's extent [wlo, whi] × [hlo, hhi]. The paper's grid
/// (inspection, mosaic): cells `spacing` apart centred on the extent. A reconstruction:
/// ReconstructionColumns along the rows (min_views come from each row alone, for points
/// `shrink` of a footprint in front of the plane too; bridgeRows keeps consecutive photos
/// sharing kReconstructionShare from one row to the next) and reconstructionRows across
/// them (fs.spacing_h_m set to theirs). Throws InputError beyond options.max_stops.
std::vector<double> sizeGrid(FlightStrategy& fs, const Surface& surface,
                             const CoverageOptions& options, double shrink, double wlo, double whi,
                             double hlo, double hhi) {
  const bool reconstruction = options.purpose == "reconstruction";
  const double cells_w = cellsAlong(whi - wlo, fs.spacing_w_m, false);
  const double rows = reconstruction ? reconstructionRows(fs, hhi - hlo, options.overlap_h, shrink)
                                     : cellsAlong(hhi - hlo, fs.spacing_h_m, false);
  const ReconstructionColumns along(wlo, whi, fs.camera.footprint_w_m * (1.0 - shrink),
                                    fs.spacing_w_m, options.min_views);
  const double cols = reconstruction ? along.count() : cells_w;
  if (!(cols * rows <= options.max_stops)) {
    std::ostringstream os;
    os << "surface " << surface.id << " (" << whi - wlo << " x " << hhi - hlo << " m) would need "
       << cols << " x " << rows << " photo stops at " << fs.spacing_w_m << " x " << fs.spacing_h_m
       << " m spacing, more than coverage.max_stops " << options.max_stops
       << "; use a larger footprint (camera) or raise coverage.max_stops";
    throw InputError(os.str());
  }
  std::vector<double> xs;
  if (reconstruction) {
    xs = along.centres();
  } else {
    const double wc = 0.5 * (wlo + whi);
    for (int c = 0; c < static_cast<int>(cells_w); ++c)
      xs.push_back(wc + (c - 0.5 * (cells_w - 1)) * fs.spacing_w_m);
  }
  fs.cols = static_cast<int>(xs.size());
  fs.rows = static_cast<int>(rows);
  return xs;
}

/// A reconstruction's spacing along its rows [m]: footprint / m with m the largest of
/// (min_views + kEdgeMargin) / (1 − shrink) (each row alone gives every point, on the
/// plane or `shrink` of a footprint nearer the camera, min_views photos),
/// 1 / (1 − kReconstructionShare) (consecutive photos of a row share that much) and
/// the file's front overlap.
double reconstructionSpacingW(const CoverageOptions& options, double footprint_w, double shrink) {
  const double m = std::max({(options.min_views + kEdgeMargin) / (1.0 - shrink),
                             1.0 / (1.0 - kReconstructionShare), 1.0 / (1.0 - options.overlap_w)});
  return footprint_w / m;
}

/// Reconstruction: the share of a footprint's width and height that the surface's
/// points in front of its plane fall outside of. A point δ [m] nearer the camera than
/// the plane, seen from the standoff d, lies in the frustum only within (1 − δ/d) of
/// the footprint around the photo's centre, so rows (and photos along them) must
/// overlap by δ/d to keep it in min_views at their seams. δ: the
/// kReconstructionFrontQuantile of the inliers' heights above the plane (the scan's
/// noise, not one stray point; photo_check counts the points left below min_views);
/// at most kMaxReconstructionShrink; 0 without inliers.
double reconstructionShrink(const Surface& surface, double standoff) {
  if (surface.inliers.empty() || !(standoff > 0.0)) return 0.0;
  const double nn = surface.plane.normal.norm();
  if (!(nn > 0.0) || !std::isfinite(nn)) return 0.0;
  std::vector<double> front;
  front.reserve(surface.inliers.size());
  for (const Vec3& p : surface.inliers) {
    const double h = surface.plane.signedDistance(p) / nn;
    front.push_back(std::isfinite(h) ? std::max(0.0, h) : 0.0);
  }
  const auto k = static_cast<std::size_t>(
      std::floor(kReconstructionFrontQuantile * static_cast<double>(front.size() - 1)));
  std::nth_element(front.begin(), front.begin() + static_cast<std::ptrdiff_t>(k), front.end());
  return std::min(kMaxReconstructionShrink, front[k] / standoff);
}

/// Row r's stops, at the column coordinates `xs` along axis_w, on the grid centred on
/// hc across the rows in the frame about origin, whose footprints overlap the region,
/// in column order; each looks at the region (photoCentre).
std::vector<Stop> rowStops(const FlightStrategy& fs, const Surface& surface, const SurfaceFrame& f,
                           const Vec3& origin, const Region& region, const Attitude& at,
                           const std::vector<double>& xs, double hc, int r) {
  const double half_w = 0.5 * fs.camera.footprint_w_m;
  const double half_h = 0.5 * fs.camera.footprint_h_m;
  const double b = hc + (r - 0.5 * (fs.rows - 1)) * fs.spacing_h_m;
  std::vector<Stop> row;
  for (int c = 0; c < fs.cols; ++c) {
    const double a = xs[static_cast<std::size_t>(c)];
    if (!(region.overlap(rectangle(a, b, half_w, half_h)).first > kOverlapTol)) continue;
    const std::optional<Vec2> centre = photoCentre(region, fs, a, b);
    if (!centre) continue;
    Stop s;
    s.surface_id = surface.id;
    s.row = r;
    s.col = c;
    s.target = surface.plane.project(origin + centre->x() * f.axis_w + centre->y() * f.axis_h);
    s.position = s.target + fs.camera.standoff_m * f.n;
    s.yaw_deg = at.yaw;
    s.gimbal_pitch_deg = at.pitch;
    s.gimbal_ok = at.gimbal_ok;
    row.push_back(s);
  }
  return row;
}

/// Most photos added between two consecutive stops of a reconstruction (bridgeRows).
constexpr int kMaxBridgeSteps = 16;

/// Reconstruction: photos added where consecutive stops share less than
/// kReconstructionShare of their footprint (a row's last stop and the next row's
/// first, rows (1 − overlap_h) of a footprint apart), evenly on the segment between
/// their targets, as few as make every step share it; none where a step would take
/// more than kMaxBridgeSteps or an added footprint would miss the region (a jump over
/// a hole). An added stop keeps the row and column of the stop it follows.
void bridgeRows(FlightStrategy& fs, const Vec3& origin, const Region& region) {
  const double fw = fs.camera.footprint_w_m;
  const double fh = fs.camera.footprint_h_m;
  if (fs.stops.size() < 2 || !(fw > 0.0) || !(fh > 0.0)) return;
  const auto uv = [&](const Vec3& p) {
    return Vec2((p - origin).dot(fs.axis_w), (p - origin).dot(fs.axis_h));
  };
  std::vector<Stop> out;
  out.reserve(fs.stops.size());
  out.push_back(fs.stops.front());
  for (std::size_t i = 1; i < fs.stops.size(); ++i) {
    const Stop& a = fs.stops[i - 1];
    const Stop& b = fs.stops[i];
    const Vec2 d = uv(b.target) - uv(a.target);
    int steps = 1;
    while (steps <= kMaxBridgeSteps &&
           (1.0 - std::abs(d.x()) / (steps * fw)) * (1.0 - std::abs(d.y()) / (steps * fh)) <
               kReconstructionShare - 1e-9)
      ++steps;
    std::vector<Stop> added;
    for (int k = 1; steps <= kMaxBridgeSteps && k < steps; ++k) {
      Stop s = a;
      const double t = static_cast<double>(k) / steps;
      s.target = a.target + t * (b.target - a.target);
      s.position = a.position + t * (b.position - a.position);
      const Vec2 c = uv(s.target);
      if (!(region.overlap(rectangle(c.x(), c.y(), 0.5 * fw, 0.5 * fh)).first > kOverlapTol)) {
        added.clear();
        break;
      }
      added.push_back(s);
    }
    out.insert(out.end(), added.begin(), added.end());
    out.push_back(b);
  }
  for (std::size_t i = 0; i < out.size(); ++i) out[i].index = static_cast<int>(i);
  fs.stops = std::move(out);
}

/// The boustrophedon of stops over the surface's boundary (fs.cols, fs.rows set).
/// Rows are independent: a large grid's rows are found on every core (each row to
/// its own slot), then joined in order.
void placeStops(FlightStrategy& fs, const Surface& surface, const SurfaceFrame& f,
                const Vec3& origin, const Region& region, const Attitude& at,
                const std::vector<double>& xs, double hc) {
  std::vector<std::vector<Stop>> rows(static_cast<std::size_t>(fs.rows));
  const double cells = static_cast<double>(fs.rows) * static_cast<double>(fs.cols);
  parallelFor(rows.size(), cells >= kParallelCells ? hardwareThreads() : 1,
              [&](std::size_t r, std::size_t) {
                rows[r] = rowStops(fs, surface, f, origin, region, at, xs, hc, static_cast<int>(r));
              });
  bool left_to_right = true;
  for (auto& row : rows) {
    if (row.empty()) continue;
    if (!left_to_right) std::reverse(row.begin(), row.end());
    left_to_right = !left_to_right;
    for (auto& s : row) {
      s.index = static_cast<int>(fs.stops.size());
      fs.stops.push_back(s);
    }
  }
}

}  // namespace

FlightStrategy planFlightStrategy(const Surface& surface, const CoverageOptions& options) {
  options.validate();
  FlightStrategy fs;
  fs.surface_id = surface.id;
  fs.camera = solveCamera(options.camera, options.standoff_m);
  fs.spacing_w_m = fs.camera.footprint_w_m * (1.0 - options.overlap_w);
  fs.spacing_h_m = fs.camera.footprint_h_m * (1.0 - options.overlap_h);
  double shrink = 0.0;
  if (options.purpose == "reconstruction") {
    shrink = reconstructionShrink(surface, fs.camera.standoff_m);
    fs.spacing_w_m = reconstructionSpacingW(options, fs.camera.footprint_w_m, shrink);
  }

  const double nnorm = surface.plane.normal.norm();
  if (!(nnorm > 0.0) || !std::isfinite(nnorm)) return fs;
  const SurfaceFrame f = surfaceFrame(
      options.purpose != "inspection" && std::abs(surface.plane.normal.z() / nnorm) >= kHorizontalNz
          ? horizontalRowAxis(surface, surface.plane.normal / nnorm)
          : surface.axis_u,
      surface.plane.normal / nnorm);
  fs.axis_w = f.axis_w;
  fs.axis_h = f.axis_h;
  const Attitude at = stopAttitude(f, options.gimbal);
  if (surface.boundary.size() < 3 || !allFinite(surface.boundary) ||
      !surface.centroid.allFinite()) {
    return fs;
  }
  const Vec3 origin = surface.plane.project(surface.centroid);
  const Region region = regionInFrame(surface, f, origin);
  const auto [wlo, whi] = projectRange(region.outer, Vec2::UnitX());
  const auto [hlo, hhi] = projectRange(region.outer, Vec2::UnitY());
  const std::vector<double> xs = sizeGrid(fs, surface, options, shrink, wlo, whi, hlo, hhi);
  placeStops(fs, surface, f, origin, region, at, xs, 0.5 * (hlo + hhi));
  if (options.purpose == "reconstruction") bridgeRows(fs, origin, region);
  return fs;
}

double footprintShare(const FlightStrategy& fs, const Stop& a, const Stop& b) {
  const Vec3 d = b.target - a.target;
  const double fw = fs.camera.footprint_w_m;
  const double fh = fs.camera.footprint_h_m;
  if (!(fw > 0.0) || !(fh > 0.0)) return 0.0;
  return std::max(0.0, 1.0 - std::abs(d.dot(fs.axis_w)) / fw) *
         std::max(0.0, 1.0 - std::abs(d.dot(fs.axis_h)) / fh);
}

namespace {

/// addStopsFor's targets: among the short points' projections onto the plane (the
/// first in each cell of kTopUpCells × kTopUpCells per footprint is a candidate), the
/// candidate whose central kTopUpFootprintShare of a footprint holds the most points
/// still short, each holding point then one view less short, until none is short.
PointList topUpTargets(const FlightStrategy& fs, const Surface& surface, const PointList& points,
                       const std::vector<int>& missing) {
  const double fw = fs.camera.footprint_w_m, fh = fs.camera.footprint_h_m;
  using Cell = std::pair<long, long>;
  PointList targets;
  std::vector<int> short_by;
  std::map<Cell, std::vector<std::size_t>> in_cell;  // the points of each cell
  std::vector<Cell> candidates;                      // cells, in the points' order
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (missing[i] <= 0 || !points[i].allFinite()) continue;
    const Vec3 t = surface.plane.project(points[i]);
    const Cell cell{static_cast<long>(std::floor(t.dot(fs.axis_w) * kTopUpCells / fw)),
                    static_cast<long>(std::floor(t.dot(fs.axis_h) * kTopUpCells / fh))};
    auto& members = in_cell[cell];
    if (members.empty()) candidates.push_back(cell);
    members.push_back(targets.size());
    targets.push_back(t);
    short_by.push_back(missing[i]);
  }
  // A candidate is its cell's first point; it holds points within kTopUpFootprintShare
  // of a footprint about it, all in the cells within `reach` of its own.
  const long reach = static_cast<long>(std::ceil(0.5 * kTopUpFootprintShare * kTopUpCells)) + 1;
  const auto forHeld = [&](const Cell& c, const auto& visit) {
    const Vec3& centre = targets[in_cell[c].front()];
    for (long du = -reach; du <= reach; ++du) {
      for (long dv = -reach; dv <= reach; ++dv) {
        const auto it = in_cell.find({c.first + du, c.second + dv});
        if (it == in_cell.end()) continue;
        for (const std::size_t i : it->second) {
          const Vec3 d = targets[i] - centre;
          if (std::abs(d.dot(fs.axis_w)) <= 0.5 * kTopUpFootprintShare * fw &&
              std::abs(d.dot(fs.axis_h)) <= 0.5 * kTopUpFootprintShare * fh)
            visit(i);
        }
      }
    }
  };
  PointList chosen;
  std::vector<char> used(candidates.size(), 0);
  while (true) {
    std::size_t best = candidates.size();
    long best_gain = 0;
    for (std::size_t c = 0; c < candidates.size(); ++c) {
      if (used[c]) continue;
      long gain = 0;
      forHeld(candidates[c], [&](std::size_t i) { gain += short_by[i] > 0 ? 1 : 0; });
      if (gain > best_gain) {
        best = c;
        best_gain = gain;
      }
    }
    if (best == candidates.size()) return chosen;
    used[best] = 1;
    forHeld(candidates[best], [&](std::size_t i) {
      if (short_by[i] > 0) --short_by[i];
    });
    chosen.push_back(targets[in_cell[candidates[best]].front()]);
  }
}

/// The stop k an added stop `s` is flown after: where the least footprint it shares
/// with stops k and k + 1 gains most on what those two share (a gap of the order is
/// filled), then the shortest detour.
std::size_t flownAfter(const FlightStrategy& fs, const Stop& s) {
  std::size_t best = 0;
  double best_share = -2.0, best_detour = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < fs.stops.size(); ++k) {
    const bool last = k + 1 == fs.stops.size();
    const double share = last ? footprintShare(fs, fs.stops[k], s) - 1.0
                              : std::min(footprintShare(fs, fs.stops[k], s),
                                         footprintShare(fs, s, fs.stops[k + 1])) -
                                    footprintShare(fs, fs.stops[k], fs.stops[k + 1]);
    const double detour = (s.target - fs.stops[k].target).norm() +
                          (last ? 0.0
                                : (fs.stops[k + 1].target - s.target).norm() -
                                      (fs.stops[k + 1].target - fs.stops[k].target).norm());
    if (share > best_share + 1e-12 ||
        (share > best_share - 1e-12 && detour < best_detour - 1e-12)) {
      best = k;
      best_share = share;
      best_detour = detour;
    }
  }
  return best;
}

}  // namespace

std::size_t addStopsFor(FlightStrategy& fs, const Surface& surface, const PointList& points,
                        const std::vector<int>& missing) {
  const double nn = surface.plane.normal.norm();
  const double standoff = fs.camera.standoff_m;
  if (fs.stops.empty() || points.size() != missing.size() || !(nn > 0.0) || !std::isfinite(nn) ||
      !(standoff > 0.0) || !(fs.camera.footprint_w_m > 0.0) || !(fs.camera.footprint_h_m > 0.0))
    return 0;
  const Vec3 n = surface.plane.normal / nn;
  const PointList chosen = topUpTargets(fs, surface, points, missing);
  std::vector<std::vector<Stop>> after(fs.stops.size());  // added stops, by the stop they follow
  for (const Vec3& target : chosen) {
    Stop s = fs.stops.front();
    s.target = target;
    s.position = target + standoff * n;
    const std::size_t k = flownAfter(fs, s);
    const Stop& before = fs.stops[k];
    s.row = before.row;
    s.col = before.col;
    s.yaw_deg = before.yaw_deg;
    s.gimbal_pitch_deg = before.gimbal_pitch_deg;
    s.gimbal_ok = before.gimbal_ok;
    after[k].push_back(s);
  }
  std::vector<Stop> out;
  out.reserve(fs.stops.size() + chosen.size());
  for (std::size_t k = 0; k < fs.stops.size(); ++k) {
    out.push_back(fs.stops[k]);
    const Vec3 from = fs.stops[k].target;  // several after one stop: nearest first
    std::stable_sort(after[k].begin(), after[k].end(), [&](const Stop& a, const Stop& b) {
      return (a.target - from).squaredNorm() < (b.target - from).squaredNorm();
    });
    out.insert(out.end(), after[k].begin(), after[k].end());
  }
  for (std::size_t i = 0; i < out.size(); ++i) out[i].index = static_cast<int>(i);
  const std::size_t before = fs.stops.size();
  fs.stops = std::move(out);
  // An added stop between rows shares less than kReconstructionShare with the stops it
  // is flown between: bridged as the rows' turns are (the planned order already is).
  const SurfaceFrame f{n, fs.axis_w, fs.axis_h, std::abs(n.z()) >= kHorizontalNz};
  const Vec3 origin = surface.plane.project(surface.centroid);
  if (surface.boundary.size() >= 3 && allFinite(surface.boundary) && origin.allFinite())
    bridgeRows(fs, origin, regionInFrame(surface, f, origin));
  return fs.stops.size() - before;
}

namespace {

/// Edges: planes at least this far from parallel and from folded flat [deg].
constexpr double kEdgeMinAngleDeg = 30.0;

/// The stretch [lo, hi] of the line p0 + t·d that `surface`'s boundary vertices within
/// `tol` of `other` reach; empty when fewer than two do.
std::optional<std::pair<double, double>> stretchNear(const Surface& surface, const Plane& other,
                                                     const Vec3& p0, const Vec3& d, double tol) {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -lo;
  int near = 0;
  for (const auto& v : surface.boundary) {
    if (!(std::abs(other.signedDistance(v)) <= tol)) continue;
    const double t = (v - p0).dot(d);
    lo = std::min(lo, t);
    hi = std::max(hi, t);
    ++near;
  }
  if (near < 2) return std::nullopt;
  return std::make_pair(lo, hi);
}

/// The convex edge of a and b, if they share one (convexEdges).
std::optional<SurfaceEdge> edgeOf(const Surface& a, const Surface& b, double tol) {
  const Vec3 na = a.plane.normal.normalized();
  const Vec3 nb = b.plane.normal.normalized();
  const double cos_max = std::cos(kEdgeMinAngleDeg * kPi / 180.0);
  if (!na.allFinite() || !nb.allFinite() || !(std::abs(na.dot(nb)) <= cos_max)) return {};
  // Convex: each centroid behind the other's plane.
  if (!(a.plane.signedDistance(b.centroid) < -tol && b.plane.signedDistance(a.centroid) < -tol))
    return {};
  // The planes' line: direction na × nb, through the point nearest the origin
  // (planes n·x = h with h = −offset).
  const Vec3 n3 = na.cross(nb);
  const double ha = -a.plane.offset / a.plane.normal.norm();
  const double hb = -b.plane.offset / b.plane.normal.norm();
  const Vec3 p0 = (ha * nb.cross(n3) + hb * n3.cross(na)) / n3.squaredNorm();
  const Vec3 d = n3.normalized();
  const Plane pa{na, -ha};
  const Plane pb{nb, -hb};
  const auto sa = stretchNear(a, pb, p0, d, tol);
  const auto sb = stretchNear(b, pa, p0, d, tol);
  if (!sa || !sb) return {};
  const double lo = std::max(sa->first, sb->first);
  const double hi = std::min(sa->second, sb->second);
  if (!(hi - lo >= tol)) return {};
  SurfaceEdge e;
  e.surface_a = a.id;
  e.surface_b = b.id;
  e.p0 = p0 + lo * d;
  e.p1 = p0 + hi * d;
  e.bisector = (na + nb).normalized();
  return e;
}

}  // namespace

std::vector<SurfaceEdge> convexEdges(const std::vector<const Surface*>& surfaces,
                                     double tolerance_m) {
  std::vector<const Surface*> sorted = surfaces;
  std::stable_sort(sorted.begin(), sorted.end(),
                   [](const Surface* x, const Surface* y) { return x->id < y->id; });
  std::vector<SurfaceEdge> edges;
  for (std::size_t i = 0; i < sorted.size(); ++i)
    for (std::size_t j = i + 1; j < sorted.size(); ++j)
      if (auto e = edgeOf(*sorted[i], *sorted[j], tolerance_m)) edges.push_back(*e);
  return edges;
}

std::vector<FlightStrategy> planEdgeLinks(const std::vector<SurfaceEdge>& edges,
                                          const CoverageOptions& options, int first_id) {
  options.validate();
  std::vector<FlightStrategy> links;
  for (std::size_t k = 0; k < edges.size(); ++k) {
    const SurfaceEdge& e = edges[k];
    FlightStrategy fs;
    fs.surface_id = first_id + static_cast<int>(k);
    fs.camera = solveCamera(options.camera, options.standoff_m);
    const Vec3 d = (e.p1 - e.p0).normalized();
    const SurfaceFrame f = surfaceFrame(d, e.bisector);
    fs.axis_w = f.axis_w;
    fs.axis_h = f.axis_h;
    // The footprint's side that lies along the edge sets the spacing.
    const bool along_w = std::abs(d.dot(f.axis_w)) >= std::abs(d.dot(f.axis_h));
    const double footprint = along_w ? fs.camera.footprint_w_m : fs.camera.footprint_h_m;
    const double spacing = footprint * (1.0 - kReconstructionShare);
    const double len = (e.p1 - e.p0).norm();
    const double cells = cellsAlong(len, spacing, true);
    const double step = edgeSpacing(len, cells, spacing);
    (along_w ? fs.spacing_w_m : fs.spacing_h_m) = step;
    (along_w ? fs.spacing_h_m : fs.spacing_w_m) = footprint;
    fs.cols = along_w ? static_cast<int>(cells) : 1;
    fs.rows = along_w ? 1 : static_cast<int>(cells);
    const Attitude at = stopAttitude(f, options.gimbal);
    for (int i = 0; i < static_cast<int>(cells); ++i) {
      Stop s;
      s.index = i;
      s.surface_id = fs.surface_id;
      (along_w ? s.col : s.row) = i;
      s.target = e.p0 + (cells > 1.0 ? kEdgeInsetM + i * step : 0.5 * len) * d;
      s.position = s.target + fs.camera.standoff_m * e.bisector;
      s.yaw_deg = at.yaw;
      s.gimbal_pitch_deg = at.pitch;
      s.gimbal_ok = at.gimbal_ok;
      fs.stops.push_back(s);
    }
    links.push_back(std::move(fs));
  }
  return links;
}

}  // namespace uavip::coverage
