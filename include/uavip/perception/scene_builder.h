#pragma once
/// \file
/// Stages 4 + 5 together: from the clean cloud to a Scene.

#include "uavip/core/types.h"
#include "uavip/perception/obstacle_clusterer.h"
#include "uavip/perception/plane_detector.h"

namespace uavip::perception {

/// Options of perception (stages 4–5).
struct PerceptionOptions {
  PlaneDetectionOptions planes;
  ClusterOptions clusters;
  /// Throws InputError naming the bad key (prefix `where`).
  void validate(const std::string& where = "perception") const;
  /// Every key of `perception:` (both structs' tables).
  static const params::Table<PerceptionOptions>& table();
};

/// Statistics of perception.
struct PerceptionStats {
  PlaneDetectionStats planes;
  double planes_seconds{0.0};
  double clusters_seconds{0.0};
};

/// Detects surfaces, then clusters the rest into obstacles. scene.cloud = clean.
Scene buildScene(const PointList& clean, const PerceptionOptions& options,
                 PerceptionStats* stats = nullptr);

}  // namespace uavip::perception
