#include "uavip/photo/ray_caster.h"

#include <embree3/rtcore.h>

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "uavip/core/error.h"

namespace uavip::photo {

struct RayCaster::Impl {
  RTCDevice device{nullptr};
  RTCScene scene{nullptr};
  Vec3 origin{Vec3::Zero()};  ///< the faces' float coordinates are relative to this [m]
  std::vector<Vec3> corners;  ///< one point of each face's plane [m]
  std::vector<Vec3> normals;  ///< each face's unit normal

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

/// One geometry of `corners_per_face` vertices a face (4: quads, 3: triangles) from
/// `faces` (relative to the caster's origin) in the empty `scene`, committed.
void fillScene(RTCDevice device, RTCScene scene, RTCGeometryType type, std::size_t corners_per_face,
               const std::vector<Vec3>& faces) {
  rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
  const std::size_t n = faces.size() / corners_per_face;
  RTCGeometry g = rtcNewGeometry(device, type);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
      g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), faces.size()));
  auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      g, RTC_BUFFER_TYPE_INDEX, 0, corners_per_face == 4 ? RTC_FORMAT_UINT4 : RTC_FORMAT_UINT3,
      corners_per_face * sizeof(unsigned), n));
  if (v == nullptr || idx == nullptr) embreeFailed(device, "allocating the faces");
  for (std::size_t i = 0; i < faces.size(); ++i) {
    for (int a = 0; a < 3; ++a)
      v[3 * i + static_cast<std::size_t>(a)] = static_cast<float>(faces[i][a]);
    idx[i] = static_cast<unsigned>(i);
  }
  rtcCommitGeometry(g);
  rtcAttachGeometry(scene, g);
  rtcReleaseGeometry(g);
  rtcCommitScene(scene);
  if (rtcGetDeviceError(device) != RTC_ERROR_NONE) embreeFailed(device, "building the scene");
}

/// A device with one build thread: the same hierarchy, and tie order, whatever the
/// machine.
RTCDevice newDevice() {
  RTCDevice device = rtcNewDevice("threads=1");
  if (device == nullptr) throw std::runtime_error("Embree: rtcNewDevice failed");
  return device;
}

}  // namespace

RayCaster::RayCaster(const sim::WorldModel& world) : impl_(std::make_unique<Impl>()) {
  if (world.rects().empty())
    throw InputError("the world has no surface a photo could see (only lines or points)");
  Impl& m = *impl_;
  for (const auto& r : world.rects()) {
    for (const Vec3& c : {r.corner, Vec3(r.corner + r.edge_u), Vec3(r.corner + r.edge_v),
                          Vec3(r.corner + r.edge_u + r.edge_v)})
      bounds_.extend(c);
    m.corners.push_back(r.corner);
    m.normals.push_back(r.normal());
  }
  m.origin = 0.5 * (bounds_.min + bounds_.max);
  std::vector<Vec3> faces;
  for (const auto& r : world.rects()) {
    const Vec3 c = r.corner - m.origin;
    for (const Vec3& corner :
         {c, Vec3(c + r.edge_u), Vec3(c + r.edge_u + r.edge_v), Vec3(c + r.edge_v)})
      faces.push_back(corner);
  }
  m.device = newDevice();
  m.scene = rtcNewScene(m.device);
  fillScene(m.device, m.scene, RTC_GEOMETRY_TYPE_QUAD, 4, faces);
}

RayCaster::RayCaster(const io::TriangleMesh& mesh, const std::string& path)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  std::vector<Vec3> faces;
  for (const auto& t : mesh.triangles) {
    if (t[0] >= mesh.vertices.size() || t[1] >= mesh.vertices.size() ||
        t[2] >= mesh.vertices.size())
      throw InputError(path + ": a triangle indexes past the mesh's " +
                       std::to_string(mesh.vertices.size()) + " vertices");
    const std::array<Vec3, 3> p{mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]};
    const Vec3 n = (p[1] - p[0]).cross(p[2] - p[0]);
    if (!n.allFinite() || n.norm() <= 0.0) continue;  // degenerate: no area
    for (const Vec3& c : p) {
      bounds_.extend(c);
      faces.push_back(c);  // made relative to the origin below
    }
    m.corners.push_back(p[0]);
    m.normals.push_back(n.normalized());
  }
  if (m.corners.empty())
    throw InputError(path + ": the mesh has no triangle with area; nothing a photo could see");
  m.origin = 0.5 * (bounds_.min + bounds_.max);
  for (Vec3& c : faces) c -= m.origin;
  m.device = newDevice();
  m.scene = rtcNewScene(m.device);
  fillScene(m.device, m.scene, RTC_GEOMETRY_TYPE_TRIANGLE, 3, faces);
}

RayCaster::~RayCaster() = default;

std::size_t RayCaster::faces() const { return impl_->corners.size(); }

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
  out.face = rh.hit.primID;
  out.normal = m.normals[out.face];
  // The hit again in double, on the plane of the face hit.
  const double along = out.normal.dot(dir);
  out.t = std::abs(along) > 1e-12 ? out.normal.dot(m.corners[out.face] - origin) / along
                                  : static_cast<double>(rh.ray.tfar);
  out.point = origin + out.t * dir;
  return out;
}

}  // namespace uavip::photo
