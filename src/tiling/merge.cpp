#include "uavip/tiling/merge.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <memory>
#include <numeric>

#include "uavip/core/error.h"
#include "uavip/core/geometry.h"
#include "uavip/core/math.h"
#include "uavip/core/neighbour_index.h"
#include "uavip/core/text.h"
#include "uavip/core/union_find.h"
#include "uavip/core/voxel_key.h"

namespace uavip::tiling {
namespace {

/// A surface or obstacle of one tile, cut to the points its tile owns.
struct Part {
  std::size_t tile{0};  ///< position in the tiles given
  int id{0};            ///< id in its tile
  bool whole{true};     ///< no point was cut away
  const Surface* surface{nullptr};
  PointList points;  ///< owned points [m]
  Aabb box;
  std::unique_ptr<NeighbourIndex> index;  ///< built when first needed
};

/// True when `p` lies in the core of tile `t` (the owner rule of the manifest).
bool owns(const Manifest& m, const TileRecord& t, const Vec3& p) {
  const auto [c, r] = m.cellOf(p);
  return c == t.column && r == t.row;
}

/// True when some point of b comes within `gap` of a point of a.
bool touches(Part& a, const Part& b, double gap) {
  Aabb grown = a.box;
  grown.min -= Vec3::Constant(gap);
  grown.max += Vec3::Constant(gap);
  if ((grown.min.array() > b.box.max.array()).any() ||
      (grown.max.array() < b.box.min.array()).any())
    return false;
  if (!a.index) a.index = std::make_unique<NeighbourIndex>(a.points);
  const float gap2 = static_cast<float>(gap * gap);
  for (const Vec3& q : b.points) {
    if (q.x() < grown.min.x() || q.x() > grown.max.x() || q.y() < grown.min.y() ||
        q.y() > grown.max.y() || q.z() < grown.min.z() || q.z() > grown.max.z())
      continue;
    float d2 = 0.0F;
    a.index->nearestTo(q, &d2);
    if (d2 <= gap2) return true;
  }
  return false;
}

/// True when two surface parts lie on one plane within the thresholds.
bool samePlane(const Surface& a, const Surface& b, const MergeOptions& o) {
  if (a.plane.normal.dot(b.plane.normal) < std::cos(o.max_angle_deg * kPi / 180.0)) return false;
  return std::abs(a.plane.signedDistance(b.centroid)) <= o.planes.distance_threshold_m &&
         std::abs(b.plane.signedDistance(a.centroid)) <= o.planes.distance_threshold_m;
}

/// A surface refitted to `points`: PCA plane with the normal on the side of `like`,
/// in-plane axes, boundary as the detector draws it (o.planes.boundary; counter-clockwise seen
/// from the normal, holes clockwise), areas.
Surface refit(PointList points, const Vec3& like, const MergeOptions& o) {
  Surface s;
  Vec3 c = Vec3::Zero();
  for (const Vec3& p : points) c += p;
  c /= static_cast<double>(points.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const Vec3& p : points) cov += (p - c) * (p - c).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  Vec3 n = eig.eigenvectors().col(0).normalized();
  if (n.dot(like) < 0.0) n = -n;
  const Vec3 major = eig.eigenvectors().col(2);
  Vec3 u = major - major.dot(n) * n;
  u = u.norm() > 1e-12 ? u.normalized() : n.unitOrthogonal();
  s.centroid = c;
  s.plane.normal = n;
  s.plane.offset = -n.dot(c);
  s.axis_u = u;
  s.axis_v = n.cross(u);
  std::vector<Eigen::Vector2d> uv;
  PointList flat;
  uv.reserve(points.size());
  flat.reserve(points.size());
  for (const Vec3& p : points) {
    const Vec3 d = p - c;
    uv.emplace_back(s.axis_u.dot(d), s.axis_v.dot(d));
    flat.emplace_back(uv.back().x(), uv.back().y(), 0.0);
  }
  const auto to3d = [&](const std::vector<Eigen::Vector2d>& loop) {
    PointList out;
    out.reserve(loop.size());
    for (const auto& q : loop) out.push_back(c + q.x() * s.axis_u + q.y() * s.axis_v);
    return out;
  };
  if (o.planes.boundary == "convex") {
    s.boundary = to3d(convexHull2d(uv));
    s.area_m2 = polygonArea(s.boundary);
  } else {
    const perception::Outline2d outline =
        perception::occupiedOutline2d(uv, o.planes.outlineOptions());
    s.boundary = to3d(outline.outer);
    for (const auto& h : outline.holes) s.holes.push_back(to3d(h));
    s.area_m2 = outline.area_m2;
  }
  const double cell = o.planes.cell_size_m;
  const auto cells = static_cast<double>(
      occupiedKeys(flat, VoxelKeyer::forPoints(flat, cell, "the merge's area cell")).size());
  s.density_area_m2 = cells * cell * cell;
  s.inliers = std::move(points);
  return s;
}

/// Joins parts of neighbouring tiles that `joinable` accepts and that touch.
template <typename Joinable>
UnionFind groupParts(std::vector<Part>& parts, const std::vector<TileScene>& tiles, double gap,
                     Joinable joinable, int& joined) {
  UnionFind g(parts.size());
  for (std::size_t i = 0; i < parts.size(); ++i) {
    for (std::size_t j = i + 1; j < parts.size(); ++j) {
      const TileRecord& a = tiles[parts[i].tile].tile;
      const TileRecord& b = tiles[parts[j].tile].tile;
      if (parts[i].tile == parts[j].tile || std::abs(a.column - b.column) > 1 ||
          std::abs(a.row - b.row) > 1)
        continue;
      if (g.find(i) == g.find(j) || !joinable(parts[i], parts[j])) continue;
      if (touches(parts[i], parts[j], gap)) {
        g.join(i, j);
        ++joined;
      }
    }
  }
  return g;
}

/// The parts of each group, in part order (groups ordered by their first part).
std::vector<std::vector<std::size_t>> members(UnionFind& g, std::size_t n) {
  std::vector<std::vector<std::size_t>> out;
  std::vector<long> slot(n, -1);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t root = g.find(i);
    if (slot[root] < 0) {
      slot[root] = static_cast<long>(out.size());
      out.emplace_back();
    }
    out[static_cast<std::size_t>(slot[root])].push_back(i);
  }
  return out;
}

Obstacle makeObstacle(PointList points, int id) {
  Obstacle o;
  o.id = id;
  const Aabb box = boundingBox(points);
  o.aabb_min = box.min;
  o.aabb_max = box.max;
  o.points = std::move(points);
  return o;
}

}  // namespace

void MergeOptions::validate(const std::string& where) const {
  planes.validate(where);
  if (!(max_angle_deg > 0.0 && max_angle_deg < 90.0))
    throw InputError(where + ": max_angle_deg must be in (0, 90), got " +
                     formatNumber(max_angle_deg));
}

namespace {

/// The tile's surfaces and obstacles cut to its core, appended to the parts.
void cutTile(const Manifest& manifest, const TileScene& ts, std::size_t t,
             std::vector<Part>& surfaces, std::vector<Part>& obstacles, MergeStats& st) {
  const auto cut = [&](const PointList& points, Part& part) {
    for (const Vec3& p : points) {
      if (owns(manifest, ts.tile, p)) {
        part.points.push_back(p);
        part.box.extend(p);
      }
    }
    part.whole = part.points.size() == points.size();
  };
  for (const Surface& s : ts.scene.surfaces) {
    ++st.surface_parts;
    Part part;
    part.tile = t;
    part.id = s.id;
    part.surface = &s;
    cut(s.inliers, part);
    if (part.points.empty()) {
      ++st.surfaces_dropped;
      continue;
    }
    surfaces.push_back(std::move(part));
  }
  for (const Obstacle& o : ts.scene.obstacles) {
    ++st.obstacle_parts;
    Part part;
    part.tile = t;
    part.id = o.id;
    cut(o.points, part);
    if (!part.points.empty()) obstacles.push_back(std::move(part));
  }
}

/// Adds tile t's owned safety points (and, with keep_buffer_safety, those of cores not
/// given, each by the first given tile whose box holds it).
void addSafety(const Manifest& manifest, const std::vector<TileScene>& tiles, std::size_t t,
               const MergeOptions& options, Scene& out) {
  const TileScene& ts = tiles[t];
  if (!ts.scene.safety) return;
  const SafetyCloud& sc = *ts.scene.safety;
  if (!out.safety) {
    out.safety = SafetyCloud{};
    out.safety->source = manifest.input;
    out.safety->sha256 = manifest.input_sha256;
    out.safety->input_points = manifest.input_points;
  }
  out.safety->cell_m = std::max(out.safety->cell_m, sc.cell_m);
  out.safety->margin_m = std::max(out.safety->margin_m, sc.margin_m);
  out.safety->perception_dropped += sc.perception_dropped;
  for (const Vec3& p : sc.points) {
    if (owns(manifest, ts.tile, p)) {
      out.safety->points.push_back(p);
    } else if (options.keep_buffer_safety) {
      const auto [c, r] = manifest.cellOf(p);
      bool given = false, earlier = false;
      for (std::size_t u = 0; u < tiles.size() && !given; ++u) {
        given = tiles[u].tile.column == c && tiles[u].tile.row == r;
        earlier = earlier || (u < t && tiles[u].tile.buffered.contains(p));
      }
      if (!given && !earlier) out.safety->points.push_back(p);
    }
  }
}

/// The joined surfaces into out.surfaces; those too small once cut into `demoted`.
void joinSurfaces(std::vector<Part>& surfaces, const std::vector<TileScene>& tiles,
                  const MergeOptions& options, Scene& out, std::vector<PointList>& demoted,
                  MergeStats& st) {
  UnionFind sg = groupParts(
      surfaces, tiles, options.planes.cluster_tolerance_m,
      [&](const Part& a, const Part& b) { return samePlane(*a.surface, *b.surface, options); },
      st.surfaces_joined);
  for (const auto& group : members(sg, surfaces.size())) {
    const Part& lead = surfaces[group.front()];
    Surface s;
    if (group.size() == 1 && lead.whole) {
      s = *lead.surface;  // untouched by the cut: as the tile detected it
    } else {
      PointList points;
      const Part* largest_part = &lead;
      for (const std::size_t i : group) {
        points.insert(points.end(), surfaces[i].points.begin(), surfaces[i].points.end());
        if (surfaces[i].points.size() > largest_part->points.size()) largest_part = &surfaces[i];
      }
      s = refit(std::move(points), largest_part->surface->plane.normal, options);
      if (std::min(s.area_m2, s.density_area_m2) < options.planes.min_area_m2) {
        ++st.surfaces_demoted;
        demoted.push_back(std::move(s.inliers));
        continue;
      }
    }
    s.id = static_cast<int>(out.surfaces.size());
    out.surfaces.push_back(std::move(s));
  }
}

}  // namespace

Scene mergeTileScenes(const Manifest& manifest, const std::vector<TileScene>& tiles,
                      const MergeOptions& options, MergeStats* stats) {
  options.validate();
  MergeStats st;
  std::vector<Part> surfaces, obstacles;
  Scene out;
  const CloudStats* largest = nullptr;
  std::uint64_t owned = 0;
  for (std::size_t t = 0; t < tiles.size(); ++t) {
    cutTile(manifest, tiles[t], t, surfaces, obstacles, st);
    addSafety(manifest, tiles, t, options, out);
    owned += tiles[t].tile.core_points;
    const auto& measured = tiles[t].scene.measured;
    if (measured && (largest == nullptr || measured->points > largest->points))
      largest = &*measured;
  }
  std::vector<PointList> demoted;
  joinSurfaces(surfaces, tiles, options, out, demoted, st);
  UnionFind og = groupParts(
      obstacles, tiles, options.planes.cluster_tolerance_m,
      [](const Part&, const Part&) { return true; }, st.obstacles_joined);
  for (const auto& group : members(og, obstacles.size())) {
    PointList points;
    for (const std::size_t i : group)
      points.insert(points.end(), obstacles[i].points.begin(), obstacles[i].points.end());
    out.obstacles.push_back(
        makeObstacle(std::move(points), static_cast<int>(out.obstacles.size())));
  }
  for (PointList& points : demoted)
    out.obstacles.push_back(
        makeObstacle(std::move(points), static_cast<int>(out.obstacles.size())));

  for (const Surface& s : out.surfaces)
    out.cloud.insert(out.cloud.end(), s.inliers.begin(), s.inliers.end());
  for (const Obstacle& o : out.obstacles)
    out.cloud.insert(out.cloud.end(), o.points.begin(), o.points.end());
  if (largest != nullptr && !out.cloud.empty()) {
    // The largest tile's spacing and noise; the points and box of what is merged.
    CloudStats m = *largest;
    const Aabb box = boundingBox(out.cloud);
    m.points = static_cast<std::size_t>(owned);
    m.min = box.min;
    m.max = box.max;
    m.extent_m = box.max - box.min;
    out.measured = m;
  }
  st.safety_points = out.safety ? out.safety->points.size() : 0;
  if (stats != nullptr) *stats = st;
  return out;
}

}  // namespace uavip::tiling
