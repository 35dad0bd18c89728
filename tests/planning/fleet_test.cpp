// The fleet's geometry and assignment against independent references: closest
// approach against brute-force sampling (segment distance: tests/core/geometry_test.cpp), the
// separation check on hand-made schedules, the min–max assignment against every assignment.
#include "uavip/planning/fleet.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <random>
#include <vector>

#include "planners/registry.h"
#include "uavip/core/error.h"
#include "uavip/core/geometry.h"
#include "uavip/core/math.h"
#include "uavip/planning/mission_planner.h"

namespace uavip::planning {
namespace {

Vec3 randomPoint(std::mt19937& rng, double half) {
  std::uniform_real_distribution<double> d(-half, half);
  const double x = d(rng);
  const double y = d(rng);
  const double z = d(rng);
  return {x, y, z};
}

TEST(ClosestApproach, MatchesBruteForceSampling) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> time(0.0, 10.0);
  for (int trial = 0; trial < 300; ++trial) {
    MotionPiece p{randomPoint(rng, 10.0), randomPoint(rng, 10.0), time(rng), 0.0, 0};
    p.t1 = p.t0 + time(rng);
    MotionPiece q{randomPoint(rng, 10.0), randomPoint(rng, 10.0), time(rng), 0.0, 0};
    q.t1 = q.t0 + time(rng);
    if (trial % 10 == 0) q.b = q.a;  // one stays put
    const auto exact = closestApproach(p, q);
    const double lo = std::max(p.t0, q.t0);
    const double hi = std::min(p.t1, q.t1);
    if (lo > hi) {
      EXPECT_FALSE(exact);
      continue;
    }
    ASSERT_TRUE(exact);
    double best = kInf;
    const int n = 20000;
    for (int i = 0; i <= n; ++i) {
      const double t = lo + (hi - lo) * i / n;
      const Vec3 a = p.a + (p.b - p.a) * (t - p.t0) / (p.t1 - p.t0);
      const Vec3 b = q.a + (q.b - q.a) * (t - q.t0) / (q.t1 - q.t0);
      best = std::min(best, (a - b).norm());
    }
    EXPECT_LE(exact->distance_m, best + 1e-9);
    EXPECT_NEAR(exact->distance_m, best, 0.01);  // relative speeds ≤ ~30 m/s, dt ≤ 5e-4 s
    EXPECT_GE(exact->time_s, lo - 1e-12);
    EXPECT_LE(exact->time_s, hi + 1e-12);
  }
}

TEST(SortieMotion, TimesFollowTheFlightModel) {
  FlightModel model;
  const PointList w{{0, 0, 0}, {3, 0, 0}, {3, 0, 2}, {0, 0, 0}};
  const auto pieces = sortieMotion(w, {1}, model, 10.0, 100.0, 0);
  // take-off 5 s, 1 s flight, 3 s photo, 1 s climb, 1.33 s back, landing 5 s.
  ASSERT_EQ(pieces.size(), 6U);
  EXPECT_DOUBLE_EQ(pieces.front().t0, 100.0);
  EXPECT_DOUBLE_EQ(pieces[0].t1, 105.0);
  EXPECT_DOUBLE_EQ(pieces[1].t1, 106.0);
  EXPECT_DOUBLE_EQ(pieces[2].t1, 109.0);
  EXPECT_EQ(pieces[2].a, pieces[2].b);
  // The way back: 3 m across (1 s) and 2 m down at 1.5 m/s (4/3 s): the slower counts.
  EXPECT_NEAR(pieces.back().t1, 100.0 + 10.0 + 1.0 + 3.0 + 1.0 + 4.0 / 3.0, 1e-9);
}

/// Two UAVs crossing at the origin: A along x, B along y, both at t ∈ [0, 10].
std::vector<std::vector<MotionPiece>> crossing(double b_start) {
  return {{{Vec3(-15, 0, 0), Vec3(15, 0, 0), 0.0, 10.0, 0}},
          {{Vec3(0, -15, 0), Vec3(0, 15, 0), b_start, b_start + 10.0, 0}}};
}

TEST(Separation, CrossingConflictsAndItsRepairPasses) {
  const SeparationCheck bad = checkSeparation(crossing(0.0), 5.0, 0.0);
  ASSERT_TRUE(bad.conflict);
  EXPECT_EQ(bad.conflict->uav_a, 0);
  EXPECT_EQ(bad.conflict->uav_b, 1);
  EXPECT_NEAR(bad.nominal_min_m, 0.0, 1e-9);
  EXPECT_NEAR(bad.nominal_time_s, 5.0, 1e-9);
  // B waits until A has gone: windows no longer overlap.
  const SeparationCheck repaired = checkSeparation(crossing(10.5), 5.0, 0.0);
  EXPECT_FALSE(repaired.conflict);
  // With 1 s of slack the same schedule may still conflict; with the wait past the
  // slack it does not.
  EXPECT_TRUE(checkSeparation(crossing(10.5), 5.0, 1.0).conflict);
  EXPECT_FALSE(checkSeparation(crossing(11.5), 5.0, 1.0).conflict);
}

TEST(Separation, ParallelTracksApartPass) {
  const std::vector<std::vector<MotionPiece>> uavs{{{Vec3(0, 0, 0), Vec3(30, 0, 0), 0.0, 10.0, 0}},
                                                   {{Vec3(0, 6, 0), Vec3(30, 6, 0), 0.0, 10.0, 0}}};
  const SeparationCheck c = checkSeparation(uavs, 5.0, 60.0);
  EXPECT_FALSE(c.conflict);
  EXPECT_NEAR(c.swept_min_m, 6.0, 1e-9);
  EXPECT_TRUE(checkSeparation(uavs, 6.5, 0.0).conflict);
}

/// A UAV's motion in time order: `n` contiguous pieces (every third a hover) from t0,
/// a gap of a few seconds (on the ground) every seventh piece, inside a cube of 2 × half
/// centred at `centre`.
std::vector<MotionPiece> randomMotion(std::mt19937& rng, const Vec3& centre, double half, double t0,
                                      int n) {
  std::uniform_real_distribution<double> dt(0.5, 6.0);
  std::vector<MotionPiece> out;
  Vec3 at = centre + randomPoint(rng, half);
  double t = t0;
  for (int i = 0; i < n; ++i) {
    if (i % 7 == 6) t += dt(rng);
    const Vec3 to = i % 3 == 2 ? at : Vec3(centre + randomPoint(rng, half));
    const double d = dt(rng);
    out.push_back({at, to, t, t + d, i / 7});
    at = to;
    t += d;
  }
  return out;
}

TEST(Separation, FirstConflictAndLeastDistancesMatchEveryPair) {
  std::mt19937 rng(11);
  int conflicts = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const double sep = 2.0 + 0.1 * (trial % 30);
    const double slack = trial % 3 == 0 ? 0.0 : 5.0 * (trial % 4);
    std::vector<std::vector<MotionPiece>> uavs;
    uavs.reserve(3);
    const double apart = 12.0 + 3.0 * (trial % 5);  // cubes of 20 m: 8 m overlap to 4 m apart
    for (int u = 0; u < 3; ++u)
      uavs.push_back(randomMotion(rng, Vec3(apart * u, 0, 0), 10.0, 10.0 * u, 30));
    // Every pair of pieces whose widened windows overlap, in (a, b, i, j) order.
    std::optional<FleetConflict> first;
    double swept = kInf;
    double nominal = kInf;
    for (std::size_t a = 0; a < uavs.size(); ++a)
      for (std::size_t b = a + 1; b < uavs.size(); ++b)
        for (std::size_t i = 0; i < uavs[a].size(); ++i)
          for (std::size_t j = 0; j < uavs[b].size(); ++j) {
            const MotionPiece& p = uavs[a][i];
            const MotionPiece& q = uavs[b][j];
            if (p.t0 > q.t1 + slack || q.t0 > p.t1 + slack) continue;
            const double d = segmentSegmentDistance(p.a, p.b, q.a, q.b);
            swept = std::min(swept, d);
            if (const auto c = closestApproach(p, q)) nominal = std::min(nominal, c->distance_m);
            const double when = std::max(p.t0, q.t0);
            if (d < sep && (!first || when < first->time_s))
              first = FleetConflict{static_cast<int>(a), static_cast<int>(b), 0, 0, i, j, when, d};
          }
    const SeparationCheck full = checkSeparation(uavs, sep, slack);
    const auto quick = firstConflict(uavs, sep, slack);
    EXPECT_NEAR(full.swept_min_m, swept, 1e-12) << trial;
    EXPECT_NEAR(full.nominal_min_m, nominal, 1e-12) << trial;
    ASSERT_EQ(first.has_value(), full.conflict.has_value()) << trial;
    ASSERT_EQ(first.has_value(), quick.has_value()) << trial;
    if (!first) continue;
    ++conflicts;
    for (const auto& c : {*full.conflict, *quick}) {
      EXPECT_EQ(c.uav_a, first->uav_a) << trial;
      EXPECT_EQ(c.uav_b, first->uav_b) << trial;
      EXPECT_EQ(c.piece_a, first->piece_a) << trial;
      EXPECT_EQ(c.piece_b, first->piece_b) << trial;
      EXPECT_DOUBLE_EQ(c.time_s, first->time_s) << trial;
    }
  }
  EXPECT_GT(conflicts, 10);  // the cases exercise both outcomes
  EXPECT_LT(conflicts, 60);
}

/// The least makespan over every assignment (additive job costs plus an offset per UAV).
double bruteForce(int uavs, const std::vector<double>& jobs, const std::vector<double>& offset) {
  const auto n = jobs.size();
  std::vector<int> owner(n, 0);
  double best = kInf;
  for (;;) {
    std::vector<double> load(static_cast<std::size_t>(uavs), 0.0);
    std::vector<bool> used(static_cast<std::size_t>(uavs), false);
    for (std::size_t j = 0; j < n; ++j) {
      load[static_cast<std::size_t>(owner[j])] += jobs[j];
      used[static_cast<std::size_t>(owner[j])] = true;
    }
    double m = 0.0;
    for (int u = 0; u < uavs; ++u)
      if (used[static_cast<std::size_t>(u)])
        m = std::max(m, load[static_cast<std::size_t>(u)] + offset[static_cast<std::size_t>(u)]);
    best = std::min(best, m);
    std::size_t k = 0;
    while (k < n && ++owner[k] == uavs) owner[k++] = 0;
    if (k == n) return best;
  }
}

TEST(AssignMinMax, WithinFivePercentOfTheOptimum) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> seconds(60.0, 900.0);
  for (int trial = 0; trial < 40; ++trial) {
    const int uavs = 2 + trial % 2;
    std::vector<double> jobs(8);
    for (auto& j : jobs) j = seconds(rng);
    std::vector<double> offset(static_cast<std::size_t>(uavs));
    for (int u = 0; u < uavs; ++u) offset[static_cast<std::size_t>(u)] = 30.0 * u;
    const auto cost = [&](int u, const std::vector<int>& set) {
      if (set.empty()) return 0.0;
      double t = offset[static_cast<std::size_t>(u)];
      for (const int j : set) t += jobs[static_cast<std::size_t>(j)];
      return t;
    };
    const std::vector<int> owner = assignMinMax(uavs, jobs, cost);
    std::vector<std::vector<int>> sets(static_cast<std::size_t>(uavs));
    for (std::size_t j = 0; j < jobs.size(); ++j)
      sets[static_cast<std::size_t>(owner[j])].push_back(static_cast<int>(j));
    double makespan = 0.0;
    for (int u = 0; u < uavs; ++u)
      makespan = std::max(makespan, cost(u, sets[static_cast<std::size_t>(u)]));
    const double optimum = bruteForce(uavs, jobs, offset);
    EXPECT_GE(makespan, optimum - 1e-9);
    EXPECT_LE(makespan, 1.05 * optimum) << "trial " << trial << ", " << uavs << " UAVs";
  }
}

TEST(FleetLowerBound, KnownGeometry) {
  FlightModel model;  // 3 m/s horizontal, 3 s per photo
  FleetOptions fleet;
  fleet.uavs = 2;
  fleet.launch_interval_s = 30.0;
  // Four stops 3 m apart on a line from a home 3 m before the first.
  const PointList stops{{3, 0, 0}, {6, 0, 0}, {9, 0, 0}, {12, 0, 0}};
  const FleetBound b = fleetLowerBound(stops, {Vec3(0, 0, 0)}, model, fleet);
  EXPECT_NEAR(b.work_s, 4 * (3.0 + 1.0), 1e-9);
  EXPECT_NEAR(b.round_trip_s, 2 * 4.0 + 3.0, 1e-9);
  // min((16 + 0) / 1, (16 + 30) / 2) = 16 > the round trip 11.
  EXPECT_NEAR(b.bound_s, 16.0, 1e-9);
}

// The work W takes each stop's fastest approach from a kd-tree's radius search; the
// reference is every other stop and home tried, on clouds with duplicates and with
// climbs and descents slower than the cruise.
TEST(FleetLowerBound, WorkMatchesEveryPairTried) {
  std::mt19937 rng(45);
  FlightModel model;
  model.climb_speed_m_s = 0.7;
  model.descent_speed_m_s = 4.0;
  FleetOptions fleet;
  fleet.uavs = 3;
  for (int trial = 0; trial < 20; ++trial) {
    PointList stops;
    for (int i = 0; i < 60 + 7 * trial; ++i) stops.push_back(randomPoint(rng, 20.0));
    stops.push_back(stops[5]);  // a duplicate: reached in no time
    const PointList homes{randomPoint(rng, 30.0), randomPoint(rng, 30.0)};
    double work = 0.0;
    for (std::size_t i = 0; i < stops.size(); ++i) {
      double reach = kInf;
      for (const Vec3& h : homes) reach = std::min(reach, model.segmentSeconds(h, stops[i]));
      for (std::size_t k = 0; k < stops.size(); ++k)
        if (k != i) reach = std::min(reach, model.segmentSeconds(stops[k], stops[i]));
      work += model.stopSeconds() + reach;
    }
    EXPECT_NEAR(fleetLowerBound(stops, homes, model, fleet).work_s, work, 1e-9 * work)
        << "trial " << trial;
  }
  // One stop: reached from a home only.
  const FleetBound one = fleetLowerBound({Vec3(6, 0, 0)}, {Vec3(0, 0, 0)}, model, fleet);
  EXPECT_NEAR(one.work_s, 2.0 + model.stopSeconds(), 1e-12);
}

TEST(FleetOptions, RefusesHomesTooCloseOrMiscounted) {
  FleetOptions o;
  o.uavs = 2;
  o.homes = {Vec3(0, 0, 0), Vec3(3, 0, 0)};
  EXPECT_THROW(o.validate(), InputError);
  o.homes = {Vec3(0, 0, 0)};
  EXPECT_THROW(o.validate(), InputError);
  o.homes = {Vec3(0, 0, 0), Vec3(6, 0, 0)};
  EXPECT_NO_THROW(o.validate());
  o.uavs = 0;
  o.homes.clear();
  EXPECT_THROW(o.validate(), InputError);
}

/// The least makespan of K UAVs over `stops`, by brute force: every assignment of the
/// stops to the UAVs and, for each UAV, every order of its stops (Held–Karp over
/// subsets, exact), under the flight model with straight legs — UAV u takes off from
/// homes[u] at u × launch_interval, flies its stops in one sortie (hover + settle at
/// each) and lands at its home; an idle UAV does not count. Separation is left out, so
/// this is a lower bound on the optimum with it.
double bruteForceMakespan(const PointList& stops, const PointList& homes, const FlightModel& model,
                          double launch_interval_s) {
  const std::size_t n = stops.size(), k = homes.size(), full = std::size_t{1} << n;
  // tour[u][mask]: UAV u's least time home → the stops of mask (any order) → home [s].
  std::vector<std::vector<double>> tour(k, std::vector<double>(full, kInf));
  for (std::size_t u = 0; u < k; ++u) {
    // path[mask][j]: home → stops of mask, ending at j ∈ mask.
    std::vector<std::vector<double>> path(full, std::vector<double>(n, kInf));
    for (std::size_t j = 0; j < n; ++j)
      path[std::size_t{1} << j][j] = model.segmentSeconds(homes[u], stops[j]) + model.stopSeconds();
    for (std::size_t mask = 1; mask < full; ++mask)
      for (std::size_t j = 0; j < n; ++j) {
        if (!(mask >> j & 1U) || !std::isfinite(path[mask][j])) continue;
        for (std::size_t i = 0; i < n; ++i) {
          if (mask >> i & 1U) continue;
          const double t =
              path[mask][j] + model.segmentSeconds(stops[j], stops[i]) + model.stopSeconds();
          double& to = path[mask | std::size_t{1} << i][i];
          to = std::min(to, t);
        }
      }
    tour[u][0] = 0.0;
    for (std::size_t mask = 1; mask < full; ++mask)
      for (std::size_t j = 0; j < n; ++j)
        if (mask >> j & 1U)
          tour[u][mask] =
              std::min(tour[u][mask], path[mask][j] + model.segmentSeconds(stops[j], homes[u]));
  }
  // Every assignment: owner digits in base K.
  std::vector<std::size_t> owner(n, 0);
  double best = kInf;
  for (;;) {
    std::vector<std::size_t> mask(k, 0);
    for (std::size_t j = 0; j < n; ++j) mask[owner[j]] |= std::size_t{1} << j;
    double m = 0.0;
    for (std::size_t u = 0; u < k; ++u)
      if (mask[u] != 0)
        m = std::max(m, static_cast<double>(u) * launch_interval_s + tour[u][mask[u]]);
    best = std::min(best, m);
    std::size_t d = 0;
    while (d < n && ++owner[d] == k) owner[d++] = 0;
    if (d == n) return best;
  }
}

/// One photo stop as its own surface (a job the planner may give any UAV).
coverage::FlightStrategy oneStop(int id, const Vec3& p) {
  coverage::FlightStrategy s;
  s.surface_id = id;
  coverage::Stop stop;
  stop.surface_id = id;
  stop.position = p;
  stop.target = p - Vec3(0.0, 0.0, 2.0);
  stop.gimbal_pitch_deg = -90.0;
  s.stops.push_back(stop);
  return s;
}

// Issue 45, "tests against independent references": on 12 instances of 6–8 stops in
// open air (a post far off the way is the only obstacle), K = 2 and 3, planFleet's
// makespan lies within 5 % of the brute-force optimum of every assignment and order
// under the same flight model, and never below it.
TEST(PlanFleet, WithinFivePercentOfTheExhaustiveOptimum) {
  std::mt19937 rng(45);
  std::uniform_real_distribution<double> xy(-25.0, 25.0), z(4.0, 14.0);
  PointList post;  // the only cloud: a post 60 m off
  for (double h = 0.0; h <= 3.0; h += 0.25) post.emplace_back(60.0, 60.0, h);
  const FlightModel model;
  int instances = 0;
  double worst = 0.0;
  for (int trial = 0; trial < 12; ++trial) {
    const int uavs = 2 + trial % 2;
    const std::size_t n = 6 + static_cast<std::size_t>(trial % 3);
    PointList stops;
    for (std::size_t j = 0; j < n; ++j) stops.emplace_back(xy(rng), xy(rng), z(rng));
    FleetOptions fleet;
    fleet.uavs = uavs;
    fleet.launch_interval_s = 10.0;
    fleet.slack_s = 0.0;  // the reference flies to the clock
    // The reference leaves the separation out: the least the check allows (twice the
    // inflation radius), so that the comparison is of assignment and order. (With 5 m,
    // the conservative swept-segment rule adds waits on this 50 m site: up to 1.35 ×.)
    fleet.separation_m = 1.01;
    for (int u = 0; u < uavs; ++u) fleet.homes.emplace_back(-4.0 + 8.0 * u, -32.0, 1.0);
    std::vector<coverage::FlightStrategy> strategies;
    PointList extra = fleet.homes;
    for (std::size_t j = 0; j < n; ++j) {
      strategies.push_back(oneStop(static_cast<int>(j), stops[j]));
      extra.push_back(stops[j]);
    }
    world::GridOptions go;
    go.resolution_m = 0.5;
    go.inflation_radius_m = 0.5;
    go.padding_m = 3.0;
    const world::VoxelGrid grid = world::VoxelGrid::build(post, extra, go);
    const PathValidator validator(post, 0.5);
    const std::unique_ptr<Planner> planner = planners::makePlanner("astar", {});
    std::vector<SurfaceMission> missions;
    missions.reserve(strategies.size());
    for (const auto& s : strategies)
      missions.push_back(planSurfaceMission(s, grid, validator, *planner, MissionOptions{}));
    FlightOptions flight;
    flight.home = fleet.homes.front();
    flight.model = model;
    const FlightPlan single = planFlight(missions, grid, validator, *planner, flight);
    ASSERT_EQ(single.status, FlightPlan::Status::Ok) << single.reason;
    const FleetPlan plan = planFleet(missions, single, grid, validator, *planner, flight, fleet);
    ASSERT_EQ(plan.status, FleetPlan::Status::Ok) << plan.reason;
    EXPECT_FALSE(plan.separation.conflict);
    const double optimum = bruteForceMakespan(stops, fleet.homes, model, fleet.launch_interval_s);
    ++instances;
    worst = std::max(worst, plan.makespan_s / optimum);
    EXPECT_GE(plan.makespan_s, optimum - 1e-6) << "trial " << trial;
    EXPECT_LE(plan.makespan_s, 1.05 * optimum)
        << "trial " << trial << ": " << n << " stops, " << uavs << " UAVs, assignment "
        << plan.assignment << ", " << plan.waits << " waits, fallback " << plan.fallback_single
        << ", single " << plan.single_uav_s << " s, swept " << plan.separation.swept_min_m;
  }
  std::cout << instances << " instances: planFleet / exhaustive optimum at most " << worst << "\n";
}

}  // namespace
}  // namespace uavip::planning
