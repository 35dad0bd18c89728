// uavip_fcplanner_compare [DATA_DIR] -o OUT: structure coverage (plan --cover
// structure) against FC-Planner's published table on its own three clouds, with its
// settings (camera, visible range, viewpoint distance, drone radius, start, ground).
// For each scene: the whole chain from the cloud in memory to the validated flight,
// median of 3 runs (views off), with the time split by stage; then, once, the scores: photos, path
// from home to the last photo (no return, as theirs), coverage by rule (a) (their pixel rule, on
// the dense cloud they score on, at our photo stops only) and rule (b) (ours), and the minimum
// distance from the flight to every input point; at the default target and at the smallest target
// whose rule (a) reaches theirs. Writes OUT/<scene>_<run>/scene.json,
// OUT/<scene>_<run>/mission.json, OUT/results.json and OUT/results.md.
// DATA_DIR defaults to ../shared/data/real from the repository root.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
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
/// (no battery limit), home at their start. `purpose` (issue 46): coverage.purpose, the
/// purpose's own overlap instead of 0 (empty: inspection with FC-Planner's none).
app::Config peerConfig(const Peer& p, bool with_start, double target, const std::string& purpose) {
  std::ostringstream y;
  y << "camera: {fx: 417.0467, fy: 461.0951, cx: 320, cy: 240, image_px: [640, 480], max_range_m: "
    << p.visible_range_m << "}\n"
    << "coverage: {mode: structure, standoff_m: " << p.standoff_m << ", gimbal_pitch_deg: [-85, 70]"
    << ", structure_target: " << target
    << (purpose.empty() ? std::string(", overlap: 0") : ", purpose: " + purpose)
    << (p.ground_z_m ? ", ground_z_m: " + std::to_string(*p.ground_z_m) : std::string()) << "}\n"
    << "uav: {inflation_radius_m: 0.3}\n"
    << "flight: {endurance_s: 1000000}\n";
  if (with_start)
    y << "mission: {start: [" << p.start.x() << ", " << p.start.y() << ", " << p.start.z()
      << "]}\n";
  return app::parseConfig(y.str(), "(FC-Planner settings for " + p.name + ")");
}

/// One run of the chain and where its time went [s].
struct Run {
  app::DetectResult detect;
  app::PlanResult plan;
  double seconds{0.0};
  double measure_s{0.0};
  double detect_s{0.0};
};

Run runChain(const PointList& raw, const app::Config& config) {
  Run r;
  const auto t0 = SteadyClock::now();
  app::CloudIndex index;
  const preprocess::CloudStats measured = app::measure(raw, nullptr, &index);
  r.measure_s = secondsSince(t0);
  const auto t1 = SteadyClock::now();
  r.detect = app::detect(raw, config, measured, {}, index);
  r.detect_s = secondsSince(t1);
  r.plan = app::planStructure(r.detect.scene, r.detect.resolved.config);
  r.seconds = secondsSince(t0);
  return r;
}

/// The time split of a run, by stage [s]: measure, detect, grid, prepare (normals,
/// their orientation, line of sight), views (the selection: candidates, scoring, set
/// cover), order, legs, score (rules a and b at the stops), flight (home legs,
/// sorties, validation), total.
std::vector<std::pair<std::string, double>> timeSplit(const Run& r) {
  const auto& t = r.plan.times;
  const planning::StructureSummary none;
  const auto& s = r.plan.structure ? *r.plan.structure : none;
  return {{"measure", r.measure_s}, {"detect", r.detect_s}, {"grid", t.grid_s},
          {"prepare", s.prepare_s}, {"views", s.select_s},  {"order", s.order_s},
          {"legs", s.legs_s},       {"score", s.score_s},   {"flight", t.flight_s},
          {"total", r.seconds}};
}

/// Per stage, the median over the runs [s].
std::vector<std::pair<std::string, double>> medianSplit(const std::vector<Run>& runs) {
  std::vector<std::vector<std::pair<std::string, double>>> splits;
  splits.reserve(runs.size());
  for (const Run& r : runs) splits.push_back(timeSplit(r));
  std::vector<std::pair<std::string, double>> out = splits.front();
  for (std::size_t k = 0; k < out.size(); ++k) {
    std::vector<double> v;
    v.reserve(splits.size());
    for (const auto& split : splits) v.push_back(split[k].second);
    out[k].second = bench_util::median(v);
  }
  return out;
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

/// Bold when we miss their figure (`worse`).
std::string mark(const std::string& v, bool worse) { return worse ? "**" + v + "**" : v; }

/// A scene's inputs, loaded once.
struct SceneData {
  PointList raw, dense;
};

/// The chain `runs` times at `target` (the first also decides home: their start, or
/// the lowest photo stop when it is not free); `home_note` says which.
std::vector<Run> runAt(const Peer& p, const SceneData& d, double target, int runs,
                       const std::string& purpose, std::string& home_note, app::Config& config) {
  home_note = "their start";
  config = peerConfig(p, true, target, purpose);
  std::vector<Run> out;
  try {
    out.push_back(runChain(d.raw, config));
  } catch (const InputError& e) {
    home_note = std::string("lowest photo stop (their start is not free: ") + e.what() + ")";
    config = peerConfig(p, false, target, purpose);
    out.push_back(runChain(d.raw, config));
  }
  for (int k = 1; k < runs; ++k) out.push_back(runChain(d.raw, config));
  return out;
}

/// Rule (a) on the dense cloud at the flown stops of `r`.
double ruleA(const Peer& p, const SceneData& d, const Run& r) {
  coverage::PinholeIntrinsics k;  // FC-Planner's camera (the defaults)
  return coverage::evaluatePixelCoverage(d.dense, flownViews(r.plan), k, p.visible_range_m)
      .fraction;
}

/// Targets tried, smallest first, when the run is to match their coverage.
const std::vector<double> kTargetLadder = {0.90, 0.92, 0.94, 0.95, 0.96, 0.97, 0.98, 0.99};

/// One scene at one target: the chain `runs` times (median compute), the scores of the
/// first run, its files under OUT/<scene>[_<label>]; appends its rows.
void reportRuns(const Peer& p, const SceneData& d, const std::vector<Run>& runs, double target,
                const std::string& label, const std::string& home_note, const std::string& out,
                nlohmann::json& results, std::ostringstream& md, std::ostringstream& split_md) {
  std::vector<double> times;
  times.reserve(runs.size());
  for (const Run& r : runs) times.push_back(r.seconds);
  const double compute = bench_util::median(times);
  const Run& first = runs.front();
  const auto& plan = first.plan;
  const std::size_t photos = flownViews(plan).size();
  const double rule_a = ruleA(p, d, first);
  const double path = pathToLastPhoto(plan.flight);
  const double clearance = minClearance(plan.flight, d.raw);
  const double rule_b = plan.structure ? plan.structure->rule_b : 0.0;
  const fs::path dir = fs::path(out) / (p.name + "_" + label);
  fs::create_directories(dir);
  io::writeFileAtomic((dir / "scene.json").string(),
                      io::sceneToJson(first.detect.scene).dump(1) + "\n");
  // Through mission.json's one writer: the camera model and targets uavip photos reads.
  const app::Config& planned_with = first.detect.resolved.config;
  io::writeFileAtomic((dir / "mission.json").string(),
                      io::missionJsonText(plan.missions, plan.flight, planned_with.flight.model,
                                          app::missionExtras(plan, planned_with, p.name)));
  const auto split = medianSplit(runs);
  nlohmann::json split_json = nlohmann::json::object();
  for (const auto& [stage, seconds] : split) split_json[stage] = seconds;
  const int wins = (static_cast<int>(photos) <= p.fc_views) + (path <= p.fc_path_m) +
                   (rule_a >= p.fc_coverage) + (compute <= p.fc_time_s);
  results.push_back({{"scene", p.name},
                     {"run", label},
                     {"target", target},
                     {"photos", photos},
                     {"path_m", path},
                     {"coverage_rule_a", rule_a},
                     {"coverage_rule_b", rule_b},
                     {"compute_s", compute},
                     {"compute_runs_s", times},
                     {"split_s", split_json},
                     {"counts_won", wins},
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
  md << "| " << p.name << " | " << label << " " << fixed(target, 2) << " | "
     << mark(std::to_string(photos), static_cast<int>(photos) > p.fc_views) << " (" << p.fc_views
     << " / " << p.sip_views << ") | " << mark(fixed(path, 1), path > p.fc_path_m) << " ("
     << fixed(p.fc_path_m, 1) << " / " << fixed(p.sip_path_m, 1) << ") | "
     << mark(pct(rule_a), rule_a < p.fc_coverage) << " (" << pct(p.fc_coverage) << " / "
     << pct(p.sip_coverage) << ") | " << pct(rule_b) << " | "
     << mark(fixed(compute, 2), compute > p.fc_time_s) << " (" << fixed(p.fc_time_s, 2) << " / "
     << fixed(p.sip_time_s, 1) << ") | " << wins << " / 4 | " << fixed(clearance, 3) << " |\n";
  split_md << "| " << p.name << " | " << label << " " << fixed(target, 2);
  for (const auto& [stage, seconds] : split) split_md << " | " << fixed(seconds, 2);
  split_md << " |\n";
}

/// Options of the comparison.
struct CompareOptions {
  std::string data = "../shared/data/real", out;
  std::optional<double> target;  ///< one fixed target instead of default + matched
  std::vector<std::string> scenes;
  int runs{3};
  std::string purpose;  ///< coverage.purpose; empty: inspection as FC-Planner plans
};

/// One scene: the default target and the smallest target of kTargetLadder whose rule
/// (a) reaches FC-Planner's coverage (or only `o.target`).
void runScene(const Peer& p, const CompareOptions& o, nlohmann::json& results,
              std::ostringstream& md, std::ostringstream& split_md) {
  std::cerr << "fcplanner_compare: " << p.name << "\n";
  SceneData d;
  d.raw = io::loadCloud((fs::path(o.data) / p.cloud).string());
  d.dense = io::loadCloud((fs::path(o.data) / p.dense).string());
  std::string home_note;
  app::Config config;
  const double default_target = coverage::CoverageOptions{}.structure_target;
  const double first_target = o.target ? *o.target : default_target;
  const std::vector<Run> runs = runAt(p, d, first_target, o.runs, o.purpose, home_note, config);
  reportRuns(p, d, runs, first_target, o.target ? "given" : "default", home_note, o.out, results,
             md, split_md);
  if (o.target) return;
  for (const double t : kTargetLadder) {
    std::vector<Run> one = runAt(p, d, t, 1, o.purpose, home_note, config);
    const bool matched = ruleA(p, d, one.front()) >= p.fc_coverage;
    if (!matched && t != kTargetLadder.back()) continue;
    std::cerr << "fcplanner_compare: " << p.name << (matched ? " matched" : " not matched even")
              << " at target " << t << "\n";
    const std::vector<Run> more = runAt(p, d, t, o.runs - 1, o.purpose, home_note, config);
    one.insert(one.end(), more.begin(), more.end());
    reportRuns(p, d, one, t, matched ? "matched" : "unmatched", home_note, o.out, results, md,
               split_md);
    return;
  }
}

/// A numeric command-line value; InputError naming the option otherwise.
double numberArg(const std::string& text, const std::string& option) {
  std::size_t used = 0;
  double v = 0.0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || !std::isfinite(v))
    throw InputError(option + ": '" + text + "' is not a number");
  return v;
}

}  // namespace

int main(int argc, char** argv) {
  bench_util::prepareProcess();
  CompareOptions o;
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      if ((a == "-o" || a == "--out") && i + 1 < argc) {
        o.out = argv[++i];
      } else if (a == "--target" && i + 1 < argc) {
        o.target = numberArg(argv[++i], "--target");
      } else if (a == "--scene" && i + 1 < argc) {
        o.scenes.emplace_back(argv[++i]);
      } else if (a == "--purpose" && i + 1 < argc) {
        o.purpose = argv[++i];
      } else if (a == "--runs" && i + 1 < argc) {
        o.runs = std::max(1, static_cast<int>(numberArg(argv[++i], "--runs")));
      } else if (a == "-h" || a == "--help") {
        std::cout
            << "usage: uavip_fcplanner_compare [DATA_DIR] -o OUT [--target T] [--scene NAME]... "
               "[--runs N] [--purpose P]\n"
               "  without --target: the default coverage.structure_target, and the smallest "
               "of 0.90 … 0.99 whose rule (a) reaches FC-Planner's\n"
               "  --target T: that coverage.structure_target only\n"
               "  --scene NAME: MBS, christ or pipe (default: all three)\n"
               "  --runs N: runs of the chain per target, the median is reported (default 3)\n"
               "  --purpose P: coverage.purpose (inspection, mosaic, reconstruction) with its "
               "own overlap (default: inspection, no overlap, as FC-Planner)\n"
               "  DATA_DIR holds fcplanner_{MBS,MBSmore,christ,christmore,pipe}.pcd (default "
               "../shared/data/real)\n";
        return 0;
      } else {
        o.data = a;
      }
    }
    for (const auto& name : o.scenes)
      if (std::none_of(kPeers.begin(), kPeers.end(), [&](const Peer& p) { return p.name == name; }))
        throw InputError("--scene: '" + name + "' is not one of MBS, christ, pipe");
  } catch (const InputError& e) {
    std::cerr << "uavip_fcplanner_compare: " << e.what() << "\n";
    return 2;
  }
  if (o.out.empty()) {
    std::cerr << "uavip_fcplanner_compare: give -o OUT (the output directory)\n";
    return 2;
  }
  try {
    fs::create_directories(o.out);
    nlohmann::json results = nlohmann::json::array();
    std::ostringstream md, split_md;
    md << "| scene | run, target | photos (FC / SIP) | path home → last photo [m] (FC / SIP) | "
          "rule (a) (FC / SIP) | rule (b) | compute [s] (FC / SIP) | counts won | min distance "
          "to every input point [m] |\n|---|---|---|---|---|---|---|---|---|\n";
    split_md
        << "| scene | run, target | measure | detect | grid | prepare | views | order | legs "
           "| score | flight | total [s] |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const Peer& p : kPeers) {
      if (!o.scenes.empty() &&
          std::find(o.scenes.begin(), o.scenes.end(), p.name) == o.scenes.end())
        continue;
      runScene(p, o, results, md, split_md);
    }
    io::writeFileAtomic((fs::path(o.out) / "results.json").string(), results.dump(1) + "\n");
    io::writeFileAtomic((fs::path(o.out) / "results.md").string(),
                        md.str() + "\n" + split_md.str());
    std::cout << md.str() << "\n" << split_md.str();
  } catch (const std::exception& e) {
    std::cerr << "uavip_fcplanner_compare: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
