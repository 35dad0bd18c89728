// The fleet's geometry and assignment against independent references: closest
// approach against brute-force sampling (segment distance: tests/core/geometry_test.cpp), the
// separation check on hand-made schedules, the min–max assignment against every assignment.
#include "uavip/planning/fleet.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "uavip/core/error.h"
#include "uavip/core/math.h"

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
    std::vector<double> offset;
    for (int u = 0; u < uavs; ++u) offset.push_back(30.0 * u);
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

}  // namespace
}  // namespace uavip::planning
