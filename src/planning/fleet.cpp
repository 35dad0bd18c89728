#include "uavip/planning/fleet.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>

#include "uavip/core/error.h"
#include "uavip/core/geometry.h"
#include "uavip/core/math.h"
#include "uavip/core/stopwatch.h"
#include "uavip/core/text.h"
#include "uavip/planning/tour.h"

namespace uavip::planning {

namespace {

/// Assignments tried one by one when there are at most this many.
constexpr double kExhaustiveAssignments = 729.0;

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

/// One job: a surface, or a part of consecutive stops of one.
struct Job {
  SurfaceMission mission;  ///< its stops only are flown
  std::size_t stops{0};
  Vec3 first{Vec3::Zero()};     ///< first flown stop [m]
  Vec3 last{Vec3::Zero()};      ///< last flown stop [m]
  Vec3 centroid{Vec3::Zero()};  ///< of its stops [m]
  double inner_s{0.0};          ///< along its path with the photos [s]
  bool part{false};             ///< a part of a surface
};

/// The job of stops [k0, k1) of `path` (flown stops of `m`).
Job makeJob(const SurfaceMission& m, const std::vector<PathStop>& path, std::size_t k0,
            std::size_t k1, const FlightModel& model) {
  Job j;
  j.mission = m;
  j.mission.raw_path.clear();
  j.mission.coverage.uncovered_points.clear();
  j.part = k1 - k0 < path.size();
  for (std::size_t k = 0; k < path.size(); ++k) {
    if (k < k0 || k >= k1)
      j.mission.stop_problems[static_cast<std::size_t>(path[k].stop)] = StopProblem::Unreachable;
  }
  const std::size_t w0 = path[k0].waypoint;
  const std::size_t w1 = path[k1 - 1].waypoint;
  const auto& wp = m.waypoints;
  j.mission.waypoints.assign(wp.begin() + static_cast<std::ptrdiff_t>(w0),
                             wp.begin() + static_cast<std::ptrdiff_t>(w1 + 1));
  const auto& clear = m.validation.segment_clearance_m;
  if (clear.size() + 1 == wp.size()) {
    j.mission.validation.segment_clearance_m.assign(
        clear.begin() + static_cast<std::ptrdiff_t>(w0),
        clear.begin() + static_cast<std::ptrdiff_t>(w1));
  }
  j.mission.path_length_m = polylineLength(j.mission.waypoints);
  j.stops = k1 - k0;
  j.first = wp[w0];
  j.last = wp[w1];
  for (std::size_t k = k0; k < k1; ++k) j.centroid += wp[path[k].waypoint];
  j.centroid /= static_cast<double>(j.stops);
  j.inner_s =
      model.pathSeconds(j.mission.waypoints) + static_cast<double>(j.stops) * model.stopSeconds();
  return j;
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

FleetBound fleetLowerBound(const PointList& stops, const PointList& homes, const FlightModel& model,
                           const FleetOptions& fleet) {
  FleetBound b;
  for (std::size_t i = 0; i < stops.size(); ++i) {
    double reach = kInf;
    double trip = kInf;
    for (const auto& h : homes) {
      reach = std::min(reach, model.segmentSeconds(h, stops[i]));
      trip = std::min(trip, model.segmentSeconds(h, stops[i]) + model.segmentSeconds(stops[i], h));
    }
    for (std::size_t k = 0; k < stops.size(); ++k)
      if (k != i) reach = std::min(reach, model.segmentSeconds(stops[k], stops[i]));
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
    if (segmentSegmentDistance(p.a, p.b, q.a, q.b) < separation_m) shift = p.t1 + slack_s - q.t0 + kEps;
  }
  return std::max(shift, kEps);
}

/// Waits on the ground until the separation check finds no conflict (fleet.h).
/// False when the number of waits runs out.
bool resolveConflicts(FleetPlan& plan) {
  std::vector<std::vector<double>> wait;
  for (const auto& u : plan.uavs) wait.emplace_back(u.flight.sorties.size(), 0.0);
  const double slack = plan.options.slack_s;
  std::map<std::array<int, 4>, int> seen;  // conflicts per pair of sorties
  constexpr double kEps = 1e-3;
  for (int round = 0; round < 4000; ++round) {
    scheduleSorties(plan, wait);
    const auto motion = fleetMotion(plan);
    plan.separation = checkSeparation(motion, plan.options.separation_m, slack);
    if (!plan.separation.conflict) return true;
    const FleetConflict& c = *plan.separation.conflict;
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
      const auto path = flownStops(m);
      if (!path.empty()) jobs.push_back(makeJob(m, path, 0, path.size(), model));
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
    const SurfaceMission& m = jobs[i].mission;
    const auto path = flownStops(m);
    for (std::size_t p = 0; p < parts; ++p) {
      const std::size_t k0 = path.size() * p / parts;
      const std::size_t k1 = path.size() * (p + 1) / parts;
      if (k1 > k0) out.push_back(makeJob(m, path, k0, k1, model));
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

}  // namespace

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

  Assignment a;
  const std::vector<Job> jobs =
      splitSurfaces(surfaceJobs(missions, single, flight.model), plan.uavs, flight.model, fleet, a,
                    plan.split_surfaces);
  plan.jobs = jobs.size();
  bool flown = true;
  for (std::size_t u = 0; u < plan.uavs.size() && flown; ++u) {
    std::vector<SurfaceMission> mine;
    for (std::size_t j = 0; j < jobs.size(); ++j)
      if (a.owner[j] == static_cast<int>(u)) mine.push_back(jobs[j].mission);
    FleetUav& uav = plan.uavs[u];
    uav.flight = FlightPlan{};
    uav.flight.status = FlightPlan::Status::Ok;
    uav.flight.home = uav.home;
    if (mine.empty()) continue;
    FlightOptions own = flight;
    own.home = uav.home;
    own.start.reset();
    own.compare_naive = false;
    uav.flight = planFlight(mine, grid, validator, planner, own);
    uav.stops = flownPositions(uav.flight).size();
    flown = uav.flight.status == FlightPlan::Status::Ok && uav.flight.excluded.empty();
  }
  const bool resolved = flown && resolveConflicts(plan);
  if (!resolved || plan.makespan_s >= plan.single_uav_s) {
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
