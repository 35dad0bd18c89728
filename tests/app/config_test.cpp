// Parameters resolved from the measured cloud (app/config.h): measured numbers
// against clouds of known spacing and noise, the paper's values on a dense scan,
// values set in the YAML always winning.

#include "uavip/app/config.h"

#include <gtest/gtest.h>

#include <random>

#include "uavip/app/scenario.h"
#include "uavip/core/aircraft.h"
#include "uavip/core/error.h"
#include "uavip/coverage/camera.h"
#include "uavip/preprocess/cloud_stats.h"

namespace uavip::app {
namespace {

/// A horizontal w × h plane sampled on a lattice of `spacing`, with Gaussian noise in z.
PointList lattice(double w, double h, double spacing, double noise, std::uint32_t seed = 1) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, noise > 0.0 ? noise : 1.0);
  PointList out;
  for (double x = 0.0; x <= w; x += spacing) {
    for (double y = 0.0; y <= h; y += spacing) out.emplace_back(x, y, noise > 0.0 ? n(rng) : 0.0);
  }
  return out;
}

double valueOf(const ResolvedConfig& r, const std::string& key) {
  for (const auto& v : r.values) {
    if (v.key == key) return v.value;
  }
  ADD_FAILURE() << "no resolved value " << key;
  return 0.0;
}

TEST(CloudStats, SpacingExtentAndNoiseOfAKnownLattice) {
  const PointList cloud = lattice(30.0, 20.0, 0.3, 0.02);
  const CloudStats s = preprocess::measureCloud(cloud);
  EXPECT_EQ(s.points, cloud.size());
  EXPECT_NEAR(s.spacing_m, 0.3, 0.03);
  EXPECT_NEAR(s.extent_m.x(), 30.0, 0.31);
  EXPECT_NEAR(s.extent_m.y(), 20.0, 0.31);
  // The plane fit of 13 neighbours removes 3 of their degrees of freedom.
  EXPECT_NEAR(s.noise_m, 0.02, 0.008);
  EXPECT_FALSE(s.lattice);  // measureCloud cannot know; the caller says so
}

TEST(CloudStats, DuplicatesDoNotMakeTheSpacingZero) {
  PointList cloud = lattice(5.0, 5.0, 0.1, 0.0);
  const PointList copy = cloud;
  cloud.insert(cloud.end(), copy.begin(), copy.end());
  EXPECT_NEAR(preprocess::measureCloud(cloud).spacing_m, 0.1, 0.01);
}

TEST(ResolveConfig, DenseScanGivesThePapersValues) {
  CloudStats stats = preprocess::measureCloud(lattice(10.0, 10.0, 0.02, 0.002));
  const ResolvedConfig r = resolveConfig(app::parseConfig("", "cfg"), stats);
  EXPECT_DOUBLE_EQ(r.config.preprocess.voxel_m, 0.05);
  EXPECT_DOUBLE_EQ(r.config.perception.planes.distance_threshold_m, 0.2);
  EXPECT_EQ(r.config.perception.planes.max_iterations, 200);
  EXPECT_DOUBLE_EQ(r.config.perception.planes.min_area_m2, 2.0);
  EXPECT_DOUBLE_EQ(r.config.perception.planes.cluster_tolerance_m, 0.3);
  EXPECT_DOUBLE_EQ(r.config.perception.clusters.tolerance_m, 0.3);
  EXPECT_DOUBLE_EQ(r.config.perception.planes.cell_size_m,
                   0.1);  // a voxel grid coarser than the scan: a lattice, 2 × 5 cm
  EXPECT_DOUBLE_EQ(r.config.grid.resolution_m, 0.2);
  EXPECT_FALSE(r.config.perception.planes.viewpoint_known);  // a cloud file has no sensor position
}

TEST(ResolveConfig, SparseCloudScalesWithItsSpacing) {
  CloudStats stats = preprocess::measureCloud(lattice(40.0, 40.0, 0.5, 0.01));
  const ResolvedConfig r = resolveConfig(app::parseConfig("", "cfg"), stats);
  const double s = stats.spacing_m;
  EXPECT_NEAR(r.config.preprocess.voxel_m, s, 0.001);
  EXPECT_NEAR(r.config.perception.planes.cluster_tolerance_m, 3.0 * s,
              0.005);  // voxel rounded up to mm
  EXPECT_NEAR(r.config.perception.clusters.tolerance_m, 3.0 * s, 0.005);
  EXPECT_NEAR(r.config.perception.planes.distance_threshold_m, std::max(0.2, 0.5 * s), 0.005);
  EXPECT_NEAR(r.config.perception.planes.cell_size_m, 3.0 * s,
              0.005);  // irregular sampling assumed
  EXPECT_NEAR(valueOf(r, "perception.plane_cluster_tolerance_m"),
              r.config.perception.planes.cluster_tolerance_m, 1e-12);
}

TEST(ResolveConfig, ValuesSetInTheFileWin) {
  CloudStats stats = preprocess::measureCloud(lattice(40.0, 40.0, 0.5, 0.01));
  const app::Config c = app::parseConfig(
      "preprocess: {voxel_m: 0.07}\nperception: {distance_threshold_m: 0.15, obstacle_tolerance_m: "
      "0.4}\n",
      "cfg");
  const ResolvedConfig r = resolveConfig(c, stats);
  EXPECT_DOUBLE_EQ(r.config.preprocess.voxel_m, 0.07);
  EXPECT_DOUBLE_EQ(r.config.perception.planes.distance_threshold_m, 0.15);
  EXPECT_DOUBLE_EQ(r.config.perception.clusters.tolerance_m, 0.4);
  for (const auto& v : r.values) {
    if (v.key == "preprocess.voxel_m") {
      EXPECT_EQ(v.source, "set");
    }
  }
  // Not set: still follows the cloud (spacing' = max(0.5, 0.07)).
  EXPECT_NEAR(r.config.perception.planes.cluster_tolerance_m, 3.0 * stats.spacing_m, 0.005);
}

TEST(ResolveConfig, LargeStructureWithoutACameraGetsAnInspectionCamera) {
  CloudStats stats = preprocess::measureCloud(lattice(60.0, 10.0, 0.5, 0.0));
  const ResolvedConfig big = resolveConfig(app::parseConfig("", "cfg"), stats);
  EXPECT_TRUE(big.config.coverage.camera.from_sensor);
  EXPECT_DOUBLE_EQ(big.config.coverage.camera.gsd_mm_per_px, 2.0);
  const ResolvedConfig own =
      resolveConfig(app::parseConfig("camera: {footprint_m: [1.0, 0.8]}\n", "cfg"), stats);
  EXPECT_FALSE(own.config.coverage.camera.from_sensor);
  EXPECT_DOUBLE_EQ(own.config.coverage.camera.footprint_w_m, 1.0);
}

TEST(ResolveConfig, MosaicOverlapsUnlessTheFileSetsThem) {
  const CloudStats stats = preprocess::measureCloud(lattice(4.0, 4.0, 0.1, 0.0));
  const ResolvedConfig paper = resolveConfig(app::parseConfig("", "cfg"), stats);
  EXPECT_DOUBLE_EQ(paper.config.coverage.overlap_w, 0.2);
  EXPECT_DOUBLE_EQ(paper.config.coverage.overlap_h, 0.2);
  const ResolvedConfig mosaic =
      resolveConfig(app::parseConfig("coverage: {purpose: mosaic}\n", "cfg"), stats);
  EXPECT_DOUBLE_EQ(mosaic.config.coverage.overlap_w, 0.6);
  EXPECT_DOUBLE_EQ(mosaic.config.coverage.overlap_h, 0.3);
  const ResolvedConfig own = resolveConfig(
      app::parseConfig("coverage: {purpose: mosaic, overlap: [0.5, 0.4]}\n", "cfg"), stats);
  EXPECT_DOUBLE_EQ(own.config.coverage.overlap_w, 0.5);
  EXPECT_DOUBLE_EQ(own.config.coverage.overlap_h, 0.4);
  const ResolvedConfig scalar =
      resolveConfig(app::parseConfig("coverage: {purpose: mosaic, overlap: 0.45}\n", "cfg"), stats);
  EXPECT_DOUBLE_EQ(scalar.config.coverage.overlap_h, 0.45);
  EXPECT_THROW(app::parseConfig("coverage: {purpose: survey}\n", "cfg"), InputError);
  // Structure mode plans every purpose (structure_views.h's multi-cover).
  EXPECT_EQ(app::parseConfig("coverage: {purpose: reconstruction, mode: structure}\n", "cfg")
                .coverage.purpose,
            "reconstruction");
  EXPECT_THROW(app::parseConfig("coverage: {purpose: reconstruction, min_views: 1}\n", "cfg"),
               InputError);
}

TEST(ResolveConfig, SiteGridStaysWithinTheMemoryGuard) {
  CloudStats stats;
  stats.spacing_m = 0.5;
  stats.extent_m = Vec3(1000.0, 1000.0, 60.0);  // a 1 km tile
  const ResolvedConfig r = resolveConfig(app::parseConfig("", "cfg"), stats);
  const Vec3 span = stats.extent_m + Vec3::Constant(2.0 * r.config.grid.padding_m);
  const double voxels = span.prod() / std::pow(r.config.grid.resolution_m, 3);
  EXPECT_LE(voxels, static_cast<double>(r.config.grid.max_voxels) / 4.0 * 1.01);
}

}  // namespace
}  // namespace uavip::app

namespace uavip::app {
namespace {

// Aircraft profiles (app/aircraft_profile.h): the profile fills what the file leaves
// unset, the file's keys win, the reference is the profile table itself.
TEST(AircraftProfile, FillsWhatTheFileLeavesAndTheFileWins) {
  const aircraft::Profile m3e = aircraft::findProfile("m3e");
  const Config c = parseConfig("uav: {model: m3e}\nflight: {endurance_s: 900}\n", "p.yaml");
  EXPECT_TRUE(c.coverage.camera.from_sensor);
  EXPECT_DOUBLE_EQ(c.coverage.camera.focal_mm, m3e.payload.camera.focal_mm);
  EXPECT_EQ(c.coverage.camera.image_w_px, m3e.payload.camera.image_w_px);
  // The GSD the camera gives at the standoff, on its coarser axis: the standoff stays.
  const coverage::CameraGeometry g = coverage::solveCamera(c.coverage.camera, 0.0);
  EXPECT_NEAR(g.standoff_m, c.coverage.standoff_m, 1e-9);
  EXPECT_DOUBLE_EQ(c.coverage.gimbal.pitch_max_deg, m3e.payload.pitch_max_deg);
  EXPECT_DOUBLE_EQ(c.coverage.gimbal.pitch_min_deg, -90.0);
  EXPECT_DOUBLE_EQ(c.flight.model.endurance_s, 900.0);  // the file's
  EXPECT_DOUBLE_EQ(c.uav.size_m.x(), m3e.span_m);
  EXPECT_EQ(c.sources.of(c.keyOf(&c.uav.size_m)), params::Source::Profile);

  // A file that describes its camera keeps it whole; speeds above the maker's are capped.
  Config f = parseConfig(
      "uav: {model: m3e, size_m: [1, 1, 1]}\ncamera: {footprint_m: [0.6, 0.4]}\n"
      "flight: {cruise_speed_m_s: 30}\n",
      "q.yaml");
  EXPECT_FALSE(f.coverage.camera.from_sensor);
  EXPECT_DOUBLE_EQ(f.coverage.camera.footprint_w_m, 0.6);
  EXPECT_DOUBLE_EQ(f.flight.model.cruise_speed_m_s, m3e.max_speed_mps);
  EXPECT_DOUBLE_EQ(f.uav.size_m.x(), 1.0);
  EXPECT_FALSE(f.uav.inflation_radius_m.has_value());
  EXPECT_DOUBLE_EQ(f.flight.model.endurance_s, m3e.enduranceS());

  // generic sets nothing; an unknown model or a payload on a drone with its own camera is
  // refused naming the file.
  EXPECT_FALSE(parseConfig("uav: {model: generic}\n", "g.yaml").coverage.camera.from_sensor);
  EXPECT_THROW(parseConfig("uav: {model: phantom}\n", "b.yaml"), InputError);
  EXPECT_THROW(parseConfig("uav: {model: m3e, payload: h30}\n", "b.yaml"), InputError);
}

}  // namespace
}  // namespace uavip::app
