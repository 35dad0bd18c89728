// uavip tile | run-tile | merge: a kilometre-scale cloud in tiles, each tile's stages
// 3–5 in a process of its own (a Slurm array task), one validated mission from all
// (issue 34; tiling/tiles.h, tiling/merge.h, scripts/slurm/).

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
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
#include "uavip/io/json_numbers.h"
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
  const double standoff =
      coverage::solveCamera(c.coverage.camera, c.coverage.standoff_m).standoff_m;
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
    std::cout << "tiles: " << m.tiles.size() << " of " << m.columns << " x " << m.rows
              << " cells of " << formatNumber(m.tile_size_m) << " m, buffer "
              << formatNumber(m.buffer_m) << " m; " << m.input_points << " points, largest tile "
              << largest << " points (core + buffer)"
              << (io::streamsInBoundedMemory(cloud)
                      ? ""
                      : "; note: PCD and PLY are read whole, LAS and text are streamed")
              << "\n";
    std::cout << "time: " << formatFixed(secondsSince(t0), 2) << " s\n";
    std::cout << "results: " << pathIn(out, "manifest.json") << "\n";
  }
  return kExitOk;
}

/// The tile's cloud, checked against the manifest: present, with points, unchanged.
std::string tileCloudChecked(const tiling::Manifest& m, const tiling::TileRecord& t) {
  std::string path = pathIn(m.dir(), t.cloud);
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
    std::cout << "tile " << t.index << " (column " << t.column << ", row " << t.row
              << "): " << raw.size() << " points, " << d.scene.surfaces.size() << " surfaces, "
              << d.scene.obstacles.size() << " obstacles, " << formatFixed(secondsSince(t0), 2)
              << " s -> " << pathIn(out, "scene.json") << "\n";
  return kExitOk;
}

/// Throws InputError listing the tiles without a result (scene.json), so that none
/// of the merged output is written; the Slurm array indices to run again are named.
void requireTileResults(const tiling::Manifest& m) {
  std::string missing;
  for (const auto& t : m.tiles)
    if (!std::filesystem::exists(pathIn(pathIn(m.dir(), t.out), "scene.json")))
      missing += (missing.empty() ? "" : ",") + std::to_string(t.index);
  if (!missing.empty())
    throw InputError(m.path + ": no result for tile(s) " + missing + "; run them: uavip run-tile " +
                     m.path + " --index I (Slurm: scripts/slurm/submit.sh " + m.dir() +
                     " --array=" + missing + "), then merge again");
}

/// The scenes of the given tiles; InputError when one is from another tiling.
std::vector<tiling::TileScene> tileScenes(const tiling::Manifest& m,
                                          const std::vector<std::size_t>& which) {
  std::vector<tiling::TileScene> out;
  for (const std::size_t i : which) {
    const tiling::TileRecord& t = m.tiles[i];
    tiling::TileScene ts{t, io::loadScene(pathIn(pathIn(m.dir(), t.out), "scene.json"))};
    if (!ts.scene.safety || ts.scene.safety->sha256 != t.sha256)
      throw InputError(pathIn(m.dir(), t.out) +
                       "/scene.json: the result of another tiling for tile " +
                       std::to_string(t.index) + "; run it again: uavip run-tile " + m.path +
                       " --index " + std::to_string(t.index) + " (Slurm: scripts/slurm/submit.sh " +
                       m.dir() + " --array=" + std::to_string(t.index) + "), then merge again");
    out.push_back(std::move(ts));
  }
  return out;
}

/// Points of a section above which merge splits the site (about 1.3 GB of merge, see
/// benchmarks/README.md "Tiles"): a section is planned, staged and freed before the next.
constexpr std::uint64_t kSectionPoints = 2'000'000;

/// Sections of K × K tile cells, in row-major order of their blocks; each lists its
/// tiles (indices into manifest.tiles). K = `tiles` when > 0, else the largest K whose
/// every block holds at most kSectionPoints (core + buffer), at least 1.
std::vector<std::vector<std::size_t>> sections(const tiling::Manifest& m, int tiles) {
  const auto blocks = [&](int k) {
    std::map<std::pair<int, int>, std::vector<std::size_t>> by_block;
    for (std::size_t i = 0; i < m.tiles.size(); ++i)
      by_block[{m.tiles[i].row / k, m.tiles[i].column / k}].push_back(i);
    std::vector<std::vector<std::size_t>> out;
    out.reserve(by_block.size());
    for (auto& [key, list] : by_block) out.push_back(std::move(list));
    return out;
  };
  if (tiles > 0) return blocks(tiles);
  int best = 1;
  for (int k = 2; k <= std::max(m.columns, m.rows); ++k) {
    bool fits = true;
    for (const auto& b : blocks(k)) {
      std::uint64_t points = 0;
      for (const std::size_t i : b) points += m.tiles[i].core_points + m.tiles[i].buffer_points;
      fits = fits && points <= kSectionPoints;
    }
    if (!fits) break;
    best = k;
  }
  return blocks(best);
}

/// The flight measured against every input point, streamed once: the smallest
/// distance per sortie of every flight [m].
struct StreamedCheck {
  std::vector<std::vector<double>> min_clearance_m;  ///< per flight, per sortie
  std::uint64_t points{0};
};

StreamedCheck checkAgainstInput(const tiling::Manifest& m,
                                const std::vector<planning::FlightPlan>& flights,
                                double clearance) {
  StreamedCheck c;
  for (const auto& f : flights)
    c.min_clearance_m.emplace_back(f.sorties.size(), std::numeric_limits<double>::infinity());
  const io::CloudStreamInfo info =
      io::streamCloud(m.input, m.read, kStreamChunk, [&](const PointList& points) {
        const planning::PathValidator validator(points, clearance);
        for (std::size_t f = 0; f < flights.size(); ++f)
          for (std::size_t s = 0; s < flights[f].sorties.size(); ++s) {
            const planning::ValidationResult r =
                validator.validate(flights[f].sorties[s].waypoints);
            c.min_clearance_m[f][s] = std::min(c.min_clearance_m[f][s], r.min_clearance_m);
          }
      });
  if ((info.read.origin_m - m.source_offset_m).norm() > 1e-6)
    throw InputError(m.input + ": read in another frame than when it was tiled; tile it again");
  c.points = info.points;
  return c;
}

/// What one section's merge and plan gave (its scene and plan are staged and freed).
struct SectionResult {
  std::string out;  ///< its folder
  std::vector<int> tiles;
  tiling::MergeStats stats;
  std::size_t surfaces{0}, obstacles{0}, stops{0};
  planning::FlightPlan flight;  ///< kept for the streamed validation
  bool flyable{false};
  double merge_s{0.0}, plan_s{0.0};
};

/// Merges, plans and stages one section (the whole site when it is the only one).
SectionResult mergeSection(const tiling::Manifest& m, const std::vector<std::size_t>& which,
                           bool alone, const app::Config& config, const std::string& out,
                           bool views, io::StagedOutputs& outputs, const Verbosity& v) {
  SectionResult r;
  r.out = out;
  const auto t0 = SteadyClock::now();
  const std::vector<tiling::TileScene> tiles = tileScenes(m, which);
  for (const auto& t : tiles) r.tiles.push_back(t.tile.index);
  // The join follows the detector's thresholds, resolved as the largest tile had them.
  const auto largest = std::max_element(
      tiles.begin(), tiles.end(),
      [](const auto& a, const auto& b) { return a.scene.cloud.size() < b.scene.cloud.size(); });
  const tiling::MergeOptions mo =
      app::resolveForScene(largest->scene, config).config.mergeOptions(!alone);
  app::DetectResult d;
  d.scene = tiling::mergeTileScenes(m, tiles, mo, &r.stats);
  d.resolved = app::resolveForScene(d.scene, config);
  r.merge_s = secondsSince(t0);

  const auto t1 = SteadyClock::now();
  const app::Config& resolved = d.resolved.config;
  std::vector<int> ids;
  for (const auto& s : d.scene.surfaces) ids.push_back(s.id);
  const app::PlanResult p = app::plan(d.scene, resolved, ids, progressPrinter(v));
  r.plan_s = secondsSince(t1);
  r.surfaces = d.scene.surfaces.size();
  r.obstacles = d.scene.obstacles.size();
  for (const auto& mission : p.missions) r.stops += mission.strategy.stops.size();
  r.flyable = p.flight.status == planning::FlightPlan::Status::Ok && !p.flight.sorties.empty();

  io::ensureDirectory(out);
  io::CloudReadInfo read;
  read.origin_m = m.source_offset_m;
  writeScene(outputs, out, d, &read);
  writeMission(outputs, out, p, resolved, m.path);
  if (views) {
    view::OverviewOptions o;
    o.title = alone ? "merged tiles: uavip mission overview"
                    : std::filesystem::path(out).filename().string() + ": uavip mission overview";
    o.clearance_m = resolved.uav.inflationRadius();
    view::stageViews(outputs, out, view::renderViews(d.scene, p.missions, o, &p.flight));
  }
  r.flight = p.flight;
  return r;
}

/// OUT/site.json: the sections, each with its folder, tiles and flight (sections > 1).
std::string siteJsonText(const tiling::Manifest& m, const std::vector<SectionResult>& sections,
                         const StreamedCheck& check, double clearance) {
  nlohmann::json list = nlohmann::json::array();
  for (std::size_t i = 0; i < sections.size(); ++i) {
    const SectionResult& s = sections[i];
    double min_clear = std::numeric_limits<double>::infinity();
    for (const double c : check.min_clearance_m[i]) min_clear = std::min(min_clear, c);
    list.push_back(
        {{"folder", std::filesystem::path(s.out).filename().string()},
         {"tiles", s.tiles},
         {"surfaces", s.surfaces},
         {"photo_stops", s.stops},
         {"flight_status", planning::toString(s.flight.status)},
         {"home", io::vec(s.flight.home)},
         {"length_m", io::round4(s.flight.length_m)},
         {"sorties", s.flight.sorties.size()},
         {"min_clearance_to_input_m",
          std::isfinite(min_clear) ? nlohmann::json(io::round4(min_clear)) : nlohmann::json()}});
  }
  const nlohmann::json j = {
      {"format", "uavip site 1"}, {"manifest", m.path},
      {"input", m.input},         {"input_points", check.points},
      {"clearance_m", clearance}, {"source_offset_m", io::vec(m.source_offset_m)},
      {"sections", list}};
  return j.dump(1) + "\n";
}

/// Validates every sortie of every section against every input point (streamed once);
/// InputError naming the sortie when one comes closer than `radius`, so that nothing
/// is written. Returns the check and the smallest clearance [m].
StreamedCheck validateSections(const tiling::Manifest& m, const std::vector<SectionResult>& results,
                               bool alone, double radius, double& min_clear) {
  std::vector<planning::FlightPlan> flights;
  flights.reserve(results.size());
  for (const auto& r : results) flights.push_back(r.flight);
  StreamedCheck check = checkAgainstInput(m, flights, radius);
  min_clear = std::numeric_limits<double>::infinity();
  for (std::size_t f = 0; f < flights.size(); ++f)
    for (std::size_t s = 0; s < check.min_clearance_m[f].size(); ++s) {
      const double c = check.min_clearance_m[f][s];
      min_clear = std::min(min_clear, c);
      if (c < radius)
        throw InputError((alone ? std::string() : results[f].out + ": ") + "sortie " +
                         std::to_string(s + 1) + " comes " + formatFixed(c, 3) +
                         " m from an input point of " + m.input + " (required " +
                         formatFixed(radius, 3) + " m); nothing written");
    }
  return check;
}

void printMergeSummary(const tiling::Manifest& m, const std::vector<SectionResult>& results,
                       const StreamedCheck& check, double min_clear, double radius, double check_s,
                       const std::string& out, bool views) {
  const bool alone = results.size() == 1;
  double merge_s = 0.0, plan_s = 0.0, length = 0.0;
  std::size_t stops = 0, sorties = 0, surfaces = 0;
  tiling::MergeStats ms;
  for (const auto& r : results) {
    merge_s += r.merge_s;
    plan_s += r.plan_s;
    length += r.flight.length_m;
    stops += r.stops;
    sorties += r.flight.sorties.size();
    surfaces += r.surfaces;
    ms.surface_parts += r.stats.surface_parts;
    ms.surfaces_joined += r.stats.surfaces_joined;
    ms.surfaces_dropped += r.stats.surfaces_dropped;
    ms.surfaces_demoted += r.stats.surfaces_demoted;
    ms.obstacle_parts += r.stats.obstacle_parts;
    ms.obstacles_joined += r.stats.obstacles_joined;
  }
  std::cout << "merged " << m.tiles.size() << " tiles"
            << (alone ? std::string() : " in " + std::to_string(results.size()) + " sections")
            << ": " << surfaces << " surfaces (" << ms.surface_parts << " parts, "
            << ms.surfaces_joined << " joined across borders, " << ms.surfaces_dropped
            << " owned by another tile, " << ms.surfaces_demoted << " too small once cut); "
            << ms.obstacle_parts << " obstacle parts, " << ms.obstacles_joined << " joined\n";
  std::cout << (alone ? "flight: " + std::string(planning::toString(results[0].flight.status))
                      : std::to_string(results.size()) + " flights (one per section)")
            << ", " << formatFixed(length, 1) << " m, " << sorties << " sorties, " << stops
            << " photo stops; against all " << check.points
            << " input points (streamed): min clearance "
            << (std::isfinite(min_clear) ? formatFixed(min_clear, 3) + " m" : std::string("-"))
            << " (required " << formatFixed(radius, 3) << " m)\n";
  std::cout << "time: merge " << formatFixed(merge_s, 2) << " s, plan " << formatFixed(plan_s, 2)
            << " s, validation " << formatFixed(check_s, 2) << " s\n";
  std::cout << "results: "
            << (alone ? pathIn(out, "mission.json") + ", " + pathIn(out, "scene.json") +
                            (views ? ", " + pathIn(out, "mission.html") : std::string())
                      : pathIn(out, "site.json") + ", " + pathIn(out, "section_NNN") +
                            "/{mission,scene}.json")
            << "\n";
}

int mergeCommand(const std::string& manifest_path, const std::string& config_path,
                 const std::string& out, int section_tiles, bool views, const Verbosity& v) {
  const tiling::Manifest m = tiling::loadManifest(manifest_path);
  if (section_tiles < 0)
    throw InputError("--section-tiles must be >= 1 (0: chosen from the tile sizes), got " +
                     std::to_string(section_tiles));
  if (!std::filesystem::exists(m.input))
    throw InputError(m.path + ": the input " + m.input +
                     " is no longer there; the merged flight is validated against every input "
                     "point: put it back or tile again");
  if (io::sha256File(m.input) != m.input_sha256)
    throw InputError(m.path + ": the input " + m.input +
                     " changed since it was tiled (sha256 differs); tile it again (uavip tile)");
  requireTileResults(m);
  const app::Config config = tileConfig(config_path.empty() ? m.config : config_path);
  const auto parts = sections(m, section_tiles);
  const bool alone = parts.size() == 1;
  io::StagedOutputs outputs;  // temporaries on disk: a section's scene is freed once staged
  std::vector<SectionResult> results;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "section_%03zu", i);
    results.push_back(mergeSection(m, parts[i], alone, config, alone ? out : pathIn(out, name),
                                   views, outputs, v));
    if (!alone && v.showProgress())
      std::cerr << "uavip: section " << i + 1 << " of " << parts.size() << " planned\n";
  }
  const auto t2 = SteadyClock::now();
  const double radius = config.uav.inflationRadius();
  double min_clear = 0.0;
  const StreamedCheck check = validateSections(m, results, alone, radius, min_clear);
  const double check_s = secondsSince(t2);
  if (!alone) outputs.write(pathIn(out, "site.json"), siteJsonText(m, results, check, radius));
  outputs.commit();
  if (!v.quiet) printMergeSummary(m, results, check, min_clear, radius, check_s, out, views);

  std::size_t flying = 0, with_surfaces = 0;
  for (const auto& r : results) {
    flying += r.flyable;
    with_surfaces += r.surfaces > 0;
  }
  if (with_surfaces > 0 && flying == 0) {
    std::cerr << "uavip: no collision-free flight: " << results[0].flight.reason << "\n";
    return kExitNoMission;
  }
  return kExitOk;
}

/// Options of tile, run-tile and merge, kept alive until dispatch.
struct TileArgs {
  std::string cloud, manifest, config, out;
  double tile_size{0.0}, buffer{0.0};
  long index{-1};
  int section_tiles{0};
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
  registry.add(run,
               [a, &v] { return runTileCommand(a->manifest, a->index, a->config, a->views, v); });

  auto* merge = cli.add_subcommand(
      "merge", "Join the tiles' scenes, plan one flight, validate it against every input point");
  merge->add_option("manifest", a->manifest, "TILES/manifest.json written by uavip tile")
      ->required();
  merge->add_option("-c,--config", a->config, "Config YAML (default: the one given to uavip tile)");
  merge->add_option("-o,--out", a->out, "Output folder")->required();
  merge->add_option("--section-tiles", a->section_tiles,
                    "Plan the site in sections of K x K tiles, one flight each (0: one flight "
                    "when the site holds at most 2 M points, else sections that do)");
  merge->add_flag("--no-views", a->no_views,
                  "Skip overview.png, scene.ply, path.obj, mission.html");
  registry.add(merge, [a, &v] {
    return mergeCommand(a->manifest, a->config, a->out, a->section_tiles, !a->no_views, v);
  });
}

}  // namespace uavip::cli
