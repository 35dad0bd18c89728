// uavip bench: runs, summaries against counts made here, the OMPL log
// loaded by ompl_benchmark_statistics into SQLite, leg sampling, the CLI.

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>

#include "planners/harness.h"
#include "planners/registry.h"
#include "uavip/app/pipeline.h"
#include "uavip/app/scenario.h"
#include "uavip/bench/report.h"
#include "uavip/bench/runner.h"
#include "uavip/core/error.h"
#include "uavip/io/atomic_file.h"

namespace uavip::bench {
namespace {

namespace fs = std::filesystem;

// A 3 m wall at x = 2 and a sealed hollow 3 m box at x ∈ [5, 8]. Leg 0 and 1 go
// around the wall; leg 2 ends inside the box (free voxels, unreachable).
const char* kScenario = R"(
name: bench_test
world:
  - {type: plane, name: wall, corner: [2.0, 0.0, 0.0], edge_u: [0.0, 3.0, 0.0], edge_v: [0.0, 0.0, 3.0]}
  - {type: box, name: box, min: [5.0, 0.0, 0.0], max: [8.0, 3.0, 3.0]}
sensing: {mode: sample, spacing_m: 0.1, noise_sigma_m: 0.0, outlier_fraction: 0.0, seed: 1}
preprocess: {voxel_m: 0.1}
bench:
  legs:
    - [[0.5, 1.5, 1.5], [3.5, 1.5, 1.5]]
    - [[0.5, 0.5, 1.0], [3.5, 2.5, 2.0]]
    - [[3.5, 1.5, 1.5], [6.5, 1.5, 1.5]]
)";

fs::path tempDir(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("uavip_bench_test_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

/// Output of a shell command, or nullopt if it failed.
std::optional<std::string> shell(const std::string& cmd) {
  FILE* p = ::popen(cmd.c_str(), "r");
  if (p == nullptr) return std::nullopt;
  std::string out;
  char buf[512];
  while (std::fgets(buf, sizeof(buf), p) != nullptr) out += buf;
  const int rc = ::pclose(p);
  if (rc != 0) return std::nullopt;
  return out;
}

bool haveTool(const std::string& tool) {
  return std::system(("command -v " + tool + " >/dev/null 2>&1").c_str()) == 0;
}

BenchOptions smallOptions() {
  BenchOptions o;
  o.planners = {"astar", "rrtconnect", "prmstar"};
  o.runs = 2;
  o.time_limit_s = 0.2;
  return o;
}

/// One benchmark shared by the tests (it is the slow part).
const BenchResult& sharedResult() {
  static const BenchResult r =
      runBench({app::parseScenario(kScenario, "bench_test.yaml")}, smallOptions());
  return r;
}

TEST(Bench, OneRunPerPlannerLegAndRepetition) {
  const BenchResult& r = sharedResult();
  ASSERT_EQ(r.legs.size(), 3u);
  EXPECT_TRUE(r.legs[0].feasible);
  EXPECT_TRUE(r.legs[1].feasible);
  EXPECT_FALSE(r.legs[2].feasible);
  EXPECT_EQ(r.runs.size(), 3u * 3u * 2u);
  std::map<std::pair<std::string, int>, int> count;
  for (const auto& run : r.runs) ++count[{run.planner, run.leg}];
  for (const auto& p : smallOptions().planners)
    for (int leg = 0; leg < 3; ++leg) EXPECT_EQ((count[{p, leg}]), 2) << p << " leg " << leg;
}

TEST(Bench, AStarSolvesTheFeasibleLegsAndEverySolvedPathIsSafe) {
  const BenchResult& r = sharedResult();
  for (const auto& run : r.runs) {
    const bool feasible = r.legs[static_cast<std::size_t>(run.leg)].feasible;
    if (run.planner == "astar") {
      EXPECT_EQ(run.solved, feasible) << "leg " << run.leg;
      if (!feasible) {
        EXPECT_EQ(planners::plannerStatusNames()[static_cast<std::size_t>(run.status)], "Abort");
      }
    }
    if (!feasible) {
      EXPECT_FALSE(run.solved) << run.planner;
    }
    if (run.solved) {
      EXPECT_TRUE(run.valid) << run.planner << " leg " << run.leg;
      EXPECT_GE(run.min_clearance_m, 0.6)
          << run.planner;  // the UAV's inflation radius (default size)
      EXPECT_GE(run.waypoints, 2u);
      EXPECT_LE(run.length_m, run.raw_length_m + 1e-9);
      EXPECT_GE(run.length_m, (r.legs[static_cast<std::size_t>(run.leg)].straight_m) - 1e-9);
    }
  }
}

/// Length of a polyline [m].
double polylineLength(const PointList& path) {
  double length = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i) length += (path[i] - path[i - 1]).norm();
  return length;
}

TEST(Bench, AStarCoarseIsThePlannerPlanFlies) {
  // The default planner as `uavip plan` flies it: app::planningSpace around the stops and
  // the leg ends (the grid and validator of app::plan), makePlanner with the config's
  // settings. The bench must report the same path on each leg (simplification off).
  const app::Scenario sc = app::parseScenario(kScenario, "bench_test.yaml");
  BenchOptions options = smallOptions();
  options.planners = {"astar-coarse"};
  options.runs = 1;
  options.simplify = false;
  const BenchResult r = runBench({sc}, options);

  const PointList raw = app::sense(sc);
  const app::DetectResult d = app::detect(raw, sc.config, app::measure(raw, &sc));
  const app::Config& config = d.resolved.config;
  PointList positions;
  for (const auto& stops : stopsBySurface(d.scene, config.coverage))
    positions.insert(positions.end(), stops.begin(), stops.end());
  for (const auto& [a, b] : sc.bench.legs) {
    positions.push_back(a);
    positions.push_back(b);
  }
  const app::PlanningSpace space = app::planningSpace(
      d.scene, std::make_shared<const world::CollisionWorld>(d.scene), config, positions);
  const auto planner = planners::makePlanner("astar-coarse", config.planner_settings);
  ASSERT_EQ(r.runs.size(), sc.bench.legs.size());
  int solved = 0;
  for (const auto& run : r.runs) {
    const BenchLeg& leg = r.legs[static_cast<std::size_t>(run.leg)];
    const planning::PathResult flown = planner->plan(space.grid, leg.start, leg.goal);
    EXPECT_EQ(run.solved, flown.solved()) << "leg " << run.leg;
    if (!run.solved || !flown.solved()) continue;
    ++solved;
    EXPECT_NEAR(run.raw_length_m, polylineLength(flown.path), 1e-9) << "leg " << run.leg;
    EXPECT_EQ(run.raw_waypoints, flown.path.size()) << "leg " << run.leg;
  }
  EXPECT_EQ(solved, 2);  // legs 0 and 1; leg 2 ends inside the sealed box
}

TEST(Bench, SummaryMatchesCountsOverTheRuns) {
  const BenchResult& r = sharedResult();
  ASSERT_EQ(r.summary.size(), 3u);  // one scenario: no "all" rows
  for (const auto& s : r.summary) {
    std::size_t runs = 0, solved = 0;
    double min_clearance = 1e9;
    for (const auto& run : r.runs) {
      if (run.planner != s.planner) continue;
      ++runs;
      if (run.solved) {
        ++solved;
        min_clearance = std::min(min_clearance, run.min_clearance_m);
      }
    }
    EXPECT_EQ(s.runs, runs);
    EXPECT_EQ(s.solved, solved);
    EXPECT_NEAR(s.success_pct, 100.0 * solved / runs, 1e-9);
    EXPECT_NEAR(s.min_clearance_m, min_clearance, 1e-12);
    EXPECT_GE(s.length_ratio_to_best, 1.0 - 1e-12);
  }
  const auto astar = std::find_if(r.summary.begin(), r.summary.end(),
                                  [](const auto& s) { return s.planner == "astar"; });
  ASSERT_NE(astar, r.summary.end());
  EXPECT_NEAR(astar->success_pct, 100.0 * 2.0 / 3.0, 1e-9);
  EXPECT_DOUBLE_EQ(astar->time_ratio_to_astar, 1.0);
  EXPECT_DOUBLE_EQ(astar->length_ratio_to_astar, 1.0);
  const std::string csv = benchCsv(r);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 4);  // header + 3 planners
  EXPECT_NE(benchMarkdown(r).find("| astar |"), std::string::npos);
}

TEST(Bench, LogLoadsIntoSqliteWithOneRowPerRun) {
  if (!haveTool("ompl_benchmark_statistics") || !haveTool("sqlite3")) {
    GTEST_SKIP() << "ompl_benchmark_statistics (ompl-demos) or sqlite3 is not installed";
  }
  const BenchResult& r = sharedResult();
  const fs::path dir = tempDir("log");
  const fs::path log = dir / "results.log";
  const fs::path db = dir / "results.db";
  io::writeFileAtomic(log.string(), benchLog(r, "bench_test", "testhost"));
  ASSERT_TRUE(
      shell("ompl_benchmark_statistics '" + log.string() + "' -d '" + db.string() + "' 2>&1"));
  auto query = [&](const std::string& sql) {
    const auto out = shell("sqlite3 '" + db.string() + "' \"" + sql + "\"");
    EXPECT_TRUE(out) << sql;
    return out ? *out : std::string();
  };
  EXPECT_EQ(query("SELECT COUNT(*) FROM runs;"), std::to_string(r.runs.size()) + "\n");
  EXPECT_EQ(query("SELECT COUNT(*) FROM plannerConfigs;"), "3\n");
  EXPECT_EQ(query("SELECT name FROM plannerConfigs ORDER BY id;"),
            "geometric_AStar\ngeometric_RRTConnect\ngeometric_PRMstar\n");
  std::size_t solved = 0;
  for (const auto& run : r.runs) solved += run.solved ? 1 : 0;
  EXPECT_EQ(query("SELECT COUNT(*) FROM runs WHERE solved = 1;"), std::to_string(solved) + "\n");
  EXPECT_EQ(query("SELECT COUNT(*) FROM runs WHERE leg_id = 2 AND solved = 1;"), "0\n");
  EXPECT_EQ(query("SELECT COUNT(*) FROM runs WHERE solved = 1 AND (validator_verdict != 1 OR "
                  "min_clearance < 0.6);"),
            "0\n");
  EXPECT_EQ(query("SELECT version FROM experiments;"), "OMPL " + planners::omplVersion() + "\n");
  fs::remove_all(dir);
}

TEST(Bench, SampledLegsJoinReachableStopsOfDifferentSurfacesAroundObstacles) {
  // A wall at x = 2 between two groups of "stops".
  PointList cloud;
  for (double y = 0.0; y <= 3.0 + 1e-9; y += 0.1)
    for (double z = 0.0; z <= 3.0 + 1e-9; z += 0.1) cloud.emplace_back(2.0, y, z);
  const std::vector<PointList> stops = {
      {Vec3(0.5, 1.0, 1.0), Vec3(0.5, 2.0, 1.5), Vec3(0.5, 1.5, 2.5)},
      {Vec3(3.5, 1.0, 1.0), Vec3(3.5, 2.0, 2.0), Vec3(2.0, 1.5, 1.5)}};
  world::GridOptions go;
  go.inflation_radius_m = 0.3;
  PointList extra;
  for (const auto& s : stops) extra.insert(extra.end(), s.begin(), s.end());
  const auto grid = world::VoxelGrid::build(cloud, extra, go);
  const auto legs = sampleLegs(grid, stops, 4, 3);
  ASSERT_FALSE(legs.empty());
  EXPECT_LE(legs.size(), 4u);
  for (const auto& [a, b] : legs) {
    const bool a_left = a.x() < 2.0, b_left = b.x() < 2.0;
    EXPECT_NE(a_left, b_left);          // different surfaces (sides of the wall)
    EXPECT_NE(a, Vec3(2.0, 1.5, 1.5));  // the stop inside the wall is never used
    EXPECT_NE(b, Vec3(2.0, 1.5, 1.5));
    EXPECT_FALSE(grid.segmentFree(a, b));  // the wall is in the way
    EXPECT_TRUE(grid.connected(grid.indexOf(a), grid.indexOf(b)));
  }
  EXPECT_EQ(sampleLegs(grid, stops, 4, 3), legs);  // deterministic
}

TEST(Bench, BadOptionsAndBenchSectionsAreRejected) {
  BenchOptions o;
  o.planners = {"astar", "rrt"};
  EXPECT_THROW(o.validate(), InputError);
  o.planners = {"astar"};
  o.runs = 0;
  EXPECT_THROW(o.validate(), InputError);
  o.runs = 1;
  o.time_limit_s = 0.0;
  EXPECT_THROW(o.validate(), InputError);
  const std::string base =
      "name: x\nworld: [{type: point, at: [0, 0, 0]}]\nsensing: {mode: sample}\n";
  EXPECT_EQ(app::parseScenario(base + "bench: {legs: [[[0, 0, 1], [1, 2, 3]]]}\n", "x.yaml")
                .bench.legs.size(),
            1u);
  EXPECT_THROW(app::parseScenario(base + "bench: {legs: [[[0, 0, 1]]]}\n", "x.yaml"), InputError);
  EXPECT_THROW(app::parseScenario(base + "bench: {legs: [[[0, 0], [1, 2, 3]]]}\n", "x.yaml"),
               InputError);
  EXPECT_THROW(app::parseScenario(base + "bench: {max_legs: 0}\n", "x.yaml"), InputError);
  EXPECT_THROW(app::parseScenario(base + "bench: {leg: []}\n", "x.yaml"), InputError);
  EXPECT_THROW(app::parseScenario(base + "planner: {time_limit_s: -1}\n", "x.yaml"), InputError);
}

TEST(Bench, CommandLineWritesLogCsvMarkdownAndPlot) {
  const fs::path dir = tempDir("cli");
  const fs::path scenario = dir / "bench_test.yaml";
  io::writeFileAtomic(scenario.string(), kScenario);
  const fs::path log = dir / "out" / "results.log";
  const std::string cmd = std::string(UAVIP_BINARY) + " bench '" + scenario.string() +
                          "' --planners astar,astar-euclid --runs 1 -q -o '" + log.string() +
                          "' 2>&1";
  ASSERT_TRUE(shell(cmd)) << cmd;
  for (const char* ext : {".log", ".csv", ".md", ".png"}) {
    fs::path p = log;
    p.replace_extension(ext);
    EXPECT_TRUE(fs::exists(p) && fs::file_size(p) > 0) << p;
  }
  EXPECT_FALSE(shell(std::string(UAVIP_BINARY) + " bench '" + scenario.string() +
                     "' --planners nope -q 2>&1"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace uavip::bench
