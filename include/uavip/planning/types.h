#pragma once
/// \file
/// Planning's plain types (library uavip_planning_types, the way Fields2Cover keeps its
/// `types/`): the statuses, a surface's mission, the flight and the flight model, and
/// the options a config sets — data and their checks, no planner, validator or
/// collision world. io/ serialises them, view/ draws them, app's config sets them; the
/// algorithms that fill them are in mission_planner.h and flight_planner.h (stage 7,
/// §II-G). A photo stop (`coverage::Stop`) and a surface's strategy
/// (`coverage::FlightStrategy`) are coverage's plain types (stage 6, §II-F).

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "uavip/core/params.h"
#include "uavip/core/types.h"
#include "uavip/coverage/flight_strategy.h"

namespace uavip::planning {

// ---- one leg and one path

/// Outcome of one leg.
enum class PathStatus { Solved, NoPath, Timeout, InvalidStart, InvalidGoal };

/// Text of a status ("solved", "no_path", …).
const char* toString(PathStatus status);

/// Verdict on one path (path_validator.h).
struct ValidationResult {
  bool collision_free{true};
  double min_clearance_m{0.0};  ///< smallest distance from the path to any object [m] (inf if none)
  int first_violation_segment{-1};  ///< index i of segment path[i]→path[i+1], −1 if none
  /// Nearest point of the violated object (a measured point for the cloud) [m].
  Vec3 violation_point{Vec3::Zero()};
  std::string violation_object;  ///< "surface 3", "obstacle 12" or "cloud"; empty if none
  /// Distance from each segment to the nearest object [m] (one entry for a single
  /// point); a segment is collision-free when its entry is ≥ the required clearance.
  std::vector<double> segment_clearance_m;
};

// ---- one surface (mission_planner.h)

/// Outcome for a surface. `Blocked` is a result (exit 0), not an error.
enum class SurfaceStatus {
  Ok,       ///< every stop visited by a validated path
  Partial,  ///< the usable stops visited by a validated path; the skipped ones are reported
  Blocked,  ///< too many stops cannot be reached safely: no waypoints (paper: crossed planes)
  NoStops,  ///< the flight strategy produced no stop
  Failed,   ///< a leg failed or the validator rejected the path
};

/// True when the surface has a validated path to fly (Ok or Partial).
inline bool flyable(SurfaceStatus status) {
  return status == SurfaceStatus::Ok || status == SurfaceStatus::Partial;
}

/// Text of a status ("ok", "partial", "blocked", "no_stops", "failed").
const char* toString(SurfaceStatus status);

/// Why a stop cannot be used.
/// MosaicCovered: a mosaic's stop in obstacle space that no square pose reaches (its
/// photo centre slid by up to half the overlap), left out because its neighbours' footprints cover
/// its own (not infeasible: the surface's status ignores it; the reason counts it).
enum class StopProblem { None, GimbalLimit, InObstacleSpace, Unreachable, MosaicCovered };
const char* toString(StopProblem problem);

/// Options of mission planning.
struct MissionOptions {
  bool simplify{true};  ///< shortcut the raw voxel path (line of sight on the grid)
  /// Unusable stops (gimbal limit, obstacle space, unreachable) are skipped and
  /// reported while they are at most this fraction of the surface's stops (status
  /// Partial); above it the surface is Blocked. 0 = any unusable stop blocks.
  double max_skipped_fraction{0.25};
  std::optional<Vec3> start;  ///< take-off / entry point; must be free. Default: the first stop
  /// Stop repair: a stop inside the inflated obstacle space is moved to a nearby
  /// free pose that still looks at its photo centre with a clear line of sight:
  /// tilted from above, below or the sides by 15–60° at the same distance or
  /// farther out up to max_standoff_factor × the standoff (footprint and GSD grow
  /// by that factor), the least stretched photo (distance / cos tilt) first. Moved
  /// stops are counted and listed.
  bool repair_stops{true};
  double max_standoff_factor{1.25};  ///< farthest repaired stop, × standoff (GSD allowance)
  /// Repair for a mosaic (coverage.purpose mosaic, set by Config::missionOptions): square
  /// at the standoff with the photo centre slid by up to half the overlap; a stop that
  /// finds no such pose is left out when its neighbours' footprints cover its own
  /// (StopProblem::MosaicCovered), else repaired as above.
  bool mosaic_repair{false};
  /// A flyable surface whose measured coverage is below this is `partial` [0, 1].
  double min_coverage{0.95};
  coverage::GimbalLimits gimbal;  ///< pitch limits a repaired stop must respect (the camera's)
  /// Fly a leg straight when its segment crosses free voxels only, or through one
  /// point beside its midpoint when both halves do, and ask the planner only for the
  /// others (structure coverage: most legs are short hops).
  bool direct_legs{false};

  /// Throws InputError "<where>: <key> must be …, got …" for a value out of range
  /// (max_skipped_fraction and min_coverage in [0, 1], max_standoff_factor in [1, 3],
  /// a finite start, valid gimbal limits). planSurfaceMission calls it.
  void validate(const std::string& where) const;
  /// The keys of `mission:` this struct holds (core/params.h).
  static const params::Table<MissionOptions>& table();
};

/// What structure coverage (app::planStructure; coverage/structure_views.h) found and reached.
struct StructureSummary {
  int surface_id{0};               ///< id of its entry in missions (above the scene's ids)
  std::size_t points{0};           ///< structure points (the clean cloud without the ground)
  std::size_t ground_points{0};    ///< points of the clean cloud taken as ground
  std::size_t seeds{0};            ///< seed points of the candidates
  std::size_t candidates{0};       ///< candidate poses
  std::size_t free_candidates{0};  ///< kept: free, reachable, within the gimbal limits, and per
                                   ///< seed and direction the nearest such
  std::size_t imageable{0};        ///< structure points some free candidate images
  std::size_t photos{0};           ///< photos chosen
  /// A reconstruction's linking (coverage/structure_views.h): photos added to join the
  /// matching groups, and the groups left (0 = no linking asked).
  std::size_t linking_photos{0};
  std::size_t photo_groups{0};
  double standoff_m{0.0};       ///< viewing distance [m]
  double visible_range_m{0.0};  ///< rule (a)'s range [m]
  double rule_a{0.0};           ///< FC-Planner's pixel rule at the flown stops [0, 1]
  double rule_b{0.0};           ///< our rule (GSD, incidence ≤ 75°, line of sight) [0, 1]
  double prepare_s{0.0};        ///< grid components, line-of-sight index, normals' orientation [s]
  double select_s{0.0};         ///< wall time of the view selection [s]
  double order_s{0.0};          ///< ordering the photos into one open path [s]
  double legs_s{0.0};           ///< the legs between consecutive photos [s]
  double score_s{0.0};          ///< rules (a) and (b) at the flown stops [s]
};

/// A planned leg between two consecutive path points.
struct Leg {
  int from_stop{-1};  ///< −1 for the start point
  int to_stop{0};
  PathStatus status{PathStatus::NoPath};
  std::size_t raw_steps{0};
  double length_m{0.0};  ///< raw voxel path length [m]
  double seconds{0.0};
};

/// The mission of one surface.
struct SurfaceMission {
  int surface_id{0};
  /// "plane": a detected surface's rows (§II-F); "edge": a reconstruction's photos
  /// along a convex edge of two surfaces (coverage::planEdgeLinks); "structure": the photos of the
  /// whole structure (coverage/structure_views.h).
  std::string kind{"plane"};
  SurfaceStatus status{SurfaceStatus::NoStops};
  std::string reason;  ///< one sentence; empty when ok
  coverage::FlightStrategy strategy;
  std::vector<StopProblem> stop_problems;  ///< one per stop of the strategy
  std::vector<int> moved_stops;  ///< stops moved by repair (strategy.stops holds the new pose)
  /// The moved stops whose planned pose needed a pitch beyond the gimbal's limits.
  std::vector<int> gimbal_moved_stops;
  /// Share of the surface's points some flown photo images (coverage_evaluator.h),
  /// filled by the caller that knows the surface's points (app::plan).
  struct Coverage {
    bool evaluated{false};
    double fraction{0.0};
    std::size_t points{0};
    std::size_t uncovered{0};
    PointList uncovered_points;  ///< [m], for the overview
    /// Views per point and triangulation angles (coverage/multi_view.h), measured
    /// for a mosaic or reconstruction purpose only.
    bool multi_view{false};
    int views_min{0};
    int views_median{0};
    /// Reconstruction: points in fewer than coverage.min_views photos; −1 otherwise.
    long views_below_min{-1};
    double angle_min_deg{0.0};     ///< [deg]
    double angle_median_deg{0.0};  ///< [deg]
    /// Least share of its footprint a photo has in common with the next one
    /// (coverage::footprintShare) [0, 1]; 1 for fewer than two flown photos.
    double consecutive_share_min{1.0};
  } coverage;
  std::vector<Leg> legs;
  PointList raw_path;   ///< every voxel step (the paper's waypoint count) [m]
  PointList waypoints;  ///< simplified (or raw) path through every stop [m]
  std::size_t raw_waypoint_count{0};
  double raw_length_m{0.0};
  double path_length_m{0.0};
  ValidationResult validation;
  double seconds{0.0};  ///< wall time of stage 7 for this surface
};

// ---- the flight over every chosen surface (flight_planner.h)

/// Time model of a small inspection quadrotor. Defaults: a 20 min battery with a
/// quarter kept in reserve, 3 m/s cruise near the structure, 2 m/s climb, 1.5 m/s
/// descent, 2 s hover per photo and 1 s to turn and settle the gimbal.
struct FlightModel {
  double cruise_speed_m_s{3.0};   ///< horizontal speed [m/s]
  double climb_speed_m_s{2.0};    ///< vertical speed up [m/s]
  double descent_speed_m_s{1.5};  ///< vertical speed down [m/s]
  double hover_s{2.0};            ///< hover per photo [s]
  double settle_s{1.0};           ///< turn to the stop's yaw and settle the gimbal [s]
  double endurance_s{1200.0};     ///< battery endurance [s]
  double reserve{0.25};           ///< share of the endurance kept for landing and wind [0, 1)

  /// Flight time of one straight segment [s]: horizontal and vertical speeds are
  /// limited separately, so t = max(horizontal / cruise, climb / climb speed or
  /// descent / descent speed).
  double segmentSeconds(const Vec3& a, const Vec3& b) const;
  /// Flight time along a polyline [s].
  double pathSeconds(const PointList& path) const;
  /// Time spent at one photo stop [s].
  double stopSeconds() const { return hover_s + settle_s; }
  /// Endurance minus the reserve [s].
  double usableSeconds() const { return endurance_s * (1.0 - reserve); }
  /// Throws InputError naming the bad field (prefix `where`).
  void validate(const std::string& where = "flight") const;
  /// The keys of `flight:` (core/params.h).
  static const params::Table<FlightModel>& table();
};

/// Options of the flight.
struct FlightOptions {
  /// Take-off / landing point of every sortie; must be free. Default: the mission's
  /// start, else the lowest flown photo stop (FlightPlan::home_source says which).
  std::optional<Vec3> home;
  /// The missions' start (MissionOptions::start): home when `home` is not given.
  std::optional<Vec3> start;
  FlightModel model;
  bool simplify{true};  ///< shortcut planned legs (path_simplifier.h)
  /// Also plan the naive tour (surfaces by id, each forward) to report its length;
  /// costs one planned leg per blocked straight line (seconds on a large site).
  bool compare_naive{false};
  /// Lazy re-solves with newly planned legs (each plans the new legs of its tour).
  int max_rounds{50};

  /// Throws InputError "<where>: …" for a non-finite home or start, a bad flight
  /// model (FlightModel::validate) or max_rounds < 1. planFlight calls it.
  void validate(const std::string& where = "flight") const;
};

/// A photo stop in a sortie.
struct FlightStop {
  int surface_id{0};
  int stop{0};              ///< index in the surface's strategy.stops
  std::size_t waypoint{0};  ///< index in the sortie's waypoints
};

/// One battery: home → stops → home, validated as one path.
struct Sortie {
  PointList waypoints;            ///< [m]; first and last are home
  std::vector<FlightStop> stops;  ///< in flight order
  double length_m{0.0};
  double duration_s{0.0};  ///< flight + hover + settle [s] (sortieSeconds)
  ValidationResult validation;
};

/// A sortie's time by the flight model [s]: its waypoints flown (FlightModel::pathSeconds)
/// plus hover and settle at each photo stop; the motion of fleet_types.h ends then too.
double sortieSeconds(const Sortie& sortie, const FlightModel& model);

/// A surface in the tour.
struct SurfaceVisit {
  int surface_id{0};
  bool reversed{false};  ///< flown from its last stop to its first
};

/// A surface left out of the flight, and why.
struct ExcludedSurface {
  int surface_id{0};
  std::string reason;
};

/// The flight over the chosen surfaces.
struct FlightPlan {
  enum class Status { Ok, Empty, Failed };
  Status status{Status::Empty};
  std::string reason;  ///< one sentence; empty when ok
  Vec3 home{Vec3::Zero()};
  /// "mission.home", "mission.start" or "lowest photo stop (surface S, stop K)".
  std::string home_source;
  std::vector<SurfaceVisit> order;
  std::vector<ExcludedSurface> excluded;
  double tour_length_m{0.0};   ///< one tour home → every surface → home [m]
  double inner_length_m{0.0};  ///< of which flown along the surfaces' own paths [m]
  /// Surfaces by id, each forward, same legs [m]; 0 unless compare_naive.
  double naive_length_m{0.0};
  double lower_bound_m{0.0};  ///< no tour is shorter (tour.h, tourLowerBound) [m]
  /// The order is optimal for the planned leg lengths (Held–Karp, converged).
  bool exact_order{false};
  std::size_t planned_legs{0};   ///< connecting legs the planner was asked for
  double order_seconds{0.0};     ///< wall time of ordering (solves + leg planning) [s]
  double validate_seconds{0.0};  ///< wall time of validating the sorties [s]
  double length_m{0.0};          ///< all sorties [m]
  double duration_s{0.0};        ///< all sorties [s]
  std::vector<Sortie> sorties;
  double seconds{0.0};  ///< wall time of the whole step [s]
};

const char* toString(FlightPlan::Status status);

}  // namespace uavip::planning
