#include "uavip/planning/flight_planner.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>

#include "uavip/core/error.h"
#include "uavip/core/geometry.h"
#include "uavip/core/parallel.h"
#include "uavip/core/stopwatch.h"
#include "uavip/planning/path_join.h"
#include "uavip/planning/path_simplifier.h"
#include "uavip/planning/tour.h"

namespace uavip::planning {

namespace {

/// Cost of a leg no planner could find [m]: keeps the solver away from it.
constexpr double kNoLegM = 1e9;

/// Connecting legs between two points: the straight segment when it is free on the
/// grid, else the planner's (simplified) path. Each pair is planned at most once.
class LegPlanner {
 public:
  LegPlanner(const world::VoxelGrid& grid, Planner& planner, bool simplify)
      : grid_(grid), planner_(planner), simplify_(simplify) {}

  /// The leg a → b, or nullptr when the planner finds none.
  const PointList* path(const Vec3& a, const Vec3& b) {
    auto& entry = lookup(a, b);
    if (!entry.known) {
      ++planned_;
      const PathResult r = planner_.plan(grid_, a, b);
      entry.known = true;
      entry.found = r.solved();
      if (entry.found) entry.path = simplify_ ? simplifyPath(r.path, grid_) : r.path;
    }
    return entry.found ? &entry.path : nullptr;
  }
  /// The leg's length when known (straight and free, or planned), else the
  /// straight-line length, a lower bound; `exact` says which.
  double length(const Vec3& a, const Vec3& b, bool* exact = nullptr) {
    auto& entry = lookup(a, b);
    if (exact != nullptr) *exact = entry.known;
    if (!entry.known) return (b - a).norm();
    return entry.found ? polylineLength(entry.path) : kNoLegM;
  }
  std::size_t planned() const { return planned_; }

 private:
  struct Entry {
    bool known{false};
    bool found{false};
    PointList path;
  };
  Entry& lookup(const Vec3& a, const Vec3& b) {
    const std::array<double, 6> key{a.x(), a.y(), a.z(), b.x(), b.y(), b.z()};
    auto [it, inserted] = cache_.try_emplace(key);
    if (inserted && (a == b || grid_.segmentFree(a, b))) {
      it->second.known = true;
      it->second.found = true;
      it->second.path = a == b ? PointList{a} : PointList{a, b};
    }
    return it->second;
  }

  const world::VoxelGrid& grid_;
  Planner& planner_;
  bool simplify_;
  std::map<std::array<double, 6>, Entry> cache_;
  std::size_t planned_{0};
};

/// A flyable surface's path from its first to its last flown stop.
struct SurfacePath {
  int surface_id{0};
  PointList waypoints;          ///< first stop … last stop
  std::vector<int> stops;       ///< stop indices in flight order
  std::vector<std::size_t> at;  ///< waypoint index of each stop
  double length_m{0.0};
};

/// The mission's waypoints cut to its stops (a mission with a start begins there).
std::optional<SurfacePath> surfacePath(const SurfaceMission& m) {
  SurfacePath s;
  s.surface_id = m.surface_id;
  std::size_t w = 0;
  std::size_t first = 0;
  for (std::size_t k = 0; k < m.strategy.stops.size(); ++k) {
    if (m.stop_problems[k] != StopProblem::None) continue;
    const Vec3& p = m.strategy.stops[k].position;
    while (w < m.waypoints.size() && m.waypoints[w] != p) ++w;
    if (w == m.waypoints.size()) return std::nullopt;  // not on the path: not a planned mission
    if (s.stops.empty()) first = w;
    s.stops.push_back(static_cast<int>(k));
    s.at.push_back(w - first);
  }
  if (s.stops.empty()) return std::nullopt;
  s.waypoints.assign(m.waypoints.begin() + static_cast<std::ptrdiff_t>(first),
                     m.waypoints.begin() + static_cast<std::ptrdiff_t>(first + s.at.back() + 1));
  s.length_m = polylineLength(s.waypoints);
  return s;
}

/// The surface flown in reverse.
SurfacePath reversed(const SurfacePath& s) {
  SurfacePath r = s;
  std::reverse(r.waypoints.begin(), r.waypoints.end());
  std::reverse(r.stops.begin(), r.stops.end());
  const std::size_t last = s.waypoints.size() - 1;
  r.at.clear();
  for (auto it = s.at.rbegin(); it != s.at.rend(); ++it) r.at.push_back(last - *it);
  return r;
}

/// Default home: the lowest flown stop (ties: first surface, first stop).
void chooseHome(const std::vector<SurfacePath>& surfaces, const FlightOptions& options,
                FlightPlan& plan) {
  if (options.home) {
    plan.home = *options.home;
    plan.home_source = "mission.home";
    return;
  }
  if (options.start) {
    plan.home = *options.start;
    plan.home_source = "mission.start";
    return;
  }
  double best = std::numeric_limits<double>::infinity();
  for (const auto& s : surfaces) {
    for (std::size_t k = 0; k < s.stops.size(); ++k) {
      const Vec3& p = s.waypoints[s.at[k]];
      if (p.z() < best) {
        best = p.z();
        plan.home = p;
        plan.home_source = "lowest photo stop (surface " + std::to_string(s.surface_id) +
                           ", stop " + std::to_string(s.stops[k]) + ")";
      }
    }
  }
}

/// The tour's stops in flight order, over one polyline home → … → home.
struct TourPath {
  PointList waypoints;
  std::vector<FlightStop> stops;  ///< waypoint = index in `waypoints`
};

TourPath buildTour(const FlightPlan& plan, const std::vector<SurfacePath>& surfaces,
                   const std::vector<int>& order, const std::vector<int>& variant,
                   LegPlanner& legs) {
  TourPath t;
  t.waypoints.push_back(plan.home);
  for (std::size_t i = 0; i < order.size(); ++i) {
    const SurfacePath s = variant[i] == 0 ? surfaces[static_cast<std::size_t>(order[i])]
                                          : reversed(surfaces[static_cast<std::size_t>(order[i])]);
    appendLeg(t.waypoints, *legs.path(t.waypoints.back(), s.waypoints.front()));
    const std::size_t base = t.waypoints.size() - 1;  // s.waypoints.front() sits here
    for (std::size_t k = 0; k < s.stops.size(); ++k)
      t.stops.push_back({s.surface_id, s.stops[k], base + s.at[k]});
    t.waypoints.insert(t.waypoints.end(), s.waypoints.begin() + 1, s.waypoints.end());
  }
  appendLeg(t.waypoints, *legs.path(t.waypoints.back(), plan.home));
  return t;
}

using SegmentKey = std::array<double, 6>;

SegmentKey segmentKey(const Vec3& a, const Vec3& b) {
  return {a.x(), a.y(), a.z(), b.x(), b.y(), b.z()};
}

/// Clearance of every segment the surfaces' own validation measured, both ways [m].
std::map<SegmentKey, double> validatedSegments(const std::vector<SurfaceMission>& missions) {
  std::map<SegmentKey, double> known;
  for (const auto& m : missions) {
    if (!flyable(m.status) || m.validation.segment_clearance_m.size() + 1 != m.waypoints.size())
      continue;
    for (std::size_t i = 0; i + 1 < m.waypoints.size(); ++i) {
      known[segmentKey(m.waypoints[i], m.waypoints[i + 1])] = m.validation.segment_clearance_m[i];
      known[segmentKey(m.waypoints[i + 1], m.waypoints[i])] = m.validation.segment_clearance_m[i];
    }
  }
  return known;
}

/// The validator's verdict on every segment of the sorties that no surface's
/// validation measured (legs between surfaces and to home), each once, on every core.
std::map<SegmentKey, ValidationResult> validateNewSegments(
    const std::vector<Sortie>& sorties, const std::map<SegmentKey, double>& known,
    const PathValidator& validator) {
  std::map<SegmentKey, ValidationResult> fresh;
  std::vector<std::pair<Vec3, Vec3>> segments;
  for (const auto& s : sorties) {
    for (std::size_t i = 0; i + 1 < s.waypoints.size(); ++i) {
      const SegmentKey key = segmentKey(s.waypoints[i], s.waypoints[i + 1]);
      if (known.count(key) == 0 && fresh.try_emplace(key).second)
        segments.emplace_back(s.waypoints[i], s.waypoints[i + 1]);
    }
  }
  std::vector<ValidationResult> results(segments.size());
  parallelFor(segments.size(), hardwareThreads(), [&](std::size_t i, std::size_t) {
    results[i] = validator.validate({segments[i].first, segments[i].second});
  });
  for (std::size_t i = 0; i < segments.size(); ++i)
    fresh[segmentKey(segments[i].first, segments[i].second)] = std::move(results[i]);
  return fresh;
}

/// The validator's verdict on a sortie, segment by segment: a segment of a
/// surface's own path keeps the clearance its surface's validation measured (the
/// same validator on the same segment), every other segment the verdict `fresh` holds.
ValidationResult validateSortie(const PointList& path, const std::map<SegmentKey, double>& known,
                                const std::map<SegmentKey, ValidationResult>& fresh,
                                const PathValidator& validator) {
  if (path.size() < 2) return validator.validate(path);
  ValidationResult r;
  r.min_clearance_m = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    double c = 0.0;
    const auto it = known.find(segmentKey(path[i], path[i + 1]));
    if (it != known.end()) {
      c = it->second;
    } else {
      const ValidationResult& v = fresh.at(segmentKey(path[i], path[i + 1]));
      c = v.segment_clearance_m.front();
      if (!v.collision_free && r.collision_free) {
        r.collision_free = false;
        r.first_violation_segment = static_cast<int>(i);
        r.violation_point = v.violation_point;
        r.violation_object = v.violation_object;
      }
    }
    r.segment_clearance_m.push_back(c);
    r.min_clearance_m = std::min(r.min_clearance_m, c);
  }
  return r;
}

std::string describeViolation(std::size_t sortie, const ValidationResult& v,
                              const PathValidator& validator) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(3) << "sortie " << sortie << " fails validation: segment "
     << v.first_violation_segment << " comes closer than the required "
     << validator.requiredClearance() << " m to " << v.violation_object << " at "
     << formatPoint(v.violation_point) << " (minimum clearance " << v.min_clearance_m << " m)";
  return os.str();
}

/// Cuts the tour into sorties that each fit the usable endurance. Returns an empty
/// string, or why a stop cannot be flown in one battery.
std::string splitSorties(const TourPath& tour, const FlightPlan& plan, const FlightModel& model,
                         LegPlanner& legs, std::vector<Sortie>& sorties) {
  // Flight time from home along the tour to each waypoint.
  std::vector<double> t(tour.waypoints.size(), 0.0);
  for (std::size_t i = 1; i < t.size(); ++i)
    t[i] = t[i - 1] + model.segmentSeconds(tour.waypoints[i - 1], tour.waypoints[i]);
  const double budget = model.usableSeconds();
  const std::size_t n = tour.stops.size();
  auto legSeconds = [&](const Vec3& a, const Vec3& b) {
    const PointList* p = legs.path(a, b);
    return p == nullptr ? std::numeric_limits<double>::infinity() : model.pathSeconds(*p);
  };
  auto along = [&](std::size_t first,
                   std::size_t last) {  // stops first..last, flight between them and photos
    return t[tour.stops[last].waypoint] - t[tour.stops[first].waypoint] +
           static_cast<double>(last - first + 1) * model.stopSeconds();
  };
  std::size_t first = 0;
  while (first < n) {
    const Vec3& entry = tour.waypoints[tour.stops[first].waypoint];
    const double out = legSeconds(plan.home, entry);
    std::size_t last = first;
    // Grow while the straight-line return (a lower bound) fits; then check the real one.
    while (last + 1 < n &&
           out + along(first, last + 1) +
                   model.segmentSeconds(tour.waypoints[tour.stops[last + 1].waypoint], plan.home) <=
               budget) {
      ++last;
    }
    while (last > first &&
           out + along(first, last) +
                   legSeconds(tour.waypoints[tour.stops[last].waypoint], plan.home) >
               budget) {
      --last;
    }
    const Vec3& exit = tour.waypoints[tour.stops[last].waypoint];
    const double total = out + along(first, last) + legSeconds(exit, plan.home);
    if (!std::isfinite(total)) {
      return "planner found no leg between home " + formatPoint(plan.home) + " and stop " +
             std::to_string(tour.stops[first].stop) + " of surface " +
             std::to_string(tour.stops[first].surface_id);
    }
    if (total > budget) {
      std::ostringstream os;
      os << std::fixed << std::setprecision(0) << "stop " << tour.stops[first].stop
         << " of surface " << tour.stops[first].surface_id << " needs " << total
         << " s from home and back, more than the usable " << budget << " s of flight.endurance_s "
         << model.endurance_s << " s less flight.reserve; raise "
         << "flight.endurance_s or move mission.home closer";
      return os.str();
    }
    Sortie s;
    s.waypoints.push_back(plan.home);
    appendLeg(s.waypoints, *legs.path(plan.home, entry));
    const std::size_t shift = s.waypoints.size() - 1 - tour.stops[first].waypoint;
    s.waypoints.insert(
        s.waypoints.end(),
        tour.waypoints.begin() + static_cast<std::ptrdiff_t>(tour.stops[first].waypoint + 1),
        tour.waypoints.begin() + static_cast<std::ptrdiff_t>(tour.stops[last].waypoint + 1));
    for (std::size_t k = first; k <= last; ++k) {
      FlightStop fs = tour.stops[k];
      fs.waypoint += shift;
      s.stops.push_back(fs);
    }
    appendLeg(s.waypoints, *legs.path(exit, plan.home));
    s.length_m = polylineLength(s.waypoints);
    s.duration_s = sortieSeconds(s, model);
    sorties.push_back(std::move(s));
    first = last + 1;
  }
  return {};
}

/// The missions that can be flown, as surface paths; the others go to plan.excluded.
std::vector<SurfacePath> flyableSurfaces(const std::vector<SurfaceMission>& missions,
                                         FlightPlan& plan) {
  std::vector<SurfacePath> surfaces;
  for (const auto& m : missions) {
    if (!flyable(m.status)) {
      plan.excluded.push_back({m.surface_id, std::string("status ") + toString(m.status)});
      continue;
    }
    auto s = surfacePath(m);
    if (!s) {
      plan.excluded.push_back({m.surface_id, "its waypoints do not pass its stops"});
      continue;
    }
    surfaces.push_back(std::move(*s));
  }
  return surfaces;
}

/// Leaves out the surfaces the home's free region cannot reach (to plan.excluded).
void dropUnreachable(std::vector<SurfacePath>& surfaces, const world::VoxelGrid& grid,
                     FlightPlan& plan) {
  const world::Index3 home_voxel = grid.indexOf(plan.home);
  std::vector<SurfacePath> reachable;
  for (auto& s : surfaces) {
    if (grid.connected(home_voxel, grid.indexOf(s.waypoints.front()))) {
      reachable.push_back(std::move(s));
    } else {
      plan.excluded.push_back(
          {s.surface_id, "cut off from home " + formatPoint(plan.home) + " on the grid"});
    }
  }
  surfaces = std::move(reachable);
}

/// The ordering problem: point 0 = home, points 2i+1 and 2i+2 = first and last
/// stop of surface i; cluster 0 is home, cluster i + 1 surface i (forward or reversed).
struct TourProblem {
  PointList points;
  std::vector<TourCluster> clusters;

  TourProblem(const std::vector<SurfacePath>& surfaces, const Vec3& home)
      : points{home}, clusters(1) {
    clusters[0].variants.push_back({0, 0, 0.0});
    for (const auto& s : surfaces) {
      const int first = static_cast<int>(points.size());
      points.push_back(s.waypoints.front());
      points.push_back(s.waypoints.back());
      TourCluster c;
      c.variants.push_back({first, first + 1, s.length_m});
      if (s.waypoints.size() > 1) c.variants.push_back({first + 1, first, s.length_m});
      clusters.push_back(c);
    }
  }

  /// The (from, to) point pairs of a tour's connecting legs, home to home.
  std::vector<std::pair<int, int>> legEnds(const Tour& tour) const {
    std::vector<std::pair<int, int>> ends;
    int at = 0;
    for (std::size_t i = 0; i < tour.order.size(); ++i) {
      const auto& v = clusters[static_cast<std::size_t>(tour.order[i])]
                          .variants[static_cast<std::size_t>(tour.variant[i])];
      ends.emplace_back(at, v.entry);
      at = v.exit;
    }
    ends.emplace_back(at, 0);
    return ends;
  }

  /// Plans the tour's legs not yet known; false when all were already exact.
  bool planUnknown(const Tour& tour, LegPlanner& legs) const {
    bool planned = false;
    for (const auto& [a, b] : legEnds(tour)) {
      bool exact = false;
      legs.length(points[a], points[b], &exact);
      if (!exact) {
        legs.path(points[a], points[b]);
        planned = true;
      }
    }
    return planned;
  }
};

/// The surface order: solve on leg-length estimates, plan the chosen tour's unknown
/// legs exactly, repeat. Estimates are lower bounds: a tour optimal for them whose
/// legs are all exact is optimal for the true lengths (docs/architecture_notes.md).
/// Fills the plan's order figures (exact_order, tour and bound lengths, naive tour).
Tour orderSurfaces(const TourProblem& problem, LegPlanner& legs, const FlightOptions& options,
                   FlightPlan& plan, SteadyClock::time_point t0) {
  const PointList& points = problem.points;
  const PointCost estimate = [&](int a, int b) { return legs.length(points[a], points[b]); };
  Tour tour;
  bool converged = false;
  for (int round = 0; round < std::max(1, options.max_rounds) && !converged; ++round) {
    tour = solveTour(problem.clusters, estimate);
    converged = !problem.planUnknown(tour, legs);
  }
  tour.cost = tourCost(problem.clusters, tour, estimate);
  plan.order_seconds = secondsSince(t0);
  plan.exact_order = tour.exact && converged;
  plan.tour_length_m = tour.cost;
  plan.lower_bound_m = tourLowerBound(problem.clusters,
                                      [&](int a, int b) { return (points[b] - points[a]).norm(); });
  if (options.compare_naive) {
    Tour naive;
    for (std::size_t c = 1; c < problem.clusters.size(); ++c) {
      naive.order.push_back(static_cast<int>(c));
      naive.variant.push_back(0);
    }
    problem.planUnknown(naive, legs);
    plan.naive_length_m = tourCost(problem.clusters, naive, estimate);
  }
  plan.planned_legs = legs.planned();
  return tour;
}

/// Sweeps the UAV along every sortie (segments the surface missions already
/// validated are reused); the first violation fails the plan. Sums length and time.
void validateSorties(FlightPlan& plan, const std::vector<SurfaceMission>& missions,
                     const PathValidator& validator) {
  const auto t_validate = SteadyClock::now();
  const std::map<SegmentKey, double> known = validatedSegments(missions);
  const std::map<SegmentKey, ValidationResult> fresh =
      validateNewSegments(plan.sorties, known, validator);
  for (std::size_t i = 0; i < plan.sorties.size(); ++i) {
    Sortie& s = plan.sorties[i];
    s.validation = validateSortie(s.waypoints, known, fresh, validator);
    plan.length_m += s.length_m;
    plan.duration_s += s.duration_s;
    if (!s.validation.collision_free && plan.status == FlightPlan::Status::Ok) {
      plan.status = FlightPlan::Status::Failed;
      plan.reason =
          describeViolation(i + 1, s.validation, validator) + "; the flight is not written";
    }
  }
  plan.validate_seconds = secondsSince(t_validate);
}

}  // namespace

FlightPlan planFlight(const std::vector<SurfaceMission>& missions, const world::VoxelGrid& grid,
                      const PathValidator& validator, Planner& planner,
                      const FlightOptions& options) {
  const auto t0 = SteadyClock::now();
  FlightPlan plan;
  options.validate("flight");
  auto fail = [&](FlightPlan::Status status, const std::string& reason) {
    plan.status = status;
    plan.reason = reason;
    plan.seconds = secondsSince(t0);
    return plan;
  };

  std::vector<SurfacePath> surfaces = flyableSurfaces(missions, plan);
  if (surfaces.empty()) return fail(FlightPlan::Status::Empty, "no surface has a flyable mission");
  chooseHome(surfaces, options, plan);
  if (!plan.home.allFinite() || !grid.isFree(plan.home)) {
    throw InputError("mission.home: " + formatPoint(plan.home) +
                     " is inside obstacle space or outside the planning grid; move it into open "
                     "space near the structure");
  }
  dropUnreachable(surfaces, grid, plan);
  if (surfaces.empty()) {
    return fail(FlightPlan::Status::Failed,
                "no flyable surface can be reached from home " + formatPoint(plan.home));
  }
  for (const auto& s : surfaces) plan.inner_length_m += s.length_m;

  const TourProblem problem(surfaces, plan.home);
  LegPlanner legs(grid, planner, options.simplify);
  const Tour tour = orderSurfaces(problem, legs, options, plan, t0);
  for (const auto& [a, b] : problem.legEnds(tour)) {
    if (legs.path(problem.points[a], problem.points[b]) == nullptr) {
      return fail(FlightPlan::Status::Failed,
                  "planner '" + planner.name() + "' found no leg from " +
                      formatPoint(problem.points[a]) + " to " + formatPoint(problem.points[b]) +
                      "; no flight generated");
    }
  }
  std::vector<int> order;
  for (std::size_t i = 0; i < tour.order.size(); ++i) {
    order.push_back(tour.order[i] - 1);
    plan.order.push_back(
        {surfaces[static_cast<std::size_t>(tour.order[i] - 1)].surface_id, tour.variant[i] == 1});
  }

  const TourPath path = buildTour(plan, surfaces, order, tour.variant, legs);
  const std::string why = splitSorties(path, plan, options.model, legs, plan.sorties);
  plan.planned_legs = legs.planned();
  if (!why.empty()) {
    plan.sorties.clear();
    return fail(FlightPlan::Status::Failed, why + "; no flight generated");
  }
  plan.status = FlightPlan::Status::Ok;
  validateSorties(plan, missions, validator);
  plan.seconds = secondsSince(t0);
  return plan;
}

}  // namespace uavip::planning
