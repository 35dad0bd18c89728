#include "uavip/app/site.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <utility>

#include "uavip/core/error.h"
#include "uavip/core/stopwatch.h"
#include "uavip/core/text.h"
#include "uavip/coverage/camera.h"
#include "uavip/io/file_digest.h"
#include "uavip/io/json_numbers.h"
#include "uavip/io/scene_json.h"
#include "uavip/planning/path_validator.h"

namespace uavip::app {
namespace {

/// Points per chunk when the input is streamed for the check against every point.
constexpr std::size_t kSiteStreamChunk = std::size_t{1} << 21;

std::string sitePath(const std::string& dir, const std::string& name) {
  return (std::filesystem::path(dir) / name).string();
}

/// The tile's cloud, checked against the manifest: present, with points, unchanged.
std::string tileCloudChecked(const tiling::Manifest& m, const tiling::TileRecord& t) {
  std::string path = sitePath(m.dir(), t.cloud);
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

/// Throws InputError listing the given tiles without a result (scene.json), so that
/// nothing of the merged output is written; the Slurm array indices to run again are
/// named.
void requireTileResults(const tiling::Manifest& m, const std::vector<std::size_t>& which) {
  std::string missing;
  for (const std::size_t i : which) {
    const tiling::TileRecord& t = m.tiles[i];
    if (!std::filesystem::exists(sitePath(sitePath(m.dir(), t.out), "scene.json")))
      missing += (missing.empty() ? "" : ",") + std::to_string(t.index);
  }
  if (!missing.empty())
    throw InputError(m.path + ": no result for tile(s) " + missing + "; run them: uavip run-tile " +
                     m.path + " --index I (Slurm: scripts/slurm/submit.sh " + m.dir() +
                     " --array=" + missing + "), then merge again");
}

/// The input named by the manifest is still there and unchanged (sha256).
void requireSiteInput(const tiling::Manifest& m) {
  if (!std::filesystem::exists(m.input))
    throw InputError(m.path + ": the input " + m.input +
                     " is no longer there; the merged flight is validated against every input "
                     "point: put it back or tile again");
  if (io::sha256File(m.input) != m.input_sha256)
    throw InputError(m.path + ": the input " + m.input +
                     " changed since it was tiled (sha256 differs); tile it again (uavip tile)");
}

/// The scenes of the given tiles; InputError when one is from another tiling.
std::vector<tiling::TileScene> tileScenes(const tiling::Manifest& m,
                                          const std::vector<std::size_t>& which) {
  std::vector<tiling::TileScene> out;
  for (const std::size_t i : which) {
    const tiling::TileRecord& t = m.tiles[i];
    tiling::TileScene ts{t, io::loadScene(sitePath(sitePath(m.dir(), t.out), "scene.json"))};
    if (!ts.scene.safety || ts.scene.safety->sha256 != t.sha256)
      throw InputError(sitePath(m.dir(), t.out) +
                       "/scene.json: the result of another tiling for tile " +
                       std::to_string(t.index) + "; run it again: uavip run-tile " + m.path +
                       " --index " + std::to_string(t.index) + " (Slurm: scripts/slurm/submit.sh " +
                       m.dir() + " --array=" + std::to_string(t.index) + "), then merge again");
    out.push_back(std::move(ts));
  }
  return out;
}

/// The join's thresholds: the detector's plane options of the largest tile.
tiling::MergeOptions sectionMergeOptions(const std::vector<tiling::TileScene>& tiles,
                                         const Config& config, bool alone) {
  // The join follows the detector's thresholds, resolved as the largest tile had them.
  const auto largest = std::max_element(
      tiles.begin(), tiles.end(),
      [](const auto& a, const auto& b) { return a.scene.cloud.size() < b.scene.cloud.size(); });
  return resolveForScene(largest->scene, config).config.mergeOptions(!alone);
}

/// Merges and plans one section of `parts` (the tiles' results checked).
SectionPlan planSectionOf(const tiling::Manifest& m,
                          const std::vector<std::vector<std::size_t>>& parts, std::size_t section,
                          const Config& config, const SiteOptions& options,
                          const Progress& progress) {
  SectionPlan r;
  r.index = section;
  r.count = parts.size();
  r.out = sectionFolder(options.out, section, parts.size());
  const auto t0 = SteadyClock::now();
  const std::vector<tiling::TileScene> tiles = tileScenes(m, parts[section]);
  for (const auto& t : tiles) r.tiles.push_back(t.tile.index);
  const tiling::MergeOptions mo = sectionMergeOptions(tiles, config, r.alone());
  r.detected.scene = tiling::mergeTileScenes(m, tiles, mo, &r.stats);
  r.detected.resolved = resolveForScene(r.detected.scene, config);
  r.merge_s = secondsSince(t0);

  const auto t1 = SteadyClock::now();
  std::vector<int> ids;
  for (const auto& s : r.detected.scene.surfaces) ids.push_back(s.id);
  r.planned = plan(r.detected.scene, r.detected.resolved.config, ids, progress);
  r.plan_s = secondsSince(t1);
  return r;
}

/// What stays of a planned section.
SectionSummary summaryOf(const SectionPlan& p) {
  SectionSummary s;
  s.out = p.out;
  s.tiles = p.tiles;
  s.stats = p.stats;
  s.surfaces = p.detected.scene.surfaces.size();
  s.obstacles = p.detected.scene.obstacles.size();
  for (const auto& mission : p.planned.missions) s.stops += mission.strategy.stops.size();
  s.flight = p.planned.flight;
  s.flyable = s.flight.status == planning::FlightPlan::Status::Ok && !s.flight.sorties.empty();
  s.merge_s = p.merge_s;
  s.plan_s = p.plan_s;
  return s;
}

/// Every sortie of every section measured against every input point, streamed once:
/// sets each section's min_clearance_to_input_m; returns the points read.
std::uint64_t checkAgainstInput(const tiling::Manifest& m, std::vector<SectionSummary>& sections,
                                double clearance) {
  for (auto& s : sections)
    s.min_clearance_to_input_m.assign(s.flight.sorties.size(),
                                      std::numeric_limits<double>::infinity());
  const io::CloudStreamInfo info =
      io::streamCloud(m.input, m.read, kSiteStreamChunk, [&](const PointList& points) {
        const planning::PathValidator validator(points, clearance);
        for (auto& section : sections)
          for (std::size_t s = 0; s < section.flight.sorties.size(); ++s) {
            const planning::ValidationResult r =
                validator.validate(section.flight.sorties[s].waypoints);
            section.min_clearance_to_input_m[s] =
                std::min(section.min_clearance_to_input_m[s], r.min_clearance_m);
          }
      });
  if ((info.read.origin_m - m.source_offset_m).norm() > 1e-6)
    throw InputError(m.input + ": read in another frame than when it was tiled; tile it again");
  return info.points;
}

/// The smallest clearance of every sortie [m]; InputError naming the sortie when one
/// comes closer than `radius`, so that nothing is written.
double requireClearOfInput(const tiling::Manifest& m, const std::vector<SectionSummary>& sections,
                           double radius) {
  const bool alone = sections.size() == 1;
  double min_clear = std::numeric_limits<double>::infinity();
  for (const auto& section : sections)
    for (std::size_t s = 0; s < section.min_clearance_to_input_m.size(); ++s) {
      const double c = section.min_clearance_to_input_m[s];
      min_clear = std::min(min_clear, c);
      if (c < radius)
        throw InputError((alone ? std::string() : section.out + ": ") + "sortie " +
                         std::to_string(s + 1) + " comes " + formatFixed(c, 3) +
                         " m from an input point of " + m.input + " (required " +
                         formatFixed(radius, 3) + " m); nothing written");
    }
  return min_clear;
}

}  // namespace

double leastTileBuffer(const Config& config) {
  const double standoff =
      coverage::solveCamera(config.coverage.camera, config.coverage.standoff_m).standoff_m;
  return standoff * config.mission.max_standoff_factor + config.uav.inflationRadius();
}

tiling::TileOptions siteTileOptions(const Config& config, double tile_size,
                                    std::optional<double> buffer, const std::string& config_path) {
  tiling::TileOptions options;
  options.tile_size_m = tile_size;
  const double least = leastTileBuffer(config);
  options.buffer_m = buffer ? *buffer : std::max(10.0, 2.0 * least);
  options.validate("uavip tile");
  if (options.buffer_m < least)
    throw InputError("--buffer " + formatNumber(options.buffer_m) +
                     " m is smaller than the standoff times mission.max_standoff_factor plus the "
                     "inflation radius (" +
                     formatNumber(least, 3) + " m" +
                     (config_path.empty() ? "" : ", from " + config_path) +
                     "): a tile would not see what its border stops fly past; give --buffer >= " +
                     formatNumber(std::ceil(least)) + " or leave it out");
  return options;
}

TileDetectResult detectTile(const tiling::Manifest& manifest, long index, const Config& config,
                            const Progress& progress) {
  const tiling::TileRecord& t = manifest.tile(index);
  TileDetectResult r;
  r.cloud = tileCloudChecked(manifest, t);
  const PointList raw = io::loadCloud(r.cloud, io::CloudReadOptions{}, &r.read);
  if (r.read.origin_m != Vec3::Zero())
    throw InputError(r.cloud + ": tile " + std::to_string(t.index) +
                     " lies beyond 10 km of the site's centre; tile a smaller site");
  r.points = raw.size();
  CloudIndex index_tree;
  const preprocess::CloudStats measured = measure(raw, nullptr, &index_tree);
  r.detected = detect(raw, config, measured, progress, index_tree);
  r.detected.scene.safety->source = std::filesystem::absolute(r.cloud).lexically_normal().string();
  r.detected.scene.safety->sha256 = t.sha256;
  r.out = sitePath(manifest.dir(), t.out);
  r.read.origin_m = manifest.source_offset_m;  // scene.json's source_offset_m: the input's
  r.read.crs = manifest.crs;                   // and its CRS, for export
  r.read.crs_source = manifest.crs_source;
  r.read.crs_vertical = manifest.crs_vertical;
  return r;
}

void SiteOptions::validate() const {
  if (section_tiles < 0)
    throw InputError("--section-tiles must be >= 1 (0: chosen from the tile sizes), got " +
                     std::to_string(section_tiles));
}

std::vector<std::vector<std::size_t>> siteSections(const tiling::Manifest& m, int section_tiles) {
  const auto blocks = [&](int k) {
    std::map<std::pair<int, int>, std::vector<std::size_t>> by_block;
    for (std::size_t i = 0; i < m.tiles.size(); ++i)
      by_block[{m.tiles[i].row / k, m.tiles[i].column / k}].push_back(i);
    std::vector<std::vector<std::size_t>> out;
    out.reserve(by_block.size());
    for (auto& [key, list] : by_block) out.push_back(std::move(list));
    return out;
  };
  if (section_tiles > 0) return blocks(section_tiles);
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

std::string sectionFolder(const std::string& out, std::size_t index, std::size_t count) {
  if (count == 1) return out;
  char name[32];
  std::snprintf(name, sizeof name, "section_%03zu", index);
  return sitePath(out, name);
}

SectionPlan planSection(const tiling::Manifest& manifest, const Config& config, std::size_t section,
                        const SiteOptions& options, const Progress& progress) {
  options.validate();
  const auto parts = siteSections(manifest, options.section_tiles);
  if (section >= parts.size())
    throw InputError(manifest.path + ": no section " + std::to_string(section) + "; the site has " +
                     std::to_string(parts.size()) + " section(s), numbered from 0");
  requireTileResults(manifest, parts[section]);
  return planSectionOf(manifest, parts, section, config, options, progress);
}

bool SiteResult::flyable() const {
  std::size_t flying = 0, with_surfaces = 0;
  for (const auto& s : sections) {
    flying += s.flyable;
    with_surfaces += s.surfaces > 0;
  }
  return with_surfaces == 0 || flying > 0;
}

SiteResult planSite(const tiling::Manifest& manifest, const Config& config,
                    const SiteOptions& options, const SectionSink& sink, const Progress& progress) {
  options.validate();
  requireSiteInput(manifest);
  std::vector<std::size_t> all(manifest.tiles.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
  requireTileResults(manifest, all);
  const auto parts = siteSections(manifest, options.section_tiles);
  SiteResult site;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const SectionPlan section = planSectionOf(manifest, parts, i, config, options, progress);
    if (sink) sink(section);
    site.sections.push_back(summaryOf(section));
    if (parts.size() > 1)
      reportProgress(progress, "section " + std::to_string(i + 1) + " of " +
                                   std::to_string(parts.size()) + " planned");
  }
  const auto t0 = SteadyClock::now();
  site.required_clearance_m = config.uav.inflationRadius();
  site.input_points = checkAgainstInput(manifest, site.sections, site.required_clearance_m);
  site.min_clearance_m = requireClearOfInput(manifest, site.sections, site.required_clearance_m);
  site.check_s = secondsSince(t0);
  return site;
}

std::string siteJsonText(const tiling::Manifest& manifest, const SiteResult& site) {
  nlohmann::json list = nlohmann::json::array();
  for (const SectionSummary& s : site.sections) {
    double min_clear = std::numeric_limits<double>::infinity();
    for (const double c : s.min_clearance_to_input_m) min_clear = std::min(min_clear, c);
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
  const nlohmann::json j = {{"format", "uavip site 1"},
                            {"manifest", manifest.path},
                            {"input", manifest.input},
                            {"input_points", site.input_points},
                            {"clearance_m", site.required_clearance_m},
                            {"source_offset_m", io::vec(manifest.source_offset_m)},
                            {"sections", list}};
  return j.dump(1) + "\n";
}

}  // namespace uavip::app
