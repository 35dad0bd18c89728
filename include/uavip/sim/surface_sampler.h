#pragma once
/// \file
/// Sensing mode `sample`: a point cloud sampled on the world's primitives with
/// Gaussian noise and sprinkled outliers, seeded (scenarios/README.md).

#include <cstdint>

#include "uavip/core/types.h"
#include "uavip/sim/world_model.h"

namespace uavip::sim {

/// Options of surface sampling.
struct SampleOptions {
  double spacing_m{0.05};        ///< grid spacing on rectangles and segments [m]
  double noise_sigma_m{0.005};   ///< Gaussian noise along the surface normal (range noise) [m]
  double outlier_fraction{0.0};  ///< outliers added, as a fraction of the sampled points [0, 1)
  double outlier_margin_m{1.0};  ///< outliers are uniform in the world box grown by this [m]
  std::uint32_t seed{1};         ///< seed of every random draw

  /// Throws InputError naming the bad field (prefix `where`).
  void validate(const std::string& where = "sample") const;
};

/// Samples every rectangle on a regular grid (spacing_m, both edges included),
/// every segment every spacing_m, every point once; adds noise and outliers.
/// Deterministic for the same world and options. Rectangles are sampled in the
/// order they were added, so the output order is stable.
PointList sampleSurfaces(const WorldModel& world, const SampleOptions& options);

}  // namespace uavip::sim
