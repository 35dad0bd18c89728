#include "uavip/core/voxel_key.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <utility>

#include "uavip/core/error.h"
#include "uavip/core/geometry.h"
#include "uavip/core/key_sort.h"
#include "uavip/core/parallel.h"

namespace uavip {

namespace {

/// |lattice index| bound: below 2^52 every index is a distinct, exact double.
constexpr double kMaxLatticeIndex = 4503599627370496.0;  // 2^52

[[noreturn]] void throwTooSmall(const std::string& what, double edge, const Vec3& extent,
                                double cells) {
  std::ostringstream os;
  os << what << " " << edge << " m is too small for the extent " << extent.x() << " x "
     << extent.y() << " x " << extent.z() << " m (" << cells << " voxels on one axis > 2^21)"
     << "; use a larger " << what;
  throw InputError(os.str());
}

}  // namespace

VoxelKeyer::VoxelKeyer(const Vec3& lo, const Vec3& hi, double edge, const std::string& what)
    : edge_(edge) {
  requirePositive(edge, "voxel grid", what);
  if (!lo.allFinite() || !hi.allFinite())
    throw InputError("voxel grid: the point bounds are not finite");
  origin_ = (lo / edge).array().floor().matrix() * edge;
  for (int a = 0; a < 3; ++a) {
    const double cells = std::floor((hi[a] - origin_[a]) / edge) + 1.0;
    if (!(cells <= static_cast<double>(kCells))) throwTooSmall(what, edge, hi - lo, cells);
  }
}

std::array<std::int64_t, 3> VoxelKeyer::latticeIndex(const Vec3& p, double edge,
                                                     const std::string& what) {
  std::array<std::int64_t, 3> c{};
  for (int a = 0; a < 3; ++a) {
    const double f = std::floor(p[a] / edge);
    if (!(std::abs(f) < kMaxLatticeIndex)) {
      std::ostringstream os;
      os << "voxel grid: point (" << p.transpose() << ") is not finite or too far from the origin"
         << " for " << what << " " << edge << " m (|index| must be < 2^52)";
      throw InputError(os.str());
    }
    c[static_cast<std::size_t>(a)] = static_cast<std::int64_t>(f);
  }
  return c;
}

VoxelKeyer VoxelKeyer::forIndexBox(const std::array<std::int64_t, 3>& lo,
                                   const std::array<std::int64_t, 3>& hi, double edge,
                                   const std::string& what) {
  requirePositive(edge, "voxel grid", what);
  Vec3 origin;
  for (std::size_t a = 0; a < 3; ++a) {
    const double cells = static_cast<double>(hi[a] - lo[a]) + 1.0;
    if (!(cells <= static_cast<double>(kCells))) {
      const Vec3 extent(static_cast<double>(hi[0] - lo[0] + 1),
                        static_cast<double>(hi[1] - lo[1] + 1),
                        static_cast<double>(hi[2] - lo[2] + 1));
      throwTooSmall(what, edge, extent * edge, cells);
    }
    origin[static_cast<Eigen::Index>(a)] = static_cast<double>(lo[a]) * edge;
  }
  return VoxelKeyer(origin, edge, lo);
}

VoxelKeyer VoxelKeyer::forPointsOnLattice(const PointList& points, double edge,
                                          const std::string& what) {
  requirePositive(edge, "voxel grid", what);
  if (points.empty()) throw InputError("voxel grid: no points for " + what);
  std::array<std::int64_t, 3> lo{}, hi{};
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto c = latticeIndex(points[i], edge, what);
    for (std::size_t a = 0; a < 3; ++a) {
      lo[a] = i == 0 ? c[a] : std::min(lo[a], c[a]);
      hi[a] = i == 0 ? c[a] : std::max(hi[a], c[a]);
    }
  }
  return forIndexBox(lo, hi, edge, what);
}

std::uint64_t VoxelKeyer::indexKey(const std::array<std::int64_t, 3>& c) const {
  return pack(c[0] - lo_index_[0], c[1] - lo_index_[1], c[2] - lo_index_[2]);
}

std::uint64_t VoxelKeyer::wrappedKey(const std::array<std::int64_t, 3>& c) {
  constexpr std::uint64_t mask = (std::uint64_t{1} << kBits) - 1;
  return pack(static_cast<std::int64_t>(static_cast<std::uint64_t>(c[0]) & mask),
              static_cast<std::int64_t>(static_cast<std::uint64_t>(c[1]) & mask),
              static_cast<std::int64_t>(static_cast<std::uint64_t>(c[2]) & mask));
}

VoxelKeyer VoxelKeyer::forPoints(const PointList& points, double edge, const std::string& what) {
  const Aabb box = boundingBox(points);
  return VoxelKeyer(box.min, box.max, edge, what);
}

std::array<std::int64_t, 3> VoxelKeyer::cell(const Vec3& p) const {
  std::array<std::int64_t, 3> c{};
  for (int a = 0; a < 3; ++a) {
    const double f = std::floor((p[a] - origin_[a]) / edge_);
    c[static_cast<std::size_t>(a)] =
        static_cast<std::int64_t>(std::clamp(f, 0.0, static_cast<double>(kCells - 1)));
  }
  return c;
}

std::uint64_t VoxelKeyer::pack(std::int64_t x, std::int64_t y, std::int64_t z) {
  return (static_cast<std::uint64_t>(x) << (2 * kBits)) | (static_cast<std::uint64_t>(y) << kBits) |
         static_cast<std::uint64_t>(z);
}

std::array<std::int64_t, 3> VoxelKeyer::unpack(std::uint64_t key) {
  constexpr std::uint64_t mask = (std::uint64_t{1} << kBits) - 1;
  return {static_cast<std::int64_t>(key >> (2 * kBits)),
          static_cast<std::int64_t>((key >> kBits) & mask), static_cast<std::int64_t>(key & mask)};
}

std::uint64_t VoxelKeyer::key(const Vec3& p) const {
  const auto c = cell(p);
  return pack(c[0], c[1], c[2]);
}

Vec3 VoxelKeyer::centre(std::uint64_t key) const {
  const auto c = unpack(key);
  return origin_ + edge_ * Vec3(static_cast<double>(c[0]) + 0.5, static_cast<double>(c[1]) + 0.5,
                                static_cast<double>(c[2]) + 0.5);
}

PointList voxelDownsample(const PointList& cloud, double edge, const std::string& what,
                          int threads) {
  if (cloud.empty()) {
    requirePositive(edge, "voxel grid", what);
    return {};
  }
  const VoxelKeyer keyer = VoxelKeyer::forPoints(cloud, edge, what);
  // Sorted with x varying fastest, then y, then z: the order of PCL's VoxelGrid,
  // so the stages after it see the points in the order they always did.
  const std::size_t n = cloud.size();
  constexpr std::size_t kSlice = std::size_t{1} << 16;
  std::vector<KeyedIndex> keyed(n);
  parallelFor((n + kSlice - 1) / kSlice, threads, [&](std::size_t slice, std::size_t) {
    const std::size_t end = std::min(n, (slice + 1) * kSlice);
    for (std::size_t i = slice * kSlice; i < end; ++i) {
      const auto c = keyer.cell(cloud[i]);
      keyed[i] = {VoxelKeyer::pack(c[2], c[1], c[0]), static_cast<std::uint32_t>(i)};
    }
  });
  sortByKey(keyed, threads);  // = std::sort on the pairs (indices ascend), faster
  // Centroids of the voxels in [from, to) of `keyed` (whole voxels), one per voxel.
  const auto centroids = [&](std::size_t from, std::size_t to) {
    PointList out;
    for (std::size_t i = from; i < to;) {
      std::size_t j = i;
      // Sum relative to the voxel's first point: exact far from the origin too.
      const Vec3& base = cloud[keyed[i].second];
      Vec3 sum = Vec3::Zero();
      for (; j < to && keyed[j].first == keyed[i].first; ++j) sum += cloud[keyed[j].second] - base;
      out.push_back(base + sum / static_cast<double>(j - i));
      i = j;
    }
    return out;
  };
  return fromRunsInHalves(keyed, threads, centroids);
}

std::vector<std::uint64_t> occupiedKeys(const PointList& cloud, const VoxelKeyer& keyer) {
  std::vector<std::uint64_t> keys;
  keys.reserve(cloud.size());
  for (const auto& p : cloud) keys.push_back(keyer.key(p));
  sortUniqueKeys(keys);
  return keys;
}

std::uint64_t planeCellKey(std::int64_t x, std::int64_t y, const char* what) {
  constexpr std::int64_t half = std::int64_t{1} << 31;
  if (!inPlaneCellRange(x) || !inPlaneCellRange(y)) {
    std::ostringstream os;
    os << what << ": cell (" << x << ", " << y << ") is outside [-2^31, 2^31)";
    throw InputError(os.str());
  }
  return static_cast<std::uint64_t>(x + half) << 32 | static_cast<std::uint64_t>(y + half);
}

std::int64_t planeCellIndex(double v, double cell, const char* what) {
  const double f = std::floor(v / cell);
  constexpr double half = 2147483648.0;  // 2^31
  if (!(f >= -half && f < half)) {
    std::ostringstream os;
    os << what << ": coordinate " << v << " is not finite or too far from the origin for cell "
       << cell << " m (|index| must be < 2^31)";
    throw InputError(os.str());
  }
  return static_cast<std::int64_t>(f);
}

}  // namespace uavip
