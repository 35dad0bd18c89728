#pragma once
/// \file
/// A site too large for one process, as tiles (tiling/tiles.h): the tiling options, one
/// tile's stages 3–5, and the site plan: the tiles' scenes merged into sections
/// (tiling/merge.h), each section planned by app::plan (its own flight and home), and
/// every sortie of every section checked against every input point, streamed once.
/// `uavip tile`, `run-tile` and `merge` call these; nothing here prints or writes files
/// (the caller stages each section's outputs as it is handed over, then it is freed).

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "uavip/app/pipeline.h"
#include "uavip/app/scenario.h"
#include "uavip/io/cloud_io.h"
#include "uavip/planning/flight_planner.h"
#include "uavip/tiling/merge.h"
#include "uavip/tiling/tiles.h"

namespace uavip::app {

/// The least overlap buffer [m]: a photo stop of a surface at a tile border lies the
/// standoff out (standoff × mission.max_standoff_factor at most), and the UAV keeps its
/// inflation radius from every point there.
double leastTileBuffer(const Config& config);

/// The options of `uavip tile`: `tile_size` [m] and `buffer` [m] (none: the default,
/// max(10 m, twice leastTileBuffer), so that a surface part reaching that far past the
/// border is still seen whole by the tile that owns most of it). Throws InputError for a
/// bad value or a buffer below leastTileBuffer (`config_path`, if not empty, is named).
tiling::TileOptions siteTileOptions(const Config& config, double tile_size,
                                    std::optional<double> buffer, const std::string& config_path);

/// One tile's stages 3–5 (`uavip run-tile`, a Slurm array task).
struct TileDetectResult {
  DetectResult detected;   ///< its scene; the safety cloud names the tile's file and sha256
  io::CloudReadInfo read;  ///< how the tile was read, origin_m the site's source offset
  std::size_t points{0};   ///< of the tile's cloud (core + buffer)
  std::string cloud;       ///< the tile's cloud file
  std::string out;         ///< the folder of its results (beside the manifest)
};

/// Measures and detects tile `index` of `manifest` (app::measure, app::detect). Throws
/// InputError for an index beyond the manifest, a tile with no points of its own, a
/// missing tile file or one that differs from the manifest's sha256, and a tile beyond
/// 10 km of the site's centre.
TileDetectResult detectTile(const tiling::Manifest& manifest, long index, const Config& config,
                            const Progress& progress = {});

/// Points of a section above which the site is planned in sections (about 1.3 GB of
/// merge, see benchmarks/README.md "Tiles"): a section is planned, handed over and freed
/// before the next.
constexpr std::uint64_t kSectionPoints = 2'000'000;

/// Options of the site plan (`uavip merge`).
struct SiteOptions {
  /// Sections of K × K tile cells, one flight each; 0: the largest K whose every section
  /// holds at most kSectionPoints (core + buffer), at least 1.
  int section_tiles{0};
  /// The output folder: the only section's, or the parent of `section_NNN/` each
  /// (sectionFolder). Only named here, in messages and SectionPlan::out.
  std::string out;
  /// Throws InputError naming --section-tiles when negative.
  void validate() const;
};

/// The sections of the site: K × K tile cells each (SiteOptions::section_tiles), in
/// row-major order of their blocks; each lists its tiles as indices into manifest.tiles.
std::vector<std::vector<std::size_t>> siteSections(const tiling::Manifest& manifest,
                                                   int section_tiles);

/// The output folder of section `index` of `count`: `out` itself for a single section,
/// else `out/section_NNN` (NNN from 000).
std::string sectionFolder(const std::string& out, std::size_t index, std::size_t count);

/// One section merged and planned (the whole site when it is the only one).
struct SectionPlan {
  std::size_t index{0};    ///< among the site's sections
  std::size_t count{1};    ///< the site's sections
  std::string out;         ///< its output folder (sectionFolder)
  std::vector<int> tiles;  ///< the tiles it joins (manifest indices)
  tiling::MergeStats stats;
  DetectResult detected;  ///< the merged scene and the config resolved for it
  PlanResult planned;     ///< one flight over all its surfaces
  double merge_s{0.0};    ///< reading and joining the tiles' scenes [s]
  double plan_s{0.0};     ///< app::plan [s]
  bool alone() const { return count == 1; }
};

/// Merges and plans section `section` of siteSections(manifest, options.section_tiles):
/// the tiles' scenes joined by tiling::mergeTileScenes with the detector's thresholds
/// resolved as the largest tile had them (a section of several also keeps the safety
/// points its tiles' buffers saw past its border), then app::plan over every surface.
/// Throws InputError when one of its tiles has no result or the result of another
/// tiling, or for a section index beyond the site's.
SectionPlan planSection(const tiling::Manifest& manifest, const Config& config, std::size_t section,
                        const SiteOptions& options, const Progress& progress = {});

/// What stays of a section once it was handed over (its scene and plan freed).
struct SectionSummary {
  std::string out;  ///< its folder
  std::vector<int> tiles;
  tiling::MergeStats stats;
  std::size_t surfaces{0}, obstacles{0}, stops{0};
  planning::FlightPlan flight;
  bool flyable{false};  ///< status ok with at least one sortie
  double merge_s{0.0}, plan_s{0.0};
  /// The smallest distance of each sortie to any input point [m] (infinity: none read).
  std::vector<double> min_clearance_to_input_m;
};

/// The site plan: each section's summary and the check against the input.
struct SiteResult {
  std::vector<SectionSummary> sections;
  std::uint64_t input_points{0};     ///< input points streamed by the check
  double required_clearance_m{0.0};  ///< the UAV's inflation radius [m]
  double min_clearance_m{0.0};       ///< over every sortie [m] (infinity: no sortie)
  double check_s{0.0};               ///< the streamed check [s]
  /// False when some section has surfaces but none has a collision-free flight.
  bool flyable() const;
};

/// Called with each section as soon as it is planned (to stage its files); the section
/// is freed when it returns.
using SectionSink = std::function<void(const SectionPlan&)>;

/// The site plan of `uavip merge`: checks that the input is there and unchanged
/// (sha256) and that every tile has a result, plans each section (planSection), hands it
/// to `sink`, then validates every sortie of every section against every input point,
/// streamed once (a planning::PathValidator per chunk). Throws InputError naming the
/// section and sortie when one comes closer than the inflation radius, so that the
/// caller commits nothing, and for a bad manifest, input or tile result.
SiteResult planSite(const tiling::Manifest& manifest, const Config& config,
                    const SiteOptions& options, const SectionSink& sink = {},
                    const Progress& progress = {});

/// OUT/site.json of a site in several sections: each section's folder, tiles and flight,
/// and its clearance to the input (its one writer).
std::string siteJsonText(const tiling::Manifest& manifest, const SiteResult& site);

}  // namespace uavip::app
