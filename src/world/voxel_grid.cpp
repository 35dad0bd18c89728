#include "uavip/world/voxel_grid.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <iomanip>
#include <limits>
#include <mutex>
#include <sstream>

#include "uavip/core/error.h"
#include "uavip/core/memory.h"
#include "uavip/core/text.h"

namespace uavip::world {

namespace {

constexpr std::uint8_t kFree = 0;
constexpr std::uint8_t kInflated = 1;
constexpr std::uint8_t kOccupied = 2;

/// Largest |index| produced by indexOf; keeps int arithmetic on neighbours safe.
constexpr double kIndexLimit = 1.0e9;

int toIndex(double v) {
  if (std::isnan(v)) return -1;
  return static_cast<int>(std::clamp(std::floor(v), -kIndexLimit, kIndexLimit));
}

/// Integer offsets (in voxels) whose centre distance is within `radius_vox` voxels.
std::vector<Index3> sphereOffsets(double radius_vox) {
  // A tiny slack makes the test conservative (blocks a voxel exactly on the sphere).
  const double r2 = radius_vox * radius_vox * (1.0 + 1e-12) + 1e-9;
  const int n = static_cast<int>(std::floor(radius_vox + 1e-9));
  std::vector<Index3> out;
  for (int dz = -n; dz <= n; ++dz) {
    for (int dy = -n; dy <= n; ++dy) {
      for (int dx = -n; dx <= n; ++dx) {
        const double d2 = static_cast<double>(dx * dx + dy * dy + dz * dz);
        if (d2 <= r2) out.push_back({dx, dy, dz});
      }
    }
  }
  return out;
}

/// Bytes per voxel: the blocked state (1) and the component labels (on first use, 12
/// bytes a run of free voxels; counted as 4 a voxel, which holds for runs ≥ 3 long).
constexpr double kBytesPerVoxel = 5.0;

/// The dense grid over [lo, hi] at options.resolution_m: its origin (on a multiple of
/// the resolution) and dims; returns the voxel count. Throws InputError, before
/// anything is allocated, when the count exceeds options.max_voxels, naming the
/// count, the memory it would take and grid.resolution_m, the key to change.
double gridShape(const Vec3& lo, const Vec3& hi, const GridOptions& options, Vec3& origin,
                 std::array<int, 3>& dims) {
  const double res = options.resolution_m;
  constexpr int kMaxCells = std::numeric_limits<int>::max() / 2;  // voxels per axis, at most
  double count = 1.0;
  for (int a = 0; a < 3; ++a) {
    const double o = std::floor(lo[a] / res) * res;
    origin[a] = o;
    const double n = std::max(1.0, std::ceil((hi[a] - o) / res));
    count *= n;
    if (n > static_cast<double>(kMaxCells)) count = std::numeric_limits<double>::infinity();
    dims[static_cast<std::size_t>(a)] = static_cast<int>(std::min(n, 1.0e9));
  }
  if (!(count <= static_cast<double>(options.max_voxels))) {
    const Vec3 extent = hi - lo;
    // The finest resolution whose grid fits max_voxels.
    const double fits =
        std::cbrt(extent.x() * extent.y() * extent.z() / static_cast<double>(options.max_voxels));
    std::ostringstream os;
    os << "grid: " << dims[0] << " x " << dims[1] << " x " << dims[2] << " = "
       << std::setprecision(3) << count << " voxels (" << count * kBytesPerVoxel / 1e9
       << " GB) exceeds max_voxels = " << options.max_voxels << " (extent " << extent.x() << " x "
       << extent.y() << " x " << extent.z() << " m at resolution_m = " << res
       << "); set grid.resolution_m >= " << std::ceil(fits * 1000.0) / 1000.0
       << " (or leave it out: auto), reduce padding_m or crop the cloud, or raise max_voxels";
    throw InputError(os.str());
  }
  requireMemory(
      count * kBytesPerVoxel,
      "the planning grid's " + formatNumber(count, 3) + " voxels of " + formatNumber(res) + " m",
      "set a larger grid.resolution_m, reduce padding_m or crop the cloud");
  return count;
}

}  // namespace

void VoxelGrid::requireFits(const Aabb& region, const GridOptions& options) {
  options.validate("grid");
  Vec3 origin;
  std::array<int, 3> dims{};
  gridShape(region.min.array() - options.padding_m, region.max.array() + options.padding_m, options,
            origin, dims);
}

void GridOptions::validate(const std::string& where) const {
  table().check(*this, where);
  if (!(std::isfinite(inflation_radius_m) && inflation_radius_m >= 0.0)) {
    std::ostringstream os;
    os << "inflation_radius_m must be >= 0, got " << inflation_radius_m;
    require(false, where, os.str());
  }
  require(max_voxels > 0, where, "max_voxels must be > 0, got 0");
}

const params::Table<GridOptions>& GridOptions::table() {
  static const params::Table<GridOptions> t = [] {
    using O = GridOptions;
    params::Table<O> p;
    p.add("resolution_m", &O::resolution_m,
          "voxel edge of the planning grid (paper: 0.2 m); a grid over max_voxels is refused")
        .unitIs("m")
        .positive()
        .mayBeAuto();
    p.add("padding_m", &O::padding_m, "free margin around the cloud's bounds")
        .unitIs("m")
        .atLeast(0);
    return p;
  }();
  return t;
}

VoxelGrid VoxelGrid::build(const std::vector<const PointList*>& clouds, const GridOptions& options,
                           const Aabb& region) {
  require(!region.empty() && region.min.allFinite() && region.max.allFinite(), "grid",
          "the region is empty");
  options.validate("grid");
  const Vec3 lo = region.min.array() - options.padding_m;
  const Vec3 hi = region.max.array() + options.padding_m;
  return buildWithin(clouds, lo, hi, options);
}

VoxelGrid VoxelGrid::build(const PointList& cloud, const PointList& extra,
                           const GridOptions& options) {
  options.validate("grid");
  require(allFinite(cloud), "grid", "the cloud contains a non-finite coordinate");
  require(allFinite(extra), "grid",
          "an extra point (e.g. a photo stop) has a non-finite coordinate");
  Aabb box = boundingBox(cloud);
  for (const auto& p : extra) box.extend(p);
  if (box.empty()) box.extend(Vec3::Zero());  // nothing to cover: a padded box around the origin
  return buildWithin({&cloud}, box.min.array() - options.padding_m,
                     box.max.array() + options.padding_m, options);
}

VoxelGrid VoxelGrid::buildWithin(const std::vector<const PointList*>& clouds, const Vec3& lo,
                                 const Vec3& hi, const GridOptions& options) {
  static std::atomic<std::uint64_t> last_id{0};
  VoxelGrid g;
  g.content_id_ = ++last_id;
  g.reach_cache_ = std::make_shared<ReachCache>();
  g.options_ = options;

  // The origin sits on a multiple of the resolution so that OctoMap's leaves (whose
  // boundaries are multiples of the resolution) coincide with the dense voxels.
  const double count = gridShape(lo, hi, options, g.origin_, g.dims_);
  g.blocked_.assign(static_cast<std::size_t>(count), kFree);
  for (const PointList* cloud : clouds) g.markOccupied(*cloud);
  g.inflate();
  g.blocked_count_ = static_cast<std::size_t>(std::count_if(
      g.blocked_.begin(), g.blocked_.end(), [](std::uint8_t v) { return v != kFree; }));
  return g;
}

void VoxelGrid::markOccupied(const PointList& cloud) {
  // Every measured point's own voxel (the safety argument above needs no more). An
  // OctoMap OcTree used to sit in between: its leaves, aligned to OctoMap's origin and
  // not the grid's, marked up to 8 voxels a point (docs/architecture_notes.md, "The grid
  // without the OctoMap detour"); the FCL world keeps its octree.
  for (const auto& p : cloud) {
    const Index3 i = indexOf(p);
    if (inBounds(i)) blocked_[linear(i)] = kOccupied;
  }
}

std::vector<Index3> VoxelGrid::occupiedSeeds() {
  const int nx = dims_[0], ny = dims_[1], nz = dims_[2];
  auto occupiedAt = [&](int x, int y, int z) {
    return x >= 0 && y >= 0 && z >= 0 && x < nx && y < ny && z < nz &&
           blocked_[linear({x, y, z})] == kOccupied;
  };
  std::vector<Index3> seeds;
  for (int z = 0; z < nz; ++z) {
    for (int y = 0; y < ny; ++y) {
      for (int x = 0; x < nx; ++x) {
        if (blocked_[linear({x, y, z})] != kOccupied) continue;
        ++occupied_count_;
        // An occupied voxel whose six face neighbours are occupied adds nothing: every
        // offset point at distance >= 1 voxel is at least as close to one of them.
        const bool interior = occupiedAt(x - 1, y, z) && occupiedAt(x + 1, y, z) &&
                              occupiedAt(x, y - 1, z) && occupiedAt(x, y + 1, z) &&
                              occupiedAt(x, y, z - 1) && occupiedAt(x, y, z + 1);
        if (!interior) seeds.push_back({x, y, z});
      }
    }
  }
  return seeds;
}

void VoxelGrid::inflate() {
  // The sphere as x-runs: for each (dy, dz) of the disc, the half-width w of its row.
  struct RowOffset {
    int dy, dz, w;
  };
  std::vector<RowOffset> rows;
  for (const auto& o : sphereOffsets(effectiveInflation() / options_.resolution_m)) {
    if (rows.empty() || rows.back().dy != o.y || rows.back().dz != o.z) {
      rows.push_back({o.y, o.z, -o.x});  // offsets run dx ascending: the first is −w
    }
  }
  const std::vector<Index3> seeds = occupiedSeeds();  // z, then y, then x ascending
  const int nx = dims_[0];
  std::uint8_t* const cells = blocked_.data();
  // Seeds of one (y, z) row stamp each target row with the union of their runs
  // [x − w, x + w]: overlapping runs are merged before they are written.
  for (std::size_t b = 0; b < seeds.size();) {
    std::size_t e = b;
    while (e < seeds.size() && seeds[e].y == seeds[b].y && seeds[e].z == seeds[b].z) ++e;
    for (const auto& r : rows) {
      const Index3 row{0, seeds[b].y + r.dy, seeds[b].z + r.dz};
      if (!inBounds(row)) continue;
      std::uint8_t* const line = cells + linear(row);
      const auto fill = [&](int x0, int x1) {
        for (int x = std::max(0, x0); x <= std::min(nx - 1, x1); ++x)
          line[x] = line[x] == kFree ? kInflated : line[x];
      };
      int x0 = seeds[b].x - r.w, x1 = seeds[b].x + r.w;
      for (std::size_t k = b + 1; k < e; ++k) {
        if (seeds[k].x - r.w > x1 + 1) {
          fill(x0, x1);
          x0 = seeds[k].x - r.w;
        }
        x1 = seeds[k].x + r.w;
      }
      fill(x0, x1);
    }
    b = e;
  }
}

double VoxelGrid::effectiveInflation() const {
  return options_.inflation_radius_m + std::sqrt(3.0) * options_.resolution_m;
}

Index3 VoxelGrid::indexOf(const Vec3& p) const {
  const double res = options_.resolution_m;
  return {toIndex((p.x() - origin_.x()) / res), toIndex((p.y() - origin_.y()) / res),
          toIndex((p.z() - origin_.z()) / res)};
}

Vec3 VoxelGrid::centreOf(const Index3& i) const {
  const double res = options_.resolution_m;
  return origin_ + res * Vec3(i.x + 0.5, i.y + 0.5, i.z + 0.5);
}

bool VoxelGrid::isOccupied(const Index3& i) const {
  return inBounds(i) && blocked_[linear(i)] == kOccupied;
}

Aabb VoxelGrid::bounds() const {
  Aabb box;
  box.min = origin_;
  box.max = origin_ + Vec3(dims_[0], dims_[1], dims_[2]) * resolution();
  return box;
}

bool VoxelGrid::segmentFree(const Vec3& a, const Vec3& b) const {
  // Stricter than sampling: every voxel the segment passes through (3D DDA,
  // Amanatides & Woo) must be free, which includes every sample spaced <= res. A
  // point inside a free voxel is within (√3/2)·res of its free centre, which the
  // file comment's argument needs; plain sampling could cut a blocked corner.
  if (!a.allFinite() || !b.allFinite()) return false;
  Index3 cur = indexOf(a);
  const Index3 last = indexOf(b);
  if (isBlocked(cur) || isBlocked(last)) return false;
  const double res = options_.resolution_m;
  const Vec3 d = b - a;
  int step[3];
  double t_max[3];
  double t_delta[3];
  int* c[3] = {&cur.x, &cur.y, &cur.z};
  for (int k = 0; k < 3; ++k) {
    const double dk = d[k];
    if (dk > 0.0) {
      step[k] = 1;
      const double boundary = origin_[k] + (*c[k] + 1) * res;
      t_max[k] = (boundary - a[k]) / dk;
      t_delta[k] = res / dk;
    } else if (dk < 0.0) {
      step[k] = -1;
      const double boundary = origin_[k] + (*c[k]) * res;
      t_max[k] = (boundary - a[k]) / dk;
      t_delta[k] = -res / dk;
    } else {
      step[k] = 0;
      t_max[k] = std::numeric_limits<double>::infinity();
      t_delta[k] = std::numeric_limits<double>::infinity();
    }
  }
  // At most |Δx|+|Δy|+|Δz| steps (plus slack for rounding at the last voxel).
  const long long budget = std::llabs(static_cast<long long>(last.x) - cur.x) +
                           std::llabs(static_cast<long long>(last.y) - cur.y) +
                           std::llabs(static_cast<long long>(last.z) - cur.z) + 3;
  for (long long n = 0; n < budget && cur != last; ++n) {
    int k = 0;
    if (t_max[1] < t_max[k]) k = 1;
    if (t_max[2] < t_max[k]) k = 2;
    if (t_max[k] > 1.0) break;  // rounding: the end lies in the current voxel's closure
    *c[k] += step[k];
    t_max[k] += t_delta[k];
    if (isBlocked(cur)) return false;
  }
  // Sample check as well (the header's contract), spaced <= res, both ends included.
  const double len = d.norm();
  const int samples = static_cast<int>(std::ceil(len / res));
  for (int s = 1; s < samples; ++s) {
    if (isBlocked(indexOf(a + d * (static_cast<double>(s) / samples)))) return false;
  }
  return true;
}

namespace {

/// Union-find root with path halving.
std::uint32_t findRoot(std::vector<std::uint32_t>& parent, std::uint32_t i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

/// Joins two sets; the smaller run index becomes the root.
void unite(std::vector<std::uint32_t>& parent, std::uint32_t a, std::uint32_t b) {
  a = findRoot(parent, a);
  b = findRoot(parent, b);
  if (a < b)
    parent[b] = a;
  else if (b < a)
    parent[a] = b;
}

}  // namespace

struct VoxelGrid::ReachCache {
  /// A run of free voxels along x in one row (fixed y, z): x0 … x1 inclusive. Nested
  /// here, not in an anonymous namespace: a unity build includes this file, and GCC's
  /// -Wsubobject-linkage rejects a header-declared class with a field of such a type.
  struct Run {
    int x0, x1;
  };
  std::mutex mutex;
  bool labelled{false};
  /// The free runs along x, row by row (row r = y + ny·z holds runs row_start[r] …
  /// row_start[r + 1] − 1), and the 26-connected component of each (1, 2, … in the
  /// order of their first voxel); filled on the first call. 12 bytes a run, not 4 a
  /// voxel: no label array the size of the grid to fill.
  std::vector<Run> runs;
  std::vector<std::size_t> row_start;
  std::vector<std::int32_t> run_label;
};

void VoxelGrid::labelComponents(ReachCache& cache) const {
  // Union-find over runs of free voxels along x. Two runs in rows whose y and z
  // differ by at most one are 26-connected exactly when their x ranges, each grown
  // by one voxel, overlap; within a row a run is connected by construction. Each
  // row is joined to its four earlier neighbour rows, so every pair is seen once.
  const int nx = dims_[0], ny = dims_[1], nz = dims_[2];
  const std::size_t rows = static_cast<std::size_t>(ny) * static_cast<std::size_t>(nz);
  std::vector<ReachCache::Run>& runs = cache.runs;
  std::vector<std::size_t>& row_start = cache.row_start;
  runs.clear();
  row_start.assign(rows + 1, 0);
  for (std::size_t r = 0; r < rows; ++r) {
    const std::uint8_t* row = blocked_.data() + r * static_cast<std::size_t>(nx);
    for (int x = 0; x < nx;) {
      if (row[x] != kFree) {
        ++x;
        continue;
      }
      const int x0 = x;
      while (x < nx && row[x] == kFree) ++x;
      runs.push_back({x0, x - 1});
    }
    row_start[r + 1] = runs.size();
  }
  require(runs.size() < std::numeric_limits<std::uint32_t>::max(), "grid",
          "too many free runs to label");
  std::vector<std::uint32_t> parent(runs.size());
  for (std::uint32_t i = 0; i < parent.size(); ++i) parent[i] = i;
  auto joinRows = [&](std::size_t ra, std::size_t rb) {
    std::size_t i = row_start[ra], j = row_start[rb];
    while (i < row_start[ra + 1] && j < row_start[rb + 1]) {
      if (runs[i].x0 <= runs[j].x1 + 1 && runs[j].x0 <= runs[i].x1 + 1)
        unite(parent, static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j));
      // Advance the run that ends first: the next run of its row starts ≥ 2 voxels
      // after that end, so it cannot meet the other row's runs already passed.
      if (runs[i].x1 < runs[j].x1)
        ++i;
      else
        ++j;
    }
  };
  for (int z = 0; z < nz; ++z) {
    for (int y = 0; y < ny; ++y) {
      const std::size_t r =
          static_cast<std::size_t>(y) + static_cast<std::size_t>(ny) * static_cast<std::size_t>(z);
      if (y > 0) joinRows(r, r - 1);
      if (z == 0) continue;
      const std::size_t below = r - static_cast<std::size_t>(ny);
      joinRows(r, below);
      if (y > 0) joinRows(r, below - 1);
      if (y + 1 < ny) joinRows(r, below + 1);
    }
  }
  // Number the components in the order their first voxel appears (roots are the
  // smallest run index of their set, and runs are in linear order).
  std::vector<std::int32_t>& run_label = cache.run_label;
  run_label.assign(runs.size(), 0);
  std::int32_t next = 0;
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const std::uint32_t root = findRoot(parent, static_cast<std::uint32_t>(k));
    run_label[k] = root == k ? ++next : run_label[root];
  }
}

std::int32_t VoxelGrid::component(const Index3& i) const {
  if (isBlocked(i)) return 0;  // also every voxel of a default-constructed grid (no cache)
  ReachCache& c = *reach_cache_;
  const std::lock_guard<std::mutex> lock(c.mutex);
  if (!c.labelled) {
    labelComponents(c);
    c.labelled = true;
  }
  // The run of i's row that holds it: the last one starting at or before i.x.
  const std::size_t r = static_cast<std::size_t>(i.y) +
                        static_cast<std::size_t>(dims_[1]) * static_cast<std::size_t>(i.z);
  const auto first = c.runs.begin() + static_cast<std::ptrdiff_t>(c.row_start[r]);
  const auto last = c.runs.begin() + static_cast<std::ptrdiff_t>(c.row_start[r + 1]);
  const auto after = std::upper_bound(first, last, i.x,
                                      [](int x, const ReachCache::Run& run) { return x < run.x0; });
  return c.run_label[static_cast<std::size_t>(after - c.runs.begin()) - 1];
}

}  // namespace uavip::world
