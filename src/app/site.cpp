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
#include "uavip/core/parallel.h"
#include "uavip/core/stopwatch.h"
#include "uavip/core/text.h"
#include "uavip/coverage/camera.h"
#include "uavip/io/atomic_file.h"
#include "uavip/io/file_digest.h"
#include "uavip/io/json_numbers.h"
#include "uavip/io/mission_json.h"
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

/// The config a section of a site in `sections` sections is planned with: with several,
/// one UAV (the site's fleet flies the sections at once, app/site_fleet.h; fleet.homes
/// refused there).
Config sectionConfig(const Config& config, std::size_t sections) {
  refuseFleetHomes(config.fleet, sections);
  if (sections <= 1 || !config.fleet.active()) return config;
  Config own = config;
  own.fleet.uavs = 1;
  return own;
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
  r.detected.resolved = resolveForScene(r.detected.scene, sectionConfig(config, parts.size()));
  r.merge_s = secondsSince(t0);

  const auto t1 = SteadyClock::now();
  std::vector<int> ids;
  for (const auto& s : r.detected.scene.surfaces) ids.push_back(s.id);
  r.planned = plan(r.detected.scene, r.detected.resolved.config, ids, progress);
  r.plan_s = secondsSince(t1);
  return r;
}

std::string tileResultPath(const tiling::Manifest& m, std::size_t tile) {
  return sitePath(sitePath(m.dir(), m.tiles[tile].out), "scene.json");
}

nlohmann::json fullVec(const Vec3& p) { return nlohmann::json::array({p.x(), p.y(), p.z()}); }

Vec3 readVec(const nlohmann::json& j) {
  return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()};
}

planning::FlightPlan::Status statusNamed(const std::string& name) {
  for (const auto s : {planning::FlightPlan::Status::Ok, planning::FlightPlan::Status::Empty,
                       planning::FlightPlan::Status::Failed})
    if (name == planning::toString(s)) return s;
  throw InputError("flight status '" + name + "'");
}

/// The summary of section.json (sectionResultJsonText).
SectionSummary readSummary(const nlohmann::json& j) {
  SectionSummary s;
  s.tiles = j.at("tiles").get<std::vector<int>>();
  const nlohmann::json& r = j.at("summary");
  s.surfaces = r.at("surfaces").get<std::size_t>();
  s.obstacles = r.at("obstacles").get<std::size_t>();
  s.stops = r.at("photo_stops").get<std::size_t>();
  s.flyable = r.at("flyable").get<bool>();
  s.merge_s = r.at("merge_s").get<double>();
  s.plan_s = r.at("plan_s").get<double>();
  const nlohmann::json& st = r.at("stats");
  s.stats.surface_parts = st.at("surface_parts").get<int>();
  s.stats.surfaces_dropped = st.at("surfaces_dropped").get<int>();
  s.stats.surfaces_joined = st.at("surfaces_joined").get<int>();
  s.stats.surfaces_demoted = st.at("surfaces_demoted").get<int>();
  s.stats.obstacle_parts = st.at("obstacle_parts").get<int>();
  s.stats.obstacles_joined = st.at("obstacles_joined").get<int>();
  s.stats.safety_points = st.at("safety_points").get<std::size_t>();
  const nlohmann::json& f = r.at("flight");
  s.flight.status = statusNamed(f.at("status").get<std::string>());
  s.flight.reason = f.at("reason").get<std::string>();
  s.flight.home = readVec(f.at("home"));
  s.flight.length_m = f.at("length_m").get<double>();
  const auto readSorties = [](const nlohmann::json& list, planning::FlightPlan& flight) {
    for (const auto& sortie : list) {
      planning::Sortie out;
      for (const auto& w : sortie) out.waypoints.push_back(readVec(w));
      flight.sorties.push_back(std::move(out));
    }
  };
  readSorties(f.at("sorties"), s.flight);
  const nlohmann::json& stops = f.at("stops");  // per sortie: [surface, stop, waypoint]
  if (stops.size() != s.flight.sorties.size()) throw InputError("stops not one list per sortie");
  for (std::size_t k = 0; k < stops.size(); ++k) {
    planning::Sortie& sortie = s.flight.sorties[k];
    for (const auto& st : stops[k]) {
      const planning::FlightStop stop{st.at(0).get<int>(), st.at(1).get<int>(),
                                      st.at(2).get<std::size_t>()};
      if (stop.waypoint >= sortie.waypoints.size()) throw InputError("a stop past its sortie");
      sortie.stops.push_back(stop);
    }
  }
  if (r.contains("fleet")) {
    const nlohmann::json& fl = r.at("fleet");
    s.uavs = fl.at("uavs").get<int>();
    s.makespan_s = fl.at("makespan_s").get<double>();
    s.single_uav_s = fl.at("single_uav_s").get<double>();
    for (const auto& u : fl.at("flights")) {
      planning::FlightPlan flight;
      flight.home = readVec(u.at("home"));
      readSorties(u.at("sorties"), flight);
      s.uav_flights.push_back(std::move(flight));
    }
  }
  return s;
}

/// Every sortie of every section measured against every input point, streamed once:
/// sets each section's min_clearance_to_input_m; returns the points read.
std::uint64_t checkAgainstInput(const tiling::Manifest& m, std::vector<SectionSummary>& sections) {
  std::vector<const planning::FlightPlan*> flights;
  flights.reserve(sections.size());
  for (const auto& s : sections) flights.push_back(&s.flight);
  for (const auto& s : sections)  // a fleet's flights after the single ones
    for (const auto& f : s.uav_flights) flights.push_back(&f);
  Vec3 origin = Vec3::Zero();
  std::uint64_t points = 0;
  // A sortie's nearest point is nearly always within the tile buffer (its stops fly
  // the standoff out); farther ones are measured in a second pass.
  // One reading pass in the manifest's frame (checked below).
  auto clear = clearanceToCloud(m.input, m.read, flights, std::max(10.0, m.buffer_m),
                                kSiteStreamChunk, &origin, &points, &m.source_offset_m);
  std::size_t next = sections.size();
  for (std::size_t i = 0; i < sections.size(); ++i) {
    sections[i].min_clearance_to_input_m = std::move(clear[i]);
    sections[i].uav_min_clearance_to_input_m.clear();
    for (std::size_t u = 0; u < sections[i].uav_flights.size(); ++u)
      sections[i].uav_min_clearance_to_input_m.push_back(std::move(clear[next++]));
  }
  if ((origin - m.source_offset_m).norm() > 1e-6)
    throw InputError(m.input + ": read in another frame than when it was tiled; tile it again");
  return points;
}

/// The smallest clearance of every sortie [m]; InputError naming the sortie when one
/// comes closer than `radius`, so that nothing is written.
double requireClearOfInput(const tiling::Manifest& m, const std::vector<SectionSummary>& sections,
                           double radius) {
  const bool alone = sections.size() == 1;
  double min_clear = std::numeric_limits<double>::infinity();
  const auto check = [&](const SectionSummary& section, const std::vector<double>& clear,
                         const std::string& who) {
    for (std::size_t s = 0; s < clear.size(); ++s) {
      const double c = clear[s];
      min_clear = std::min(min_clear, c);
      if (c < radius)
        throw InputError((alone ? std::string() : section.out + ": ") + who + "sortie " +
                         std::to_string(s + 1) + " comes " + formatFixed(c, 3) +
                         " m from an input point of " + m.input + " (required " +
                         formatFixed(radius, 3) + " m); nothing written");
    }
  };
  for (const auto& section : sections) {
    check(section, section.min_clearance_to_input_m, "");
    for (std::size_t u = 0; u < section.uav_min_clearance_to_input_m.size(); ++u)
      check(section, section.uav_min_clearance_to_input_m[u], "uav " + std::to_string(u + 1) + " ");
  }
  return min_clear;
}

}  // namespace

SectionSummary summarize(const SectionPlan& p) {
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
  if (p.planned.fleet) {
    const planning::FleetPlan& f = *p.planned.fleet;
    s.uavs = static_cast<int>(f.uavs.size());
    s.makespan_s = f.makespan_s;
    s.single_uav_s = f.single_uav_s;
    for (const auto& u : f.uavs) s.uav_flights.push_back(u.flight);
  }
  return s;
}

SectionKey sectionKey(const tiling::Manifest& manifest, const std::string& config_path,
                      int section_tiles, bool views, int uavs) {
  SectionKey k;
  // With several sections each is planned for one UAV (sectionConfig).
  k.uavs = siteSections(manifest, section_tiles).size() > 1 ? 1 : uavs;
  k.manifest_sha256 = io::sha256File(manifest.path);
  k.config_sha256 = config_path.empty() ? std::string() : io::sha256File(config_path);
  k.section_tiles = section_tiles;
  k.views = views;
  return k;
}

std::string sectionResultFolder(const tiling::Manifest& manifest, std::size_t index) {
  char name[32];
  std::snprintf(name, sizeof name, "section_%03zu", index);
  return sitePath(manifest.dir(), name);
}

std::string sectionResultJsonText(const tiling::Manifest& manifest, const SectionKey& key,
                                  const SectionPlan& plan,
                                  const std::vector<std::pair<std::string, std::string>>& files) {
  const SectionSummary s = summarize(plan);
  nlohmann::json results = nlohmann::json::array();
  for (const int t : s.tiles)
    results.push_back(io::sha256File(tileResultPath(manifest, static_cast<std::size_t>(t))));
  nlohmann::json file_list = nlohmann::json::array();
  for (const auto& [name, sha] : files) file_list.push_back({{"name", name}, {"sha256", sha}});
  const auto sortiesOf = [](const planning::FlightPlan& flight) {
    nlohmann::json sorties = nlohmann::json::array();
    for (const auto& sortie : flight.sorties) {
      nlohmann::json w = nlohmann::json::array();
      for (const Vec3& p : sortie.waypoints) w.push_back(fullVec(p));
      sorties.push_back(std::move(w));
    }
    return sorties;
  };
  const nlohmann::json sorties = sortiesOf(s.flight);
  nlohmann::json sortie_stops = nlohmann::json::array();  // the site's fleet times hovers by them
  for (const auto& sortie : s.flight.sorties) {
    nlohmann::json list = nlohmann::json::array();
    for (const auto& st : sortie.stops) list.push_back({st.surface_id, st.stop, st.waypoint});
    sortie_stops.push_back(std::move(list));
  }
  const nlohmann::json stats = {
      {"surface_parts", s.stats.surface_parts},     {"surfaces_dropped", s.stats.surfaces_dropped},
      {"surfaces_joined", s.stats.surfaces_joined}, {"surfaces_demoted", s.stats.surfaces_demoted},
      {"obstacle_parts", s.stats.obstacle_parts},   {"obstacles_joined", s.stats.obstacles_joined},
      {"safety_points", s.stats.safety_points}};
  nlohmann::json summary = {{"surfaces", s.surfaces},
                            {"obstacles", s.obstacles},
                            {"photo_stops", s.stops},
                            {"flyable", s.flyable},
                            {"merge_s", s.merge_s},
                            {"plan_s", s.plan_s},
                            {"stats", stats},
                            {"flight",
                             {{"status", planning::toString(s.flight.status)},
                              {"reason", s.flight.reason},
                              {"home", fullVec(s.flight.home)},
                              {"length_m", s.flight.length_m},
                              {"sorties", sorties},
                              {"stops", sortie_stops}}}};
  if (!s.uav_flights.empty()) {  // a fleet: each UAV's sorties (checked against the input)
    nlohmann::json flights = nlohmann::json::array();
    for (const auto& f : s.uav_flights)
      flights.push_back({{"home", fullVec(f.home)}, {"sorties", sortiesOf(f)}});
    summary["fleet"] = {{"uavs", s.uavs},
                        {"makespan_s", s.makespan_s},
                        {"single_uav_s", s.single_uav_s},
                        {"flights", flights}};
  }
  nlohmann::json j = {{"format", "uavip section 1"},
                      {"manifest", manifest.path},
                      {"manifest_sha256", key.manifest_sha256},
                      {"config_sha256", key.config_sha256},
                      {"section_tiles", key.section_tiles},
                      {"views", key.views},
                      {"section", plan.index},
                      {"sections", plan.count},
                      {"tiles", s.tiles},
                      {"tile_results_sha256", results},
                      {"files", file_list},
                      {"summary", summary}};
  if (key.uavs > 1) j["uavs"] = key.uavs;  // absent: one UAV, as before fleets
  return j.dump(1) + "\n";
}

SectionResult readSectionResult(const tiling::Manifest& manifest, const SectionKey& key,
                                const std::vector<std::vector<std::size_t>>& parts,
                                std::size_t index, const std::string& out) {
  SectionResult r;
  r.index = index;
  r.folder = sectionResultFolder(manifest, index);
  const std::string record = sitePath(r.folder, kSectionResultFile);
  if (!std::filesystem::exists(record)) {
    r.why = "no result";
    return r;
  }
  try {
    const nlohmann::json j = nlohmann::json::parse(io::readFile(record));
    if (j.at("format") != "uavip section 1") {
      r.why = "section.json of another format";
      return r;
    }
    if (j.at("manifest_sha256") != key.manifest_sha256) {
      r.why = "made from another manifest.json (sha256 differs)";
      return r;
    }
    if (j.at("config_sha256") != key.config_sha256) {
      r.why = "planned with another config (sha256 differs)";
      return r;
    }
    if (j.at("section_tiles") != key.section_tiles || j.at("sections") != parts.size() ||
        j.at("section") != index) {
      r.why = "planned for another --section-tiles";
      return r;
    }
    if (j.value("uavs", 1) != key.uavs) {
      r.why = "planned for " + std::to_string(j.value("uavs", 1)) + " UAV(s), not " +
              std::to_string(key.uavs) + " (--uavs)";
      return r;
    }
    if (j.at("views") != key.views) {
      r.why = key.views ? "planned without views" : "planned with views";
      return r;
    }
    if (!j.at("summary").at("flight").contains("stops")) {
      r.why = "made by an older uavip (no photo stops per sortie)";
      return r;
    }
    const auto tiles = j.at("tiles").get<std::vector<std::size_t>>();
    const auto digests = j.at("tile_results_sha256").get<std::vector<std::string>>();
    if (tiles != parts[index] || digests.size() != tiles.size()) {
      r.why = "made for other tiles";
      return r;
    }
    for (std::size_t i = 0; i < tiles.size(); ++i) {
      const std::string path = tileResultPath(manifest, tiles[i]);
      if (!std::filesystem::exists(path) || io::sha256File(path) != digests[i]) {
        r.why = "tile " + std::to_string(tiles[i]) + "'s result changed since (run-tile again)";
        return r;
      }
    }
    for (const auto& f : j.at("files")) {
      const std::string name = f.at("name").get<std::string>();
      const std::string path = sitePath(r.folder, name);
      if (name.find('/') != std::string::npos || !std::filesystem::exists(path) ||
          io::sha256File(path) != f.at("sha256").get<std::string>()) {
        r.why = name + " is missing or changed";
        r.files.clear();
        return r;
      }
      r.files.push_back(name);
    }
    SectionSummary s = readSummary(j);
    s.out = sectionFolder(out, index, parts.size());
    s.joined = true;
    r.summary = std::move(s);
  } catch (const std::exception& e) {
    r.why = std::string("section.json unreadable (") + e.what() + ")";
    r.files.clear();
  }
  return r;
}

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

/// One leg of a sortie (a → b; a == b for a sortie of one waypoint).
struct Leg {
  std::size_t flight, sortie;
  Vec3 a, b;
};

/// Square cells of edge `edge` over the legs' x, y boxes grown by `cutoff`; each
/// leg listed in every cell its grown box meets (compressed rows: first[c] … first[c + 1]).
struct LegGrid {
  Eigen::Vector2d lo{Eigen::Vector2d::Zero()};
  double edge{1.0};
  long nx{0}, ny{0};
  std::vector<std::uint32_t> first{0}, listed;

  LegGrid(const std::vector<Leg>& legs, double cutoff) : edge(cutoff) {
    if (legs.empty()) return;
    Eigen::Vector2d hi = Eigen::Vector2d::Constant(-kInfinity);
    lo = -hi;
    for (const auto& l : legs) {
      lo = lo.cwiseMin(l.a.head<2>().cwiseMin(l.b.head<2>()));
      hi = hi.cwiseMax(l.a.head<2>().cwiseMax(l.b.head<2>()));
    }
    lo.array() -= cutoff;
    hi.array() += cutoff;
    do {  // at most 4 M cells
      nx = static_cast<long>(std::floor((hi.x() - lo.x()) / edge)) + 1;
      ny = static_cast<long>(std::floor((hi.y() - lo.y()) / edge)) + 1;
      edge *= 2.0;
    } while (static_cast<double>(nx) * static_cast<double>(ny) > 4e6);
    edge /= 2.0;
    first.assign(static_cast<std::size_t>(nx * ny) + 1, 0);
    for (const auto& l : legs) forCells(l, cutoff, [&](std::size_t c) { ++first[c + 1]; });
    for (std::size_t c = 0; c + 1 < first.size(); ++c) first[c + 1] += first[c];
    listed.resize(first.back());
    std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
    for (std::size_t i = 0; i < legs.size(); ++i)
      forCells(legs[i], cutoff,
               [&](std::size_t c) { listed[fill[c]++] = static_cast<std::uint32_t>(i); });
  }
  std::size_t cells() const { return first.size() - 1; }
  /// The cell of p, or −1 outside the grid.
  long cellOf(const Vec3& p) const {
    const double fx = std::floor((p.x() - lo.x()) / edge), fy = std::floor((p.y() - lo.y()) / edge);
    if (!(fx >= 0.0 && fy >= 0.0 && fx < static_cast<double>(nx) && fy < static_cast<double>(ny)))
      return -1;
    return static_cast<long>(fy) * nx + static_cast<long>(fx);
  }

 private:
  template <typename Fn>
  void forCells(const Leg& l, double cutoff, const Fn& fn) const {
    const auto range = [&](double a, double b, double origin, long n) {
      return std::pair<long, long>(
          std::clamp(static_cast<long>(std::floor((a - origin) / edge)), 0L, n - 1),
          std::clamp(static_cast<long>(std::floor((b - origin) / edge)), 0L, n - 1));
    };
    const auto [x0, x1] =
        range(std::min(l.a.x(), l.b.x()) - cutoff, std::max(l.a.x(), l.b.x()) + cutoff, lo.x(), nx);
    const auto [y0, y1] =
        range(std::min(l.a.y(), l.b.y()) - cutoff, std::max(l.a.y(), l.b.y()) + cutoff, lo.y(), ny);
    for (long y = y0; y <= y1; ++y)
      for (long x = x0; x <= x1; ++x) fn(static_cast<std::size_t>(y * nx + x));
  }
};

/// The input's points in chunks: in one pass in the frame `frame_m` when given
/// (io::streamCloudInFrame), else in loadCloud's frame (io::streamCloud, two passes).
io::CloudStreamInfo streamInput(const std::string& input, const io::CloudReadOptions& read,
                                const Vec3* frame_m, std::size_t chunk_points,
                                const io::CloudChunkSink& sink) {
  if (frame_m) return io::streamCloudInFrame(input, read, *frame_m, chunk_points, sink);
  return io::streamCloud(input, read, chunk_points, sink);
}

/// The sorties with no point within the cutoff (clearance above it) measured again
/// against every point, their whole path per chunk.
void remeasureFar(const std::string& input, const io::CloudReadOptions& read, const Vec3* frame_m,
                  const std::vector<const planning::FlightPlan*>& flights, double cutoff_m,
                  std::size_t chunk_points, std::vector<std::vector<double>>& clear) {
  std::vector<std::pair<std::size_t, std::size_t>> far;
  for (std::size_t f = 0; f < flights.size(); ++f)
    for (std::size_t s = 0; s < clear[f].size(); ++s)
      if (!(clear[f][s] <= cutoff_m) && !flights[f]->sorties[s].waypoints.empty())
        far.emplace_back(f, s);
  if (far.empty()) return;
  for (const auto& [f, s] : far) clear[f][s] = kInfinity;
  streamInput(input, read, frame_m, chunk_points, [&](const PointList& chunk_cloud) {
    const planning::PathValidator validator(chunk_cloud, cutoff_m);
    for (const auto& [f, s] : far)
      clear[f][s] = std::min(clear[f][s],
                             validator.validate(flights[f]->sorties[s].waypoints).min_clearance_m);
  });
}

}  // namespace

std::vector<std::vector<double>> clearanceToCloud(
    const std::string& input, const io::CloudReadOptions& read,
    const std::vector<const planning::FlightPlan*>& flights, double cutoff_m,
    std::size_t chunk_points, Vec3* origin, std::uint64_t* points, const Vec3* frame_m) {
  std::vector<std::vector<double>> clear(flights.size());
  std::vector<Leg> legs;
  for (std::size_t f = 0; f < flights.size(); ++f) {
    const auto& sorties = flights[f]->sorties;
    clear[f].assign(sorties.size(), kInfinity);
    for (std::size_t s = 0; s < sorties.size(); ++s) {
      const PointList& w = sorties[s].waypoints;
      if (w.size() == 1) legs.push_back({f, s, w[0], w[0]});
      for (std::size_t i = 0; i + 1 < w.size(); ++i) legs.push_back({f, s, w[i], w[i + 1]});
    }
  }
  const LegGrid grid(legs, cutoff_m);
  std::vector<std::uint64_t> cell_seen(grid.cells(), 0), leg_seen(legs.size(), 0);
  std::uint64_t chunk = 0;
  const io::CloudStreamInfo info =
      streamInput(input, read, frame_m, chunk_points, [&](const PointList& chunk_cloud) {
        ++chunk;
        PointList near;  // the chunk's points in cells with a leg, and those legs
        std::vector<std::uint32_t> touched;
        for (const Vec3& p : chunk_cloud) {
          const long c = legs.empty() ? -1 : grid.cellOf(p);
          if (c < 0 || grid.first[c] == grid.first[c + 1]) continue;
          near.push_back(p);
          if (cell_seen[c] == chunk) continue;
          cell_seen[c] = chunk;
          for (std::uint32_t k = grid.first[c]; k < grid.first[c + 1]; ++k)
            if (leg_seen[grid.listed[k]] != chunk) {
              leg_seen[grid.listed[k]] = chunk;
              touched.push_back(grid.listed[k]);
            }
        }
        if (near.empty()) return;
        std::sort(touched.begin(), touched.end());
        const planning::PathValidator validator(near, cutoff_m);
        std::vector<double> d(touched.size());
        parallelFor(touched.size(), hardwareThreads(), [&](std::size_t i, std::size_t) {
          const Leg& l = legs[touched[i]];
          d[i] = validator.world().proximity(l.a, l.b, cutoff_m).distance_m;
        });
        for (std::size_t i = 0; i < touched.size(); ++i) {
          const Leg& l = legs[touched[i]];
          clear[l.flight][l.sortie] = std::min(clear[l.flight][l.sortie], d[i]);
        }
      });
  if (origin) *origin = info.read.origin_m;
  if (points) *points = info.points;
  if (info.points > 0) remeasureFar(input, read, frame_m, flights, cutoff_m, chunk_points, clear);
  return clear;
}

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
                    const SiteOptions& options, const SectionSink& sink, const Progress& progress,
                    const SectionJoin& join) {
  options.validate();
  requireSiteInput(manifest);
  const auto parts = siteSections(manifest, options.section_tiles);
  refuseFleetHomes(config.fleet, parts.size());  // before any work
  std::vector<SectionResult> found(parts.size());
  std::vector<std::size_t> here;  // sections planned here, and their tiles
  std::vector<std::size_t> tiles;
  std::string missing, why;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    if (options.results)
      found[i] = readSectionResult(manifest, *options.results, parts, i, options.out);
    else
      found[i].why = "no result";
    if (found[i].summary) continue;
    here.push_back(i);
    tiles.insert(tiles.end(), parts[i].begin(), parts[i].end());
    missing += (missing.empty() ? "" : ",") + std::to_string(i);
    why += (why.empty() ? "" : "; ") + std::to_string(i) + ": " + found[i].why;
  }
  if (options.results && options.require_results && !here.empty())
    throw InputError(manifest.path + ": no usable result of plan-section for section(s) " +
                     missing + " (" + why + "); plan them: uavip plan-section " + manifest.path +
                     " --section S (Slurm: scripts/slurm/submit.sh " + manifest.dir() +
                     " --sections " + missing + "), then merge again");
  std::sort(tiles.begin(), tiles.end());
  requireTileResults(manifest, tiles);
  SiteResult site;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    if (found[i].summary) {
      if (join) join(found[i]);
      site.sections.push_back(*found[i].summary);
      continue;
    }
    if (options.results && found[i].why != "no result")
      site.notes.push_back("section " + std::to_string(i) + ": the result in " + found[i].folder +
                           " is not used (" + found[i].why + "); planned here");
    const SectionPlan section = planSectionOf(manifest, parts, i, config, options, progress);
    if (sink) sink(section);
    site.sections.push_back(summarize(section));
    if (parts.size() > 1)
      reportProgress(progress, "section " + std::to_string(i + 1) + " of " +
                                   std::to_string(parts.size()) + " planned");
  }
  const auto t0 = SteadyClock::now();
  site.required_clearance_m = config.uav.inflationRadius();
  site.input_points = checkAgainstInput(manifest, site.sections);
  site.min_clearance_m = requireClearOfInput(manifest, site.sections, site.required_clearance_m);
  site.check_s = secondsSince(t0);
  if (parts.size() > 1 && config.fleet.active()) {  // the sections flown at once
    std::vector<const planning::FlightPlan*> flights;
    for (const auto& s : site.sections) flights.push_back(&s.flight);
    site.fleet = planSiteFleet(flights, config.fleet, config.flightOptions().model);
  }
  return site;
}

namespace {

/// site.json `fleet` (docs/fleet.md, "A tiled site"): the fleet's summary
/// (io::fleetSummaryToJson) with mode, uavs_flying, sorties and each UAV's sorties by
/// section folder and sortie number (from 1, as in its mission.json) with take-off times.
nlohmann::json siteFleetJson(const SiteFleet& fleet, const std::vector<SectionSummary>& sections) {
  nlohmann::json j = io::fleetSummaryToJson(fleet.plan);
  j["mode"] = "sections at once";
  j["uavs_flying"] = fleet.uavs_flying;
  j["sorties"] = fleet.plan.jobs;
  nlohmann::json uavs = nlohmann::json::array();
  for (std::size_t u = 0; u < fleet.plan.uavs.size(); ++u) {
    const planning::FleetUav& uav = fleet.plan.uavs[u];
    nlohmann::json list = nlohmann::json::array();
    for (std::size_t k = 0; k < fleet.runs[u].size(); ++k) {
      const SiteSortie& at = fleet.runs[u][k];
      list.push_back(
          {{"folder", std::filesystem::path(sections[at.section].out).filename().string()},
           {"section", at.section},
           {"sortie", at.sortie + 1},
           {"start_s", io::round4(uav.sortie_start_s.at(k))},
           {"duration_s", io::round4(uav.flight.sorties[k].duration_s)}});
    }
    uavs.push_back({{"uav", u + 1},
                    {"home", io::vec(uav.home)},
                    {"stop_count", uav.stops},
                    {"wait_s", io::round4(uav.wait_s)},
                    {"end_s", io::round4(uav.end_s)},
                    {"sorties", list}});
  }
  j["uavs"] = std::move(uavs);
  return j;
}

}  // namespace

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
  nlohmann::json j = {{"format", io::kSiteFormat},
                      {"manifest", manifest.path},
                      {"input", manifest.input},
                      {"input_points", site.input_points},
                      {"clearance_m", site.required_clearance_m},
                      {"source_offset_m", io::vec(manifest.source_offset_m)},
                      {"sections", list}};
  if (site.fleet) j["fleet"] = siteFleetJson(*site.fleet, site.sections);
  return j.dump(1) + "\n";
}

}  // namespace uavip::app
