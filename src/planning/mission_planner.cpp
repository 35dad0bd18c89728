#include "uavip/planning/mission_planner.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <iomanip>
#include <limits>
#include <optional>
#include <sstream>

#include "uavip/core/aircraft.h"
#include "uavip/core/error.h"
#include "uavip/core/geometry.h"
#include "uavip/core/math.h"
#include "uavip/core/stopwatch.h"
#include "uavip/planning/path_join.h"
#include "uavip/planning/path_simplifier.h"

namespace uavip::planning {

namespace {

std::string legName(const Leg& leg) {
  std::ostringstream os;
  os << (leg.from_stop < 0 ? std::string("start") : "stop " + std::to_string(leg.from_stop))
     << " -> stop " << leg.to_stop;
  return os.str();
}

/// True when nothing measured lies on the ray from `from` to `target` before the
/// ray comes within `slack` [m] of the target (the surface itself is occupied).
bool clearSight(const world::VoxelGrid& grid, const Vec3& from, const Vec3& target, double slack) {
  const Vec3 d = target - from;
  const double length = d.norm();
  const double step = 0.5 * grid.resolution();
  for (double t = 0.0; t < length - slack; t += step) {
    const world::Index3 i = grid.indexOf(from + d * (t / length));
    if (grid.inBounds(i) && grid.isOccupied(i)) return false;
  }
  return true;
}

/// Points `stop` from `p` at its target when `p` is free, in clear sight of the target
/// and the pitch it needs is within the gimbal's limits; returns whether it did.
bool lookFrom(coverage::Stop& stop, const Vec3& p, const world::VoxelGrid& grid,
              const MissionOptions& options) {
  if (!grid.isFree(p) || !clearSight(grid, p, stop.target, 0.5 * grid.resolution() + 0.3))
    return false;
  const Vec3 look = stop.target - p;
  const double pitch = std::atan2(look.z(), look.head<2>().norm()) * 180.0 / kPi;
  if (!aircraft::pitchWithin(pitch, options.gimbal.pitch_min_deg, options.gimbal.pitch_max_deg))
    return false;
  stop.position = p;
  stop.gimbal_pitch_deg = pitch;
  if (look.head<2>().norm() > 1e-6) stop.yaw_deg = std::atan2(look.y(), look.x()) * 180.0 / kPi;
  stop.gimbal_ok = true;
  return true;
}

/// The distances a repaired stop is tried at, × the standoff.
std::array<double, 3> repairFactors(const MissionOptions& options) {
  return {1.0, 0.5 * (1.0 + options.max_standoff_factor), options.max_standoff_factor};
}

/// A mosaic's repair (coverage.purpose mosaic), tried before repairStop's: OpenCV's
/// affine stitcher places photos taken square at the standoff; it misplaces photos tilted
/// 10–15° by 0.2–0.3 of a footprint and joins neither 30° tilts nor other ranges
/// (docs/photo_purposes.md). So: square at the standoff, the photo centre slid in the
/// plane by at most half the overlap on each axis (each neighbour keeps at least half its
/// planned overlap), the smallest slide that is free and in clear sight first.
bool repairMosaicStop(coverage::Stop& stop, const coverage::FlightStrategy& strategy,
                      const world::VoxelGrid& grid, const MissionOptions& options) {
  const auto& cam = strategy.camera;
  const double standoff = cam.standoff_m;
  if (!(standoff > 0.0)) return false;
  const Vec3 n = (stop.position - stop.target) / standoff;
  const double slide_w = 0.5 * std::max(0.0, cam.footprint_w_m - strategy.spacing_w_m);
  const double slide_h = 0.5 * std::max(0.0, cam.footprint_h_m - strategy.spacing_h_m);
  constexpr int kSteps = 4;  // slides of 1/4 … 4/4 of the allowance on each axis
  std::vector<Vec3> slides;
  for (int i = -kSteps; i <= kSteps; ++i) {
    for (int j = -kSteps; j <= kSteps; ++j) {
      if (i != 0 || j != 0)
        slides.push_back((i * slide_w * strategy.axis_w + j * slide_h * strategy.axis_h) / kSteps);
    }
  }
  std::stable_sort(slides.begin(), slides.end(),
                   [](const Vec3& a, const Vec3& b) { return a.squaredNorm() < b.squaredNorm(); });
  const Vec3 target = stop.target;
  for (const Vec3& d : slides) {
    stop.target = target + d;
    if (lookFrom(stop, stop.target + standoff * n, grid, options)) return true;
  }
  stop.target = target;
  return false;
}

/// Whether stop i's footprint (on its plane, along the strategy's axes) lies inside the
/// union of the footprints of the other stops still taken (problem None) within two rows
/// and three columns of it. Exact: the rectangles' edges cut stop i's footprint into
/// cells, and each cell's centre must lie in one of them. Every footprint is taken as the
/// nominal one at its target (a neighbour repaired by tilt or distance images a little
/// differently); the plan's coverage is measured afterwards as for every plan.
bool footprintCoveredByNeighbours(const SurfaceMission& m, std::size_t i,
                                  const coverage::FlightStrategy& strategy) {
  const auto& stops = m.strategy.stops;
  const double hw = 0.5 * strategy.camera.footprint_w_m, hh = 0.5 * strategy.camera.footprint_h_m;
  const auto uv = [&](const Vec3& p) {
    return Eigen::Vector2d(p.dot(strategy.axis_w), p.dot(strategy.axis_h));
  };
  const Eigen::Vector2d c = uv(stops[i].target);
  std::vector<Eigen::Vector2d> near;
  std::vector<double> us = {c.x() - hw, c.x() + hw}, vs = {c.y() - hh, c.y() + hh};
  for (std::size_t j = 0; j < stops.size(); ++j) {
    if (j == i || m.stop_problems[j] != StopProblem::None ||
        std::abs(stops[j].row - stops[i].row) > 2 || std::abs(stops[j].col - stops[i].col) > 3)
      continue;
    const Eigen::Vector2d q = uv(stops[j].target);
    near.push_back(q);
    for (const double u : {q.x() - hw, q.x() + hw})
      if (u > us[0] && u < us[1]) us.push_back(u);
    for (const double v : {q.y() - hh, q.y() + hh})
      if (v > vs[0] && v < vs[1]) vs.push_back(v);
  }
  std::sort(us.begin(), us.end());
  std::sort(vs.begin(), vs.end());
  for (std::size_t a = 0; a + 1 < us.size(); ++a) {
    for (std::size_t b = 0; b + 1 < vs.size(); ++b) {
      const Eigen::Vector2d p(0.5 * (us[a] + us[a + 1]), 0.5 * (vs[b] + vs[b + 1]));
      if (std::none_of(near.begin(), near.end(), [&](const Eigen::Vector2d& q) {
            return std::abs(p.x() - q.x()) <= hw && std::abs(p.y() - q.y()) <= hh;
          }))
        return false;
    }
  }
  return true;
}

/// Largest change of viewing direction [deg] from the stop flown before that
/// repairStop prefers to a less stretched pose: SIFT matches 15–20° of viewpoint change
/// well, 30° and more poorly (docs/photo_purposes.md).
constexpr double kFollowDeg = 20.0;

/// A free pose near an infeasible stop that still photographs its target: the
/// standoff direction tilted by 15–60° toward ±axis_h (from above / below) and
/// ±axis_w (the sides), at the standoff or farther (up to max_standoff_factor). The
/// least stretched photo first: distance / cos(tilt) (the factor its ground sample
/// grows by along the tilt), so 15° at 1.125 × the standoff comes before 45° at it and
/// every 60° last. COLMAP's SIFT, which takes a change of scale better than one of
/// viewpoint, left out single_plane's photos repaired 60° and 45° from below beside
/// neighbours repaired from above (benchmarks/README.md). The first free candidate in
/// that order, in the gimbal limits and in clear sight of the target, wins; given the
/// viewing direction `follow` of the stop flown before (unit, target to camera), the
/// first free one within kFollowDeg of it wins instead where one exists: a run of
/// repaired stops keeps one side and tilt (COLMAP left out single_plane's photo repaired
/// 15° to the side between two 30° from below). Returns false if none is free.
bool repairStop(coverage::Stop& stop, const coverage::FlightStrategy& strategy,
                const world::VoxelGrid& grid, const MissionOptions& options,
                const std::optional<Vec3>& follow) {
  const double standoff = strategy.camera.standoff_m;
  if (!(standoff > 0.0)) return false;
  const Vec3 n = (stop.position - stop.target) / standoff;
  const Vec3 up = std::abs(strategy.axis_h.z()) > 1e-6 && strategy.axis_h.z() < 0.0
                      ? Vec3(-strategy.axis_h)
                      : strategy.axis_h;
  const Vec3 sides[4] = {up, -up, strategy.axis_w, -strategy.axis_w};
  struct Candidate {
    double stretch, factor, deg;
  };
  std::vector<Candidate> candidates;
  for (const double f : repairFactors(options))
    for (const double deg : {0.0, 15.0, 30.0, 45.0, 60.0})
      candidates.push_back({f / std::cos(deg * kPi / 180.0), f, deg});
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& x, const Candidate& y) { return x.stretch < y.stretch; });
  const double cos_follow = std::cos(kFollowDeg * kPi / 180.0);
  std::optional<coverage::Stop> least;  // the least stretched free pose, kept if none follows
  for (const Candidate& c : candidates) {
    const double a = c.deg * kPi / 180.0;
    for (const auto& side : sides) {
      if (c.deg == 0.0 && &side != &sides[0]) continue;  // one untilted candidate per distance
      const Vec3 dir = (std::cos(a) * n + std::sin(a) * side).normalized();
      const bool follows = !follow || dir.dot(*follow) >= cos_follow;
      if (least && !follows) continue;
      coverage::Stop trial = stop;
      if (!lookFrom(trial, stop.target + c.factor * standoff * dir, grid, options)) continue;
      if (follows) {
        stop = trial;
        return true;
      }
      least = trial;
    }
  }
  if (!least) return false;
  stop = *least;
  return true;
}

/// The viewing direction of stop i's predecessor among the stops kept so far (problem
/// None, at most kFollowLookback before i: past a longer run left out the flight jumps
/// anyway, and the search stays linear): unit, target to camera; none for the first.
std::optional<Vec3> predecessorView(const SurfaceMission& m, std::size_t i) {
  constexpr std::size_t kFollowLookback = 4;
  for (std::size_t j = i; j-- > 0 && i - j <= kFollowLookback;) {
    if (m.stop_problems[j] != StopProblem::None) continue;
    const Vec3 d = m.strategy.stops[j].position - m.strategy.stops[j].target;
    const double len = d.norm();
    if (len > 0.0 && std::isfinite(len)) return Vec3(d / len);
    return std::nullopt;
  }
  return std::nullopt;
}

/// The search for a stop the gimbal cannot take when repairStop finds nothing: every
/// direction of a Fibonacci spiral (kGimbalSearchDirections) within
/// kMaxIncidenceDeg of the surface's outward normal, each at the repair distances;
/// the pose closest in angle to the normal, then nearest, wins. A stop it finds
/// nothing for is reported outside the gimbal limits.
bool searchGimbalPose(coverage::Stop& stop, const coverage::FlightStrategy& strategy,
                      const world::VoxelGrid& grid, const MissionOptions& options) {
  constexpr int kGimbalSearchDirections = 256;
  constexpr double kMaxIncidenceDeg = 75.0;
  const double standoff = strategy.camera.standoff_m;
  if (!(standoff > 0.0)) return false;
  const Vec3 n = ((stop.position - stop.target) / standoff).normalized();
  const Vec3 u = (strategy.axis_w - strategy.axis_w.dot(n) * n).normalized();
  const Vec3 v = n.cross(u);
  const double cos_max = std::cos(kMaxIncidenceDeg * kPi / 180.0);
  const double golden = kPi * (3.0 - std::sqrt(5.0));
  for (int k = 0; k < kGimbalSearchDirections; ++k) {
    const double c = 1.0 - (1.0 - cos_max) * (k + 0.5) / kGimbalSearchDirections;
    const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
    const double phi = golden * k;
    const Vec3 dir = c * n + s * (std::cos(phi) * u + std::sin(phi) * v);
    for (const double f : repairFactors(options)) {
      if (lookFrom(stop, stop.target + f * standoff * dir, grid, options)) return true;
    }
  }
  return false;
}

/// Throws InputError when mission.start is given but not in a free voxel.
void requireFreeStart(const world::VoxelGrid& grid, const PathValidator& validator,
                      const MissionOptions& options) {
  if (!options.start) return;
  const Vec3& s = *options.start;
  if (s.allFinite() && grid.isFree(s)) return;
  std::ostringstream os;
  os << "mission: start " << formatPoint(s) << " is inside obstacle space (clearance " << std::fixed
     << std::setprecision(2) << validator.clearance(s)
     << " m to the nearest measured point; the grid blocks voxels within "
     << grid.effectiveInflation()
     << " m of an occupied voxel and everything outside its bounds); move it farther from the "
        "structure";
  throw InputError(os.str());
}

/// Per-stop checks: gimbal limits (where stop repair, then the wider search, may turn
/// the stop into a pose the gimbal reaches), then the inflated obstacle space (where
/// stop repair may move the stop). Fills m.stop_problems and m.moved_stops; returns the
/// first usable stop, −1 if none.
int checkStops(SurfaceMission& m, const coverage::FlightStrategy& strategy,
               const world::VoxelGrid& grid, const MissionOptions& options) {
  auto& stops = m.strategy.stops;
  int first_usable = -1;
  for (std::size_t i = 0; i < stops.size(); ++i) {
    if (!stops[i].gimbal_ok) {
      if (options.repair_stops && stops[i].position.allFinite() &&
          (repairStop(stops[i], strategy, grid, options, predecessorView(m, i)) ||
           searchGimbalPose(stops[i], strategy, grid, options))) {
        m.moved_stops.push_back(static_cast<int>(i));
        m.gimbal_moved_stops.push_back(static_cast<int>(i));
        if (first_usable < 0) first_usable = static_cast<int>(i);
      } else {
        m.stop_problems[i] = StopProblem::GimbalLimit;
      }
    } else if (!stops[i].position.allFinite() || !grid.isFree(stops[i].position)) {
      const bool mosaic_kept = options.repair_stops && options.mosaic_repair &&
                               stops[i].position.allFinite() &&
                               repairMosaicStop(stops[i], strategy, grid, options);
      if (!mosaic_kept && options.repair_stops && options.mosaic_repair &&
          footprintCoveredByNeighbours(m, i, strategy)) {
        m.stop_problems[i] = StopProblem::MosaicCovered;
      } else if (mosaic_kept ||
                 (options.repair_stops && stops[i].position.allFinite() &&
                  repairStop(stops[i], strategy, grid, options, predecessorView(m, i)))) {
        m.moved_stops.push_back(static_cast<int>(i));
        if (first_usable < 0) first_usable = static_cast<int>(i);
      } else {
        m.stop_problems[i] = StopProblem::InObstacleSpace;
      }
    } else if (first_usable < 0) {
      first_usable = static_cast<int>(i);
    }
  }
  // A stop left out on neighbours that were left out after it: repaired after all
  // (adding a stop back only covers more, so one pass in order keeps every other).
  for (std::size_t i = 0; i < stops.size(); ++i) {
    if (m.stop_problems[i] != StopProblem::MosaicCovered ||
        footprintCoveredByNeighbours(m, i, strategy))
      continue;
    if (repairStop(stops[i], strategy, grid, options, predecessorView(m, i))) {
      m.stop_problems[i] = StopProblem::None;
      m.moved_stops.insert(
          std::upper_bound(m.moved_stops.begin(), m.moved_stops.end(), static_cast<int>(i)),
          static_cast<int>(i));
      if (first_usable < 0 || static_cast<int>(i) < first_usable)
        first_usable = static_cast<int>(i);
    } else {
      m.stop_problems[i] = StopProblem::InObstacleSpace;
    }
  }
  return first_usable;
}

/// 26-connectivity: usable stops outside the free region of the start (or, without
/// a start, of the region holding the most usable stops: the first usable stop may
/// sit in a pocket, between the legs of a tower, cut off from the rest; up to
/// kSeedTries regions are compared) are marked Unreachable.
void markUnreachable(SurfaceMission& m, const world::VoxelGrid& grid, const MissionOptions& options,
                     int first_usable) {
  const auto& stops = m.strategy.stops;
  constexpr int kSeedTries = 3;
  const auto componentOf = [&](std::size_t i) {
    return grid.component(grid.indexOf(stops[i].position));
  };
  std::int32_t reach = grid.component(grid.indexOf(
      options.start ? *options.start : stops[static_cast<std::size_t>(first_usable)].position));
  if (!options.start) {
    std::size_t best = 0;
    std::vector<char> tried(stops.size(), 0);
    for (int t = 0; t < kSeedTries; ++t) {
      std::size_t count = 0;
      int next = -1;
      for (std::size_t i = 0; i < stops.size(); ++i) {
        if (m.stop_problems[i] != StopProblem::None) continue;
        if (reach != 0 && componentOf(i) == reach) {
          ++count;
          tried[i] = 1;
        } else if (next < 0 && !tried[i]) {
          next = static_cast<int>(i);
        }
      }
      if (count > best) best = count;
      if (next < 0 || 2 * best >= static_cast<std::size_t>(stops.size())) break;
      const std::int32_t other = componentOf(static_cast<std::size_t>(next));
      std::size_t other_count = 0;
      for (std::size_t i = 0; i < stops.size(); ++i) {
        if (m.stop_problems[i] == StopProblem::None && other != 0 && componentOf(i) == other)
          ++other_count;
      }
      tried[static_cast<std::size_t>(next)] = 1;
      if (other_count > best) reach = other;
    }
  }
  for (std::size_t i = 0; i < stops.size(); ++i) {
    if (m.stop_problems[i] != StopProblem::None) continue;
    if (reach == 0 || componentOf(i) != reach) m.stop_problems[i] = StopProblem::Unreachable;
  }
}

/// "N of M stops infeasible: …" by cause, empty when every stop is usable; `n_bad`
/// gets the number of skipped stops, `n_obstacle` those inside the inflated space.
std::string describeSkipped(const SurfaceMission& m, const world::VoxelGrid& grid,
                            const MissionOptions& options, std::size_t& n_bad,
                            std::size_t& n_obstacle) {
  std::size_t n_gimbal = 0, n_unreachable = 0, n_covered = 0;
  n_obstacle = 0;
  for (const auto p : m.stop_problems) {
    n_gimbal += p == StopProblem::GimbalLimit;
    n_obstacle += p == StopProblem::InObstacleSpace;
    n_unreachable += p == StopProblem::Unreachable;
    n_covered += p == StopProblem::MosaicCovered;
  }
  n_bad = n_gimbal + n_obstacle + n_unreachable;
  // A mosaic's flown photos the general repair moved off square at the standoff.
  std::size_t n_off_square = 0, n_flown = 0;
  if (options.mosaic_repair) {
    const Vec3 normal = m.strategy.axis_w.cross(m.strategy.axis_h).normalized();
    const double standoff = m.strategy.camera.standoff_m;
    const double cos_square = std::cos(0.5 * kPi / 180.0);
    for (std::size_t i = 0; i < m.stop_problems.size(); ++i) {
      if (m.stop_problems[i] != StopProblem::None) continue;
      ++n_flown;
      const Vec3 d = m.strategy.stops[i].position - m.strategy.stops[i].target;
      if (std::abs(d.norm() - standoff) > 1e-3 || std::abs(d.normalized().dot(normal)) < cos_square)
        ++n_off_square;
    }
  }
  std::ostringstream covered;
  if (n_covered > 0) {
    covered << n_covered << " of " << m.stop_problems.size()
            << " stops left out of the mosaic (in obstacle space, no square pose within the "
               "overlap; their neighbours cover their footprints)";
  }
  if (n_off_square > 0) {
    covered << (n_covered > 0 ? "; " : "") << n_off_square << " of " << n_flown
            << " photos off square (tilted or farther than the standoff around obstacles: an "
               "affine stitcher such as OpenCV's SCANS misplaces them)";
  }
  if (n_bad == 0) return covered.str();
  std::ostringstream os;
  if (n_covered + n_off_square > 0) os << covered.str() << "; ";
  os << n_bad << " of " << m.stop_problems.size() << " stops infeasible: ";
  bool first = true;
  auto part = [&](std::size_t n, const std::string& what) {
    if (n == 0) return;
    os << (first ? "" : ", ") << n << " " << what;
    first = false;
  };
  std::ostringstream obstacle;
  obstacle << std::fixed << std::setprecision(2)
           << "inside the inflated obstacle space (voxel centre within "
           << grid.effectiveInflation() << " m of an occupied voxel)";
  part(n_gimbal, "outside the gimbal pitch limits");
  part(n_obstacle, obstacle.str());
  part(n_unreachable, options.start
                          ? "unreachable from the start"
                          : "unreachable (cut off from the free region holding the most stops)");
  return os.str();
}

}  // namespace

PointList straightOrDetour(const world::VoxelGrid& grid, const Vec3& a, const Vec3& b) {
  if (grid.segmentFree(a, b)) return {a, b};
  const Vec3 d = b - a;
  const double length = d.norm();
  if (!(length > 0.0)) return {};
  Vec3 side = d.cross(Vec3(Vec3::UnitZ()));
  side = side.norm() > 1e-9 * length ? side.normalized() : Vec3::UnitX();
  const Vec3 up = side.cross(d).normalized();
  PointList best;
  double best_length = std::numeric_limits<double>::infinity();
  for (const double f : {0.25, 0.5, 1.0}) {
    for (const Vec3& u : {up, Vec3(-up), side, Vec3(-side)}) {
      const Vec3 m = 0.5 * (a + b) + f * length * u;
      const double l = (m - a).norm() + (b - m).norm();
      if (l < best_length && grid.isFree(m) && grid.segmentFree(a, m) && grid.segmentFree(m, b)) {
        best = {a, m, b};
        best_length = l;
      }
    }
    if (!best.empty()) return best;  // the nearest offset that works
  }
  return best;
}

namespace {

/// Legs start → stop 0 (if given), then usable stop → next usable stop, each planned
/// on the grid; fills m.legs, m.raw_path and m.waypoints. On a failed leg: status
/// Failed with its reason, no waypoints, and false.
bool planLegs(SurfaceMission& m, const world::VoxelGrid& grid, Planner& planner,
              const MissionOptions& options) {
  const auto& stops = m.strategy.stops;
  PointList points;  // the points joined by legs, in order
  std::vector<int> ids;
  if (options.start) {
    points.push_back(*options.start);
    ids.push_back(-1);
  }
  for (std::size_t i = 0; i < stops.size(); ++i) {
    if (m.stop_problems[i] != StopProblem::None) continue;  // skipped, reported in the reason
    points.push_back(stops[i].position);
    ids.push_back(static_cast<int>(i));
  }
  m.raw_path.push_back(points.front());
  m.waypoints.push_back(points.front());
  for (std::size_t k = 0; k + 1 < points.size(); ++k) {
    PathResult r;
    PointList direct =
        options.direct_legs ? straightOrDetour(grid, points[k], points[k + 1]) : PointList{};
    if (!direct.empty()) {
      r.status = PathStatus::Solved;
      r.path = std::move(direct);
    } else {
      r = planner.plan(grid, points[k], points[k + 1]);
    }
    Leg leg;
    leg.from_stop = ids[k];
    leg.to_stop = ids[k + 1];
    leg.status = r.status;
    leg.raw_steps = r.path.empty() ? 0 : r.path.size() - 1;
    leg.length_m = polylineLength(r.path);
    leg.seconds = r.seconds;
    m.legs.push_back(leg);
    if (!r.solved()) {
      m.status = SurfaceStatus::Failed;
      m.reason = "leg " + std::to_string(k) + " (" + legName(leg) + ") failed: planner '" +
                 planner.name() + "' returned " + toString(r.status) + "; no waypoints generated";
      m.waypoints.clear();
      m.raw_waypoint_count = m.raw_path.size();
      m.raw_length_m = polylineLength(m.raw_path);
      return false;
    }
    appendLeg(m.raw_path, r.path);
    appendLeg(m.waypoints, options.simplify ? simplifyPath(r.path, grid) : r.path);
  }
  m.raw_waypoint_count = m.raw_path.size();
  m.raw_length_m = polylineLength(m.raw_path);
  m.path_length_m = polylineLength(m.waypoints);
  return true;
}

}  // namespace

SurfaceMission planSurfaceMission(const coverage::FlightStrategy& strategy,
                                  const world::VoxelGrid& grid, const PathValidator& validator,
                                  Planner& planner, const MissionOptions& options) {
  options.validate("mission");
  const auto t0 = SteadyClock::now();
  SurfaceMission m;
  m.surface_id = strategy.surface_id;
  m.strategy = strategy;
  auto finish = [&]() {
    m.seconds = secondsSince(t0);
    return m;
  };
  requireFreeStart(grid, validator, options);

  m.stop_problems.assign(m.strategy.stops.size(), StopProblem::None);
  if (m.strategy.stops.empty()) {
    m.status = SurfaceStatus::NoStops;
    m.reason = "the flight strategy produced no photo stop for surface " +
               std::to_string(strategy.surface_id);
    return finish();
  }
  const int first_usable = checkStops(m, strategy, grid, options);
  if (options.start || first_usable >= 0) markUnreachable(m, grid, options, first_usable);
  std::size_t n_bad = 0, n_obstacle = 0;
  const std::string skipped = describeSkipped(m, grid, options, n_bad, n_obstacle);
  const std::size_t n_stops = m.strategy.stops.size();
  if (static_cast<double>(n_bad) > options.max_skipped_fraction * static_cast<double>(n_stops) ||
      n_bad == n_stops) {
    std::ostringstream os;
    os << skipped << "; more than " << std::setprecision(3) << 100.0 * options.max_skipped_fraction
       << " % of the stops, so no waypoints generated";
    if (2 * n_obstacle > n_bad) {
      // Mostly a space too tight for the UAV (a room, a narrow gap): say what to change.
      os << " (the UAV, inflated by " << std::fixed << std::setprecision(2)
         << grid.effectiveInflation()
         << " m, does not fit at the standoff here: try a smaller uav.inflation_radius_m or "
            "uav.size_m, "
            "another coverage.standoff_m, or a larger mission.max_skipped_fraction)";
    }
    m.status = SurfaceStatus::Blocked;
    m.reason = os.str();
    return finish();
  }
  if (!planLegs(m, grid, planner, options)) return finish();

  m.validation = validator.validate(m.waypoints);
  if (!m.validation.collision_free) {
    std::ostringstream os;
    os << std::fixed << std::setprecision(3) << "path validation failed: segment "
       << m.validation.first_violation_segment << " comes closer than the required "
       << validator.requiredClearance() << " m to " << m.validation.violation_object << " at "
       << formatPoint(m.validation.violation_point) << " (minimum clearance "
       << m.validation.min_clearance_m << " m)";
    m.status = SurfaceStatus::Failed;
    m.reason = os.str();
    return finish();
  }
  m.status = n_bad > 0 ? SurfaceStatus::Partial : SurfaceStatus::Ok;
  if (!skipped.empty()) m.reason = skipped + (n_bad > 0 ? "; those stops are skipped" : "");
  return finish();
}

}  // namespace uavip::planning
