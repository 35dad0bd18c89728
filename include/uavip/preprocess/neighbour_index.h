#pragma once
/// \file
/// One kd-tree over a cloud for stage 3's neighbour queries: the cloud's
/// measurement (cloud_stats.h) and the statistical outlier removal (filters.h)
/// search the same points, so the caller may build the tree once for both.

#include <cstddef>
#include <memory>
#include <vector>

#include "uavip/core/types.h"

namespace uavip::preprocess {

/// FLANN's exact kd-tree (KDTreeSingleIndex, 15 points per leaf: the tree
/// pcl::search::KdTree builds) over float copies of the points taken relative to
/// the cloud's min corner (floats near 0 keep millimetres far from the origin).
/// Holds a reference to the cloud, which must outlive it and stay unchanged.
/// Queries are const and thread-safe. Memory: 12 bytes per point plus the tree.
class NeighbourIndex {
 public:
  /// Throws InputError for an empty cloud, a non-finite point, or more than
  /// 2^31 − 1 points (FLANN's int indices).
  explicit NeighbourIndex(const PointList& cloud);
  ~NeighbourIndex();
  NeighbourIndex(const NeighbourIndex&) = delete;
  NeighbourIndex& operator=(const NeighbourIndex&) = delete;

  const PointList& cloud() const { return cloud_; }

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
  std::unique_ptr<Tree> tree_;
};

}  // namespace uavip::preprocess
