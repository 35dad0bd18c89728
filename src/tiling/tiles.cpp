#include "uavip/tiling/tiles.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "uavip/core/error.h"
#include "uavip/core/text.h"
#include "uavip/io/file_digest.h"
#include "uavip/io/json_numbers.h"
#include "uavip/io/json_reader.h"

namespace uavip::tiling {
namespace {

namespace fs = std::filesystem;

/// Largest grid: beyond it the tile size is surely wrong for the cloud.
constexpr long kMaxTiles = 100000;

/// The points of one tile waiting to be appended to its temporary files.
struct Pending {
  std::vector<float> core, extra;  ///< x y z per point
  std::uint64_t core_count{0}, extra_count{0};
};

/// The temporary point files of the tiler: raw float x y z, removed when destroyed.
class RawFiles {
 public:
  explicit RawFiles(std::string dir) : dir_(std::move(dir)) {}
  RawFiles(const RawFiles&) = delete;
  RawFiles& operator=(const RawFiles&) = delete;
  ~RawFiles() {
    for (const auto& f : files_) {
      std::error_code ec;
      fs::remove(f, ec);
    }
  }
  std::string name(long cell, bool core) const {
    return (fs::path(dir_) /
            (".tile_" + std::to_string(cell) + (core ? ".core" : ".extra") + ".raw.tmp"))
        .string();
  }
  void append(long cell, bool core, std::vector<float>& values) {
    if (values.empty()) return;
    const std::string f = name(cell, core);
    if (std::find(files_.begin(), files_.end(), f) == files_.end()) files_.push_back(f);
    std::ofstream out(f, std::ios::binary | std::ios::app);
    out.write(reinterpret_cast<const char*>(values.data()),
              static_cast<std::streamsize>(values.size() * sizeof(float)));
    if (!out) throw InputError(f + ": cannot write a temporary tile file (disk full?)");
    values.clear();
  }
  void read(long cell, bool core, PointList& into) const {
    std::ifstream in(name(cell, core), std::ios::binary);
    if (!in) return;
    float xyz[3];
    while (in.read(reinterpret_cast<char*>(xyz), sizeof xyz))
      into.emplace_back(static_cast<double>(xyz[0]), static_cast<double>(xyz[1]),
                        static_cast<double>(xyz[2]));
  }

 private:
  std::string dir_;
  std::vector<std::string> files_;
};

void push(std::vector<float>& values, const Vec3& p) {
  values.push_back(static_cast<float>(p.x()));
  values.push_back(static_cast<float>(p.y()));
  values.push_back(static_cast<float>(p.z()));
}

nlohmann::json box(const Box2& b) {
  return {{"min", {io::round4(b.min.x()), io::round4(b.min.y())}},
          {"max", {io::round4(b.max.x()), io::round4(b.max.y())}}};
}

Box2 readBox(const io::JsonReader& r, const nlohmann::json& j, const std::string& field) {
  Box2 b;
  for (const char* corner : {"min", "max"}) {
    const nlohmann::json& v = r.list(r.at(j, corner, field), field + "." + corner);
    if (v.size() != 2) r.fail(field + "." + corner, "must be [x, y]");
    Eigen::Vector2d& c = std::string(corner) == "min" ? b.min : b.max;
    c = Eigen::Vector2d(r.number(v[0], field + "." + corner), r.number(v[1], field + "." + corner));
  }
  return b;
}

}  // namespace

void TileOptions::validate(const std::string& where) const {
  if (!(std::isfinite(tile_size_m) && tile_size_m > 0.0))
    throw InputError(where + ": --tile-size must be > 0 m, got " + formatNumber(tile_size_m));
  if (!(std::isfinite(buffer_m) && buffer_m >= 0.0))
    throw InputError(where + ": --buffer must be >= 0 m, got " + formatNumber(buffer_m));
  if (chunk_points < 16) throw InputError(where + ": chunk_points must be >= 16");
}

std::pair<int, int> Manifest::cellOf(const Vec3& p) const {
  const auto cell = [&](double v, double o, int n) {
    const double c = std::floor((v - o) / tile_size_m);
    return static_cast<int>(std::clamp(c, 0.0, static_cast<double>(n - 1)));
  };
  return {cell(p.x(), grid_origin.x(), columns), cell(p.y(), grid_origin.y(), rows)};
}

const TileRecord& Manifest::tile(long index) const {
  if (index < 0 || index >= static_cast<long>(tiles.size()))
    throw InputError(path + ": no tile " + std::to_string(index) + ", the tiles are 0.." +
                     std::to_string(static_cast<long>(tiles.size()) - 1));
  return tiles[static_cast<std::size_t>(index)];
}

std::string Manifest::dir() const { return fs::path(path).parent_path().string(); }

std::string manifestJsonText(const Manifest& m) {
  nlohmann::json tiles = nlohmann::json::array();
  for (const TileRecord& t : m.tiles) {
    tiles.push_back({{"index", t.index},
                     {"column", t.column},
                     {"row", t.row},
                     {"core", box(t.core)},
                     {"buffered", box(t.buffered)},
                     {"core_points", t.core_points},
                     {"buffer_points", t.buffer_points},
                     {"cloud", t.cloud},
                     {"sha256", t.sha256},
                     {"out", t.out}});
  }
  nlohmann::json j = {{"format", "uavip tiles 1"},
                      {"input",
                       {{"path", m.input},
                        {"sha256", m.input_sha256},
                        {"points", m.input_points},
                        {"scale", m.read.scale},
                        {"drop_classes", m.read.drop_classes},
                        {"source_offset_m", io::vec(m.source_offset_m)},
                        {"crs_unit", m.crs_unit}}},
                      {"config", m.config},
                      {"tile_size_m", m.tile_size_m},
                      {"buffer_m", m.buffer_m},
                      {"grid",
                       // Unrounded: ownership (Manifest::cellOf) is computed from it at every step.
                       {{"origin", {m.grid_origin.x(), m.grid_origin.y()}},
                        {"columns", m.columns},
                        {"rows", m.rows}}},
                      {"bounds", {{"min", io::vec(m.min)}, {"max", io::vec(m.max)}}},
                      {"tiles", tiles}};
  // The input's CRS (a LAS file's): every tile's and the merged scene.json record it.
  if (!m.crs.empty())
    j["crs"] = {{"definition", m.crs}, {"source", m.crs_source}, {"vertical", m.crs_vertical}};
  return j.dump(1) + "\n";
}

Manifest loadManifest(const std::string& path) {
  const io::JsonReader r(path);
  const nlohmann::json j = r.load();
  Manifest m;
  m.path = path;
  if (!j.is_object() || r.text(r.at(j, "format", ""), "format") != "uavip tiles 1")
    r.fail("format", "is not \"uavip tiles 1\"; give the manifest.json that uavip tile wrote");
  const nlohmann::json& in = r.at(j, "input", "");
  m.input = r.text(r.at(in, "path", "input"), "input.path");
  m.input_sha256 = r.text(r.at(in, "sha256", "input"), "input.sha256");
  m.input_points = static_cast<std::uint64_t>(
      r.integer(r.at(in, "points", "input"), "input.points", 1, std::int64_t{1} << 50));
  m.read.scale = r.number(r.at(in, "scale", "input"), "input.scale");
  for (const auto& c : r.list(r.at(in, "drop_classes", "input"), "input.drop_classes"))
    m.read.drop_classes.push_back(static_cast<int>(r.integer(c, "input.drop_classes", 0, 255)));
  m.source_offset_m = r.vec3(r.at(in, "source_offset_m", "input"), "input.source_offset_m", false);
  m.crs_unit = r.text(r.at(in, "crs_unit", "input"), "input.crs_unit");
  if (j.contains("crs")) {  // written since the CRS travels with the tiles
    const nlohmann::json& crs = j.at("crs");
    m.crs = r.text(r.at(crs, "definition", "crs"), "crs.definition");
    m.crs_source = r.text(r.at(crs, "source", "crs"), "crs.source");
    m.crs_vertical = r.text(r.at(crs, "vertical", "crs"), "crs.vertical");
  }
  m.config = r.text(r.at(j, "config", ""), "config");
  m.tile_size_m = r.number(r.at(j, "tile_size_m", ""), "tile_size_m", 1e-3, 1e6, "m");
  m.buffer_m = r.number(r.at(j, "buffer_m", ""), "buffer_m", 0.0, 1e6, "m");
  const nlohmann::json& g = r.at(j, "grid", "");
  const nlohmann::json& o = r.list(r.at(g, "origin", "grid"), "grid.origin");
  if (o.size() != 2) r.fail("grid.origin", "must be [x, y]");
  m.grid_origin = Eigen::Vector2d(r.number(o[0], "grid.origin"), r.number(o[1], "grid.origin"));
  m.columns = static_cast<int>(r.integer(r.at(g, "columns", "grid"), "grid.columns", 1, kMaxTiles));
  m.rows = static_cast<int>(r.integer(r.at(g, "rows", "grid"), "grid.rows", 1, kMaxTiles));
  const nlohmann::json& b = r.at(j, "bounds", "");
  m.min = r.vec3(r.at(b, "min", "bounds"), "bounds.min");
  m.max = r.vec3(r.at(b, "max", "bounds"), "bounds.max");
  const nlohmann::json& tiles = r.list(r.at(j, "tiles", ""), "tiles");
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    const std::string f = "tiles[" + std::to_string(i) + "]";
    const nlohmann::json& t = tiles[i];
    TileRecord rec;
    rec.index = static_cast<int>(r.integer(r.at(t, "index", f), f + ".index", 0, kMaxTiles));
    if (rec.index != static_cast<int>(i)) r.fail(f + ".index", "must be " + std::to_string(i));
    rec.column = static_cast<int>(r.integer(r.at(t, "column", f), f + ".column", 0, m.columns - 1));
    rec.row = static_cast<int>(r.integer(r.at(t, "row", f), f + ".row", 0, m.rows - 1));
    rec.core = readBox(r, r.at(t, "core", f), f + ".core");
    rec.buffered = readBox(r, r.at(t, "buffered", f), f + ".buffered");
    rec.core_points = static_cast<std::uint64_t>(
        r.integer(r.at(t, "core_points", f), f + ".core_points", 0, std::int64_t{1} << 50));
    rec.buffer_points = static_cast<std::uint64_t>(
        r.integer(r.at(t, "buffer_points", f), f + ".buffer_points", 0, std::int64_t{1} << 50));
    rec.cloud = r.text(r.at(t, "cloud", f), f + ".cloud");
    rec.sha256 = r.text(r.at(t, "sha256", f), f + ".sha256");
    rec.out = r.text(r.at(t, "out", f), f + ".out");
    for (const std::string* name : {&rec.cloud, &rec.out})
      if (name->empty() || name->find('/') != std::string::npos || *name == "..")
        r.fail(f, "file names must be plain names beside the manifest, got '" + *name + "'");
    m.tiles.push_back(std::move(rec));
  }
  return m;
}

namespace {

/// The grid of the manifest from the cloud's count, bounds and frame.
void setGrid(Manifest& m, const io::CloudStreamInfo& info, const std::string& cloud) {
  m.input_points = info.points;
  m.min = info.min;
  m.max = info.max;
  m.source_offset_m = info.read.origin_m;
  m.crs_unit = info.crs_unit;
  m.crs = info.read.crs;
  m.crs_source = info.read.crs_source;
  m.grid_origin = Eigen::Vector2d(info.min.x(), info.min.y());
  const double cols = std::max(1.0, std::ceil((info.max.x() - info.min.x()) / m.tile_size_m));
  const double rows = std::max(1.0, std::ceil((info.max.y() - info.min.y()) / m.tile_size_m));
  if (cols * rows > static_cast<double>(kMaxTiles))
    throw InputError(cloud + ": --tile-size " + formatNumber(m.tile_size_m) + " m gives " +
                     formatNumber(cols * rows) + " tiles over " +
                     formatNumber(info.max.x() - info.min.x(), 4) + " x " +
                     formatNumber(info.max.y() - info.min.y(), 4) + " m, more than " +
                     std::to_string(kMaxTiles) + "; give a larger --tile-size");
  m.columns = static_cast<int>(cols);
  m.rows = static_cast<int>(rows);
}

/// Hands p to its owner's core and to the buffer of every other tile whose closed box
/// [core − b, core + b] holds it.
void place(const Manifest& m, const Vec3& p, std::map<long, Pending>& pending, RawFiles& raw,
           std::size_t flush_at) {
  const double s = m.tile_size_m, b = m.buffer_m;
  const auto [cx, cy] = m.cellOf(p);
  const auto range = [&](double v, double o, int n, int& lo, int& hi) {
    lo = static_cast<int>(std::clamp(std::floor((v - o - b) / s), 0.0, n - 1.0));
    hi = static_cast<int>(std::clamp(std::floor((v - o + b) / s), 0.0, n - 1.0));
  };
  int x0 = 0, x1 = 0, y0 = 0, y1 = 0;
  range(p.x(), m.grid_origin.x(), m.columns, x0, x1);
  range(p.y(), m.grid_origin.y(), m.rows, y0, y1);
  for (int r = y0; r <= y1; ++r) {
    for (int c = x0; c <= x1; ++c) {
      const bool core = c == cx && r == cy;
      if (!core) {
        const double lx = m.grid_origin.x() + c * s - b, hx = lx + s + 2 * b;
        const double ly = m.grid_origin.y() + r * s - b, hy = ly + s + 2 * b;
        if (p.x() < lx || p.x() > hx || p.y() < ly || p.y() > hy) continue;
      }
      const long cell = static_cast<long>(r) * m.columns + c;
      Pending& t = pending[cell];
      std::vector<float>& into = core ? t.core : t.extra;
      push(into, p);
      ++(core ? t.core_count : t.extra_count);
      if (into.size() >= flush_at) raw.append(cell, core, into);
    }
  }
}

/// Stages the cloud of every tile with a core point and lists it in the manifest.
void writeTiles(Manifest& m, const std::map<long, Pending>& pending, const RawFiles& raw,
                const std::string& out_dir, io::StagedOutputs& outputs) {
  for (const auto& [cell, t] : pending) {
    if (t.core_count == 0) continue;  // buffer points only: another tile owns them all
    TileRecord rec;
    rec.index = static_cast<int>(m.tiles.size());
    rec.column = static_cast<int>(cell % m.columns);
    rec.row = static_cast<int>(cell / m.columns);
    rec.core.min = m.grid_origin + m.tile_size_m * Eigen::Vector2d(rec.column, rec.row);
    rec.core.max = rec.core.min + Eigen::Vector2d::Constant(m.tile_size_m);
    rec.buffered.min = rec.core.min - Eigen::Vector2d::Constant(m.buffer_m);
    rec.buffered.max = rec.core.max + Eigen::Vector2d::Constant(m.buffer_m);
    rec.core_points = t.core_count;
    rec.buffer_points = t.extra_count;
    char name[32];
    std::snprintf(name, sizeof name, "tile_%04d", rec.index);
    rec.cloud = std::string(name) + ".pcd";
    rec.out = name;
    PointList points;
    points.reserve(t.core_count + t.extra_count);
    raw.read(cell, true, points);
    raw.read(cell, false, points);
    const std::string path = (fs::path(out_dir) / rec.cloud).string();
    outputs.writeWith(path, [&](const std::string& tmp) {
      io::writeCloudPcdFile(tmp, points, path);
      rec.sha256 = io::sha256File(tmp);
    });
    m.tiles.push_back(std::move(rec));
  }
}

}  // namespace

Manifest tileCloud(const std::string& cloud, const io::CloudReadOptions& read,
                   const TileOptions& options, const std::string& out_dir,
                   io::StagedOutputs& outputs) {
  options.validate();
  io::ensureDirectory(out_dir);
  Manifest m;
  m.input = fs::absolute(cloud).lexically_normal().string();
  m.read = read;
  m.tile_size_m = options.tile_size_m;
  m.buffer_m = options.buffer_m;

  RawFiles raw(out_dir);
  std::map<long, Pending> pending;  // by cell row × columns + column, in that order
  const std::size_t flush_at = 3 * std::max<std::size_t>(16, options.chunk_points / 8);
  bool grid_set = false;
  // The bounds come between streamCloud's two passes, before any point.
  io::streamCloud(
      cloud, read, options.chunk_points,
      [&](const PointList& points) {
        if (!grid_set) throw InputError(cloud + ": internal: the tile grid is not set");
        for (const Vec3& p : points) place(m, p, pending, raw, flush_at);
      },
      [&](const io::CloudStreamInfo& info) {
        setGrid(m, info, cloud);
        grid_set = true;
      });
  for (auto& [cell, t] : pending) {
    raw.append(cell, true, t.core);
    raw.append(cell, false, t.extra);
  }
  writeTiles(m, pending, raw, out_dir, outputs);
  return m;
}

}  // namespace uavip::tiling
