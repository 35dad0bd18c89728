#pragma once
/// \file
/// Small helpers shared by the surface planner and the flight planner: joining
/// planned legs into one path, and a point as text for their messages.

#include "uavip/core/types.h"

#include <iomanip>
#include <sstream>
#include <string>

namespace uavip::planning {

/// Appends `points` without its first point (the joint, already in `path`) and
/// without repeating the last point of `path` (zero-length legs).
inline void appendLeg(PointList& path, const PointList& points) {
  for (std::size_t i = 1; i < points.size(); ++i) {
    if (path.empty() || points[i] != path.back()) path.push_back(points[i]);
  }
}

/// "(x, y, z)" in metres with two decimals.
inline std::string formatPoint(const Vec3& p) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(2) << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
  return os.str();
}

}  // namespace uavip::planning
