#include "uavip/app/site_fleet.h"

#include <algorithm>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "uavip/core/error.h"
#include "uavip/core/stopwatch.h"
#include "uavip/core/text.h"
#include "uavip/planning/fleet.h"

namespace uavip::app {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// The site's sorties in order, with what the plan needs of them.
struct SiteSorties {
  std::vector<SiteSortie> order;
  std::vector<planning::Sortie> sorties;  ///< durations from the model
  std::vector<double> seconds;            ///< each with its take-off/landing [s]
  PointList stops;                        ///< every photo stop's position
  PointList homes;                        ///< each flying section's home
};

SiteSorties siteSorties(const std::vector<const planning::FlightPlan*>& flights,
                        const planning::FleetOptions& fleet, const planning::FlightModel& model) {
  SiteSorties out;
  for (std::size_t s = 0; s < flights.size(); ++s) {
    const planning::FlightPlan* f = flights[s];
    if (f == nullptr || f->status != planning::FlightPlan::Status::Ok || f->sorties.empty())
      continue;
    out.homes.push_back(f->home);
    for (std::size_t k = 0; k < f->sorties.size(); ++k) {
      planning::Sortie copy = f->sorties[k];
      copy.duration_s = planning::sortieSeconds(copy, model);  // joined results carry none
      for (const auto& st : copy.stops) out.stops.push_back(copy.waypoints.at(st.waypoint));
      out.order.push_back({s, k});
      out.seconds.push_back(copy.duration_s + fleet.takeoff_landing_s);
      out.sorties.push_back(std::move(copy));
    }
  }
  return out;
}

/// The runs in the order `scheduled` flies each UAV's sorties (scheduleFlights with
/// any order reorders them; `planned` holds them in the runs' order).
void reorderRuns(const planning::FleetPlan& scheduled, const planning::FleetPlan& planned,
                 std::vector<std::vector<SiteSortie>>& runs) {
  for (std::size_t u = 0; u < runs.size(); ++u) {
    const auto& from = planned.uavs[u].flight.sorties;
    std::vector<SiteSortie> order;
    std::vector<bool> used(from.size(), false);
    for (const auto& s : scheduled.uavs[u].flight.sorties)
      for (std::size_t k = 0; k < from.size(); ++k)
        if (!used[k] && from[k].waypoints == s.waypoints) {
          used[k] = true;
          order.push_back(runs[u][k]);
          break;
        }
    runs[u] = std::move(order);
  }
}

}  // namespace

void refuseFleetHomes(const planning::FleetOptions& fleet, std::size_t sections) {
  if (sections <= 1 || fleet.homes.empty()) return;
  using planning::FleetOptions;
  throw InputError("fleet." + FleetOptions::keyOf(&FleetOptions::homes) + ": a site of " +
                   std::to_string(sections) +
                   " sections flies each section's sorties from that section's own home; "
                   "leave the homes out, or merge the site as one section (--section-tiles)");
}

std::vector<std::size_t> contiguousRuns(const std::vector<double>& seconds, int uavs,
                                        double launch_interval_s, double battery_swap_s) {
  const std::size_t n = seconds.size();
  const auto k = static_cast<std::size_t>(std::max(uavs, 1));
  std::vector<double> prefix(n + 1, 0.0);
  for (std::size_t i = 0; i < n; ++i) prefix[i + 1] = prefix[i] + seconds[i];
  const auto cost = [&](std::size_t u, std::size_t i, std::size_t j) {
    if (j == i) return 0.0;
    return static_cast<double>(u) * launch_interval_s + prefix[j] - prefix[i] +
           static_cast<double>(j - i - 1) * battery_swap_s;
  };
  // best[u][j]: the least latest end of UAVs 0..u over sorties [0, j); from[u][j] the
  // start of UAV u's run there.
  std::vector<std::vector<double>> best(k, std::vector<double>(n + 1, kInf));
  std::vector<std::vector<std::size_t>> from(k, std::vector<std::size_t>(n + 1, 0));
  for (std::size_t j = 0; j <= n; ++j) best[0][j] = cost(0, 0, j);
  for (std::size_t u = 1; u < k; ++u)
    for (std::size_t j = 0; j <= n; ++j)
      for (std::size_t i = 0; i <= j; ++i) {
        const double end = std::max(best[u - 1][i], cost(u, i, j));
        if (end < best[u][j]) {
          best[u][j] = end;
          from[u][j] = i;
        }
      }
  std::vector<std::size_t> split(k + 1, n);
  split[0] = 0;
  for (std::size_t u = k - 1; u > 0; --u) split[u] = from[u][split[u + 1]];
  return split;
}

SiteFleet planSiteFleet(const std::vector<const planning::FlightPlan*>& flights,
                        const planning::FleetOptions& fleet, const planning::FlightModel& model) {
  const auto t0 = SteadyClock::now();
  fleet.validate("fleet");
  refuseFleetHomes(fleet, flights.size());
  SiteSorties all = siteSorties(flights, fleet, model);
  if (all.stops.size() < static_cast<std::size_t>(fleet.uavs))
    throw InputError("fleet: uavs " + std::to_string(fleet.uavs) + " is more than the " +
                     std::to_string(all.stops.size()) +
                     " photo stops of the site; use at most one UAV per stop");
  SiteFleet out;
  planning::FleetPlan& plan = out.plan;
  plan.options = fleet;
  plan.model = model;
  for (const double s : all.seconds) plan.single_uav_s += s;
  if (!all.seconds.empty())
    plan.single_uav_s += static_cast<double>(all.seconds.size() - 1) * fleet.battery_swap_s;
  const planning::FleetBound bound = planning::fleetLowerBound(all.stops, all.homes, model, fleet);
  plan.work_s = bound.work_s;
  plan.lower_bound_s = bound.bound_s;
  plan.jobs = all.sorties.size();
  plan.assignment = "contiguous runs of the sections' sorties";
  plan.candidates = 1;

  const auto fly = [&](const std::vector<std::size_t>& split) {
    plan.uavs.assign(static_cast<std::size_t>(fleet.uavs), planning::FleetUav{});
    out.runs.assign(plan.uavs.size(), {});
    out.uavs_flying = 0;
    for (std::size_t u = 0; u < plan.uavs.size(); ++u) {
      planning::FleetUav& uav = plan.uavs[u];
      uav.flight.status = planning::FlightPlan::Status::Ok;
      for (std::size_t k = split[u]; k < split[u + 1]; ++k) {
        uav.flight.sorties.push_back(all.sorties[k]);
        uav.flight.duration_s += all.sorties[k].duration_s;
        uav.flight.length_m += all.sorties[k].length_m;
        uav.stops += all.sorties[k].stops.size();
        out.runs[u].push_back(all.order[k]);
      }
      const bool flies = split[u + 1] > split[u];
      out.uavs_flying += flies;
      uav.home = flies ? all.sorties[split[u]].waypoints.front() : all.homes.front();
      uav.flight.home = uav.home;
      uav.home_source = flies ? "section " + std::to_string(out.runs[u].front().section) +
                                    "'s home (its first sortie)"
                              : "idle";
    }
    // Each UAV's sorties in the site's order, or in any order (whichever can take off
    // earliest): the sooner conflict-free schedule, in order on a tie.
    planning::FleetPlan any = plan;
    const bool in_order = planning::scheduleFlights(plan);
    if (planning::scheduleFlights(any, true) && (!in_order || any.makespan_s < plan.makespan_s)) {
      reorderRuns(any, plan, out.runs);
      plan = std::move(any);
      return true;
    }
    return in_order;
  };
  const bool ok =
      fly(contiguousRuns(all.seconds, fleet.uavs, fleet.launch_interval_s, fleet.battery_swap_s));
  if (!ok || plan.makespan_s >= plan.single_uav_s) {  // never slower than one UAV
    std::vector<std::size_t> alone(static_cast<std::size_t>(fleet.uavs) + 1, all.sorties.size());
    alone[0] = 0;
    fly(alone);
    plan.fallback_single = true;
    plan.assignment = "UAV 1 alone (the fleet was no faster)";
  }
  plan.seconds = secondsSince(t0);
  return out;
}

}  // namespace uavip::app
