#include "uavip/photo/ray_caster.h"

#include <embree3/rtcore.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "uavip/core/error.h"

namespace uavip::photo {

struct RayCaster::Impl {
  RTCDevice device{nullptr};
  RTCScene scene{nullptr};
  Vec3 origin{Vec3::Zero()};  ///< the quads' float coordinates are relative to this [m]
  std::vector<sim::Rect> rects;
  std::vector<Vec3> normals;

  ~Impl() {
    if (scene != nullptr) rtcReleaseScene(scene);
    if (device != nullptr) rtcReleaseDevice(device);
  }
};

namespace {

[[noreturn]] void embreeFailed(RTCDevice device, const std::string& what) {
  throw std::runtime_error("Embree: " + what + " failed (error " +
                           std::to_string(static_cast<int>(rtcGetDeviceError(device))) + ")");
}

}  // namespace

RayCaster::RayCaster(const sim::WorldModel& world) : impl_(std::make_unique<Impl>()) {
  if (world.rects().empty())
    throw InputError("the world has no surface a photo could see (only lines or points)");
  Impl& m = *impl_;
  m.rects = world.rects();
  for (const auto& r : m.rects) {
    for (const Vec3& c : {r.corner, Vec3(r.corner + r.edge_u), Vec3(r.corner + r.edge_v),
                          Vec3(r.corner + r.edge_u + r.edge_v)})
      bounds_.extend(c);
    m.normals.push_back(r.normal());
  }
  m.origin = 0.5 * (bounds_.min + bounds_.max);
  // One build thread: the same hierarchy (and tie order) whatever the machine.
  m.device = rtcNewDevice("threads=1");
  if (m.device == nullptr) throw std::runtime_error("Embree: rtcNewDevice failed");
  m.scene = rtcNewScene(m.device);
  rtcSetSceneBuildQuality(m.scene, RTC_BUILD_QUALITY_HIGH);
  RTCGeometry g = rtcNewGeometry(m.device, RTC_GEOMETRY_TYPE_QUAD);
  const std::size_t n = m.rects.size();
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
      g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 4 * n));
  auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT4, 4 * sizeof(unsigned), n));
  if (v == nullptr || idx == nullptr) embreeFailed(m.device, "allocating the quads");
  for (std::size_t i = 0; i < n; ++i) {
    const sim::Rect& r = m.rects[i];
    const Vec3 c = r.corner - m.origin;
    const Vec3 corners[4] = {c, c + r.edge_u, c + r.edge_u + r.edge_v, c + r.edge_v};
    for (std::size_t k = 0; k < 4; ++k) {
      for (int a = 0; a < 3; ++a)
        v[3 * (4 * i + k) + static_cast<std::size_t>(a)] = static_cast<float>(corners[k][a]);
      idx[4 * i + k] = static_cast<unsigned>(4 * i + k);
    }
  }
  rtcCommitGeometry(g);
  rtcAttachGeometry(m.scene, g);
  rtcReleaseGeometry(g);
  rtcCommitScene(m.scene);
  if (rtcGetDeviceError(m.device) != RTC_ERROR_NONE) embreeFailed(m.device, "building the scene");
}

RayCaster::~RayCaster() = default;

RayHit RayCaster::cast(const Vec3& origin, const Vec3& dir, double max_t) const {
  const Impl& m = *impl_;
  const Vec3 o = origin - m.origin;
  RTCRayHit rh{};
  rh.ray.org_x = static_cast<float>(o.x());
  rh.ray.org_y = static_cast<float>(o.y());
  rh.ray.org_z = static_cast<float>(o.z());
  rh.ray.dir_x = static_cast<float>(dir.x());
  rh.ray.dir_y = static_cast<float>(dir.y());
  rh.ray.dir_z = static_cast<float>(dir.z());
  rh.ray.tnear = 0.0F;
  rh.ray.tfar = std::isfinite(max_t) ? static_cast<float>(max_t) : INFINITY;
  rh.ray.mask = ~0U;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  rtcIntersect1(m.scene, &context, &rh);
  RayHit out;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return out;
  out.hit = true;
  out.rect = rh.hit.primID;
  out.normal = m.normals[out.rect];
  // The hit again in double, on the plane of the rectangle hit.
  const double along = out.normal.dot(dir);
  out.t = std::abs(along) > 1e-12 ? out.normal.dot(m.rects[out.rect].corner - origin) / along
                                  : static_cast<double>(rh.ray.tfar);
  out.point = origin + out.t * dir;
  return out;
}

}  // namespace uavip::photo
