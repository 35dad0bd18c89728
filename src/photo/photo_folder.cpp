#include "uavip/photo/photo_folder.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <nlohmann/json.hpp>

#include "uavip/core/error.h"
#include "uavip/core/math.h"
#include "uavip/core/neighbour_index.h"
#include "uavip/core/parallel.h"
#include "uavip/core/stopwatch.h"
#include "uavip/core/text.h"
#include "uavip/io/atomic_file.h"
#include "uavip/io/mission_export.h"
#include "uavip/io/wpml_export.h"
#include "uavip/photo/view_pairs.h"
#include "uavip/world/solids.h"

namespace uavip::photo {
namespace {

/// printf into a std::string.
template <typename... Args>
std::string format(const char* fmt, Args... args) {
  char buf[512];
  const int n = std::snprintf(buf, sizeof(buf), fmt, args...);
  return std::string(buf, static_cast<std::size_t>(std::max(0, n)));
}

/// The first finite standoff of a flyable surface [m] (NaN if none).
double plannedStandoff(const io::MissionRecord& mission) {
  for (const auto& s : mission.surfaces) {
    if (s.flyable() && std::isfinite(s.standoff_m) && s.standoff_m > 0.0) return s.standoff_m;
  }
  return kNan;
}

/// One photo of stop `stop` of `surface` (a planar surface's photo keeps its id; those of
/// kind "structure" and "edge", which see several surfaces, get −1).
PlannedPhoto makePhoto(const io::SurfaceRecord& surface, std::size_t stop, int sortie,
                       const PhotoCamera& camera, const std::string& path) {
  const io::StopRecord& s = surface.stops[stop];
  PlannedPhoto p;
  io::FlightWaypoint w;
  w.surface_id = surface.surface_id;
  w.stop_index = static_cast<int>(stop);
  p.stop_id = io::stopId(w);
  if (!s.target)
    throw InputError(path + ": stop " + p.stop_id +
                     " has no target (written by an older uavip); re-run uavip plan");
  p.surface_id = surface.kind == "structure" || surface.kind == "edge" ? -1 : surface.surface_id;
  p.sortie = sortie;
  p.view.position = s.position;
  p.view.yaw_deg = s.yaw_deg;
  p.view.pitch_deg = s.gimbal_pitch_deg;
  p.pose = poseFromView(p.view);
  p.target = *s.target;
  const coverage::PinholeIntrinsics& k = camera.intrinsics;
  const double depth = std::max(0.0, projectToImage(k, p.pose, p.target).z());
  p.footprint_w_m = depth * k.width_px / k.fx_px;
  p.footprint_h_m = depth * k.height_px / k.fy_px;
  return p;
}

}  // namespace

PhotoCamera photoCamera(const io::MissionRecord& mission, const std::string& path,
                        double image_scale) {
  if (!mission.camera)
    throw InputError(path + ": has no camera_model (written by an older uavip); re-run uavip plan");
  const coverage::Camera& c = *mission.camera;
  PhotoCamera out;
  out.standoff_m = plannedStandoff(mission);
  coverage::PinholeIntrinsics& k = out.intrinsics;
  if (c.pinhole) {
    k.width_px = c.image_w_px;
    k.height_px = c.image_h_px;
    k.fx_px = c.fx_px;
    k.fy_px = c.fy_px;
    k.cx_px = c.cx_px;
    k.cy_px = c.cy_px;
    if (!std::isfinite(out.standoff_m) && c.gsd_mm_per_px > 0.0)
      out.standoff_m = c.gsd_mm_per_px * std::min(c.fx_px, c.fy_px) / 1000.0;
  } else if (c.from_sensor) {
    k.width_px = c.image_w_px;
    k.height_px = c.image_h_px;
    k.fx_px = c.focal_mm * c.image_w_px / c.sensor_w_mm;
    k.fy_px = c.focal_mm * c.image_h_px / c.sensor_h_mm;
    k.cx_px = 0.5 * k.width_px;
    k.cy_px = 0.5 * k.height_px;
  }
  if (!(std::isfinite(out.standoff_m) && out.standoff_m > 0.0))
    throw InputError(path +
                     ": no flyable surface records its camera standoff; nothing to photograph");
  if (!c.pinhole && !c.from_sensor) {  // footprint only: kFootprintPixelM at the standoff
    k.width_px = std::max(1, static_cast<int>(std::lround(c.footprint_w_m / kFootprintPixelM)));
    k.height_px = std::max(1, static_cast<int>(std::lround(c.footprint_h_m / kFootprintPixelM)));
    k.fx_px = k.width_px * out.standoff_m / c.footprint_w_m;
    k.fy_px = k.height_px * out.standoff_m / c.footprint_h_m;
    k.cx_px = 0.5 * k.width_px;
    k.cy_px = 0.5 * k.height_px;
  }
  if (image_scale != 1.0) {
    require(std::isfinite(image_scale) && image_scale > 0.0 && image_scale <= 1.0, path,
            "image scale " + formatNumber(image_scale, 4) + " must lie in (0, 1]");
    const int w = std::max(1, static_cast<int>(std::lround(k.width_px * image_scale)));
    const int h = std::max(1, static_cast<int>(std::lround(k.height_px * image_scale)));
    const double sx = static_cast<double>(w) / k.width_px;
    const double sy = static_cast<double>(h) / k.height_px;
    k.width_px = w;
    k.height_px = h;
    k.fx_px *= sx;
    k.cx_px *= sx;
    k.fy_px *= sy;
    k.cy_px *= sy;
  }
  out.gsd_m_per_px = out.standoff_m / std::min(k.fx_px, k.fy_px);
  return out;
}

std::vector<PlannedPhoto> plannedPhotos(const io::MissionRecord& mission, const PhotoCamera& camera,
                                        const std::string& path) {
  std::vector<PlannedPhoto> photos;
  if (mission.flight && !mission.flight->sorties.empty()) {
    for (std::size_t i = 0; i < mission.flight->sorties.size(); ++i) {
      for (const io::SortieStopRecord& st : mission.flight->sorties[i].stops)
        photos.push_back(makePhoto(*mission.surface(st.surface_id), st.stop,
                                   static_cast<int>(i + 1), camera, path));
    }
  } else {
    for (const auto& s : mission.surfaces) {
      if (!s.flyable()) continue;
      for (std::size_t k = 0; k < s.stops.size(); ++k) {
        if (s.stops[k].flown()) photos.push_back(makePhoto(s, k, 0, camera, path));
      }
    }
  }
  if (photos.empty()) throw InputError(path + ": the mission has no photo stop to render");
  for (std::size_t i = 0; i < photos.size(); ++i) photos[i].order = i + 1;
  return photos;
}

WorldMatch matchWorld(const std::vector<PlannedPhoto>& photos, const sim::WorldModel& world,
                      const PhotoCamera& camera) {
  WorldMatch m;
  m.tolerance_m = std::max(0.1, 0.05 * camera.standoff_m);
  std::vector<double> d;
  for (const auto& p : photos) {
    d.push_back(world.distanceToTruth(p.target));
    if (d.back() > m.tolerance_m) ++m.far;
  }
  m.targets = d.size();
  m.median_m = d.empty() ? 0.0 : median(d);
  return m;
}

WorldMatch matchMesh(const std::vector<PlannedPhoto>& photos, const io::TriangleMesh& mesh,
                     const PhotoCamera& camera) {
  WorldMatch m;
  m.tolerance_m = std::max(0.1, 0.05 * camera.standoff_m);
  std::vector<Aabb> boxes;
  boxes.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles) {
    Aabb b;
    for (const auto i : t) b.extend(mesh.vertices[i]);
    boxes.push_back(b);
  }
  std::vector<double> d(photos.size(), kInf);
  parallelFor(photos.size(), hardwareThreads(), [&](std::size_t k, std::size_t /*worker*/) {
    const Vec3& p = photos[k].target;
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
      const Vec3 gap = (boxes[i].min - p).cwiseMax(p - boxes[i].max).cwiseMax(0.0);
      if (gap.norm() >= d[k]) continue;
      const auto& t = mesh.triangles[i];
      const Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
      if (!((b - a).cross(c - a).norm() > 0.0)) continue;  // no area: nothing to be near
      Vec3 nearest;
      d[k] = std::min(d[k], world::segmentTriangle(p, p, a, b, c, nearest));
    }
  });
  for (const double x : d) m.far += x > m.tolerance_m ? 1 : 0;
  m.targets = d.size();
  m.median_m = d.empty() ? 0.0 : median(d);
  return m;
}

std::string colmapCameras(const PhotoCamera& camera) {
  const auto& k = camera.intrinsics;
  return "# Camera list with one line of data per camera:\n"
         "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
         "# Number of cameras: 1\n" +
         format("1 PINHOLE %d %d %.9g %.9g %.9g %.9g\n", k.width_px, k.height_px, k.fx_px, k.fy_px,
                k.cx_px, k.cy_px);
}

std::string colmapImages(const std::vector<PlannedPhoto>& photos) {
  std::string out =
      "# Image list with two lines of data per image:\n"
      "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n"
      "#   POINTS2D[] as (X, Y, POINT3D_ID)\n" +
      format("# Number of images: %zu, mean observations per image: 0\n", photos.size());
  for (const auto& p : photos) {
    const Eigen::Matrix3d r_wc = p.pose.camera_to_world.transpose();
    Eigen::Quaterniond q(r_wc);
    q.normalize();
    if (q.w() < 0.0) q.coeffs() = -q.coeffs();
    const Vec3 t = -(r_wc * p.pose.position);
    out += format("%zu %.12f %.12f %.12f %.12f %.9f %.9f %.9f 1 %s.png\n\n", p.order, q.w(), q.x(),
                  q.y(), q.z(), t.x(), t.y(), t.z(), p.stop_id.c_str());
  }
  return out;
}

std::string colmapPoints() {
  return "# 3D point list with one line of data per point:\n"
         "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, POINT2D_IDX)\n"
         "# Number of points: 0, mean track length: 0\n";
}

std::string posesCsv(const std::vector<PlannedPhoto>& photos) {
  std::string out =
      "order,stop_id,surface_id,sortie,x_m,y_m,z_m,qw,qx,qy,qz,target_x_m,target_y_m,target_z_m,"
      "footprint_w_m,footprint_h_m\n";
  for (const auto& p : photos) {
    Eigen::Quaterniond q(p.pose.camera_to_world);
    q.normalize();
    if (q.w() < 0.0) q.coeffs() = -q.coeffs();
    const Vec3& c = p.pose.position;
    out += format("%zu,%s,%d,%d,%.6f,%.6f,%.6f,%.9f,%.9f,%.9f,%.9f,%.6f,%.6f,%.6f,%.6f,%.6f\n",
                  p.order, p.stop_id.c_str(), p.surface_id, p.sortie, c.x(), c.y(), c.z(), q.w(),
                  q.x(), q.y(), q.z(), p.target.x(), p.target.y(), p.target.z(), p.footprint_w_m,
                  p.footprint_h_m);
  }
  return out;
}

namespace {

/// photos.json; `look` is how the pixels were made ({"texture": …} or {"preview": …}).
std::string photosJson(const std::string& mission_path, const std::string& world_path,
                       const PhotoCamera& camera, const nlohmann::json& look, std::size_t photos) {
  const auto& k = camera.intrinsics;
  nlohmann::json j = {{"mission", mission_path},
                      {"world", world_path},
                      {"camera",
                       {{"width_px", k.width_px},
                        {"height_px", k.height_px},
                        {"fx_px", k.fx_px},
                        {"fy_px", k.fy_px},
                        {"cx_px", k.cx_px},
                        {"cy_px", k.cy_px},
                        {"standoff_m", camera.standoff_m},
                        {"gsd_m_per_px", camera.gsd_m_per_px}}}};
  j.update(look);
  j["photos"] = photos;
  j["frame"] = "local ENU";
  return j.dump(2) + "\n";
}

/// The `texture` block of photos.json.
nlohmann::json textureJson(const TextureOptions& texture) {
  return {{"texture",
           {{"seed", texture.seed},
            {"finest_feature_px", kFinestFeaturePx},
            {"finest_feature_m", texture.finest_feature_m},
            {"octaves", texture.octaves}}}};
}

/// The one-line refusal when the mission was planned on another world.
[[noreturn]] void worldMismatch(const WorldMatch& m, const std::string& mission_path,
                                const std::string& world_path, const std::string& source) {
  throw InputError(mission_path + ": " + std::to_string(m.far) + " of " +
                   std::to_string(m.targets) + " photo targets lie more than " +
                   formatNumber(m.tolerance_m, 3) + " m from the surfaces of world " + world_path +
                   " (median " + formatNumber(m.median_m, 3) +
                   " m): the mission was not planned on this world; give --world the scenario or "
                   "mesh it was planned from" +
                   (source.empty() ? std::string() : " (mission.json source: " + source + ")"));
}

}  // namespace

namespace {

/// Draws one photo.
using PhotoDrawer = std::function<Image(const PhotoPose&)>;

/// Renders every photo with `draw` and writes the folder (writePhotoFolder);
/// `surface` (the world or mesh the photos show; none for a preview, which is not for
/// photogrammetry) gives pairs.txt.
PhotoSummary renderFolder(const std::vector<PlannedPhoto>& photos, const PhotoCamera& camera,
                          const PhotoDrawer& draw, const nlohmann::json& look,
                          const std::string& mission_path, const std::string& world_path,
                          const std::string& out, const PhotoOptions& options, PhotoSummary summary,
                          const RayCaster* surface) {
  const auto t0 = SteadyClock::now();
  io::StagedOutputs staged;
  const int threads = std::max(1, options.threads);
  const std::size_t batch = 2 * static_cast<std::size_t>(threads);
  for (std::size_t first = 0; first < photos.size(); first += batch) {
    const std::size_t n = std::min(batch, photos.size() - first);
    std::vector<std::string> png(n);
    parallelFor(n, threads, [&](std::size_t i, std::size_t /*worker*/) {
      png[i] = encodePng(draw(photos[first + i].pose));
    });
    for (std::size_t i = 0; i < n; ++i)
      staged.write(out + "/images/" + photos[first + i].stop_id + ".png", png[i]);
    if (options.progress) options.progress(first + n, photos.size());
  }
  summary.photos = photos.size();
  summary.megapixels = static_cast<double>(photos.size()) * camera.intrinsics.width_px *
                       camera.intrinsics.height_px / 1e6;
  summary.seconds = secondsSince(t0);
  staged.write(out + "/sparse/cameras.txt", colmapCameras(camera));
  staged.write(out + "/sparse/images.txt", colmapImages(photos));
  staged.write(out + "/sparse/points3D.txt", colmapPoints());
  staged.write(out + "/poses.csv", posesCsv(photos));
  if (surface != nullptr)
    staged.write(out + "/pairs.txt",
                 colmapPairs(photos, viewPairs(photos, camera, *surface, kPairsPerPhoto, threads)));
  staged.write(out + "/photos.json",
               photosJson(mission_path, world_path, camera, look, photos.size()));
  staged.commit();
  return summary;
}

/// The world texture at the camera's GSD (texture.h).
TextureOptions textureFor(const PhotoCamera& camera, const PhotoOptions& options) {
  TextureOptions texture;
  texture.seed = options.texture_seed;
  texture.finest_feature_m = kFinestFeaturePx * camera.gsd_m_per_px;
  return texture;
}

/// Renders against `caster` with the world texture.
PhotoSummary renderTextured(const std::vector<PlannedPhoto>& photos, const PhotoCamera& camera,
                            const RayCaster& caster, const std::string& mission_path,
                            const std::string& world_path, const std::string& out,
                            const PhotoOptions& options, const PhotoSummary& summary) {
  const TextureOptions texture = textureFor(camera, options);
  const SurfaceTexture surface_texture(texture);
  return renderFolder(
      photos, camera,
      [&](const PhotoPose& pose) {
        return renderPhoto(caster, surface_texture, camera.intrinsics, pose);
      },
      textureJson(texture), mission_path, world_path, out, options, summary, &caster);
}

}  // namespace

PhotoSummary writePhotoFolder(const io::MissionRecord& mission, const std::string& mission_path,
                              const sim::WorldModel& world, const std::string& world_path,
                              const std::string& out, const PhotoOptions& options) {
  const PhotoCamera camera = photoCamera(mission, mission_path, options.image_scale);
  const std::vector<PlannedPhoto> photos = plannedPhotos(mission, camera, mission_path);
  PhotoSummary summary;
  summary.match = matchWorld(photos, world, camera);
  if (!summary.match.matches())
    worldMismatch(summary.match, mission_path, world_path, mission.source);
  const RayCaster caster(world);
  return renderTextured(photos, camera, caster, mission_path, world_path, out, options, summary);
}

PhotoSummary writePhotoFolder(const io::MissionRecord& mission, const std::string& mission_path,
                              const io::TriangleMesh& mesh, const std::string& mesh_path,
                              const std::string& out, const PhotoOptions& options) {
  const PhotoCamera camera = photoCamera(mission, mission_path, options.image_scale);
  const std::vector<PlannedPhoto> photos = plannedPhotos(mission, camera, mission_path);
  const RayCaster caster(mesh, mesh_path);  // checks the indices matchMesh reads
  PhotoSummary summary;
  summary.match = matchMesh(photos, mesh, camera);
  if (!summary.match.matches())
    worldMismatch(summary.match, mission_path, mesh_path, mission.source);
  return renderTextured(photos, camera, caster, mission_path, mesh_path, out, options, summary);
}

WorldMatch matchCloud(const std::vector<PlannedPhoto>& photos, const PointList& points,
                      const PhotoCamera& camera) {
  WorldMatch m;
  m.tolerance_m = std::max({0.1, 0.05 * camera.standoff_m, 3.0 * medianSpacing(points)});
  if (points.empty()) {
    m.targets = m.far = photos.size();
    m.median_m = kInf;
    return m;
  }
  const NeighbourIndex index(points);
  std::vector<double> d;
  for (const auto& p : photos) {
    const int i = index.nearestTo(p.target);
    d.push_back(i < 0 ? kInf : (points[static_cast<std::size_t>(i)] - p.target).norm());
    if (d.back() > m.tolerance_m) ++m.far;
  }
  m.targets = d.size();
  m.median_m = d.empty() ? 0.0 : median(d);
  return m;
}

PhotoSummary writePreviewFolder(const io::MissionRecord& mission, const std::string& mission_path,
                                const PreviewCloud& cloud, const std::string& cloud_path,
                                const std::string& colour_source, const std::string& out,
                                const PhotoOptions& options) {
  const PhotoCamera camera = photoCamera(mission, mission_path, options.image_scale);
  const std::vector<PlannedPhoto> photos = plannedPhotos(mission, camera, mission_path);
  PhotoSummary summary;
  summary.match = matchCloud(photos, cloud.points, camera);
  if (!summary.match.matches())
    worldMismatch(summary.match, mission_path, cloud_path, mission.source);
  const nlohmann::json look = {
      {"preview",
       {{"points", cloud.points.size()},
        {"colour", colour_source.empty() ? std::string("height") : colour_source},
        {"splat_m", cloud.splat_m},
        {"max_depth_m", cloud.max_depth_m}}}};
  return renderFolder(
      photos, camera,
      [&](const PhotoPose& pose) { return renderPointPreview(cloud, camera.intrinsics, pose); },
      look, mission_path, cloud_path, out, options, summary, nullptr);
}

}  // namespace uavip::photo
