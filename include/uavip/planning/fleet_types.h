#pragma once
/// \file
/// A fleet's plain types (library uavip_planning_types): the `fleet:` options, the
/// fleet's plan (one flight per UAV with its schedule), and the motion model with the
/// separation check that both the planner (planning/fleet.h) and `uavip validate` use.
///
/// Motion: a sortie that takes off at time t0 [s] stays at its first waypoint (home)
/// for half the take-off/landing time, then flies each segment in a straight line at
/// constant speed for FlightModel::segmentSeconds, hovering FlightModel::stopSeconds at
/// each photo stop's waypoint before leaving it, and stays at its last waypoint (home)
/// for the other half. Before its first take-off, between sorties (battery swap, waits)
/// and after its last landing a UAV is on the ground and takes no airspace.
///
/// Separation with slack: each UAV may run up to `slack_s` behind its schedule at any
/// instant. The check is conservative: a pair of pieces of two UAVs whose time windows
/// [t0, t1 + slack] overlap must keep `separation_m` between the segments they sweep
/// (segment–segment distance), whatever the delays.

#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "uavip/core/params.h"
#include "uavip/core/types.h"
#include "uavip/planning/types.h"

namespace uavip::planning {

/// Options of the fleet, section `fleet:`. The keys are in `table()`.
struct FleetOptions {
  int uavs{1};  ///< UAVs flying the site at once; 1 = today's single flight
  /// Take-off / landing point of each UAV [m]; empty = K points spaced beside the home
  /// the single-UAV flight chooses. Given: one per UAV.
  PointList homes;
  double separation_m{5.0};        ///< least distance between two UAVs at any instant [m]
  double launch_interval_s{30.0};  ///< UAV i takes off i × this after UAV 0 [s]
  double slack_s{60.0};            ///< delay any UAV may run behind its schedule [s]
  double takeoff_landing_s{0.0};   ///< take-off plus landing, per sortie, at home [s]
  double battery_swap_s{0.0};      ///< on the ground between two sorties of a UAV [s]

  /// True when a fleet block is planned: more than one UAV, or homes given.
  bool active() const { return uavs > 1 || !homes.empty(); }
  /// Throws InputError "<where>: <key> …": the table's bounds, homes not one per UAV,
  /// two homes closer than separation_m.
  void validate(const std::string& where = "fleet") const;
  /// The keys of `fleet:` (core/params.h).
  static const params::Table<FleetOptions>& table();
  /// The key of a field of this struct (e.g. the separation's), for messages and files.
  template <typename T>
  static const std::string& keyOf(T FleetOptions::*field) {
    static const FleetOptions defaults;
    const auto* row = table().find(defaults, &(defaults.*field));
    if (row == nullptr) throw std::logic_error("FleetOptions::keyOf: a field no table lists");
    return row->key;
  }
};

/// One piece of a UAV's motion: from `a` at `t0` to `b` at `t1` at constant velocity
/// (a == b: staying put) [m, s].
struct MotionPiece {
  Vec3 a{Vec3::Zero()};
  Vec3 b{Vec3::Zero()};
  double t0{0.0};
  double t1{0.0};
  int sortie{0};  ///< index of the UAV's sortie it belongs to
};

/// The motion of one sortie that takes off at `start_s` (see the file comment):
/// `stop_waypoints` holds the waypoint index of each photo stop (a waypoint listed
/// twice hovers twice). Pieces in time order, contiguous.
std::vector<MotionPiece> sortieMotion(const PointList& waypoints,
                                      const std::vector<std::size_t>& stop_waypoints,
                                      const FlightModel& model, double takeoff_landing_s,
                                      double start_s, int sortie);

/// Closest approach of two points moving linearly over their pieces, while both are
/// in the air at once (the overlap of [t0, t1]); nullopt when the windows do not
/// overlap. The squared distance is a quadratic in t: its minimum is exact.
struct Approach {
  double distance_m{0.0};
  double time_s{0.0};
};
std::optional<Approach> closestApproach(const MotionPiece& p, const MotionPiece& q);

/// A pair of UAVs closer than the separation.
struct FleetConflict {
  int uav_a{0};  ///< index (0-based) of the first UAV
  int uav_b{0};
  int sortie_a{0};  ///< index (0-based) of its sortie
  int sortie_b{0};
  std::size_t piece_a{0};  ///< index of the piece in the UAV's motion
  std::size_t piece_b{0};
  double time_s{0.0};      ///< start of the overlap of their widened windows [s]
  double distance_m{0.0};  ///< segment–segment distance of the two pieces [m]
};

/// Result of the separation check.
struct SeparationCheck {
  std::optional<FleetConflict> conflict;  ///< the earliest conflict, if any
  /// Least segment–segment distance over every pair of pieces whose widened windows
  /// overlap (inf when none) [m].
  double swept_min_m{0.0};
  /// Least distance between two UAVs on the nominal schedule (no delay; exact
  /// closest approach) [m], inf when never airborne together.
  double nominal_min_m{0.0};
  double nominal_time_s{0.0};  ///< when it happens [s]
  std::size_t pairs{0};        ///< piece pairs measured
};

/// Checks every pair of UAVs (their motions in time order, as sortieMotion gives
/// them): the conservative rule of the file comment with `slack_s`, and the exact
/// nominal closest approach.
SeparationCheck checkSeparation(const std::vector<std::vector<MotionPiece>>& uavs,
                                double separation_m, double slack_s);

/// The conflict checkSeparation reports (the same one), without its least distances:
/// for a planner that checks many schedules, it stops at the earliest conflict found.
std::optional<FleetConflict> firstConflict(const std::vector<std::vector<MotionPiece>>& uavs,
                                           double separation_m, double slack_s);

/// One UAV of the fleet: its flight (sorties from its home) and when each sortie
/// takes off.
struct FleetUav {
  Vec3 home{Vec3::Zero()};
  std::string home_source;             ///< the fleet's homes key, or how the default was placed
  FlightPlan flight;                   ///< its own flight (planning/flight_planner.h) from `home`
  std::vector<double> sortie_start_s;  ///< take-off of each sortie [s] from the fleet's t = 0
  double wait_s{0.0};                  ///< waits the schedule added before its sorties [s]
  double end_s{0.0};                   ///< landing of its last sortie [s] (0 when idle)
  std::size_t stops{0};                ///< photo stops it flies
};

/// The fleet's plan.
struct FleetPlan {
  enum class Status { Ok, Failed };
  Status status{Status::Ok};
  std::string reason;  ///< one sentence; empty when ok
  FleetOptions options;
  FlightModel model;
  std::vector<FleetUav> uavs;
  double makespan_s{0.0};         ///< landing of the last UAV [s]
  double single_uav_s{0.0};       ///< the single-UAV flight, sorties and their overheads [s]
  double lower_bound_s{0.0};      ///< no schedule of this fleet lands sooner [s]
  double work_s{0.0};             ///< the bound's total work: photos and least approach flights [s]
  std::size_t jobs{0};            ///< surfaces and surface parts shared out
  std::size_t split_surfaces{0};  ///< surfaces shared between UAVs
  std::size_t waits{0};           ///< waits added to resolve conflicts
  bool fallback_single{false};    ///< the fleet was slower: UAV 1 flies everything
  std::size_t candidates{0};      ///< assignments flown and scheduled (planning/fleet.h)
  std::string assignment;         ///< the one kept: "min-max", "next best N", "slabs along …"
  SeparationCheck separation;     ///< of the final schedule
  double seconds{0.0};            ///< wall time [s]
};

const char* toString(FleetPlan::Status status);

/// Every UAV's motion (sortieMotion over its sorties at their start times).
std::vector<std::vector<MotionPiece>> fleetMotion(const FleetPlan& plan);

}  // namespace uavip::planning
