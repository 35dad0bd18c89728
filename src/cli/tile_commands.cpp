// uavip tile | run-tile | plan-section | merge: a kilometre-scale cloud in tiles, each
// tile's stages 3–5 in a process of its own (a Slurm array task), each section planned
// in one of its own (a second array), one validated mission from all.
// The work is app/site.h's; here the options are parsed, outputs staged and printed
// (tiling/tiles.h, tiling/merge.h, scripts/slurm/).

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>

#include "src/cli/commands.h"
#include "uavip/app/scenario.h"
#include "uavip/app/site.h"
#include "uavip/core/error.h"
#include "uavip/core/stopwatch.h"
#include "uavip/core/test_fault.h"
#include "uavip/core/text.h"
#include "uavip/io/atomic_file.h"
#include "uavip/io/cloud_io.h"
#include "uavip/io/file_digest.h"
#include "uavip/tiling/tiles.h"
#include "uavip/view/views.h"

namespace uavip::cli {
namespace {

std::string pathIn(const std::string& dir, const std::string& name) {
  return (std::filesystem::path(dir) / name).string();
}

app::Config tileConfig(const std::string& path) {
  return path.empty() ? app::parseConfig("", "(defaults)") : app::loadConfig(path);
}

int tileCommand(const std::string& cloud, double tile_size, std::optional<double> buffer,
                const std::string& config_path, const std::string& out, const Verbosity& v) {
  const app::Config config = tileConfig(config_path);
  const tiling::TileOptions options = app::siteTileOptions(config, tile_size, buffer, config_path);
  io::requireRegularFile(cloud);
  const auto t0 = SteadyClock::now();
  io::StagedOutputs outputs;
  tiling::Manifest m = tiling::tileCloud(cloud, config.input, options, out, outputs);
  m.input_sha256 = io::sha256File(cloud);
  if (!m.crs.empty()) {  // its vertical datum as detect finds it
    io::CloudReadInfo read;
    read.crs = m.crs;
    resolveCrs(read, cloud, "", "", v);
    m.crs_vertical = read.crs_vertical;
  }
  m.config = config_path.empty()
                 ? std::string()
                 : std::filesystem::absolute(config_path).lexically_normal().string();
  outputs.write(pathIn(out, "manifest.json"), tiling::manifestJsonText(m));
  outputs.commit();
  if (!v.quiet) {
    std::uint64_t largest = 0;
    for (const auto& t : m.tiles) largest = std::max(largest, t.core_points + t.buffer_points);
    std::cout
        << "tiles: " << m.tiles.size() << " of " << m.columns << " x " << m.rows << " cells of "
        << formatNumber(m.tile_size_m) << " m, buffer " << formatNumber(m.buffer_m) << " m; "
        << m.input_points << " points, largest tile " << largest << " points (core + buffer)"
        << (io::streamsInBoundedMemory(cloud)
                ? ""
                : "; note: compressed PCD, big-endian PLY and meshes are read whole; LAS, text, "
                  "other PCD and PLY are streamed")
        << "\n";
    std::cout << "time: " << formatFixed(secondsSince(t0), 2) << " s\n";
    std::cout << "results: " << pathIn(out, "manifest.json") << "\n";
  }
  return kExitOk;
}

int runTileCommand(const std::string& manifest_path, long index, const std::string& config_path,
                   bool views, const Verbosity& v) {
  core::setFaultTask("run-tile " + std::to_string(index));
  const tiling::Manifest m = tiling::loadManifest(manifest_path);
  const tiling::TileRecord& t = m.tile(index);
  const app::Config config = tileConfig(config_path.empty() ? m.config : config_path);
  const auto t0 = SteadyClock::now();
  const app::TileDetectResult r = app::detectTile(m, index, config, progressPrinter(v));
  io::ensureDirectory(r.out);
  io::StagedOutputs outputs;
  writeScene(outputs, r.out, r.detected, &r.read);
  if (views) {
    view::OverviewOptions o;
    o.title = "tile " + std::to_string(t.index) + ": uavip scene";
    view::stageViews(outputs, r.out, view::renderViews(r.detected.scene, {}, o, nullptr));
  }
  core::failIfArmed();
  outputs.commit();
  if (!v.quiet)
    std::cout << "tile " << t.index << " (column " << t.column << ", row " << t.row
              << "): " << r.points << " points, " << r.detected.scene.surfaces.size()
              << " surfaces, " << r.detected.scene.obstacles.size() << " obstacles, "
              << formatFixed(secondsSince(t0), 2) << " s -> " << pathIn(r.out, "scene.json")
              << "\n";
  return kExitOk;
}

/// Stages a planned section's scene.json, views and mission.json in its folder
/// (mission.json last: renamed last, it marks the folder complete).
void stageSection(io::StagedOutputs& outputs, const tiling::Manifest& m, const app::SectionPlan& s,
                  bool views) {
  io::ensureDirectory(s.out);
  io::CloudReadInfo read;
  read.origin_m = m.source_offset_m;
  read.crs = m.crs;  // the input's CRS (manifest.json), so export needs no --crs
  read.crs_source = m.crs_source;
  read.crs_vertical = m.crs_vertical;
  const app::Config& resolved = s.detected.resolved.config;
  writeScene(outputs, s.out, s.detected, &read);
  if (views) {
    view::OverviewOptions o;
    o.title = s.alone()
                  ? "merged tiles: uavip mission overview"
                  : std::filesystem::path(s.out).filename().string() + ": uavip mission overview";
    o.clearance_m = resolved.uav.inflationRadius();
    view::stageViews(outputs, s.out,
                     view::renderViews(s.detected.scene, s.planned.missions, o, &s.planned.flight,
                                       s.planned.fleet ? &*s.planned.fleet : nullptr));
  }
  writeMission(outputs, s.out, s.planned, resolved, m.path);
}

/// Stages copies of a plan-section result's files in the section's folder of the site.
void stageJoined(io::StagedOutputs& outputs, const app::SectionResult& r) {
  io::ensureDirectory(r.summary->out);
  for (const std::string& name : r.files) {
    const std::string from = pathIn(r.folder, name);
    outputs.writeWith(pathIn(r.summary->out, name), [&](const std::string& tmp) {
      std::error_code ec;
      std::filesystem::copy_file(from, tmp, std::filesystem::copy_options::overwrite_existing, ec);
      if (ec) throw InputError(from + ": cannot copy (" + ec.message() + "); merge again");
    });
  }
}

/// The file whose presence marks a merged site complete: site.json, or the only
/// section's mission.json.
std::string mergeMark(const std::string& out, std::size_t sections) {
  return pathIn(out, sections > 1 ? "site.json" : "mission.json");
}

/// `plan-section --list`: one line per section (its tiles and points) for scripts.
void listSections(const tiling::Manifest& m, int section_tiles) {
  const auto parts = app::siteSections(m, section_tiles);
  std::cout << "sections: " << parts.size() << "\n";
  for (std::size_t i = 0; i < parts.size(); ++i) {
    std::uint64_t points = 0;
    std::string tiles;
    for (const std::size_t t : parts[i]) {
      points += m.tiles[t].core_points + m.tiles[t].buffer_points;
      tiles += (tiles.empty() ? "" : ",") + std::to_string(t);
    }
    std::cout << "section " << i << ": tiles " << tiles << "; " << points << " points\n";
  }
}

int planSectionCommand(const std::string& manifest_path, long section,
                       const std::string& config_path, int section_tiles, bool views, bool if_stale,
                       bool list, int uavs, const Verbosity& v) {
  const tiling::Manifest m = tiling::loadManifest(manifest_path);
  app::SiteOptions options;
  options.section_tiles = section_tiles;
  options.validate();
  if (list) {
    listSections(m, section_tiles);
    return kExitOk;
  }
  if (section < 0)
    throw InputError(
        "plan-section: give --section S (a Slurm array task: $SLURM_ARRAY_TASK_ID), "
        "or --list for the sections");
  core::setFaultTask("plan-section " + std::to_string(section));
  const std::string used_config = config_path.empty() ? m.config : config_path;
  app::Config config = tileConfig(used_config);
  setUavs(config, uavs);
  const app::SectionKey key =
      app::sectionKey(m, used_config, section_tiles, views, config.fleet.uavs);
  const auto t0 = SteadyClock::now();
  const std::string folder = app::sectionResultFolder(m, static_cast<std::size_t>(section));
  if (if_stale) {
    const auto parts = app::siteSections(m, section_tiles);
    if (static_cast<std::size_t>(section) < parts.size() &&
        app::readSectionResult(m, key, parts, static_cast<std::size_t>(section), "").summary) {
      if (!v.quiet)
        std::cout << "section " << section << ": its result in " << folder
                  << " is up to date; nothing to do\n";
      return kExitOk;
    }
  }
  app::SectionPlan plan =
      app::planSection(m, config, static_cast<std::size_t>(section), options, progressPrinter(v));
  plan.out = folder;
  // Without its record the folder is no result: a task killed while it writes leaves none.
  std::error_code ec;
  std::filesystem::remove(pathIn(folder, app::kSectionResultFile), ec);
  io::StagedOutputs outputs;
  stageSection(outputs, m, plan, views);
  std::vector<std::pair<std::string, std::string>> files;
  for (const auto& [tmp, target] : outputs.staged())
    files.emplace_back(std::filesystem::path(target).filename().string(), io::sha256File(tmp));
  outputs.write(pathIn(folder, app::kSectionResultFile),
                app::sectionResultJsonText(m, key, plan, files));
  core::failIfArmed();
  outputs.commit();
  if (!v.quiet) {
    std::size_t stops = 0;
    for (const auto& mission : plan.planned.missions) stops += mission.strategy.stops.size();
    std::cout << "section " << section << " of " << plan.count << " (tiles " << plan.tiles.size()
              << "): " << plan.detected.scene.surfaces.size() << " surfaces, " << stops
              << " photo stops, flight " << planning::toString(plan.planned.flight.status) << ", "
              << plan.planned.flight.sorties.size() << " sorties, "
              << formatFixed(secondsSince(t0), 2) << " s -> "
              << pathIn(folder, app::kSectionResultFile) << "\n";
    printFleet(plan.planned.fleet);
    if (config.fleet.uavs > 1 && plan.count > 1)
      std::cout << "planned for one UAV: merge --uavs " << config.fleet.uavs
                << " shares the site's sorties among the UAVs (the sections flown at once)\n";
  }
  return kExitOk;
}

/// The site's fleet (sections at once): makespan against one UAV and the bound, the
/// separation, and each UAV's run of sections with its take-off.
void printSiteFleet(const app::SiteFleet& fleet, const std::vector<app::SectionSummary>& sections) {
  const planning::FleetPlan& f = fleet.plan;
  std::cout << "fleet: " << f.uavs.size() << " UAVs flying the sections at once ("
            << fleet.uavs_flying << " flying), " << fleetTimesText(f) << ", " << f.jobs
            << " sorties, " << f.waits << " waits"
            << (f.fallback_single ? "; UAV 1 flies alone" : "") << "; " << fleetSeparationText(f)
            << "\n";
  for (std::size_t u = 0; u < f.uavs.size(); ++u) {
    const auto& run = fleet.runs[u];
    std::cout << "  uav " << u + 1 << ": ";
    if (run.empty()) {
      std::cout << "idle\n";
      continue;
    }
    const auto name = [&](const app::SiteSortie& s) {
      return std::filesystem::path(sections[s.section].out).filename().string() + " sortie " +
             std::to_string(s.sortie + 1);
    };
    std::cout << run.size() << " sorties, " << name(run.front()) << " to " << name(run.back())
              << ", take-off at " << formatFixed(f.uavs[u].sortie_start_s.front(), 1)
              << " s, lands " << formatFixed(f.uavs[u].end_s, 1) << " s\n";
  }
}

void printMergeSummary(const tiling::Manifest& m, const app::SiteResult& site,
                       const std::string& out, bool views) {
  const auto& results = site.sections;
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
            << " photo stops; against all " << site.input_points
            << " input points (streamed): min clearance "
            << (std::isfinite(site.min_clearance_m) ? formatFixed(site.min_clearance_m, 3) + " m"
                                                    : std::string("-"))
            << " (required " << formatFixed(site.required_clearance_m, 3) << " m)\n";
  std::size_t joined = 0;
  for (const auto& r : results) joined += r.joined;
  std::cout << "time: merge " << formatFixed(merge_s, 2) << " s, plan " << formatFixed(plan_s, 2)
            << " s"
            << (joined > 0 ? " (" + std::to_string(joined) + " of " +
                                 std::to_string(results.size()) + " section(s) by plan-section)"
                           : std::string())
            << ", validation " << formatFixed(site.check_s, 2) << " s\n";
  if (alone && results[0].uavs > 1) {
    const auto& r = results[0];
    std::cout << "fleet: " << r.uavs << " UAVs flying the site, makespan "
              << formatFixed(r.makespan_s / 60.0, 1) << " min (single UAV "
              << formatFixed(r.single_uav_s / 60.0, 1) << " min, speed-up "
              << formatFixed(r.makespan_s > 0.0 ? r.single_uav_s / r.makespan_s : 0.0, 2) << ")\n";
  }
  if (site.fleet) printSiteFleet(*site.fleet, results);
  std::cout << "results: "
            << (alone ? pathIn(out, "mission.json") + ", " + pathIn(out, "scene.json") +
                            (views ? ", " + pathIn(out, "mission.html") : std::string())
                      : pathIn(out, "site.json") + ", " + pathIn(out, "section_NNN") +
                            "/{mission,scene}.json")
            << "\n";
}

int mergeCommand(const std::string& manifest_path, const std::string& config_path,
                 const std::string& out, int section_tiles, bool views, bool require_sections,
                 int uavs, const Verbosity& v) {
  core::setFaultTask("merge");
  const tiling::Manifest m = tiling::loadManifest(manifest_path);
  app::SiteOptions options;
  options.section_tiles = section_tiles;
  options.out = out;
  options.validate();
  const std::string used_config = config_path.empty() ? m.config : config_path;
  app::Config config = tileConfig(used_config);
  setUavs(config, uavs);
  const app::SectionKey key =
      app::sectionKey(m, used_config, section_tiles, views, config.fleet.uavs);
  options.results = &key;
  options.require_results = require_sections;
  io::StagedOutputs outputs;  // temporaries on disk: a section's scene is freed once staged
  const app::SiteResult site = app::planSite(
      m, config, options, [&](const app::SectionPlan& s) { stageSection(outputs, m, s, views); },
      progressPrinter(v), [&](const app::SectionResult& r) { stageJoined(outputs, r); });
  for (const std::string& note : site.notes) std::cerr << "uavip: note: " << note << "\n";
  if (site.sections.size() > 1) outputs.write(pathIn(out, "site.json"), app::siteJsonText(m, site));
  core::failIfArmed();
  // The mark of a complete site goes first and comes back last: a merge killed while it
  // renames leaves no site.json (no mission.json of a single section), never a mix
  // taken as done.
  std::error_code ec;
  std::filesystem::remove(mergeMark(out, site.sections.size()), ec);
  outputs.commit();
  if (!v.quiet) printMergeSummary(m, site, out, views);
  if (!site.flyable()) {
    std::cerr << "uavip: no collision-free flight: " << site.sections[0].flight.reason << "\n";
    return kExitNoMission;
  }
  return kExitOk;
}

/// Options of tile, run-tile and merge, kept alive until dispatch.
struct TileArgs {
  std::string cloud, manifest, config, out;
  double tile_size{0.0}, buffer{0.0};
  long index{-1}, section{-1};
  int section_tiles{0};
  int uavs{-1};  ///< --uavs; −1 when not given
  CLI::Option* buffer_opt{nullptr};
  bool views{false}, no_views{false}, require_sections{false}, if_stale{false}, list{false};
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
    return tileCommand(a->cloud, a->tile_size,
                       a->buffer_opt->count() > 0 ? std::optional<double>(a->buffer) : std::nullopt,
                       a->config, a->out, v);
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
  merge->add_flag("--require-sections", a->require_sections,
                  "Join only results of plan-section (the Slurm merge): refuse, naming the "
                  "sections to plan, instead of planning a missing or stale one here");
  merge->add_option("--uavs", a->uavs,
                    "Fly the site with K UAVs at once (fleet.uavs): several sections are "
                    "flown at once, each UAV a run of their sorties (site.json `fleet`; check "
                    "it with `uavip validate site.json`); a site of one section shares its "
                    "stops as `plan --uavs K` does");
  registry.add(merge, [a, &v] {
    return mergeCommand(a->manifest, a->config, a->out, a->section_tiles, !a->no_views,
                        a->require_sections, a->uavs, v);
  });

  auto* section = cli.add_subcommand(
      "plan-section",
      "Merge and plan one section of a tiled site -> TILES/section_NNN/ (joined by merge)");
  section->add_option("manifest", a->manifest, "TILES/manifest.json written by uavip tile")
      ->required();
  section->add_option("--section", a->section,
                      "Section index from 0 (a Slurm array task: $SLURM_ARRAY_TASK_ID)");
  section->add_option("-c,--config", a->config,
                      "Config YAML (default: the one given to uavip tile); give merge the same");
  section->add_option("--section-tiles", a->section_tiles,
                      "Sections of K x K tiles, as merge's option (give merge the same)");
  section->add_flag("--no-views", a->no_views,
                    "Skip the views (give merge the same: a result is joined only as made)");
  section->add_flag("--if-stale", a->if_stale,
                    "Do nothing when the section's result is there and up to date");
  section->add_flag("--list", a->list, "Print the sections (tiles and points) and exit");
  section->add_option("--uavs", a->uavs,
                      "K UAVs, as merge's option (give merge the same); only a site of one "
                      "section plans a fleet here, several sections are planned for one UAV "
                      "and shared by the merge");
  registry.add(section, [a, &v] {
    return planSectionCommand(a->manifest, a->section, a->config, a->section_tiles, !a->no_views,
                              a->if_stale, a->list, a->uavs, v);
  });
}

}  // namespace uavip::cli
