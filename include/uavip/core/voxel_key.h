#pragma once
/// \file
/// One 64-bit voxel key for every grid that hashes points: 21 bits per axis,
/// relative to an origin on the voxel lattice, so a cloud may span up to
/// 2^21 voxels per axis (105 km at 5 cm) whatever its absolute coordinates.
/// PCL's VoxelGrid packs three axes into one 32-bit int (2^31 voxels in all: a
/// 130 m building at 5 cm already overflows it); this key does not.

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "uavip/core/types.h"

namespace uavip {

/// Packs voxel coordinates of points into 64-bit keys. Voxel borders lie at
/// multiples of `edge` in the world frame (the origin is floored onto the lattice).
/// Key order is z-fastest, then y, then x (lexicographic in (x, y, z)).
/// Immutable; thread-safe.
class VoxelKeyer {
 public:
  static constexpr int kBits = 21;
  static constexpr std::int64_t kCells = std::int64_t{1} << kBits;  ///< voxels per axis

  /// Keyer for points inside [lo, hi] with voxel edge `edge` [m]. Throws InputError
  /// "<what>: <edge> m is too small for the extent …; use a larger <what>" when the
  /// box spans more than 2^21 voxels on an axis, or for a non-positive edge.
  VoxelKeyer(const Vec3& lo, const Vec3& hi, double edge, const std::string& what = "voxel_m");
  /// Keyer for the bounding box of `points` (non-empty, finite).
  static VoxelKeyer forPoints(const PointList& points, double edge,
                              const std::string& what = "voxel_m");

  double edge() const { return edge_; }
  const Vec3& origin() const { return origin_; }  ///< min corner of voxel (0,0,0) [m]
  /// Voxel coordinates of p, clamped to [0, 2^21) on each axis.
  std::array<std::int64_t, 3> cell(const Vec3& p) const;
  /// Key of the voxel holding p (clamped like cell()).
  std::uint64_t key(const Vec3& p) const;
  /// Key of voxel coordinates (each in [0, 2^21)).
  static std::uint64_t pack(std::int64_t x, std::int64_t y, std::int64_t z);
  /// Inverse of pack().
  static std::array<std::int64_t, 3> unpack(std::uint64_t key);
  /// Centre of the voxel with this key [m].
  Vec3 centre(std::uint64_t key) const;

  // World-lattice indices: for grids whose voxel borders must be floor(p / edge)
  // exactly (the line-of-sight grid walks rays on it, registration keeps its order).

  /// Lattice index floor(p / edge) on each axis, unclamped. Throws InputError when p
  /// is not finite or an index reaches ±2^52 (beyond it int64 casts lose voxels).
  static std::array<std::int64_t, 3> latticeIndex(const Vec3& p, double edge,
                                                  const std::string& what = "voxel_m");
  /// Keyer for the voxels with lattice indices in [lo, hi] (from latticeIndex); voxel
  /// (0,0,0) is lattice index lo. Throws like the constructor beyond 2^21 per axis.
  static VoxelKeyer forIndexBox(const std::array<std::int64_t, 3>& lo,
                                const std::array<std::int64_t, 3>& hi, double edge,
                                const std::string& what = "voxel_m");
  /// Keyer for the lattice indices of `points` (non-empty).
  static VoxelKeyer forPointsOnLattice(const PointList& points, double edge,
                                       const std::string& what = "voxel_m");
  /// Key of lattice index c, which must lie in the keyer's index box: pack(c − lo).
  std::uint64_t indexKey(const std::array<std::int64_t, 3>& c) const;
  /// Key of lattice index c in the world lattice's own order: the low 21 bits of each
  /// axis (two's complement), so on an axis negative indices sort after positive
  /// ones. Unique for the indices of the keyer's box (≤ 2^21 per axis, checked at
  /// construction), which c must lie in.
  static std::uint64_t wrappedKey(const std::array<std::int64_t, 3>& c);

 private:
  VoxelKeyer(const Vec3& origin, double edge, const std::array<std::int64_t, 3>& lo_index)
      : origin_(origin), edge_(edge), lo_index_(lo_index) {}
  Vec3 origin_;
  double edge_;
  std::array<std::int64_t, 3> lo_index_{};  ///< lattice index of voxel (0,0,0)
};

/// True when a 2D cell index is in planeCellKey's range [−2^31, 2^31).
inline bool inPlaneCellRange(std::int64_t v) {
  return v >= -(std::int64_t{1} << 31) && v < (std::int64_t{1} << 31);
}
/// Exact key of a cell (x, y) of a 2D lattice, both in [−2^31, 2^31): the two
/// offset-binary 32-bit halves. Throws InputError ("<what>: …") outside that range.
std::uint64_t planeCellKey(std::int64_t x, std::int64_t y, const char* what = "plane cell");
/// 2D cell index floor(v / cell), checked: throws InputError when v / cell is not
/// finite or outside [−2^31, 2^31) (planeCellKey's range).
std::int64_t planeCellIndex(double v, double cell, const char* what = "plane cell");

/// Voxel-grid down-sampling (paper §II-C): each occupied voxel of edge `edge` [m]
/// is replaced by the centroid of its points (double precision). Output ordered
/// with x varying fastest, then y, then z (pcl::VoxelGrid's order): deterministic.
/// Memory: 16 bytes per input point. On `threads` threads (keys by slices, the sort
/// in two halves, the centroids in two halves cut between voxels): the same output.
PointList voxelDownsample(const PointList& cloud, double edge, const std::string& what = "voxel_m",
                          int threads = 1);

/// Sorted, unique keys of the voxels that hold at least one point.
std::vector<std::uint64_t> occupiedKeys(const PointList& cloud, const VoxelKeyer& keyer);

}  // namespace uavip
