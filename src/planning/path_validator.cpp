#include "uavip/planning/path_validator.h"

#include <algorithm>
#include <limits>
#include <utility>
#include <vector>

#include "uavip/core/math.h"
#include "uavip/core/parallel.h"

namespace uavip::planning {

namespace {

/// Tolerance of the clearance test [m].
constexpr double kTolerance = 1e-9;
/// Paths of at least this many segments are validated on all cores.
constexpr std::size_t kParallelSegments = 64;

}  // namespace

PathValidator::PathValidator(const PointList& cloud, double required_clearance_m)
    : world_(
          std::make_shared<const world::CollisionWorld>(world::CollisionWorld::fromCloud(cloud))),
      required_clearance_m_(required_clearance_m) {}

PathValidator::PathValidator(WorldTag, std::shared_ptr<const world::CollisionWorld> world,
                             double required_clearance_m)
    : world_(std::move(world)), required_clearance_m_(required_clearance_m) {
  if (!world_)
    world_ = std::make_shared<const world::CollisionWorld>(world::CollisionWorld::fromCloud({}));
}

PathValidator::~PathValidator() = default;
PathValidator::PathValidator(PathValidator&&) noexcept = default;
PathValidator& PathValidator::operator=(PathValidator&&) noexcept = default;

double PathValidator::clearance(const Vec3& p) const {
  return world_ ? world_->proximity(p, p, required_clearance_m_).distance_m : kInf;
}

ValidationResult PathValidator::validate(const PointList& path) const {
  ValidationResult out;
  out.min_clearance_m = kInf;
  if (path.empty() || !world_ || world_->objects().empty()) return out;
  const double req = required_clearance_m_;
  const std::size_t segments = path.size() == 1 ? 1 : path.size() - 1;
  // The segments are independent read-only queries: spread over the cores, then
  // summarised in order, so the result does not depend on the threads.
  std::vector<world::Proximity> near(segments);
  const int threads = segments >= kParallelSegments ? hardwareThreads() : 1;
  parallelFor(segments, threads, [&](std::size_t s, std::size_t) {
    near[s] = world_->proximity(path[s], path.size() == 1 ? path[0] : path[s + 1], req);
  });
  out.segment_clearance_m.reserve(segments);
  for (std::size_t s = 0; s < segments; ++s) {
    const world::Proximity& p = near[s];
    out.segment_clearance_m.push_back(p.distance_m);
    out.min_clearance_m = std::min(out.min_clearance_m, p.distance_m);
    if (p.distance_m < req - kTolerance && out.first_violation_segment < 0) {
      out.collision_free = false;
      out.first_violation_segment = static_cast<int>(s);
      out.violation_point = p.point;
      out.violation_object = world_->objects()[static_cast<std::size_t>(p.object)].name();
    }
  }
  return out;
}

}  // namespace uavip::planning
