#pragma once
/// \file
/// Euclidean clustering (paper §II-D, §II-E: isolated clusters of a plane are
/// trimmed; the rest is grouped into obstacles): two points are connected when they
/// are closer than the tolerance, and a cluster is a connected component.
///
/// Same partition as pcl::EuclideanClusterExtraction (tested against it), computed
/// on a voxel grid instead of one kd-tree radius search per point: with cells of
/// edge tolerance/√3 every cell is connected inside, so components are found
/// between occupied cells, and two cells are joined at once when their farthest
/// corners are within the tolerance, else by the first pair of their points that
/// is. On a 5 cm cloud with a 0.3 m tolerance a radius search returns ~100 points
/// per query; here most cell pairs are decided without looking at a point.
/// Measured on the bridge (stage 4, 22 candidate planes on 295 k points): see
/// docs/architecture_notes.md, perception.

#include <vector>

#include "uavip/core/types.h"

namespace uavip::perception {

/// Connected components of points[indices] with links between points closer than
/// tolerance_m (strictly, like PCL). Each cluster lists indices into `points` in
/// increasing order; clusters are ordered by their smallest index. Deterministic.
/// Throws InputError if tolerance_m is not > 0.
std::vector<std::vector<int>> euclideanClusters(const PointList& points,
                                                const std::vector<int>& indices,
                                                double tolerance_m);

}  // namespace uavip::perception
