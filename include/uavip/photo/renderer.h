#pragma once
/// \file
/// One photo of the ground-truth world through a pinhole camera (issue 46): a ray
/// through the centre of every pixel (Embree, ray_caster.h), the texture of the point
/// it hits (texture.h) under a fixed, view-independent shading, and an 8-bit RGB PNG.
///
/// Camera convention (COLMAP's and OpenCV's): camera x right, y down, z forward
/// (the optical axis); pixel (u, v) covers [u, u+1) × [v, v+1), so its centre is
/// (u + ½, v + ½), and image point (x, y) lies on the ray along
/// R_cw · ((x − cx)/fx, (y − cy)/fy, 1) from the camera centre. From a
/// coverage::ViewPose (coverage_evaluator.h), R_cw's columns are right, −up, forward.

#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "uavip/core/types.h"
#include "uavip/coverage/coverage_evaluator.h"
#include "uavip/photo/ray_caster.h"
#include "uavip/photo/texture.h"

namespace uavip::photo {

/// A photo's pose: camera centre and camera-to-world rotation (columns: the camera's
/// x right, y down, z forward in world coordinates).
struct PhotoPose {
  Vec3 position{Vec3::Zero()};                                   ///< camera centre [m]
  Eigen::Matrix3d camera_to_world{Eigen::Matrix3d::Identity()};  ///< R_cw
};

/// The pose of a 2-DOF gimbal view (coverage::makeViewFrame: no roll).
PhotoPose poseFromView(const coverage::ViewPose& view);

/// Unit world direction of image point (x, y) [px] (pixel centres at +½).
Vec3 pixelRay(const coverage::PinholeIntrinsics& k, const PhotoPose& pose, double x, double y);

/// Image point [px] of world point p, and its depth along the optical axis [m].
Eigen::Vector3d projectToImage(const coverage::PinholeIntrinsics& k, const PhotoPose& pose,
                               const Vec3& p);

/// An 8-bit RGB image, rows top to bottom.
struct Image {
  int width{0};
  int height{0};
  std::vector<std::uint8_t> rgb;  ///< width·height·3 bytes
};

/// The colour of what the ray through a pixel meets: the texture's albedo at the hit
/// point times 0.55 + 0.45·|n·l| (a fixed light l, the normal's sign ignored, so the
/// two faces of a plane shade alike), 8 bits a channel; the sky (no hit) is one flat colour.
/// Deterministic: a pixel depends only on its ray.
Image renderPhoto(const RayCaster& world, const SurfaceTexture& texture,
                  const coverage::PinholeIntrinsics& k, const PhotoPose& pose);

/// The flat colour of a pixel whose ray meets nothing (8-bit RGB).
constexpr std::uint8_t kSkyRgb[3] = {178, 204, 232};

/// The PNG bytes of an image (libpng, zlib level 1; no time stamp: the same image
/// gives the same bytes).
std::string encodePng(const Image& image);

}  // namespace uavip::photo
