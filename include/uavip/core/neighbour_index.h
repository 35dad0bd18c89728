#pragma once
/// \file
/// The one kd-tree over a cloud: stage 3's neighbour queries (the cloud's measurement,
/// cloud_stats.h, and the statistical outlier removal, filters.h, search the same
/// points, so the caller may build the tree once for both), registration's ICP pairs,
/// the collision world's point distances, the mission page's clearance, the benches.

#include <cstddef>
#include <memory>
#include <vector>

#include "uavip/core/types.h"

namespace uavip {

/// FLANN's exact kd-tree (KDTreeSingleIndex, 15 points per leaf: the tree
/// pcl::KdTreeFLANN and pcl::search::KdTree build, with their search parameters) over
/// float copies of the points taken relative to an origin near the cloud (by default
/// its min corner: floats near 0 keep millimetres far from the origin, e.g. in UTM).
/// Distances it reports are float ones in that frame. From 2^18 points it is two
/// trees, one per side of the median of the cloud's longest axis, built at once on
/// two threads (a tree's build is serial); a
/// query searches the other side only when the split plane is nearer than what it
/// found, and gets the same neighbours and distances (tested against brute force).
/// The split depends on the points only, never on the machine. Holds a reference to
/// the cloud, which must outlive it and stay unchanged. Queries are const and
/// thread-safe. Memory: 12 bytes per point plus the tree (17–21 when split). FLANN is
/// linked privately (core's headers name no third-party type).
class NeighbourIndex {
 public:
  /// Throws InputError for an empty cloud, a non-finite point, or more than
  /// 2^31 − 1 points (FLANN's int indices).
  explicit NeighbourIndex(const PointList& cloud);
  /// The same with the float frame's origin given [m] (a caller's established frame).
  NeighbourIndex(const PointList& cloud, const Vec3& origin);
  ~NeighbourIndex();
  NeighbourIndex(const NeighbourIndex&) = delete;
  NeighbourIndex& operator=(const NeighbourIndex&) = delete;

  const PointList& cloud() const { return cloud_; }
  const Vec3& origin() const { return origin_; }  ///< of the float frame [m]

  /// The stored point nearest to the query q (any point) [index into cloud()]; its
  /// squared float distance goes to *squared_m2 if given [m²].
  int nearestTo(const Vec3& q, float* squared_m2 = nullptr) const;

  /// The stored points within `radius` [m] of q (float test d² ≤ radius², as
  /// pcl::KdTreeFLANN::radiusSearch): indices and squared distances [m²], sorted by
  /// distance or, unsorted, in the tree's order.
  void within(const Vec3& q, double radius, std::vector<int>& indices,
              std::vector<float>& squared_m2, bool sorted = true) const;

  /// The k nearest stored points of each stored point first … first + count − 1,
  /// row by row (count × k entries each), every row sorted by distance, so the
  /// point itself (or a duplicate of it) comes first: indices into cloud(), and
  /// squared distances in the float frame [m²].
  void nearest(std::size_t first, std::size_t count, int k, int* indices, float* squared_m2) const;

  /// The same for stored point i alone; `indices` and `squared_m2` get k entries
  /// (fewer if the cloud has fewer points).
  void nearest(std::size_t i, int k, std::vector<int>& indices,
               std::vector<float>& squared_m2) const;

 private:
  struct Tree;
  const PointList& cloud_;
  Vec3 origin_;
  std::unique_ptr<Tree> tree_;
};

}  // namespace uavip
