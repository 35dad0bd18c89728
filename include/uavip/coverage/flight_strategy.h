#pragma once
/// \file
/// Stage 6 (paper §II-F): photo stops over a surface. Spacing = footprint ×
/// (1 − overlap) on each axis; a grid aligned with the surface's in-plane axes,
/// centred on the surface's extent, one stop per cell whose footprint meets the
/// boundary polygon minus its holes (by area); its photo centre lies on the surface (the
/// cell centre, or the nearest point of the surface to what the cell holds: no photo of
/// air beside a concave outline or in a window); each stop offset by the standoff
/// along the outward normal, ordered boustrophedon, with yaw and gimbal pitch for a
/// 2-DOF gimbal. A reconstruction (issue 46) keeps the rows but spaces a row's photos
/// so that the row alone puts every point in min_views of them (denser at the row's
/// ends) and adds photos between rows so that consecutive photos share
/// kReconstructionShare of their footprint.

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "uavip/core/params.h"
#include "uavip/core/types.h"
#include "uavip/coverage/camera.h"

namespace uavip::coverage {

/// Pitch limits of the 2-DOF (yaw by the UAV, pitch by the gimbal) camera mount.
struct GimbalLimits {
  double pitch_min_deg{-90.0};  ///< most downward pitch [deg] (−90 = straight down)
  double pitch_max_deg{90.0};   ///< most upward pitch [deg] (+90 = straight up)
};

/// Options of stage 6.
struct CoverageOptions {
  Camera camera;
  double overlap_w{0.2};  ///< overlap between neighbouring photos along the image width [0, 1)
  double overlap_h{0.2};  ///< overlap along the image height [0, 1)
  double standoff_m{
      1.5};  ///< distance from the surface when the camera gives a footprint directly [m]
  GimbalLimits gimbal;
  /// Most photo stops one surface may get (the footprint grid's cells, counted
  /// before any stop is made); a tiny footprint on a large surface is refused.
  double max_stops{200000};
  /// "surfaces": the paper's rows plane by plane (§II-F); "structure": one view
  /// selection over the whole structure (structure_views.h).
  std::string mode{"surfaces"};
  /// Structure mode: points below this height are ground, not structure, and no
  /// photo is taken below it plus the UAV's clearance [m]; given, it alone decides
  /// (level surfaces are not taken as ground); unset = the level surfaces at the
  /// site's lowest level.
  std::optional<double> ground_z_m;
  /// Structure mode: share of the imageable structure points the photos must image, (0, 1].
  double structure_target{0.99};
  /// What the photos are for: "inspection" (the paper's rows at `overlap`),
  /// "mosaic" (rows the app gives 0.6 / 0.3 overlap unless the file sets it) or
  /// "reconstruction" (rows dense enough that every point is in min_views
  /// footprints and consecutive photos share >= kReconstructionShare of theirs; the
  /// rows overlap by at least what the surface's points in front of its plane need,
  /// and by `overlap` when the file sets it).
  std::string purpose{"inspection"};
  /// Reconstruction: photos that must image every surface point.
  int min_views{3};
  /// Reconstruction: the largest angle between two rays to a point, at least [deg].
  double min_triangulation_deg{5.0};

  /// Throws InputError naming the bad field (prefix `where`).
  void validate(const std::string& where = "coverage") const;
  /// The keys of the `coverage:` section (core/params.h); camera is its own section.
  static const params::Table<CoverageOptions>& table();
};

/// Share of its footprint a photo of a reconstruction plan shares with the next one.
constexpr double kReconstructionShare = 0.6;
/// Overlaps of a mosaic when the file sets none (front = along the image width, side).
constexpr double kMosaicOverlapW = 0.6;
constexpr double kMosaicOverlapH = 0.3;
/// Overlap of a reconstruction when the file sets none: its rows then overlap by what
/// the surface's points in front of the plane need (planFlightStrategy).
constexpr double kReconstructionOverlap = 0.0;

/// One photo stop.
struct Stop {
  int index{0};  ///< position in the flight order
  int surface_id{0};
  int row{0}, col{0};            ///< cell of the footprint grid (col along the image width axis)
  Vec3 target{Vec3::Zero()};     ///< centre of the photo on the surface plane [m]
  Vec3 position{Vec3::Zero()};   ///< UAV position = target + standoff·normal [m]
  double yaw_deg{0.0};           ///< UAV heading, counter-clockwise from +x (east) [deg]
  double gimbal_pitch_deg{0.0};  ///< camera pitch, up positive, 0 = horizontal [deg]
  bool gimbal_ok{true};          ///< false when the pitch is outside the gimbal limits
};

/// The flight strategy of one surface.
struct FlightStrategy {
  int surface_id{0};
  CameraGeometry camera;
  Vec3 axis_w{Vec3::UnitX()};  ///< in-plane direction of the image width (horizontal for
                               ///< non-horizontal surfaces)
  Vec3 axis_h{Vec3::UnitY()};  ///< in-plane direction of the image height
  double spacing_w_m{0.0};     ///< footprint_w·(1 − overlap_w); a reconstruction's
                               ///< inner spacing along its rows [m]
  double spacing_h_m{0.0};     ///< footprint_h·(1 − overlap_h) [m]
  int cols{0}, rows{0};        ///< grid size before removing cells off the surface
  std::vector<Stop>
      stops;  ///< boustrophedon order: rows along axis_h, alternating direction along axis_w
};

/// Share of the footprint two photos of one planar surface's rows have in common:
/// (1 − |Δw|/footprint_w)·(1 − |Δh|/footprint_h), each factor clamped at 0, Δ their
/// targets' offset along the strategy's axes [0, 1].
double footprintShare(const FlightStrategy& fs, const Stop& a, const Stop& b);

/// Reconstruction's top-up (issue 46): photos for the `points` of `surface` that the
/// planned flight images too few times, `missing[i]` views short (a stop the obstacle
/// repair tilted or moved images less than its nominal footprint; a centre moved off a
/// hole's air leaves a gap). Greedy cover: among the points' projections (one candidate
/// per eighth of a footprint), the target whose central 0.8 of a footprint holds the
/// most points still short gets a stop, square to the plane at the standoff, until none
/// is short. Each is flown right after the stop k where the least footprint it shares
/// with stop k and stop k + 1 (footprintShare) gains most on what those two share (it
/// fills a gap of the order; then the shortest detour), nearest to stop k first, with
/// stop k's attitude, row and column; where an added stop and a stop it is flown beside
/// share less than kReconstructionShare, photos between them bridge the step as between
/// rows. Returns how many stops were added (bridges included).
std::size_t addStopsFor(FlightStrategy& fs, const Surface& surface, const PointList& points,
                        const std::vector<int>& missing);

/// Plans the photo stops of one surface. Cells: n = max(⌈extent/spacing⌉, 1) per
/// axis, grid centred on the boundary's extent (a reconstruction's columns: edge to
/// edge of the extent, min_views photos within half a footprint of each edge). A
/// surface with < 3 boundary vertices gives no stops. Throws InputError, naming the
/// surface, the count and coverage.max_stops, when the grid would have more cells
/// than max_stops.
FlightStrategy planFlightStrategy(const Surface& surface, const CoverageOptions& options);

/// A convex edge where two surfaces meet (the side faces of a box, a face and its roof):
/// the segment [p0, p1] of the planes' line that both boundaries reach.
struct SurfaceEdge {
  int surface_a{0}, surface_b{0};
  Vec3 p0{Vec3::Zero()}, p1{Vec3::Zero()};  ///< ends of the shared edge [m]
  Vec3 bisector{Vec3::UnitX()};  ///< unit, normalize(n_a + n_b): into free space at the edge
};

/// The convex edges between `surfaces`: two planes 30°–150° apart, whose boundaries
/// both have vertices within `tolerance_m` of the other plane along a common stretch of
/// their line (the edge), each surface's centroid behind the other's plane. Edges
/// shorter than `tolerance_m` are left out. Order: by (surface_a, surface_b).
std::vector<SurfaceEdge> convexEdges(const std::vector<const Surface*>& surfaces,
                                     double tolerance_m);

/// Reconstruction across surface edges (issue 46): photos square to each face meet a
/// convex edge 90° apart, which SIFT does not match, so a model stops at the edge.
/// One column of photos per edge, on its bisector at the standoff, aimed at the edge
/// (45° incidence on both faces of a right angle), edge to edge along it at
/// (1 − kReconstructionShare) of the footprint, ties one face's model to the next's.
/// Each edge is a FlightStrategy of its own with id `first_id` + its index in `edges`
/// (rows along the edge, one column; axis_w, axis_h the image axes).
std::vector<FlightStrategy> planEdgeLinks(const std::vector<SurfaceEdge>& edges,
                                          const CoverageOptions& options, int first_id);

}  // namespace uavip::coverage
