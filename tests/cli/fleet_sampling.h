#pragma once
// A fleet's motion rebuilt by the tests themselves from a `fleet` block's waypoints,
// stops, take-off times and flight model (mission.json's shape), and the brute-force
// closest approach of two UAVs over sampled times and delays: the reference the
// planner's exact separation check is tested against.

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <vector>

namespace uavip::cli_test {

/// One UAV's airborne motion rebuilt here from mission.json's waypoints, stops, take-off
/// times and flight model (not the planner's times): pieces (t0, t1, a, b).
struct Piece {
  double t0, t1;
  std::array<double, 3> a, b;
};
inline std::vector<Piece> rebuildMotion(const nlohmann::json& uav, const nlohmann::json& fleet) {
  const auto& m = fleet["model"];
  const double stop_s = m["hover_s"].get<double>() + m["settle_s"].get<double>();
  const double half = 0.5 * fleet["options"]["takeoff_landing_s"].get<double>();
  std::vector<Piece> out;
  for (const auto& s : uav["sorties"]) {
    const auto& w = s["waypoints"];
    std::vector<int> hovers(w.size(), 0);
    for (const auto& st : s["stops"]) ++hovers[st["waypoint"].get<std::size_t>()];
    double t = s["start_s"].get<double>() + half;
    const std::array<double, 3> home{w[0][0].get<double>(), w[0][1].get<double>(),
                                     w[0][2].get<double>()};
    out.push_back({t - half, t, home, home});  // taking off
    for (std::size_t i = 0; i < w.size(); ++i) {
      const std::array<double, 3> p{w[i][0].get<double>(), w[i][1].get<double>(),
                                    w[i][2].get<double>()};
      out.push_back({t, t + hovers[i] * stop_s, p, p});
      t += hovers[i] * stop_s;
      if (i + 1 == w.size()) break;
      const std::array<double, 3> q{w[i + 1][0].get<double>(), w[i + 1][1].get<double>(),
                                    w[i + 1][2].get<double>()};
      const double dz = q[2] - p[2];
      const double dt =
          std::max(std::hypot(q[0] - p[0], q[1] - p[1]) / m["cruise_speed_m_s"].get<double>(),
                   dz > 0 ? dz / m["climb_speed_m_s"].get<double>()
                          : -dz / m["descent_speed_m_s"].get<double>());
      out.push_back({t, t + dt, p, q});
      t += dt;
    }
    out.back().t1 += half;  // at home until landed
  }
  return out;
}

/// Position at time t, or false when on the ground.
inline bool positionAt(const std::vector<Piece>& motion, double t, std::array<double, 3>& p) {
  for (const Piece& q : motion) {
    if (t < q.t0 || t > q.t1) continue;
    const double s = q.t1 > q.t0 ? (t - q.t0) / (q.t1 - q.t0) : 0.0;
    for (int i = 0; i < 3; ++i) p[i] = q.a[i] + s * (q.b[i] - q.a[i]);
    return true;
  }
  return false;
}

/// Brute force: the least distance of two UAVs over times every 0.25 s, each UAV
/// running late by a constant 0, slack / 2 or slack [m].
inline double sampledClosestApproach(const nlohmann::json& fleet) {
  std::vector<std::vector<Piece>> uavs;
  double end = 0.0;
  for (const auto& u : fleet["uavs"]) {
    uavs.push_back(rebuildMotion(u, fleet));
    if (!uavs.back().empty()) end = std::max(end, uavs.back().back().t1);
  }
  const double slack = fleet["options"]["slack_s"].get<double>();
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t a = 0; a < uavs.size(); ++a)
    for (std::size_t b = a + 1; b < uavs.size(); ++b)
      for (const double da : {0.0, 0.5 * slack, slack})
        for (const double db : {0.0, 0.5 * slack, slack})
          for (double t = 0.0; t <= end + slack; t += 0.25) {
            std::array<double, 3> pa{};
            std::array<double, 3> pb{};
            if (!positionAt(uavs[a], t - da, pa) || !positionAt(uavs[b], t - db, pb)) continue;
            best = std::min(best, std::hypot(pa[0] - pb[0], pa[1] - pb[1], pa[2] - pb[2]));
          }
  return best;
}

}  // namespace uavip::cli_test
