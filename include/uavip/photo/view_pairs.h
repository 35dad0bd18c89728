#pragma once
/// \file
/// The image pairs worth matching (issue 46), written beside the photos as `pairs.txt`
/// (COLMAP's `matches_importer --match_type pairs`; docs/formats.md "The photo folder").
///
/// COLMAP's spatial matcher pairs each photo with the k nearest camera centres. An
/// edge link's photos (45° to both faces of a structure's edge, 0.15 m apart along it)
/// are each other's nearest, so they were matched only among themselves and one link
/// of the default scenario stayed out of the model (benchmarks/README.md, "Stop 61").
/// These pairs come from what the photos see instead: the rays through a grid of
/// kPairSamplesW × kPairSamplesH pixels of each photo meet the surface (the world or
/// mesh the photos are rendered from) at its samples; photo b sees a sample of photo a
/// when it lies in b's image, on the side of its face b stands on, unoccluded from b,
/// and the rays from it to the two cameras part by at most kPairMaxRayDeg (what SIFT
/// matches across viewpoints). share(a, b) is the share of a's samples b sees; a pair
/// scores min(share(a, b), share(b, a)), and each photo is paired with the
/// kPairsPerPhoto others of the highest score (ties in flown order). Only a photo's
/// target (one point) was too little: photos of the tower's top from above share with
/// the photos of its sides what both see of the sides' upper parts, not their targets.

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "uavip/photo/photo_folder.h"
#include "uavip/photo/ray_caster.h"

namespace uavip::photo {

/// Photos each photo is paired with, at most (COLMAP's matchers' 10 neighbours).
constexpr int kPairsPerPhoto = 10;
/// Largest angle between the rays from a sample to the two cameras of a pair [deg].
constexpr double kPairMaxRayDeg = 60.0;
/// Pixel grid whose rays give a photo's samples.
constexpr int kPairSamplesW = 12;
constexpr int kPairSamplesH = 8;

/// What one photo sees at its pixel grid: the first hit of each ray.
struct PhotoSamples {
  std::vector<Vec3> points;   ///< [m]
  std::vector<Vec3> normals;  ///< unit, the face's
};

/// The samples of a photo (rays that meet nothing give none).
PhotoSamples photoSamples(const RayCaster& surface, const coverage::PinholeIntrinsics& k,
                          const PhotoPose& pose);

/// Share of `a`'s samples that a camera at `b` sees (see the file comment), in [0, 1].
double seenShare(const RayCaster& surface, const coverage::PinholeIntrinsics& k,
                 const PhotoSamples& a, const PhotoPose& a_pose, const PhotoPose& b_pose);

/// The pairs (i < j, indices into `photos`), ascending: every photo with the
/// `per_photo` others of the highest score > 0. On every core; the same pairs whatever
/// the thread count.
std::vector<std::pair<std::size_t, std::size_t>> viewPairs(const std::vector<PlannedPhoto>& photos,
                                                           const PhotoCamera& camera,
                                                           const RayCaster& surface,
                                                           int per_photo = kPairsPerPhoto,
                                                           int threads = 1);

/// pairs.txt: one pair a line, "<stop_id>.png <stop_id>.png".
std::string colmapPairs(const std::vector<PlannedPhoto>& photos,
                        const std::vector<std::pair<std::size_t, std::size_t>>& pairs);

}  // namespace uavip::photo
