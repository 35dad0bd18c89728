#pragma once
/// \file
/// Independent check of every waypoint path (docs/ARCHITECTURE.md, "Planning"; not the
/// grid): for each segment the UAV is swept as a capsule of radius r (the required
/// clearance) against the world::CollisionWorld — surface slabs, obstacle boxes and
/// the measured points — and the segment is collision-free when the capsule touches
/// nothing, i.e. when the segment's distance to every object is ≥ r.
///
/// How the verdict is computed (measured; docs/architecture_notes.md): FCL's
/// broadphase (DynamicAABBTree) picks the objects near the capsule, and the
/// distance to each is exact: segment–polyhedron distance for slabs and boxes, and
/// exact point-to-segment distances for the cloud (a box tree over its cells). The
/// exact point distance is the final word for measured points because FCL's
/// OcTree treats each occupied leaf as a box, conservative by up to the leaf's
/// diagonal, which would fail a path that grazes a point at exactly the margin. So
/// a path grazing at r + 1e-6 passes and at r − 1e-6 fails, for points, slabs and
/// boxes alike. FCL's own GJK sweep is CollisionWorld::sweepContacts().

#include <memory>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "uavip/core/types.h"
#include "uavip/planning/types.h"
#include "uavip/world/collision_world.h"

namespace uavip::planning {

/// Checks paths against a collision world with a required clearance. Thread-safe
/// for const use after construction.
class PathValidator {
 public:
  /// A world of just `cloud` (kept as a copy). required_clearance_m: a path is
  /// collision-free when every point of it is at least this far from every cloud
  /// point [m].
  PathValidator(const PointList& cloud, double required_clearance_m);
  /// Validates against `world` (a std::shared_ptr to a CollisionWorld, shared, not
  /// copied): surfaces, obstacles and cloud. A template only so that the older
  /// `PathValidator({}, r)` still means an empty cloud.
  template <typename World, typename = std::enable_if_t<std::is_convertible_v<
                                World, std::shared_ptr<const world::CollisionWorld>>>>
  PathValidator(World world, double required_clearance_m)
      : PathValidator(WorldTag{}, std::shared_ptr<const world::CollisionWorld>(std::move(world)),
                      required_clearance_m) {}
  ~PathValidator();
  PathValidator(PathValidator&&) noexcept;
  PathValidator& operator=(PathValidator&&) noexcept;

  double requiredClearance() const { return required_clearance_m_; }
  const world::CollisionWorld& world() const { return *world_; }
  /// Distance from p to the nearest object [m] (inf if the world is empty).
  double clearance(const Vec3& p) const;
  /// Validates the polyline `path` (a single point is checked as a point).
  ValidationResult validate(const PointList& path) const;

 private:
  struct WorldTag {};
  PathValidator(WorldTag, std::shared_ptr<const world::CollisionWorld> world,
                double required_clearance_m);

  std::shared_ptr<const world::CollisionWorld> world_;
  double required_clearance_m_{0.0};
};

}  // namespace uavip::planning
