#include "uavip/app/pipeline.h"

#include <algorithm>
#include <future>
#include <iomanip>
#include <limits>
#include <memory>
#include <sstream>

#include "plan_steps.h"
#include "planners/astar.h"
#include "planners/registry.h"
#include "uavip/app/assemble.h"
#include "uavip/app/assemble_truth.h"
#include "uavip/core/error.h"
#include "uavip/core/geometry.h"
#include "uavip/core/parallel.h"
#include "uavip/core/stopwatch.h"
#include "uavip/core/text.h"
#include "uavip/coverage/coverage_evaluator.h"
#include "uavip/coverage/flight_strategy.h"
#include "uavip/coverage/multi_view.h"
#include "uavip/io/cloud_io.h"
#include "uavip/perception/scene_builder.h"
#include "uavip/planning/path_validator.h"
#include "uavip/preprocess/safety_cloud.h"
#include "uavip/sim/surface_sampler.h"
#include "uavip/world/collision_world.h"
#include "uavip/world/solids.h"
#include "uavip/world/voxel_grid.h"

#ifndef UAVIP_VERSION
#define UAVIP_VERSION "dev"
#endif

namespace uavip::app {
namespace {

/// Free space kept around the photo stops when the planning grid is cropped to them [m].
constexpr double kLocalMarginM = 6.0;

/// The poses of a mission's flown stops.
std::vector<coverage::ViewPose> flownViews(const planning::SurfaceMission& m) {
  std::vector<coverage::ViewPose> views;
  for (std::size_t k = 0; k < m.strategy.stops.size(); ++k) {
    if (m.stop_problems[k] != planning::StopProblem::None) continue;
    const auto& s = m.strategy.stops[k];
    views.push_back({s.position, s.yaw_deg, s.gimbal_pitch_deg});
  }
  return views;
}

/// The camera the flown photos' coverage is measured with: the footprint frustum, out
/// to 1.5 × the standoff (or mission.max_standoff_factor).
coverage::FootprintCamera coverageCamera(const app::Config& config) {
  coverage::FootprintCameraOptions camera_options;
  camera_options.camera = config.coverage.camera;
  camera_options.standoff_m = config.coverage.standoff_m;
  camera_options.range_slack = std::max(1.5, config.mission.max_standoff_factor);
  return coverage::FootprintCamera(camera_options);
}

/// What counts as imaged in a mission's coverage: incidence <= 75°.
coverage::CoverageCriteria coverageCriteria() {
  coverage::CoverageCriteria criteria;
  criteria.max_incidence_deg = 75.0;
  return criteria;
}

/// Coverage (coverage_evaluator.h) of a flyable mission: the surface's points that a
/// flown stop images — inside the photo (the footprint frustum, out to 1.5 × the
/// standoff), incidence ≤ 75° (coverageCriteria), line of sight through the cloud's voxels
/// (grid-sized; a ray ends 3.5 voxels before its point, whose own surface never hides it
/// at ≤ 75°).
/// Nothing when the mission is not flyable or the surface has no points; applyCoverage
/// writes it into the mission. The views are shared by every core, but beside the
/// flight only the calling thread works until `gate` opens (the flight's A* legs use
/// the other core; the same counts).
std::optional<coverage::CoverageResult> coverageOf(const planning::SurfaceMission& m,
                                                   const Surface& surface,
                                                   const coverage::LineOfSight& sight,
                                                   const app::Config& config, WorkerGate& gate) {
  if (!planning::flyable(m.status) || surface.inliers.empty()) return std::nullopt;
  return coverage::evaluateCoverage(surface.inliers, {surface.plane.normal}, flownViews(m),
                                    coverageCamera(config), coverageCriteria(), &sight,
                                    hardwareThreads(), nullptr, &gate);
}

/// Views per point, triangulation angles (coverage/multi_view.h, the same test as
/// coverageOf) and the least footprint share of consecutive flown photos, recorded in
/// a mission whose coverage was measured, for a purpose other than inspection.
void applyMultiView(planning::SurfaceMission& m, const Surface& surface,
                    const coverage::LineOfSight& sight, const app::Config& config) {
  if (config.coverage.purpose == "inspection" || !m.coverage.evaluated) return;
  const coverage::MultiViewStats st = coverage::multiViewStats(
      surface.inliers, {surface.plane.normal}, flownViews(m), coverageCamera(config),
      coverageCriteria(), &sight, hardwareThreads());
  auto& c = m.coverage;
  c.multi_view = true;
  c.views_min = st.views_min;
  c.views_median = st.views_median;
  if (config.coverage.purpose == "reconstruction")
    c.views_below_min = std::count_if(st.views.begin(), st.views.end(),
                                      [&](int v) { return v < config.coverage.min_views; });
  c.angle_min_deg = st.angle_min_deg;
  c.angle_median_deg = st.angle_median_deg;
  const coverage::Stop* previous = nullptr;
  for (std::size_t k = 0; k < m.strategy.stops.size(); ++k) {
    if (m.stop_problems[k] != planning::StopProblem::None) continue;
    const coverage::Stop& s = m.strategy.stops[k];
    if (previous != nullptr)
      c.consecutive_share_min =
          std::min(c.consecutive_share_min, coverage::footprintShare(m.strategy, *previous, s));
    previous = &s;
  }
}

/// Records coverageOf's result `r` in the mission. Below mission.min_coverage an `ok`
/// surface becomes `partial`, stating the fraction.
void applyCoverage(planning::SurfaceMission& m, const coverage::CoverageResult& r,
                   const Surface& surface, const app::Config& config) {
  m.coverage.evaluated = true;
  m.coverage.fraction = r.fraction;
  m.coverage.points = r.points;
  m.coverage.uncovered = r.uncovered.size();
  for (const auto i : r.uncovered) m.coverage.uncovered_points.push_back(surface.inliers[i]);
  if (r.fraction < config.mission.min_coverage) {
    std::ostringstream os;
    os << "coverage " << std::fixed << std::setprecision(1) << 100.0 * r.fraction
       << " % of the surface's points (" << r.uncovered.size()
       << " not imaged) is below mission.min_coverage " << 100.0 * config.mission.min_coverage
       << " %";
    m.status = planning::SurfaceStatus::Partial;
    m.reason = m.reason.empty() ? os.str() : m.reason + "; " + os.str();
  }
}

}  // namespace

PointList sense(const app::Scenario& scenario) {
  // Mode scan: simulate the raw scans, then stages 1-2 (app/assemble.h).
  if (scenario.sensing_mode == "scan") return senseScans(scenario).cloud;
  return sim::sampleSurfaces(scenario.world, scenario.sample);
}

Vec3 recentreScenario(app::Scenario& scenario) {
  Aabb box;
  for (const auto& r : scenario.world.rects()) {
    for (const Vec3& p : {r.corner, Vec3(r.corner + r.edge_u), Vec3(r.corner + r.edge_v),
                          Vec3(r.corner + r.edge_u + r.edge_v)})
      box.extend(p);
  }
  for (const auto& s : scenario.world.segments()) {
    box.extend(s.a);
    box.extend(s.b);
  }
  for (const auto& p : scenario.world.points()) box.extend(p.p);
  if (box.empty() || !io::farFromOrigin(box.min, box.max)) return Vec3::Zero();
  Vec3 origin = io::recentringOrigin(box.min, box.max);
  scenario.world = worldInLogFrame(scenario.world, origin);
  for (Vec3& s : scenario.scan.stations) s -= origin;
  auto& planes = scenario.config.perception.planes;
  planes.viewpoint -= origin;
  for (Vec3& v : planes.extra_viewpoints) v -= origin;
  for (std::optional<Vec3>* p : {&scenario.config.mission.start, &scenario.config.flight.home,
                                 &scenario.config.flight.start})
    if (*p) **p -= origin;
  return origin;
}

preprocess::CloudStats measure(const PointList& raw, const app::Scenario* scenario,
                               CloudIndex* index) {
  for (std::size_t i = 0; i < raw.size(); ++i) {
    if (!raw[i].allFinite())
      throw InputError("cloud: point " + std::to_string(i) + " is not finite");
  }
  CloudIndex tree = raw.size() >= 2 ? std::make_shared<const NeighbourIndex>(raw) : nullptr;
  preprocess::CloudStats stats = preprocess::measureCloud(raw, {}, tree.get());
  if (index != nullptr) *index = std::move(tree);
  if (scenario != nullptr) {
    stats.lattice = true;
    if (scenario->sensing_mode == "sample" && scenario->sample.spacing_m > 0.0) {
      stats.spacing_m = scenario->sample.spacing_m;
    }
  }
  return stats;
}

DetectResult detect(const PointList& raw, const app::Config& config,
                    const preprocess::CloudStats& cloud, const Progress& progress,
                    const CloudIndex& index) {
  DetectResult result;
  result.resolved = resolveConfig(config, cloud);
  const app::Config& resolved = result.resolved.config;
  const auto t0 = SteadyClock::now();
  reportProgress(progress, "stage 3: outlier removal and voxel grid on " +
                               std::to_string(raw.size()) + " points");
  PointList clean =
      preprocess::preprocess(raw, resolved.preprocess, &result.preprocess, index.get());
  result.times.preprocess_s = secondsSince(t0);

  const auto t1 = SteadyClock::now();
  // Safety keeps every input point, whatever stage 3 dropped or merged. Built on a
  // second thread beside stages 4-5, which run on one (its time is in theirs).
  auto safety = std::async(std::launch::async, [&raw, cell = resolved.safety.cell_m] {
    return preprocess::safetyCloud(raw, cell);
  });
  reportProgress(progress, "stages 4-5: planes and obstacle clusters on " +
                               std::to_string(clean.size()) + " points");
  result.scene = perception::buildScene(clean, resolved.perception);
  result.scene.measured = cloud;
  result.scene.safety = safety.get();
  result.scene.safety->perception_dropped =
      result.preprocess.input_points - result.preprocess.after_outliers;
  result.times.perception_s = secondsSince(t1);
  result.times.total_s = secondsSince(t0);
  return result;
}

double safetyClearance(const Scene& scene, const app::Config& config) {
  const double uav = config.uav.inflationRadius();
  // No safety cloud (an older scene): the points alone. A mesh input: the collision
  // world measures to its triangles exactly, so neither the thinning margin nor the
  // sparse-cloud allowance is needed (the grid marks every triangle, solidSamples).
  if (!scene.safety || scene.safety->mesh) return uav;
  const double spacing = scene.measured ? scene.measured->spacing_m : 0.0;
  return uav + preprocess::safetyMargin(*scene.safety, spacing, config.safety);
}

ResolvedConfig resolveForScene(const Scene& scene, const app::Config& config) {
  return resolveConfig(config,
                       scene.measured ? *scene.measured : preprocess::measureCloud(scene.cloud));
}

std::vector<int> selectSurfaces(const Scene& scene, const std::string& selection) {
  std::vector<int> ids;
  if (selection == "all") {
    for (const auto& s : scene.surfaces) ids.push_back(s.id);
    return ids;
  }
  std::string valid;
  for (const auto& s : scene.surfaces) valid += (valid.empty() ? "" : ", ") + std::to_string(s.id);
  if (valid.empty()) valid = "none: no surface was detected";
  std::stringstream list(selection);
  std::string item;
  while (std::getline(list, item, ',')) {
    int id = -1;
    try {
      std::size_t used = 0;
      id = std::stoi(item, &used);
      if (used != item.size()) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      throw InputError(
          "--surface: '" + selection +
          "' is not a surface id, a list of ids like 0,3,5, or 'all' (valid ids: " + valid + ")");
    }
    const bool exists = std::any_of(scene.surfaces.begin(), scene.surfaces.end(),
                                    [id](const Surface& s) { return s.id == id; });
    if (!exists)
      throw InputError("--surface: no surface with id " + item + " (valid ids: " + valid + ")");
    if (std::find(ids.begin(), ids.end(), id) != ids.end())
      throw InputError("--surface: surface " + item + " is listed twice in '" + selection + "'");
    ids.push_back(id);
  }
  if (ids.empty())
    throw InputError(
        "--surface: empty; give a surface id, a list like 0,3,5, or 'all' (valid ids: " + valid +
        ")");
  return ids;
}

namespace {

/// The surface with this id (the selection was validated against the scene).
const Surface& surfaceById(const Scene& scene, int id) {
  const auto it = std::find_if(scene.surfaces.begin(), scene.surfaces.end(),
                               [id](const Surface& s) { return s.id == id; });
  if (it == scene.surfaces.end())
    throw InputError("--surface: no surface with id " + std::to_string(id));
  return *it;
}

}  // namespace

namespace {

/// The grid of planningSpace (pipeline.h), inflated by `clearance_m`.
world::VoxelGrid planningGrid(const Scene& scene, const world::CollisionWorld& world,
                              const app::Config& config, const PointList& stop_positions,
                              double clearance_m) {
  Aabb region = boundingBox(stop_positions);
  region.min.array() -= kLocalMarginM;
  region.max.array() += kLocalMarginM;
  world::GridOptions grid_options = config.gridOptions(clearance_m);
  if (!config.setInFile(&config.grid.resolution_m))
    grid_options.resolution_m = autoGridResolution(region.max - region.min, grid_options);
  world::VoxelGrid::requireFits(region,
                                grid_options);  // before the solids are sampled at the resolution
  // The measured points (safetyPoints: the clean and the safety cloud) are read in
  // place; a site section's copy of them was the grid's peak of memory.
  std::vector<const PointList*> occupied{&scene.cloud};
  if (scene.safety) occupied.push_back(&scene.safety->points);
  // Solids matter as far as a point can block a voxel of the grid.
  const double reach_m =
      grid_options.padding_m + grid_options.inflation_radius_m + 3.0 * grid_options.resolution_m;
  Aabb reach = region;
  reach.min.array() -= reach_m;
  reach.max.array() += reach_m;
  const PointList solids = world.solidSamples(0.5 * grid_options.resolution_m, occupied, &reach);
  std::vector<PointList> keep_out_insides;  // the operator's volumes are solid inside too
  keep_out_insides.reserve(scene.keep_out.size());
  for (const auto& k : scene.keep_out) {
    keep_out_insides.push_back(
        world::interiorSamples(world::keepOutSolid(k), grid_options.resolution_m, &reach));
  }
  occupied.push_back(&solids);
  for (const auto& inside : keep_out_insides) occupied.push_back(&inside);
  return world::VoxelGrid::build(occupied, grid_options, region);
}

}  // namespace

PlanningSpace planningSpace(const Scene& scene,
                            const std::shared_ptr<const world::CollisionWorld>& world,
                            const app::Config& config, const PointList& positions) {
  const double clearance_m = safetyClearance(scene, config);
  world::VoxelGrid grid = planningGrid(scene, *world, config, positions, clearance_m);
  return {clearance_m, std::move(grid), planning::PathValidator(world, clearance_m)};
}

namespace {

/// Stage 7 for every surface. Surfaces are independent: with a deterministic
/// planner they are spread over the cores, one planner per worker (`planner` is the
/// caller's, for worker 0), each mission written to its own slot; OMPL's planners
/// plan them in order (one random stream).
std::vector<planning::SurfaceMission> planMissions(
    const std::vector<coverage::FlightStrategy>& strategies, const std::vector<int>& surface_ids,
    const world::VoxelGrid& grid, const planning::PathValidator& validator,
    planning::Planner& planner, const app::Config& config, const Progress& progress) {
  const planning::MissionOptions mission_options = config.missionOptions();
  const int threads = planners::isDeterministic(config.planner) ? hardwareThreads() : 1;
  if (threads > 1) {
    std::size_t stops = 0;
    for (const auto& s : strategies) stops += s.stops.size();
    reportProgress(progress, "stage 7: " + std::to_string(strategies.size()) + " surfaces, " +
                                 std::to_string(stops) + " stops, on " + std::to_string(threads) +
                                 " threads");
  }
  std::vector<std::unique_ptr<planning::Planner>> worker_planners(
      static_cast<std::size_t>(threads));
  std::vector<planning::SurfaceMission> missions(strategies.size());
  parallelFor(strategies.size(), threads, [&](std::size_t i, std::size_t worker) {
    auto& own = worker_planners[worker];
    if (worker > 0 && !own) own = planners::makePlanner(config.planner, config.planner_settings);
    planning::Planner& mine = worker == 0 ? planner : *own;
    if (threads == 1) {
      reportProgress(progress, "stage 7: surface " + std::to_string(surface_ids[i]) + " (" +
                                   std::to_string(i + 1) + "/" + std::to_string(strategies.size()) +
                                   "), " + std::to_string(strategies[i].stops.size()) + " stops");
    }
    missions[i] =
        planning::planSurfaceMission(strategies[i], grid, validator, mine, mission_options);
  });
  planners::releaseSearchScratch();  // the flight then searches on one thread: one scratch
  return missions;
}

/// Rounds of reconstruction's top-up (topUpSurface).
constexpr int kTopUpRounds = 3;
/// Most path the top-up may add per photo it adds, × the surface's path per photo
/// before it: points photographed too rarely in a tight corner (bridge_span's deck
/// above its pier) take stops that the obstacle repair sends to both sides of the
/// pier, 8 × the deck's path per photo each (single_cube's bottom face: 1.4 ×).
constexpr double kTopUpPathPerPhoto = 3.0;

/// Reconstruction (issue 46): where the planned flight images a surface's point, but
/// fewer than coverage.min_views times (the test of coverageOf), stops aimed at those
/// points (coverage::addStopsFor) and the surface planned again, up to kTopUpRounds
/// rounds while the count of such points falls; `m` is replaced only by a mission that
/// is flyable, leaves fewer of them and whose path grew by at most kTopUpPathPerPhoto
/// × the first's path per photo for each photo added. A point no photo images is a coverage gap
/// (obstacles, line of sight: the surface's coverage reports it), not topped up: on
/// bridge_span's deck that doubled the surface's path for 2 % of its points.
void topUpSurface(planning::SurfaceMission& m, const coverage::FlightStrategy& planned,
                  const Surface& surface, const coverage::LineOfSight& sight,
                  const PlanningSpace& space, planning::Planner& planner,
                  const app::Config& config) {
  if (!planning::flyable(m.status) || surface.inliers.empty()) return;
  const auto lowPoints = [&](const planning::SurfaceMission& mission) {
    const coverage::MultiViewStats st = coverage::multiViewStats(
        surface.inliers, {surface.plane.normal}, flownViews(mission), coverageCamera(config),
        coverageCriteria(), &sight, hardwareThreads());
    std::pair<PointList, std::vector<int>> low;
    for (std::size_t k = 0; k < st.views.size(); ++k) {
      if (st.views[k] > 0 && st.views[k] < config.coverage.min_views) {
        low.first.push_back(surface.inliers[k]);
        low.second.push_back(config.coverage.min_views - st.views[k]);
      }
    }
    return low;
  };
  coverage::FlightStrategy strategy = planned;
  auto low = lowPoints(m);
  const double photos = static_cast<double>(flownViews(m).size());
  const double path_per_photo_m = photos > 0.0 ? m.path_length_m / photos : 0.0;
  const double first_path_m = m.path_length_m;
  for (int round = 0; round < kTopUpRounds && !low.first.empty(); ++round) {
    if (coverage::addStopsFor(strategy, surface, low.first, low.second) == 0) return;
    planning::SurfaceMission next = planning::planSurfaceMission(
        strategy, space.grid, space.validator, planner, config.missionOptions());
    const double added = static_cast<double>(flownViews(next).size()) - photos;
    if (!planning::flyable(next.status) ||
        next.path_length_m - first_path_m > kTopUpPathPerPhoto * added * path_per_photo_m)
      return;
    auto still = lowPoints(next);
    if (still.first.size() >= low.first.size()) return;
    m = std::move(next);
    low = std::move(still);
  }
}

/// topUpSurface for each of `surface_ids` (the first missions; edge links follow them)
/// when coverage.purpose is reconstruction, a progress line each.
void topUpViews(std::vector<planning::SurfaceMission>& missions,
                const std::vector<coverage::FlightStrategy>& strategies, const Scene& scene,
                const std::vector<int>& surface_ids, const coverage::LineOfSight& sight,
                const PlanningSpace& space, planning::Planner& planner, const app::Config& config,
                const Progress& progress) {
  if (config.coverage.purpose != "reconstruction") return;
  for (std::size_t i = 0; i < surface_ids.size(); ++i) {
    reportProgress(progress, "stage 7: reconstruction top-up, surface " +
                                 std::to_string(surface_ids[i]) + " (" + std::to_string(i + 1) +
                                 "/" + std::to_string(surface_ids.size()) + ")");
    topUpSurface(missions[i], strategies[i], surfaceById(scene, surface_ids[i]), sight, space,
                 planner, config);
  }
}

}  // namespace

void requireWithinReach(const std::optional<Vec3>& point, const std::string& key,
                        const PointList& stops, const planning::FlightModel& model) {
  if (!point || stops.empty()) return;
  double nearest = std::numeric_limits<double>::infinity();
  for (const auto& s : stops) nearest = std::min(nearest, (s - *point).norm());
  const double reach = 0.5 * model.usableSeconds() * model.cruise_speed_m_s;
  if (nearest > reach) {
    std::ostringstream os;
    os << key << " " << formatPoint(*point) << " is " << formatFixed(nearest, 0)
       << " m from the nearest photo stop, beyond one battery's reach (" << formatFixed(reach, 0)
       << " m there and back at flight.cruise_speed_m_s in the usable flight.endurance_s); give it "
          "in the scene's frame, "
          "near the structure";
    throw InputError(os.str());
  }
}

void requireFree(const std::optional<Vec3>& point, const std::string& key,
                 const planning::PathValidator& validator) {
  if (!point) return;
  const double clearance = validator.clearance(*point);
  if (clearance < validator.requiredClearance()) {
    std::ostringstream os;
    os << key << " " << formatPoint(*point) << " lies " << formatFixed(clearance, 2)
       << " m from the structure, inside the " << formatFixed(validator.requiredClearance(), 2)
       << " m the UAV keeps from every measured point; move it into free space";
    throw InputError(os.str());
  }
}

planning::FlightPlan flyMissions(const std::vector<planning::SurfaceMission>& missions,
                                 const world::VoxelGrid& grid,
                                 const planning::PathValidator& validator,
                                 planning::Planner& planner, const app::Config& config) {
  return planning::planFlight(missions, grid, validator, planner, config.flightOptions());
}

void addFleetRegion(const app::Config& config, PointList& positions, std::size_t stops) {
  if (!config.fleet.active() || positions.empty()) return;
  if (static_cast<std::size_t>(config.fleet.uavs) > stops) {
    throw InputError("fleet: uavs " + std::to_string(config.fleet.uavs) + " is more than the " +
                     std::to_string(stops) + " photo stops to fly; use at most one UAV per stop");
  }
  Vec3 anchor = positions.front();
  for (const auto& p : positions)
    if (p.z() < anchor.z()) anchor = p;
  if (config.mission.start) anchor = *config.mission.start;
  if (config.flight.home) anchor = *config.flight.home;
  for (const auto& p : planning::fleetRegion(config.fleet, anchor)) positions.push_back(p);
}

std::optional<planning::FleetPlan> flyFleet(const std::vector<planning::SurfaceMission>& missions,
                                            const planning::FlightPlan& single,
                                            const world::VoxelGrid& grid,
                                            const planning::PathValidator& validator,
                                            planning::Planner& planner, const app::Config& config) {
  if (!config.fleet.active() || single.status != planning::FlightPlan::Status::Ok) return {};
  return planning::planFleet(missions, single, grid, validator, planner, config.flightOptions(),
                             config.fleet);
}

namespace {

/// A reconstruction in surfaces mode: a column of photos along every convex edge
/// between two chosen surfaces (coverage::planEdgeLinks), appended to `strategies`
/// with ids above every surface's (in `mission_ids`), so that the faces' photos join
/// into one model. An edge is found within the RANSAC distance plus a voxel.
void addEdgeLinks(const Scene& scene, const app::Config& config,
                  const std::vector<int>& surface_ids,
                  std::vector<coverage::FlightStrategy>& strategies,
                  std::vector<int>& mission_ids) {
  if (config.coverage.purpose != "reconstruction" || surface_ids.size() < 2) return;
  std::vector<const Surface*> chosen;
  chosen.reserve(surface_ids.size());
  for (const int id : surface_ids) chosen.push_back(&surfaceById(scene, id));
  int first_id = 0;
  for (const auto& s : scene.surfaces) first_id = std::max(first_id, s.id + 1);
  const double tolerance_m =
      config.perception.planes.distance_threshold_m + config.preprocess.voxel_m;
  for (auto& link : coverage::planEdgeLinks(coverage::convexEdges(chosen, tolerance_m),
                                            config.coverage, first_id)) {
    mission_ids.push_back(link.surface_id);
    strategies.push_back(std::move(link));
  }
}

/// Stage 6 of plan(): the chosen surfaces' photo stops, then the edge links; the
/// missions' ids (the surfaces', then the links') in `mission_ids`. Surfaces are
/// independent, each strategy written to its own slot, on every core.
std::vector<coverage::FlightStrategy> photoStops(const Scene& scene, const app::Config& config,
                                                 const std::vector<int>& surface_ids,
                                                 std::vector<int>& mission_ids) {
  std::vector<coverage::FlightStrategy> strategies(surface_ids.size());
  parallelFor(surface_ids.size(), hardwareThreads(), [&](std::size_t i, std::size_t) {
    strategies[i] =
        coverage::planFlightStrategy(surfaceById(scene, surface_ids[i]), config.coverage);
  });
  mission_ids = surface_ids;
  addEdgeLinks(scene, config, surface_ids, strategies, mission_ids);
  return strategies;
}

}  // namespace

PlanResult plan(const Scene& scene, const app::Config& config, const std::vector<int>& surface_ids,
                const Progress& progress) {
  PlanResult result;
  const auto t0 = SteadyClock::now();
  for (const int id : surface_ids) surfaceById(scene, id);  // a bad id fails before any work
  // The collision world needs the scene only: built on a second thread beside stage 6
  // (whose surfaces rarely keep both cores busy to the end).
  std::future<std::shared_ptr<const world::CollisionWorld>> world_build;
  if (!surface_ids.empty()) {
    world_build = std::async(std::launch::async, [&scene] {
      return std::make_shared<const world::CollisionWorld>(scene);
    });
  }

  // Stage 6 first: the grid must also cover every stop.
  std::vector<int> mission_ids;
  const std::vector<coverage::FlightStrategy> strategies =
      photoStops(scene, config, surface_ids, mission_ids);
  const std::size_t surfaces = surface_ids.size();
  PointList stop_positions;
  for (const auto& strategy : strategies)
    for (const auto& stop : strategy.stops) stop_positions.push_back(stop.position);
  requireWithinReach(config.mission.start, config.keyOf(&config.mission.start), stop_positions,
                     config.flight.model);
  requireWithinReach(config.flight.home, config.keyOf(&config.flight.home), stop_positions,
                     config.flight.model);
  addFleetRegion(config, stop_positions, stop_positions.size());
  if (config.mission.start) stop_positions.push_back(*config.mission.start);
  if (config.flight.home) stop_positions.push_back(*config.flight.home);
  result.times.coverage_s = secondsSince(t0);
  if (surface_ids.empty()) return result;

  const auto t1 = SteadyClock::now();
  reportProgress(progress, "stage 7: inflated voxel grid");
  const PlanningSpace space = planningSpace(scene, world_build.get(), config, stop_positions);
  result.clearance_m = space.clearance_m;
  const world::VoxelGrid& grid = space.grid;
  const planning::PathValidator& validator = space.validator;
  requireFree(config.mission.start, config.keyOf(&config.mission.start), validator);
  requireFree(config.flight.home, config.keyOf(&config.flight.home), validator);
  result.grid_resolution_m = grid.resolution();
  result.grid_voxels = grid.voxelCount();
  result.grid_blocked = grid.blockedCount();
  result.times.grid_s = secondsSince(t1);

  const auto t2 = SteadyClock::now();
  const auto planner = planners::makePlanner(config.planner, config.planner_settings);
  result.missions =
      planMissions(strategies, mission_ids, grid, validator, *planner, config, progress);
  for (std::size_t i = surfaces; i < result.missions.size(); ++i) result.missions[i].kind = "edge";
  const coverage::VoxelLineOfSight sight(scene.cloud, grid.resolution(), 3.5 * grid.resolution());
  topUpViews(result.missions, strategies, scene, surface_ids, sight, space, *planner, config,
             progress);
  // The flight and the coverage of the flown photos only read the missions (a
  // surface that coverage turns `partial` stays flyable): the flight runs on a second
  // thread meanwhile (its A* legs use one core), the coverage is written in after.
  // planning_s and flight_s overlap by the coverage's time.
  reportProgress(progress, "flight: order, connecting legs, sorties; coverage of the photos");
  WorkerGate flight_done;  // the coverage takes the second core when the flight ends
  auto flight = std::async(std::launch::async, [&] {
    const auto t3 = SteadyClock::now();
    planning::FlightPlan f = flyMissions(result.missions, grid, validator, *planner, config);
    flight_done.open();
    return std::make_pair(std::move(f), secondsSince(t3));
  });
  std::vector<std::optional<coverage::CoverageResult>> measured(surfaces);
  for (std::size_t i = 0; i < surfaces; ++i)
    measured[i] = coverageOf(result.missions[i], surfaceById(scene, surface_ids[i]), sight, config,
                             flight_done);
  result.times.planning_s = secondsSince(t2);
  auto [flown, flight_s] = flight.get();
  for (std::size_t i = 0; i < surfaces; ++i) {
    if (!measured[i]) continue;
    applyCoverage(result.missions[i], *measured[i], surfaceById(scene, surface_ids[i]), config);
    applyMultiView(result.missions[i], surfaceById(scene, surface_ids[i]), sight, config);
  }
  result.flight = std::move(flown);
  result.times.flight_s = flight_s;
  result.fleet = flyFleet(result.missions, result.flight, grid, validator, *planner, config);
  result.times.total_s = secondsSince(t0);
  return result;
}

io::SceneExtras sceneExtras(const DetectResult& detected, const io::CloudReadInfo* read) {
  io::SceneExtras e;
  e.parameters = detected.resolved.values;
  e.preprocess_s = detected.times.preprocess_s;
  e.perception_s = detected.times.perception_s;
  if (read != nullptr) {
    const io::CloudReadOptions& input = detected.resolved.config.input;
    e.input_read =
        io::InputReadRecord{input.scale,        input.drop_classes, read->origin_m, read->crs,
                            read->crs_vertical, read->crs_source,   read->mesh};
  }
  return e;
}

io::MissionExtras missionExtras(const PlanResult& planned, const app::Config& config,
                                const std::string& source) {
  io::MissionExtras e;
  e.uavip_version = UAVIP_VERSION;
  e.source = source;
  e.planner = config.planner;
  const auto& a = config.planner_settings.astar;
  e.cost_weights = Vec3(a.a1, a.a2, a.a3);
  e.inflation_radius_m = config.uav.inflationRadius();
  e.overlap_w = config.coverage.overlap_w;
  e.overlap_h = config.coverage.overlap_h;
  e.purpose = config.coverage.purpose;
  e.camera = config.coverage.camera;
  e.grid_voxels = planned.grid_voxels;
  e.grid_blocked = planned.grid_blocked;
  e.grid_resolution_m = planned.grid_resolution_m;
  e.safety_clearance_m = planned.clearance_m;
  e.coverage_s = planned.times.coverage_s;
  e.grid_s = planned.times.grid_s;
  e.planning_s = planned.times.planning_s;
  e.flight_s = planned.times.flight_s;
  e.structure = planned.structure;
  if (config.uav.model != "generic") {
    e.drone = config.uav.model;
    e.payload = config.uav.payload;
  }
  e.fleet = planned.fleet;
  return e;
}

}  // namespace uavip::app
