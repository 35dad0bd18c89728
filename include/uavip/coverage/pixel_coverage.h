#pragma once
/// \file
/// Coverage by the pixel rule of FC-Planner's `CoverageEvaluation` (rule (a) of
/// docs/ARCHITECTURE.md, "Structure coverage"): every point within the visible range
/// of a pose and inside its image is projected into that pose's pixels; per pixel
/// only the nearest point (by range) is kept; a point is covered when it is the
/// nearest one in some pixel of some pose. No normals, no line of sight beyond the
/// pixel z-buffer: a point hidden behind another one in the same pixel is not
/// covered by that pose. Here it is applied at the photo stops only.

#include <cstddef>
#include <vector>

#include "uavip/core/types.h"
#include "uavip/coverage/coverage_evaluator.h"

namespace uavip::coverage {

/// Result of the pixel rule.
struct PixelCoverageResult {
  std::size_t points{0};    ///< points evaluated
  std::size_t covered{0};   ///< nearest point of some pixel of some view
  double fraction{0.0};     ///< covered / points (1 for 0 points)
  std::vector<char> flags;  ///< 1 per covered point, indexed like the input
};

/// The pixel rule for `views` of `camera` (pixel (⌊u⌋, ⌊v⌋) for 0 ≤ u < width,
/// 0 ≤ v < height, u = cx + fx·x/z, v = cy + fy·y/z, z > 0) up to `visible_range_m`
/// [m] (> 0). Views are spread over `threads` workers; the result does not depend on
/// their number. Throws InputError for a non-finite point or view, or a bad range.
PixelCoverageResult evaluatePixelCoverage(const PointList& points,
                                          const std::vector<ViewPose>& views,
                                          const PinholeIntrinsics& camera, double visible_range_m,
                                          int threads = 2);

}  // namespace uavip::coverage
