// uavip_fcplanner_compare [DATA_DIR] -o OUT: structure coverage (plan --cover
// structure) against FC-Planner's published table on its own three clouds, with its
// settings (camera, visible range, viewpoint distance, drone radius, start, ground).
// For each scene: the whole chain from the cloud in memory to the validated flight,
// median of 3 runs (views off); then, once, the scores: photos, path from home to the
// last photo (no return, as theirs), coverage by rule (a) (their pixel rule, on the
// dense cloud they score on, at our photo stops only) and rule (b) (ours), and the
// minimum distance from the flight to every input point. Writes OUT/<scene>/scene.json,
// OUT/<scene>/mission.json, OUT/results.json and OUT/results.md.
// DATA_DIR defaults to ../shared/data/real from the repository root.

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "bench_util.h"
#include "uavip/app/pipeline.h"
#include "uavip/app/scenario.h"
#include "uavip/core/error.h"
#include "uavip/core/geometry.h"
#include "uavip/core/neighbour_index.h"
#include "uavip/core/stopwatch.h"
#include "uavip/coverage/pixel_coverage.h"
#include "uavip/io/atomic_file.h"
#include "uavip/io/cloud_io.h"
#include "uavip/io/mission_json.h"
#include "uavip/io/scene_json.h"

namespace fs = std::filesystem;
using namespace uavip;

namespace {

/// One scene of FC-Planner's table: its files, settings and published numbers.
struct Peer {
  std::string name, cloud, dense;
  double visible_range_m, standoff_m;
  Vec3 start;
  std::optional<double> ground_z_m;
  // FC-Planner (ICRA 2024, table II) and SIP on the same clouds.
  double fc_time_s, fc_path_m, fc_coverage;
  int fc_views;
  double sip_time_s, sip_path_m, sip_coverage;
  int sip_views;
};

const std::vector<Peer> kPeers = {
    {"MBS",
     "fcplanner_MBS.pcd",
     "fcplanner_MBSmore.pcd",
     11.0,
     8.0,
     {0, 20, -13},
     -10.5,
     0.95,
     1396.2,
     0.940,
     185,
     131.5,
     1635.5,
     0.685,
     1770},
    {"christ",
     "fcplanner_christ.pcd",
     "fcplanner_christmore.pcd",
     8.0,
     6.0,
     {10, 0, 0},
     -7.4,
     0.51,
     530.4,
     0.997,
     111,
     62.1,
     700.5,
     0.859,
     787},
    {"pipe",
     "fcplanner_pipe.pcd",
     "fcplanner_pipe.pcd",
     11.0,
     8.0,
     {0, 0, 0},
     std::nullopt,
     1.61,
     1440.4,
     0.975,
     210,
     235.0,
     2754.1,
     0.692,
     3078},
};

/// Their settings as a uavip config: pinhole 640 × 480, drone radius 0.3 m, gimbal
/// −85° to +70°, no photo overlap asked (their coverage rule has none), one sortie
/// (no battery limit), home at their start.
app::Config peerConfig(const Peer& p, bool with_start, double target) {
  std::ostringstream y;
  y << "camera: {fx: 417.0467, fy: 461.0951, cx: 320, cy: 240, image_px: [640, 480], max_range_m: "
    << p.visible_range_m << "}\n"
    << "coverage: {mode: structure, standoff_m: " << p.standoff_m << ", gimbal_pitch_deg: [-85, 70]"
    << ", structure_target: " << target << ", overlap: 0"
    << (p.ground_z_m ? ", ground_z_m: " + std::to_string(*p.ground_z_m) : std::string()) << "}\n"
    << "uav: {inflation_radius_m: 0.3}\n"
    << "flight: {endurance_s: 1000000}\n";
  if (with_start)
    y << "mission: {start: [" << p.start.x() << ", " << p.start.y() << ", " << p.start.z()
      << "]}\n";
  return app::parseConfig(y.str(), "(FC-Planner settings for " + p.name + ")");
}

struct Run {
  app::DetectResult detect;
  app::PlanResult plan;
  double seconds{0.0};
};

Run runChain(const PointList& raw, const app::Config& config) {
  Run r;
  const auto t0 = SteadyClock::now();
  app::CloudIndex index;
  const preprocess::CloudStats measured = app::measure(raw, nullptr, &index);
  r.detect = app::detect(raw, config, measured, {}, index);
  r.plan = app::planStructure(r.detect.scene, r.detect.resolved.config);
  r.seconds = secondsSince(t0);
  return r;
}

/// Flown photo poses of the structure mission.
std::vector<coverage::ViewPose> flownViews(const app::PlanResult& p) {
  std::vector<coverage::ViewPose> views;
  for (const auto& sortie : p.flight.sorties) {
    for (const auto& st : sortie.stops) {
      for (const auto& m : p.missions) {
        if (m.surface_id != st.surface_id) continue;
        const auto& s = m.strategy.stops[static_cast<std::size_t>(st.stop)];
        views.push_back({s.position, s.yaw_deg, s.gimbal_pitch_deg});
      }
    }
  }
  return views;
}

/// Path from home to the last photo of the (single) sortie [m].
double pathToLastPhoto(const planning::FlightPlan& f) {
  double length = 0.0;
  for (const auto& s : f.sorties) {
    if (s.stops.empty()) continue;
    const std::size_t last = s.stops.back().waypoint;
    for (std::size_t i = 0; i < last; ++i) length += (s.waypoints[i + 1] - s.waypoints[i]).norm();
  }
  return length;
}

/// Minimum distance from every sortie segment to every input point [m], the segments
/// sampled every 2 cm (the nearest point by a kd-tree).
double minClearance(const planning::FlightPlan& f, const PointList& raw) {
  const NeighbourIndex tree(raw, raw.front());
  double best = std::numeric_limits<double>::infinity();
  for (const auto& s : f.sorties) {
    for (std::size_t i = 0; i + 1 < s.waypoints.size(); ++i) {
      const Vec3 a = s.waypoints[i], b = s.waypoints[i + 1];
      const int steps = std::max(1, static_cast<int>(std::ceil((b - a).norm() / 0.02)));
      for (int k = 0; k <= steps; ++k) {
        const Vec3 q = a + (b - a) * (static_cast<double>(k) / steps);
        float d2 = 0.0f;
        if (tree.nearestTo(q, &d2) >= 0) best = std::min(best, std::sqrt(static_cast<double>(d2)));
      }
    }
  }
  return best;
}

std::string pct(double f) {
  char b[32];
  std::snprintf(b, sizeof b, "%.1f %%", 100.0 * f);
  return b;
}

std::string fixed(double v, int digits) {
  char b[32];
  std::snprintf(b, sizeof b, "%.*f", digits, v);
  return b;
}

/// One scene: the chain (median of 3), the scores, the scene and mission files; appends
/// its row to `results` and `md`.
void runScene(const Peer& p, const std::string& data, const std::string& out, double target,
              nlohmann::json& results, std::ostringstream& md) {
  std::cerr << "fcplanner_compare: " << p.name << "\n";
  const PointList raw = io::loadCloud((fs::path(data) / p.cloud).string());
  const PointList dense = io::loadCloud((fs::path(data) / p.dense).string());
  // Their start, unless it lies inside the clearance (the pipe's (0, 0, 0) is 0.07 m
  // from a pipe): then home is the lowest photo stop, and the note says so.
  std::string home_note = "their start";
  app::Config config = peerConfig(p, true, target);
  Run first;
  const auto wall0 = SteadyClock::now();
  try {
    first = runChain(raw, config);
  } catch (const InputError& e) {
    home_note = std::string("lowest photo stop (their start is not free: ") + e.what() + ")";
    config = peerConfig(p, false, target);
    first = runChain(raw, config);
  }
  const double wall = secondsSince(wall0);
  std::vector<double> times = {first.seconds};
  for (int k = 0; k < 2; ++k) times.push_back(runChain(raw, config).seconds);
  const double compute = bench_util::median(times);
  const auto& plan = first.plan;
  const auto views = flownViews(plan);
  coverage::PinholeIntrinsics k;  // FC-Planner's camera (the defaults)
  const double rule_a =
      coverage::evaluatePixelCoverage(dense, views, k, p.visible_range_m).fraction;
  const double path = pathToLastPhoto(plan.flight);
  const double clearance = minClearance(plan.flight, raw);
  const double rule_b = plan.structure ? plan.structure->rule_b : 0.0;
  const fs::path dir = fs::path(out) / p.name;
  fs::create_directories(dir);
  io::writeFileAtomic((dir / "scene.json").string(),
                      io::sceneToJson(first.detect.scene).dump(1) + "\n");
  nlohmann::json mission = io::missionToJson(plan.missions, {{"scene", p.name}});
  mission["flight"] = io::flightToJson(plan.flight, config.flight.model);
  io::writeFileAtomic((dir / "mission.json").string(), mission.dump(1) + "\n");
  results.push_back({{"scene", p.name},
                     {"photos", views.size()},
                     {"path_m", path},
                     {"coverage_rule_a", rule_a},
                     {"coverage_rule_b", rule_b},
                     {"compute_s", compute},
                     {"compute_runs_s", times},
                     {"wall_s", wall},
                     {"min_clearance_m", clearance},
                     {"flight_status", planning::toString(plan.flight.status)},
                     {"home", home_note},
                     {"fcplanner",
                      {{"views", p.fc_views},
                       {"path_m", p.fc_path_m},
                       {"coverage", p.fc_coverage},
                       {"time_s", p.fc_time_s}}},
                     {"sip",
                      {{"views", p.sip_views},
                       {"path_m", p.sip_path_m},
                       {"coverage", p.sip_coverage},
                       {"time_s", p.sip_time_s}}}});
  md << "| " << p.name << " | " << views.size() << " (" << p.fc_views << " / " << p.sip_views
     << ") | " << fixed(path, 1) << " (" << fixed(p.fc_path_m, 1) << " / " << fixed(p.sip_path_m, 1)
     << ") | " << pct(rule_a) << " (" << pct(p.fc_coverage) << " / " << pct(p.sip_coverage)
     << ") | " << pct(rule_b) << " | " << fixed(compute, 2) << " (" << fixed(p.fc_time_s, 2)
     << " / " << fixed(p.sip_time_s, 1) << ") | " << fixed(wall, 2) << " | " << fixed(clearance, 3)
     << " |\n";
}

}  // namespace

int main(int argc, char** argv) {
  bench_util::prepareProcess();
  std::string data = "../shared/data/real", out;
  double target = coverage::CoverageOptions{}.structure_target;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if ((a == "-o" || a == "--out") && i + 1 < argc) {
      out = argv[++i];
    } else if (a == "--target" && i + 1 < argc) {
      target = std::stod(argv[++i]);
    } else if (a == "-h" || a == "--help") {
      std::cout << "usage: uavip_fcplanner_compare [DATA_DIR] -o OUT [--target T]\n"
                   "  --target T: coverage.structure_target (default 0.99)\n"
                   "  DATA_DIR holds fcplanner_{MBS,MBSmore,christ,christmore,pipe}.pcd (default "
                   "../shared/data/real)\n";
      return 0;
    } else {
      data = a;
    }
  }
  if (out.empty()) {
    std::cerr << "uavip_fcplanner_compare: give -o OUT (the output directory)\n";
    return 2;
  }
  try {
    fs::create_directories(out);
    nlohmann::json results = nlohmann::json::array();
    std::ostringstream md;
    md << "| scene | photos (FC / SIP) | path home → last photo [m] (FC / SIP) | coverage rule (a) "
          "(FC / SIP) | rule (b) "
          "| compute [s] (FC / SIP) | wall [s] | min distance to every input point [m] |\n"
          "|---|---|---|---|---|---|---|---|\n";
    for (const Peer& p : kPeers) runScene(p, data, out, target, results, md);
    io::writeFileAtomic((fs::path(out) / "results.json").string(), results.dump(1) + "\n");
    io::writeFileAtomic((fs::path(out) / "results.md").string(), md.str());
    std::cout << md.str();
  } catch (const std::exception& e) {
    std::cerr << "uavip_fcplanner_compare: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
