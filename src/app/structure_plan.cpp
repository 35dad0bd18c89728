/// \file
/// app::planStructure (app/pipeline.h): structure coverage over the whole cloud.

#include <algorithm>
#include <cmath>
#include <future>
#include <limits>
#include <memory>

#include "plan_steps.h"
#include "planners/registry.h"
#include "uavip/app/pipeline.h"
#include "uavip/core/error.h"
#include "uavip/core/geometry.h"
#include "uavip/core/parallel.h"
#include "uavip/core/stopwatch.h"
#include "uavip/core/text.h"
#include "uavip/core/voxel_key.h"
#include "uavip/coverage/coverage_evaluator.h"
#include "uavip/coverage/multi_view.h"
#include "uavip/coverage/pixel_coverage.h"
#include "uavip/coverage/structure_views.h"
#include "uavip/planning/tour.h"
#include "uavip/preprocess/normals.h"

namespace uavip::app {
namespace {

constexpr double kMaxIncidenceDeg = 75.0;  ///< rule (b) and the view selection
constexpr double kRangeAllowance = 1.25;   ///< photos count up to 1.25 × the viewing distance
/// The view selection scores at most this many structure points (a voxel grid thins more).
constexpr std::size_t kMaxScoredPoints = 40000;
constexpr int kNormalNeighbours = 12;
/// A reconstruction's photos are registered (structure_views.h, simulated incremental
/// registration) when this share of a photo's points is seen by two photos of the model
/// within kLinkMaxAngleDeg of its axis: the overlap and the viewpoint change SIFT
/// matching bridges across the structure's edges. Corner candidates turned by
/// kCornerYawDeg see both faces of a vertical edge, each within the link angle of the
/// face-on photos. Measured by COLMAP on the tower (issue 46, ¼-resolution photos):
/// share 0.3 gave 161 photos in 3 models (largest 100), 0.5 gives 209 in one.
constexpr double kLinkShare = 0.5;
constexpr double kLinkMaxAngleDeg = 50.0;
constexpr double kCornerYawDeg = 45.0;
/// A reconstruction counts a photo's view of a point only within this incidence [deg]
/// (kMaxIncidenceDeg otherwise): SIFT matches little at grazing views. The tower's
/// platform top and underside, seen by a median 32 and 25 photos within
/// kMaxIncidenceDeg but 11 and 3 within 45°, were what COLMAP's points left out.
/// Below 60° the simulated registration splits the tower's photos (45°: 30 groups).
constexpr double kReconstructionMaxIncidenceDeg = 60.0;

/// The clean cloud without the ground (app/pipeline.h, planStructure): returns the
/// structure points; `ground` counts the others, `ground_z` gets the height of the
/// highest ground surface found (none: unset). coverage.ground_z_m, when given, alone
/// says where the ground is (a plinth or a deck at the cloud's lowest level is then
/// structure); otherwise the level surfaces at the lowest level are the ground.
PointList structurePoints(const Scene& scene, const app::Config& config, std::size_t& ground,
                          std::optional<double>& ground_z) {
  const Aabb box = boundingBox(scene.cloud);
  const double footprint = (box.max.x() - box.min.x()) * (box.max.y() - box.min.y());
  const double band = config.perception.planes.distance_threshold_m;
  std::vector<const Surface*> level;
  const std::vector<Surface> none;
  for (const auto& s : config.coverage.ground_z_m ? none : scene.surfaces) {
    if (s.plane.normal.z() >= 0.95 && s.centroid.z() <= box.min.z() + std::max(1.0, 2.0 * band) &&
        s.area_m2 >= 0.25 * footprint) {
      level.push_back(&s);
      ground_z = std::max(ground_z.value_or(s.centroid.z()), s.centroid.z());
    }
  }
  PointList out;
  ground = 0;
  for (const auto& p : scene.cloud) {
    bool is_ground = config.coverage.ground_z_m && p.z() < *config.coverage.ground_z_m;
    for (const Surface* s : level)
      is_ground = is_ground || std::abs(s->plane.signedDistance(p)) <= band;
    if (is_ground) {
      ++ground;
    } else {
      out.push_back(p);
    }
  }
  return out;
}

/// At most kMaxScoredPoints points: a voxel grid of growing edge.
PointList thinForScoring(const PointList& points, double spacing_m) {
  if (points.size() <= kMaxScoredPoints) return points;
  double edge = std::max(spacing_m, 0.05);
  PointList thin = points;
  while (thin.size() > kMaxScoredPoints) {
    edge *= 1.25;
    thin = voxelDownsample(points, edge, "structure scoring voxel");
  }
  return thin;
}

/// The camera as a pinhole (a footprint camera gets the footprint's field of view
/// over 1000 px of width).
coverage::PinholeIntrinsics structureIntrinsics(const coverage::Camera& c, double standoff_m) {
  coverage::PinholeIntrinsics k;
  if (c.pinhole) {
    k.width_px = c.image_w_px;
    k.height_px = c.image_h_px;
    k.fx_px = c.fx_px;
    k.fy_px = c.fy_px;
    k.cx_px = c.cx_px;
    k.cy_px = c.cy_px;
  } else if (c.from_sensor) {
    k.width_px = c.image_w_px;
    k.height_px = c.image_h_px;
    k.fx_px = c.focal_mm * c.image_w_px / c.sensor_w_mm;
    k.fy_px = c.focal_mm * c.image_h_px / c.sensor_h_mm;
    k.cx_px = 0.5 * k.width_px;
    k.cy_px = 0.5 * k.height_px;
  } else {
    k.width_px = 1000;
    k.height_px =
        std::max(1, static_cast<int>(std::lround(1000.0 * c.footprint_h_m / c.footprint_w_m)));
    k.fx_px = k.fy_px = 1000.0 * standoff_m / c.footprint_w_m;
    k.cx_px = 0.5 * k.width_px;
    k.cy_px = 0.5 * k.height_px;
  }
  return k;
}

/// The central part of the image a photo is chosen for: coverage.overlap cropped
/// off (half on each side), so neighbouring photos overlap and leave no sliver
/// between the points they were chosen for.
coverage::PinholeIntrinsics cropForOverlap(coverage::PinholeIntrinsics k, double overlap_w,
                                           double overlap_h) {
  const double crop_w = std::floor(0.5 * overlap_w * k.width_px),
               crop_h = std::floor(0.5 * overlap_h * k.height_px);
  k.width_px -= static_cast<int>(2.0 * crop_w);
  k.height_px -= static_cast<int>(2.0 * crop_h);
  k.cx_px -= crop_w;
  k.cy_px -= crop_h;
  return k;
}

/// The camera a photo is chosen for: a reconstruction counts what the whole image
/// shows (its min_views photos of every point overlap by themselves); inspection and
/// mosaic crop coverage.overlap off (cropForOverlap).
coverage::PinholeIntrinsics scoringIntrinsics(const coverage::PinholeIntrinsics& k,
                                              const app::Config& config) {
  if (config.coverage.purpose == "reconstruction") return k;
  return cropForOverlap(k, config.coverage.overlap_w, config.coverage.overlap_h);
}

/// coverage.standoff_m when set, else what the camera's GSD implies.
double viewingDistance(const app::Config& config) {
  if (config.setInFile(&config.coverage.standoff_m)) return config.coverage.standoff_m;
  return coverage::solveCamera(config.coverage.camera, config.coverage.standoff_m).standoff_m;
}

/// Rule (b): in the image, GSD and range within kRangeAllowance × the viewing
/// distance (and camera.max_range_m), incidence ≤ kMaxIncidenceDeg (normals oriented
/// by orientNormals); the line of sight is given separately.
coverage::CoverageCriteria ruleB(const coverage::PinholeIntrinsics& k, const coverage::Camera& c,
                                 double standoff_m) {
  coverage::CoverageCriteria criteria;
  criteria.max_incidence_deg = kMaxIncidenceDeg;
  criteria.max_range_m = kRangeAllowance * standoff_m;
  if (c.max_range_m > 0.0) criteria.max_range_m = std::min(criteria.max_range_m, c.max_range_m);
  criteria.max_gsd_mm_per_px = kRangeAllowance * standoff_m * 1000.0 / std::min(k.fx_px, k.fy_px);
  return criteria;
}

/// Orients each normal toward the free space the UAV can reach: a side is open when
/// the voxels from 2 voxels to `probe_m` along it hold no point and its end is
/// reachable; one open side orients the normal, both or none leave it two-sided.
std::vector<char> orientNormals(const PointList& points, std::vector<Vec3>& normals,
                                const coverage::VoxelLineOfSight& sight,
                                const coverage::ViewpointFree& reachable, double probe_m) {
  std::vector<char> two_sided(points.size(), 1);
  const double step = 0.5 * sight.voxelSize();
  const auto open = [&](const Vec3& p, const Vec3& n) {
    for (double t = 2.0 * sight.voxelSize(); t < probe_m; t += step)
      if (sight.occupied(p + t * n)) return false;
    return reachable(p + probe_m * n);
  };
  for (std::size_t i = 0; i < points.size(); ++i) {
    const bool plus = open(points[i], normals[i]);
    const bool minus = open(points[i], -normals[i]);
    if (plus == minus) continue;
    two_sided[i] = 0;
    if (minus) normals[i] = -normals[i];
  }
  return two_sided;
}

/// The flight strategy of the chosen photos, in flight order from `start`.
/// Ordering cost of a hop that neither a straight segment nor a one-point detour
/// flies: this many times its length plus kBlockedHopExtraM, so that the order avoids
/// it wherever it can (the planner's way around a building is long and slow to find).
constexpr double kBlockedHopFactor = 3.0;
constexpr double kBlockedHopExtraM = 50.0;

/// `share_cost_m` > 0 (a mosaic or a reconstruction): a hop between photos also costs
/// share_cost_m × (1 − imagedShare of the two), so that consecutive photos image
/// what their neighbour does where the path allows it.
coverage::FlightStrategy structureStrategy(const coverage::StructureViews& views, const Vec3& start,
                                           int id, const coverage::PinholeIntrinsics& k,
                                           double standoff_m, const world::VoxelGrid& grid,
                                           double share_cost_m) {
  coverage::FlightStrategy s;
  s.surface_id = id;
  s.camera.standoff_m = standoff_m;
  s.camera.footprint_w_m = standoff_m * k.width_px / k.fx_px;
  s.camera.footprint_h_m = standoff_m * k.height_px / k.fy_px;
  s.camera.gsd_w_mm = standoff_m * 1000.0 / k.fx_px;
  s.camera.gsd_h_mm = standoff_m * 1000.0 / k.fy_px;
  PointList positions;
  for (const auto& v : views.views) positions.push_back(v.position);
  const auto at = [&](int i) -> const Vec3& {
    return i < 0 ? start : positions[static_cast<std::size_t>(i)];
  };
  // straightOrDetour only reads the grid: the pairs are costed on every core.
  const std::vector<int> order = planning::orderOpenPath(
      start, positions,
      [&](int a, int b) {
        const PointList hop = planning::straightOrDetour(grid, at(a), at(b));
        const double length = hop.empty()
                                  ? kBlockedHopFactor * (at(a) - at(b)).norm() + kBlockedHopExtraM
                                  : polylineLength(hop);
        if (share_cost_m <= 0.0 || a < 0 || b < 0) return length;
        return length + share_cost_m * (1.0 - coverage::imagedShare(
                                                  views.imaged[static_cast<std::size_t>(a)],
                                                  views.imaged[static_cast<std::size_t>(b)]));
      },
      50, hardwareThreads());
  s.cols = static_cast<int>(order.size());
  s.rows = 1;
  for (std::size_t n = 0; n < order.size(); ++n) {
    const auto i = static_cast<std::size_t>(order[n]);
    coverage::Stop stop;
    stop.index = static_cast<int>(n);
    stop.surface_id = id;
    stop.col = static_cast<int>(n);
    stop.position = views.views[i].position;
    stop.target = views.targets[i];
    stop.yaw_deg = views.views[i].yaw_deg;
    stop.gimbal_pitch_deg = views.views[i].pitch_deg;
    s.stops.push_back(stop);
  }
  return s;
}

/// The viewing distance, which must lie beyond the clearance (InputError).
double checkedStandoff(const app::Config& config, double clearance_m) {
  const double standoff = viewingDistance(config);
  if (!(standoff > clearance_m)) {
    throw InputError(
        "coverage.standoff_m: viewing distance " + formatFixed(standoff, 2) + " m is inside the " +
        formatFixed(clearance_m, 2) +
        " m the UAV keeps from every measured point; fly farther (coverage.standoff_m) or use a "
        "smaller uav.inflation_radius_m");
  }
  return standoff;
}

/// The structure's points as scored, their normals (oriented later), the ground height.
struct StructurePoints {
  PointList points;
  std::vector<Vec3> normals;
  std::vector<char> two_sided;
  std::optional<double> ground_z;
};

StructurePoints prepareStructure(const Scene& scene, const app::Config& config,
                                 planning::StructureSummary& summary, const Progress& progress) {
  StructurePoints s;
  s.ground_z = config.coverage.ground_z_m;
  const PointList structure = structurePoints(scene, config, summary.ground_points, s.ground_z);
  if (structure.empty()) {
    throw InputError(
        "structure coverage: all " + std::to_string(scene.cloud.size()) +
        " points of the scene are ground (level surfaces at its lowest level, or below "
        "coverage.ground_z_m); nothing to photograph");
  }
  s.points = thinForScoring(structure, scene.measured ? scene.measured->spacing_m : 0.0);
  summary.points = s.points.size();
  reportProgress(progress, "structure: normals of " + std::to_string(s.points.size()) + " points");
  s.normals = preprocess::estimateNormals(s.points, s.points, kNormalNeighbours);
  return s;
}

/// The planning grid over the structure's box grown by the viewing distance (and
/// mission.start / mission.home), with the validator on `world`; both must be free.
world::VoxelGrid structureGrid(const Scene& scene, const app::Config& config,
                               const PointList& points, double standoff,
                               const std::shared_ptr<const world::CollisionWorld>& world,
                               PlanResult& result,
                               std::unique_ptr<planning::PathValidator>& validator) {
  Aabb box = boundingBox(points);
  box.min.array() -= standoff;
  box.max.array() += standoff;
  PointList corners = {box.min, box.max};
  if (config.mission.start) corners.push_back(*config.mission.start);
  if (config.flight.home) corners.push_back(*config.flight.home);
  addFleetRegion(config, corners, std::numeric_limits<std::size_t>::max());
  PlanningSpace space = planningSpace(scene, world, config, corners);
  world::VoxelGrid grid = std::move(space.grid);
  validator = std::make_unique<planning::PathValidator>(std::move(space.validator));
  requireFree(config.mission.start, config.keyOf(&config.mission.start), *validator);
  requireFree(config.flight.home, config.keyOf(&config.flight.home), *validator);
  result.grid_resolution_m = grid.resolution();
  result.grid_voxels = grid.voxelCount();
  result.grid_blocked = grid.blockedCount();
  return grid;
}

/// Where a photo may be taken: a free voxel in the free space reachable from home (or
/// from the grid's top corner, outside the structure), above the ground + clearance.
coverage::ViewpointFree viewpointTest(const world::VoxelGrid& grid, const std::optional<Vec3>& home,
                                      const std::optional<double>& ground_z, double clearance_m) {
  const auto dims = grid.dims();
  const std::int32_t outside = home ? grid.component(grid.indexOf(*home))
                                    : grid.component({dims[0] - 1, dims[1] - 1, dims[2] - 1});
  const std::optional<double> floor_z =
      ground_z ? std::optional<double>(*ground_z + clearance_m) : std::nullopt;
  return [&grid, outside, floor_z](const Vec3& p) {
    const world::Index3 i = grid.indexOf(p);
    return grid.inBounds(i) && outside != 0 && grid.component(i) == outside &&
           (!floor_z || p.z() >= *floor_z);
  };
}

/// The view selection's options for this config and camera.
coverage::StructureViewOptions viewOptions(const app::Config& config,
                                           const coverage::PinholeIntrinsics& k, double standoff) {
  coverage::StructureViewOptions options;
  options.standoff_m = standoff;
  options.distance_factors = {1.0};
  if (config.mission.max_standoff_factor > 1.0)
    options.distance_factors.push_back(config.mission.max_standoff_factor);
  options.tilts_deg = {20.0, 45.0};
  // Seeds closer than half the photo's smaller side: a narrow camera leaves no gaps.
  options.seed_spacing_m = std::min(
      standoff / 3.0, 0.5 * standoff * std::min(k.width_px / k.fx_px, k.height_px / k.fy_px));
  options.target_coverage = config.coverage.structure_target;
  options.gimbal = config.coverage.gimbal;
  options.criteria = ruleB(k, config.coverage.camera, standoff);
  options.threads = hardwareThreads();
  if (config.coverage.purpose != "inspection") options.prefer_consistent = true;
  if (config.coverage.purpose == "reconstruction") {
    options.min_views = config.coverage.min_views;
    options.min_triangulation_deg = config.coverage.min_triangulation_deg;
    options.link_share = kLinkShare;
    options.link_max_angle_deg = kLinkMaxAngleDeg;
    options.yaws_deg = {kCornerYawDeg};
    options.criteria.max_incidence_deg = kReconstructionMaxIncidenceDeg;
  }
  return options;
}

/// The lowest photo when no home is given: where the open path starts.
Vec3 pathStart(const std::optional<Vec3>& home, const coverage::StructureViews& views) {
  if (home) return *home;
  Vec3 start = Vec3::Zero();
  for (std::size_t k = 0; k < views.views.size(); ++k)
    if (k == 0 || views.views[k].position.z() < start.z()) start = views.views[k].position;
  return start;
}

/// A mosaic's or a reconstruction's multi-view counts of the flown photos
/// (coverage/multi_view.h, rule (b) with the full image) and the least share of what
/// consecutive flown photos image (imagedShare), into the mission.
void multiViewFlown(planning::SurfaceMission& mission, const StructurePoints& s,
                    const std::vector<coverage::ViewPose>& flown,
                    const coverage::PinholeCamera& camera,
                    const coverage::StructureViewOptions& options,
                    const coverage::LineOfSight& sight) {
  const coverage::MultiViewStats st = coverage::multiViewStats(
      s.points, s.normals, flown, camera, options.criteria, &sight, options.threads, &s.two_sided);
  auto& c = mission.coverage;
  c.multi_view = true;
  c.views_min = st.views_min;
  c.views_median = st.views_median;
  if (options.min_views > 1)
    c.views_below_min = std::count_if(st.views.begin(), st.views.end(),
                                      [&](int v) { return v < options.min_views; });
  c.angle_min_deg = st.angle_min_deg;
  c.angle_median_deg = st.angle_median_deg;
  const auto imaged = coverage::imagedByView(s.points, s.normals, flown, camera, options.criteria,
                                             &sight, options.threads, &s.two_sided);
  for (std::size_t i = 1; i < imaged.size(); ++i)
    c.consecutive_share_min =
        std::min(c.consecutive_share_min, coverage::imagedShare(imaged[i - 1], imaged[i]));
}

/// Both coverage rules at the flown stops, into the mission and the summary.
void scoreFlown(planning::SurfaceMission& mission, const StructurePoints& s,
                const coverage::PinholeIntrinsics& k, const coverage::StructureViewOptions& options,
                const coverage::LineOfSight& sight, const app::Config& config,
                planning::StructureSummary& summary) {
  std::vector<coverage::ViewPose> flown;
  for (std::size_t i = 0; i < mission.strategy.stops.size(); ++i) {
    if (mission.stop_problems[i] != planning::StopProblem::None ||
        !planning::flyable(mission.status))
      continue;
    const auto& stop = mission.strategy.stops[i];
    flown.push_back({stop.position, stop.yaw_deg, stop.gimbal_pitch_deg});
  }
  const coverage::PinholeCamera camera(k);
  const coverage::CoverageResult b = coverage::evaluateCoverage(
      s.points, s.normals, flown, camera, options.criteria, &sight, options.threads, &s.two_sided);
  summary.visible_range_m = config.coverage.camera.max_range_m > 0.0
                                ? config.coverage.camera.max_range_m
                                : kRangeAllowance * summary.standoff_m;
  summary.rule_a =
      coverage::evaluatePixelCoverage(s.points, flown, k, summary.visible_range_m, options.threads)
          .fraction;
  summary.rule_b = b.fraction;
  mission.coverage.evaluated = true;
  mission.coverage.fraction = b.fraction;
  mission.coverage.points = b.points;
  mission.coverage.uncovered = b.uncovered.size();
  for (const auto i : b.uncovered) mission.coverage.uncovered_points.push_back(s.points[i]);
  if (config.coverage.purpose != "inspection")
    multiViewFlown(mission, s, flown, camera, options, sight);
}

/// The line of sight used for aiming: each point closes a cube of max(voxel, point
/// spacing) around it, so a face is a wall without holes and no camera aims at its seed
/// through it (coverage_evaluator.h). Scoring keeps the undilated sight.
coverage::VoxelLineOfSight aimingSight(const Scene& scene, const world::VoxelGrid& grid) {
  const double spacing = scene.measured ? scene.measured->spacing_m : 0.0;
  return coverage::VoxelLineOfSight(scene.cloud, grid.resolution(), 3.5 * grid.resolution(),
                                    std::max(grid.resolution(), spacing));
}

/// The selection's counts (seeds, candidates, photos, linking photos, groups) into the summary.
void copyViewCounts(const coverage::StructureViews& views, planning::StructureSummary& summary) {
  summary.seeds = views.seeds;
  summary.candidates = views.candidates;
  summary.free_candidates = views.free_candidates;
  summary.imageable = views.imageable;
  summary.photos = views.views.size();
  summary.linking_photos = views.linking;
  summary.photo_groups = views.components;
}

}  // namespace

PlanResult planStructure(const Scene& scene, const app::Config& config, const Progress& progress) {
  PlanResult result;
  planning::StructureSummary summary;
  const auto t0 = SteadyClock::now();
  result.clearance_m = safetyClearance(scene, config);
  summary.standoff_m = checkedStandoff(config, result.clearance_m);
  const double standoff = summary.standoff_m;
  // The collision world needs the scene only: built on a second thread beside the
  // structure's points and normals.
  auto world_build = std::async(std::launch::async, [&scene] {
    return std::make_shared<const world::CollisionWorld>(scene);
  });
  StructurePoints s = prepareStructure(scene, config, summary, progress);
  reportProgress(progress, "structure: inflated voxel grid");
  std::unique_ptr<planning::PathValidator> validator;
  const world::VoxelGrid grid =
      structureGrid(scene, config, s.points, standoff, world_build.get(), result, validator);
  result.times.grid_s = secondsSince(t0);

  const auto t_prepare = SteadyClock::now();
  const std::optional<Vec3> home = config.mission.start ? config.mission.start : config.flight.home;
  const coverage::ViewpointFree is_free = viewpointTest(grid, home, s.ground_z, result.clearance_m);
  const coverage::PinholeIntrinsics intrinsics =
      structureIntrinsics(config.coverage.camera, standoff);
  const coverage::PinholeCamera scoring_camera(scoringIntrinsics(intrinsics, config));
  const coverage::VoxelLineOfSight sight(scene.cloud, grid.resolution(), 3.5 * grid.resolution());
  const coverage::VoxelLineOfSight aim_sight = aimingSight(scene, grid);
  s.two_sided = orientNormals(s.points, s.normals, sight, is_free,
                              result.clearance_m + 2.0 * grid.resolution());
  const coverage::StructureViewOptions options = viewOptions(config, intrinsics, standoff);
  const auto t1 = SteadyClock::now();
  summary.prepare_s = secondsSince(t_prepare);
  reportProgress(progress, "structure: choosing photos");
  const coverage::StructureViews views = selectStructureViews(
      s.points, s.normals, s.two_sided, scoring_camera, &sight, is_free, options, &aim_sight);
  summary.select_s = secondsSince(t1);
  copyViewCounts(views, summary);
  result.times.coverage_s = secondsSince(t0);

  const auto t2 = SteadyClock::now();
  for (const auto& surface : scene.surfaces)
    summary.surface_id = std::max(summary.surface_id, surface.id + 1);
  const coverage::FlightStrategy strategy =
      structureStrategy(views, pathStart(home, views), summary.surface_id, intrinsics, standoff,
                        grid, config.coverage.purpose == "inspection" ? 0.0 : standoff);
  summary.order_s = secondsSince(t2);
  const auto t_legs = SteadyClock::now();
  reportProgress(progress, "structure: " + std::to_string(strategy.stops.size()) +
                               " photos, legs between them");
  const auto planner = planners::makePlanner(config.planner, config.planner_settings);
  planning::MissionOptions mission_options = config.missionOptions();
  mission_options.direct_legs = true;
  mission_options.mosaic_repair = false;  // views, not rows: nothing to slide along or to cover
  planning::SurfaceMission mission =
      planning::planSurfaceMission(strategy, grid, *validator, *planner, mission_options);
  mission.kind = "structure";
  if (strategy.stops.empty()) {
    mission.reason = "no free viewpoint: no camera pose " + formatFixed(standoff, 2) +
                     " m from the structure is clear of every measured point by " +
                     formatFixed(result.clearance_m, 2) + " m and reachable from outside";
  }
  summary.legs_s = secondsSince(t_legs);
  const auto t_score = SteadyClock::now();
  scoreFlown(mission, s, intrinsics, options, sight, config, summary);
  summary.score_s = secondsSince(t_score);
  result.missions.push_back(std::move(mission));
  result.times.planning_s = secondsSince(t2);

  const auto t3 = SteadyClock::now();
  reportProgress(progress, "flight: connecting legs, sorties");
  result.flight = flyMissions(result.missions, grid, *validator, *planner, config);
  result.times.flight_s = secondsSince(t3);
  result.fleet = flyFleet(result.missions, result.flight, grid, *validator, *planner, config);
  result.times.total_s = secondsSince(t0);
  result.structure = summary;
  return result;
}

}  // namespace uavip::app
