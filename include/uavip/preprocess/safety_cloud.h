#pragma once
/// \file
/// Safety from every measured point. Stage 3 (outlier removal, voxel grid) serves
/// perception only: the points it drops or merges still stand for something the UAV
/// can hit (railings, poles, antennas, the sparse edge of a model), and a voxel
/// centroid can lie up to a voxel diagonal from the points it replaced. The safety
/// cloud keeps every input point, thinned on a fine lattice with a stated bound:
///
///   for every input point p there is a safety point q with |p − q| ≤ margin_m,
///   margin_m = √3 · cell_m (a cell's diagonal; q is the first input point of p's cell).
///
/// Planning and validation keep `clearance + margin_m` from the safety points, so the
/// flight keeps `clearance` from every input point (docs/ARCHITECTURE.md, "Safety").

#include <cstddef>
#include <string>

#include "uavip/core/params.h"
#include "uavip/core/types.h"

namespace uavip::preprocess {

/// Options of the safety cloud (YAML `safety:`).
struct SafetyOptions {
  /// Edge of the thinning lattice [m]; its diagonal √3·cell_m is added to every
  /// clearance. Grown automatically when the cloud spans more than 2^21 cells.
  double cell_m{0.02};
  /// Where the cloud is sparse the surface lies between its points: a planar surface
  /// sampled every s metres has every point within s/√2 of a sample, so planning keeps
  /// sparse_factor × spacing more from the points (spacing: the cloud's measured median
  /// nearest-neighbour distance). 0 trusts the points as the whole surface.
  double sparse_factor{0.71};

  /// Throws InputError naming the bad field (prefix `where`).
  void validate(const std::string& where = "safety") const;
  /// The keys of `safety:` this struct holds (core/params.h).
  static const params::Table<SafetyOptions>& table();
};

/// The safety cloud of `raw` (every measured point, see the file comment): one point
/// per occupied cell of edge `cell_m` (grown so that the box spans at most 2^21 − 2
/// cells per axis), the cell's first input point, rounded to float so that a copy
/// written to a PCD file reads back identically. Ordered by cell (x slowest):
/// deterministic. Throws InputError for a non-finite point or cell_m ≤ 0.
/// Memory: 16 bytes per input point while it runs.
SafetyCloud safetyCloud(const PointList& raw, double cell_m);

/// Extra distance planning keeps from the safety points beyond the UAV's clearance
/// [m]: the thinning bound (margin_m) plus options.sparse_factor × spacing_m.
double safetyMargin(const SafetyCloud& safety, double spacing_m, const SafetyOptions& options);

}  // namespace uavip::preprocess
