#pragma once
/// \file
/// A site too large for one process, as tiles (tiling/tiles.h): the tiling options, one
/// tile's stages 3–5, and the site plan: the tiles' scenes merged into sections
/// (tiling/merge.h), each section planned by app::plan (its own flight and home), and
/// every sortie of every section checked against every input point, streamed once.
/// A section may be planned apart (`uavip plan-section`, a second Slurm array): its
/// result, TILES/section_NNN/ with section.json written last, is then only joined by the
/// merge when it was made from this manifest, config and tile results (SectionKey).
/// `uavip tile`, `run-tile`, `plan-section` and `merge` call these; nothing here prints
/// or writes files (the caller stages each section's outputs as it is handed over, then
/// it is freed).

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "uavip/app/pipeline.h"
#include "uavip/app/scenario.h"
#include "uavip/app/site_fleet.h"
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

struct SectionKey;

/// Options of the site plan (`uavip merge`).
struct SiteOptions {
  /// Sections of K × K tile cells, one flight each; 0: the largest K whose every section
  /// holds at most kSectionPoints (core + buffer), at least 1.
  int section_tiles{0};
  /// The output folder: the only section's, or the parent of `section_NNN/` each
  /// (sectionFolder). Only named here, in messages and SectionPlan::out.
  std::string out;
  /// Join the results plan-section left beside the manifest when they were made for
  /// this key (readSectionResult); null: plan every section here.
  const SectionKey* results{nullptr};
  /// With `results`: refuse (InputError naming each section without a usable result
  /// and the command that plans it) instead of planning such a section here.
  bool require_results{false};
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
  bool joined{false};  ///< read from plan-section's result, not planned by the merge
  /// The smallest distance of each sortie to any input point [m] (infinity: none read).
  std::vector<double> min_clearance_to_input_m;
  /// A fleet over a site of one section (merge --uavs K, K > 1): each UAV's flight, the
  /// makespan and the single UAV's [s]. A site of several sections plans each for one
  /// UAV and flies them at once (SiteResult::fleet).
  std::vector<planning::FlightPlan> uav_flights;
  int uavs{1};
  double makespan_s{0.0};
  double single_uav_s{0.0};
  /// Of each UAV's sorties, as min_clearance_to_input_m [m].
  std::vector<std::vector<double>> uav_min_clearance_to_input_m;
};

/// What stays of a planned section.
SectionSummary summarize(const SectionPlan& plan);

/// What a section's result was made from: a result made for other values is stale.
struct SectionKey {
  std::string manifest_sha256;  ///< of manifest.json
  std::string config_sha256;    ///< of the config file used; empty for the defaults
  int section_tiles{0};         ///< SiteOptions::section_tiles as given (0: chosen)
  bool views{true};             ///< the section's views were drawn
  /// The UAVs a section is planned for: fleet.uavs (merge --uavs) on a site of one
  /// section, else 1 (the site's fleet flies the sections at once).
  int uavs{1};
};

/// The key of `manifest` planned with the config file `config_path` (empty: defaults).
SectionKey sectionKey(const tiling::Manifest& manifest, const std::string& config_path,
                      int section_tiles, bool views, int uavs = 1);

/// The record of a section's result, written after its other files (their presence
/// without it is no result).
inline constexpr const char* kSectionResultFile = "section.json";

/// The folder of section `index`'s result beside the manifest: TILES/section_NNN.
std::string sectionResultFolder(const tiling::Manifest& manifest, std::size_t index);

/// The text of section.json (its one writer): the key, the section's tiles with the
/// sha256 of each tile's scene.json it was planned from, `files` (name beside it,
/// sha256) and the summary, the flight's waypoints at full precision.
std::string sectionResultJsonText(const tiling::Manifest& manifest, const SectionKey& key,
                                  const SectionPlan& plan,
                                  const std::vector<std::pair<std::string, std::string>>& files);

/// A section's result as plan-section left it.
struct SectionResult {
  std::size_t index{0};
  std::string folder;  ///< TILES/section_NNN
  /// Usable: made for the key, from the section's tiles and their present results,
  /// every file there with its sha256. `out` is the site's folder of the section.
  std::optional<SectionSummary> summary;
  std::vector<std::string> files;  ///< names beside section.json, in the order written
  std::string why;                 ///< why not usable ("no result", "made from another …")
};

/// Reads section `index` of `parts` (siteSections) beside the manifest; never throws
/// for a missing, stale or damaged result (SectionResult::why says which).
SectionResult readSectionResult(const tiling::Manifest& manifest, const SectionKey& key,
                                const std::vector<std::vector<std::size_t>>& parts,
                                std::size_t index, const std::string& out);

/// The site plan: each section's summary and the check against the input.
struct SiteResult {
  std::vector<SectionSummary> sections;
  /// One line per section planned here although a result was there, and why.
  std::vector<std::string> notes;
  std::uint64_t input_points{0};     ///< input points streamed by the check
  double required_clearance_m{0.0};  ///< the UAV's inflation radius [m]
  double min_clearance_m{0.0};       ///< over every sortie [m] (infinity: no sortie)
  double check_s{0.0};               ///< the streamed check [s]
  /// With a fleet (fleet.uavs > 1) over several sections: the sections flown at once.
  std::optional<SiteFleet> fleet;
  /// False when some section has surfaces but none has a collision-free flight.
  bool flyable() const;
};

/// Called with each section as soon as it is planned (to stage its files); the section
/// is freed when it returns.
using SectionSink = std::function<void(const SectionPlan&)>;
/// Called with each usable result of plan-section (to stage copies of its files).
using SectionJoin = std::function<void(const SectionResult&)>;

/// The site plan of `uavip merge`: checks that the input is there and unchanged
/// (sha256); joins each section's usable result (options.results; handed to `join`)
/// and plans each other one here (planSection; handed to `sink`), after checking that
/// its tiles have results; then validates every sortie of every section against every
/// input point, streamed once (validateAgainstInput). Throws InputError naming the
/// section and sortie when one comes closer than the inflation radius, so that the
/// caller commits nothing, for a bad manifest, input or tile result, and (with
/// options.require_results) naming each section without a usable result.
SiteResult planSite(const tiling::Manifest& manifest, const Config& config,
                    const SiteOptions& options, const SectionSink& sink = {},
                    const Progress& progress = {}, const SectionJoin& join = {});

/// The smallest distance [m] from each sortie of `flights` to any point of the cloud
/// `input` (read with `read`), streamed once in chunks of `chunk_points` (infinity: no
/// point). Exact, and linear in points + segments: the segments are binned into square
/// cells of edge `cutoff_m` over their x, y boxes grown by `cutoff_m`; a chunk's points
/// in cells without a segment are dropped, and each segment is measured
/// (world::CollisionWorld::proximity) only against the chunks whose points fell into
/// its cells. A sortie whose nearest point lies farther than `cutoff_m` is measured
/// again against every point (a second pass, for those sorties only). `origin` gets
/// the read's origin (io::CloudReadInfo::origin_m), `points` the points read. With
/// `frame_m` (the flights' frame, e.g. the manifest's source_offset_m) the input is
/// read in one pass in that frame (io::streamCloudInFrame; compare `origin` with it),
/// else in loadCloud's frame (io::streamCloud, which finds it in a pass of its own).
std::vector<std::vector<double>> clearanceToCloud(
    const std::string& input, const io::CloudReadOptions& read,
    const std::vector<const planning::FlightPlan*>& flights, double cutoff_m,
    std::size_t chunk_points, Vec3* origin = nullptr, std::uint64_t* points = nullptr,
    const Vec3* frame_m = nullptr);

/// OUT/site.json of a site in several sections: each section's folder, tiles and flight,
/// and its clearance to the input; with a fleet, `fleet` (the sections flown at once,
/// site_fleet.h: the schedule of every UAV's sorties by section) (its one writer).
std::string siteJsonText(const tiling::Manifest& manifest, const SiteResult& site);

}  // namespace uavip::app
