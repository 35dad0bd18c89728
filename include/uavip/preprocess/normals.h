#pragma once
/// \file
/// Surface normals of a cloud without a known sensor: the least-squares plane of
/// each point's k nearest neighbours (PCL NormalEstimation on a kd-tree). The sign
/// is unknown (two-sided): callers that need a side test both or use a line of sight.

#include <vector>

#include "uavip/core/types.h"

namespace uavip::preprocess {

/// Unit normal at each of `queries` from its `k` nearest points of `surface` (PCL
/// NormalEstimation, KdTreeFLANN); flipped so that its z is ≥ 0 (then x ≥ 0, then y)
/// to be deterministic. Where the neighbourhood is degenerate (fewer than 3 points,
/// collinear) the normal is +z. Throws InputError for k < 3 or an empty surface with
/// queries.
std::vector<Vec3> estimateNormals(const PointList& queries, const PointList& surface, int k = 12);

}  // namespace uavip::preprocess
