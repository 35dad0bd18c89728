#include "uavip/perception/euclidean_clusters.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <tuple>
#include <utility>

#include "uavip/core/error.h"
#include "uavip/core/key_sort.h"
#include "uavip/core/voxel_key.h"

namespace uavip::perception {
namespace {

/// Union–find over cells (path halving, union by index: deterministic).
class DisjointSets {
 public:
  explicit DisjointSets(std::size_t n) : parent_(n) {
    std::iota(parent_.begin(), parent_.end(), std::size_t{0});
  }
  std::size_t find(std::size_t a) {
    while (parent_[a] != a) {
      parent_[a] = parent_[parent_[a]];
      a = parent_[a];
    }
    return a;
  }
  void unite(std::size_t a, std::size_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<std::size_t> parent_;
};

/// Points sorted by cell; each cell is a run [begin[c], begin[c + 1]) of `order`.
struct CellRuns {
  std::vector<KeyedIndex> order;    ///< (cell key, point index), sorted
  std::vector<std::uint64_t> keys;  ///< occupied cells, ascending
  std::vector<std::size_t> begin;   ///< keys.size() + 1 offsets into order

  /// Index of the cell with `key`, or −1 when it holds no point.
  std::ptrdiff_t cellOf(std::uint64_t key) const {
    const auto it = std::lower_bound(keys.begin(), keys.end(), key);
    return it != keys.end() && *it == key ? it - keys.begin() : -1;
  }
};

CellRuns cellRuns(const PointList& points, const std::vector<int>& indices,
                  const VoxelKeyer& keyer) {
  CellRuns runs;
  auto& order = runs.order;
  order.reserve(indices.size());
  for (const int i : indices) {
    order.emplace_back(keyer.key(points[static_cast<std::size_t>(i)]),
                       static_cast<std::uint32_t>(i));
  }
  sortByKey(order);  // within a cell the input order: the components do not depend on it
  for (std::size_t k = 0; k < order.size(); ++k) {
    if (k == 0 || order[k].first != order[k - 1].first) {
      runs.keys.push_back(order[k].first);
      runs.begin.push_back(k);
    }
  }
  runs.begin.push_back(order.size());
  return runs;
}

/// True when a point of cell a is closer than √tol2 to one of cell b.
bool pointsLinked(const PointList& points, const CellRuns& runs, std::size_t a, std::size_t b,
                  double tol2) {
  for (std::size_t i = runs.begin[a]; i < runs.begin[a + 1]; ++i) {
    const Vec3& p = points[static_cast<std::size_t>(runs.order[i].second)];
    for (std::size_t j = runs.begin[b]; j < runs.begin[b + 1]; ++j) {
      if ((p - points[static_cast<std::size_t>(runs.order[j].second)]).squaredNorm() < tol2)
        return true;
    }
  }
  return false;
}

/// A neighbour cell up to two apart on each axis, with a higher key (each pair of
/// cells is visited once, from its lower key) and closer than the tolerance at its
/// nearest (3 × edge > tolerance: farther cells cannot link).
struct NeighbourOffset {
  int dx, dy, dz;
  bool always_linked;  ///< even the farthest corners are within the tolerance
};

std::vector<NeighbourOffset> neighbourOffsets(double cell, double tol2) {
  std::vector<NeighbourOffset> offsets;
  for (int dx = -2; dx <= 2; ++dx) {
    for (int dy = -2; dy <= 2; ++dy) {
      for (int dz = -2; dz <= 2; ++dz) {
        // Keys are lexicographic in (x, y, z): a higher key is a positive offset.
        if (std::make_tuple(dx, dy, dz) <= std::make_tuple(0, 0, 0)) continue;
        const double gx = std::max(0, std::abs(dx) - 1), gy = std::max(0, std::abs(dy) - 1),
                     gz = std::max(0, std::abs(dz) - 1);
        if ((gx * gx + gy * gy + gz * gz) * cell * cell >= tol2) continue;
        const double fx = std::abs(dx) + 1, fy = std::abs(dy) + 1, fz = std::abs(dz) + 1;
        offsets.push_back({dx, dy, dz, (fx * fx + fy * fy + fz * fz) * cell * cell < tol2});
      }
    }
  }
  return offsets;
}

/// Joins every occupied cell with each occupied neighbour cell (neighbourOffsets) that
/// holds a point within the tolerance of one of its own. Cells are visited in key
/// order, so for one offset the neighbour's key only grows: one cursor per offset
/// walks the sorted keys instead of a binary search per pair.
void linkNeighbours(const PointList& points, const CellRuns& runs, double cell, double tol2,
                    DisjointSets& sets) {
  const std::vector<NeighbourOffset> offsets = neighbourOffsets(cell, tol2);
  const std::vector<std::uint64_t>& keys = runs.keys;
  std::vector<std::size_t> cursor(offsets.size(), 0);
  for (std::size_t a = 0; a < keys.size(); ++a) {
    const auto [ax, ay, az] = VoxelKeyer::unpack(keys[a]);
    for (std::size_t m = 0; m < offsets.size(); ++m) {
      const NeighbourOffset& o = offsets[m];
      const std::int64_t bx = ax + o.dx, by = ay + o.dy, bz = az + o.dz;
      if (bx < 0 || by < 0 || bz < 0 || bx >= VoxelKeyer::kCells || by >= VoxelKeyer::kCells ||
          bz >= VoxelKeyer::kCells) {
        continue;
      }
      const std::uint64_t kb = VoxelKeyer::pack(bx, by, bz);
      std::size_t& b = cursor[m];
      while (b < keys.size() && keys[b] < kb) ++b;
      if (b == keys.size() || keys[b] != kb) continue;
      if (sets.find(a) == sets.find(b)) continue;
      if (o.always_linked || pointsLinked(points, runs, a, b, tol2)) sets.unite(a, b);
    }
  }
}

/// The components' point indices, each sorted, ordered by their smallest index.
std::vector<std::vector<int>> gatherClusters(const CellRuns& runs, DisjointSets& sets) {
  const std::size_t cells = runs.keys.size();
  std::vector<std::vector<int>> by_root(cells);
  for (std::size_t c = 0; c < cells; ++c) {
    auto& dst = by_root[sets.find(c)];
    for (std::size_t k = runs.begin[c]; k < runs.begin[c + 1]; ++k)
      dst.push_back(static_cast<int>(runs.order[k].second));
  }
  std::vector<std::vector<int>> clusters;
  for (auto& c : by_root) {
    if (c.empty()) continue;
    std::sort(c.begin(), c.end());
    clusters.push_back(std::move(c));
  }
  std::sort(clusters.begin(), clusters.end(),
            [](const auto& x, const auto& y) { return x.front() < y.front(); });
  return clusters;
}

}  // namespace

std::vector<std::vector<int>> euclideanClusters(const PointList& points,
                                                const std::vector<int>& indices,
                                                double tolerance_m) {
  requirePositive(tolerance_m, "perception", "cluster tolerance_m");
  if (indices.empty()) return {};
  Vec3 lo = points[static_cast<std::size_t>(indices.front())];
  Vec3 hi = lo;
  for (const int i : indices) {
    lo = lo.cwiseMin(points[static_cast<std::size_t>(i)]);
    hi = hi.cwiseMax(points[static_cast<std::size_t>(i)]);
  }
  // Cell edge: the diagonal equals the tolerance less a hair, so any two points of
  // one cell are strictly closer than it.
  const double cell = tolerance_m / std::sqrt(3.0) * (1.0 - 1e-9);
  const double tol2 = tolerance_m * tolerance_m;
  const VoxelKeyer keyer(lo, hi, cell, "perception.cluster_tolerance_m / sqrt(3)");
  const CellRuns runs = cellRuns(points, indices, keyer);
  DisjointSets sets(runs.keys.size());
  linkNeighbours(points, runs, cell, tol2, sets);
  return gatherClusters(runs, sets);
}

}  // namespace uavip::perception
