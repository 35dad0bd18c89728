// uavip tile | run-tile | merge: a kilometre-scale cloud in tiles, each tile's stages
// 3–5 in a process of its own (a Slurm array task), one validated mission from all
// (issue 34; tiling/tiles.h, tiling/merge.h, scripts/slurm/).

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>
#include <sstream>

#include "src/cli/commands.h"
#include "uavip/app/pipeline.h"
#include "uavip/app/scenario.h"
#include "uavip/core/error.h"
#include "uavip/core/stopwatch.h"
#include "uavip/core/text.h"
#include "uavip/coverage/camera.h"
#include "uavip/io/atomic_file.h"
#include "uavip/io/cloud_io.h"
#include "uavip/io/file_digest.h"
#include "uavip/io/scene_json.h"
#include "uavip/planning/path_validator.h"
#include "uavip/tiling/merge.h"
#include "uavip/tiling/tiles.h"
#include "uavip/view/views.h"

namespace uavip::cli {
namespace {

/// Points per chunk when the input is streamed (validation, tiling).
constexpr std::size_t kStreamChunk = std::size_t{1} << 21;

std::string pathIn(const std::string& dir, const std::string& name) {
  return (std::filesystem::path(dir) / name).string();
}

app::Config tileConfig(const std::string& path) {
  return path.empty() ? app::parseConfig("", "(defaults)") : app::loadConfig(path);
}

/// The least overlap buffer [m]: a photo stop of a surface at a tile border lies the
/// standoff out, and the UAV keeps its inflation radius from every point there.
double leastBuffer(const app::Config& c) {
  const double standoff = coverage::solveCamera(c.coverage.camera, c.coverage.standoff_m).standoff_m;
  return standoff * c.mission.max_standoff_factor + c.uav.inflationRadius();
}

int tileCommand(const std::string& cloud, double tile_size, double buffer, bool buffer_given,
                const std::string& config_path, const std::string& out, const Verbosity& v) {
  const app::Config config = tileConfig(config_path);
  tiling::TileOptions options;
  options.tile_size_m = tile_size;
  const double least = leastBuffer(config);
  // Default: twice the least, at least 10 m, so that a surface part reaching that far
  // past the border is still seen whole by the tile that owns most of it.
  options.buffer_m = buffer_given ? buffer : std::max(10.0, 2.0 * least);
  options.validate("uavip tile");
  if (options.buffer_m < least)
    throw InputError("--buffer " + formatNumber(options.buffer_m) +
                     " m is smaller than the standoff times mission.max_standoff_factor plus the "
                     "inflation radius (" +
                     formatNumber(least, 3) + " m" +
                     (config_path.empty() ? "" : ", from " + config_path) +
                     "): a tile would not see what its border stops fly past; give --buffer >= " +
                     formatNumber(std::ceil(least)) + " or leave it out");
  io::requireRegularFile(cloud);
  const auto t0 = SteadyClock::now();
  io::StagedOutputs outputs;
  tiling::Manifest m = tiling::tileCloud(cloud, config.input, options, out, outputs);
  m.input_sha256 = io::sha256File(cloud);
  m.config = config_path.empty()
                 ? std::string()
                 : std::filesystem::absolute(config_path).lexically_normal().string();
  outputs.write(pathIn(out, "manifest.json"), tiling::manifestJsonText(m));
  outputs.commit();
  if (!v.quiet) {
    std::uint64_t largest = 0;
    for (const auto& t : m.tiles) largest = std::max(largest, t.core_points + t.buffer_points);
    std::cout << "tiles: " << m.tiles.size() << " of " << m.columns << " x " << m.rows << " cells of "
              << formatNumber(m.tile_size_m) << " m, buffer " << formatNumber(m.buffer_m)
              << " m; " << m.input_points << " points, largest tile " << largest
              << " points (core + buffer)" << (io::streamsInBoundedMemory(cloud) ? "" : "; note: PCD and PLY are read whole, LAS and text are streamed")
              << "\n";
    std::cout << "time: " << formatFixed(secondsSince(t0), 2) << " s\n";
    std::cout << "results: " << pathIn(out, "manifest.json") << "\n";
  }
  return kExitOk;
}

/// The tile's cloud, checked against the manifest: present, with points, unchanged.
std::string tileCloudChecked(const tiling::Manifest& m, const tiling::TileRecord& t) {
  const std::string path = pathIn(m.dir(), t.cloud);
  if (t.core_points == 0)
    throw InputError(m.path + ": tile " + std::to_string(t.index) +
                     " has no points of its own; tile the cloud again (uavip tile)");
  if (!std::filesystem::exists(path))
    throw InputError(path + ": the cloud of tile " + std::to_string(t.index) +
                     " is missing; tile the cloud again (uavip tile)");
  if (io::sha256File(path) != t.sha256)
    throw InputError(path + ": tile " + std::to_string(t.index) +
                     " differs from the one manifest.json records (sha256); tile the cloud again");
  return path;
}

int runTileCommand(const std::string& manifest_path, long index, const std::string& config_path,
                   bool views, const Verbosity& v) {
  const tiling::Manifest m = tiling::loadManifest(manifest_path);
  const tiling::TileRecord& t = m.tile(index);
  const std::string cloud = tileCloudChecked(m, t);
  const app::Config config = tileConfig(config_path.empty() ? m.config : config_path);
  const auto t0 = SteadyClock::now();
  io::CloudReadInfo read;
  const PointList raw = io::loadCloud(cloud, io::CloudReadOptions{}, &read);
  if (read.origin_m != Vec3::Zero())
    throw InputError(cloud + ": tile " + std::to_string(t.index) +
                     " lies beyond 10 km of the site's centre; tile a smaller site");
  app::CloudIndex index_tree;
  const preprocess::CloudStats measured = app::measure(raw, nullptr, &index_tree);
  app::DetectResult d = app::detect(raw, config, measured, progressPrinter(v), index_tree);
  d.scene.safety->source = std::filesystem::absolute(cloud).lexically_normal().string();
  d.scene.safety->sha256 = t.sha256;
  const std::string out = pathIn(m.dir(), t.out);
  io::ensureDirectory(out);
  io::StagedOutputs outputs;
  read.origin_m = m.source_offset_m;  // scene.json's source_offset_m: the input's
  writeScene(outputs, out, d, &read);
  if (views) {
    view::OverviewOptions o;
    o.title = "tile " + std::to_string(t.index) + ": uavip scene";
    view::stageViews(outputs, out, view::renderViews(d.scene, {}, o, nullptr));
  }
  outputs.commit();
  if (!v.quiet)
    std::cout << "tile " << t.index << " (column " << t.column << ", row " << t.row << "): "
              << raw.size() << " points, " << d.scene.surfaces.size() << " surfaces, "
              << d.scene.obstacles.size() << " obstacles, " << formatFixed(secondsSince(t0), 2)
              << " s -> " << pathIn(out, "scene.json") << "\n";
  return kExitOk;
}

/// Every tile's scene; InputError listing the tiles without a current result.
std::vector<tiling::TileScene> tileScenes(const tiling::Manifest& m) {
  std::vector<tiling::TileScene> out;
  std::string missing, stale;
  for (const auto& t : m.tiles) {
    const std::string scene = pathIn(pathIn(m.dir(), t.out), "scene.json");
    if (!std::filesystem::exists(scene)) {
      missing += (missing.empty() ? "" : ",") + std::to_string(t.index);
      continue;
    }
    tiling::TileScene ts{t, io::loadScene(scene)};
    if (!ts.scene.safety || ts.scene.safety->sha256 != t.sha256) {
      stale += (stale.empty() ? "" : ",") + std::to_string(t.index);
      continue;
    }
    out.push_back(std::move(ts));
  }
  if (!missing.empty() || !stale.empty())
    throw InputError(m.path + ": " +
                     (missing.empty() ? "" : "no result for tile(s) " + missing + " ") +
                     (stale.empty() ? "" : "a result of another tiling for tile(s) " + stale + " ") +
                     "; run them again: uavip run-tile " + m.path + " --index I (Slurm: sbatch --array=" +
                     missing + (missing.empty() || stale.empty() ? "" : ",") + stale +
                     " ...), then merge");
  return out;
}

/// The flight measured against every input point, streamed: the smallest distance
/// per sortie [m] and the first sortie closer than `clearance` (−1 if none).
struct StreamedCheck {
  std::vector<double> min_clearance_m;
  int violated{-1};
  std::uint64_t points{0};
};

StreamedCheck checkAgainstInput(const tiling::Manifest& m, const planning::FlightPlan& flight,
                                double clearance) {
  StreamedCheck c;
  c.min_clearance_m.assign(flight.sorties.size(), std::numeric_limits<double>::infinity());
  const io::CloudStreamInfo info =
      io::streamCloud(m.input, m.read, kStreamChunk, [&](const PointList& points) {
        const planning::PathValidator validator(points, clearance);
        for (std::size_t s = 0; s < flight.sorties.size(); ++s) {
          const planning::ValidationResult r = validator.validate(flight.sorties[s].waypoints);
          c.min_clearance_m[s] = std::min(c.min_clearance_m[s], r.min_clearance_m);
        }
      });
  if ((info.read.origin_m - m.source_offset_m).norm() > 1e-6)
    throw InputError(m.input + ": read in another frame than when it was tiled; tile it again");
  c.points = info.points;
  for (std::size_t s = 0; s < c.min_clearance_m.size(); ++s)
    if (c.min_clearance_m[s] < clearance && c.violated < 0) c.violated = static_cast<int>(s);
  return c;
}

int mergeCommand(const std::string& manifest_path, const std::string& config_path,
                 const std::string& out, bool views, const Verbosity& v) {
  const tiling::Manifest m = tiling::loadManifest(manifest_path);
  if (!std::filesystem::exists(m.input))
    throw InputError(m.path + ": the input " + m.input +
                     " is no longer there; the merged flight is validated against every input "
                     "point: put it back or tile again");
  if (io::sha256File(m.input) != m.input_sha256)
    throw InputError(m.path + ": the input " + m.input +
                     " changed since it was tiled (sha256 differs); tile it again (uavip tile)");
  const app::Config config = tileConfig(config_path.empty() ? m.config : config_path);
  const auto t0 = SteadyClock::now();
  const std::vector<tiling::TileScene> tiles = tileScenes(m);
  // The join follows the detector's thresholds, resolved as the largest tile had them.
  const auto largest = std::max_element(tiles.begin(), tiles.end(), [](const auto& a, const auto& b) {
    return a.scene.cloud.size() < b.scene.cloud.size();
  });
  const perception::PlaneDetectionOptions& planes =
      app::resolveForScene(largest->scene, config).config.perception.planes;
  tiling::MergeOptions mo;
  mo.distance_threshold_m = planes.distance_threshold_m;
  mo.join_gap_m = planes.cluster_tolerance_m;
  mo.min_area_m2 = planes.min_area_m2;
  mo.area_cell_m = planes.cell_size_m;
  tiling::MergeStats ms;
  app::DetectResult d;
  d.scene = tiling::mergeTileScenes(m, tiles, mo, &ms);
  d.resolved = app::resolveForScene(d.scene, config);
  const double merge_s = secondsSince(t0);

  const auto t1 = SteadyClock::now();
  const app::Config& resolved = d.resolved.config;
  std::vector<int> ids;
  for (const auto& s : d.scene.surfaces) ids.push_back(s.id);
  const app::PlanResult p = app::plan(d.scene, resolved, ids, progressPrinter(v));
  const double plan_s = secondsSince(t1);

  const auto t2 = SteadyClock::now();
  const double radius = resolved.uav.inflationRadius();
  const StreamedCheck check = checkAgainstInput(m, p.flight, radius);
  const double check_s = secondsSince(t2);
  if (check.violated >= 0)
    throw InputError("sortie " + std::to_string(check.violated + 1) + " comes " +
                     formatFixed(check.min_clearance_m[static_cast<std::size_t>(check.violated)], 3) +
                     " m from an input point of " + m.input + " (required " +
                     formatFixed(radius, 3) + " m); nothing written");

  io::ensureDirectory(out);
  io::StagedOutputs outputs;
  io::CloudReadInfo read;
  read.origin_m = m.source_offset_m;
  writeScene(outputs, out, d, &read);
  writeMission(outputs, out, p, resolved, m.path);
  if (views) {
    view::OverviewOptions o;
    o.title = "merged tiles: uavip mission overview";
    o.clearance_m = radius;
    view::stageViews(outputs, out, view::renderViews(d.scene, p.missions, o, &p.flight));
  }
  outputs.commit();

  if (!v.quiet) {
    std::cout << "merged " << tiles.size() << " tiles: " << d.scene.surfaces.size() << " surfaces ("
              << ms.surface_parts << " parts, " << ms.surfaces_joined << " joined across borders, "
              << ms.surfaces_dropped << " owned by another tile, " << ms.surfaces_demoted
              << " too small once cut), " << d.scene.obstacles.size() << " obstacles ("
              << ms.obstacle_parts << " parts, " << ms.obstacles_joined << " joined), "
              << d.scene.cloud.size() << " clean points, " << ms.safety_points << " safety points\n";
    double min_clear = std::numeric_limits<double>::infinity();
    for (const double c : check.min_clearance_m) min_clear = std::min(min_clear, c);
    std::size_t stops = 0;
    for (const auto& mission : p.missions) stops += mission.strategy.stops.size();
    std::cout << "flight: " << planning::toString(p.flight.status) << ", "
              << formatFixed(p.flight.length_m, 1) << " m, " << p.flight.sorties.size()
              << " sorties, " << stops << " photo stops; against all " << check.points
              << " input points (streamed): min clearance "
              << (std::isfinite(min_clear) ? formatFixed(min_clear, 3) + " m" : std::string("-"))
              << " (required " << formatFixed(radius, 3) << " m)\n";
    std::cout << "time: merge " << formatFixed(merge_s, 2) << " s, plan " << formatFixed(plan_s, 2)
              << " s, validation " << formatFixed(check_s, 2) << " s\n";
    std::cout << "results: " << pathIn(out, "mission.json") << ", " << pathIn(out, "scene.json")
              << (views ? ", " + pathIn(out, "mission.html") : std::string()) << "\n";
  }
  if (p.missions.empty()) return kExitOk;
  const bool flight = p.flight.status == planning::FlightPlan::Status::Ok && !p.flight.sorties.empty();
  if (!flight) {
    std::cerr << "uavip: no collision-free flight: " << p.flight.reason << "\n";
    return kExitNoMission;
  }
  return kExitOk;
}

/// Options of tile, run-tile and merge, kept alive until dispatch.
struct TileArgs {
  std::string cloud, manifest, config, out;
  double tile_size{0.0}, buffer{0.0};
  long index{-1};
  CLI::Option* buffer_opt{nullptr};
  bool views{false}, no_views{false};
};

}  // namespace

void addTileCommands(CLI::App& cli, CommandRegistry& registry) {
  auto a = std::make_shared<TileArgs>();
  const Verbosity& v = registry.verbosity();
  auto* tile = cli.add_subcommand(
      "tile", "Stream a large cloud into square tiles with an overlap buffer + manifest.json");
  tile->add_option("cloud", a->cloud, "Cloud file (.las, .xyz/.txt/.csv streamed; .pcd, .ply)")
      ->required();
  tile->add_option("--tile-size", a->tile_size, "Edge of a tile's core [m]")->required();
  a->buffer_opt = tile->add_option(
      "--buffer", a->buffer,
      "Overlap around each core [m] (default: max(10, 2 x (standoff x max_standoff_factor + "
      "inflation radius)))");
  tile->add_option("-c,--config", a->config,
                   "Config YAML for every tile (input:, camera, uav; recorded in the manifest)");
  tile->add_option("-o,--out", a->out, "Output folder TILES/")->required();
  registry.add(tile, [a, &v] {
    return tileCommand(a->cloud, a->tile_size, a->buffer, a->buffer_opt->count() > 0, a->config,
                       a->out, v);
  });

  auto* run = cli.add_subcommand(
      "run-tile", "Stages 3-5 on one tile of a manifest -> TILES/tile_NNNN/scene.json");
  run->add_option("manifest", a->manifest, "TILES/manifest.json written by uavip tile")->required();
  run->add_option("--index", a->index, "Tile index (a Slurm array task: $SLURM_ARRAY_TASK_ID)")
      ->required();
  run->add_option("-c,--config", a->config, "Config YAML (default: the one given to uavip tile)");
  run->add_flag("--views", a->views, "Also write the tile's overview.png, scene.ply, mission.html");
  registry.add(run, [a, &v] {
    return runTileCommand(a->manifest, a->index, a->config, a->views, v);
  });

  auto* merge = cli.add_subcommand(
      "merge", "Join the tiles' scenes, plan one flight, validate it against every input point");
  merge->add_option("manifest", a->manifest, "TILES/manifest.json written by uavip tile")->required();
  merge->add_option("-c,--config", a->config, "Config YAML (default: the one given to uavip tile)");
  merge->add_option("-o,--out", a->out, "Output folder")->required();
  merge->add_flag("--no-views", a->no_views, "Skip overview.png, scene.ply, path.obj, mission.html");
  registry.add(merge, [a, &v] {
    return mergeCommand(a->manifest, a->config, a->out, !a->no_views, v);
  });
}

}  // namespace uavip::cli
