#include "uavip/planning/path_simplifier.h"

#include <algorithm>

namespace uavip::planning {

namespace {

/// How far ahead (in raw points) a shortcut may reach from one anchor; bounds the
/// cost to O(n · kLookAhead) segment tests.
constexpr std::size_t kLookAhead = 200;

}  // namespace

PointList simplifyPath(const PointList& raw, const world::VoxelGrid& grid) {
  if (raw.size() <= 2) return raw;
  PointList out;
  out.push_back(raw.front());
  std::size_t i = 0;
  const std::size_t last = raw.size() - 1;
  while (i < last) {
    // The raw step i → i+1 is always kept as a fallback (it is the planner's own
    // step); a longer jump needs a free segment on the grid. Farthest first.
    std::size_t next = i + 1;
    const std::size_t far = std::min(last, i + kLookAhead);
    for (std::size_t j = far; j >= i + 2; --j) {
      if (grid.segmentFree(raw[i], raw[j])) {
        next = j;
        break;
      }
    }
    out.push_back(raw[next]);
    i = next;
  }
  return out;
}

}  // namespace uavip::planning
