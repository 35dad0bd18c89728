#pragma once
/// \file
/// Independent check of every waypoint path against the measured points (not the
/// grid): exact point-to-segment distances for the points near each segment, found
/// with a kd-tree. The FCL swept-volume validator of ARCHITECTURE.md extends this.

#include "uavip/core/types.h"

#include <memory>

namespace uavip::planning {

/// Verdict on one path.
struct ValidationResult {
  bool collision_free{true};
  double min_clearance_m{0.0};  ///< smallest distance from the path to any point [m] (inf if no points)
  int first_violation_segment{-1};  ///< index i of segment path[i]→path[i+1], −1 if none
  Vec3 violation_point{Vec3::Zero()};  ///< the measured point that violates first [m]
};

/// Checks paths against a point cloud with a required clearance. Thread-safe for
/// const use after construction; keeps its own copy of the points.
class PathValidator {
 public:
  /// required_clearance_m: a path is collision-free when every point of it is at
  /// least this far from every cloud point [m].
  PathValidator(const PointList& cloud, double required_clearance_m);
  ~PathValidator();
  PathValidator(PathValidator&&) noexcept;
  PathValidator& operator=(PathValidator&&) noexcept;

  double requiredClearance() const { return required_clearance_m_; }
  /// Distance from p to the nearest cloud point [m] (inf if the cloud is empty).
  double clearance(const Vec3& p) const;
  /// Validates the polyline `path` (a single point is checked as a point).
  ValidationResult validate(const PointList& path) const;

 private:
  struct Index;
  std::unique_ptr<Index> index_;
  double required_clearance_m_{0.0};
};

}  // namespace uavip::planning
