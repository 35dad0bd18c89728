#include "uavip/perception/surface_outline.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <deque>
#include <functional>
#include <limits>
#include <string>

#include "uavip/core/error.h"
#include "uavip/core/geometry.h"

namespace uavip::perception {
namespace {

using Vec2 = Eigen::Vector2d;

/// The in-plane axis of the smallest-area rectangle around the hull (one of its edges'
/// directions, turned into [0°, 90°)); ties keep the first edge.
Vec2 rectangleAxis(const std::vector<Vec2>& hull) {
  Vec2 best_axis = Vec2::UnitX();
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < hull.size(); ++i) {
    Vec2 e = hull[(i + 1) % hull.size()] - hull[i];
    if (!(e.norm() > 0.0)) continue;
    e.normalize();
    while (!(e.x() > 0.0 && e.y() >= 0.0)) e = Vec2(e.y(), -e.x());  // quarter turns
    const Vec2 f(-e.y(), e.x());
    double ulo = std::numeric_limits<double>::infinity();
    double uhi = -ulo;
    double vlo = ulo;
    double vhi = -ulo;
    for (const auto& p : hull) {
      ulo = std::min(ulo, p.dot(e));
      uhi = std::max(uhi, p.dot(e));
      vlo = std::min(vlo, p.dot(f));
      vhi = std::max(vhi, p.dot(f));
    }
    const double area = (uhi - ulo) * (vhi - vlo);
    if (area < best * (1.0 - 1e-9)) {
      best = area;
      best_axis = e;
    }
  }
  return best_axis;
}

/// A row-major grid of cells, x fastest.
struct CellGrid {
  int w{0};
  int h{0};
  std::vector<std::uint8_t> on;
  std::uint8_t at(int x, int y) const {
    return x < 0 || y < 0 || x >= w || y >= h ? 0 : on[static_cast<std::size_t>(y) * w + x];
  }
  std::size_t index(int x, int y) const { return static_cast<std::size_t>(y) * w + x; }
};

/// Dilation (grow = true) or erosion by a (2r + 1)² square, separable.
void morph(CellGrid& g, int r, bool grow) {
  std::vector<std::uint8_t> tmp(g.on.size());
  for (int pass = 0; pass < 2; ++pass) {
    for (int y = 0; y < g.h; ++y) {
      for (int x = 0; x < g.w; ++x) {
        std::uint8_t v = grow ? 0 : 1;
        for (int k = -r; k <= r; ++k) {
          const int xx = pass == 0 ? x + k : x;
          const int yy = pass == 0 ? y : y + k;
          const bool inside = xx >= 0 && yy >= 0 && xx < g.w && yy < g.h;
          const std::uint8_t c = inside ? g.on[g.index(xx, yy)] : 0;
          v = grow ? static_cast<std::uint8_t>(v | c) : static_cast<std::uint8_t>(v & c);
        }
        tmp[g.index(x, y)] = v;
      }
    }
    g.on.swap(tmp);
  }
}

/// Labels the connected components of cells whose value equals `value` (4- or
/// 8-connected), in scan order from 1; 0 elsewhere. Returns the component sizes
/// (index = label).
std::vector<std::size_t> label(const CellGrid& g, std::uint8_t value, bool eight,
                               std::vector<int>& labels) {
  labels.assign(g.on.size(), 0);
  std::vector<std::size_t> sizes{0};
  std::deque<std::pair<int, int>> queue;
  for (int y = 0; y < g.h; ++y) {
    for (int x = 0; x < g.w; ++x) {
      if (g.on[g.index(x, y)] != value || labels[g.index(x, y)] != 0) continue;
      const int id = static_cast<int>(sizes.size());
      sizes.push_back(0);
      labels[g.index(x, y)] = id;
      queue.emplace_back(x, y);
      while (!queue.empty()) {
        const auto [cx, cy] = queue.front();
        queue.pop_front();
        ++sizes.back();
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dx = -1; dx <= 1; ++dx) {
            if ((dx == 0 && dy == 0) || (!eight && dx != 0 && dy != 0)) continue;
            const int nx = cx + dx;
            const int ny = cy + dy;
            if (nx < 0 || ny < 0 || nx >= g.w || ny >= g.h) continue;
            const std::size_t i = g.index(nx, ny);
            if (g.on[i] != value || labels[i] != 0) continue;
            labels[i] = id;
            queue.emplace_back(nx, ny);
          }
        }
      }
    }
  }
  return sizes;
}

/// A directed unit edge between lattice corners, the region on its left.
struct Edge {
  std::int64_t from{0};
  std::int64_t to{0};
  int dir{0};  ///< 0 +x, 1 +y, 2 −x, 3 −y
};

/// The closed loops of the region's cell edges, as corner ids; at a corner where two
/// loops touch diagonally the left turn is taken (the region stays 4-connected).
std::vector<std::vector<std::int64_t>> traceLoops(const CellGrid& g) {
  const std::int64_t stride = g.w + 1;
  const auto corner = [&](int x, int y) { return static_cast<std::int64_t>(y) * stride + x; };
  std::vector<Edge> edges;
  for (int y = 0; y < g.h; ++y) {
    for (int x = 0; x < g.w; ++x) {
      if (!g.at(x, y)) continue;
      if (!g.at(x, y - 1)) edges.push_back({corner(x, y), corner(x + 1, y), 0});
      if (!g.at(x + 1, y)) edges.push_back({corner(x + 1, y), corner(x + 1, y + 1), 1});
      if (!g.at(x, y + 1)) edges.push_back({corner(x + 1, y + 1), corner(x, y + 1), 2});
      if (!g.at(x - 1, y)) edges.push_back({corner(x, y + 1), corner(x, y), 3});
    }
  }
  std::sort(edges.begin(), edges.end(), [](const Edge& a, const Edge& b) {
    return a.from != b.from ? a.from < b.from : a.dir < b.dir;
  });
  std::vector<char> used(edges.size(), 0);
  std::vector<std::vector<std::int64_t>> loops;
  for (std::size_t first = 0; first < edges.size(); ++first) {
    if (used[first]) continue;
    std::vector<std::int64_t> loop;
    std::size_t e = first;
    while (true) {
      used[e] = 1;
      loop.push_back(edges[e].from);
      const std::int64_t at = edges[e].to;
      auto it = std::lower_bound(edges.begin(), edges.end(), at,
                                 [](const Edge& a, std::int64_t v) { return a.from < v; });
      std::size_t next = edges.size();
      int best_rank = 4;
      for (; it != edges.end() && it->from == at; ++it) {
        const auto k = static_cast<std::size_t>(it - edges.begin());
        if (used[k] && k != first) continue;
        // left turn first, then straight, then right
        const int rank = ((edges[e].dir - it->dir + 4) % 4 == 3)   ? 0
                         : ((edges[e].dir - it->dir + 4) % 4 == 0) ? 1
                                                                   : 2;
        if (rank < best_rank) {
          best_rank = rank;
          next = k;
        }
      }
      if (next == edges.size() || next == first) break;
      e = next;
    }
    loops.push_back(std::move(loop));
  }
  return loops;
}

/// Drops the corners where a loop goes straight on.
std::vector<Vec2> simplifyLoop(const std::vector<Vec2>& loop) {
  std::vector<Vec2> out;
  const std::size_t n = loop.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2& a = loop[(i + n - 1) % n];
    const Vec2& b = loop[i];
    const Vec2& c = loop[(i + 1) % n];
    const Vec2 u = b - a;
    const Vec2 v = c - b;
    if (std::abs(u.x() * v.y() - u.y() * v.x()) > 1e-12 * (u.norm() * v.norm() + 1e-300))
      out.push_back(b);
  }
  return out;
}

/// The outline of the largest 4-connected region of `g` (cells of edge `cell` from
/// `origin` in the frame ex, ex turned 90°), its openings under `min_hole_m2` filled.
Outline2d outlineOfCells(CellGrid g, const Vec2& origin, double cell, const Vec2& ex,
                         double min_hole_m2) {
  const Vec2 ey(-ex.y(), ex.x());
  Outline2d out;
  // The largest 4-connected region (ties: the first in scan order).
  std::vector<int> labels;
  const std::vector<std::size_t> sizes = label(g, 1, false, labels);
  if (sizes.size() < 2) return out;
  const auto keep =
      static_cast<int>(std::max_element(sizes.begin() + 1, sizes.end()) - sizes.begin());
  for (std::size_t i = 0; i < g.on.size(); ++i) g.on[i] = labels[i] == keep ? 1 : 0;

  // Openings: 8-connected empty components that do not touch the grid's border.
  const std::vector<std::size_t> gaps = label(g, 0, true, labels);
  std::vector<char> outside(gaps.size(), 0);
  for (int x = 0; x < g.w; ++x) {
    outside[static_cast<std::size_t>(labels[g.index(x, 0)])] = 1;
    outside[static_cast<std::size_t>(labels[g.index(x, g.h - 1)])] = 1;
  }
  for (int y = 0; y < g.h; ++y) {
    outside[static_cast<std::size_t>(labels[g.index(0, y)])] = 1;
    outside[static_cast<std::size_t>(labels[g.index(g.w - 1, y)])] = 1;
  }
  for (std::size_t i = 0; i < g.on.size(); ++i) {
    const auto l = static_cast<std::size_t>(labels[i]);
    if (g.on[i] == 0 && !outside[l] && static_cast<double>(gaps[l]) * cell * cell < min_hole_m2) {
      g.on[i] = 1;
    }
  }
  std::size_t occupied = 0;
  for (const auto v : g.on) occupied += v;
  out.area_m2 = static_cast<double>(occupied) * cell * cell;

  const std::int64_t stride = g.w + 1;
  double best_outer = 0.0;
  for (const auto& ids : traceLoops(g)) {
    std::vector<Vec2> loop;
    loop.reserve(ids.size());
    for (const auto id : ids) {
      const std::int64_t column = id % stride;
      const std::int64_t row = id / stride;  // corner ids are row-major
      const double x = origin.x() + static_cast<double>(column) * cell;
      const double y = origin.y() + static_cast<double>(row) * cell;
      loop.push_back(x * ex + y * ey);
    }
    loop = simplifyLoop(loop);
    if (loop.size() < 3) continue;
    const double a2 = polygonTwiceSignedArea2d(loop);
    if (a2 > 0.0) {
      if (a2 > best_outer) {  // one region: one outer loop
        best_outer = a2;
        out.outer = std::move(loop);
      }
    } else {
      out.holes.push_back(std::move(loop));
    }
  }
  return out;
}

}  // namespace

void OutlineOptions::validate(const std::string& where) const {
  requirePositive(cell_m, where, "cell_m");
  requireThat(close_cells >= 0 && close_cells <= 64, where, "close_cells", "in [0, 64]",
              static_cast<double>(close_cells));
  requireThat(std::isfinite(min_hole_m2) && min_hole_m2 >= 0.0, where, "min_hole_m2", ">= 0",
              min_hole_m2);
  requireThat(max_cells >= 16, where, "max_cells", ">= 16", static_cast<double>(max_cells));
}

Outline2d occupiedOutline2d(const std::vector<Vec2>& uv, const OutlineOptions& options) {
  options.validate();
  Outline2d out;
  if (uv.size() < 3) return out;
  const std::vector<Vec2> hull = convexHull2d(uv);
  if (hull.size() < 3) return out;
  const Vec2 ex = rectangleAxis(hull);
  const Vec2 ey(-ex.y(), ex.x());

  Vec2 lo = Vec2::Constant(std::numeric_limits<double>::infinity());
  Vec2 hi = -lo;
  for (const auto& p : uv) {
    const Vec2 q(p.dot(ex), p.dot(ey));
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  }
  const int pad = options.close_cells + 1;
  double cell = options.cell_m;
  // ⌈extent / cell⌉ cells (at least 1): the outline reaches at most half a cell past
  // the outermost points, and not at all when the extent is a whole number of cells.
  const auto cellsAlong = [&](double extent) {
    return std::max(1.0, std::ceil(extent / cell - 1e-9));
  };
  while ((cellsAlong(hi.x() - lo.x()) + 2.0 * pad) * (cellsAlong(hi.y() - lo.y()) + 2.0 * pad) >
         static_cast<double>(options.max_cells)) {
    cell *= 2.0;
  }
  const int nx = static_cast<int>(cellsAlong(hi.x() - lo.x()));
  const int ny = static_cast<int>(cellsAlong(hi.y() - lo.y()));
  // The cells are centred on the extent, so each side of it reaches equally far out.
  const Vec2 origin(lo.x() - 0.5 * (nx * cell - (hi.x() - lo.x())) - pad * cell,
                    lo.y() - 0.5 * (ny * cell - (hi.y() - lo.y())) - pad * cell);
  CellGrid g;
  g.w = nx + 2 * pad;
  g.h = ny + 2 * pad;
  g.on.assign(static_cast<std::size_t>(g.w) * static_cast<std::size_t>(g.h), 0);
  for (const auto& p : uv) {
    const int x = std::clamp(static_cast<int>(std::floor((p.dot(ex) - origin.x()) / cell)), pad,
                             pad + nx - 1);
    const int y = std::clamp(static_cast<int>(std::floor((p.dot(ey) - origin.y()) / cell)), pad,
                             pad + ny - 1);
    g.on[g.index(x, y)] = 1;
  }
  if (options.close_cells > 0) {
    morph(g, options.close_cells, true);
    morph(g, options.close_cells, false);
  }

  return outlineOfCells(std::move(g), origin, cell, ex, options.min_hole_m2);
}

Outline2d rasterOutline2d(const std::function<bool(const Vec2&)>& inside, const Vec2& lo,
                          const Vec2& hi, const Vec2& axis, double cell_m, double min_hole_m2) {
  requirePositive(cell_m, "outline", "cell_m");
  const Vec2 ex = axis.normalized();
  const Vec2 ey(-ex.y(), ex.x());
  const int nx = static_cast<int>(std::ceil((hi.x() - lo.x()) / cell_m)) + 1;
  const int ny = static_cast<int>(std::ceil((hi.y() - lo.y()) / cell_m)) + 1;
  if (!(nx > 0 && ny > 0) || static_cast<double>(nx) * ny > 2e7)
    throw InputError("outline: a raster of " + std::to_string(nx) + " x " + std::to_string(ny) +
                     " cells is too large; use a coarser cell");
  CellGrid g;
  g.w = nx + 2;
  g.h = ny + 2;
  g.on.assign(static_cast<std::size_t>(g.w) * static_cast<std::size_t>(g.h), 0);
  const Vec2 origin = lo - Vec2::Constant(cell_m);
  for (int y = 0; y < g.h; ++y) {
    for (int x = 0; x < g.w; ++x) {
      const Vec2 c(origin.x() + (x + 0.5) * cell_m, origin.y() + (y + 0.5) * cell_m);
      g.on[g.index(x, y)] = inside(c.x() * ex + c.y() * ey) ? 1 : 0;
    }
  }
  return outlineOfCells(std::move(g), origin, cell_m, ex, min_hole_m2);
}

}  // namespace uavip::perception
