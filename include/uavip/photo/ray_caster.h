#pragma once
/// \file
/// Exact ray casting against the ground-truth world (sim::WorldModel) on Embree 3:
/// every rectangle of the world is one quad; segments and isolated points have no
/// area and are not seen. A box is six closed faces, so the first hit of a ray from
/// outside is always on the outer surface: faces of one primitive that lie inside
/// another solid (the tower's platform inside its shaft) are never visible.
///
/// Embree works in float: the quads are stored relative to the centre of the world's
/// box, and the hit point is recomputed in double on the plane of the quad it hit.

#include <cstddef>
#include <limits>
#include <memory>

#include "uavip/core/geometry.h"
#include "uavip/core/types.h"
#include "uavip/sim/world_model.h"

namespace uavip::photo {

/// The first surface a ray meets.
struct RayHit {
  bool hit{false};
  double t{std::numeric_limits<double>::infinity()};  ///< distance along the unit ray [m]
  Vec3 point{Vec3::Zero()};                           ///< hit point [m]
  Vec3 normal{Vec3::UnitZ()};                         ///< the rectangle's unit normal
  std::size_t rect{0};                                ///< index in WorldModel::rects()
};

/// The world's rectangles in an Embree scene. Built once (one build thread, so the
/// hierarchy and with it every tie between coincident faces is the same on every
/// machine); cast() is const and thread-safe.
class RayCaster {
 public:
  /// Throws InputError when the world has no rectangle (nothing a photo could see).
  explicit RayCaster(const sim::WorldModel& world);
  ~RayCaster();
  RayCaster(const RayCaster&) = delete;
  RayCaster& operator=(const RayCaster&) = delete;

  /// The first hit of the ray origin + t·dir (dir a unit vector), t in (0, max_t] [m].
  RayHit cast(const Vec3& origin, const Vec3& dir,
              double max_t = std::numeric_limits<double>::infinity()) const;

  /// The world's box (rectangles only) [m].
  const Aabb& bounds() const { return bounds_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  Aabb bounds_;
};

}  // namespace uavip::photo
