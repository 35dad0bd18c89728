#pragma once
/// \file
/// A preview of what each photo of a plan will show, drawn from a measured cloud where
/// no ground-truth world exists (a real scan; issue 46): every point is projected
/// through the photo's pinhole camera (renderer.h's convention) and drawn as a square
/// splat `splat_m` wide at its depth, the nearest point winning each pixel (a z-buffer;
/// ties to the lower point index). Colour: the file's RGB or intensity
/// (io::loadCloudColours), else a height ramp over the cloud's z range; farther points
/// are darkened (1 − 0.4 × their depth's share of `max_depth_m`) so that the parts
/// separate. Pixels no point reaches show the sky (kSkyRgb). Deterministic: a pixel
/// depends only on the points and the pose.

#include <array>
#include <cstdint>
#include <vector>

#include "uavip/core/types.h"
#include "uavip/coverage/coverage_evaluator.h"
#include "uavip/photo/renderer.h"

namespace uavip::photo {

/// The cloud a preview is drawn from.
struct PreviewCloud {
  PointList points;                              ///< [m], the mission's frame
  std::vector<std::array<std::uint8_t, 3>> rgb;  ///< one per point, or empty (height ramp)
  double splat_m{0.05};                          ///< a point's drawn width [m] (> 0)
  double max_depth_m{50.0};                      ///< points farther are not drawn [m]
};

/// The colour of height z on the ramp from z_min (blue) to z_max (yellow).
std::array<std::uint8_t, 3> heightColour(double z, double z_min, double z_max);

/// One preview photo (see the file comment).
Image renderPointPreview(const PreviewCloud& cloud, const coverage::PinholeIntrinsics& k,
                         const PhotoPose& pose);

/// Median distance from a point to its nearest neighbour over at most `sample` points
/// spread through the cloud [m] (0 for fewer than 2 points): the splat width to use.
double medianSpacing(const PointList& points, std::size_t sample = 4000);

}  // namespace uavip::photo
