#pragma once
/// \file
/// What a cloud is like before any stage runs: point spacing, extent and noise.
/// Real clouds come at every density (a terrestrial scan at 1 cm, airborne LiDAR at
/// 0.5–1 m); app/config.h scales every `auto` parameter with these numbers.

#include <cstddef>
#include <cstdint>
#include <string>

#include "uavip/core/neighbour_index.h"
#include "uavip/core/types.h"

namespace uavip::preprocess {

/// Options of the measurement.
struct CloudStatsOptions {
  /// Points (a seeded random sample) whose neighbours are measured.
  std::size_t sample_points{4000};
  int noise_k{12};  ///< neighbours of the local plane fit for the noise estimate
  std::uint32_t seed{7};
};

/// Measured properties of a cloud (core/types.h).
using CloudStats = uavip::CloudStats;

/// Measures spacing, extent and noise on a seeded sample. `index`, if given, is a
/// kd-tree over this very cloud (built once for this and the outlier removal);
/// else one is built. Never throws for a non-empty finite cloud; fewer than 2
/// distinct points give spacing 0. std::invalid_argument for an index over another cloud.
CloudStats measureCloud(const PointList& cloud, const CloudStatsOptions& options = {},
                        const NeighbourIndex* index = nullptr);

/// Why a measured cloud looks like it is not in metres, as one line naming what fixes
/// it, or "" when it looks like metres:
///  - x and y span under 0.1 while z spans over 100 times more: longitude/latitude in
///    degrees with heights in metres (reproject to a metric CRS first);
///  - a structure over 5 km across, or points over 5 m apart: millimetres or
///    centimetres (input.scale 0.001 / 0.01) or feet (0.3048);
///  - a structure under 1 m across: kilometres (input.scale 1000).
std::string unitWarning(const CloudStats& stats);

}  // namespace uavip::preprocess
