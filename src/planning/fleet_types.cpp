// A fleet's plain types (planning/fleet_types.h): the `fleet:` table and checks, the
// motion model and the separation check (library uavip_planning_types).
#include "uavip/planning/fleet_types.h"

#include <algorithm>
#include <cmath>

#include "uavip/core/error.h"
#include "uavip/core/geometry.h"
#include "uavip/core/math.h"
#include "uavip/core/text.h"

namespace uavip::planning {

const params::Table<FleetOptions>& FleetOptions::table() {
  static const params::Table<FleetOptions> t = [] {
    using O = FleetOptions;
    params::Table<O> p;
    p.add("uavs", &O::uavs, "UAVs flying the site at once (1: the single flight)").atLeast(1);
    p.add(
         "homes", params::Kind::Numbers,
         [](const O& o) {
           params::Value v;
           v.present = !o.homes.empty();
           for (const auto& h : o.homes) v.numbers.insert(v.numbers.end(), {h.x(), h.y(), h.z()});
           return v;
         },
         [](O& o, const params::Value& v) {
           o.homes.clear();
           for (std::size_t i = 0; i + 2 < v.numbers.size(); i += 3)
             o.homes.emplace_back(v.numbers[i], v.numbers[i + 1], v.numbers[i + 2]);
         },
         "take-off point [[x, y, z], …] of each UAV; none: spaced beside the single flight's home")
        .unitIs("m")
        .count(3, std::size_t{192})
        .address = [](const O& o) -> const void* { return &o.homes; };
    p.add("separation_m", &O::separation_m, "least distance between two UAVs at any instant")
        .unitIs("m")
        .positive();
    p.add("launch_interval_s", &O::launch_interval_s, "UAV i takes off i × this after UAV 1")
        .unitIs("s")
        .atLeast(0);
    p.add("slack_s", &O::slack_s, "delay a UAV may run behind its schedule, kept conflict-free")
        .unitIs("s")
        .atLeast(0);
    p.add("takeoff_landing_s", &O::takeoff_landing_s, "take-off plus landing at home, per sortie")
        .unitIs("s")
        .atLeast(0);
    p.add("battery_swap_s", &O::battery_swap_s, "on the ground between two sorties of a UAV")
        .unitIs("s")
        .atLeast(0);
    return p;
  }();
  return t;
}

void FleetOptions::validate(const std::string& where) const {
  table().check(*this, where);
  if (!homes.empty() && static_cast<int>(homes.size()) != uavs) {
    throw InputError(where + ": homes lists " + std::to_string(homes.size()) + " points for uavs " +
                     std::to_string(uavs) + "; give one home per UAV");
  }
  for (std::size_t i = 0; i < homes.size(); ++i) {
    require(homes[i].allFinite(), where, "homes must be finite");
    for (std::size_t j = 0; j < i; ++j) {
      const double d = (homes[i] - homes[j]).norm();
      if (d < separation_m) {
        throw InputError(where + ": homes " + std::to_string(j + 1) + " " + formatPoint(homes[j]) +
                         " and " + std::to_string(i + 1) + " " + formatPoint(homes[i]) + " are " +
                         formatFixed(d, 2) + " m apart, closer than separation_m " +
                         formatNumber(separation_m) + " m; move them apart");
      }
    }
  }
}

const char* toString(FleetPlan::Status status) {
  return status == FleetPlan::Status::Ok ? "ok" : "failed";
}

std::vector<MotionPiece> sortieMotion(const PointList& waypoints,
                                      const std::vector<std::size_t>& stop_waypoints,
                                      const FlightModel& model, double takeoff_landing_s,
                                      double start_s, int sortie) {
  std::vector<MotionPiece> out;
  if (waypoints.empty()) return out;
  std::vector<int> hovers(waypoints.size(), 0);
  for (const std::size_t w : stop_waypoints)
    if (w < waypoints.size()) ++hovers[w];
  double t = start_s;
  auto stay = [&](const Vec3& p, double seconds) {
    if (seconds <= 0.0) return;
    out.push_back({p, p, t, t + seconds, sortie});
    t += seconds;
  };
  stay(waypoints.front(), 0.5 * takeoff_landing_s);
  for (std::size_t i = 0; i < waypoints.size(); ++i) {
    stay(waypoints[i], hovers[i] * model.stopSeconds());
    if (i + 1 == waypoints.size()) break;
    const double dt = model.segmentSeconds(waypoints[i], waypoints[i + 1]);
    out.push_back({waypoints[i], waypoints[i + 1], t, t + dt, sortie});
    t += dt;
  }
  stay(waypoints.back(), 0.5 * takeoff_landing_s);
  return out;
}

namespace {

/// Position on a piece at time t (clamped to the piece).
Vec3 positionAt(const MotionPiece& p, double t) {
  if (p.t1 <= p.t0) return p.a;
  const double s = std::clamp((t - p.t0) / (p.t1 - p.t0), 0.0, 1.0);
  return p.a + s * (p.b - p.a);
}

/// Velocity of a piece [m/s] (zero when it stays put or lasts no time).
Vec3 velocityOf(const MotionPiece& p) {
  return p.t1 > p.t0 ? Vec3((p.b - p.a) / (p.t1 - p.t0)) : Vec3(Vec3::Zero());
}

}  // namespace

std::optional<Approach> closestApproach(const MotionPiece& p, const MotionPiece& q) {
  const double lo = std::max(p.t0, q.t0);
  const double hi = std::min(p.t1, q.t1);
  if (lo > hi) return std::nullopt;
  // d(t) = d0 + v (t − lo); |d|² is least at t = lo − d0·v / |v|², clamped to [lo, hi].
  const Vec3 d0 = positionAt(q, lo) - positionAt(p, lo);
  const Vec3 v = velocityOf(q) - velocityOf(p);
  double t = lo;
  const double vv = v.squaredNorm();
  if (vv > 0.0) t = std::clamp(lo - d0.dot(v) / vv, lo, hi);
  return Approach{(d0 + (t - lo) * v).norm(), t};
}

namespace {

/// Checks UAVs a and b into `out` (keeps the earliest conflict).
void checkPair(const std::vector<MotionPiece>& pa, const std::vector<MotionPiece>& pb, int a, int b,
               double separation_m, double slack_s, SeparationCheck& out) {
  std::size_t first = 0;  // first piece of b whose widened window can still overlap
  for (std::size_t i = 0; i < pa.size(); ++i) {
    const MotionPiece& p = pa[i];
    while (first < pb.size() && pb[first].t1 + slack_s < p.t0) ++first;
    for (std::size_t j = first; j < pb.size() && pb[j].t0 <= p.t1 + slack_s; ++j) {
      const MotionPiece& q = pb[j];
      ++out.pairs;
      // A pair no nearer than the separation and every least distance so far changes
      // nothing; the nominal approach is no nearer than the segments (d).
      const double far = segmentBoxesDistance(p.a, p.b, q.a, q.b);
      if (far >= separation_m && far >= out.swept_min_m && far >= out.nominal_min_m) continue;
      const double d = segmentSegmentDistance(p.a, p.b, q.a, q.b);
      out.swept_min_m = std::min(out.swept_min_m, d);
      if (d < out.nominal_min_m) {
        if (const auto c = closestApproach(p, q); c && c->distance_m < out.nominal_min_m) {
          out.nominal_min_m = c->distance_m;
          out.nominal_time_s = c->time_s;
        }
      }
      if (d >= separation_m) continue;
      const double when = std::max(p.t0, q.t0);
      if (!out.conflict || when < out.conflict->time_s)
        out.conflict = FleetConflict{a, b, p.sortie, q.sortie, i, j, when, d};
    }
  }
}

}  // namespace

SeparationCheck checkSeparation(const std::vector<std::vector<MotionPiece>>& uavs,
                                double separation_m, double slack_s) {
  SeparationCheck out;
  out.swept_min_m = kInf;
  out.nominal_min_m = kInf;
  for (std::size_t a = 0; a < uavs.size(); ++a)
    for (std::size_t b = a + 1; b < uavs.size(); ++b)
      checkPair(uavs[a], uavs[b], static_cast<int>(a), static_cast<int>(b), separation_m, slack_s,
                out);
  return out;
}

std::optional<FleetConflict> firstConflict(const std::vector<std::vector<MotionPiece>>& uavs,
                                           double separation_m, double slack_s) {
  std::optional<FleetConflict> best;
  // checkSeparation's conflict: the least start of the pair's overlap, the first pair in
  // (a, b, piece of a, piece of b) order among equals; pairs no earlier are skipped.
  for (std::size_t a = 0; a < uavs.size(); ++a) {
    for (std::size_t b = a + 1; b < uavs.size(); ++b) {
      const auto& pa = uavs[a];
      const auto& pb = uavs[b];
      std::size_t first = 0;
      for (std::size_t i = 0; i < pa.size() && (!best || pa[i].t0 < best->time_s); ++i) {
        const MotionPiece& p = pa[i];
        while (first < pb.size() && pb[first].t1 + slack_s < p.t0) ++first;
        for (std::size_t j = first; j < pb.size() && pb[j].t0 <= p.t1 + slack_s; ++j) {
          const MotionPiece& q = pb[j];
          const double when = std::max(p.t0, q.t0);
          if (best && when >= best->time_s) {
            if (q.t0 >= best->time_s) break;  // so is every later piece of b
            continue;
          }
          if (segmentBoxesDistance(p.a, p.b, q.a, q.b) >= separation_m) continue;
          const double d = segmentSegmentDistance(p.a, p.b, q.a, q.b);
          if (d >= separation_m) continue;
          best = FleetConflict{
              static_cast<int>(a), static_cast<int>(b), p.sortie, q.sortie, i, j, when, d};
        }
      }
    }
  }
  return best;
}

std::vector<std::vector<MotionPiece>> fleetMotion(const FleetPlan& plan) {
  std::vector<std::vector<MotionPiece>> out;
  for (const auto& u : plan.uavs) {
    std::vector<MotionPiece> motion;
    for (std::size_t s = 0; s < u.flight.sorties.size(); ++s) {
      const Sortie& sortie = u.flight.sorties[s];
      std::vector<std::size_t> at;
      for (const auto& st : sortie.stops) at.push_back(st.waypoint);
      const auto pieces =
          sortieMotion(sortie.waypoints, at, plan.model, plan.options.takeoff_landing_s,
                       u.sortie_start_s.at(s), static_cast<int>(s));
      motion.insert(motion.end(), pieces.begin(), pieces.end());
    }
    out.push_back(std::move(motion));
  }
  return out;
}

}  // namespace uavip::planning
