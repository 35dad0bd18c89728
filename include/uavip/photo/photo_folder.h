#pragma once
/// \file
/// `uavip photos`: every photo stop of a mission, in flown order, rendered against the
/// ground-truth world (or a mesh of the structure), and the folder other photogrammetry
/// tools read
/// (docs/formats.md "The photo folder"): images/<stop_id>.png, a COLMAP text model
/// with the planned poses and intrinsics (sparse/cameras.txt, images.txt, empty
/// points3D.txt), the image pairs worth matching (pairs.txt, view_pairs.h), poses.csv
/// and photos.json.
///
/// The camera: a pinhole camera's intrinsics as planned; a sensor camera's
/// fx = f·Iw/Sw, fy = f·Ih/Sh, principal point at the image centre; a camera given
/// by its footprint only gets kFootprintPixelM per pixel at the planned standoff
/// (0.6 × 0.4 m → 1200 × 800 px). The texture's finest octave is
/// kFinestFeaturePx pixels at the planned GSD (texture.h).

#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "uavip/core/types.h"
#include "uavip/coverage/coverage_evaluator.h"
#include "uavip/io/mission_json.h"
#include "uavip/photo/point_preview.h"
#include "uavip/photo/ray_caster.h"
#include "uavip/photo/renderer.h"
#include "uavip/sim/world_model.h"

namespace uavip::photo {

/// Pixel size of a camera given by its footprint only, at the planned standoff [m].
constexpr double kFootprintPixelM = 0.0005;
/// The texture's finest octave in pixels at the planned GSD (issue 46: >= 3 px).
constexpr double kFinestFeaturePx = 4.0;

/// The camera the photos are taken with.
struct PhotoCamera {
  coverage::PinholeIntrinsics intrinsics;  ///< image size and pinhole [px]
  double standoff_m{0.0};                  ///< the planned viewing distance [m]
  double gsd_m_per_px{0.0};                ///< standoff / min(fx, fy) [m/px]
};

/// The camera of a mission (its `camera_model` and the first flown surface's standoff),
/// its image size and pinhole scaled by `image_scale` in (0, 1] (a quicker render of the
/// same views at a coarser GSD). Throws InputError naming `path` when the file has no
/// camera_model (an older uavip) or the scale is out of range.
PhotoCamera photoCamera(const io::MissionRecord& mission, const std::string& path,
                        double image_scale = 1.0);

/// One photo of the flight.
struct PlannedPhoto {
  std::size_t order{0};  ///< flown order, from 1
  std::string stop_id;   ///< s<surface>_<stop> (as the exports name it)
  int surface_id{-1};    ///< the surface photographed; −1 for a view of the whole structure
  int sortie{0};         ///< battery sortie, from 1 (0: the mission has no ordered flight)
  coverage::ViewPose view;
  PhotoPose pose;
  Vec3 target{Vec3::Zero()};  ///< the surface point the stop aims at [m]
  double footprint_w_m{0.0};  ///< the image's width at the target's depth [m]
  double footprint_h_m{0.0};  ///< its height [m]
};

/// The photo stops of the ordered flight in flown order (without a flight: every flown
/// stop of each flyable surface, in file order). Throws InputError naming `path` when
/// there is none, or a stop has no target (an older uavip).
std::vector<PlannedPhoto> plannedPhotos(const io::MissionRecord& mission, const PhotoCamera& camera,
                                        const std::string& path);

/// How far the stops' targets lie from the world's surfaces.
struct WorldMatch {
  std::size_t targets{0};
  std::size_t far{0};       ///< targets farther than the tolerance
  double median_m{0.0};     ///< median distance [m]
  double tolerance_m{0.0};  ///< [m]
  bool matches() const { return far * 10 <= targets; }
};

/// The mission was planned on this world when at least 90 % of the targets lie within
/// max(0.1 m, 0.05 × the standoff) of the world's rectangles (the planner aims at
/// points of the detected surfaces, which lie on the truth within the sensing noise).
WorldMatch matchWorld(const std::vector<PlannedPhoto>& photos, const sim::WorldModel& world,
                      const PhotoCamera& camera);

/// The same test against a mesh: a target's distance is to the nearest triangle
/// (exact, brute force over the triangles' boxes, on every core).
WorldMatch matchMesh(const std::vector<PlannedPhoto>& photos, const io::TriangleMesh& mesh,
                     const PhotoCamera& camera);

/// The same test against a measured cloud: a target's distance is to the nearest point,
/// the tolerance at least 3 × the cloud's median spacing (a stop aims at its surface's
/// plane, which passes between the points of a sparse scan).
WorldMatch matchCloud(const std::vector<PlannedPhoto>& photos, const PointList& points,
                      const PhotoCamera& camera);

/// The COLMAP text model (cameras.txt: one PINHOLE camera; images.txt: per photo
/// IMAGE_ID QW QX QY QZ TX TY TZ 1 NAME, world to camera, and an empty points line;
/// points3D.txt: the header only).
std::string colmapCameras(const PhotoCamera& camera);
std::string colmapImages(const std::vector<PlannedPhoto>& photos);
std::string colmapPoints();
/// poses.csv (docs/formats.md): one row per photo, camera-to-world quaternion.
std::string posesCsv(const std::vector<PlannedPhoto>& photos);

/// What `uavip photos` does.
struct PhotoOptions {
  int threads{1};                  ///< worker threads (the PNG bytes do not depend on it)
  std::uint32_t texture_seed{46};  ///< the texture's seed
  double image_scale{1.0};         ///< image size and pinhole × this, in (0, 1] (photoCamera)
  /// Called after each batch of photos with (done, total); may be empty.
  std::function<void(std::size_t, std::size_t)> progress;
};

/// What was written.
struct PhotoSummary {
  std::size_t photos{0};
  double megapixels{0.0};  ///< all photos [MP]
  double seconds{0.0};     ///< rendering and encoding [s]
  WorldMatch match;
};

/// Renders every photo and writes the folder `out` (io::StagedOutputs: renamed into
/// place together once all are written). Throws InputError (one line naming the files
/// and what to do) when the world does not match the mission (matchWorld).
PhotoSummary writePhotoFolder(const io::MissionRecord& mission, const std::string& mission_path,
                              const sim::WorldModel& world, const std::string& world_path,
                              const std::string& out, const PhotoOptions& options);

/// The same against a triangle mesh in the mission's frame (the model the structure
/// was detected from, or any mesh of it: the world texture is laid on its triangles),
/// checked by matchMesh. Throws InputError naming `mesh_path` when no triangle has area.
PhotoSummary writePhotoFolder(const io::MissionRecord& mission, const std::string& mission_path,
                              const io::TriangleMesh& mesh, const std::string& mesh_path,
                              const std::string& out, const PhotoOptions& options);

/// A preview of the photos drawn from a measured cloud in the mission's frame
/// (point_preview.h; `colour_source` names the file's colour fields, empty for the
/// height ramp), the same folder with a `preview` block in photos.json instead of
/// `texture`. Checked by matchCloud; throws InputError like writePhotoFolder.
PhotoSummary writePreviewFolder(const io::MissionRecord& mission, const std::string& mission_path,
                                const PreviewCloud& cloud, const std::string& cloud_path,
                                const std::string& colour_source, const std::string& out,
                                const PhotoOptions& options);

}  // namespace uavip::photo
