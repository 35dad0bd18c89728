#include "uavip/coverage/coverage_evaluator.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>

#include "uavip/core/error.h"
#include "uavip/core/math.h"
#include "uavip/core/parallel.h"
#include "uavip/core/voxel_key.h"

namespace uavip::coverage {

namespace {

constexpr std::uint64_t kEmptySlot = ~std::uint64_t{0};
/// Most bricks of VoxelLineOfSight's empty-space bitmap (8 MB of bits).
constexpr double kMaxBricks = 67108864.0;
/// Occupied boxes of at most this many voxels also get a bit per voxel (32 MiB at
/// most): a ray's step inside an occupied brick is then one load instead of a hash
/// probe (the view selection is mostly such steps).
constexpr double kMaxDenseVoxels = 268435456.0;
/// Cells per axis of the evaluator's point grid are capped at this.
constexpr double kMaxGridCells = 1.0e6;
/// Grid cells per range limit: a view reads the cells within its range that meet
/// the camera's cone, ~(2k + 1)³ cells at most.
constexpr double kCellsPerRange = 2.0;

/// Key of voxel (i, j, k) of VoxelLineOfSight, which must lie in its index box (≤ 2^21
/// voxels per axis, checked by its VoxelKeyer: the keys are unique there).
std::uint64_t packKey(std::int64_t i, std::int64_t j, std::int64_t k) {
  return VoxelKeyer::wrappedKey({i, j, k});
}

/// SplitMix64 finaliser: spreads packed keys over the table.
std::uint64_t mixKey(std::uint64_t x) {
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ULL;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebULL;
  x ^= x >> 31;
  return x;
}

/// True when the open-addressing table holds key.
inline bool tableHas(const std::vector<std::uint64_t>& table, std::uint64_t mask,
                     std::uint64_t key) {
  std::uint64_t slot = mixKey(key) & mask;
  while (true) {
    const std::uint64_t s = table[slot];
    if (s == key) return true;
    if (s == kEmptySlot) return false;
    slot = (slot + 1) & mask;
  }
}

/// Points bucketed in a uniform grid (cell = the range limit / kCellsPerRange),
/// stored cell by cell (cells in x-fastest linear order) so a query over a box of
/// cells reads a few contiguous runs.
struct PointGrid {
  Vec3 origin{Vec3::Zero()};
  double cell{1.0};
  std::int64_t dims[3]{1, 1, 1};
  std::vector<std::uint64_t> keys;  ///< occupied cells, ascending
  std::vector<std::size_t> begin;   ///< keys.size() + 1 offsets into the arrays below
  std::vector<Vec3> pos;            ///< points in cell order [m]
  std::vector<Vec3> nrm;            ///< their unit normals
  std::vector<char> both;           ///< 1 where the normal is two-sided
  std::vector<std::size_t> index;   ///< their indices in the input

  std::uint64_t key(std::int64_t x, std::int64_t y, std::int64_t z) const {
    return static_cast<std::uint64_t>(x + dims[0] * (y + dims[1] * z));
  }
};

PointGrid buildGrid(const PointList& points, const std::vector<Vec3>& unit_normals,
                    const std::vector<char>* two_sided, double range_limit) {
  PointGrid g;
  Vec3 lo = Vec3::Constant(kInf), hi = Vec3::Constant(-kInf);
  for (const auto& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const Vec3 extent = hi - lo;
  const double emax = extent.maxCoeff();
  g.origin = lo;
  g.cell = std::isfinite(range_limit) ? range_limit / kCellsPerRange : emax + 1.0;
  if (emax / g.cell > kMaxGridCells) g.cell = emax / kMaxGridCells;
  for (int a = 0; a < 3; ++a) {
    g.dims[a] = static_cast<std::int64_t>(std::floor(extent[a] / g.cell)) + 1;
  }
  const std::size_t n = points.size();
  std::vector<std::pair<std::uint64_t, std::size_t>> order(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::int64_t c[3];
    for (int a = 0; a < 3; ++a) {
      c[a] = std::min(static_cast<std::int64_t>(std::floor((points[i][a] - lo[a]) / g.cell)),
                      g.dims[a] - 1);
    }
    order[i] = {g.key(c[0], c[1], c[2]), i};
  }
  std::sort(order.begin(), order.end());
  g.pos.reserve(n);
  g.nrm.reserve(n);
  g.index.reserve(n);
  for (std::size_t j = 0; j < n; ++j) {
    const auto& [key, i] = order[j];
    if (j == 0 || key != order[j - 1].first) {
      g.keys.push_back(key);
      g.begin.push_back(j);
    }
    g.pos.push_back(points[i]);
    g.nrm.push_back(unit_normals.size() == 1 ? unit_normals[0] : unit_normals[i]);
    g.both.push_back(two_sided != nullptr && (*two_sided)[i] != 0 ? 1 : 0);
    g.index.push_back(i);
  }
  g.begin.push_back(n);
  return g;
}

/// What one view's visit counted (statistics).
struct ViewTally {
  std::size_t pairs_in_range{0};
  std::size_t los_queries{0};
};

/// The criteria of one evaluation, prepared once.
struct VisitRule {
  double range_limit{0.0};
  double cos_cone{-1.0};  ///< cos and sin of the camera's largest off-axis angle
  double sin_cone{0.0};
  double cos_max_incidence{0.0};
  double max_gsd{0.0};
  bool two_sided{false};
  const LineOfSight* los{nullptr};
};

/// False when no point of grid cell `key` can be imaged from the view: the ball
/// around the cell (its circumscribed sphere) lies beyond the range limit, or
/// outside the cone of the camera's largest off-axis angle (rule.cos_cone,
/// rule.sin_cone; a point in the image lies inside that cone). With a = the
/// distance along the axis and b = across it, a point is outside the cone by
/// b·cos − a·sin, or by its distance to the apex when a·cos + b·sin < 0.
bool cellMayBeSeen(const PointGrid& g, std::uint64_t key, const ViewFrame& frame,
                   const VisitRule& rule) {
  const auto x = static_cast<std::int64_t>(key % static_cast<std::uint64_t>(g.dims[0]));
  const auto yz = static_cast<std::int64_t>(key / static_cast<std::uint64_t>(g.dims[0]));
  const std::int64_t y = yz % g.dims[1], z = yz / g.dims[1];
  const Vec3 centre =
      g.origin + g.cell * Vec3(static_cast<double>(x) + 0.5, static_cast<double>(y) + 0.5,
                               static_cast<double>(z) + 0.5);
  const double radius = 0.5 * std::sqrt(3.0) * g.cell;
  const Vec3 v = centre - frame.pose.position;
  const double dist = v.norm();
  if (dist - radius > rule.range_limit) return false;
  if (rule.cos_cone <= -1.0) return true;
  const double a = frame.forward.dot(v);
  const double b = std::sqrt(std::max(0.0, dist * dist - a * a));
  if (a * rule.cos_cone + b * rule.sin_cone < 0.0) return dist <= radius;
  return b * rule.cos_cone - a * rule.sin_cone <= radius;
}

/// Calls on_imaged(input index) for every point within rule.range_limit of one view
/// that the view images (criteria 1–5, cheap first), in the grid's cell order.
template <typename OnImaged>
void visitView(const PointGrid& g, const ViewPose& view, const CameraModel& camera,
               const VisitRule& rule, ViewTally& tally, OnImaged&& on_imaged) {
  const ViewFrame frame = makeViewFrame(view);
  const Vec3& c = view.position;
  // Cell box holding every point within range_limit of c (clamped doubles: ±inf safe).
  std::int64_t lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    const double top = static_cast<double>(g.dims[a] - 1);
    const double l = std::floor((c[a] - rule.range_limit - g.origin[a]) / g.cell);
    const double h = std::floor((c[a] + rule.range_limit - g.origin[a]) / g.cell);
    if (l > top || h < 0.0) return;
    lo[a] = static_cast<std::int64_t>(std::max(0.0, l));
    hi[a] = static_cast<std::int64_t>(std::min(top, h));
  }
  const double r2_max = rule.range_limit * rule.range_limit;  // +inf stays +inf
  for (std::int64_t z = lo[2]; z <= hi[2]; ++z) {
    for (std::int64_t y = lo[1]; y <= hi[1]; ++y) {
      auto it = std::lower_bound(g.keys.begin(), g.keys.end(), g.key(lo[0], y, z));
      const std::uint64_t k_last = g.key(hi[0], y, z);
      for (; it != g.keys.end() && *it <= k_last; ++it) {
        const std::size_t cell = static_cast<std::size_t>(it - g.keys.begin());
        if (!cellMayBeSeen(g, *it, frame, rule)) continue;
        for (std::size_t j = g.begin[cell]; j < g.begin[cell + 1]; ++j) {
          const Vec3 d = g.pos[j] - c;
          const double r2 = d.squaredNorm();
          if (r2 > r2_max || r2 <= 0.0) continue;
          ++tally.pairs_in_range;
          // cos(incidence) = n·(c − p)/r; a two-sided normal faces either way.
          const double facing = -g.nrm[j].dot(d);
          if ((rule.two_sided || g.both[j] ? std::abs(facing) : facing) <
              rule.cos_max_incidence * std::sqrt(r2))
            continue;
          const Projection pr = camera.projectInFrame(frame, g.pos[j]);
          if (!pr.in_image) continue;
          if (rule.max_gsd > 0.0 && !(pr.gsd_mm_per_px <= rule.max_gsd)) continue;
          if (rule.los != nullptr) {
            ++tally.los_queries;
            if (!rule.los->clear(c, g.pos[j])) continue;
          }
          on_imaged(g.index[j]);
        }
      }
    }
  }
}

/// Puts key into an open-addressing table (linear probing, power-of-two size);
/// false when it was already there.
bool putKey(std::vector<std::uint64_t>& table, std::uint64_t key) {
  const std::uint64_t mask = table.size() - 1;
  std::uint64_t slot = mixKey(key) & mask;
  while (table[slot] != kEmptySlot && table[slot] != key) slot = (slot + 1) & mask;
  if (table[slot] != kEmptySlot) return false;
  table[slot] = key;
  return true;
}

}  // namespace

// ---------------------------------------------------------------- voxel line of sight

VoxelLineOfSight::VoxelLineOfSight(const PointList& occupied_points, double voxel_m,
                                   double end_slack_m, double point_extent_m)
    : voxel_m_(voxel_m), end_slack_m_(end_slack_m) {
  const std::string where = "voxel_line_of_sight";
  requirePositive(voxel_m, where, "voxel_m");
  requireThat(std::isfinite(end_slack_m) && end_slack_m >= 0.0, where, "end_slack_m",
              ">= 0 and finite", end_slack_m);
  requireThat(std::isfinite(point_extent_m) && point_extent_m >= 0.0, where, "point_extent_m",
              ">= 0 and finite", point_extent_m);
  const double half = 0.5 * point_extent_m;
  // Cubes of neighbouring points share voxels: a surface sampled at the voxel size
  // occupies about 2 voxels a point; the table doubles when it is half full.
  std::size_t capacity = 16;
  while (capacity < (half > 0.0 ? 6 : 2) * occupied_points.size()) capacity *= 2;
  table_.assign(capacity, kEmptySlot);
  mask_ = capacity - 1;
  if (occupied_points.empty()) return;
  // Checks every point and that the box spans at most 2^21 voxels per axis.
  (void)VoxelKeyer::forPointsOnLattice(occupied_points, voxel_m, where + ".voxel_m");
  // Calls f(i, j, k) for every voxel a point occupies (its own, or those its cube meets).
  const auto each_voxel = [&](const auto& f) {
    for (const Vec3& p : occupied_points) {
      if (half <= 0.0) {
        const auto [i, j, k] = VoxelKeyer::latticeIndex(p, voxel_m);
        f(i, j, k);
        continue;
      }
      const auto lo = VoxelKeyer::latticeIndex(p - Vec3::Constant(half), voxel_m);
      const auto hi = VoxelKeyer::latticeIndex(p + Vec3::Constant(half), voxel_m);
      for (std::int64_t i = lo[0]; i <= hi[0]; ++i)
        for (std::int64_t j = lo[1]; j <= hi[1]; ++j)
          for (std::int64_t k = lo[2]; k <= hi[2]; ++k) f(i, j, k);
    }
  };
  each_voxel([&](std::int64_t i, std::int64_t j, std::int64_t k) { insert(i, j, k); });
  for (int a = 0; a < 3; ++a)  // the points' cubes may widen the checked box
    requireThat(hi_[a] - lo_[a] < (std::int64_t{1} << 21), where, "point_extent_m",
                "small enough that the occupied box spans < 2^21 voxels", point_extent_m);
  if (count_ == 0) return;
  // Brick bitmap over the occupied box: the smallest brick (≥ 8 voxels) that fits.
  auto brick_count = [&](int shift) {
    double total = 1.0;
    for (int a = 0; a < 3; ++a) total *= static_cast<double>(((hi_[a] - lo_[a]) >> shift) + 1);
    return total;
  };
  while (brick_count(brick_shift_) > kMaxBricks) ++brick_shift_;
  for (int a = 0; a < 3; ++a) brick_dims_[a] = ((hi_[a] - lo_[a]) >> brick_shift_) + 1;
  brick_bits_.assign(static_cast<std::size_t>(brick_count(brick_shift_) / 64.0) + 1, 0);
  each_voxel([&](std::int64_t i, std::int64_t j, std::int64_t k) {
    const std::uint64_t b = brickIndex(i, j, k);
    brick_bits_[b >> 6] |= std::uint64_t{1} << (b & 63);
  });
  if (brick_count(0) > kMaxDenseVoxels) return;
  dense_bits_.assign(static_cast<std::size_t>(brick_count(0) / 64.0) + 1, 0);
  each_voxel([&](std::int64_t i, std::int64_t j, std::int64_t k) {
    const std::uint64_t d = denseIndex(i, j, k);
    dense_bits_[d >> 6] |= std::uint64_t{1} << (d & 63);
  });
}

void VoxelLineOfSight::insert(std::int64_t i, std::int64_t j, std::int64_t k) {
  const std::int64_t idx[3] = {i, j, k};
  for (int a = 0; a < 3; ++a) {
    lo_[a] = count_ == 0 ? idx[a] : std::min(lo_[a], idx[a]);
    hi_[a] = count_ == 0 ? idx[a] : std::max(hi_[a], idx[a]);
  }
  if (!putKey(table_, packKey(i, j, k))) return;
  if (++count_ * 2 <= table_.size()) return;
  std::vector<std::uint64_t> grown(2 * table_.size(), kEmptySlot);
  for (const std::uint64_t key : table_)
    if (key != kEmptySlot) putKey(grown, key);
  table_ = std::move(grown);
  mask_ = table_.size() - 1;
}

std::uint64_t VoxelLineOfSight::denseIndex(std::int64_t i, std::int64_t j, std::int64_t k) const {
  const std::int64_t nx = hi_[0] - lo_[0] + 1, ny = hi_[1] - lo_[1] + 1;
  return static_cast<std::uint64_t>((i - lo_[0]) + nx * ((j - lo_[1]) + ny * (k - lo_[2])));
}

bool VoxelLineOfSight::occupiedInBox(std::int64_t i, std::int64_t j, std::int64_t k) const {
  if (!dense_bits_.empty()) {
    const std::uint64_t d = denseIndex(i, j, k);
    return (dense_bits_[d >> 6] >> (d & 63) & 1) != 0;
  }
  return tableHas(table_, mask_, packKey(i, j, k));
}

std::uint64_t VoxelLineOfSight::brickIndex(std::int64_t i, std::int64_t j, std::int64_t k) const {
  const std::int64_t bi = (i - lo_[0]) >> brick_shift_;
  const std::int64_t bj = (j - lo_[1]) >> brick_shift_;
  const std::int64_t bk = (k - lo_[2]) >> brick_shift_;
  return static_cast<std::uint64_t>(bi + brick_dims_[0] * (bj + brick_dims_[1] * bk));
}

bool VoxelLineOfSight::occupiedIndex(std::int64_t i, std::int64_t j, std::int64_t k) const {
  if (i < lo_[0] || i > hi_[0] || j < lo_[1] || j > hi_[1] || k < lo_[2] || k > hi_[2]) {
    return false;
  }
  const std::uint64_t b = brickIndex(i, j, k);
  if ((brick_bits_[b >> 6] >> (b & 63) & 1) == 0) return false;
  return occupiedInBox(i, j, k);
}

bool VoxelLineOfSight::occupied(const Vec3& p) const {
  if (count_ == 0 || !p.allFinite()) return false;
  std::int64_t idx[3];
  for (int a = 0; a < 3; ++a) {
    const double f = std::floor(p[a] / voxel_m_);
    if (f < static_cast<double>(lo_[a]) || f > static_cast<double>(hi_[a])) return false;
    idx[a] = static_cast<std::int64_t>(f);
  }
  return occupiedIndex(idx[0], idx[1], idx[2]);
}

namespace {

/// Clips [t0, t1] (t along the unit direction `dir` from `from` [m]) to the box of
/// voxels lo..hi (edge v) by the slab test; false when the segment misses the box.
inline bool clipToBox(const Vec3& from, const Vec3& dir, double v, const std::int64_t (&lo)[3],
                      const std::int64_t (&hi)[3], double& t0, double& t1) {
  for (int a = 0; a < 3; ++a) {
    const double bmin = static_cast<double>(lo[a]) * v;
    const double bmax = static_cast<double>(hi[a] + 1) * v;
    if (dir[a] == 0.0) {
      if (from[a] < bmin || from[a] > bmax) return false;
      continue;
    }
    double ta = (bmin - from[a]) / dir[a];
    double tb = (bmax - from[a]) / dir[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return !(t0 > t1);
}

/// The state of an Amanatides–Woo walk: the current voxel, the step along each axis,
/// the t at which each axis's next boundary is crossed and the t between boundaries
/// (t measured from the segment's start along its unit direction).
struct DdaWalk {
  std::int64_t idx[3];
  std::int64_t step[3];
  double t_max[3];
  double t_delta[3];
};

/// The walk from the voxel holding from + t0·dir (clamped into the box lo..hi).
inline DdaWalk startWalk(const Vec3& from, const Vec3& dir, double t0, double v,
                         const std::int64_t (&lo)[3], const std::int64_t (&hi)[3]) {
  const Vec3 p0 = from + t0 * dir;
  DdaWalk w;
  for (int a = 0; a < 3; ++a) {
    // p0 is on or inside the box; clamping absorbs rounding at its faces.
    const double f = std::floor(p0[a] / v);
    w.idx[a] = static_cast<std::int64_t>(
        std::clamp(f, static_cast<double>(lo[a]), static_cast<double>(hi[a])));
    if (dir[a] > 0.0) {
      w.step[a] = 1;
      w.t_max[a] = (static_cast<double>(w.idx[a] + 1) * v - from[a]) / dir[a];
      w.t_delta[a] = v / dir[a];
    } else if (dir[a] < 0.0) {
      w.step[a] = -1;
      w.t_max[a] = (static_cast<double>(w.idx[a]) * v - from[a]) / dir[a];
      w.t_delta[a] = -v / dir[a];
    } else {
      w.step[a] = 0;
      w.t_max[a] = kInf;
      w.t_delta[a] = kInf;
    }
  }
  return w;
}

/// Moves the walk out of its current (empty) brick, of 2^shift voxels per edge over
/// the box lo..hi, to the voxel where the ray leaves it; false when that is beyond t1
/// or outside the box (the walk is over). rem[a] = voxels of the brick (within the
/// box) still ahead along axis a; the brick is left through the face of the axis whose
/// (rem + 1)-th boundary comes first.
inline bool leaveBrick(DdaWalk& w, double t1, const std::int64_t (&lo)[3],
                       const std::int64_t (&hi)[3], int shift) {
  const std::int64_t brick_edge = std::int64_t{1} << shift;
  std::int64_t rem[3]{0, 0, 0};
  double t_exit = kInf;
  int exit_axis = 0;
  for (int a = 0; a < 3; ++a) {
    if (w.step[a] == 0) continue;
    const std::int64_t start = lo[a] + (((w.idx[a] - lo[a]) >> shift) << shift);
    const std::int64_t end = std::min(start + brick_edge - 1, hi[a]);
    rem[a] = w.step[a] > 0 ? end - w.idx[a] : w.idx[a] - start;
    const double t_face = w.t_max[a] + static_cast<double>(rem[a]) * w.t_delta[a];
    if (t_face < t_exit) {
      t_exit = t_face;
      exit_axis = a;
    }
  }
  if (t_exit > t1) return false;
  for (int a = 0; a < 3; ++a) {
    if (a == exit_axis || w.step[a] == 0) continue;
    std::int64_t n = 0;
    while (n < rem[a] && w.t_max[a] < t_exit) {
      w.t_max[a] += w.t_delta[a];
      ++n;
    }
    w.idx[a] += n * w.step[a];
  }
  w.idx[exit_axis] += (rem[exit_axis] + 1) * w.step[exit_axis];
  w.t_max[exit_axis] = t_exit + w.t_delta[exit_axis];
  return w.idx[exit_axis] >= lo[exit_axis] && w.idx[exit_axis] <= hi[exit_axis];
}

/// One voxel step of the walk; false when the next voxel is entered beyond t1 or
/// lies outside the box lo..hi.
inline bool stepVoxel(DdaWalk& w, double t1, const std::int64_t (&lo)[3],
                      const std::int64_t (&hi)[3]) {
  int a = 0;
  if (w.t_max[1] < w.t_max[a]) a = 1;
  if (w.t_max[2] < w.t_max[a]) a = 2;
  if (w.t_max[a] > t1) return false;  // the next voxel is entered beyond the tested part
  w.idx[a] += w.step[a];
  if (w.idx[a] < lo[a] || w.idx[a] > hi[a]) return false;  // left the occupied box
  w.t_max[a] += w.t_delta[a];
  return true;
}

}  // namespace

bool VoxelLineOfSight::clear(const Vec3& from, const Vec3& to) const {
  require(from.allFinite() && to.allFinite(), "voxel_line_of_sight",
          "clear() needs finite end points");
  if (count_ == 0) return true;
  const Vec3 delta = to - from;
  const double len = delta.norm();
  const double t_end = len - end_slack_m_;
  if (!(t_end > 0.0)) return true;  // the whole segment is within the slack
  const Vec3 dir = delta / len;
  // Clip [0, t_end] to the bounding box of the occupied voxels.
  double t0 = 0.0, t1 = t_end;
  if (!clipToBox(from, dir, voxel_m_, lo_, hi_, t0, t1)) return true;
  // Amanatides–Woo, skipping empty bricks whole.
  DdaWalk w = startWalk(from, dir, t0, voxel_m_, lo_, hi_);
  while (true) {
    const std::uint64_t b = brickIndex(w.idx[0], w.idx[1], w.idx[2]);
    if ((brick_bits_[b >> 6] >> (b & 63) & 1) == 0) {
      if (!leaveBrick(w, t1, lo_, hi_, brick_shift_)) return true;
      continue;
    }
    if (occupiedInBox(w.idx[0], w.idx[1], w.idx[2])) return false;
    if (!stepVoxel(w, t1, lo_, hi_)) return true;
  }
}

// ---------------------------------------------------------------- evaluator

void CoverageCriteria::validate(const std::string& where) const {
  requireThat(std::isfinite(max_gsd_mm_per_px) && max_gsd_mm_per_px >= 0.0, where,
              "max_gsd_mm_per_px", ">= 0 and finite", max_gsd_mm_per_px);
  requireThat(
      std::isfinite(max_incidence_deg) && max_incidence_deg > 0.0 && max_incidence_deg <= 180.0,
      where, "max_incidence_deg", "in (0, 180]", max_incidence_deg);
  requireThat(std::isfinite(max_range_m) && max_range_m >= 0.0, where, "max_range_m",
              ">= 0 and finite (0 = from the camera model)", max_range_m);
}

namespace {

/// Checks the inputs of an evaluation and prepares its grid and rule; `grid` stays
/// empty when there is nothing to evaluate.
VisitRule prepareEvaluation(const PointList& points, const std::vector<Vec3>& normals,
                            const std::vector<ViewPose>& views, const CameraModel& camera,
                            const CoverageCriteria& criteria, const LineOfSight* los, int threads,
                            const std::vector<char>* two_sided, const std::string& where,
                            PointGrid& grid) {
  criteria.validate(where + ".criteria");
  requireThat(threads >= 1, where, "threads", ">= 1", threads);
  const std::size_t n = points.size();
  for (std::size_t i = 0; i < n; ++i) {
    require(points[i].allFinite(), where, "point " + std::to_string(i) + " is not finite");
  }
  if (n > 0) {
    require(normals.size() == n || normals.size() == 1, where,
            "normals must hold one normal per point (" + std::to_string(n) +
                ") or one for all, got " + std::to_string(normals.size()));
  }
  if (two_sided != nullptr) {
    require(two_sided->size() == n, where,
            "two-sided flags must hold one flag per point (" + std::to_string(n) + "), got " +
                std::to_string(two_sided->size()));
  }
  std::vector<Vec3> unit_normals(n > 0 ? normals.size() : 0);
  for (std::size_t i = 0; i < unit_normals.size(); ++i) {
    const double len = normals[i].norm();
    require(std::isfinite(len) && len > 0.0, where,
            "normal " + std::to_string(i) + " is zero or not finite");
    unit_normals[i] = normals[i] / len;
  }
  for (std::size_t v = 0; v < views.size(); ++v) {
    const ViewPose& p = views[v];
    require(p.position.allFinite() && std::isfinite(p.yaw_deg) && std::isfinite(p.pitch_deg), where,
            "view " + std::to_string(v) + " is not finite");
  }
  VisitRule rule;
  rule.range_limit = criteria.max_range_m > 0.0 ? criteria.max_range_m
                                                : camera.maxRange(criteria.max_gsd_mm_per_px);
  requireThat(rule.range_limit > 0.0, where, "the range limit (criteria or camera model)", "> 0",
              rule.range_limit);
  rule.cos_max_incidence = criteria.max_incidence_deg >= 180.0 ? -1.0
                           : criteria.max_incidence_deg == 90.0
                               ? 0.0
                               : std::cos(criteria.max_incidence_deg * kDegToRad);
  rule.max_gsd = criteria.max_gsd_mm_per_px;
  rule.two_sided = criteria.two_sided_normals;
  const double cone = camera.maxOffAxisRad();
  if (cone < 0.5 * kPi) {  // a wider camera is culled by range only
    rule.cos_cone = std::cos(cone);
    rule.sin_cone = std::sin(cone);
  }
  rule.los = los;
  if (n > 0 && !views.empty()) grid = buildGrid(points, unit_normals, two_sided, rule.range_limit);
  return rule;
}

}  // namespace

std::vector<std::vector<std::uint32_t>> imagedByView(
    const PointList& points, const std::vector<Vec3>& normals, const std::vector<ViewPose>& views,
    const CameraModel& camera, const CoverageCriteria& criteria, const LineOfSight* los,
    int threads, const std::vector<char>* two_sided) {
  require(points.size() < std::numeric_limits<std::uint32_t>::max(), "imagedByView",
          "more than 2^32 - 1 points");
  PointGrid grid;
  const VisitRule rule = prepareEvaluation(points, normals, views, camera, criteria, los, threads,
                                           two_sided, "imagedByView", grid);
  std::vector<std::vector<std::uint32_t>> imaged(views.size());
  if (grid.pos.empty()) return imaged;
  parallelFor(views.size(), threads, [&](std::size_t v, std::size_t) {
    ViewTally tally;
    auto& list = imaged[v];
    visitView(grid, views[v], camera, rule, tally,
              [&list](std::size_t i) { list.push_back(static_cast<std::uint32_t>(i)); });
    std::sort(list.begin(), list.end());
  });
  return imaged;
}

CoverageResult evaluateCoverage(const PointList& points, const std::vector<Vec3>& normals,
                                const std::vector<ViewPose>& views, const CameraModel& camera,
                                const CoverageCriteria& criteria, const LineOfSight* los,
                                int threads, const std::vector<char>* two_sided, WorkerGate* gate) {
  PointGrid grid;
  const VisitRule rule = prepareEvaluation(points, normals, views, camera, criteria, los, threads,
                                           two_sided, "evaluateCoverage", grid);
  const std::size_t n = points.size();
  CoverageResult res;
  res.points = n;
  res.range_limit_m = rule.range_limit;
  res.views_per_point.assign(n, 0);
  if (!grid.pos.empty()) {
    // Each worker counts into its own tally; the sums do not depend on the split.
    const std::size_t workers = std::min(static_cast<std::size_t>(threads), views.size());
    std::vector<std::vector<int>> counts(workers);
    std::vector<ViewTally> tallies(workers);
    parallelFor(
        views.size(), static_cast<int>(workers),
        [&](std::size_t v, std::size_t worker) {
          auto& count = counts[worker];
          if (count.empty()) count.assign(n, 0);
          visitView(grid, views[v], camera, rule, tallies[worker],
                    [&count](std::size_t i) { ++count[i]; });
        },
        gate);
    for (std::size_t t = 0; t < workers; ++t) {
      for (std::size_t i = 0; i < counts[t].size(); ++i) res.views_per_point[i] += counts[t][i];
      res.pairs_in_range += tallies[t].pairs_in_range;
      res.los_queries += tallies[t].los_queries;
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (res.views_per_point[i] > 0) {
      ++res.covered;
    } else {
      res.uncovered.push_back(i);
    }
  }
  res.fraction = n == 0 ? 1.0 : static_cast<double>(res.covered) / static_cast<double>(n);
  return res;
}

}  // namespace uavip::coverage
