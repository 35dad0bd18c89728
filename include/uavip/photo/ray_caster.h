#pragma once
/// \file
/// Exact ray casting on Embree 3 against the ground-truth world (sim::WorldModel) or a
/// triangle mesh (io::TriangleMesh, the model a structure was planned from):
/// every rectangle of the world is one quad, every triangle of a mesh one triangle;
/// a world's segments and isolated points have no area and are not seen. A box is six
/// closed faces, so the first hit of a ray from outside is always on the outer
/// surface: faces of one primitive that lie inside another solid (the tower's platform
/// inside its shaft) are never visible.
///
/// Embree works in float: the faces are stored relative to the centre of their box,
/// and the hit point is recomputed in double on the plane of the face it hit.

#include <cstddef>
#include <limits>
#include <memory>
#include <string>

#include "uavip/core/geometry.h"
#include "uavip/core/types.h"
#include "uavip/io/mesh_reader.h"
#include "uavip/sim/world_model.h"

namespace uavip::photo {

/// The first surface a ray meets.
struct RayHit {
  bool hit{false};
  double t{std::numeric_limits<double>::infinity()};  ///< distance along the unit ray [m]
  Vec3 point{Vec3::Zero()};                           ///< hit point [m]
  Vec3 normal{Vec3::UnitZ()};                         ///< the face's unit normal
  /// The face hit: index in WorldModel::rects(), or of the mesh's non-degenerate
  /// triangles in file order (RayCaster::faces()).
  std::size_t face{0};
};

/// The world's rectangles or a mesh's triangles in an Embree scene. Built once (one
/// build thread, so the hierarchy and with it every tie between coincident faces is
/// the same on every machine); cast() is const and thread-safe.
class RayCaster {
 public:
  /// Throws InputError when the world has no rectangle (nothing a photo could see).
  explicit RayCaster(const sim::WorldModel& world);
  /// A mesh's triangles; degenerate ones (no area, or non-finite) are left out.
  /// Throws InputError naming `path` when no triangle has area.
  RayCaster(const io::TriangleMesh& mesh, const std::string& path);
  ~RayCaster();
  RayCaster(const RayCaster&) = delete;
  RayCaster& operator=(const RayCaster&) = delete;

  /// The first hit of the ray origin + t·dir (dir a unit vector), t in (0, max_t] [m].
  RayHit cast(const Vec3& origin, const Vec3& dir,
              double max_t = std::numeric_limits<double>::infinity()) const;

  /// The box of the faces [m].
  const Aabb& bounds() const { return bounds_; }
  /// Faces in the scene (rectangles or non-degenerate triangles).
  std::size_t faces() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  Aabb bounds_;
};

}  // namespace uavip::photo
