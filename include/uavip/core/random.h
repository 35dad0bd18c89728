#pragma once
/// \file
/// Random draws in a fixed order, so a seed gives the same numbers whichever compiler
/// built the program. Header-only.

#include "uavip/core/types.h"

namespace uavip {

/// Three draws from `dist` as a vector, drawn z first, then y, then x.
/// `Vec3(dist(rng), dist(rng), dist(rng))` leaves the order to the compiler (GCC draws
/// right to left, Clang left to right); this fixes GCC's order, so the simulated scans
/// and worlds made before keep their bits.
template <typename Distribution, typename Rng>
Vec3 drawVec3(Distribution& dist, Rng& rng) {
  const double z = dist(rng);
  const double y = dist(rng);
  const double x = dist(rng);
  return Vec3(x, y, z);
}

}  // namespace uavip
