#include "uavip/planning/fleet.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <numeric>
#include <set>
#include <string>
#include <tuple>

#include "uavip/core/error.h"
#include "uavip/core/geometry.h"
#include "uavip/core/math.h"
#include "uavip/core/neighbour_index.h"
#include "uavip/core/stopwatch.h"
#include "uavip/core/text.h"
#include "uavip/planning/tour.h"

namespace uavip::planning {

namespace {

/// Assignments tried one by one when there are at most this many (3 UAVs and 8 jobs,
/// 2 and 12): each UAV's estimate is cached by its set of jobs, so a UAV solves at most
/// 2^jobs tours.
constexpr double kExhaustiveAssignments = 6561.0;

/// A flown stop of a mission and its waypoint index.
struct PathStop {
  int stop{0};
  std::size_t waypoint{0};
};

/// The mission's flown stops in flight order with their waypoints (as the flight
/// planner cuts a surface's path); empty when a stop is not on the path.
std::vector<PathStop> flownStops(const SurfaceMission& m) {
  std::vector<PathStop> out;
  std::size_t w = 0;
  for (std::size_t k = 0; k < m.strategy.stops.size(); ++k) {
    if (k < m.stop_problems.size() && m.stop_problems[k] != StopProblem::None) continue;
    const Vec3& p = m.strategy.stops[k].position;
    while (w < m.waypoints.size() && m.waypoints[w] != p) ++w;
    if (w == m.waypoints.size()) return {};
    out.push_back({static_cast<int>(k), w});
  }
  return out;
}

/// One job: a surface, or a part of consecutive flown stops of one. The surface's mission
/// (thousands of stops on a large surface) is shared by its parts and by every candidate's
/// copy of the job; a part's own mission is made only when it is flown (partMission).
struct Job {
  std::shared_ptr<const SurfaceMission> surface;  ///< the whole surface's mission
  std::size_t k0{0};                              ///< its flown stops: [k0, k1) of
  std::size_t k1{0};                              ///< flownStops(*surface)
  std::size_t stops{0};
  Vec3 first{Vec3::Zero()};     ///< first flown stop [m]
  Vec3 last{Vec3::Zero()};      ///< last flown stop [m]
  Vec3 centroid{Vec3::Zero()};  ///< of its stops [m]
  double inner_s{0.0};          ///< along its path with the photos [s]
  bool part{false};             ///< a part of a surface
};

/// The job of stops [k0, k1) of `path` (flown stops of `surface`).
Job makeJob(const std::shared_ptr<const SurfaceMission>& surface, const std::vector<PathStop>& path,
            std::size_t k0, std::size_t k1, const FlightModel& model) {
  Job j;
  j.surface = surface;
  j.k0 = k0;
  j.k1 = k1;
  j.part = k1 - k0 < path.size();
  const std::size_t w0 = path[k0].waypoint;
  const std::size_t w1 = path[k1 - 1].waypoint;
  const auto& wp = surface->waypoints;
  const PointList own(wp.begin() + static_cast<std::ptrdiff_t>(w0),
                      wp.begin() + static_cast<std::ptrdiff_t>(w1 + 1));
  j.stops = k1 - k0;
  j.first = wp[w0];
  j.last = wp[w1];
  for (std::size_t k = k0; k < k1; ++k) j.centroid += wp[path[k].waypoint];
  j.centroid /= static_cast<double>(j.stops);
  j.inner_s = model.pathSeconds(own) + static_cast<double>(j.stops) * model.stopSeconds();
  return j;
}

/// The mission a job flies: its surface's, the stops outside the job marked Unreachable,
/// the path cut from its first flown stop to its last.
SurfaceMission partMission(const Job& j) {
  const SurfaceMission& m = *j.surface;
  const auto path = flownStops(m);
  SurfaceMission out = m;
  for (std::size_t k = 0; k < path.size(); ++k) {
    if (k < j.k0 || k >= j.k1)
      out.stop_problems[static_cast<std::size_t>(path[k].stop)] = StopProblem::Unreachable;
  }
  const std::size_t w0 = path[j.k0].waypoint;
  const std::size_t w1 = path[j.k1 - 1].waypoint;
  const auto& wp = m.waypoints;
  out.waypoints.assign(wp.begin() + static_cast<std::ptrdiff_t>(w0),
                       wp.begin() + static_cast<std::ptrdiff_t>(w1 + 1));
  const auto& clear = m.validation.segment_clearance_m;
  if (clear.size() + 1 == wp.size()) {
    out.validation.segment_clearance_m.assign(clear.begin() + static_cast<std::ptrdiff_t>(w0),
                                              clear.begin() + static_cast<std::ptrdiff_t>(w1));
  }
  out.path_length_m = polylineLength(out.waypoints);
  return out;
}

/// Estimated time of one UAV flying `jobs` from `home` (the file comment of fleet.h) [s].
double estimateSeconds(const std::vector<const Job*>& jobs, const Vec3& home,
                       const FlightModel& model, const FleetOptions& fleet) {
  if (jobs.empty()) return 0.0;
  PointList points{home};
  std::vector<TourCluster> clusters(1);
  clusters[0].variants.push_back({0, 0, 0.0});
  double radius = 0.0;
  for (const Job* j : jobs) {
    const int a = static_cast<int>(points.size());
    points.push_back(j->first);
    points.push_back(j->last);
    TourCluster c;
    c.variants.push_back({a, a + 1, j->inner_s});
    c.variants.push_back({a + 1, a, j->inner_s});
    clusters.push_back(c);
    radius += model.segmentSeconds(home, j->centroid) + model.segmentSeconds(j->centroid, home);
  }
  radius /= static_cast<double>(jobs.size());
  TourOptions options;
  options.exact_max_clusters = 7;
  options.max_passes = 10;
  const Tour tour = solveTour(
      clusters, [&](int a, int b) { return model.segmentSeconds(points[a], points[b]); }, options);
  const double usable = model.usableSeconds();
  double total = tour.cost;
  double sorties = std::ceil(total / usable);
  for (int i = 0; i < 2; ++i) {
    total = tour.cost + (sorties - 1.0) * radius;
    sorties = std::max(1.0, std::ceil(total / usable));
  }
  return total + sorties * fleet.takeoff_landing_s + (sorties - 1.0) * fleet.battery_swap_s;
}

/// The largest UAV time of an assignment.
double makespanOf(const std::vector<double>& load) {
  return load.empty() ? 0.0 : *std::max_element(load.begin(), load.end());
}

}  // namespace

namespace {

/// Every assignment of n jobs to `uavs` UAVs (uavs^n of them): the least makespan.
std::vector<int> exhaustiveMinMax(
    int uavs, std::size_t n,
    const std::function<double(int uav, const std::vector<int>& jobs)>& cost) {
  std::vector<int> owner(n, 0);
  std::vector<int> best = owner;
  double best_makespan = kInf;
  for (;;) {
    std::vector<std::vector<int>> sets(static_cast<std::size_t>(uavs));
    for (std::size_t j = 0; j < n; ++j)
      sets[static_cast<std::size_t>(owner[j])].push_back(static_cast<int>(j));
    double makespan = 0.0;
    for (int u = 0; u < uavs && makespan < best_makespan; ++u)
      makespan = std::max(makespan, cost(u, sets[static_cast<std::size_t>(u)]));
    if (makespan < best_makespan - 1e-9) {
      best_makespan = makespan;
      best = owner;
    }
    std::size_t k = 0;  // next assignment (a base-uavs counter)
    while (k < n && ++owner[k] == uavs) owner[k++] = 0;
    if (k == n) return best;
  }
}

}  // namespace

std::vector<int> assignMinMax(
    int uavs, const std::vector<double>& alone,
    const std::function<double(int uav, const std::vector<int>& jobs)>& cost) {
  const std::size_t n = alone.size();
  if (std::pow(static_cast<double>(uavs), static_cast<double>(n)) <= kExhaustiveAssignments)
    return exhaustiveMinMax(uavs, n, cost);
  std::vector<int> owner(n, 0);
  std::vector<std::vector<int>> sets(static_cast<std::size_t>(uavs));
  std::vector<double> load(static_cast<std::size_t>(uavs), 0.0);
  std::vector<int> by_size(n);
  std::iota(by_size.begin(), by_size.end(), 0);
  std::stable_sort(by_size.begin(), by_size.end(), [&](int a, int b) {
    return alone[static_cast<std::size_t>(a)] > alone[static_cast<std::size_t>(b)];
  });
  for (const int j : by_size) {  // LPT: the UAV that ends earliest with it
    int best = 0;
    double best_end = kInf;
    for (int u = 0; u < uavs; ++u) {
      auto with = sets[static_cast<std::size_t>(u)];
      with.push_back(j);
      const double end = cost(u, with);
      if (end < best_end - 1e-9) {
        best_end = end;
        best = u;
      }
    }
    sets[static_cast<std::size_t>(best)].push_back(j);
    load[static_cast<std::size_t>(best)] = best_end;
  }
  // Local search: move or swap a job of the latest UAV while the makespan falls.
  for (int round = 0; round < 200; ++round) {
    const auto top =
        static_cast<std::size_t>(std::max_element(load.begin(), load.end()) - load.begin());
    const double now = load[top];
    bool improved = false;
    for (std::size_t v = 0; v < load.size() && !improved; ++v) {
      if (v == top) continue;
      const auto& a = sets[top];
      for (std::size_t i = 0; i < a.size() && !improved; ++i) {
        // Move a[i] to v, or swap it with each job of v (k = −1: move).
        for (int k = -1; k < static_cast<int>(sets[v].size()) && !improved; ++k) {
          auto na = a;
          auto nv = sets[v];
          na.erase(na.begin() + static_cast<std::ptrdiff_t>(i));
          nv.push_back(a[i]);
          if (k >= 0) {
            na.push_back(sets[v][static_cast<std::size_t>(k)]);
            nv.erase(nv.begin() + k);
          }
          const double la = cost(static_cast<int>(top), na);
          const double lv = cost(static_cast<int>(v), nv);
          if (std::max(la, lv) < now - 1e-6) {
            sets[top] = na;
            sets[v] = nv;
            load[top] = la;
            load[v] = lv;
            improved = true;
          }
        }
      }
    }
    if (!improved) break;
  }
  for (std::size_t u = 0; u < sets.size(); ++u)
    for (const int j : sets[u]) owner[static_cast<std::size_t>(j)] = static_cast<int>(u);
  return owner;
}

double fleetHomeSpacing(const FleetOptions& fleet) {
  return std::max(1.2 * fleet.separation_m, fleet.separation_m + 1.0);
}

PointList fleetRegion(const FleetOptions& fleet, const Vec3& home) {
  if (!fleet.active()) return {};
  if (!fleet.homes.empty()) return fleet.homes;
  const double r = fleetHomeSpacing(fleet) * static_cast<double>(fleet.uavs - 1);
  return {home + Vec3(r, r, 0.0), home - Vec3(r, r, 0.0)};
}

namespace {

/// The least flight time [s] from any other stop to stop i (infinity: none), exact:
/// a flight of T seconds covers at most T × √(cruise² + vertical²) metres
/// (FlightModel::segmentSeconds), so every stop faster to reach than the nearest one
/// lies within that radius of it.
double fromNearestStop(const PointList& stops, std::size_t i, const FlightModel& model,
                       const NeighbourIndex& index, std::vector<int>& found,
                       std::vector<float>& squared) {
  int near[2];
  float near_m2[2];
  index.nearest(i, 1, 2, near, near_m2);
  const auto other = static_cast<std::size_t>(near[0]) != i ? near[0] : near[1];
  double reach = model.segmentSeconds(stops[static_cast<std::size_t>(other)], stops[i]);
  const double vertical = std::max(model.climb_speed_m_s, model.descent_speed_m_s);
  const double radius = reach * std::hypot(model.cruise_speed_m_s, vertical);
  index.within(stops[i], radius * (1.0 + 1e-6) + 1e-3, found, squared, false);
  for (const int k : found)
    if (static_cast<std::size_t>(k) != i)
      reach = std::min(reach, model.segmentSeconds(stops[static_cast<std::size_t>(k)], stops[i]));
  return reach;
}

}  // namespace

FleetBound fleetLowerBound(const PointList& stops, const PointList& homes, const FlightModel& model,
                           const FleetOptions& fleet) {
  FleetBound b;
  std::unique_ptr<NeighbourIndex> index;
  if (stops.size() > 1) index = std::make_unique<NeighbourIndex>(stops);
  std::vector<int> found;
  std::vector<float> squared;
  for (std::size_t i = 0; i < stops.size(); ++i) {
    double reach = kInf;
    double trip = kInf;
    for (const auto& h : homes) {
      reach = std::min(reach, model.segmentSeconds(h, stops[i]));
      trip = std::min(trip, model.segmentSeconds(h, stops[i]) + model.segmentSeconds(stops[i], h));
    }
    if (index) reach = std::min(reach, fromNearestStop(stops, i, model, *index, found, squared));
    b.work_s += model.stopSeconds() + reach;
    b.round_trip_s = std::max(b.round_trip_s, trip + model.stopSeconds() + fleet.takeoff_landing_s);
  }
  double shared = kInf;
  for (int k = 1; k <= fleet.uavs; ++k) {
    const double kk = static_cast<double>(k);
    shared = std::min(shared, (b.work_s + fleet.launch_interval_s * kk * (kk - 1.0) / 2.0) / kk);
  }
  b.bound_s = std::max(b.round_trip_s, stops.empty() ? 0.0 : shared);
  return b;
}

namespace {

/// A home a UAV may use: free on the grid, the validator's clearance, and in the
/// grid component of the single flight's home.
bool usableHome(const Vec3& p, const Vec3& home, const world::VoxelGrid& grid,
                const PathValidator& validator) {
  return grid.isFree(p) && grid.connected(grid.indexOf(home), grid.indexOf(p)) &&
         validator.clearance(p) >= validator.requiredClearance();
}

/// K homes beside `home` along a horizontal line (0, +s, −s, +2s, … or 0, s, 2s, …) in
/// one of 8 directions, s the larger of fleetHomeSpacing and the stops' extent along the
/// line / K (each UAV near its own part of a long structure): of the lines whose homes
/// are all usable, the one whose homes lie nearest the stops (least sum of distances to
/// the nearest stop).
std::vector<FleetUav> defaultHomes(const Vec3& home, const std::string& home_source,
                                   const PointList& stops, const world::VoxelGrid& grid,
                                   const PathValidator& validator, const FleetOptions& fleet) {
  std::vector<FleetUav> best;
  double best_score = kInf;
  for (int turn = 0; turn < 16; ++turn) {
    const double a = (turn % 8) * kPi / 8.0 + (turn >= 8 ? kPi : 0.0);
    const Vec3 u(std::cos(a), std::sin(a), 0.0);
    double lo = kInf;
    double hi = -kInf;
    for (const auto& q : stops) {
      lo = std::min(lo, q.dot(u));
      hi = std::max(hi, q.dot(u));
    }
    const double s = std::max(fleetHomeSpacing(fleet), (hi - lo) / fleet.uavs);
    const bool one_side = turn >= 8;  // then 0, s, 2s, … on one side (both ways round)
    std::vector<FleetUav> out;
    double score = 0.0;
    for (int i = 0; i < fleet.uavs; ++i) {
      const double k = one_side ? i : (i % 2 == 1 ? (i + 1) / 2 : -(i / 2));
      const Vec3 p = home + k * s * u;
      if (!usableHome(p, home, grid, validator)) break;
      double nearest = kInf;
      for (const auto& q : stops) nearest = std::min(nearest, (q - p).squaredNorm());
      score += std::sqrt(nearest);
      FleetUav uav;
      uav.home = p;
      uav.home_source = i == 0 ? home_source
                               : formatFixed(k * s, 1) + " m beside home 1 towards " +
                                     formatFixed(std::fmod(a * 180.0 / kPi + 720.0, 360.0), 1) +
                                     " deg";
      out.push_back(std::move(uav));
    }
    if (static_cast<int>(out.size()) == fleet.uavs && score < best_score - 1e-9) {
      best_score = score;
      best = std::move(out);
    }
  }
  if (!best.empty()) return best;
  throw InputError("fleet: no free place for " + std::to_string(fleet.uavs) + " homes " +
                   formatFixed(fleetHomeSpacing(fleet), 1) + " m apart beside home " +
                   formatPoint(home) + " within the planning grid; give fleet.homes");
}

/// The fleet's homes: fleet.homes checked, else the default ones.
std::vector<FleetUav> fleetHomes(const FlightPlan& single, const PointList& stops,
                                 const world::VoxelGrid& grid, const PathValidator& validator,
                                 const FleetOptions& fleet) {
  if (fleet.homes.empty())
    return defaultHomes(single.home, single.home_source, stops, grid, validator, fleet);
  std::vector<FleetUav> out;
  for (std::size_t i = 0; i < fleet.homes.size(); ++i) {
    const Vec3& p = fleet.homes[i];
    const std::string what = "fleet." + FleetOptions::keyOf(&FleetOptions::homes) + " " +
                             std::to_string(i + 1) + " " + formatPoint(p);
    const double c = grid.isFree(p) ? validator.clearance(p) : 0.0;
    if (c < validator.requiredClearance()) {
      throw InputError(what + " lies " + formatFixed(c, 2) +
                       " m from the structure (or outside the planning grid), inside the " +
                       formatFixed(validator.requiredClearance(), 2) +
                       " m the UAV keeps; move it into free space near the structure");
    }
    if (!grid.connected(grid.indexOf(single.home), grid.indexOf(p)))
      throw InputError(what + " cannot reach the structure on the planning grid; move it");
    FleetUav uav;
    uav.home = p;
    uav.home_source = "fleet." + FleetOptions::keyOf(&FleetOptions::homes);
    out.push_back(std::move(uav));
  }
  return out;
}

/// Take-off times of every sortie from the waits: launch offsets, landings, swaps.
void scheduleSorties(FleetPlan& plan, const std::vector<std::vector<double>>& wait) {
  const FleetOptions& o = plan.options;
  for (std::size_t u = 0; u < plan.uavs.size(); ++u) {
    FleetUav& uav = plan.uavs[u];
    uav.sortie_start_s.clear();
    uav.wait_s = 0.0;
    double t = static_cast<double>(u) * o.launch_interval_s;
    uav.end_s = 0.0;
    for (std::size_t s = 0; s < uav.flight.sorties.size(); ++s) {
      if (s > 0) t += o.battery_swap_s;
      t += wait[u][s];
      uav.wait_s += wait[u][s];
      uav.sortie_start_s.push_back(t);
      t += o.takeoff_landing_s + uav.flight.sorties[s].duration_s;
      uav.end_s = t;
    }
  }
  plan.makespan_s = 0.0;
  for (const auto& u : plan.uavs) plan.makespan_s = std::max(plan.makespan_s, u.end_s);
}

/// Start and end of a sortie in the schedule [s].
std::pair<double, double> sortieWindow(const FleetPlan& plan, int u, int s) {
  const FleetUav& uav = plan.uavs[static_cast<std::size_t>(u)];
  const double start = uav.sortie_start_s[static_cast<std::size_t>(s)];
  return {start, start + plan.options.takeoff_landing_s +
                     uav.flight.sorties[static_cast<std::size_t>(s)].duration_s};
}

/// The least delay of piece `q` that keeps it `separation_m` from every piece of
/// `other` (in time order) whose widened window would overlap its own [s].
double clearShift(const MotionPiece& q, const std::vector<MotionPiece>& other, double separation_m,
                  double slack_s) {
  constexpr double kEps = 1e-3;
  double shift = 0.0;
  for (const MotionPiece& p : other) {
    if (p.t1 + slack_s < q.t0 + shift) continue;
    if (p.t0 > q.t1 + shift + slack_s) break;
    if (segmentBoxesDistance(p.a, p.b, q.a, q.b) < separation_m &&
        segmentSegmentDistance(p.a, p.b, q.a, q.b) < separation_m)
      shift = p.t1 + slack_s - q.t0 + kEps;
  }
  return std::max(shift, kEps);
}

/// Waits on the ground until the separation check finds no conflict (fleet.h).
/// False when the number of waits runs out, or as soon as the makespan reaches
/// `stop_at` [s] (waits only add: that schedule cannot beat it).
bool resolveConflicts(FleetPlan& plan, double stop_at = kInf) {
  std::vector<std::vector<double>> wait;
  for (const auto& u : plan.uavs) wait.emplace_back(u.flight.sorties.size(), 0.0);
  const double slack = plan.options.slack_s;
  std::map<std::array<int, 4>, int> seen;  // conflicts per pair of sorties
  constexpr double kEps = 1e-3;
  for (int round = 0; round < 4000; ++round) {
    scheduleSorties(plan, wait);
    if (plan.makespan_s >= stop_at) return false;
    const auto motion = fleetMotion(plan);
    const auto conflict = firstConflict(motion, plan.options.separation_m, slack);
    if (!conflict) {
      plan.separation = checkSeparation(motion, plan.options.separation_m, slack);
      return true;
    }
    plan.separation = SeparationCheck{};  // the least distances only for the final schedule
    plan.separation.conflict = conflict;
    const FleetConflict& c = *conflict;
    const MotionPiece& p = motion[static_cast<std::size_t>(c.uav_a)][c.piece_a];
    const MotionPiece& q = motion[static_cast<std::size_t>(c.uav_b)][c.piece_b];
    // Least shift of a's sortie that clears p of every piece of b, or of b's for q.
    const double sep = plan.options.separation_m;
    double shift_a = clearShift(p, motion[static_cast<std::size_t>(c.uav_b)], sep, slack);
    double shift_b = clearShift(q, motion[static_cast<std::size_t>(c.uav_a)], sep, slack);
    if (++seen[{c.uav_a, c.sortie_a, c.uav_b, c.sortie_b}] > 50) {  // serialise the sorties
      const auto wa = sortieWindow(plan, c.uav_a, c.sortie_a);
      const auto wb = sortieWindow(plan, c.uav_b, c.sortie_b);
      shift_a = wb.second + slack - wa.first + kEps;
      shift_b = wa.second + slack - wb.first + kEps;
    }
    const double end_a = plan.uavs[static_cast<std::size_t>(c.uav_a)].end_s + shift_a;
    const double end_b = plan.uavs[static_cast<std::size_t>(c.uav_b)].end_s + shift_b;
    if (end_a < end_b) {
      wait[static_cast<std::size_t>(c.uav_a)][static_cast<std::size_t>(c.sortie_a)] += shift_a;
    } else {
      wait[static_cast<std::size_t>(c.uav_b)][static_cast<std::size_t>(c.sortie_b)] += shift_b;
    }
    ++plan.waits;
  }
  scheduleSorties(plan, wait);
  return false;
}

/// The earliest take-off at or after `ready` [s] of UAV u's pieces `base` (timed from
/// t = 0) that keeps clear, by the separation and slack, of every piece placed for the
/// other UAVs; ≥ stop_at when none is found before it.
double earliestTakeoff(double ready, std::size_t u, const std::vector<MotionPiece>& base,
                       const std::vector<std::vector<MotionPiece>>& placed, const FleetOptions& o,
                       double stop_at) {
  constexpr double kEps = 1e-3;
  if (base.empty()) return ready;
  // The sortie's bounding box: another UAV's piece that far from it meets none of its pieces.
  Vec3 lo = base.front().a;
  Vec3 hi = lo;
  for (const MotionPiece& q : base) {
    lo = lo.cwiseMin(q.a).cwiseMin(q.b);
    hi = hi.cwiseMax(q.a).cwiseMax(q.b);
  }
  std::vector<const MotionPiece*> near;  // of one other UAV, in time order
  double t = ready;
  for (bool moved = true; moved && t < stop_at;) {
    moved = false;
    for (std::size_t v = 0; v < placed.size() && !moved; ++v) {
      if (v == u) continue;
      const std::vector<MotionPiece>& other = placed[v];  // in time order
      // Its pieces whose widened windows overlap the sortie's and whose boxes come
      // within the separation of the sortie's box.
      near.clear();
      const double s_t0 = base.front().t0 + t;
      const double s_t1 = base.back().t1 + t;
      auto it = std::partition_point(other.begin(), other.end(),
                                     [&](const MotionPiece& p) { return p.t1 + o.slack_s < s_t0; });
      for (; it != other.end() && it->t0 <= s_t1 + o.slack_s; ++it)
        if (segmentBoxesDistance(it->a, it->b, lo, hi) < o.separation_m) near.push_back(&*it);
      if (near.empty()) continue;
      for (const MotionPiece& q0 : base) {
        const double q_t0 = q0.t0 + t;
        const double q_t1 = q0.t1 + t;
        // The pieces whose widened windows overlap q's: from the first that ends no
        // earlier than q_t0 − slack to the last that starts by q_t1 + slack.
        auto p_it = std::partition_point(near.begin(), near.end(), [&](const MotionPiece* p) {
          return p->t1 + o.slack_s < q_t0;
        });
        for (; p_it != near.end() && (*p_it)->t0 <= q_t1 + o.slack_s; ++p_it) {
          const MotionPiece& p = **p_it;
          if (segmentBoxesDistance(p.a, p.b, q0.a, q0.b) >= o.separation_m ||
              segmentSegmentDistance(p.a, p.b, q0.a, q0.b) >= o.separation_m)
            continue;
          t += p.t1 + o.slack_s - q_t0 + kEps;  // q starts after p's widened window
          moved = true;
          break;
        }
        if (moved) break;
      }
    }
  }
  return t;
}

/// Sortie `pick` flown as the `next`-th: the sorties between move one later (and the
/// flight's order with them).
void flyNow(FlightPlan& flight, std::size_t next, std::size_t pick) {
  auto& sorties = flight.sorties;
  std::rotate(sorties.begin() + static_cast<std::ptrdiff_t>(next),
              sorties.begin() + static_cast<std::ptrdiff_t>(pick),
              sorties.begin() + static_cast<std::ptrdiff_t>(pick + 1));
  auto& order = flight.order;
  if (order.size() == sorties.size())
    std::rotate(order.begin() + static_cast<std::ptrdiff_t>(next),
                order.begin() + static_cast<std::ptrdiff_t>(pick),
                order.begin() + static_cast<std::ptrdiff_t>(pick + 1));
}

/// List scheduling (fleet.h): sorties taken in the order their UAV is ready (launch
/// offset, or the previous landing plus the battery swap), each taking off at the
/// earliest time from then on at which it keeps the separation, with the slack, from
/// every sortie already placed. Places waits, then checks the whole schedule as
/// resolveConflicts does. With `free_order` (every sortie a round trip of its own
/// job, order free) the ready UAV takes, of its sorties left, the one that can take
/// off earliest, and its sorties are reordered so. False when the check still finds
/// a conflict or the makespan reaches `stop_at`.
bool packSorties(FleetPlan& plan, double stop_at, bool free_order = false) {
  const FleetOptions& o = plan.options;
  constexpr double kEps = 1e-3;
  const std::size_t n = plan.uavs.size();
  std::vector<std::vector<double>> wait;
  for (const auto& u : plan.uavs) wait.emplace_back(u.flight.sorties.size(), 0.0);
  std::vector<std::size_t> next(n, 0);
  std::vector<double> ready(n);
  for (std::size_t u = 0; u < n; ++u) ready[u] = static_cast<double>(u) * o.launch_interval_s;
  std::vector<std::vector<MotionPiece>> placed(n);  // per UAV, in time order
  plan.waits = 0;
  for (;;) {
    std::size_t u = n;
    for (std::size_t v = 0; v < n; ++v)
      if (next[v] < plan.uavs[v].flight.sorties.size() && (u == n || ready[v] < ready[u])) u = v;
    if (u == n) break;
    auto& sorties = plan.uavs[u].flight.sorties;
    const std::size_t last = free_order ? sorties.size() : next[u] + 1;
    std::size_t pick = next[u];
    double t = kInf;
    std::vector<MotionPiece> base;
    for (std::size_t k = next[u]; k < last; ++k) {
      std::vector<std::size_t> at;
      for (const auto& st : sorties[k].stops) at.push_back(st.waypoint);
      auto pieces = sortieMotion(sorties[k].waypoints, at, plan.model, o.takeoff_landing_s, 0.0,
                                 static_cast<int>(next[u]));
      const double tk = earliestTakeoff(ready[u], u, pieces, placed, o, stop_at);
      if (tk < t - kEps) {
        t = tk;
        pick = k;
        base = std::move(pieces);
      }
    }
    if (t >= stop_at) return false;
    if (pick != next[u]) flyNow(plan.uavs[u].flight, next[u], pick);
    const Sortie& sortie = sorties[next[u]];
    if (t > ready[u] + kEps) ++plan.waits;
    wait[u][next[u]] = t - ready[u];
    for (MotionPiece q : base) {
      q.t0 += t;
      q.t1 += t;
      placed[u].push_back(q);
    }
    ready[u] = t + o.takeoff_landing_s + sortie.duration_s + o.battery_swap_s;
    ++next[u];
  }
  scheduleSorties(plan, wait);
  if (plan.makespan_s >= stop_at) return false;
  plan.separation = checkSeparation(fleetMotion(plan), o.separation_m, o.slack_s);
  return !plan.separation.conflict;
}

/// The single flight's time with the fleet's overheads [s].
double singleSeconds(const FlightPlan& single, const FleetOptions& o) {
  const auto n = static_cast<double>(single.sorties.size());
  return single.duration_s + n * o.takeoff_landing_s + std::max(0.0, n - 1.0) * o.battery_swap_s;
}

/// The jobs: every flown surface whole.
std::vector<Job> surfaceJobs(const std::vector<SurfaceMission>& missions, const FlightPlan& single,
                             const FlightModel& model) {
  std::vector<Job> jobs;
  for (const auto& visit : single.order) {
    for (const auto& m : missions) {
      if (m.surface_id != visit.surface_id || !flyable(m.status)) continue;
      auto surface = std::make_shared<SurfaceMission>(m);
      surface->raw_path.clear();
      surface->coverage.uncovered_points.clear();
      const auto path = flownStops(*surface);
      if (!path.empty()) jobs.push_back(makeJob(surface, path, 0, path.size(), model));
      break;
    }
  }
  return jobs;
}

/// The assignment of `jobs` and its estimated makespan.
struct Assignment {
  std::vector<int> owner;
  double makespan_s{kInf};
};

Assignment assign(const std::vector<Job>& jobs, const std::vector<FleetUav>& uavs,
                  const FlightModel& model, const FleetOptions& fleet) {
  std::map<std::pair<int, std::vector<int>>, double> cache;
  const auto cost = [&](int u, const std::vector<int>& set) {
    auto key = std::make_pair(u, set);
    std::sort(key.second.begin(), key.second.end());
    const auto it = cache.find(key);
    if (it != cache.end()) return it->second;
    std::vector<const Job*> js;
    for (const int j : key.second) js.push_back(&jobs[static_cast<std::size_t>(j)]);
    const double t =
        set.empty() ? 0.0
                    : static_cast<double>(u) * fleet.launch_interval_s +
                          estimateSeconds(js, uavs[static_cast<std::size_t>(u)].home, model, fleet);
    cache.emplace(std::move(key), t);
    return t;
  };
  std::vector<double> alone;
  for (std::size_t j = 0; j < jobs.size(); ++j) alone.push_back(cost(0, {static_cast<int>(j)}));
  Assignment a;
  a.owner = assignMinMax(static_cast<int>(uavs.size()), alone, cost);
  std::vector<std::vector<int>> sets(uavs.size());
  for (std::size_t j = 0; j < jobs.size(); ++j)
    sets[static_cast<std::size_t>(a.owner[j])].push_back(static_cast<int>(j));
  std::vector<double> load;
  for (std::size_t u = 0; u < uavs.size(); ++u) load.push_back(cost(static_cast<int>(u), sets[u]));
  a.makespan_s = makespanOf(load);
  return a;
}

/// `jobs` with job `j` cut into `parts` parts of consecutive stops.
std::vector<Job> splitJob(const std::vector<Job>& jobs, std::size_t j, std::size_t parts,
                          const FlightModel& model) {
  std::vector<Job> out;
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    if (i != j) {
      out.push_back(jobs[i]);
      continue;
    }
    const auto path = flownStops(*jobs[i].surface);
    for (std::size_t p = 0; p < parts; ++p) {
      const std::size_t k0 = path.size() * p / parts;
      const std::size_t k1 = path.size() * (p + 1) / parts;
      if (k1 > k0) out.push_back(makeJob(jobs[i].surface, path, k0, k1, model));
    }
  }
  return out;
}

/// Cuts the longest whole surfaces while that lowers the estimated makespan by 5 %.
std::vector<Job> splitSurfaces(std::vector<Job> jobs, const std::vector<FleetUav>& uavs,
                               const FlightModel& model, const FleetOptions& fleet,
                               Assignment& current, std::size_t& split) {
  current = assign(jobs, uavs, model, fleet);
  std::vector<bool> tried(jobs.size(), false);
  for (;;) {
    std::size_t pick = jobs.size();
    for (std::size_t j = 0; j < jobs.size(); ++j) {
      if (jobs[j].part || tried[j] || jobs[j].stops < 2) continue;
      if (pick == jobs.size() || jobs[j].inner_s > jobs[pick].inner_s) pick = j;
    }
    if (pick == jobs.size()) return jobs;
    tried[pick] = true;
    std::vector<Job> best_jobs;
    Assignment best;
    const auto most = std::min<std::size_t>(uavs.size(), jobs[pick].stops);
    for (std::size_t parts = 2; parts <= most; ++parts) {
      auto cut = splitJob(jobs, pick, parts, model);
      Assignment a = assign(cut, uavs, model, fleet);
      if (a.makespan_s < best.makespan_s) {
        best = std::move(a);
        best_jobs = std::move(cut);
      }
    }
    if (best_jobs.empty() || best.makespan_s > 0.95 * current.makespan_s) continue;
    current = std::move(best);
    jobs = std::move(best_jobs);
    tried.assign(jobs.size(), false);
    for (std::size_t j = 0; j < jobs.size(); ++j) tried[j] = jobs[j].part;
    ++split;
  }
}

/// The flown stops' positions of a flight.
PointList flownPositions(const FlightPlan& f) {
  PointList out;
  for (const auto& s : f.sorties)
    for (const auto& st : s.stops) out.push_back(s.waypoints[st.waypoint]);
  return out;
}

/// UAV 1 flies the single flight alone (the others stay on the ground).
void flySingle(FleetPlan& plan, const FlightPlan& single) {
  for (auto& u : plan.uavs) {
    u.flight = FlightPlan{};
    u.flight.status = FlightPlan::Status::Ok;
    u.flight.home = u.home;
    u.stops = 0;
  }
  plan.uavs[0].flight = single;
  plan.uavs[0].stops = flownPositions(single).size();
  plan.fallback_single = true;
  plan.waits = 0;
  resolveConflicts(plan);
}

/// Jobs shared out by some candidates, and how many surfaces they split.
struct JobSet {
  std::vector<Job> jobs;
  std::size_t split{0};
};

/// An assignment to try: the UAV of each job of sets[set], its estimated makespan.
struct Candidate {
  std::size_t set{0};
  std::vector<int> owner;
  double estimate_s{kInf};
  std::string how;  ///< "min-max", "next best N", "slabs along (x, y, z)"
};

/// Estimated makespan of an assignment (per-UAV costs as in assign()).
double estimateAssignment(const std::vector<Job>& jobs, const std::vector<int>& owner,
                          const std::vector<FleetUav>& uavs, const FlightModel& model,
                          const FleetOptions& fleet) {
  double worst = 0.0;
  for (std::size_t u = 0; u < uavs.size(); ++u) {
    std::vector<const Job*> js;
    for (std::size_t j = 0; j < jobs.size(); ++j)
      if (owner[j] == static_cast<int>(u)) js.push_back(&jobs[j]);
    if (js.empty()) continue;
    worst = std::max(worst, static_cast<double>(u) * fleet.launch_interval_s +
                                estimateSeconds(js, uavs[u].home, model, fleet));
  }
  return worst;
}

/// Job sets of at most this many jobs are also tried with one flight per job (and
/// slab partitions of at most twice this many runs are tried at all).
constexpr std::size_t kPerJobMax = 24;

/// The next best assignments of the estimates after `first` (at most kNextBest), when
/// every assignment can be tried (at most 729).
constexpr std::size_t kNextBest = 8;
std::vector<Candidate> nextBest(const std::vector<Job>& jobs, const std::vector<FleetUav>& uavs,
                                const FlightModel& model, const FleetOptions& fleet,
                                const std::vector<int>& first) {
  const std::size_t n = jobs.size();
  const auto k = static_cast<int>(uavs.size());
  std::vector<Candidate> out;
  if (std::pow(static_cast<double>(k), static_cast<double>(n)) > kExhaustiveAssignments) return out;
  // Each UAV's estimate by its set of jobs (a bit mask: n ≤ 13 here).
  std::map<std::pair<int, std::uint32_t>, double> cache;
  const auto estimate = [&](const std::vector<int>& owner) {
    double worst = 0.0;
    for (int u = 0; u < k; ++u) {
      std::uint32_t mask = 0;
      for (std::size_t j = 0; j < n; ++j)
        if (owner[j] == u) mask |= std::uint32_t{1} << j;
      if (mask == 0) continue;
      auto it = cache.find({u, mask});
      if (it == cache.end()) {
        std::vector<int> one(n, -1);
        for (std::size_t j = 0; j < n; ++j)
          if (owner[j] == u) one[j] = u;
        it =
            cache
                .emplace(std::make_pair(u, mask), estimateAssignment(jobs, one, uavs, model, fleet))
                .first;
      }
      worst = std::max(worst, it->second);
    }
    return worst;
  };
  std::vector<int> owner(n, 0);
  std::vector<Candidate> all;
  for (;;) {
    if (owner != first) all.push_back({0, owner, estimate(owner), ""});
    std::size_t i = 0;
    while (i < n && ++owner[i] == k) owner[i++] = 0;
    if (i == n) break;
  }
  std::stable_sort(all.begin(), all.end(), [](const Candidate& x, const Candidate& y) {
    return x.estimate_s < y.estimate_s;
  });
  for (std::size_t i = 0; i < all.size() && out.size() < kNextBest; ++i) {
    all[i].how = "next best " + std::to_string(out.size() + 1);
    out.push_back(std::move(all[i]));
  }
  return out;
}

/// Spatial partitions: the flown stops cut into K slabs of equal stop counts along an
/// axis (the stops' main horizontal axis, the one across it, and the vertical), each
/// surface cut into runs of consecutive stops within one slab, every run of slab i
/// flown by one UAV (the matching of slabs to UAVs with the least estimated makespan).
/// UAVs then work apart, meeting only where slabs touch.
void spatialCandidates(const std::vector<Job>& whole, const PointList& stops,
                       const std::vector<FleetUav>& uavs, const FlightModel& model,
                       const FleetOptions& fleet, std::vector<JobSet>& sets,
                       std::vector<Candidate>& out) {
  const auto k = static_cast<int>(uavs.size());
  if (stops.empty() || k < 2) return;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : stops) mean += p.head<2>();
  mean /= static_cast<double>(stops.size());
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  for (const auto& p : stops) cov += (p.head<2>() - mean) * (p.head<2>() - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov);
  Eigen::Vector2d main = eig.eigenvectors().col(1);
  if (main.x() < 0.0 || (main.x() == 0.0 && main.y() < 0.0)) main = -main;  // deterministic sign
  const std::array<Vec3, 3> axes{Vec3(main.x(), main.y(), 0.0), Vec3(-main.y(), main.x(), 0.0),
                                 Vec3(0.0, 0.0, 1.0)};
  for (const Vec3& axis : axes) {
    std::vector<double> along;
    for (const auto& p : stops) along.push_back(p.dot(axis));
    std::sort(along.begin(), along.end());
    std::vector<double> cuts;  // slab i: cuts[i-1] <= x < cuts[i]
    for (int i = 1; i < k; ++i)
      cuts.push_back(
          along[along.size() * static_cast<std::size_t>(i) / static_cast<std::size_t>(k)]);
    const auto slabOf = [&](const Vec3& p) {
      return static_cast<int>(std::upper_bound(cuts.begin(), cuts.end(), p.dot(axis)) -
                              cuts.begin());
    };
    JobSet set;
    std::vector<int> slab;
    for (const Job& w : whole) {
      const auto path = flownStops(*w.surface);
      std::size_t k0 = 0;
      for (std::size_t i = 1; i <= path.size(); ++i) {
        if (i < path.size() && slabOf(w.surface->waypoints[path[i].waypoint]) ==
                                   slabOf(w.surface->waypoints[path[k0].waypoint]))
          continue;
        set.jobs.push_back(makeJob(w.surface, path, k0, i, model));
        slab.push_back(slabOf(w.surface->waypoints[path[k0].waypoint]));
        k0 = i;
      }
    }
    // Slabs to UAVs: every matching for K <= 5, else in order.
    if (set.jobs.size() > 2 * kPerJobMax)
      continue;  // many runs: a planned leg each, too slow to try
    std::vector<int> perm(static_cast<std::size_t>(k));
    std::iota(perm.begin(), perm.end(), 0);
    Candidate best;
    do {
      std::vector<int> owner;
      owner.reserve(slab.size());
      for (const int s : slab) owner.push_back(perm[static_cast<std::size_t>(s)]);
      const double e = estimateAssignment(set.jobs, owner, uavs, model, fleet);
      if (e < best.estimate_s - 1e-9) best = {sets.size(), owner, e, ""};
    } while (k <= 5 && std::next_permutation(perm.begin(), perm.end()));
    std::set<int> parted;
    for (const Job& j : set.jobs)
      if (j.part) parted.insert(j.surface->surface_id);
    set.split = parted.size();
    best.how = "slabs along (" + formatFixed(axis.x(), 2) + ", " + formatFixed(axis.y(), 2) + ", " +
               formatFixed(axis.z(), 2) + ")";
    sets.push_back(std::move(set));
    out.push_back(std::move(best));
  }
}

/// Short jobs: every surface cut into parts of consecutive stops of about
/// 2 × and 4 × slack_s of work each (at least 60 s), shared by the min–max assignment;
/// flown one flight per job, they let the schedule pair far-apart parts.
void chunkCandidates(const std::vector<Job>& whole, const std::vector<FleetUav>& uavs,
                     const FlightModel& model, const FleetOptions& fleet, std::vector<JobSet>& sets,
                     std::vector<Candidate>& out) {
  for (const double factor : {2.0, 4.0}) {
    const double chunk = std::max(60.0, factor * fleet.slack_s);
    JobSet set;
    for (const Job& w : whole) {
      const auto path = flownStops(*w.surface);
      const auto parts = std::min<std::size_t>(
          path.size(), static_cast<std::size_t>(std::max(1.0, std::round(w.inner_s / chunk))));
      for (std::size_t p = 0; p < parts; ++p) {
        const std::size_t k0 = path.size() * p / parts;
        const std::size_t k1 = path.size() * (p + 1) / parts;
        if (k1 > k0) set.jobs.push_back(makeJob(w.surface, path, k0, k1, model));
      }
      if (parts > 1) ++set.split;
    }
    if (set.jobs.size() == whole.size() || set.jobs.size() > kPerJobMax) continue;
    Assignment a = assign(set.jobs, uavs, model, fleet);
    out.push_back(
        {sets.size(), a.owner, a.makespan_s, "parts of ~" + formatFixed(chunk, 0) + " s, min-max"});
    sets.push_back(std::move(set));
  }
}

/// Planned flights per (job set, UAV, jobs): candidates share them.
using FlightCache = std::map<std::tuple<const void*, int, std::vector<int>>, FlightPlan>;

/// Jobs of `mine` in the order of the shortest tour from `home` (straight-line times).
std::vector<int> tourOrder(const std::vector<Job>& jobs, const std::vector<int>& mine,
                           const Vec3& home, const FlightModel& model) {
  PointList points{home};
  std::vector<TourCluster> clusters(1);
  clusters[0].variants.push_back({0, 0, 0.0});
  for (const int j : mine) {
    const Job& job = jobs[static_cast<std::size_t>(j)];
    const int a = static_cast<int>(points.size());
    points.push_back(job.first);
    points.push_back(job.last);
    TourCluster c;
    c.variants.push_back({a, a + 1, job.inner_s});
    c.variants.push_back({a + 1, a, job.inner_s});
    clusters.push_back(c);
  }
  TourOptions options;
  options.exact_max_clusters = 9;
  const Tour tour = solveTour(
      clusters, [&](int a, int b) { return model.segmentSeconds(points[a], points[b]); }, options);
  std::vector<int> out;
  for (const int c : tour.order) out.push_back(mine[static_cast<std::size_t>(c - 1)]);
  return out;
}

/// `add`'s sorties flown after those of `into` (one UAV's flights, one after another).
void appendFlight(FlightPlan& into, const FlightPlan& add) {
  into.order.insert(into.order.end(), add.order.begin(), add.order.end());
  into.excluded.insert(into.excluded.end(), add.excluded.begin(), add.excluded.end());
  into.sorties.insert(into.sorties.end(), add.sorties.begin(), add.sorties.end());
  into.tour_length_m += add.tour_length_m;
  into.inner_length_m += add.inner_length_m;
  into.lower_bound_m += add.lower_bound_m;
  into.exact_order = into.exact_order && add.exact_order;
  into.planned_legs += add.planned_legs;
  into.order_seconds += add.order_seconds;
  into.validate_seconds += add.validate_seconds;
  into.length_m += add.length_m;
  into.duration_s += add.duration_s;
  into.seconds += add.seconds;
  if (add.status != FlightPlan::Status::Ok && into.status == FlightPlan::Status::Ok) {
    into.status = add.status;
    into.reason = add.reason;
  }
}

/// Flies each UAV's jobs of `owner` from its home (cached): one planFlight over them,
/// or with `per_job` one flight per job in the order of the tour (each job its own
/// sorties, so that waits on the ground can shift one job). False when a flight
/// fails or leaves a surface out.
bool flyCandidate(FleetPlan& plan, const std::vector<Job>& jobs, const std::vector<int>& owner,
                  bool per_job, FlightCache& cache, const world::VoxelGrid& grid,
                  const PathValidator& validator, Planner& planner, const FlightOptions& flight) {
  FlightOptions own = flight;
  own.start.reset();
  own.compare_naive = false;
  const auto fly = [&](int u, const std::vector<int>& set) -> const FlightPlan& {
    auto key = std::make_tuple(static_cast<const void*>(&jobs), u, set);
    auto it = cache.find(key);
    if (it == cache.end()) {
      std::vector<SurfaceMission> ms;
      ms.reserve(set.size());
      for (const int j : set) ms.push_back(partMission(jobs[static_cast<std::size_t>(j)]));
      own.home = plan.uavs[static_cast<std::size_t>(u)].home;
      it = cache.emplace(std::move(key), planFlight(ms, grid, validator, planner, own)).first;
    }
    return it->second;
  };
  for (std::size_t u = 0; u < plan.uavs.size(); ++u) {
    std::vector<int> mine;
    for (std::size_t j = 0; j < jobs.size(); ++j)
      if (owner[j] == static_cast<int>(u)) mine.push_back(static_cast<int>(j));
    FleetUav& uav = plan.uavs[u];
    uav.flight = FlightPlan{};
    uav.flight.status = FlightPlan::Status::Ok;
    uav.flight.home = uav.home;
    uav.stops = 0;
    if (mine.empty()) continue;
    if (!per_job || mine.size() == 1) {
      uav.flight = fly(static_cast<int>(u), mine);
    } else {
      uav.flight.exact_order = true;
      for (const int j : tourOrder(jobs, mine, uav.home, flight.model)) {
        const FlightPlan& f = fly(static_cast<int>(u), {j});
        if (uav.flight.sorties.empty()) uav.flight.home_source = f.home_source;
        appendFlight(uav.flight, f);
      }
    }
    uav.stops = flownPositions(uav.flight).size();
    if (uav.flight.status != FlightPlan::Status::Ok || !uav.flight.excluded.empty()) return false;
  }
  return true;
}

/// The fleet's candidate assignments (fleet.h): the min–max assignment of the
/// estimates, the next best ones, spatial partitions and chunks, by estimate; fills
/// `sets` with the job sets they assign.
std::vector<Candidate> fleetCandidates(const std::vector<SurfaceMission>& missions,
                                       const FlightPlan& single, const PointList& stops,
                                       const std::vector<FleetUav>& uavs,
                                       const FlightOptions& flight, const FleetOptions& fleet,
                                       std::vector<JobSet>& sets) {
  std::vector<Candidate> candidates;
  Assignment a;
  std::size_t split = 0;
  const std::vector<Job> whole = surfaceJobs(missions, single, flight.model);
  std::vector<Job> jobs = splitSurfaces(whole, uavs, flight.model, fleet, a, split);
  sets.push_back({std::move(jobs), split});
  candidates.push_back({0, a.owner, a.makespan_s, "min-max"});
  for (auto& c : nextBest(sets[0].jobs, uavs, flight.model, fleet, a.owner))
    candidates.push_back(std::move(c));
  spatialCandidates(whole, stops, uavs, flight.model, fleet, sets, candidates);
  chunkCandidates(whole, uavs, flight.model, fleet, sets, candidates);
  std::stable_sort(
      candidates.begin(), candidates.end(),
      [](const Candidate& x, const Candidate& y) { return x.estimate_s < y.estimate_s; });
  return candidates;
}

/// The waits of a flown trial placed two ways, list scheduling (any order when
/// `per_job`: every sortie a round trip of one job) and the earliest conflict's wait;
/// keeps the shorter conflict-free schedule. False when none is conflict-free and
/// shorter than `bar` [s].
bool placeWaits(FleetPlan& trial, double bar, bool per_job) {
  FleetPlan packed = trial;
  bool ok_packed = packSorties(packed, bar);
  if (per_job) {
    FleetPlan free = trial;
    if (packSorties(free, ok_packed ? packed.makespan_s : bar, true)) {
      packed = std::move(free);
      ok_packed = true;
    }
  }
  const bool ok = resolveConflicts(trial, ok_packed ? packed.makespan_s : bar) || ok_packed;
  if (ok_packed && (trial.separation.conflict || trial.makespan_s >= packed.makespan_s))
    trial = std::move(packed);
  return ok && !trial.separation.conflict && trial.makespan_s < bar;
}

}  // namespace

bool scheduleFlights(FleetPlan& plan, bool any_order) { return packSorties(plan, kInf, any_order); }

FleetPlan planFleet(const std::vector<SurfaceMission>& missions, const FlightPlan& single,
                    const world::VoxelGrid& grid, const PathValidator& validator, Planner& planner,
                    const FlightOptions& flight, const FleetOptions& fleet) {
  const auto t0 = SteadyClock::now();
  fleet.validate("fleet");
  FleetPlan plan;
  plan.options = fleet;
  plan.model = flight.model;
  if (single.status != FlightPlan::Status::Ok) {
    plan.status = FleetPlan::Status::Failed;
    plan.reason = "no single flight to share out: " + single.reason;
    return plan;
  }
  const PointList stops = flownPositions(single);
  if (static_cast<int>(stops.size()) < fleet.uavs) {
    throw InputError("fleet: uavs " + std::to_string(fleet.uavs) + " is more than the " +
                     std::to_string(stops.size()) +
                     " photo stops to fly; use at most one UAV per stop");
  }
  plan.uavs = fleetHomes(single, stops, grid, validator, fleet);
  plan.single_uav_s = singleSeconds(single, fleet);
  PointList homes;
  for (const auto& u : plan.uavs) homes.push_back(u.home);
  const FleetBound bound = fleetLowerBound(stops, homes, flight.model, fleet);
  plan.work_s = bound.work_s;
  plan.lower_bound_s = bound.bound_s;

  // Candidates (fleet.h): the min–max assignment of the estimates, the next best
  // assignments, and spatial partitions; each flown and scheduled, the shortest
  // makespan with its waits kept.
  std::vector<JobSet> sets;
  const std::vector<Candidate> candidates =
      fleetCandidates(missions, single, stops, plan.uavs, flight, fleet, sets);
  // Each candidate flown as one flight per UAV, then (small job sets) one flight per job.
  std::vector<std::pair<const Candidate*, bool>> tries;
  for (const bool per_job : {false, true})
    for (const Candidate& c : candidates)
      if (!per_job || sets[c.set].jobs.size() <= kPerJobMax) tries.emplace_back(&c, per_job);
  FlightCache cache;
  FleetPlan best;
  bool found = false;
  for (const auto& [c, per_job] : tries) {
    FleetPlan trial = plan;
    const JobSet& set = sets[c->set];
    if (!flyCandidate(trial, set.jobs, c->owner, per_job, cache, grid, validator, planner, flight))
      continue;
    const double bar = found ? best.makespan_s : plan.single_uav_s;
    if (!placeWaits(trial, bar, per_job)) continue;
    trial.jobs = set.jobs.size();
    trial.split_surfaces = set.split;
    trial.assignment = c->how + (per_job ? ", a flight per job" : "");
    best = std::move(trial);
    found = true;
  }
  plan.candidates = candidates.size();
  if (found) {
    const std::size_t n = plan.candidates;
    plan = std::move(best);
    plan.candidates = n;
  } else {
    plan.jobs = sets[0].jobs.size();
    plan.split_surfaces = sets[0].split;
    if (plan.uavs[0].home == single.home) {
      flySingle(plan, single);
    } else {  // fleet.homes: the single flight from UAV 1's home
      FlightOptions own = flight;
      own.home = plan.uavs[0].home;
      own.start.reset();
      flySingle(plan, planFlight(missions, grid, validator, planner, own));
    }
  }
  plan.seconds = secondsSince(t0);
  return plan;
}

}  // namespace uavip::planning
