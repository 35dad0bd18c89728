// Safety from every measured point: the flight over every surface keeps the UAV's
// inflation radius from every point of the cloud the user gave, whatever stage 3
// dropped or merged. The reference is independent of the planner and its validator:
// each input cloud is read again here and the distance from every sortie segment to
// every point within reach is computed exactly (PCL's kd-tree picks the candidates).
// Heavy (real clouds, the bridge): label `heavy`, out of the sanitizer run.

#include <gtest/gtest.h>
#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#include "uavip/app/pipeline.h"
#include "uavip/app/scenario.h"
#include "uavip/core/geometry.h"
#include "uavip/io/cloud_io.h"

namespace uavip::app {
namespace {

const std::string kData = std::string(UAVIP_SOURCE_DIR) + "/tests/data/";
const std::string kScenarios = std::string(UAVIP_SOURCE_DIR) + "/scenarios/";
const char* const kSmallUav = "uav: {size_m: [0.3, 0.3, 0.2]}\ncoverage: {standoff_m: 1.0}\n";
const char* const kTinyUav =
    "uav: {size_m: [0.2, 0.2, 0.1]}\ncoverage: {standoff_m: 0.8}\nmission: {max_skipped_fraction: "
    "0.5}\n";

/// Exact smallest distance from the polylines to the cloud [m]: every segment is cut
/// into pieces ≤ 1 m, every point within (half the piece + `reach`) of a piece's
/// middle is a candidate, and the candidates' point–segment distances are exact.
/// Distances beyond `reach` are reported as `reach`.
double minDistance(const std::vector<PointList>& paths, const PointList& cloud, double reach) {
  auto pcl_cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  for (const auto& p : cloud)
    pcl_cloud->push_back(pcl::PointXYZ(float(p.x()), float(p.y()), float(p.z())));
  pcl::KdTreeFLANN<pcl::PointXYZ> tree;
  tree.setInputCloud(pcl_cloud);
  double best = reach;
  std::vector<int> idx;
  std::vector<float> d2;
  for (const auto& path : paths) {
    for (std::size_t i = 0; i + 1 < path.size(); ++i) {
      const Vec3 a = path[i], b = path[i + 1];
      const int pieces = std::max(1, static_cast<int>(std::ceil((b - a).norm())));
      for (int k = 0; k < pieces; ++k) {
        const Vec3 p0 = a + (b - a) * (double(k) / pieces),
                   p1 = a + (b - a) * (double(k + 1) / pieces);
        const Vec3 mid = 0.5 * (p0 + p1);
        const double radius = 0.5 * (p1 - p0).norm() + reach + 0.01;
        tree.radiusSearch(pcl::PointXYZ(float(mid.x()), float(mid.y()), float(mid.z())), radius,
                          idx, d2);
        for (const int j : idx)
          best = std::min(best, pointSegmentDistance(cloud[static_cast<std::size_t>(j)], p0, p1));
      }
    }
  }
  return best;
}

std::vector<PointList> sortiesOf(const PlanResult& p) {
  std::vector<PointList> out;
  for (const auto& s : p.flight.sorties) out.push_back(s.waypoints);
  return out;
}

struct Flown {
  PlanResult plan;
  double inflation_m{0.0};
};

Flown flyAll(const Scene& scene, const app::Config& config) {
  const app::Config resolved = resolveForScene(scene, config).config;
  return {plan(scene, resolved, selectSurfaces(scene, "all")), resolved.uav.inflationRadius()};
}

/// The flight over every surface of a cloud file detected with defaults.
Flown flyCloud(const PointList& raw, const app::Config& config) {
  const DetectResult d = detect(raw, config, measure(raw));
  return flyAll(d.scene, config);
}

void expectClear(const std::string& name, const Flown& f, const PointList& reference) {
  ASSERT_EQ(f.plan.flight.status, planning::FlightPlan::Status::Ok)
      << name << ": " << f.plan.flight.reason;
  ASSERT_FALSE(f.plan.flight.sorties.empty()) << name;
  const double d = minDistance(sortiesOf(f.plan), reference, 5.0);
  std::cout << name << ": flight " << f.plan.flight.length_m << " m, min distance to "
            << reference.size() << " input points " << d << " m (inflation radius " << f.inflation_m
            << " m, clearance kept " << f.plan.clearance_m << " m)\n";
  EXPECT_GE(d, f.inflation_m - 1e-4) << name;
}

/// A real cloud and the config it is flown with.
struct RealCase {
  std::string file;
  std::string config;  ///< YAML; empty = defaults
};

void PrintTo(const RealCase& c, std::ostream* os) {
  *os << c.file << (c.config.empty() ? "" : " (small UAV)");
}

class RealCloud : public ::testing::TestWithParam<RealCase> {};

TEST_P(RealCloud, TheFlightKeepsTheInflationRadiusFromEveryInputPoint) {
  const app::Config config = app::parseConfig(GetParam().config, "(test config)");
  const PointList raw = io::loadCloud(kData + GetParam().file, config.input);
  expectClear(GetParam().file, flyCloud(raw, config), raw);
}

// The room scans fly only with a small UAV close to the walls (a cluttered 3 m room
// leaves no free layer for the default 0.6 m inflation); the second room needs a
// smaller one still.
INSTANTIATE_TEST_SUITE_P(
    Safety, RealCloud,
    ::testing::Values(RealCase{"fcplanner_MBS.pcd", ""}, RealCase{"fcplanner_christ.pcd", ""},
                      RealCase{"fcplanner_pipe.pcd", ""},
                      RealCase{"hk_fruits_wholesale_market.pcd", ""},
                      RealCase{"room_scan1.pcd", kSmallUav}, RealCase{"room_scan2.pcd", kTinyUav},
                      RealCase{"autzen_trim.las", ""}),
    [](const auto& info) { return info.param.file.substr(0, info.param.file.find('.')); });

class DenserCloud : public ::testing::TestWithParam<std::pair<std::string, std::string>> {};

// A sparse cloud samples its surfaces every few decimetres; the true surface lies
// between the points. The same model's denser cloud shows where it is.
TEST_P(DenserCloud, AFlightPlannedOnTheSparseCloudKeepsClearOfTheDenseOne) {
  const app::Config defaults = app::parseConfig("", "(defaults)");
  const PointList sparse = io::loadCloud(kData + GetParam().first);
  const PointList dense = io::loadCloud(kData + GetParam().second);
  expectClear(GetParam().first + " vs " + GetParam().second, flyCloud(sparse, defaults), dense);
}

INSTANTIATE_TEST_SUITE_P(Safety, DenserCloud,
                         ::testing::Values(std::make_pair(std::string("fcplanner_MBS.pcd"),
                                                          std::string("fcplanner_MBSmore.pcd")),
                                           std::make_pair(std::string("fcplanner_christ.pcd"),
                                                          std::string("fcplanner_christmore.pcd"))),
                         [](const auto& info) {
                           return info.param.first.substr(10, info.param.first.find('.') - 10);
                         });

class ScenarioCloud : public ::testing::TestWithParam<std::string> {};

// The paper's hypothetical cases and the bridge: the sensed cloud (before stage 3)
// is the input.
TEST_P(ScenarioCloud, TheFlightKeepsTheInflationRadiusFromEverySensedPoint) {
  const app::Scenario scenario = app::loadScenario(kScenarios + GetParam() + ".yaml");
  const PointList raw = sense(scenario);
  const DetectResult d = detect(raw, scenario.config, measure(raw, &scenario));
  const app::Config resolved = d.resolved.config;
  const Flown f{plan(d.scene, resolved, selectSurfaces(d.scene, "all")),
                resolved.uav.inflationRadius()};
  if (d.scene.surfaces.empty() || GetParam() == "cube_crossed_planes") {
    // Nothing to fly (the point, the line) or nothing flyable (the crossed planes, as the paper
    // says).
    EXPECT_TRUE(f.plan.flight.sorties.empty()) << GetParam();
    return;
  }
  expectClear(GetParam(), f, raw);
}

INSTANTIATE_TEST_SUITE_P(Safety, ScenarioCloud,
                         ::testing::Values("single_point", "single_line", "single_plane",
                                           "single_cube", "cube_crossed_planes", "wall_on_ground",
                                           "bridge_sampled", "bridge"));

}  // namespace
}  // namespace uavip::app
