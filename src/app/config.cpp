#include "uavip/app/config.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

namespace uavip::app {
namespace {

/// Largest extent above which a cloud is a building or bridge, not one of the
/// paper's small cases [m].
constexpr double kLargeStructureM = 20.0;

/// Rounds up to whole millimetres, so printed and used values agree.
double mm(double metres) { return std::ceil(metres * 1000.0 - 1e-6) / 1000.0; }

/// The row of `field` (a field of `c`) in Config::table(); it must be one `auto` may set.
const params::Param<Config>& autoRow(const Config& c, const void* field) {
  const params::Param<Config>* row = Config::table().find(c, field);
  if (row == nullptr || (row->layers & params::kAuto) == 0U)
    throw std::logic_error("resolveConfig: a field the tables do not mark auto");
  return *row;
}

/// Keeps `field` when a higher layer (the file) set it, else sets it to `auto_value`;
/// records the value and which with the rule.
template <typename T>
void resolve(ResolvedConfig& r, T& field, T auto_value, const std::string& rule) {
  const params::Param<Config>& row = autoRow(r.config, &field);
  const bool auto_set = r.config.sources.set(row.key, params::Source::Auto);
  if (auto_set) field = auto_value;
  r.values.push_back({row.key, static_cast<double>(field), auto_set ? "auto: " + rule : "set"});
}

/// Records a key `auto` leaves as it is: "set" when the file set it, else `otherwise`.
void record(ResolvedConfig& r, const void* field, double value, const std::string& otherwise) {
  const std::string& key = r.config.keyOf(field);
  r.values.push_back({key, value, r.config.sources.fromFile(key) ? "set" : otherwise});
}

/// The overlap of a purpose whose file sets no coverage.overlap: a mosaic's photos
/// overlap 0.6 along the rows and 0.3 across them; a reconstruction's rows overlap by
/// what its surfaces' points in front of the plane need (coverage/flight_strategy.cpp,
/// reconstructionShrink): the paper's 0.2 is for inspection.
void purposeOverlap(ResolvedConfig& r) {
  Config& c = r.config;
  if (c.setInFile(&c.coverage.overlap_w)) return;
  if (c.coverage.purpose == "mosaic") {
    c.coverage.overlap_w = coverage::kMosaicOverlapW;
    c.coverage.overlap_h = coverage::kMosaicOverlapH;
    r.values.push_back({c.keyOf(&c.coverage.overlap_w), c.coverage.overlap_w,
                        "purpose mosaic: 0.6 along the rows, 0.3 across them"});
  } else if (c.coverage.purpose == "reconstruction") {
    c.coverage.overlap_w = coverage::kReconstructionOverlap;
    c.coverage.overlap_h = coverage::kReconstructionOverlap;
    r.values.push_back({c.keyOf(&c.coverage.overlap_w), c.coverage.overlap_w,
                        "purpose reconstruction: what the points in front of each plane need"});
  }
}

}  // namespace

double autoGridResolution(const Vec3& extent_m, const world::GridOptions& grid) {
  const Vec3 span = extent_m + Vec3::Constant(2.0 * grid.padding_m);
  const double budget = static_cast<double>(grid.max_voxels) / 4.0;
  return mm(std::max(0.2, std::cbrt(span.x() * span.y() * span.z() / budget)));
}

ResolvedConfig resolveConfig(const app::Config& config, const preprocess::CloudStats& stats) {
  ResolvedConfig r;
  r.config = config;
  app::Config& c = r.config;
  const double spacing = stats.spacing_m > 0.0 ? stats.spacing_m : 0.05;
  const double noise = std::max(stats.noise_m, 0.0);

  resolve(r, c.preprocess.voxel_m, mm(std::max(0.05, spacing)), "max(0.05, spacing)");
  const double s_eff = c.preprocess.voxelize ? std::max(spacing, c.preprocess.voxel_m) : spacing;

  auto& planes = c.perception.planes;
  resolve(r, planes.distance_threshold_m, mm(std::max({0.2, 4.0 * noise, 0.5 * s_eff})),
          "max(0.2, 4 noise, spacing'/2)");
  resolve(r, planes.cluster_tolerance_m, mm(std::max(0.3, 3.0 * s_eff)), "max(0.3, 3 spacing')");
  resolve(r, c.perception.clusters.tolerance_m, mm(std::max(0.3, 3.0 * s_eff)),
          "max(0.3, 3 spacing')");
  // After a voxel grid coarser than the spacing, the points form a lattice too.
  const bool lattice =
      stats.lattice || (c.preprocess.voxelize && c.preprocess.voxel_m >= 1.5 * spacing);
  resolve(r, planes.cell_size_m, mm(lattice ? 2.0 * s_eff : 3.0 * s_eff),
          lattice ? "2 spacing' (lattice)" : "3 spacing' (irregular sampling)");
  // A scenario knows its sensor; a cloud file knows none unless the config gives one.
  planes.viewpoint_known = c.setInFile(&planes.viewpoint);
  if (!planes.viewpoint_known && stats.scanned_from_origin) {
    // One terrestrial scan from the origin: the sensor is known, and it saw the
    // front of every surface.
    planes.viewpoint_known = true;
    planes.viewpoint = Vec3::Zero();
    planes.single_station = true;
  }
  resolve(r, planes.open_voxel_m, mm(std::max(0.1, 2.0 * s_eff)), "max(0.1, 2 spacing')");
  resolve(r, planes.min_inliers, 30, "30");
  record(r, &planes.min_area_m2, planes.min_area_m2, "default (paper)");

  // Camera: the paper's 0.6 × 0.4 m footprint at 1.5 m suits its small cases; a
  // building or bridge (largest extent > 20 m) with no camera in the config gets a
  // 1-inch 20 MP inspection camera at 2 mm/px (7.3 m standoff, 10.9 × 7.3 m photos).
  const bool camera_set = c.sources.anyFromFile("camera.") || c.setInFile(&c.coverage.standoff_m);
  // A single terrestrial scan (a room, a street) is close-range work: the paper's camera.
  const bool large =
      !camera_set && stats.extent_m.maxCoeff() > kLargeStructureM && !stats.scanned_from_origin;
  auto& cam = c.coverage.camera;
  if (large && c.sources.of(c.keyOf(&cam.sensor_w_mm)) == params::Source::Profile) {
    // The aircraft profile's camera stays; only its GSD follows the structure's size.
    c.sources.set(c.keyOf(&cam.gsd_mm_per_px), params::Source::Auto);
    cam.gsd_mm_per_px = 2.0;
    r.values.push_back({c.keyOf(&cam.gsd_mm_per_px), cam.gsd_mm_per_px,
                        "auto: the profile's camera at 2 mm/px (structure > 20 m)"});
  } else if (large) {
    cam.from_sensor = true;
    cam.sensor_w_mm = 13.2;
    cam.sensor_h_mm = 8.8;
    cam.focal_mm = 8.8;
    cam.image_w_px = 5472;
    cam.image_h_px = 3648;
    cam.gsd_mm_per_px = 2.0;
    r.values.push_back({c.keyOf(&cam.gsd_mm_per_px), cam.gsd_mm_per_px,
                        "auto: 1-inch 20 MP camera (structure > 20 m)"});
  } else {
    r.values.push_back({c.keyOf(&c.coverage.standoff_m), c.coverage.standoff_m,
                        camera_set ? "set" : "default (paper)"});
  }

  purposeOverlap(r);

  // The planning grid of the whole site (app::plan applies the rule again to the
  // region it plans): a 1 km site gets a coarser grid, not an error.
  resolve(r, c.grid.resolution_m, autoGridResolution(stats.extent_m, c.grid),
          "max(0.2, (site volume / (max_voxels/4))^(1/3))");
  c.validate("config");
  return r;
}

}  // namespace uavip::app
