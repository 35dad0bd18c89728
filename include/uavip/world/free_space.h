#pragma once
/// \file
/// What a sampling planner may ask of the space it plans in: OMPL's
/// StateValidityChecker (isFree) and MotionValidator (segmentFree), the box it
/// samples in, and an identity that says when something it learned (a PRM roadmap)
/// still holds. VoxelGrid is the implementation; the OMPL planners of planners/ see
/// nothing else of it.

#include <cstdint>

#include "uavip/core/geometry.h"
#include "uavip/core/types.h"

namespace uavip::world {

/// A free space for point robots. Implementations are immutable after construction
/// and their const queries are thread-safe.
class FreeSpace {
 public:
  virtual ~FreeSpace() = default;
  /// True if a UAV centred at p [m] is clear of every obstacle (state validity).
  virtual bool isFree(const Vec3& p) const = 0;
  /// True if the whole straight segment a → b [m] is free (motion validity), exactly,
  /// not only at samples.
  virtual bool segmentFree(const Vec3& a, const Vec3& b) const = 0;
  /// The box states are sampled in [m]; nothing outside it is free.
  virtual Aabb bounds() const = 0;
  /// The size of the space's smallest detail [m] (a grid's voxel edge): the step
  /// when a motion is searched for its last free point.
  virtual double resolution() const = 0;
  /// Identity of the content: two spaces with the same id answer every query alike,
  /// so a planner may keep a roadmap built on one for the other. Never 0 for a
  /// built space.
  virtual std::uint64_t contentId() const = 0;
};

}  // namespace uavip::world
