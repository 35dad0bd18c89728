#pragma once
/// \file
/// Small helpers shared by the surface planner and the flight planner: joining
/// planned legs into one path.

#include "uavip/core/text.h"
#include "uavip/core/types.h"

namespace uavip::planning {

/// Appends `points` without its first point (the joint, already in `path`) and
/// without repeating the last point of `path` (zero-length legs).
inline void appendLeg(PointList& path, const PointList& points) {
  for (std::size_t i = 1; i < points.size(); ++i) {
    if (path.empty() || points[i] != path.back()) path.push_back(points[i]);
  }
}

}  // namespace uavip::planning
