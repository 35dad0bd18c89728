#pragma once
/// \file
/// The planning world of the paper's stage 7 (§II-G): occupancy of the measured points
/// (each point's voxel) in a dense voxel grid, then
/// every free voxel within the inflation sphere of an occupied one is marked
/// blocked, so the UAV can be treated as a particle moving between voxel centres.
///
/// Safety argument (why the inflation is larger than the UAV radius r): a point
/// lies at most h = (√3/2)·res from its voxel's centre, and every point of a step
/// between two adjacent voxel centres (length ≤ √3·res) lies within h of one of
/// them. Blocking every voxel whose centre is within r + 2h = r + √3·res of an
/// occupied voxel centre therefore guarantees a clearance ≥ r from every measured
/// point along any path of 26-neighbour steps between free voxel centres, and along
/// any segment that crosses free voxels only (a point inside a free voxel is within
/// h of its centre). Samples spaced ≤ res are not enough on their own: a segment
/// can cut the corner of a blocked voxel between two samples, so segmentFree also
/// walks every voxel the segment crosses.

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "uavip/core/geometry.h"
#include "uavip/core/params.h"
#include "uavip/core/types.h"
#include "uavip/world/free_space.h"

namespace uavip::world {

/// Options of the planning grid.
struct GridOptions {
  double resolution_m{0.2};        ///< voxel edge [m]
  double inflation_radius_m{0.6};  ///< r: the UAV's largest dimension (paper) [m]
  double padding_m{2.0};  ///< free margin around the cloud's (and extra points') bounds [m]
  std::size_t max_voxels{60'000'000};  ///< refuse grids larger than this (memory guard)

  /// Throws InputError naming the bad field (prefix `where`).
  void validate(const std::string& where = "grid") const;
  /// The keys of `grid:` this struct holds (core/params.h).
  static const params::Table<GridOptions>& table();
};

/// Integer voxel coordinates.
struct Index3 {
  int x{0}, y{0}, z{0};
  bool operator==(const Index3& o) const { return x == o.x && y == o.y && z == o.z; }
  bool operator!=(const Index3& o) const { return !(*this == o); }
};

/// Dense inflated occupancy grid. Immutable after build(); const queries are
/// thread-safe. The FreeSpace the OMPL planners plan in.
class VoxelGrid final : public FreeSpace {
 public:
  /// Builds the grid covering the bounds of `cloud` and `extra` (e.g. photo stops)
  /// grown by padding_m. Occupancy comes from an octomap::OcTree filled with the
  /// cloud; inflation blocks voxels within r + √3·res (see the file comment).
  /// Throws InputError for bad options or a grid over max_voxels.
  static VoxelGrid build(const PointList& cloud, const PointList& extra,
                         const GridOptions& options);
  /// A grid over `region` only (grown by padding_m): a surface's neighbourhood on a
  /// large site instead of the whole site. Every point of every cloud of `clouds`
  /// marks its voxel when it lies inside (read in place: a site section's clouds are
  /// tens of MB, not copied); a point outside blocks nothing, and everything outside
  /// the grid counts as blocked, so the safety argument holds. Non-finite points mark
  /// nothing.
  static VoxelGrid build(const std::vector<const PointList*>& clouds, const GridOptions& options,
                         const Aabb& region);

  /// Throws the InputError build(…, region) would throw for a grid over max_voxels
  /// (naming the voxels, their memory and grid.resolution_m), before anything is
  /// allocated: a caller that samples at the grid's resolution first (the solids of
  /// app::plan) calls it before that sampling.
  static void requireFits(const Aabb& region, const GridOptions& options);

  const GridOptions& options() const { return options_; }
  double resolution() const override { return options_.resolution_m; }
  /// The grid's box: origin to origin + dims·resolution [m].
  Aabb bounds() const override;
  /// Set by build() from a process-wide counter; a copy keeps it (same voxels).
  std::uint64_t contentId() const override { return content_id_; }
  /// Radius used to block voxels around occupied ones: r + √3·res [m].
  double effectiveInflation() const;
  const std::array<int, 3>& dims() const { return dims_; }
  const Vec3& origin() const { return origin_; }  ///< min corner of voxel (0,0,0) [m]
  std::size_t voxelCount() const { return blocked_.size(); }
  std::size_t occupiedCount() const { return occupied_count_; }
  std::size_t blockedCount() const { return blocked_count_; }

  bool inBounds(const Index3& i) const {
    return i.x >= 0 && i.y >= 0 && i.z >= 0 && i.x < dims_[0] && i.y < dims_[1] && i.z < dims_[2];
  }
  /// Voxel holding p (may be out of bounds).
  Index3 indexOf(const Vec3& p) const;
  /// Centre of voxel i [m].
  Vec3 centreOf(const Index3& i) const;
  /// True if the voxel contains a measured point (before inflation).
  bool isOccupied(const Index3& i) const;
  /// True if out of bounds, occupied or inside the inflation of an occupied voxel.
  bool isBlocked(const Index3& i) const { return !inBounds(i) || blocked_[linear(i)] != 0; }
  bool isFree(const Index3& i) const { return !isBlocked(i); }
  /// True if the voxel holding p is free.
  bool isFree(const Vec3& p) const override { return isFree(indexOf(p)); }
  /// True if every sample of the segment a→b, spaced ≤ resolution, lies in a free
  /// voxel, and so does every voxel the segment crosses (3D DDA).
  bool segmentFree(const Vec3& a, const Vec3& b) const override;
  /// Linear index of an in-bounds voxel (x fastest, then y, then z).
  std::size_t linear(const Index3& i) const {
    return static_cast<std::size_t>(i.x) +
           static_cast<std::size_t>(dims_[0]) *
               (static_cast<std::size_t>(i.y) +
                static_cast<std::size_t>(dims_[1]) * static_cast<std::size_t>(i.z));
  }
  /// The 26-connected component of voxel i: 0 if blocked, else a label ≥ 1 shared
  /// by exactly the free voxels connected to it. The grid's components are labelled
  /// once, on the first call (union-find over free runs along x). Thread-safe.
  std::int32_t component(const Index3& i) const;
  /// True if a and b are free and 26-connected through free voxels.
  bool connected(const Index3& a, const Index3& b) const {
    const std::int32_t c = component(a);
    return c != 0 && c == component(b);
  }

 private:
  /// The grid over [lo, hi]; every point of the clouds marks its voxel if inside.
  static VoxelGrid buildWithin(const std::vector<const PointList*>& clouds, const Vec3& lo,
                               const Vec3& hi, const GridOptions& options);
  /// Occupancy (paper §II-G): every point's own voxel.
  void markOccupied(const PointList& cloud);
  /// Counts the occupied voxels; returns those with a free face neighbour (the
  /// inflation's seeds, z-major order).
  std::vector<Index3> occupiedSeeds();
  /// Blocks every free voxel whose centre is within r + √3·res of an occupied centre.
  void inflate();

  GridOptions options_;
  Vec3 origin_{Vec3::Zero()};
  std::array<int, 3> dims_{{0, 0, 0}};
  std::vector<std::uint8_t> blocked_;  ///< 0 free, 1 inflated, 2 occupied
  struct ReachCache;                   ///< component labels (mutex + labelled runs)
  /// Labels the 26-connected components of the free voxels into `cache` (runs).
  void labelComponents(ReachCache& cache) const;
  std::shared_ptr<ReachCache> reach_cache_;
  std::size_t occupied_count_{0};
  std::size_t blocked_count_{0};
  std::uint64_t content_id_{0};
};

}  // namespace uavip::world
