// The site's fleet (app/site_fleet.h) against independent references: the contiguous
// runs against every split of small instances, and the schedule of two UAVs over
// sections side by side against the separation check and the flights it was given.
#include "uavip/app/site_fleet.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <limits>
#include <random>
#include <vector>

#include "uavip/core/error.h"

namespace uavip::app {
namespace {

/// The latest end of a split (contiguousRuns' cost), computed here.
double latestEnd(const std::vector<double>& seconds, const std::vector<std::size_t>& split,
                 double launch, double swap) {
  double end = 0.0;
  for (std::size_t u = 0; u + 1 < split.size(); ++u) {
    if (split[u + 1] == split[u]) continue;
    double t = static_cast<double>(u) * launch;
    for (std::size_t k = split[u]; k < split[u + 1]; ++k)
      t += seconds[k] + (k > split[u] ? swap : 0.0);
    end = std::max(end, t);
  }
  return end;
}

TEST(ContiguousRuns, OptimalOverEverySplit) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> len(60.0, 900.0);
  for (int trial = 0; trial < 40; ++trial) {
    const int uavs = 2 + trial % 3;
    std::vector<double> seconds(static_cast<std::size_t>(3 + trial % 6));
    for (double& s : seconds) s = len(rng);
    const double launch = trial % 2 == 0 ? 30.0 : 400.0;
    const double swap = trial % 4 < 2 ? 0.0 : 120.0;
    // Every split: non-decreasing cut points between 0 and n.
    double best = std::numeric_limits<double>::infinity();
    std::vector<std::size_t> cut(static_cast<std::size_t>(uavs) + 1, 0);
    cut.back() = seconds.size();
    std::function<void(std::size_t)> enumerate = [&](std::size_t u) {
      if (u == cut.size() - 1) {
        best = std::min(best, latestEnd(seconds, cut, launch, swap));
        return;
      }
      for (std::size_t c = cut[u - 1]; c <= seconds.size(); ++c) {
        cut[u] = c;
        enumerate(u + 1);
      }
    };
    enumerate(1);
    const auto split = contiguousRuns(seconds, uavs, launch, swap);
    ASSERT_EQ(split.size(), static_cast<std::size_t>(uavs) + 1);
    EXPECT_EQ(split.front(), 0U);
    EXPECT_EQ(split.back(), seconds.size());
    EXPECT_TRUE(std::is_sorted(split.begin(), split.end()));
    EXPECT_NEAR(latestEnd(seconds, split, launch, swap), best, 1e-9) << "trial " << trial;
  }
}

/// A sortie from `home` over a row of stops at x0..x1 (y = 0, z = 5) and back.
planning::Sortie rowSortie(const Vec3& home, double x0, double x1) {
  planning::Sortie s;
  s.waypoints.push_back(home);
  for (double x = x0; x <= x1 + 1e-9; x += 2.0) {
    s.stops.push_back({0, static_cast<int>(s.stops.size()), s.waypoints.size()});
    s.waypoints.emplace_back(x, 0.0, 5.0);
  }
  s.waypoints.push_back(home);
  return s;
}

// Two sections 60 m apart, two sorties each: two UAVs fly one section each, at once,
// every sortie once, kept apart, and sooner than one UAV; homes given are refused.
TEST(SiteFleet, SectionsSideBySideFlyAtOnce) {
  planning::FlightPlan a, b;
  for (auto* f : {&a, &b}) f->status = planning::FlightPlan::Status::Ok;
  a.home = Vec3(0, -10, 0);
  b.home = Vec3(60, -10, 0);
  a.sorties = {rowSortie(a.home, 0, 20), rowSortie(a.home, 22, 40)};
  b.sorties = {rowSortie(b.home, 60, 80), rowSortie(b.home, 82, 100)};
  planning::FleetOptions fleet;
  fleet.uavs = 2;
  const planning::FlightModel model;
  const SiteFleet f = planSiteFleet({&a, &b}, fleet, model);
  ASSERT_EQ(f.runs.size(), 2U);
  EXPECT_EQ(f.uavs_flying, 2U);
  std::vector<int> flown(4, 0);
  for (const auto& run : f.runs)
    for (const SiteSortie& s : run) ++flown[s.section * 2 + s.sortie];
  EXPECT_EQ(flown, std::vector<int>(4, 1));
  EXPECT_FALSE(f.plan.fallback_single);
  // The sections mirror each other: UAV 2 lands half the work after its launch.
  EXPECT_EQ(f.plan.waits, 0U);
  EXPECT_NEAR(f.plan.makespan_s, 0.5 * f.plan.single_uav_s + fleet.launch_interval_s, 1e-6);
  EXPECT_GE(f.plan.makespan_s, f.plan.lower_bound_s);
  const auto check =
      planning::checkSeparation(planning::fleetMotion(f.plan), fleet.separation_m, fleet.slack_s);
  EXPECT_FALSE(check.conflict.has_value());
  EXPECT_GE(check.swept_min_m, fleet.separation_m);

  fleet.homes = {Vec3(0, -20, 0), Vec3(20, -20, 0)};
  EXPECT_THROW(planSiteFleet({&a, &b}, fleet, model), InputError);
  fleet.homes.clear();
  fleet.uavs = 43;  // more UAVs than the 42 photo stops
  EXPECT_THROW(planSiteFleet({&a, &b}, fleet, model), InputError);
}

}  // namespace
}  // namespace uavip::app
