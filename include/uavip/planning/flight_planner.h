#pragma once
/// \file
/// One flight for the whole structure: the surfaces' missions (mission_planner.h)
/// ordered into a tour from home and back, every connecting leg planned on the
/// shared grid, the tour split into battery sorties, each validated as one path.
///
/// Order (the paper's follow-up: a travelling-salesman order on A* distances):
/// each flyable surface keeps its boustrophedon rows and is flown forward or
/// reversed (entry at its first or its last stop); the order and directions solve a
/// generalised TSP (planning/tour.h). Leg costs are lengths [m]: the straight line
/// when it is free on the grid, else the planner's simplified path, planned lazily —
/// the solver first sees the straight-line length as a lower bound, the legs its
/// tour uses are planned, and it solves again until every leg of its tour is exact.
///
/// Sorties: the ordered stops are cut greedily so that each sortie, home → first
/// stop → … → last stop → home, lasts at most the usable endurance of the flight
/// model (FlightModel), counting flight time, hover and settle time per photo.
///
/// Validation: every segment of every sortie has the validator's clearance. A
/// segment of a surface's own path keeps the clearance its surface's validation
/// measured (same validator, same segment); connecting, outbound and return legs are
/// validated here.

#include <optional>
#include <string>
#include <vector>

#include "uavip/core/types.h"
#include "uavip/planning/mission_planner.h"
#include "uavip/planning/path_validator.h"
#include "uavip/planning/planner.h"
#include "uavip/world/voxel_grid.h"

namespace uavip::planning {

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
};

/// Options of the flight.
struct FlightOptions {
  /// Take-off / landing point of every sortie; must be free. Default: the mission's
  /// start, else the lowest flown photo stop (FlightPlan::home_source says which).
  std::optional<Vec3> home;
  std::optional<Vec3>
      start;  ///< the missions' start (MissionOptions::start): home when `home` is not given
  FlightModel model;
  bool simplify{true};  ///< shortcut planned legs (path_simplifier.h)
  /// Also plan the naive tour (surfaces by id, each forward) to report its length;
  /// costs one planned leg per blocked straight line (seconds on a large site).
  bool compare_naive{false};
  int max_rounds{
      50};  ///< lazy re-solves with newly planned legs (each plans the new legs of its tour)

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
  double duration_s{0.0};  ///< flight + hover + settle [s]
  ValidationResult validation;
};

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
  std::string
      home_source;  ///< "mission.home", "mission.start" or "lowest photo stop (surface S, stop K)"
  std::vector<SurfaceVisit> order;
  std::vector<ExcludedSurface> excluded;
  double tour_length_m{0.0};   ///< one tour home → every surface → home [m]
  double inner_length_m{0.0};  ///< of which flown along the surfaces' own paths [m]
  double naive_length_m{
      0.0};  ///< surfaces by id, each forward, same legs [m]; 0 unless compare_naive
  double lower_bound_m{0.0};  ///< no tour is shorter (tour.h, tourLowerBound) [m]
  bool exact_order{
      false};  ///< the order is optimal for the planned leg lengths (Held–Karp, converged)
  std::size_t planned_legs{0};   ///< connecting legs the planner was asked for
  double order_seconds{0.0};     ///< wall time of ordering (solves + leg planning) [s]
  double validate_seconds{0.0};  ///< wall time of validating the sorties [s]
  double length_m{0.0};          ///< all sorties [m]
  double duration_s{0.0};        ///< all sorties [s]
  std::vector<Sortie> sorties;
  double seconds{0.0};  ///< wall time of the whole step [s]
};

const char* toString(FlightPlan::Status status);

/// Orders, connects, splits and validates. Throws InputError when options.home is
/// given and not free. Surfaces whose mission is not flyable, or that home cannot
/// reach, are listed in `excluded`. Status Failed when a leg cannot be planned, a
/// stop cannot be flown within one battery, or a sortie fails validation (reason
/// names the sortie and segment).
FlightPlan planFlight(const std::vector<SurfaceMission>& missions, const world::VoxelGrid& grid,
                      const PathValidator& validator, Planner& planner,
                      const FlightOptions& options);

}  // namespace uavip::planning
